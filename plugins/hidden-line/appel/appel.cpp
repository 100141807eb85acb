// appel: hidden lines by quantitative invisibility, after Arthur Appel, "The notion of quantitative
// invisibility and the machine rendering of solids", Proceedings of the ACM National Conference, 1967.
//
// The quantitative invisibility (QI) of a point is the number of faces between it and the eye. It
// can only change where the point's line of sight sweeps across a contour edge (a silhouette between
// a face turned toward the eye and one turned away, or a boundary of an open surface), or where the
// point passes through a face. So it is counted directly only once per connected part of the mesh,
// at a seed vertex, and then carried along the edges: an edge walked from a vertex of known QI
// changes its QI wherever it passes behind a contour edge (the contour edge pierces the triangle
// the eye makes with the walked edge) and wherever it pierces a face; corrections at the vertices
// (Appel's vertex rules) account for the faces around a vertex that hide an edge leaving it. Pieces
// with QI 0 are visible. docs/algorithms/appel.md describes the steps, the data and the limits.
#include "grids.hpp"
#include "mesh_graph.hpp"
#include "sight.hpp"

#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace {

using appel::FacePlane;
using appel::MeshGraph;
using appel::SightPlane;
using appel::Viewer;
using hsr::sdk::InvalidArgument;
using hsr::sdk::ParamSpec;

constexpr int32_t kUnknownQi = std::numeric_limits<int32_t>::min();
constexpr uint32_t kNone = 0xFFFFFFFFu;
// Changes of QI closer than this along an edge (as a fraction of it) happen at one point: where an
// edge passes behind the vertex of a contour, for example.
constexpr double kSameParameter = 1e-9;
// A seed vertex whose line of sight passes within this angle (radians, roughly) of a face's border
// or plane is avoided when another one is available.
constexpr double kSeedMargin = 1e-9;
// How many vertices of a component are tried as its seed.
constexpr size_t kSeedCandidates = 16;

struct ContourEdge {
    uint32_t v0, v1;
    int32_t weight;  // faces on the positive side of the sight plane minus faces on its negative side
    uint32_t face;   // a face of the edge, for the trace
    SightPlane plane;
};

struct FaceBox {
    glm::vec3 low, high;
};

struct Crossing {
    double t;       // along the walk, 0 at its first vertex
    int32_t delta;  // change of QI
    uint32_t face;  // the face that starts or stops hiding the edge
};

struct QiChange {
    double t;
    int32_t qi;  // after the change
    uint32_t face;
};

struct Statistics {
    uint64_t seeds = 0, seeds_ambiguous = 0, seed_face_tests = 0;
    uint64_t edges_walked = 0, crossing_tests = 0, crossings = 0, piercing_tests = 0, piercings = 0;
    uint64_t qi_changes = 0, qi_conflicts = 0;
};

class Appel final : public hsr::sdk::HiddenLineRemover {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "appel", "1.0.0",
        "Appel (1967) quantitative invisibility: QI counted at one vertex per part, carried along the edges, "
        "changed behind contour edges"};
    static inline const ParamSpec params[] = {
        ParamSpec::choice("prefilter", "grid", "grid|none",
                          "find the contour edges an edge may pass behind with a screen grid, or test every one"),
        ParamSpec::boolean("check-all-edges", false,
                           "walk every edge, not only a spanning tree and the requested ones, and count vertices "
                           "reached with two different QIs (qi-conflicts)"),
    };

    explicit Appel(const hsr::sdk::Params& p)
        : use_grid_(p.choice("prefilter") == 0), check_all_edges_(p.boolean("check-all-edges")) {}

    void render_lines(const hsr::sdk::Scene& scene, const hsr_camera& camera, const hsr::sdk::LineRequest& request,
                      hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace,
                      hsr::sdk::Counters& counters) override {
        validate(scene.raw(), camera);
        const Viewer viewer(camera);
        viewer_ = &viewer;
        camera_ = &camera;
        scene_ = &scene.raw();
        stats_ = {};
        graph_.build(scene.raw());
        prepare_vertices(scene.raw(), camera);
        prepare_faces(viewer);
        find_contours(viewer);
        build_grids();
        map_request(request);
        propagate(request, segments, trace);

        counters.set("triangles-in", graph_.face_count());
        counters.set("edges-in", graph_.edge_count());
        counters.set("contour-edges", contours_.size());
        counters.set("seeds", stats_.seeds);
        counters.set("seed-face-tests", stats_.seed_face_tests);
        counters.set("seeds-ambiguous", stats_.seeds_ambiguous);
        counters.set("edges-walked", stats_.edges_walked);
        counters.set("crossing-tests", stats_.crossing_tests);
        counters.set("crossings", stats_.crossings);
        counters.set("piercing-tests", stats_.piercing_tests);
        counters.set("piercings", stats_.piercings);
        counters.set("qi-changes", stats_.qi_changes);
        counters.set("qi-conflicts", stats_.qi_conflicts);
    }

private:
    static void validate(const hsr_scene& scene, const hsr_camera& camera) {
        auto fail = [](const std::string& message) { throw InvalidArgument("appel: " + message); };
        if (scene.struct_size < sizeof(hsr_scene)) fail("scene struct is smaller than the ABI this plugin was built with");
        if (camera.struct_size < sizeof(hsr_camera)) fail("camera struct is smaller than the ABI this plugin was built with");
        if (camera.width == 0 || camera.height == 0) fail("image has zero size");
        if (camera.projection_type != HSR_PROJECTION_PERSPECTIVE && camera.projection_type != HSR_PROJECTION_ORTHOGRAPHIC)
            fail("unknown projection type " + std::to_string(int(camera.projection_type)));
        for (float m : camera.view_projection)
            if (!std::isfinite(m)) fail("camera view_projection matrix is not finite");
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(camera.eye[k]) || !std::isfinite(camera.view_direction[k]))
                fail("camera eye or view direction is not finite");
        const glm::dvec3 d(camera.view_direction[0], camera.view_direction[1], camera.view_direction[2]);
        if (!(glm::length(d) > 0.0)) fail("camera view direction is zero");
    }

    // World positions in double precision and window positions; every vertex a face uses must be
    // finite and, for a perspective camera, in front of the eye.
    void prepare_vertices(const hsr_scene& scene, const hsr_camera& camera) {
        const uint32_t n = graph_.vertex_count();
        position_.resize(n);
        window_.resize(n);
        view_projection_ = glm::dmat4(hsr::sdk::load_matrix(camera.view_projection));
        const bool perspective = camera.projection_type == HSR_PROJECTION_PERSPECTIVE;
        for (uint32_t v = 0; v < n; ++v) {
            position_[v] = {scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]};
            if (graph_.faces_at(v).empty()) {
                window_[v] = glm::dvec2(0.0);
                continue;
            }
            if (!std::isfinite(position_[v].x) || !std::isfinite(position_[v].y) || !std::isfinite(position_[v].z))
                throw InvalidArgument("appel: vertex " + std::to_string(v) + " has a position that is not finite");
            const glm::dvec4 clip = view_projection_ * glm::dvec4(position_[v], 1.0);
            if (perspective && !(clip.w > 0.0))
                throw InvalidArgument("appel: vertex " + std::to_string(v) +
                                      " is not in front of the eye; with a perspective camera every vertex must be "
                                      "(move the camera out of the scene)");
            window_[v] = to_window(clip);
        }
    }

    glm::dvec2 to_window(const glm::dvec4& clip) const {
        return {(clip.x / clip.w + 1.0) * 0.5 * camera_->width, (1.0 - clip.y / clip.w) * 0.5 * camera_->height};
    }
    glm::dvec2 window_of(const glm::dvec3& p) const { return to_window(view_projection_ * glm::dvec4(p, 1.0)); }

    void prepare_faces(const Viewer& viewer) {
        face_plane_.resize(graph_.face_count());
        face_box_.resize(graph_.face_count());
        constexpr float kWiden = 1.0f / (1 << 21), kTiny = 1e-30f;
        for (uint32_t f = 0; f < graph_.face_count(); ++f) {
            const glm::dvec3 &a = position_[graph_.corner(f, 0)], &b = position_[graph_.corner(f, 1)],
                             &c = position_[graph_.corner(f, 2)];
            face_plane_[f] = appel::face_plane(viewer, a, b, c);
            // Widened by more than a float's rounding, so that the float box holds the face.
            const glm::vec3 low(glm::min(a, glm::min(b, c))), high(glm::max(a, glm::max(b, c)));
            face_box_[f].low = low - glm::abs(low) * kWiden - kTiny;
            face_box_[f].high = high + glm::abs(high) * kWiden + kTiny;
        }
    }

    // Contour edges: those whose faces do not lie equally on both sides of the plane through the eye
    // and the edge. A silhouette edge has both faces on one side (weight +-2), a boundary edge its one
    // face (+-1); an ordinary edge one on each side (0, not a contour).
    void find_contours(const Viewer& viewer) {
        contours_.clear();
        for (uint32_t e = 0; e < graph_.edge_count(); ++e) {
            const uint32_t a = graph_.edge_vertex(e, 0), b = graph_.edge_vertex(e, 1);
            const SightPlane plane = appel::sight_plane(viewer, a, position_[a], b, position_[b]);
            int32_t weight = 0;
            for (int side = 0; side < 2; ++side) {
                const uint32_t f = graph_.edge_face(e, side);
                if (f == HSR_NO_FACE || face_plane_[f].eye_side == 0) continue;
                weight += plane.side(position_[graph_.third_corner(f, a, b)]);
            }
            if (weight != 0) contours_.push_back({a, b, weight, graph_.edge_face(e, 0), plane});
        }
    }

    void build_grids() {
        // Contour edges on the screen, for the crossing tests.
        contour_stamp_.assign(contours_.size(), 0);
        if (!contours_.empty()) {
            glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
            for (const ContourEdge& c : contours_) {
                lo = glm::min(lo, glm::min(window_[c.v0], window_[c.v1]));
                hi = glm::max(hi, glm::max(window_[c.v0], window_[c.v1]));
            }
            contour_grid_.frame(lo, hi, 2.0 * double(contours_.size()), kPadPixels);
            contour_bins_.build(contour_grid_.cell_count(), [&](auto&& add) {
                for (uint32_t c = 0; c < contours_.size(); ++c)
                    contour_grid_.for_segment(window_[contours_[c].v0], window_[contours_[c].v1],
                                              [&](uint32_t cell) { add(cell, c); });
            });
        }

        // Faces on the screen, for counting what hides a seed vertex.
        glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        glm::dvec3 world_lo(std::numeric_limits<double>::max()), world_hi(-std::numeric_limits<double>::max());
        double edge_length = 0.0;
        for (uint32_t v = 0; v < graph_.vertex_count(); ++v) {
            if (graph_.faces_at(v).empty()) continue;
            lo = glm::min(lo, window_[v]);
            hi = glm::max(hi, window_[v]);
            world_lo = glm::min(world_lo, position_[v]);
            world_hi = glm::max(world_hi, position_[v]);
        }
        for (uint32_t e = 0; e < graph_.edge_count(); ++e)
            edge_length += glm::length(position_[graph_.edge_vertex(e, 1)] - position_[graph_.edge_vertex(e, 0)]);
        if (graph_.face_count() == 0) return;
        face_grid_.frame(lo, hi, std::max(1.0, graph_.face_count() / 2.0), kPadPixels);
        face_bins_.build(face_grid_.cell_count(), [&](auto&& add) {
            for (uint32_t f = 0; f < graph_.face_count(); ++f) {
                const glm::dvec2 a = window_[graph_.corner(f, 0)], b = window_[graph_.corner(f, 1)],
                                 c = window_[graph_.corner(f, 2)];
                face_grid_.for_box(glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c)),
                                   [&](uint32_t cell) { add(cell, f); });
            }
        });

        // Faces in space, for the faces an edge passes through (bodies that intersect).
        const double mean_edge = graph_.edge_count() > 0 ? edge_length / graph_.edge_count() : 0.0;
        const double extent = glm::length(world_hi - world_lo);
        space_grid_.frame(world_lo, world_hi, mean_edge, 1e-9 * extent, 4.0 * graph_.face_count());
        space_bins_.build(space_grid_.cell_count(), [&](auto&& add) {
            for (uint32_t f = 0; f < graph_.face_count(); ++f) {
                const glm::dvec3 &a = position_[graph_.corner(f, 0)], &b = position_[graph_.corner(f, 1)],
                                 &c = position_[graph_.corner(f, 2)];
                space_grid_.for_box(glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c)),
                                    [&](uint32_t cell) { add(cell, f); });
            }
        });
        face_stamp_.assign(graph_.face_count(), 0);
        stamp_ = 0;
    }

    // Which mesh edge each requested edge is (a list per mesh edge, in case one is asked for twice).
    void map_request(const hsr::sdk::LineRequest& request) {
        first_request_.assign(graph_.edge_count(), kNone);
        next_request_.assign(request.edge_count(), kNone);
        if (request.edge_count() > 0 &&
            (request.raw().edge_vertices == nullptr || request.raw().edge_faces == nullptr || request.raw().edge_flags == nullptr))
            throw InvalidArgument("appel: the line request has NULL arrays");
        for (uint32_t r = request.edge_count(); r-- > 0;) {
            const uint32_t a = request.vertex(r, 0), b = request.vertex(r, 1);
            uint32_t edge = kNone;
            for (int side = 0; side < 2 && edge == kNone; ++side) {
                const uint32_t f = request.face(r, side);
                if (f >= graph_.face_count()) continue;
                for (int i = 0; i < 3; ++i) {
                    const uint32_t c = graph_.corner(f, i), d = graph_.corner(f, (i + 1) % 3);
                    if ((c == a && d == b) || (c == b && d == a)) edge = graph_.side_edge(f, i);
                }
            }
            if (edge == kNone)
                throw InvalidArgument("appel: requested edge " + std::to_string(r) + " (vertices " + std::to_string(a) +
                                      "-" + std::to_string(b) + ") is not a side of the triangles it names");
            next_request_[r] = first_request_[edge];
            first_request_[edge] = r;
        }
    }

    // ------------------------------------------------------------------------------------------ //
    // The walk

    void propagate(const hsr::sdk::LineRequest& request, hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace) {
        const uint32_t vertex_count = graph_.vertex_count();
        qi_.assign(vertex_count, kUnknownQi);
        component_mark_.assign(vertex_count, 0);
        walked_.assign(graph_.edge_count(), 0);
        uint32_t component = 0;
        for (uint32_t start = 0; start < vertex_count; ++start) {
            if (component_mark_[start] != 0 || graph_.edges_at(start).empty()) continue;
            ++component;
            ++stats_.seeds;
            collect_component(start, component);
            const uint32_t seed = choose_seed();
            qi_[seed] = seed_qi_;
            if (trace.enabled()) trace_seed(seed, request, trace);

            queue_.clear();
            queue_.push_back(seed);
            for (size_t head = 0; head < queue_.size(); ++head) {
                const uint32_t v = queue_[head];
                for (const uint32_t e : graph_.edges_at(v)) {
                    if (walked_[e]) continue;
                    const uint32_t w = graph_.other_end(e, v);
                    const bool tree_edge = qi_[w] == kUnknownQi;
                    const bool requested = first_request_[e] != kNone;
                    if (!tree_edge && !requested && !check_all_edges_) continue;
                    walked_[e] = 1;
                    const int32_t qi_start = qi_[v] + faces_hiding_edge_start(v, w);
                    const int32_t qi_end = walk(v, w, qi_start);
                    if (requested) emit(e, v, w, qi_start, qi_end, request, segments, trace);
                    const int32_t qi_w = qi_end - faces_hiding_edge_start(w, v);
                    if (tree_edge) {
                        qi_[w] = qi_w;
                        queue_.push_back(w);
                    } else if (qi_w != qi_[w]) {
                        ++stats_.qi_conflicts;
                    }
                }
            }
        }
    }

    void collect_component(uint32_t start, uint32_t component) {
        members_.clear();
        members_.push_back(start);
        component_mark_[start] = component;
        for (size_t head = 0; head < members_.size(); ++head)
            for (const uint32_t e : graph_.edges_at(members_[head])) {
                const uint32_t w = graph_.other_end(e, members_[head]);
                if (component_mark_[w] == component) continue;
                component_mark_[w] = component;
                members_.push_back(w);
            }
    }

    // A vertex of the component whose line of sight passes clearly inside or outside every face, and
    // its QI counted directly (into seed_qi_).
    uint32_t choose_seed() {
        const size_t step = std::max<size_t>(1, members_.size() / kSeedCandidates);
        uint32_t fallback = members_[0];
        int32_t fallback_qi = 0;
        for (size_t k = 0; k < members_.size() && k / step < kSeedCandidates; k += step) {
            bool clean = true;
            const int32_t qi = faces_hiding_vertex(members_[k], clean);
            if (clean) {
                seed_qi_ = qi;
                return members_[k];
            }
            if (k == 0) fallback_qi = qi;
        }
        ++stats_.seeds_ambiguous;
        seed_qi_ = fallback_qi;
        return fallback;
    }

    // The QI of a vertex by counting: faces (not its own) whose image covers the vertex's image and
    // whose plane it lies behind. `clean` is cleared when the line of sight passes close to a face's
    // border or plane, where rounding could decide.
    int32_t faces_hiding_vertex(uint32_t s, bool& clean) {
        const glm::dvec3& p = position_[s];
        int32_t qi = 0;
        for (const uint32_t f : face_bins_[face_grid_.cell_of(window_[s])]) {
            if (graph_.face_has(f, s)) continue;
            const FacePlane& plane = face_plane_[f];
            if (plane.eye_side == 0) continue;
            ++stats_.seed_face_tests;
            bool inside = true, clearly_outside = false, clearly_inside = true;
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = graph_.corner(f, k), b = graph_.corner(f, (k + 1) % 3), c = graph_.corner(f, (k + 2) % 3);
                const SightPlane side = appel::sight_plane(*viewer_, a, position_[a], b, position_[b]);
                const double value = side.value(p);
                const bool near = std::abs(value) <= kSeedMargin * glm::length(side.normal) * glm::length(p - side.origin);
                if (side.side(p) != side.side(position_[c])) {
                    inside = false;
                    if (!near) clearly_outside = true;
                } else if (near) {
                    clearly_inside = false;
                }
            }
            if (!inside) {
                if (!clearly_outside) clean = false;
                continue;
            }
            const double depth = glm::dot(plane.normal, p - plane.corner);
            if (!clearly_inside || std::abs(depth) <= kSeedMargin * glm::length(plane.normal) * glm::length(p - plane.corner))
                clean = false;
            if (plane.hides(p)) ++qi;
        }
        return qi;
    }

    // Appel's vertex rule: how many faces around v (other than those of the edge v-w itself) hide the
    // edge from v toward w just after it leaves v. Such a face covers the edge's image near v when
    // the image of w lies inside the face's corner at v, and hides it when w is behind its plane.
    int32_t faces_hiding_edge_start(uint32_t v, uint32_t w) const {
        int32_t count = 0;
        const glm::dvec3& pv = position_[v];
        const glm::dvec3& pw = position_[w];
        for (const uint32_t f : graph_.faces_at(v)) {
            const FacePlane& plane = face_plane_[f];
            if (plane.eye_side == 0 || graph_.face_has(f, w)) continue;
            if (appel::sign_of(glm::dot(plane.normal, pw - pv)) != -plane.eye_side) continue;
            int k = 0;
            while (graph_.corner(f, k) != v) ++k;
            const uint32_t a = graph_.corner(f, (k + 1) % 3), b = graph_.corner(f, (k + 2) % 3);
            const SightPlane va = appel::sight_plane(*viewer_, v, pv, a, position_[a]);
            const int inner_a = va.side(position_[b]);
            if (inner_a == 0 || va.side(pw) != inner_a) continue;
            const SightPlane vb = appel::sight_plane(*viewer_, v, pv, b, position_[b]);
            const int inner_b = vb.side(position_[a]);
            if (inner_b == 0 || vb.side(pw) != inner_b) continue;
            ++count;
        }
        return count;
    }

    // Walks the edge from vertex `from` to vertex `to`, starting with QI qi_start just after `from`:
    // collects where its QI changes (into changes_) and returns the QI just before `to`.
    int32_t walk(uint32_t from, uint32_t to, int32_t qi_start) {
        ++stats_.edges_walked;
        crossings_.clear();
        const glm::dvec3& a = position_[from];
        const glm::dvec3& b = position_[to];
        const SightPlane walked = appel::sight_plane(*viewer_, from, a, to, b);

        // Passing behind a contour edge: it pierces the triangle (eye, a, b).
        auto test_contour = [&](uint32_t index) {
            const ContourEdge& c = contours_[index];
            if (c.v0 == from || c.v0 == to || c.v1 == from || c.v1 == to) return;  // the vertex rule's business
            ++stats_.crossing_tests;
            const glm::dvec3& c0 = position_[c.v0];
            const glm::dvec3& c1 = position_[c.v1];
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
                if (appel::sign_of(volume) != s1) return;
            } else {
                // Both edges in one plane through the eye: the volume is 0 whatever their depths,
                // so compare the points where the (tie-broken) crossing puts them.
                const double s = walked.crossing(c0, c1);
                if (!(viewer_->distance(c0 + s * (c1 - c0)) < viewer_->distance(a + t * (b - a)))) return;
            }
            ++stats_.crossings;
            crossings_.push_back({t, side_b > 0 ? c.weight : -c.weight, c.face});
        };
        next_stamp();  // one stamp per walk, for contour edges and faces alike
        if (use_grid_) {
            contour_grid_.for_segment(window_[from], window_[to], [&](uint32_t cell) {
                for (const uint32_t c : contour_bins_[cell]) {
                    if (contour_stamp_[c] == stamp_) continue;
                    contour_stamp_[c] = stamp_;
                    test_contour(c);
                }
            });
        } else {
            for (uint32_t c = 0; c < contours_.size(); ++c) test_contour(c);
        }

        // Passing through a face (where bodies intersect): the face starts or stops hiding the edge.
        const glm::vec3 low(glm::min(a, b)), high(glm::max(a, b));
        space_grid_.for_segment(a, b, [&](uint32_t cell) {
            for (const uint32_t f : space_bins_[cell]) {
                if (face_stamp_[f] == stamp_) continue;
                face_stamp_[f] = stamp_;
                const FaceBox& box = face_box_[f];
                if (high.x < box.low.x || high.y < box.low.y || high.z < box.low.z || low.x > box.high.x ||
                    low.y > box.high.y || low.z > box.high.z)
                    continue;
                const FacePlane& plane = face_plane_[f];
                if (plane.eye_side == 0 || graph_.face_has(f, from) || graph_.face_has(f, to)) continue;
                ++stats_.piercing_tests;
                const double da = glm::dot(plane.normal, a - plane.corner), db = glm::dot(plane.normal, b - plane.corner);
                const bool hidden_a = appel::sign_of(da) == -plane.eye_side, hidden_b = appel::sign_of(db) == -plane.eye_side;
                if (hidden_a == hidden_b) continue;
                if (!line_meets_triangle(a, b, f)) continue;
                ++stats_.piercings;
                const double t = std::clamp(da / (da - db), 0.0, 1.0);
                crossings_.push_back({t, hidden_b ? 1 : -1, f});
            }
        });

        // Changes at one point are one change; none is made of changes that cancel.
        std::sort(crossings_.begin(), crossings_.end(), [](const Crossing& x, const Crossing& y) { return x.t < y.t; });
        changes_.clear();
        int32_t qi = qi_start;
        for (size_t k = 0; k < crossings_.size();) {
            const double t = crossings_[k].t;
            int32_t delta = 0;
            uint32_t face = HSR_NO_FACE;
            for (; k < crossings_.size() && crossings_[k].t - t <= kSameParameter; ++k) {
                delta += crossings_[k].delta;
                face = crossings_[k].face;
            }
            if (delta == 0) continue;
            qi += delta;
            if (qi < 0) ++stats_.qi_conflicts;
            changes_.push_back({t, qi, face});
        }
        stats_.qi_changes += changes_.size();
        return qi;
    }

    // Does the line through a and b pass through the inside of face f? Signed volumes of the line
    // with the face's sides, each side taken in one fixed vertex order (lower index first) so that
    // two faces sharing a side never both claim a line through it.
    bool line_meets_triangle(const glm::dvec3& a, const glm::dvec3& b, uint32_t f) const {
        const glm::dvec3 toward_eye = viewer_->perspective() ? viewer_->eye() - a : viewer_->toward_viewer();
        int first = 0;
        for (int k = 0; k < 3; ++k) {
            uint32_t p = graph_.corner(f, k), q = graph_.corner(f, (k + 1) % 3);
            int flip = 1;
            if (p > q) {
                std::swap(p, q);
                flip = -1;
            }
            const glm::dvec3& pp = position_[p];
            const glm::dvec3& pq = position_[q];
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

    // ------------------------------------------------------------------------------------------ //
    // Output

    glm::dvec2 window_at(uint32_t from, uint32_t to, double t) const {
        if (t <= 0.0) return window_[from];
        if (t >= 1.0) return window_[to];
        return window_of(position_[from] + t * (position_[to] - position_[from]));
    }

    // The pieces of a walked edge (in changes_) for each request of that mesh edge, in the request's
    // direction, and the trace of the walk.
    void emit(uint32_t edge, uint32_t from, uint32_t to, int32_t qi_start, int32_t qi_end,
              const hsr::sdk::LineRequest& request, hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace) const {
        const bool want_hidden = request.want_hidden();
        for (uint32_t r = first_request_[edge]; r != kNone; r = next_request_[r]) {
            const bool reversed = request.vertex(r, 0) != from;
            const uint32_t flags = request.flags(r);
            auto param = [&](double t) { return reversed ? 1.0 - t : t; };
            const uint32_t object = scene_->face_object != nullptr ? scene_->face_object[graph_.edge_face(edge, 0)] : HSR_NO_OBJECT;
            if (trace.enabled()) trace.emit({"edge-begin", r, HSR_NO_FACE, object, std::max(qi_start, 0), param(0.0)});
            double t0 = 0.0;
            int32_t qi = qi_start;
            auto piece = [&](double t1) {
                if (t1 <= t0) return;
                const int32_t shown = std::max(qi, 0);
                if (shown != 0 && !want_hidden) return;
                glm::dvec2 p = window_at(from, to, t0), q = window_at(from, to, t1);
                if (reversed) std::swap(p, q);
                segments.add(glm::vec2(p), glm::vec2(q), r, flags, shown);
            };
            for (const QiChange& change : changes_) {
                piece(change.t);
                if (trace.enabled()) {
                    const uint32_t face_object = scene_->face_object != nullptr && change.face != HSR_NO_FACE
                                                     ? scene_->face_object[change.face]
                                                     : HSR_NO_OBJECT;
                    trace.emit({"qi-change", r, change.face, face_object, std::max(change.qi, 0), param(change.t)});
                }
                t0 = std::max(t0, change.t);
                qi = change.qi;
            }
            piece(1.0);
            if (trace.enabled()) trace.emit({"edge-end", r, HSR_NO_FACE, object, std::max(qi_end, 0), param(1.0)});
        }
    }

    void trace_seed(uint32_t seed, const hsr::sdk::LineRequest& request, const hsr::sdk::Trace& trace) const {
        uint32_t edge = HSR_NO_EDGE;
        double t = std::numeric_limits<double>::quiet_NaN();
        for (const uint32_t e : graph_.edges_at(seed))
            if (first_request_[e] != kNone) {
                edge = first_request_[e];
                t = request.vertex(edge, 0) == seed ? 0.0 : 1.0;
                break;
            }
        const uint32_t face = graph_.faces_at(seed)[0];
        const uint32_t object = scene_->face_object != nullptr ? scene_->face_object[face] : HSR_NO_OBJECT;
        trace.emit({"component-seed", edge, HSR_NO_FACE, object, seed_qi_, t});
    }

    static constexpr double kPadPixels = 0.01;

    const bool use_grid_;
    const bool check_all_edges_;

    // Per call (kept to reuse their memory).
    const Viewer* viewer_ = nullptr;
    const hsr_camera* camera_ = nullptr;
    const hsr_scene* scene_ = nullptr;
    glm::dmat4 view_projection_{1.0};
    MeshGraph graph_;
    std::vector<glm::dvec3> position_;
    std::vector<glm::dvec2> window_;
    std::vector<FacePlane> face_plane_;
    std::vector<FaceBox> face_box_;
    std::vector<ContourEdge> contours_;
    appel::ImageGrid contour_grid_, face_grid_;
    appel::SpaceGrid space_grid_;
    appel::Bins contour_bins_, face_bins_, space_bins_;
    std::vector<uint32_t> contour_stamp_, face_stamp_;
    uint32_t stamp_ = 0;
    std::vector<uint32_t> first_request_, next_request_;
    std::vector<int32_t> qi_;
    std::vector<uint32_t> component_mark_, members_, queue_;
    std::vector<uint8_t> walked_;
    int32_t seed_qi_ = 0;
    std::vector<Crossing> crossings_;
    std::vector<QiChange> changes_;
    Statistics stats_;
};

}  // namespace

HSR_EXPORT_PLUGIN(Appel)
