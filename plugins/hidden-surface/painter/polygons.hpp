// painter: the polygons a depth sort works on and the geometric tests of Newell, Newell & Sancha,
// "A solution to the hidden surface problem", Proc. ACM Annual Conference 1972, pp. 443-450:
// window-space extents, the side of a polygon's plane another polygon lies on, and whether two
// projections overlap. Polygons are convex pieces of the scene's triangles in clip space, their
// corners carrying the original triangle's barycentrics (hsr/triangle_setup.hpp, ClipVertex).
// Header-only so that tests/test_painter.cpp can check the tests directly.
#pragma once

#include "hsr/triangle_setup.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace painter {

using hsr::raster::ClipVertex;

// Projections closer than this (window pixels) count as overlapping: snapping the corners to the
// rasterizer's 1/256-pixel grid moves each by up to 1/512 pixel, and polygons that merely touch can
// share a pixel centre on the touching line.
inline constexpr double kOverlapMargin = 1.0 / 64.0;
// A corner this close to a plane, relative to the size of the terms of the plane equation, lies in
// it: corners shared by two triangles of a mesh, or made by splitting, are not moved off their
// plane by rounding.
inline constexpr double kPlaneTolerance = 1e-10;

// Window-space bounds of a polygon: x and y in pixels (y down), depth in [0, 1] (larger is farther).
struct Extent {
    double x0, x1, y0, y1, z0, z1;
};

// A half-space a piece of a triangle keeps, from a clip-space plane: at a pixel centre of the
// triangle, the point of the triangle there (window x, y and depth, as NDC) is kept where
// dot(plane, point) >= 0, or > 0 when strict. The two pieces of a split get the plane with opposite
// signs, one of them strict, so each pixel centre of the triangle goes to exactly one of them.
struct Cut {
    glm::dvec4 plane;
    bool strict;
};

struct Polygon {
    uint32_t first = 0;  // its corners are corners[first, first + count) of the PolygonStore
    uint32_t count = 0;
    uint32_t face = 0;  // the triangle it is (a piece of)
    uint32_t instance = 0;
    // Pixels: those of polygon `root` (the triangle's clipped polygon, rasterized) that all the
    // cuts cuts[first_cut, first_cut + cut_count) keep. Corners and extents serve the tests.
    uint32_t root = 0;
    uint32_t first_cut = 0;
    uint32_t cut_count = 0;
    // The pixels (indices, inclusive) outside which its cuts keep no pixel centre of the root: all
    // of them for a triangle's own polygon.
    int32_t pixels_x0 = INT32_MIN, pixels_y0 = INT32_MIN, pixels_x1 = INT32_MAX, pixels_y1 = INT32_MAX;
    // The plane of the triangle in clip space, oriented so that points nearer the viewer are on its
    // positive side, scaled to |(x, y, z)| = 1.
    glm::dvec4 plane{0.0};
    Extent extent{};
    bool marked = false;  // moved ahead of another polygon and not yet painted
};

// Where a polygon's corners lie against a plane (as Polygon::plane): all on the near side or on the
// plane, all on the far side or on it. Both for a polygon in the plane; neither when it crosses it.
struct Sides {
    bool all_near = true;
    bool all_far = true;
};

inline Sides sides_of(const glm::dvec4& plane, const ClipVertex* corners, uint32_t count) {
    Sides s;
    for (uint32_t k = 0; k < count; ++k) {
        const glm::dvec4& c = corners[k].position;
        const double d = glm::dot(plane, c);
        const double size = std::abs(plane.x * c.x) + std::abs(plane.y * c.y) + std::abs(plane.z * c.z) +
                            std::abs(plane.w * c.w);
        const double tolerance = kPlaneTolerance * size;
        if (d < -tolerance) s.all_near = false;
        if (d > tolerance) s.all_far = false;
    }
    return s;
}

// The plane of the triangle with clip-space corners a, b, c, oriented and scaled as
// Polygon::plane; zero when the triangle is seen edge-on (its plane contains the view direction) or
// degenerate. In NDC the plane reads x*p.x + y*p.y + z*p.z + p.w = 0 (clip space divided by w > 0
// keeps the sign), and the viewer looks toward +z, so the near side is where p.z < 0 points.
inline glm::dvec4 oriented_plane(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c) {
    glm::dvec4 p = hsr::raster::plane_through(a, b, c);
    const double length = glm::length(glm::dvec3(p));
    if (!(length > 0.0) || !std::isfinite(length) || p.z == 0.0) return glm::dvec4(0.0);
    p /= length;
    return p.z > 0.0 ? -p : p;
}

// True when the convex polygons a and b (window x, y) have a separating line with a gap wider than
// kOverlapMargin: the separating-axis test over the edge normals of both.
inline bool projections_disjoint(const glm::dvec2* a, uint32_t na, const glm::dvec2* b, uint32_t nb) {
    auto separated_along = [&](glm::dvec2 axis) {
        const double length = glm::length(axis);
        if (!(length > 0.0)) return false;
        axis /= length;
        double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
        for (uint32_t k = 0; k < na; ++k) {
            const double t = glm::dot(axis, a[k]);
            a0 = std::min(a0, t);
            a1 = std::max(a1, t);
        }
        for (uint32_t k = 0; k < nb; ++k) {
            const double t = glm::dot(axis, b[k]);
            b0 = std::min(b0, t);
            b1 = std::max(b1, t);
        }
        return a1 + kOverlapMargin < b0 || b1 + kOverlapMargin < a0;
    };
    auto any_edge_separates = [&](const glm::dvec2* p, uint32_t n) {
        for (uint32_t k = 0; k < n; ++k) {
            const glm::dvec2 edge = p[k + 1 == n ? 0 : k + 1] - p[k];
            if (separated_along({-edge.y, edge.x})) return true;
        }
        return false;
    };
    return any_edge_separates(a, na) || any_edge_separates(b, nb);
}

// The part of convex polygon a (window x, y) inside convex polygon b, either orientation, into
// `out` (room for na + nb corners): Sutherland-Hodgman clipping by b's edges. Returns its corner
// count, below 3 when they do not overlap in an area.
inline int convex_intersection(const glm::dvec2* a, uint32_t na, const glm::dvec2* b, uint32_t nb,
                               glm::dvec2* out, glm::dvec2* scratch) {
    double twice_area = 0.0;
    for (uint32_t k = 0; k < nb; ++k) {
        const glm::dvec2 &p = b[k], &q = b[k + 1 == nb ? 0 : k + 1];
        twice_area += p.x * q.y - p.y * q.x;
    }
    if (twice_area == 0.0) return 0;
    const double orientation = twice_area > 0.0 ? 1.0 : -1.0;
    int count = int(na);
    std::copy(a, a + na, out);
    for (uint32_t k = 0; k < nb && count >= 3; ++k) {
        const glm::dvec2 &e0 = b[k], &e1 = b[k + 1 == nb ? 0 : k + 1];
        auto side = [&](const glm::dvec2& p) {
            return orientation * ((e1.x - e0.x) * (p.y - e0.y) - (e1.y - e0.y) * (p.x - e0.x));
        };
        std::copy(out, out + count, scratch);
        int kept = 0;
        for (int i = 0; i < count; ++i) {
            const glm::dvec2 &p = scratch[i], &q = scratch[i + 1 == count ? 0 : i + 1];
            const double sp = side(p), sq = side(q);
            if (sp >= 0.0) out[kept++] = p;
            if ((sp >= 0.0) != (sq >= 0.0)) out[kept++] = p + (q - p) * (sp / (sp - sq));
        }
        count = kept;
    }
    return count;
}

// Depth differences this small (NDC) do not decide test 7: float depths at pixel centres round by
// about 1e-7 of the depth, so where two planes come this close the painted order could disagree
// with the z-buffer's comparison.
inline constexpr double kDepthMargin = 1e-6;

// Test 7: true when the plane `behind` (as Polygon::plane) is farther than the plane `front` at
// every point of the convex window polygon c (pixels, y down, in an image of width x height), with
// room to spare: the gap at each corner exceeds kDepthMargin plus the change of the gap over
// kOverlapMargin pixels, which covers pixel centres a snapped corner lets just outside c. The gap
// between two planes is linear in window x and y (a projective map keeps planes planar), so its
// least value over c is at a corner. Where c is the overlap of two polygons' projections, the
// polygon in `behind` then hides no part of the one in `front`.
inline bool farther_over(const glm::dvec4& behind, const glm::dvec4& front, const glm::dvec2* c, int n, double width,
                         double height) {
    if (n < 3 || behind.z == 0.0 || front.z == 0.0) return false;
    // NDC depth on a plane: z = -(p.x X + p.y Y + p.w) / p.z with X = 2x/width - 1, Y = 1 - 2y/height.
    const glm::dvec4 b = behind / -behind.z, f = front / -front.z;
    const glm::dvec4 gap = b - f;  // gap(X, Y) = gap.x X + gap.y Y + gap.w
    const double per_pixel = std::abs(gap.x) * 2.0 / width + std::abs(gap.y) * 2.0 / height;
    const double needed = kDepthMargin + per_pixel * kOverlapMargin;
    for (int k = 0; k < n; ++k) {
        const double X = 2.0 * c[k].x / width - 1.0, Y = 1.0 - 2.0 * c[k].y / height;
        if (!(gap.x * X + gap.y * Y + gap.w > needed)) return false;
    }
    return true;
}

// The length of segment ab (window pixels) that lies outside convex polygon c (either
// orientation): the segment clipped by each edge's half-plane (Cyrus-Beck).
inline double length_outside(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2* c, int n) {
    const double length = glm::length(b - a);
    double twice_area = 0.0;
    for (int k = 0; k < n; ++k) {
        const glm::dvec2 &p = c[k], &q = c[k + 1 == n ? 0 : k + 1];
        twice_area += p.x * q.y - p.y * q.x;
    }
    if (twice_area == 0.0) return length;
    const double orientation = twice_area > 0.0 ? 1.0 : -1.0;
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < n && t0 < t1; ++k) {
        const glm::dvec2 &p = c[k], &q = c[k + 1 == n ? 0 : k + 1];
        auto side = [&](const glm::dvec2& r) { return orientation * ((q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x)); };
        const double sa = side(a), sb = side(b);
        if (sa < 0.0 && sb < 0.0) return length;
        if (sa < 0.0) t0 = std::max(t0, sa / (sa - sb));
        else if (sb < 0.0) t1 = std::min(t1, sa / (sa - sb));
    }
    return t0 < t1 ? length * (1.0 - (t1 - t0)) : length;
}

// True when the point lies inside convex polygon c (either orientation) at least `margin` from the
// line of each of its edges.
inline bool deep_inside(const glm::dvec2& point, const glm::dvec2* c, int n, double margin) {
    double twice_area = 0.0;
    for (int k = 0; k < n; ++k) {
        const glm::dvec2 &p = c[k], &q = c[k + 1 == n ? 0 : k + 1];
        twice_area += p.x * q.y - p.y * q.x;
    }
    const double orientation = twice_area > 0.0 ? 1.0 : -1.0;
    for (int k = 0; k < n; ++k) {
        const glm::dvec2 &p = c[k], &q = c[k + 1 == n ? 0 : k + 1];
        const double length = glm::length(q - p);
        if (!(length > 0.0)) continue;
        const double distance = orientation * ((q.x - p.x) * (point.y - p.y) - (q.y - p.y) * (point.x - p.x)) / length;
        if (!(distance > margin)) return false;
    }
    return twice_area != 0.0;
}

// The polygons of a frame, their corners and cuts, kept between frames.
class PolygonStore {
public:
    std::vector<Polygon> polygons;
    std::vector<ClipVertex> corners;
    std::vector<glm::dvec2> window;  // per corner, its window x and y (pixels)
    std::vector<Cut> cuts;
    // Per polygon: painted, dropped or split. Apart from the polygons, so that the bin search,
    // which asks it of every polygon it passes, reads a byte and not a polygon's cache line.
    std::vector<uint8_t> done;

    void clear() {
        polygons.clear();
        done.clear();
        window.clear();
        corners.clear();
        cuts.clear();
    }
    const ClipVertex* corners_of(const Polygon& p) const { return corners.data() + p.first; }
    const glm::dvec2* window_of(const Polygon& p) const { return window.data() + p.first; }
    const Cut* cuts_of(const Polygon& p) const { return cuts.data() + p.first_cut; }

    // Adds a triangle's clipped polygon (3..kMaxPieceVertices corners) with the face, instance
    // and plane of `like`, or, with a cut, a convex piece of any size of polygon `like` that keeps
    // its cuts and this one. False when a corner cannot be projected (w <= 0 or not finite):
    // nothing is added.
    template <class ViewportT>
    bool add(const ViewportT& viewport, const ClipVertex* in, int count, const Polygon& like,
             const Cut* cut = nullptr) {
        for (int k = 0; k < count; ++k) {
            const glm::dvec4& c = in[k].position;
            if (!(c.w > 0.0) || !std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) ||
                !std::isfinite(c.w))
                return false;
        }
        Polygon p = like;
        p.first = uint32_t(corners.size());
        p.count = uint32_t(count);
        p.marked = false;
        if (cut == nullptr) {
            p.root = uint32_t(polygons.size());
            p.first_cut = uint32_t(cuts.size());
            p.cut_count = 0;
        } else {
            const uint32_t from = like.first_cut;
            p.first_cut = uint32_t(cuts.size());
            p.cut_count = like.cut_count + 1;
            for (uint32_t k = 0; k < like.cut_count; ++k) cuts.push_back(cuts[from + k]);
            cuts.push_back(*cut);
        }
        Extent& e = p.extent;
        e = {INFINITY, -INFINITY, INFINITY, -INFINITY, INFINITY, -INFINITY};
        for (int k = 0; k < count; ++k) {
            corners.push_back(in[k]);
            const glm::dvec3 w = viewport.project(in[k].position);
            window.emplace_back(w.x, w.y);
            e.x0 = std::min(e.x0, w.x);
            e.x1 = std::max(e.x1, w.x);
            e.y0 = std::min(e.y0, w.y);
            e.y1 = std::max(e.y1, w.y);
            e.z0 = std::min(e.z0, w.z);
            e.z1 = std::max(e.z1, w.z);
        }
        polygons.push_back(p);
        done.push_back(0);
        return true;
    }
};

// Yes-or-no answers remembered for unordered pairs of polygon ids (each below 2^31), in one flat
// table with open addressing: a lookup costs about one cache miss, where a node-based map costs
// several. Holds up to `limit` answers and forgets all of them when full.
class PairAnswers {
public:
    explicit PairAnswers(size_t limit) : limit_(limit) {}

    void clear() {
        slots_.assign(kFirstSize, kEmpty);
        count_ = 0;
    }
    // 1 or 0 for a remembered answer, -1 for none.
    int find(uint32_t a, uint32_t b) const {
        const uint64_t key = pack(a, b);
        for (size_t k = slot(key);; k = (k + 1) & (slots_.size() - 1)) {
            if (slots_[k] == kEmpty) return -1;
            if ((slots_[k] >> 1) == key) return int(slots_[k] & 1);
        }
    }
    void remember(uint32_t a, uint32_t b, bool answer) {
        if (count_ >= limit_) clear();
        if (2 * (count_ + 1) > slots_.size()) grow();
        const uint64_t key = pack(a, b);
        size_t k = slot(key);
        while (slots_[k] != kEmpty && (slots_[k] >> 1) != key) k = (k + 1) & (slots_.size() - 1);
        if (slots_[k] == kEmpty) ++count_;
        slots_[k] = (key << 1) | uint64_t(answer);
    }

private:
    static constexpr uint64_t kEmpty = ~uint64_t(0);
    static constexpr size_t kFirstSize = size_t(1) << 12;
    static uint64_t pack(uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); }
    size_t slot(uint64_t key) const {
        return size_t((key * 0x9E3779B97F4A7C15ull) >> 32) & (slots_.size() - 1);
    }
    void grow() {
        std::vector<uint64_t> old(slots_.size() * 2, kEmpty);
        old.swap(slots_);
        for (const uint64_t entry : old) {
            if (entry == kEmpty) continue;
            size_t k = slot(entry >> 1);
            while (slots_[k] != kEmpty) k = (k + 1) & (slots_.size() - 1);
            slots_[k] = entry;
        }
    }

    size_t limit_;
    size_t count_ = 0;
    std::vector<uint64_t> slots_ = std::vector<uint64_t>(kFirstSize, kEmpty);
};

// Screen-space bins of polygon ids, so that the polygons whose window extents may overlap a
// polygon's are found without looking at all of them. A polygon is listed in every bin its x, y
// extent (widened by kOverlapMargin, held to the image) touches. Each bin is kept in order of
// farthest depth, farthest first, so that a search for the polygons reaching behind a depth stops
// at the first that does not; done polygons are dropped from a bin when a search passes them.
class BinGrid {
public:
    void reset(uint32_t width, uint32_t height) {
        // Bins of 8 pixels, or fewer bins for very large images.
        size_ = std::max(8.0, std::ceil(std::max(width, height) / 256.0));
        columns_ = int(std::ceil(width / size_));
        rows_ = int(std::ceil(height / size_));
        bins_.resize(size_t(columns_) * rows_);
        for (auto& bin : bins_) bin.clear();
    }

    struct Range {
        int c0, c1, r0, r1;
    };
    Range range(const Extent& e) const {
        auto column = [&](double x) { return std::clamp(int(std::floor(x / size_)), 0, columns_ - 1); };
        auto row = [&](double y) { return std::clamp(int(std::floor(y / size_)), 0, rows_ - 1); };
        return {column(e.x0 - kOverlapMargin), column(e.x1 + kOverlapMargin), row(e.y0 - kOverlapMargin),
                row(e.y1 + kOverlapMargin)};
    }

    void add(uint32_t id, const Extent& e) {
        const Range r = range(e);
        const Entry entry{e.z1, id};
        for (int y = r.r0; y <= r.r1; ++y)
            for (int x = r.c0; x <= r.c1; ++x) {
                std::vector<Entry>& bin = bins_[size_t(y) * columns_ + x];
                bin.insert(std::upper_bound(bin.begin(), bin.end(), entry,
                                            [](const Entry& a, const Entry& b) { return a.z1 > b.z1; }),
                           entry);
            }
    }

    // Calls visit(id) for each polygon not done in the bins of `e` whose farthest depth is beyond
    // `behind` or as far, and stopped_at(id) for the first polygon in a bin that is not (the search
    // of that bin stops there); a polygon may come more than once. Stops when visit returns true.
    template <class Visit, class StoppedAt>
    void for_each_near(const Extent& e, double behind, const std::vector<uint8_t>& done, Visit&& visit,
                       StoppedAt&& stopped_at) {
        const Range r = range(e);
        for (int y = r.r0; y <= r.r1; ++y)
            for (int x = r.c0; x <= r.c1; ++x) {
                std::vector<Entry>& bin = bins_[size_t(y) * columns_ + x];
                size_t kept = 0, k = 0;
                bool stop = false;
                for (; k < bin.size() && bin[k].z1 >= behind; ++k) {
                    if (done[bin[k].id] != 0) continue;
                    bin[kept++] = bin[k];
                    if (visit(bin[k].id)) {
                        stop = true;
                        ++k;
                        break;
                    }
                }
                if (!stop) {
                    while (k < bin.size() && done[bin[k].id] != 0) ++k;
                    if (k < bin.size()) stopped_at(bin[k].id);
                }
                bin.erase(bin.begin() + ptrdiff_t(kept), bin.begin() + ptrdiff_t(k));
                if (stop) return;
            }
    }

private:
    struct Entry {
        double z1;
        uint32_t id;
    };
    double size_ = 8.0;
    int columns_ = 0;
    int rows_ = 0;
    std::vector<std::vector<Entry>> bins_;
};

}  // namespace painter
