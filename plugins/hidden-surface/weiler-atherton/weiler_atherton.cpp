// weiler-atherton: hidden-surface removal by polygon area sorting (K. Weiler and P. Atherton, "Hidden
// Surface Removal Using Polygon Area Sorting", SIGGRAPH 1977, Computer Graphics 11(2), pp. 214-222).
// Object-space visibility: the polygons are sorted by their nearest depth; the front one becomes the
// clip polygon, every polygon overlapping it on screen is clipped into a piece inside it and pieces
// outside it; inside pieces behind the clip polygon are hidden and deleted; inside pieces in front of
// it somewhere start a recursive subdivision within the clip polygon's area; the outside pieces go on
// to the next clip polygon. The surviving fragments are the visible areas, disjoint on screen; they
// are drawn at the end, each as its original triangle's pixels inside it (widened by 1/64 pixel to
// close the cracks that snapping opens along cuts), so each pixel is written once but along cuts.
//
// The polygons are the triangles clipped to near/far and the camera's clip planes
// (GeometryStage::clipped_polygon), in clip space. Clipping against a convex clip polygon splits the
// subject by the clip-space planes (a, b, 0, c) of the clip polygon's window-space edges
// (raster::split_by_plane), so a subject's pieces tile it exactly. The paper's clipper keeps a
// concave outside remainder (with holes) as one polygon; here it is a set of convex pieces.
// docs/algorithms/weiler-atherton.md describes the steps, the counters and the parameters. The file
// is over 700 lines because the clipping, the area sort and the drawing share one frame's state.
#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using hsr::sdk::russian_plural;

namespace {

namespace raster = hsr::raster;
using hsr::sdk::ParamSpec;
using raster::ClipVertex;

// Pieces with less window-space area than this (pixels squared) are slivers left by rounding along
// edges that two polygons share; they are dropped (the widening at drawing covers what they hold).
constexpr double kSliverArea = 1e-9;
// Recursive subdivisions nested deeper than this are refused (a stack of polygons each in front of
// the last; real scenes nest a few levels).
constexpr int kMaxRecursion = 1000;
// Corners within this many pixels of a clip polygon's edge count as on it when deciding whether two
// polygons overlap at all (corners shared by neighbouring triangles land on either side by rounding).
constexpr double kTouch = 1e-7;
// A piece whose corners all lie within this NDC depth of the clip polygon's plane lies in it.
constexpr double kCoplanar = 1e-9;
// A visible fragment is drawn as the pixels of its original triangle whose centres lie inside the
// fragment widened by this many pixels (well above the 1/512 pixel that snapping moves a corner).
constexpr double kWidening = 1.0 / 64.0;

// An input polygon: the original triangle a fragment comes from.
struct Source {
    uint32_t face;
    uint32_t instance;
    glm::dvec4 plane;  // its clip-space plane, positive on the far side (behind it, seen from the camera)
    uint32_t first;    // its clipped polygon (GeometryStage::clipped_polygon) in source_corners_
    uint32_t count;
};

// A convex piece of a source polygon, corners in clip space.
struct Fragment {
    uint32_t first;  // in corners_
    uint32_t count;
    uint32_t source;
    double nearest;  // the nearest window depth of its corners
    float x0, y0, x1, y1;  // window-space bounds
};

class WeilerAtherton final : public hsr::sdk::StepwiseRemover<WeilerAtherton> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "weiler-atherton", "1.0.0",
        "Weiler-Atherton (1977): polygons clipped against polygons in object space, visible fragments rasterized"};
    static inline const ParamSpec params[] = {
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::integer("max-fragments", "1000000", 1000, 100000000,
                           "refuse a frame needing more input polygons and fragments than this (about 400 bytes each)"),
    };

    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"sort", "sort the polygons by nearest depth"},
        {"clip", "clip against the front polygon: inside and outside lists"},
        {"recurse", "pieces in front of it: subdivide within its area"},
        {"draw", "draw the visible fragments"},
    };

    static inline const hsr::sdk::TranslationSpec translations[] = {
        {"ru", "description",
         "алгоритм Вейлера — Азертона (1977): одни многоугольники отсекаются по другим в объектном пространстве, "
         "видимые фрагменты растеризуются"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не выводить треугольники, обращённые к камере обратной стороной"},
        {"ru", "param:max-fragments", "предельное число фрагментов"},
        {"ru", "help:max-fragments",
         "отказаться от кадра, которому нужно больше исходных многоугольников и фрагментов (около 400 байт на "
         "каждый)"},
        {"ru", "phase:sort", "упорядочить многоугольники по наименьшей глубине"},
        {"ru", "phase:clip", "отсечь по переднему многоугольнику: внутренний и внешний списки"},
        {"ru", "phase:recurse", "перед ним есть части: рекурсивное разбиение внутри его области"},
        {"ru", "phase:draw", "нарисовать видимые фрагменты"},
        {"ru", "counter:polygons-in", "многоугольников на входе"},
        {"ru", "counter:clips", "отсечений"},
        {"ru", "counter:fragments", "фрагментов получено"},
        {"ru", "counter:fragments-hidden", "фрагментов удалено как невидимые"},
        {"ru", "counter:fragments-visible", "видимых фрагментов"},
        {"ru", "counter:recursive-subdivisions", "рекурсивных разбиений"},
        {"ru", "counter:pixels-depth-tested", "пикселей проверено"},
        {"ru", "counter:pixels-written", "пикселей записано"},
        {"ru", "step:sort", "сортировка по глубине"},
        {"ru", "step:clip-polygon", "отсекающий многоугольник"},
        {"ru", "step:fragment", "видимый фрагмент"},
        {"ru", "step:recurse", "рекурсивное разбиение"},
    };

    explicit WeilerAtherton(const hsr::sdk::Params& p)
        : cull_backfaces_(p.boolean("cull-backfaces")), max_fragments_(uint64_t(p.integer("max-fragments"))) {}

    // render_steps (from StepwiseRemover) takes one step for the sort, one per clip polygon and per
    // recursive subdivision, then one per visible fragment rasterized.

private:
    struct Stats {
        uint64_t polygons_in = 0;
        uint64_t clips = 0;
        uint64_t fragments = 0;
        uint64_t hidden = 0;
        uint64_t visible = 0;
        uint64_t recursions = 0;
        uint64_t pixels_tested = 0;
        uint64_t pixels_written = 0;
        void report(hsr::sdk::Counters& counters) const {
            counters.set("polygons-in", polygons_in);
            counters.set("clips", clips);
            counters.set("fragments", fragments);
            counters.set("fragments-hidden", hidden);
            counters.set("fragments-visible", visible);
            counters.set("recursive-subdivisions", recursions);
            counters.set("pixels-depth-tested", pixels_tested);
            counters.set("pixels-written", pixels_written);
        }
    };

    // The window-space edges of a clip polygon as clip-space planes, positive inside.
    struct ClipRegion {
        uint32_t fragment;
        std::vector<glm::dvec4> edges;
    };

    friend class hsr::sdk::StepwiseRemover<WeilerAtherton>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        uint64_t triangles = 0;
        for (uint32_t k = 0; k < scene.placement_count(); ++k) triangles += scene.placement(k).triangle_count;
        if (triangles > max_fragments_) refuse();  // before holding any
        geometry_.begin_frame(scene.raw(), camera, cull_backfaces_);
        width_ = camera.width;
        height_ = camera.height;
        stats_ = Stats{};
        sources_.clear();
        source_corners_.clear();
        corners_.clear();
        fragments_.clear();
        visible_.clear();
        clip_stack_.clear();  // a frame stopped part way may have left it
        try {
            gather(scene);
            if constexpr (Steps::enabled) sort_step(steps);
            sort_areas(steps);
            rasterize(target, steps);
        } catch (const hsr::sdk::StepLimitReached&) {
            stats_.report(counters);
            throw;
        }
        stats_.report(counters);
    }

    // ------------------------------------------------------------------------------------------ //
    // Input polygons

    void gather(const hsr::sdk::Scene& scene) {
        const uint32_t* indices = scene.raw().indices;
        // The view's sides, widened by a pixel: what lies beyond hides nothing in the image.
        const double margin_x = 1.0 + 2.0 / width_, margin_y = 1.0 + 2.0 / height_;
        const glm::dvec4 sides[4] = {{1, 0, 0, margin_x}, {-1, 0, 0, margin_x}, {0, 1, 0, margin_y}, {0, -1, 0, margin_y}};
        ClipVertex polygon[raster::kMaxClipVertices + 4], scratch[raster::kMaxClipVertices + 4];
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            geometry_.place(placement);
            const uint32_t end = placement.first_triangle + placement.triangle_count;
            for (uint32_t t = placement.first_triangle; t < end; ++t) {
                ClipVertex clipped[raster::kMaxClipVertices];
                const int clipped_count = geometry_.clipped_polygon(t, clipped);
                if (clipped_count < 3) continue;
                int count = clipped_count;
                std::copy(clipped, clipped + count, polygon);
                for (const glm::dvec4& side : sides) {
                    count = raster::clip_against_plane(polygon, count, side, scratch);
                    std::copy(scratch, scratch + count, polygon);
                    if (count < 3) break;
                }
                if (count < 3) continue;
                glm::dvec4 plane = raster::plane_through(geometry_.clip_vertex(indices[3 * t]),
                                                         geometry_.clip_vertex(indices[3 * t + 1]),
                                                         geometry_.clip_vertex(indices[3 * t + 2]));
                const double length = glm::length(plane);
                if (!(length > 0.0) || !std::isfinite(length) || plane.z == 0.0) continue;  // edge-on
                plane /= plane.z > 0.0 ? length : -length;
                sources_.push_back({t, placement.instance, plane, uint32_t(source_corners_.size()), uint32_t(clipped_count)});
                if (add_fragment(polygon, count, uint32_t(sources_.size() - 1), false) != kNone) {
                    ++stats_.polygons_in;
                    source_corners_.insert(source_corners_.end(), clipped, clipped + clipped_count);
                } else {
                    sources_.pop_back();
                }
            }
        }
    }

    static constexpr uint32_t kNone = ~0u;

    // Stores a piece (made = it counts as a fragment made by clipping); kNone for a sliver or a
    // piece that cannot be projected.
    uint32_t add_fragment(const ClipVertex* polygon, int count, uint32_t source, bool made) {
        const raster::Viewport& viewport = geometry_.viewport();
        Fragment f{uint32_t(corners_.size()), uint32_t(count), source, std::numeric_limits<double>::infinity(),
                   std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                   -std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
        double area = 0.0, px = 0.0, py = 0.0;
        for (int k = 0; k <= count; ++k) {
            const glm::dvec4& c = polygon[k % count].position;
            if (!(c.w > 0.0)) return kNone;
            const glm::dvec3 w = viewport.project(c);
            if (!(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z))) return kNone;
            if (k > 0) area += px * w.y - w.x * py;
            px = w.x;
            py = w.y;
            if (k == count) break;
            f.nearest = std::min(f.nearest, w.z);
            f.x0 = std::min(f.x0, float(w.x));
            f.y0 = std::min(f.y0, float(w.y));
            f.x1 = std::max(f.x1, float(w.x));
            f.y1 = std::max(f.y1, float(w.y));
        }
        if (!(std::abs(area) > 2.0 * kSliverArea)) return kNone;
        if (made) count_fragment();
        corners_.insert(corners_.end(), polygon, polygon + count);
        fragments_.push_back(f);
        return uint32_t(fragments_.size() - 1);
    }

    // The fragment's corners, copied (corners_ may grow while they are used).
    void load(uint32_t id, std::vector<ClipVertex>& out) const {
        const Fragment& f = fragments_[id];
        out.assign(corners_.begin() + f.first, corners_.begin() + f.first + f.count);
    }

    ClipRegion region_of(uint32_t id) const {
        ClipRegion region{id, {}};
        const Fragment& f = fragments_[id];
        window_edges(corners_.data() + f.first, int(f.count), region.edges);
        return region;
    }

    // The window-space edges of a convex polygon as clip-space planes (a, b, 0, c), positive inside
    // and scaled so that dot(plane, p) / p.w is the distance from the edge in pixels.
    void window_edges(const ClipVertex* c, int count, std::vector<glm::dvec4>& edges) const {
        edges.clear();
        double area = 0.0;
        for (int k = 0; k < count; ++k) {
            const glm::dvec4& a = c[k].position;
            const glm::dvec4& b = c[(k + 1) % count].position;
            area += a.x / a.w * (b.y / b.w) - b.x / b.w * (a.y / a.w);
        }
        const double orientation = area > 0.0 ? 1.0 : -1.0;
        for (int k = 0; k < count; ++k) {
            const glm::dvec4& a = c[k].position;
            const glm::dvec4& b = c[(k + 1) % count].position;
            const double ax = a.x / a.w, ay = a.y / a.w, bx = b.x / b.w, by = b.y / b.w;
            // Inside is to the left of a -> b in NDC (y up) for a counter-clockwise polygon.
            const double ea = (ay - by) * orientation, eb = (bx - ax) * orientation;
            const double length = std::hypot(2.0 * ea / width_, 2.0 * eb / height_);
            if (!(std::hypot(ea * width_, eb * height_) > 2e-9)) continue;  // a repeated corner
            edges.push_back(glm::dvec4(ea, eb, 0.0, -(ea * ax + eb * ay)) / length);
        }
    }

    // An edge of `edges` has every corner of the polygon on its outside (or within kTouch pixels
    // of it): the polygons do not overlap.
    static bool separated_by(const std::vector<glm::dvec4>& edges, const ClipVertex* polygon, int count) {
        for (const glm::dvec4& edge : edges) {
            bool all_outside = true;
            for (int k = 0; k < count && all_outside; ++k)
                all_outside = glm::dot(edge, polygon[k].position) <= kTouch * polygon[k].position.w;
            if (all_outside) return true;
        }
        return false;
    }

    static bool boxes_overlap(const Fragment& a, const Fragment& b) {
        return a.x0 <= b.x1 && b.x0 <= a.x1 && a.y0 <= b.y1 && b.y0 <= a.y1;
    }

    // ------------------------------------------------------------------------------------------ //
    // Clipping one subject against a clip polygon

    enum class Clipped { kOutside, kConsumed };

    // Cuts subject q by the clip polygon's edges: the pieces outside go to `outside`, the piece
    // inside is left in piece_ (empty when there is none), and `cut` says whether q was cut.
    // kOutside: the polygons do not overlap and q is untouched (nor counted as a clip).
    template <class Steps>
    Clipped cut_by_region(const ClipRegion& region, uint32_t q, std::vector<uint32_t>& outside, bool& cut,
                          Steps& steps) {
        const Fragment clip = fragments_[region.fragment];
        const Fragment subject = fragments_[q];
        if (subject.source == clip.source || !boxes_overlap(clip, subject)) return Clipped::kOutside;
        load(q, piece_);
        if (separated_by(region.edges, piece_.data(), int(piece_.size()))) return Clipped::kOutside;
        window_edges(piece_.data(), int(piece_.size()), subject_edges_);
        if (separated_by(subject_edges_, corners_.data() + clip.first, int(clip.count))) return Clipped::kOutside;
        ++stats_.clips;
        cut = false;
        for (const glm::dvec4& edge : region.edges) {
            bool any_in = false, any_out = false;
            for (const ClipVertex& c : piece_) {
                const double d = glm::dot(edge, c.position);
                any_in |= d > 0.0;
                any_out |= d < 0.0;
            }
            if (!any_out) continue;
            if (!any_in) {  // what is left lies outside this edge (a cut left only a sliver inside)
                keep_outside(piece_.data(), int(piece_.size()), subject.source, outside, steps);
                piece_.clear();
                cut = true;
                return Clipped::kConsumed;
            }
            split(piece_, edge);
            keep_outside(back_.data(), back_count_, subject.source, outside, steps);
            piece_.assign(front_.begin(), front_.begin() + front_count_);
            cut = true;
        }
        return Clipped::kConsumed;
    }

    // Clips subject q against the clip polygon: pieces outside it go to `outside`; the piece inside
    // is compared with the clip polygon's plane: behind it, deleted; in front of it (or the part in
    // front, split off by that plane), appended to `front`. kOutside: q lies outside, untouched.
    template <class Steps>
    Clipped clip_subject(const ClipRegion& region, uint32_t q, std::vector<uint32_t>& outside,
                         std::vector<uint32_t>& front, Steps& steps) {
        bool cut = false;
        if (cut_by_region(region, q, outside, cut, steps) == Clipped::kOutside) return Clipped::kOutside;
        if (piece_.size() < 3) return Clipped::kConsumed;
        const Fragment clip = fragments_[region.fragment];
        const Fragment subject = fragments_[q];
        // piece_ is inside the clip polygon: compare it with the clip polygon's plane.
        const glm::dvec4& plane = sources_[clip.source].plane;
        bool any_behind = false, any_in_front = false, coplanar = true;
        for (const ClipVertex& c : piece_) {
            const double d = glm::dot(plane, c.position);
            any_behind |= d > 0.0;
            any_in_front |= d < 0.0;
            coplanar &= std::abs(d) <= kCoplanar * plane.z * c.position.w;
        }
        if (coplanar) {
            // In the clip polygon's plane: the one the z-buffer draws first stays in front.
            const Source& a = sources_[subject.source];
            const Source& b = sources_[clip.source];
            any_in_front = a.instance < b.instance || (a.instance == b.instance && a.face < b.face);
            any_behind = false;
        }
        if (!any_in_front) {
            hide(piece_.data(), int(piece_.size()), cut, steps);
            return Clipped::kConsumed;
        }
        if (any_behind) {
            split(piece_, -plane);  // front_ = the part nearer the camera
            hide(back_.data(), back_count_, true, steps);
            piece_.assign(front_.begin(), front_.begin() + front_count_);
            cut = true;
        }
        if (on_stack(subject.source)) {
            // The paper's guard against cycles: a polygon already clipping at an outer level is not
            // taken again (only a sliver along its own edges can get here).
            hide(piece_.data(), int(piece_.size()), cut, steps);
            return Clipped::kConsumed;
        }
        const uint32_t id = cut ? add_fragment(piece_.data(), int(piece_.size()), subject.source, true) : q;
        if (id != kNone) front.push_back(id);
        return Clipped::kConsumed;
    }

    void split(const std::vector<ClipVertex>& in, const glm::dvec4& plane) {
        const size_t room = in.size() + 2;
        if (front_.size() < room) front_.resize(room);
        if (back_.size() < room) back_.resize(room);
        raster::split_by_plane(in.data(), int(in.size()), plane, front_.data(), front_count_, back_.data(), back_count_);
    }

    template <class Steps>
    void keep_outside(const ClipVertex* polygon, int count, uint32_t source, std::vector<uint32_t>& outside,
                      Steps& steps) {
        if (count < 3) return;
        const uint32_t id = add_fragment(polygon, count, source, true);
        if (id == kNone) return;
        outside.push_back(id);
        if constexpr (Steps::enabled) outline(steps, polygon, count, HSR_STEP_CONTEXT);
    }

    template <class Steps>
    void hide(const ClipVertex* polygon, int count, bool made, Steps& steps) {
        if (count < 3) return;
        if (made) {
            if (!(window_area(polygon, count) > 2.0 * kSliverArea)) return;
            count_fragment();
        }
        ++stats_.hidden;
        if constexpr (Steps::enabled) outline(steps, polygon, count, HSR_STEP_REJECTED);
    }

    // The fragment limit bounds the memory of a frame: input polygons and fragments together.
    void count_fragment() {
        if (++stats_.fragments > max_fragments_ - std::min(max_fragments_, stats_.polygons_in)) refuse();
    }

    [[noreturn]] void refuse() const {
        throw hsr::sdk::Unsupported("weiler-atherton: the frame needs more than " + std::to_string(max_fragments_) +
                                    " polygons and fragments (parameter max-fragments)");
    }

    double window_area(const ClipVertex* polygon, int count) const {
        double area = 0.0;
        for (int k = 0; k < count; ++k) {
            const glm::dvec3 a = geometry_.viewport().project(polygon[k].position);
            const glm::dvec3 b = geometry_.viewport().project(polygon[(k + 1) % count].position);
            area += a.x * b.y - b.x * a.y;
        }
        return std::abs(area);
    }

    bool on_stack(uint32_t source) const {
        return std::find(clip_stack_.begin(), clip_stack_.end(), source) != clip_stack_.end();
    }

    // ------------------------------------------------------------------------------------------ //
    // Area sorting

    // The top level: every polygon in order of nearest depth, candidates found through screen bins.
    template <class Steps>
    void sort_areas(Steps& steps) {
        const int32_t bins_x = int32_t((width_ + kBinSize - 1) / kBinSize);
        const int32_t bins_y = int32_t((height_ + kBinSize - 1) / kBinSize);
        bins_.assign(size_t(bins_x) * bins_y, {});
        alive_.assign(fragments_.size(), 1);
        seen_.assign(fragments_.size(), 0);
        uint32_t stamp = 0;
        auto bin_range = [&](const Fragment& f, int32_t& bx0, int32_t& by0, int32_t& bx1, int32_t& by1) {
            bx0 = std::clamp(int32_t(std::floor(f.x0 / kBinSize)), 0, bins_x - 1);
            by0 = std::clamp(int32_t(std::floor(f.y0 / kBinSize)), 0, bins_y - 1);
            bx1 = std::clamp(int32_t(std::floor(f.x1 / kBinSize)), 0, bins_x - 1);
            by1 = std::clamp(int32_t(std::floor(f.y1 / kBinSize)), 0, bins_y - 1);
        };
        auto later = [&](uint32_t a, uint32_t b) {  // heap order: nearest first, then the older fragment
            return fragments_[a].nearest > fragments_[b].nearest ||
                   (fragments_[a].nearest == fragments_[b].nearest && a > b);
        };
        std::vector<uint32_t> heap;
        auto insert = [&](uint32_t id) {
            if (alive_.size() <= id) {
                alive_.resize(id + 1, 0);
                seen_.resize(id + 1, 0);
            }
            alive_[id] = 1;
            int32_t bx0, by0, bx1, by1;
            bin_range(fragments_[id], bx0, by0, bx1, by1);
            for (int32_t by = by0; by <= by1; ++by)
                for (int32_t bx = bx0; bx <= bx1; ++bx) bins_[size_t(by) * bins_x + bx].push_back(id);
            heap.push_back(id);
            std::push_heap(heap.begin(), heap.end(), later);
        };
        for (uint32_t id = 0; id < fragments_.size(); ++id) insert(id);

        std::vector<uint32_t> candidates, outside, front;
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end(), later);
            const uint32_t c = heap.back();
            heap.pop_back();
            if (!alive_[c]) continue;
            alive_[c] = 0;
            const ClipRegion region = region_of(c);
            int32_t bx0, by0, bx1, by1;
            bin_range(fragments_[c], bx0, by0, bx1, by1);
            ++stamp;
            candidates.clear();
            for (int32_t by = by0; by <= by1; ++by)
                for (int32_t bx = bx0; bx <= bx1; ++bx) {
                    std::vector<uint32_t>& bin = bins_[size_t(by) * bins_x + bx];
                    for (size_t k = 0; k < bin.size();) {
                        const uint32_t id = bin[k];
                        if (!alive_[id]) {  // consumed: drop it from the bin
                            bin[k] = bin.back();
                            bin.pop_back();
                            continue;
                        }
                        ++k;
                        if (seen_[id] == stamp) continue;
                        seen_[id] = stamp;
                        candidates.push_back(id);
                    }
                }
            std::sort(candidates.begin(), candidates.end());  // bins hold them in no fixed order
            outside.clear();
            front.clear();
            const uint64_t hidden_before = stats_.hidden;
            for (uint32_t q : candidates)
                if (clip_subject(region, q, outside, front, steps) == Clipped::kConsumed) alive_[q] = 0;
            clip_step(c, candidates.size(), stats_.hidden - hidden_before, outside.size(), front.size(), steps);
            finish_clip_polygon(c, front, 0, steps);
            for (uint32_t id : outside) insert(id);
        }
    }

    // Below the top level: the fragments `list`, all in front of the clip polygons above, sorted
    // among themselves the same way (few of them: no bins).
    template <class Steps>
    void sort_areas(std::vector<uint32_t> list, int depth, Steps& steps) {
        std::vector<uint32_t> outside, front;
        while (!list.empty()) {
            std::sort(list.begin(), list.end(), [&](uint32_t a, uint32_t b) {
                return fragments_[a].nearest < fragments_[b].nearest ||
                       (fragments_[a].nearest == fragments_[b].nearest && a < b);
            });
            const uint32_t c = list.front();
            const ClipRegion region = region_of(c);
            outside.clear();
            front.clear();
            const uint64_t hidden_before = stats_.hidden;
            size_t clipped = 0;
            for (size_t k = 1; k < list.size(); ++k) {
                ++clipped;
                if (clip_subject(region, list[k], outside, front, steps) == Clipped::kOutside)
                    outside.push_back(list[k]);
            }
            clip_step(c, clipped, stats_.hidden - hidden_before, outside.size(), front.size(), steps);
            finish_clip_polygon(c, front, depth, steps);
            list.swap(outside);
        }
    }

    // The clip polygon c after its subjects were clipped: visible when nothing lies in front of
    // it; otherwise the fragments in front are sorted recursively within its area, and what they
    // leave of it is visible.
    template <class Steps>
    void finish_clip_polygon(uint32_t c, const std::vector<uint32_t>& front, int depth, Steps& steps) {
        if (front.empty()) {
            visible_.push_back(c);
            return;
        }
        ++stats_.recursions;
        if (depth >= kMaxRecursion)
            throw hsr::sdk::Unsupported("weiler-atherton: polygons in front of one another nest deeper than " +
                                        std::to_string(kMaxRecursion) + " levels");
        if constexpr (Steps::enabled) recurse_step(c, front, steps);
        clip_stack_.push_back(fragments_[c].source);
        sort_areas(front, depth + 1, steps);
        clip_stack_.pop_back();
        // What the fragments in front leave of c.
        std::vector<uint32_t> remains{c}, next, outside;
        for (uint32_t f : front) {
            const ClipRegion region = region_of(f);
            next.clear();
            for (uint32_t r : remains) {
                outside.clear();
                if (clip_subject_behind(region, r, outside) == Clipped::kOutside)
                    next.push_back(r);
                else
                    next.insert(next.end(), outside.begin(), outside.end());
            }
            remains.swap(next);
        }
        visible_.insert(visible_.end(), remains.begin(), remains.end());
    }

    // clip_subject for a subject known to lie behind the clip polygon: its inside piece is hidden.
    Clipped clip_subject_behind(const ClipRegion& region, uint32_t q, std::vector<uint32_t>& outside) {
        hsr::sdk::NoSteps quiet;
        bool cut = false;
        if (cut_by_region(region, q, outside, cut, quiet) == Clipped::kOutside) return Clipped::kOutside;
        hide(piece_.data(), int(piece_.size()), cut, quiet);
        return Clipped::kConsumed;
    }

    template <class Steps>
    void clip_step(uint32_t c, size_t clipped, uint64_t hidden, size_t outside, size_t front, Steps& steps) {
        if constexpr (Steps::enabled) {
            const Fragment& f = fragments_[c];
            outline(steps, corners_.data() + f.first, int(f.count), HSR_STEP_SUBJECT);
            const Source& s = sources_[f.source];
            hsr::sdk::Steps::Event event{"clip-polygon", s.face, s.instance, HSR_NO_LEVEL, 0, 0};
            event.phase = "clip";
            const unsigned long long nearby = clipped;
            if (steps.russian())
                steps.step(event, "отсекающий многоугольник — треугольник %llu; рядом %llu %s; частей скрыто: %llu, "
                                  "вне его: %llu, перед ним: %llu",
                           (unsigned long long)s.face, nearby,
                           russian_plural(nearby, "многоугольник", "многоугольника", "многоугольников"),
                           (unsigned long long)hidden, (unsigned long long)outside, (unsigned long long)front);
            else
                steps.step(event, "clip polygon of triangle %llu: %llu polygons near it, %llu pieces hidden, %llu outside, %llu in front",
                           (unsigned long long)s.face, nearby, (unsigned long long)hidden, (unsigned long long)outside,
                           (unsigned long long)front);
        }
    }

    template <class Steps>
    void sort_step(Steps& steps) {
        const unsigned long long count = fragments_.size();
        hsr::sdk::Steps::Event event{"sort"};
        event.phase = "sort";
        if (steps.russian())
            steps.step(event, "многоугольники упорядочены по наименьшей глубине, ближние первыми: %llu %s", count,
                       russian_plural(count, "многоугольник", "многоугольника", "многоугольников"));
        else
            steps.step(event, "%llu polygon%s sorted by nearest depth, the nearest first", count, count == 1 ? "" : "s");
    }

    // Pieces lie in front of clip polygon c somewhere: they are sorted again, within c's area.
    template <class Steps>
    void recurse_step(uint32_t c, const std::vector<uint32_t>& front, Steps& steps) {
        const Fragment& f = fragments_[c];
        outline(steps, corners_.data() + f.first, int(f.count), HSR_STEP_CONTEXT);
        for (uint32_t id : front) {
            const Fragment& piece = fragments_[id];
            outline(steps, corners_.data() + piece.first, int(piece.count), HSR_STEP_SUBJECT);
        }
        const Source& s = sources_[f.source];
        hsr::sdk::Steps::Event event{"recurse", s.face, s.instance};
        event.phase = "recurse";
        const unsigned long long count = front.size(), face = s.face;
        if (steps.russian())
            steps.step(event, "перед отсекающим многоугольником (треугольник %llu) %s %llu %s: рекурсивное "
                              "разбиение внутри его области",
                       face, count % 10 == 1 && count % 100 != 11 ? "лежит" : "лежат", count,
                       russian_plural(count, "часть", "части", "частей"));
        else
            steps.step(event, "%llu piece%s in front of the clip polygon of triangle %llu: sorted again within its area",
                       count, count == 1 ? "" : "s", face);
    }

    template <class Steps>
    void outline(Steps& steps, const ClipVertex* polygon, int count, hsr_step_role role) const {
        const float w = float(width_), h = float(height_);
        for (int k = 0; k < count; ++k) {
            const glm::dvec3 a = geometry_.viewport().project(polygon[k].position);
            const glm::dvec3 b = geometry_.viewport().project(polygon[(k + 1) % count].position);
            steps.line(std::clamp(float(a.x), 0.0f, w), std::clamp(float(a.y), 0.0f, h),
                       std::clamp(float(b.x), 0.0f, w), std::clamp(float(b.y), 0.0f, h), role);
        }
    }

    // ------------------------------------------------------------------------------------------ //
    // Rasterizing the visible fragments

    template <class Steps>
    void rasterize(hsr::sdk::VisibilityBuffer& target, Steps& steps) {
        stats_.visible = visible_.size();
        if (target.depth_tests() == nullptr)
            rasterize<false>(target, steps);
        else
            rasterize<true>(target, steps);
    }

    // Each visible fragment as the pixels of its original triangle (the z-buffer's coverage, depth
    // and barycentrics) whose centres lie in the fragment widened by kWidening. The fragments tile
    // the visible area up to rounding at their cuts, where snapping a cut's corners would open
    // cracks or overlaps one pixel centre wide; the widening turns the cracks into overlaps, and a
    // depth test decides those (nearer, then the lower instance and face, as the z-buffer's order).
    template <bool kCountTests, class Steps>
    void rasterize(hsr::sdk::VisibilityBuffer& target, Steps& steps) {
        const raster::PixelBuffers buffers(target);
        for (uint32_t id : visible_) {
            const Fragment f = fragments_[id];
            const Source& s = sources_[f.source];
            window_edges(corners_.data() + f.first, int(f.count), subject_edges_);
            for (glm::dvec4& edge : subject_edges_) edge.w += kWidening;  // dot / w moves out by kWidening pixels
            // Pixels whose centres may lie in the widened fragment.
            const int32_t x0 = int32_t(std::ceil(f.x0 - kWidening - 0.5)), x1 = int32_t(std::floor(f.x1 + kWidening - 0.5));
            const int32_t y0 = int32_t(std::ceil(f.y0 - kWidening - 0.5)), y1 = int32_t(std::floor(f.y1 + kWidening - 0.5));
            raster::DepthTest<raster::DepthRule::kNearerThenLowerId, kCountTests> test(buffers, s.face, s.instance);
            const double to_ndc_x = 2.0 / width_, to_ndc_y = 2.0 / height_;
            geometry_.rasterize_polygon(source_corners_.data() + s.first, int(s.count), [&](const raster::TriangleSetup& setup) {
                const int32_t rx0 = std::max(x0, setup.min_x), rx1 = std::min(x1, setup.max_x);
                const int32_t ry0 = std::max(y0, setup.min_y), ry1 = std::min(y1, setup.max_y);
                if (rx0 > rx1 || ry0 > ry1) return;
                raster::for_each_covered_pixel_in(setup, rx0, ry0, rx1, ry1, [&](int32_t x, int32_t y, double i, double j) {
                    const glm::dvec4 centre((x + 0.5) * to_ndc_x - 1.0, 1.0 - (y + 0.5) * to_ndc_y, 0.0, 1.0);
                    for (const glm::dvec4& edge : subject_edges_)
                        if (glm::dot(edge, centre) < 0.0) return;
                    test(setup, x, y, i, j);
                });
            });
            stats_.pixels_tested += test.tested;
            stats_.pixels_written += test.written;
            if constexpr (Steps::enabled) {
                outline(steps, corners_.data() + f.first, int(f.count), HSR_STEP_WRITTEN);
                hsr::sdk::Steps::Event event{"fragment", s.face, s.instance, HSR_NO_LEVEL, test.written,
                                             test.tested - test.written};
                event.phase = "draw";
                const unsigned long long written = test.written;
                if (steps.russian())
                    steps.step(event, "видимый фрагмент треугольника %llu: записано %llu %s", (unsigned long long)s.face,
                               written, russian_plural(written, "пиксель", "пикселя", "пикселей"));
                else
                    steps.step(event, "visible fragment of triangle %llu: %llu pixels written",
                               (unsigned long long)s.face, written);
            }
        }
    }

    static constexpr float kBinSize = 8.0f;

    bool cull_backfaces_;
    uint64_t max_fragments_;
    uint32_t width_ = 0, height_ = 0;
    raster::GeometryStage geometry_;
    Stats stats_;
    std::vector<Source> sources_;
    std::vector<ClipVertex> source_corners_;
    std::vector<ClipVertex> corners_;
    std::vector<Fragment> fragments_;
    std::vector<uint32_t> visible_;
    std::vector<uint32_t> clip_stack_;  // sources of the clip polygons of the enclosing recursions
    std::vector<std::vector<uint32_t>> bins_;
    std::vector<uint8_t> alive_;
    std::vector<uint32_t> seen_;
    std::vector<ClipVertex> piece_, front_, back_;
    std::vector<glm::dvec4> subject_edges_;
    int front_count_ = 0, back_count_ = 0;
};

}  // namespace

HSR_EXPORT_PLUGIN(WeilerAtherton)
