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
//
// This file: the plugin and the propagation of QI over each connected part (propagate). Beside it:
// view_geometry.hpp (the scene seen from the camera: the edge graph, contour edges, grids),
// vertex_qi.hpp (QI counted at a seed vertex; the vertex rule), edge_walk.hpp (QI changes along one
// edge), sight.hpp (the geometric predicates), mesh_graph.hpp and grids.hpp.
#include "edge_walk.hpp"
#include "vertex_qi.hpp"
#include "view_geometry.hpp"

#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace {

using appel::MeshGraph;
using appel::QiChange;
using appel::Viewer;
using hsr::sdk::InvalidArgument;
using hsr::sdk::ParamSpec;

constexpr int32_t kUnknownQi = std::numeric_limits<int32_t>::min();
constexpr uint32_t kNone = 0xFFFFFFFFu;
// How many vertices of a component are tried as its seed.
constexpr size_t kSeedCandidates = 16;
// Neighbouring triangles whose unit normals agree this closely are one flat face (a polygon).
constexpr double kCoplanarCosine = 0.999999;

struct SeedCounts {
    uint64_t seeds = 0, seeds_ambiguous = 0, seed_face_tests = 0;
    uint64_t vertex_conflicts = 0;  // vertices reached with two different QIs
};

class Appel final : public hsr::sdk::HiddenLineRemover {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "appel", "1.0.0",
        "Appel (1967) quantitative invisibility: QI counted at one vertex per part, carried along the edges, "
        "changed behind contour edges"};
    // The steps of Appel's method as a textbook gives them. The contour lines are found once, for
    // the whole scene, and shown with the first part's start vertex; the vertex rule (faces at a
    // vertex that hide an edge leaving it) is folded into the walk's first step.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"seed-qi", "find the contour lines; count the QI of a start vertex of each part directly"},
        {"walk-edge", "walk the next edge from a vertex of known QI"},
        {"qi-change", "QI changes where the edge passes behind a contour line or through a face"},
        {"draw-visible", "draw the pieces of the edge whose QI is 0"},
    };
    static inline const ParamSpec params[] = {
        ParamSpec::choice("prefilter", "grid", "grid|none",
                          "find the contour edges an edge may pass behind with a screen grid, or test every one"),
        ParamSpec::boolean("check-all-edges", false,
                           "walk every edge, not only a spanning tree and the requested ones, and count vertices "
                           "reached with two different QIs (qi-conflicts)"),
        ParamSpec::integer("max-candidates", "250000000", 1, 1e15,
                           "the most candidates (contour edges and faces in the grids' cells) one drawing may store "
                           "and test, each counted before the walks begin; bounds memory (4 bytes a stored one) and "
                           "time"),
    };

    static inline const hsr::sdk::TranslationSpec translations[] = {
        {"ru", "description",
         "алгоритм Аппеля (1967), количественная невидимость: она подсчитывается в одной вершине каждой связной "
         "части, переносится вдоль рёбер и меняется там, где ребро проходит за контурной линией"},
        {"ru", "phase:seed-qi",
         "найти контурные линии; в начальной вершине каждой части подсчитать количественную невидимость напрямую"},
        {"ru", "phase:walk-edge", "пройти очередное ребро от вершины с известной количественной невидимостью"},
        {"ru", "phase:qi-change",
         "количественная невидимость меняется там, где ребро проходит за контурной линией или пронзает грань"},
        {"ru", "phase:draw-visible", "нарисовать участки ребра с нулевой количественной невидимостью"},
        {"ru", "param:prefilter", "предварительный отбор"},
        {"ru", "help:prefilter",
         "контурные рёбра, за которыми может пройти ребро, искать по экранной сетке или проверять все"},
        {"ru", "choice:prefilter:grid", "по экранной сетке"},
        {"ru", "choice:prefilter:none", "без отбора"},
        {"ru", "param:check-all-edges", "обходить все рёбра"},
        {"ru", "help:check-all-edges",
         "обходить все рёбра, а не только остовное дерево и запрошенные, и считать вершины, куда обход пришёл с "
         "разной количественной невидимостью (счётчик противоречий)"},
        {"ru", "param:max-candidates", "предельное число кандидатов"},
        {"ru", "help:max-candidates",
         "сколько кандидатов (контурных рёбер и граней в ячейках сеток) можно хранить и проверять за один рисунок; "
         "подсчитывается до начала обхода и ограничивает память (4 байта на кандидата) и время"},
        {"ru", "counter:triangles-in", "треугольников"},
        {"ru", "counter:edges-in", "рёбер сетки"},
        {"ru", "counter:contour-edges", "контурных рёбер"},
        {"ru", "counter:seeds", "связных частей (начальных вершин)"},
        {"ru", "counter:seed-face-tests", "проверок граней в начальных вершинах"},
        {"ru", "counter:seeds-ambiguous", "частей без однозначной начальной вершины"},
        {"ru", "counter:edges-walked", "рёбер пройдено"},
        {"ru", "counter:crossing-tests", "проверок прохождения за контуром"},
        {"ru", "counter:crossings", "прохождений за контуром"},
        {"ru", "counter:piercing-tests", "проверок пересечения с гранями"},
        {"ru", "counter:piercings", "пересечений граней"},
        {"ru", "counter:qi-changes", "изменений количественной невидимости"},
        {"ru", "counter:qi-conflicts", "противоречий в количественной невидимости"},
        {"ru", "step:component-seed", "начальная вершина части"},
        {"ru", "step:edge-begin", "обход ребра"},
        {"ru", "step:qi-change", "смена количественной невидимости"},
        {"ru", "step:edge-end", "итог по ребру"},
    };

    explicit Appel(const hsr::sdk::Params& p)
        : use_grid_(p.choice("prefilter") == 0),
          check_all_edges_(p.boolean("check-all-edges")),
          max_candidates_(uint64_t(p.integer("max-candidates"))) {}

    void render_lines(const hsr::sdk::Scene& scene, const hsr_camera& camera, const hsr::sdk::LineRequest& request,
                      hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace,
                      hsr::sdk::Counters& counters) override {
        validate(scene.raw(), camera);
        const Viewer viewer(camera);
        hsr::sdk::refuse_clip_planes("appel", camera);
        viewer_ = &viewer;
        scene_ = &scene.raw();
        seed_counts_ = {};
        geometry_.build(scene.raw(), camera, viewer, max_candidates_);
        check_candidates_tested();
        edge_walk_.start(geometry_, viewer, use_grid_);
        map_request(request);
        propagate(request, segments, trace);

        const appel::WalkCounts& walk = edge_walk_.counts();
        counters.set("triangles-in", geometry_.graph.face_count());
        counters.set("edges-in", geometry_.graph.edge_count());
        counters.set("contour-edges", geometry_.contours.size());
        counters.set("seeds", seed_counts_.seeds);
        counters.set("seed-face-tests", seed_counts_.seed_face_tests);
        counters.set("seeds-ambiguous", seed_counts_.seeds_ambiguous);
        counters.set("edges-walked", walk.edges_walked);
        counters.set("crossing-tests", walk.crossing_tests);
        counters.set("crossings", walk.crossings);
        counters.set("piercing-tests", walk.piercing_tests);
        counters.set("piercings", walk.piercings);
        counters.set("qi-changes", walk.qi_changes);
        counters.set("qi-conflicts", walk.qi_conflicts + seed_counts_.vertex_conflicts);
    }

private:
    // ------------------------------------------------------------------------------------------ //
    // The propagation: per connected part, a seed whose QI is counted, then breadth first over the
    // edges, each walked from a vertex of known QI.

    void propagate(const hsr::sdk::LineRequest& request, hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace) {
        const MeshGraph& graph = geometry_.graph;
        const uint32_t vertex_count = graph.vertex_count();
        qi_.assign(vertex_count, kUnknownQi);
        component_mark_.assign(vertex_count, 0);
        walked_.assign(graph.edge_count(), 0);
        uint32_t component = 0;
        for (uint32_t start = 0; start < vertex_count; ++start) {
            if (component_mark_[start] != 0 || graph.edges_at(start).empty()) continue;
            ++component;
            ++seed_counts_.seeds;
            collect_component(start, component);
            const uint32_t seed = choose_seed();
            qi_[seed] = seed_qi_;
            if (trace.enabled()) trace_seed(seed, request, trace);

            queue_.clear();
            queue_.push_back(seed);
            for (size_t head = 0; head < queue_.size(); ++head) {
                const uint32_t v = queue_[head];
                for (const uint32_t e : graph.edges_at(v)) {
                    if (walked_[e]) continue;
                    const uint32_t w = graph.other_end(e, v);
                    const bool tree_edge = qi_[w] == kUnknownQi;
                    const bool requested = first_request_[e] != kNone;
                    if (!tree_edge && !requested && !check_all_edges_) continue;
                    walked_[e] = 1;
                    const int32_t qi_start = qi_[v] + appel::faces_hiding_edge_start(geometry_, *viewer_, v, w);
                    const int32_t qi_end = edge_walk_.walk(v, w, qi_start);
                    if (requested) emit(e, v, w, qi_start, qi_end, request, segments, trace);
                    const int32_t qi_w = qi_end - appel::faces_hiding_edge_start(geometry_, *viewer_, w, v);
                    if (tree_edge) {
                        qi_[w] = qi_w;
                        queue_.push_back(w);
                    } else if (qi_w != qi_[w]) {
                        ++seed_counts_.vertex_conflicts;
                    }
                }
            }
        }
    }

    // Refuses the drawing when the walks could test more candidates than max-candidates allows, with
    // the grids' entries: each edge walked tests the contour edges and faces in the cells it passes
    // (every contour edge, with prefilter=none), and each seed the faces in its vertex's cell. Every
    // edge is counted, though only a spanning tree and the requested edges are walked: an upper bound,
    // found from the cells' sizes without testing anything.
    void check_candidates_tested() const {
        const appel::ViewGeometry& g = geometry_;
        uint64_t candidates = g.grid_entries;
        const auto check = [&] {
            if (candidates > max_candidates_)
                throw InvalidArgument("appel: the walks along the edges could test " + std::to_string(candidates) +
                                      " candidates (contour edges and faces in their grid cells), over the limit of " +
                                      std::to_string(max_candidates_) + " (raise it with max-candidates=N)");
        };
        if (g.graph.face_count() == 0) return;
        for (uint32_t v = 0; v < g.graph.vertex_count(); ++v)
            if (!g.graph.edges_at(v).empty()) candidates += g.face_bins.size(g.face_grid.cell_of(g.window[v]));
        check();
        for (uint32_t e = 0; e < g.graph.edge_count(); ++e) {
            const uint32_t a = g.graph.edge_vertex(e, 0), b = g.graph.edge_vertex(e, 1);
            if (!use_grid_)
                candidates += g.contours.size();
            else if (!g.contours.empty())
                g.contour_grid.for_segment(g.window[a], g.window[b],
                                           [&](uint32_t cell) { candidates += g.contour_bins.size(cell); });
            g.space_grid.for_segment(g.position[a], g.position[b],
                                     [&](uint32_t cell) { candidates += g.space_bins.size(cell); });
            if (candidates > max_candidates_) break;  // the count so far is enough to refuse
        }
        check();
    }

    void collect_component(uint32_t start, uint32_t component) {
        const MeshGraph& graph = geometry_.graph;
        members_.clear();
        members_.push_back(start);
        component_mark_[start] = component;
        for (size_t head = 0; head < members_.size(); ++head)
            for (const uint32_t e : graph.edges_at(members_[head])) {
                const uint32_t w = graph.other_end(e, members_[head]);
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
            const int32_t qi =
                appel::faces_hiding_vertex(geometry_, *viewer_, members_[k], clean, seed_counts_.seed_face_tests);
            if (clean) {
                seed_qi_ = qi;
                return members_[k];
            }
            if (k == 0) fallback_qi = qi;
        }
        ++seed_counts_.seeds_ambiguous;
        seed_qi_ = fallback_qi;
        return fallback;
    }

    // ------------------------------------------------------------------------------------------ //
    // Input

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

    // Which mesh edge each requested edge is (a list per mesh edge, in case one is asked for twice).
    void map_request(const hsr::sdk::LineRequest& request) {
        const MeshGraph& graph = geometry_.graph;
        first_request_.assign(graph.edge_count(), kNone);
        next_request_.assign(request.edge_count(), kNone);
        if (request.edge_count() > 0 &&
            (request.raw().edge_vertices == nullptr || request.raw().edge_faces == nullptr || request.raw().edge_flags == nullptr))
            throw InvalidArgument("appel: the line request has NULL arrays");
        for (uint32_t r = request.edge_count(); r-- > 0;) {
            const uint32_t a = request.vertex(r, 0), b = request.vertex(r, 1);
            uint32_t edge = kNone;
            for (int side = 0; side < 2 && edge == kNone; ++side) {
                const uint32_t f = request.face(r, side);
                if (f >= graph.face_count()) continue;
                for (int i = 0; i < 3; ++i) {
                    const uint32_t c = graph.corner(f, i), d = graph.corner(f, (i + 1) % 3);
                    if ((c == a && d == b) || (c == b && d == a)) edge = graph.side_edge(f, i);
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
    // Output

    // The pieces of the edge just walked (at edge_walk_.changes()) for each request of that mesh edge,
    // in the request's direction, and the trace of the walk.
    void emit(uint32_t edge, uint32_t from, uint32_t to, int32_t qi_start, int32_t qi_end,
              const hsr::sdk::LineRequest& request, hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace) const {
        const bool want_hidden = request.want_hidden();
        for (uint32_t r = first_request_[edge]; r != kNone; r = next_request_[r]) {
            const bool reversed = request.vertex(r, 0) != from;
            const uint32_t flags = request.flags(r);
            auto param = [&](double t) { return reversed ? 1.0 - t : t; };
            const uint32_t object =
                scene_->face_object != nullptr ? scene_->face_object[geometry_.graph.edge_face(edge, 0)] : HSR_NO_OBJECT;
            // The piece [t0, t1] of the walk as a line of the next trace event.
            auto trace_piece = [&](double t0, double t1, hsr_step_role role) {
                const glm::dvec2 p = geometry_.window_at(from, to, t0), q = geometry_.window_at(from, to, t1);
                trace.line(float(p.x), float(p.y), float(q.x), float(q.y), role);
            };
            const std::vector<QiChange>& changes = edge_walk_.changes();
            const bool russian = trace.russian();
            // The walk's pieces up to `until` (a parameter along it), each as visible (QI 0) or
            // hidden (QI > 0), after the whole edge as the subject of the step.
            auto trace_pieces = [&](double until) {
                trace_piece(0.0, 1.0, HSR_STEP_SUBJECT);
                double from = 0.0;
                int32_t piece_qi = qi_start;
                for (const QiChange& change : changes) {
                    if (from >= until) break;
                    const double to = std::min(change.t, until);
                    if (to > from) trace_piece(from, to, piece_qi <= 0 ? HSR_STEP_WRITTEN : HSR_STEP_REJECTED);
                    from = std::max(from, change.t);
                    piece_qi = change.qi;
                }
                if (until > from) trace_piece(from, until, piece_qi <= 0 ? HSR_STEP_WRITTEN : HSR_STEP_REJECTED);
            };
            if (trace.enabled()) {
                trace_piece(0.0, 1.0, HSR_STEP_SUBJECT);
                trace.emit({.type = "edge-begin", .edge = r, .object = object, .qi = std::max(qi_start, 0),
                            .t0 = param(0.0), .phase = "walk-edge"},
                           russian ? "ребро %u: начинаем обход, количественная невидимость в начале равна %d"
                                   : "edge %u: the walk starts with QI %d (the number of faces in front of it)",
                           r, std::max(qi_start, 0));
            }
            double t0 = 0.0;
            int32_t qi = qi_start;
            auto piece = [&](double t1) {
                if (t1 <= t0) return;
                const int32_t shown = std::max(qi, 0);
                if (shown != 0 && !want_hidden) return;
                glm::dvec2 p = geometry_.window_at(from, to, t0), q = geometry_.window_at(from, to, t1);
                if (reversed) std::swap(p, q);
                segments.add(glm::vec2(p), glm::vec2(q), r, flags, shown);
            };
            for (size_t k = 0; k < changes.size(); ++k) {
                const QiChange& change = changes[k];
                piece(change.t);
                if (trace.enabled()) {
                    const uint32_t face = change.face != HSR_NO_FACE ? polygon_face(change.face) : HSR_NO_FACE;
                    const uint32_t face_object =
                        scene_->face_object != nullptr && face != HSR_NO_FACE ? scene_->face_object[face] : HSR_NO_OBJECT;
                    // The edge, its pieces walked so far up to the next change, and the contour line
                    // it passes behind.
                    trace_pieces(k + 1 < changes.size() ? std::max(changes[k + 1].t, change.t) : 1.0);
                    const bool behind_contour = change.contour != appel::kNoContour;
                    if (behind_contour) {
                        const appel::ContourEdge& c = geometry_.contours[change.contour];
                        const glm::dvec2 p = geometry_.window[c.v0], q = geometry_.window[c.v1];
                        trace.line(float(p.x), float(p.y), float(q.x), float(q.y), HSR_STEP_CONTEXT);
                    }
                    const int32_t before = std::max(qi, 0), after = std::max(change.qi, 0);
                    if (russian)
                        trace.emit({"qi-change", r, face, face_object, after, param(change.t), std::nan(""), "qi-change"},
                                   behind_contour
                                       ? "ребро %u: количественная невидимость меняется с %d на %d при t = %.4g — "
                                         "ребро проходит за контурной линией грани %u"
                                       : "ребро %u: количественная невидимость меняется с %d на %d при t = %.4g — "
                                         "ребро пронзает грань %u",
                                   r, before, after, param(change.t), face);
                    else
                        trace.emit({"qi-change", r, face, face_object, after, param(change.t), std::nan(""), "qi-change"},
                                   behind_contour ? "edge %u: QI %d to %d at t %.4g (passing behind a contour line of face %u)"
                                                  : "edge %u: QI %d to %d at t %.4g (passing through face %u)",
                                   r, before, after, param(change.t), face);
                }
                t0 = std::max(t0, change.t);
                qi = change.qi;
            }
            piece(1.0);
            if (trace.enabled()) {
                trace_pieces(1.0);
                trace.emit({.type = "edge-end", .edge = r, .object = object, .qi = std::max(qi_end, 0),
                            .t0 = param(1.0), .phase = "draw-visible"},
                           russian ? "ребро %u: в конце количественная невидимость %d; рисуем участки с невидимостью 0"
                                   : "edge %u: ends with QI %d; its pieces of QI 0 are drawn",
                           r, std::max(qi_end, 0));
            }
        }
    }

    // The face a person sees: the polygon of face f's object (its triangles joined across edges
    // whose faces are coplanar), named by its lowest triangle, as the viewer numbers faces.
    uint32_t polygon_face(uint32_t f) const {
        const hsr_scene& s = *scene_;
        if (s.edge_neighbors == nullptr || f >= s.triangle_count) return f;
        auto normal = [&](uint32_t t) {
            const glm::dvec3 a = geometry_.position[s.indices[3 * size_t(t)]];
            const glm::dvec3 b = geometry_.position[s.indices[3 * size_t(t) + 1]];
            const glm::dvec3 c = geometry_.position[s.indices[3 * size_t(t) + 2]];
            const glm::dvec3 n = glm::cross(b - a, c - a);
            const double length = glm::length(n);
            return length > 0.0 ? n / length : n;
        };
        const glm::dvec3 n = normal(f);
        polygon_stack_.assign(1, f);
        polygon_seen_.assign(1, f);
        uint32_t lowest = f;
        while (!polygon_stack_.empty()) {
            const uint32_t t = polygon_stack_.back();
            polygon_stack_.pop_back();
            for (int i = 0; i < 3; ++i) {
                const int32_t u = s.edge_neighbors[3 * size_t(t) + i];
                if (u == HSR_NO_NEIGHBOR || uint32_t(u) >= s.triangle_count) continue;
                if (std::find(polygon_seen_.begin(), polygon_seen_.end(), uint32_t(u)) != polygon_seen_.end()) continue;
                if (glm::dot(normal(uint32_t(u)), n) < kCoplanarCosine) continue;
                polygon_seen_.push_back(uint32_t(u));
                polygon_stack_.push_back(uint32_t(u));
                lowest = std::min(lowest, uint32_t(u));
            }
        }
        return lowest;
    }

    void trace_seed(uint32_t seed, const hsr::sdk::LineRequest& request, const hsr::sdk::Trace& trace) const {
        uint32_t edge = HSR_NO_EDGE;
        double t = std::numeric_limits<double>::quiet_NaN();
        for (const uint32_t e : geometry_.graph.edges_at(seed))
            if (first_request_[e] != kNone) {
                edge = first_request_[e];
                t = request.vertex(edge, 0) == seed ? 0.0 : 1.0;
                break;
            }
        const uint32_t face = geometry_.graph.faces_at(seed)[0];
        const uint32_t object = scene_->face_object != nullptr ? scene_->face_object[face] : HSR_NO_OBJECT;
        // The first seed's step also shows the contour edges, found for the whole scene before it.
        const bool first = seed_counts_.seeds == 1;
        if (first)
            for (const appel::ContourEdge& c : geometry_.contours) {
                const glm::dvec2 p = geometry_.window[c.v0], q = geometry_.window[c.v1];
                trace.line(float(p.x), float(p.y), float(q.x), float(q.y), HSR_STEP_CONTEXT);
            }
        const glm::dvec2 at = geometry_.window[seed];
        const float cross = 4.0f;  // pixels: a cross marking the seed vertex
        trace.line(float(at.x) - cross, float(at.y), float(at.x) + cross, float(at.y), HSR_STEP_SUBJECT);
        trace.line(float(at.x), float(at.y) - cross, float(at.x), float(at.y) + cross, HSR_STEP_SUBJECT);
        const hsr::sdk::Trace::Event event{"component-seed", edge, HSR_NO_FACE, object, seed_qi_, t, std::nan(""),
                                           "seed-qi"};
        const auto part = static_cast<unsigned long long>(seed_counts_.seeds);
        if (trace.russian() && first)
            trace.emit(event,
                       "%zu контурных рёбер; часть %llu: в начальной вершине %u подсчёт по всем граням даёт "
                       "количественную невидимость %d",
                       geometry_.contours.size(), part, seed, seed_qi_);
        else if (trace.russian())
            trace.emit(event, "часть %llu: начальная вершина %u, её количественная невидимость равна %d", part, seed,
                       seed_qi_);
        else if (first)
            trace.emit(event,
                       "%zu contour edges; part %llu starts at vertex %u with QI %d (faces counted between it and "
                       "the eye)",
                       geometry_.contours.size(), part, seed, seed_qi_);
        else
            trace.emit(event, "part %llu starts at vertex %u with QI %d", part, seed, seed_qi_);
    }

    const bool use_grid_;
    const bool check_all_edges_;
    const uint64_t max_candidates_;

    // Per call (kept to reuse their memory).
    const Viewer* viewer_ = nullptr;
    const hsr_scene* scene_ = nullptr;
    appel::ViewGeometry geometry_;
    appel::EdgeWalk edge_walk_;
    std::vector<uint32_t> first_request_, next_request_;
    std::vector<int32_t> qi_;
    std::vector<uint32_t> component_mark_, members_, queue_;
    std::vector<uint8_t> walked_;
    int32_t seed_qi_ = 0;
    SeedCounts seed_counts_;
    mutable std::vector<uint32_t> polygon_stack_, polygon_seen_;  // polygon_face's scratch (steps only)
};

}  // namespace

HSR_EXPORT_PLUGIN(Appel)
