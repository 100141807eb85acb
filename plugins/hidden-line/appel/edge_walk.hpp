// The walk along one edge in Appel's algorithm (step 6 of docs/algorithms/appel.md): given the QI
// just after its first vertex, where along the edge its QI changes. It changes where the edge passes
// behind a contour edge (the contour edge pierces the triangle the eye makes with the edge) and
// where it passes through a face (bodies that intersect); the grids of ViewGeometry give the
// candidates, each tested once per walk.
#pragma once

#include "view_geometry.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace appel {
// Internal linkage: only appel.cpp includes this, and so the compiler inlines the grid traversal
// into walk as it would in one file.
namespace {

// Changes of QI closer than this along an edge (as a fraction of it) happen at one point: where an
// edge passes behind the vertex of a contour, for example.
constexpr double kSameParameter = 1e-9;

inline constexpr uint32_t kNoContour = 0xFFFFFFFFu;

struct QiChange {
    double t;    // along the walk, 0 at its first vertex
    int32_t qi;  // after the change
    uint32_t face;
    uint32_t contour;  // the contour edge passed behind (ViewGeometry::contours), or kNoContour: a face pierced
};

struct WalkCounts {
    uint64_t edges_walked = 0, crossing_tests = 0, crossings = 0, piercing_tests = 0, piercings = 0;
    uint64_t qi_changes = 0, qi_conflicts = 0;
};

class EdgeWalk {
public:
    // Ready to walk the edges of `geometry`; with use_grid off, every contour edge is tested.
    void start(const ViewGeometry& geometry, const Viewer& viewer, bool use_grid) {
        geometry_ = &geometry;
        viewer_ = &viewer;
        use_grid_ = use_grid;
        counts_ = {};
        contour_stamp_.assign(geometry.contours.size(), 0);
        face_stamp_.assign(geometry.graph.face_count(), 0);
        stamp_ = 0;
    }

    // Walks the edge from vertex `from` to vertex `to`, starting with QI qi_start just after `from`:
    // collects where its QI changes (into changes()) and returns the QI just before `to`.
    int32_t walk(uint32_t from, uint32_t to, int32_t qi_start) {
        const ViewGeometry& g = *geometry_;
        ++counts_.edges_walked;
        crossings_.clear();
        const glm::dvec3& a = g.position[from];
        const glm::dvec3& b = g.position[to];
        const SightPlane walked = sight_plane(*viewer_, from, a, to, b);

        // Passing behind a contour edge: it pierces the triangle (eye, a, b).
        auto test_contour = [&](uint32_t index) {
            const ContourEdge& c = g.contours[index];
            if (c.v0 == from || c.v0 == to || c.v1 == from || c.v1 == to) return;  // the vertex rule's business
            ++counts_.crossing_tests;
            const glm::dvec3& c0 = g.position[c.v0];
            const glm::dvec3& c1 = g.position[c.v1];
            const int s0 = walked.side(c0), s1 = walked.side(c1);
            if (s0 == s1 || s0 == 0 || s1 == 0) return;
            const int side_a = c.plane.side(a), side_b = c.plane.side(b);
            if (side_a == side_b || side_a == 0 || side_b == 0) return;
            // The images cross. The contour edge is the nearer one when the volume of a, b, c0, c1
            // has the sign with which c1 lies on the walked edge's sight plane; 0 means the two
            // edges meet in space, and a point on a face counts as just in front of it.
            const double t = c.plane.crossing(a, b);
            if (walked.value(c0) != 0.0 || walked.value(c1) != 0.0) {
                const double volume = glm::dot(b - a, glm::cross(c0 - a, c1 - a));
                if (sign_of(volume) != s1) return;
            } else {
                // Both edges in one plane through the eye: the volume is 0 whatever their depths,
                // so compare the points where the (tie-broken) crossing puts them.
                const double s = walked.crossing(c0, c1);
                if (!(viewer_->distance(c0 + s * (c1 - c0)) < viewer_->distance(a + t * (b - a)))) return;
            }
            ++counts_.crossings;
            crossings_.push_back({t, side_b > 0 ? c.weight : -c.weight, c.face, index});
        };
        next_stamp();  // one stamp per walk, for contour edges and faces alike
        if (use_grid_) {
            g.contour_grid.for_segment(g.window[from], g.window[to], [&](uint32_t cell) {
                for (const uint32_t c : g.contour_bins[cell]) {
                    if (contour_stamp_[c] == stamp_) continue;
                    contour_stamp_[c] = stamp_;
                    test_contour(c);
                }
            });
        } else {
            for (uint32_t c = 0; c < g.contours.size(); ++c) test_contour(c);
        }

        // Passing through a face (where bodies intersect): the face starts or stops hiding the edge.
        const glm::vec3 low(glm::min(a, b)), high(glm::max(a, b));
        g.space_grid.for_segment(a, b, [&](uint32_t cell) {
            for (const uint32_t f : g.space_bins[cell]) {
                if (face_stamp_[f] == stamp_) continue;
                face_stamp_[f] = stamp_;
                const FaceBox& box = g.face_box[f];
                if (high.x < box.low.x || high.y < box.low.y || high.z < box.low.z || low.x > box.high.x ||
                    low.y > box.high.y || low.z > box.high.z)
                    continue;
                const FacePlane& plane = g.face_plane[f];
                if (plane.eye_side == 0 || g.graph.face_has(f, from) || g.graph.face_has(f, to)) continue;
                ++counts_.piercing_tests;
                const double da = glm::dot(plane.normal, a - plane.corner), db = glm::dot(plane.normal, b - plane.corner);
                const bool hidden_a = sign_of(da) == -plane.eye_side, hidden_b = sign_of(db) == -plane.eye_side;
                if (hidden_a == hidden_b) continue;
                if (!line_meets_triangle(a, b, f)) continue;
                ++counts_.piercings;
                const double t = std::clamp(da / (da - db), 0.0, 1.0);
                crossings_.push_back({t, hidden_b ? 1 : -1, f, kNoContour});
            }
        });

        // Changes at one point are one change; none is made of changes that cancel.
        std::sort(crossings_.begin(), crossings_.end(), [](const Crossing& x, const Crossing& y) { return x.t < y.t; });
        changes_.clear();
        int32_t qi = qi_start;
        for (size_t k = 0; k < crossings_.size();) {
            const double t = crossings_[k].t;
            int32_t delta = 0;
            uint32_t face = HSR_NO_FACE, contour = kNoContour;
            for (; k < crossings_.size() && crossings_[k].t - t <= kSameParameter; ++k) {
                delta += crossings_[k].delta;
                face = crossings_[k].face;
                contour = crossings_[k].contour;
            }
            if (delta == 0) continue;
            qi += delta;
            if (qi < 0) ++counts_.qi_conflicts;
            changes_.push_back({t, qi, face, contour});
        }
        counts_.qi_changes += changes_.size();
        return qi;
    }

    // Where the QI of the last walked edge changes, in order along it.
    const std::vector<QiChange>& changes() const { return changes_; }
    const WalkCounts& counts() const { return counts_; }

private:
    struct Crossing {
        double t;       // along the walk, 0 at its first vertex
        int32_t delta;  // change of QI
        uint32_t face;  // the face that starts or stops hiding the edge
        uint32_t contour;
    };

    // Does the line through a and b pass through the inside of face f? Signed volumes of the line
    // with the face's sides, each side taken in one fixed vertex order (lower index first) so that
    // two faces sharing a side never both claim a line through it.
    bool line_meets_triangle(const glm::dvec3& a, const glm::dvec3& b, uint32_t f) const {
        const ViewGeometry& g = *geometry_;
        const glm::dvec3 toward_eye = viewer_->perspective() ? viewer_->eye() - a : viewer_->toward_viewer();
        int first = 0;
        for (int k = 0; k < 3; ++k) {
            uint32_t p = g.graph.corner(f, k), q = g.graph.corner(f, (k + 1) % 3);
            int flip = 1;
            if (p > q) {
                std::swap(p, q);
                flip = -1;
            }
            const glm::dvec3& pp = g.position[p];
            const glm::dvec3& pq = g.position[q];
            double volume = glm::dot(b - a, glm::cross(pp - a, pq - a));
            // Through the side itself: decide as for the line moved slightly toward the eye, the
            // same rule by which a point on a face's plane is in front of the face.
            if (volume == 0.0) volume = -glm::dot(b - a, glm::cross(toward_eye, pq - pp));
            const int side = flip * (volume >= 0.0 ? 1 : -1);
            if (k == 0)
                first = side;
            else if (side != first)
                return false;
        }
        return true;
    }

    void next_stamp() {
        if (++stamp_ == 0) {
            std::fill(contour_stamp_.begin(), contour_stamp_.end(), 0);
            std::fill(face_stamp_.begin(), face_stamp_.end(), 0);
            stamp_ = 1;
        }
    }

    const ViewGeometry* geometry_ = nullptr;
    const Viewer* viewer_ = nullptr;
    bool use_grid_ = true;
    // Kept between calls to reuse their memory.
    std::vector<uint32_t> contour_stamp_, face_stamp_;
    uint32_t stamp_ = 0;
    std::vector<Crossing> crossings_;
    std::vector<QiChange> changes_;
    WalkCounts counts_;
};

}  // namespace
}  // namespace appel
