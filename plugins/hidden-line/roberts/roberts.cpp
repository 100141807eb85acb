// roberts: hidden-line removal for scenes of convex bodies, after L. G. Roberts, "Machine Perception
// of Three-Dimensional Solids", MIT Lincoln Laboratory Technical Report 315, 1963 — the first
// hidden-line algorithm — in the form David F. Rogers gives it in "Procedural Elements for Computer
// Graphics", 2nd ed., McGraw-Hill 1998, section 4.3 (the parametric visibility test).
//
// Each object of the scene is one convex body, described by the matrix of its face planes (one
// column (a, b, c, d) per face, signs fixed by an interior point: bodies.hpp). For the camera, the
// faces turned away from the eye are found from the same matrix, and edges between two of them are
// removed at once. Every remaining edge is then tested against every other body with the
// parametric test (parametric_test.hpp): the points h(t, a) = P(t) + a·E between the edge point
// P(t) and the eye E are inside a body where every plane gives a positive value, and the edge
// points for which such a point exists form one hidden interval per body, so a body leaves at most
// two visible pieces of an edge. Bounding-box (window) and depth pre-tests skip bodies that cannot
// hide the edge. Where bodies intersect, the penetration lines (penetration.hpp) are added and
// tested the same way. A perspective eye point is E = (eye, 1); an eye at infinity (orthographic)
// is E = (direction toward the viewer, 0): the same formulas serve both.
//
// docs/algorithms/roberts.md describes the steps, the counters and the limits.
// The file is just over 700 lines: the per-edge tests, the penetration lines and the steps that
// narrate both share one frame's bodies, and its Russian texts sit beside the English ones.
#include "bodies.hpp"
#include "parametric_test.hpp"
#include "penetration.hpp"

#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

using roberts::BodyPlanes;
using roberts::Interval;
using roberts::kNoBody;
using roberts::refuse;

// A visible piece shorter than this (in pixels) left between two hidden ones is dropped, and a
// hidden interval shorter than this is ignored: both are rounding, not drawing.
constexpr double kSliverPixels = 1e-3;

bool finite(const float* values, size_t count) {
    for (size_t k = 0; k < count; ++k)
        if (!std::isfinite(values[k])) return false;
    return true;
}

// The camera in the form the algorithm uses it, in double precision.
struct View {
    glm::dmat4 view_projection{1.0};
    bool perspective = true;
    glm::dvec4 eye{0.0};           // homogeneous: (eye, 1) or (toward the viewer, 0)
    glm::dvec3 eye_point{0.0};     // perspective only
    glm::dvec3 view_direction{0.0};
    double width = 0, height = 0;
    double near_w = 0;             // perspective: what is drawn has clip-space w >= near_w

    void load(const hsr_camera& camera) {
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) view_projection[c][r] = camera.view_projection[4 * c + r];
        perspective = camera.projection_type == HSR_PROJECTION_PERSPECTIVE;
        view_direction = glm::normalize(glm::dvec3(camera.view_direction[0], camera.view_direction[1],
                                                   camera.view_direction[2]));
        eye_point = glm::dvec3(camera.eye[0], camera.eye[1], camera.eye[2]);
        eye = perspective ? glm::dvec4(eye_point, 1.0) : glm::dvec4(-view_direction, 0.0);
        width = camera.width;
        height = camera.height;
        near_w = std::isfinite(camera.near_plane) && camera.near_plane > 0 ? double(camera.near_plane) : 1e-6;
    }
    double clip_w(glm::dvec3 p) const {
        return view_projection[0][3] * p.x + view_projection[1][3] * p.y + view_projection[2][3] * p.z +
               view_projection[3][3];
    }
    glm::dvec2 window(glm::dvec3 p) const {
        const glm::dvec4 clip = view_projection * glm::dvec4(p, 1.0);
        return {(clip.x / clip.w + 1.0) * 0.5 * width, (1.0 - clip.y / clip.w) * 0.5 * height};
    }
    // Distance along the view direction: what is nearer the eye has a smaller depth.
    double depth(glm::dvec3 p) const {
        return perspective ? glm::dot(p - eye_point, view_direction) : glm::dot(p, view_direction);
    }
    // The part [t_begin, t_end] of a + t·(b - a), t in [0, 1], in front of the near plane
    // (perspective; all of it for an eye at infinity). False when none is.
    bool in_front(glm::dvec3 a, glm::dvec3 b, double& t_begin, double& t_end) const {
        t_begin = 0;
        t_end = 1;
        if (!perspective) return true;
        const double wa = clip_w(a) - near_w, wb = clip_w(b) - near_w;
        if (wa < 0 && wb < 0) return false;
        if (wa < 0) t_begin = wa / (wa - wb);
        if (wb < 0) t_end = wa / (wa - wb);
        return t_begin < t_end;
    }
};

// One body's planes for the current camera, in the order the parametric test reads them: front
// faces, edge-on faces, back faces (by the sign of w for the planes as given or as shrunk).
struct PlaneSplit {
    uint32_t front_count = 0, edge_on_count = 0, back_count = 0;
};

// One body for the current camera.
struct BodyView {
    uint32_t first_ordered = 0;  // its planes' first entry in ordered_planes_ / ordered_shrunk_
    PlaneSplit exact, shrunk;    // the true planes; the planes moved inward by the body's shrink
    glm::dvec2 window_min{0.0}, window_max{0.0};
    bool window_box_valid = false;  // false when part of the body lies behind the eye
    double depth_min = 0;
};

struct Stats {
    uint64_t edges_behind_eye = 0, edges_back = 0;
    uint64_t tests = 0, bounds_rejections = 0, depth_rejections = 0, hidden_intervals = 0, touching_rejections = 0;
    uint64_t pieces_visible = 0, pieces_hidden = 0, penetration_pieces_visible = 0;
};

class Roberts final : public hsr::sdk::HiddenLineRemover {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "roberts", "1.0.0",
        "Roberts (1963): convex bodies as plane matrices, parametric visibility test, penetration lines"};
    static inline const std::array<hsr::sdk::ParamSpec, 0> params{};
    // The steps of Roberts' method as a textbook gives them. The parametric test of one edge against
    // one body (every plane's inequality solved, the interval t0..t1 where all hold) is one step; the
    // penetration lines are found for all pairs of bodies at once, and each is then tested as an edge.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"back-faces", "remove each body's back faces (planes turned away from the eye)"},
        {"own-body", "an edge between two back faces is hidden by its own body"},
        {"edge", "take the next edge"},
        {"pretest", "skip a body whose box or depth cannot hide the edge"},
        {"hidden-interval", "find the interval t0..t1 of the edge a body hides"},
        {"visible-pieces", "keep the visible pieces of the edge"},
        {"penetration", "penetration lines where two bodies meet, tested as edges"},
    };

    static inline const hsr::sdk::TranslationSpec translations[] = {
        {"ru", "description",
         "алгоритм Робертса (1963): выпуклые тела задаются матрицами плоскостей граней, видимость рёбер — "
         "параметрической проверкой; строятся и линии пересечения тел"},
        {"ru", "phase:back-faces", "удалить нелицевые грани каждого тела (плоскости, обращённые от наблюдателя)"},
        {"ru", "phase:own-body", "ребро между двумя нелицевыми гранями закрыто собственным телом"},
        {"ru", "phase:edge", "взять очередное ребро"},
        {"ru", "phase:pretest", "пропустить тело, которое по габаритам или по глубине не может закрыть ребро"},
        {"ru", "phase:hidden-interval", "найти участок ребра t0..t1, закрытый телом"},
        {"ru", "phase:visible-pieces", "оставить видимые участки ребра"},
        {"ru", "phase:penetration", "линии пересечения тел проверить так же, как рёбра"},
        {"ru", "counter:bodies", "тел"},
        {"ru", "counter:planes", "плоскостей граней"},
        {"ru", "counter:edges-in", "рёбер на входе"},
        {"ru", "counter:edges-behind-eye", "рёбер позади наблюдателя"},
        {"ru", "counter:edges-back", "рёбер между нелицевыми гранями"},
        {"ru", "counter:edge-body-tests", "проверок «ребро — тело»"},
        {"ru", "counter:bounds-rejections", "тел отброшено по габаритам"},
        {"ru", "counter:depth-rejections", "тел отброшено по глубине"},
        {"ru", "counter:hidden-intervals", "закрытых участков найдено"},
        {"ru", "counter:touching-rejections", "участков отброшено как касание"},
        {"ru", "counter:pieces-visible", "видимых отрезков"},
        {"ru", "counter:pieces-hidden", "невидимых отрезков"},
        {"ru", "counter:body-pairs-overlapping", "пар тел с перекрытием габаритов"},
        {"ru", "counter:penetration-lines", "линий пересечения тел"},
        {"ru", "counter:penetration-pieces-visible", "видимых отрезков линий пересечения"},
        {"ru", "step:body", "нелицевые грани тела"},
        {"ru", "step:edge-begin", "очередное ребро"},
        {"ru", "step:edge-behind-eye", "ребро позади наблюдателя"},
        {"ru", "step:back-edge", "нелицевое ребро"},
        {"ru", "step:rejected-by-depth", "тело дальше ребра"},
        {"ru", "step:rejected-by-bounds", "тело в стороне от ребра"},
        {"ru", "step:hidden-by", "участок, закрытый телом"},
        {"ru", "step:visible", "видимый участок"},
        {"ru", "step:edge-end", "итог по ребру"},
        {"ru", "step:penetration-begin", "линия пересечения тел"},
        {"ru", "step:penetration-body", "грань с линией пересечения"},
        {"ru", "step:penetration-end", "итог по линии пересечения"},
    };

    explicit Roberts(const hsr::sdk::Params&) {}

    void render_lines(const hsr::sdk::Scene& scene, const hsr_camera& camera, const hsr::sdk::LineRequest& request,
                      hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace,
                      hsr::sdk::Counters& counters) override {
        check_scene(scene.raw());
        check_camera(camera);
        hsr::sdk::refuse_clip_planes("roberts", camera);
        check_request(scene.raw(), request);

        builder_.build(scene, set_);
        view_.load(camera);
        prepare_bodies(scene.raw());
        russian_ = trace.russian();
        if (trace.enabled()) trace_bodies(scene.raw(), trace);

        Stats stats;
        const bool want_hidden = request.want_hidden();
        const hsr_scene& s = scene.raw();
        for (uint32_t e = 0; e < request.edge_count(); ++e) {
            const glm::dvec3 a = position(s, request.vertex(e, 0)), b = position(s, request.vertex(e, 1));
            const uint32_t face0 = request.face(e, 0), face1 = request.face(e, 1);
            const uint32_t body = set_.body_of_object[s.face_object[face0]];
            const uint32_t object = set_.bodies[body].object;
            double t_begin, t_end;
            if (!view_.in_front(a, b, t_begin, t_end)) {
                ++stats.edges_behind_eye;
                if (trace.enabled())
                    trace.emit({.type = "edge-behind-eye", .edge = e, .object = object, .phase = "edge"},
                               russian_ ? "ребро %u лежит позади наблюдателя и не рисуется"
                                        : "edge %u lies behind the eye: it is not drawn",
                               e);
                continue;
            }
            if (trace.enabled()) {
                trace_line(a, b - a, t_begin, t_end, HSR_STEP_SUBJECT, trace);
                trace.emit({.type = "edge-begin", .edge = e, .object = object, .t0 = t_begin, .t1 = t_end, .phase = "edge"},
                           russian_ ? "ребро %u тела %u: проверяем его по всем телам, от ближних к дальним"
                                    : "edge %u of body %u: tested against the bodies nearest first",
                           e, object);
            }
            // Roberts' first step: an edge whose faces are all turned away is hidden by its own body.
            const bool back = plane_is_back_[set_.plane_of_triangle[face0]] &&
                              (face1 == HSR_NO_FACE || plane_is_back_[set_.plane_of_triangle[face1]]);
            if (back) {
                ++stats.edges_back;
                if (trace.enabled()) {
                    trace_line(a, b - a, t_begin, t_end, HSR_STEP_REJECTED, trace);
                    trace.emit({.type = "back-edge", .edge = e, .face = set_.plane_face[set_.plane_of_triangle[face0]],
                                .object = object, .t0 = t_begin, .t1 = t_end, .phase = "own-body"},
                               russian_ ? "ребро %u: обе его грани нелицевые, ребро закрыто собственным телом"
                                        : "edge %u: every face of it is turned away, so its own body hides it",
                               e);
                }
                if (want_hidden) {
                    segments.add(window_at(a, b - a, t_begin), window_at(a, b - a, t_end), e, request.flags(e), -1);
                    ++stats.pieces_hidden;
                }
                if (trace.enabled()) {
                    trace_line(a, b - a, t_begin, t_end, HSR_STEP_REJECTED, trace);
                    trace.emit({.type = "edge-end", .edge = e, .object = object, .qi = -1, .phase = "own-body"},
                               russian_ ? "ребро %u: невидимо" : "edge %u: hidden", e);
                }
                continue;
            }
            const bool visible =
                resolve(a, b - a, t_begin, t_end, e, request.flags(e), body, want_hidden, segments, trace, stats);
            if (trace.enabled()) {
                trace_line(a, b - a, t_begin, t_end, visible ? HSR_STEP_WRITTEN : HSR_STEP_REJECTED, trace);
                trace.emit({.type = "edge-end", .edge = e, .object = object, .qi = visible ? 0 : -1, .phase = "visible-pieces"},
                           russian_ ? (visible ? "ребро %u: готово, видимо целиком или частично" : "ребро %u: готово, невидимо")
                                    : (visible ? "edge %u: done, visible in part or whole" : "edge %u: done, hidden"),
                           e);
            }
        }

        roberts::PenetrationStats penetration;
        roberts::find_penetration_lines(set_, penetration_lines_, penetration);
        for (const roberts::PenetrationLine& line : penetration_lines_) {
            const roberts::Body& A = set_.bodies[line.body_a];
            const roberts::Body& B = set_.bodies[line.body_b];
            double t_begin, t_end;
            const bool in_front = view_.in_front(line.start, line.end, t_begin, t_end);
            if (trace.enabled()) {
                if (in_front) trace_line(line.start, line.end - line.start, t_begin, t_end, HSR_STEP_SUBJECT, trace);
                trace.emit({.type = "penetration-begin", .face = set_.plane_face[line.plane_a], .object = A.object,
                            .phase = "penetration"},
                           russian_ ? "линия пересечения: здесь тело %u входит в тело %u"
                                    : "penetration line: where body %u meets body %u",
                           A.object, B.object);
                if (in_front) trace_line(line.start, line.end - line.start, t_begin, t_end, HSR_STEP_SUBJECT, trace);
                trace.emit({.type = "penetration-body", .face = set_.plane_face[line.plane_b], .object = B.object,
                            .phase = "penetration"},
                           russian_ ? "линия пересечения лежит на грани тела %u" : "penetration line: on a face of body %u",
                           B.object);
            }
            bool visible = false;
            // A line that comes out as a point in the picture (a short one, or one seen end-on) is
            // not drawn.
            if (in_front &&
                glm::length(window_at(line.start, line.end - line.start, t_end) -
                            window_at(line.start, line.end - line.start, t_begin)) >= kSliverPixels) {
                const uint64_t before = stats.pieces_visible;
                visible = resolve(line.start, line.end - line.start, t_begin, t_end, HSR_NO_EDGE, HSR_EDGE_PENETRATION,
                                  kNoBody, want_hidden, segments, trace, stats);
                stats.penetration_pieces_visible += stats.pieces_visible - before;
            }
            if (trace.enabled()) {
                if (in_front)
                    trace_line(line.start, line.end - line.start, t_begin, t_end,
                               visible ? HSR_STEP_WRITTEN : HSR_STEP_REJECTED, trace);
                trace.emit({.type = "penetration-end", .qi = visible ? 0 : -1, .phase = "penetration"},
                           russian_ ? (visible ? "линия пересечения видима целиком или частично" : "линия пересечения невидима")
                                    : (visible ? "penetration line: visible in part or whole" : "penetration line: hidden"));
            }
        }

        counters.set("bodies", set_.bodies.size());
        counters.set("planes", set_.planes.size());
        counters.set("edges-in", request.edge_count());
        counters.set("edges-behind-eye", stats.edges_behind_eye);
        counters.set("edges-back", stats.edges_back);
        counters.set("edge-body-tests", stats.tests);
        counters.set("bounds-rejections", stats.bounds_rejections);
        counters.set("depth-rejections", stats.depth_rejections);
        counters.set("hidden-intervals", stats.hidden_intervals);
        counters.set("touching-rejections", stats.touching_rejections);
        counters.set("pieces-visible", stats.pieces_visible);
        counters.set("pieces-hidden", stats.pieces_hidden);
        counters.set("body-pairs-overlapping", penetration.body_pairs_overlapping);
        counters.set("penetration-lines", penetration_lines_.size());
        counters.set("penetration-pieces-visible", stats.penetration_pieces_visible);
    }

private:
    static glm::dvec3 position(const hsr_scene& s, uint32_t v) {
        return {s.positions[3 * size_t(v)], s.positions[3 * size_t(v) + 1], s.positions[3 * size_t(v) + 2]};
    }
    glm::dvec2 window_at(glm::dvec3 start, glm::dvec3 direction, double t) const {
        return view_.window(start + t * direction);
    }

    // --- input checks: a clear message, never a crash ---------------------------------------------

    static void check_scene(const hsr_scene& s) {
        if (s.struct_size < offsetof(hsr_scene, face_object) + sizeof s.face_object)
            refuse("the scene struct is too small (%u bytes)", s.struct_size);
        if (s.triangle_count == 0) return;
        if (s.positions == nullptr || s.indices == nullptr || s.edge_neighbors == nullptr || s.face_object == nullptr)
            refuse("the scene has triangles but lacks positions, indices, edge_neighbors or face_object");
        if (!finite(s.positions, 3 * size_t(s.vertex_count))) refuse("the scene has a vertex that is not finite");
        for (size_t k = 0; k < 3 * size_t(s.triangle_count); ++k)
            if (s.indices[k] >= s.vertex_count)
                refuse("triangle %zu names vertex %u, but the scene has %u vertices", k / 3, s.indices[k], s.vertex_count);
        for (size_t k = 0; k < 3 * size_t(s.triangle_count); ++k) {
            const int32_t n = s.edge_neighbors[k];
            if (n != HSR_NO_NEIGHBOR && (n < 0 || uint32_t(n) >= s.triangle_count))
                refuse("triangle %zu has neighbour %d, but the scene has %u triangles", k / 3, n, s.triangle_count);
        }
        for (uint32_t t = 0; t < s.triangle_count; ++t)
            if (s.face_object[t] >= s.object_count)
                refuse("triangle %u belongs to object %u, but the scene has %u objects", t, s.face_object[t],
                       s.object_count);
    }

    static void check_camera(const hsr_camera& c) {
        if (c.struct_size < offsetof(hsr_camera, far_plane) + sizeof c.far_plane)
            refuse("the camera struct is too small (%u bytes)", c.struct_size);
        if (c.width == 0 || c.height == 0) refuse("the image is %ux%u pixels", c.width, c.height);
        if (c.projection_type != HSR_PROJECTION_PERSPECTIVE && c.projection_type != HSR_PROJECTION_ORTHOGRAPHIC)
            refuse("unknown projection type %d", int(c.projection_type));
        if (!finite(c.view_projection, 16) || !finite(c.eye, 3) || !finite(c.view_direction, 3))
            refuse("the camera has a matrix, eye point or view direction that is not finite");
        const double length = std::sqrt(double(c.view_direction[0]) * c.view_direction[0] +
                                         double(c.view_direction[1]) * c.view_direction[1] +
                                         double(c.view_direction[2]) * c.view_direction[2]);
        if (!(length > 0.5 && length < 2.0)) refuse("the camera's view direction is not a unit vector");
    }

    static void check_request(const hsr_scene& s, const hsr::sdk::LineRequest& request) {
        const hsr_line_request& r = request.raw();
        if (r.struct_size < offsetof(hsr_line_request, want_hidden) + sizeof r.want_hidden)
            refuse("the line request struct is too small (%u bytes)", r.struct_size);
        if (r.edge_count == 0) return;
        if (r.edge_vertices == nullptr || r.edge_faces == nullptr || r.edge_flags == nullptr)
            refuse("the line request has %u edges but NULL arrays", r.edge_count);
        for (uint32_t e = 0; e < r.edge_count; ++e) {
            for (int end = 0; end < 2; ++end)
                if (request.vertex(e, end) >= s.vertex_count)
                    refuse("edge %u names vertex %u, but the scene has %u vertices", e, request.vertex(e, end),
                           s.vertex_count);
            const uint32_t f0 = request.face(e, 0), f1 = request.face(e, 1);
            if (f0 >= s.triangle_count)
                refuse("edge %u names face %u, but the scene has %u triangles", e, f0, s.triangle_count);
            if (f1 != HSR_NO_FACE && f1 >= s.triangle_count)
                refuse("edge %u names face %u, but the scene has %u triangles", e, f1, s.triangle_count);
            if (f1 != HSR_NO_FACE && s.face_object[f0] != s.face_object[f1])
                refuse("edge %u joins faces of two objects (%u and %u)", e, s.face_object[f0], s.face_object[f1]);
        }
    }

    // --- per camera ---------------------------------------------------------------------------------

    void prepare_bodies(const hsr_scene& s) {
        const size_t plane_count = set_.planes.size();
        const size_t body_count = set_.bodies.size();
        eye_weight_.resize(plane_count);
        shrunk_weight_.resize(plane_count);
        plane_is_back_.resize(plane_count);
        ordered_planes_.resize(plane_count);
        ordered_shrunk_.resize(plane_count);
        body_views_.resize(body_count);
        size_t largest = 0;
        for (size_t b = 0; b < body_count; ++b) {
            const roberts::Body& body = set_.bodies[b];
            BodyView& v = body_views_[b];
            largest = std::max<size_t>(largest, body.plane_count);
            // The row w = E · V: the sign says which faces are turned away (w >= 0: the eye is on the
            // inner side of the plane, or in it). The hidden intervals come from the true planes; the
            // planes moved inward by `shrink` (w loses shrink·E_w) only confirm that a line of sight
            // goes deeper into the body than touching.
            const double weight_shrink = body.shrink * view_.eye.w;
            for (uint32_t j = body.first_plane; j < body.first_plane + body.plane_count; ++j) {
                const double w = glm::dot(view_.eye, set_.planes[j]);
                plane_is_back_[j] = w >= 0 ? 1 : 0;
                eye_weight_[j] = w;
                shrunk_weight_[j] = w - weight_shrink;
            }
            v.first_ordered = body.first_plane;
            v.exact = split_planes(body, eye_weight_, ordered_planes_);
            v.shrunk = split_planes(body, shrunk_weight_, ordered_shrunk_);
            // Window box and depth range of its vertices.
            v.window_box_valid = true;
            v.depth_min = std::numeric_limits<double>::infinity();
            v.window_min = glm::dvec2(std::numeric_limits<double>::infinity());
            v.window_max = -v.window_min;
            for (uint32_t k = body.first_vertex; k < body.first_vertex + body.vertex_count; ++k) {
                const glm::dvec3 p = position(s, set_.vertices[k]);
                const double depth = view_.depth(p);
                v.depth_min = std::min(v.depth_min, depth);
                if (view_.perspective && !(view_.clip_w(p) > 0)) {
                    v.window_box_valid = false;
                    continue;
                }
                const glm::dvec2 w = view_.window(p);
                v.window_min = glm::min(v.window_min, w);
                v.window_max = glm::max(v.window_max, w);
            }
        }
        test_.reserve(largest);
        // Bodies nearest first: once a body's nearest point is behind a line's farthest, so are all
        // that follow.
        // The pre-tests read one compact record per body, in that order; a body reaching behind the
        // eye gets an unbounded window box (it is never rejected by bounds).
        screens_.resize(body_count);
        for (uint32_t b = 0; b < body_count; ++b) {
            const BodyView& v = body_views_[b];
            const double infinity = std::numeric_limits<double>::infinity();
            screens_[b] = {v.depth_min, v.window_box_valid ? v.window_min : glm::dvec2(-infinity),
                           v.window_box_valid ? v.window_max : glm::dvec2(infinity), b};
        }
        std::sort(screens_.begin(), screens_.end(),
                  [](const Screen& x, const Screen& y) { return x.depth_min < y.depth_min; });
        pieces_.reserve(2 * body_count + 2);
        next_pieces_.reserve(2 * body_count + 2);
    }

    // Sorts a body's planes into front (weight < 0), edge-on (= 0) and back (> 0) faces, in that
    // order, into its range of `ordered`.
    static PlaneSplit split_planes(const roberts::Body& body, const std::vector<double>& weight,
                                   std::vector<uint32_t>& ordered) {
        PlaneSplit split;
        for (uint32_t j = body.first_plane; j < body.first_plane + body.plane_count; ++j) {
            if (weight[j] < 0)
                ++split.front_count;
            else if (weight[j] == 0)
                ++split.edge_on_count;
            else
                ++split.back_count;
        }
        uint32_t next_front = body.first_plane, next_edge_on = body.first_plane + split.front_count,
                 next_back = body.first_plane + split.front_count + split.edge_on_count;
        for (uint32_t j = body.first_plane; j < body.first_plane + body.plane_count; ++j) {
            const double w = weight[j];
            ordered[w < 0 ? next_front++ : w == 0 ? next_edge_on++ : next_back++] = j;
        }
        return split;
    }

    // The body's true planes (what its hidden intervals are computed with).
    BodyPlanes planes_of(uint32_t body) const {
        const BodyView& v = body_views_[body];
        return {set_.planes.data(), ordered_planes_.data() + v.first_ordered, v.exact.front_count,
                v.exact.edge_on_count, v.exact.back_count, eye_weight_.data(), 0.0};
    }
    // Its planes moved inward by its shrink (what decides whether a hidden interval is real).
    BodyPlanes shrunk_planes_of(uint32_t body) const {
        const BodyView& v = body_views_[body];
        return {set_.planes.data(), ordered_shrunk_.data() + v.first_ordered, v.shrunk.front_count,
                v.shrunk.edge_on_count, v.shrunk.back_count, shrunk_weight_.data(), set_.bodies[body].shrink};
    }

    // --- per line -----------------------------------------------------------------------------------

    // Tests the part [t_begin, t_end] of the line start + t·direction against every body except
    // `skip_body` and adds its visible pieces (and hidden ones when asked) to `segments`. Returns
    // whether any piece is visible.
    bool resolve(glm::dvec3 start, glm::dvec3 direction, double t_begin, double t_end, uint32_t edge, uint32_t flags,
                 uint32_t skip_body, bool want_hidden, hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace,
                 Stats& stats) {
        const glm::dvec2 window_begin = window_at(start, direction, t_begin);
        const glm::dvec2 window_end = window_at(start, direction, t_end);
        const glm::dvec2 line_min = glm::min(window_begin, window_end), line_max = glm::max(window_begin, window_end);
        const double line_depth_max = std::max(view_.depth(start + t_begin * direction), view_.depth(start + t_end * direction));
        const double pixels_per_t = glm::length(window_end - window_begin) / (t_end - t_begin);

        pieces_.clear();
        pieces_.push_back({t_begin, t_end});
        for (uint32_t rank = 0; rank < screens_.size() && !pieces_.empty(); ++rank) {
            const Screen& screen = screens_[rank];
            const uint32_t body = screen.body;
            if (body == skip_body) continue;
            // Depth pre-test: a body whose nearest point is no nearer than the line's farthest cannot
            // lie between the line and the eye; nor can any after it (nearest first).
            if (screen.depth_min >= line_depth_max) {
                for (uint32_t later = rank; later < screens_.size(); ++later) {
                    if (screens_[later].body == skip_body) continue;
                    ++stats.depth_rejections;
                    if (trace.enabled()) {
                        trace_line(start, direction, t_begin, t_end, HSR_STEP_SUBJECT, trace);
                        trace_box(screens_[later].body, trace);
                        trace.emit({.type = "rejected-by-depth", .edge = edge,
                                    .object = set_.bodies[screens_[later].body].object, .phase = "pretest"},
                                   russian_ ? "тело %u целиком дальше ребра и закрыть его не может"
                                            : "body %u lies wholly behind the line: it cannot hide it",
                                   set_.bodies[screens_[later].body].object);
                    }
                }
                break;
            }
            // Bounding-box pre-test in the window.
            if (line_max.x < screen.window_min.x || line_min.x > screen.window_max.x ||
                line_max.y < screen.window_min.y || line_min.y > screen.window_max.y) {
                ++stats.bounds_rejections;
                if (trace.enabled()) {
                    trace_line(start, direction, t_begin, t_end, HSR_STEP_SUBJECT, trace);
                    trace_box(body, trace);
                    trace.emit({.type = "rejected-by-bounds", .edge = edge, .object = set_.bodies[body].object,
                                .phase = "pretest"},
                               russian_ ? "тело %u: его габаритный прямоугольник на экране не задевает ребро"
                                        : "body %u: its box in the picture misses the line",
                               set_.bodies[body].object);
                }
                continue;
            }
            const uint32_t object = set_.bodies[body].object;
            ++stats.tests;
            const BodyPlanes planes = planes_of(body);
            // The hidden interval of the true body: its ends are where the line crosses the body's
            // silhouette (or surface), exactly.
            const Interval hidden = test_.hidden(planes, start, direction, t_begin, t_end);
            if (hidden.empty() || (hidden.t1 - hidden.t0) * pixels_per_t < kSliverPixels) continue;
            // It counts only if somewhere in it the line of sight passes more than `shrink` deep
            // inside the body, that is, through the body shrunk by that much. A line lying on the
            // surface, or whose line of sight only grazes it (surfaces that touch or share a plane),
            // can come out "inside" the true planes by rounding, but never inside the shrunk ones. A
            // line that does pass through the inside meets the surface of the (convex) shadow of
            // the body in at most two points, so the shrunk test never stands for a stretch of
            // touching: the interval's ends are left where the true planes put them.
            if (test_.hidden(shrunk_planes_of(body), start, direction, hidden.t0, hidden.t1).empty()) {
                ++stats.touching_rejections;
                continue;
            }
            ++stats.hidden_intervals;
            if (trace.enabled()) {
                const uint32_t exit = roberts::ParametricTest::exit_plane(planes, start, direction,
                                                                          0.5 * (hidden.t0 + hidden.t1));
                trace_line(start, direction, t_begin, t_end, HSR_STEP_SUBJECT, trace);
                trace_line(start, direction, hidden.t0, hidden.t1, HSR_STEP_REJECTED, trace);
                trace_front_polygons(body, trace);
                const uint32_t face = exit == UINT32_MAX ? HSR_NO_FACE : set_.plane_face[exit];
                trace.emit({.type = "hidden-by", .edge = edge, .face = face, .object = object, .t0 = hidden.t0,
                            .t1 = hidden.t1, .phase = "hidden-interval"},
                           russian_ ? "тело %u закрывает участок t = %.4g … %.4g (его грань %u ближе к наблюдателю)"
                                    : "body %u hides t %.4g to %.4g of the line (its face %u lies in front)",
                           object, hidden.t0, hidden.t1, face);
            }
            // Each piece loses what the body hides: at most two pieces are left of it.
            next_pieces_.clear();
            for (const Interval& piece : pieces_) {
                if (hidden.t1 <= piece.t0 || hidden.t0 >= piece.t1) {
                    next_pieces_.push_back(piece);
                    continue;
                }
                if (hidden.t0 > piece.t0) next_pieces_.push_back({piece.t0, hidden.t0});
                if (hidden.t1 < piece.t1) next_pieces_.push_back({hidden.t1, piece.t1});
            }
            pieces_.swap(next_pieces_);
        }
        // Slivers between two hidden intervals are rounding.
        if (!(pieces_.size() == 1 && pieces_[0].t0 == t_begin && pieces_[0].t1 == t_end))
            std::erase_if(pieces_, [&](const Interval& p) { return (p.t1 - p.t0) * pixels_per_t < kSliverPixels; });

        double hidden_from = t_begin;
        for (const Interval& piece : pieces_) {
            if (want_hidden && piece.t0 > hidden_from) {
                segments.add(window_at(start, direction, hidden_from), window_at(start, direction, piece.t0), edge, flags, -1);
                ++stats.pieces_hidden;
            }
            segments.add(window_at(start, direction, piece.t0), window_at(start, direction, piece.t1), edge, flags, 0);
            ++stats.pieces_visible;
            if (trace.enabled()) {
                trace_line(start, direction, t_begin, t_end, HSR_STEP_SUBJECT, trace);
                trace_line(start, direction, piece.t0, piece.t1, HSR_STEP_WRITTEN, trace);
                trace.emit({.type = "visible", .edge = edge, .qi = 0, .t0 = piece.t0, .t1 = piece.t1,
                            .phase = "visible-pieces"},
                           russian_ ? "видимый участок: t = %.4g … %.4g" : "visible: t %.4g to %.4g of the line",
                           piece.t0, piece.t1);
            }
            hidden_from = piece.t1;
        }
        if (want_hidden && t_end > hidden_from) {
            segments.add(window_at(start, direction, hidden_from), window_at(start, direction, t_end), edge, flags, -1);
            ++stats.pieces_hidden;
        }
        return !pieces_.empty();
    }

    // --- steps for a viewer (only when tracing) ----------------------------------------------------

    // The piece [t0, t1] of start + t·direction (in front of the eye) as a line of the next event.
    void trace_line(glm::dvec3 start, glm::dvec3 direction, double t0, double t1, hsr_step_role role,
                    const hsr::sdk::Trace& trace) const {
        const glm::dvec2 p = window_at(start, direction, t0), q = window_at(start, direction, t1);
        trace.line(float(p.x), float(p.y), float(q.x), float(q.y), role);
    }
    // A body's box in the picture (none when it reaches behind the eye).
    void trace_box(uint32_t body, const hsr::sdk::Trace& trace) const {
        const BodyView& v = body_views_[body];
        if (!v.window_box_valid) return;
        const float x0 = float(v.window_min.x), y0 = float(v.window_min.y);
        const float x1 = float(v.window_max.x), y1 = float(v.window_max.y);
        trace.line(x0, y0, x1, y0, HSR_STEP_CONTEXT);
        trace.line(x1, y0, x1, y1, HSR_STEP_CONTEXT);
        trace.line(x1, y1, x0, y1, HSR_STEP_CONTEXT);
        trace.line(x0, y1, x0, y0, HSR_STEP_CONTEXT);
    }
    // The edges of a body's faces turned toward the eye, as lines of the next event (CONTEXT): the
    // sides of its polygons, never the diagonals a triangulation added inside one.
    void trace_front_polygons(uint32_t b, const hsr::sdk::Trace& trace) const {
        const hsr_scene& s = *scene_;
        for (uint32_t k = body_triangle_first_[b]; k < body_triangle_first_[b + 1]; ++k) {
            const uint32_t t = body_triangles_[k];
            const uint32_t plane = set_.plane_of_triangle[t];
            if (plane_is_back_[plane]) continue;
            for (int i = 0; i < 3; ++i) {
                const int32_t n = s.edge_neighbors[3 * size_t(t) + i];
                if (n != HSR_NO_NEIGHBOR) {
                    const uint32_t other = set_.plane_of_triangle[uint32_t(n)];
                    if (other == plane) continue;                                // a diagonal
                    if (!plane_is_back_[other] && uint32_t(n) < t) continue;  // drawn from the other side
                }
                const glm::dvec3 a = position(s, s.indices[3 * size_t(t) + i]);
                const glm::dvec3 c = position(s, s.indices[3 * size_t(t) + (i + 1) % 3]);
                double t_begin, t_end;
                if (view_.in_front(a, c, t_begin, t_end)) trace_line(a, c - a, t_begin, t_end, HSR_STEP_CONTEXT, trace);
            }
        }
    }
    // One "body" event per body, showing the sides of its faces that face the eye (CONTEXT).
    void trace_bodies(const hsr_scene& s, const hsr::sdk::Trace& trace) {
        scene_ = &s;
        // The triangles of each body, grouped by a counting sort over the planes' bodies.
        std::vector<uint32_t> body_of_plane(set_.planes.size(), 0);
        body_triangle_first_.assign(set_.bodies.size() + 1, 0);
        body_triangles_.resize(s.triangle_count);
        for (uint32_t b = 0; b < set_.bodies.size(); ++b)
            for (uint32_t j = 0; j < set_.bodies[b].plane_count; ++j) body_of_plane[set_.bodies[b].first_plane + j] = b;
        for (uint32_t t = 0; t < s.triangle_count; ++t) ++body_triangle_first_[body_of_plane[set_.plane_of_triangle[t]] + 1];
        for (size_t b = 0; b < set_.bodies.size(); ++b) body_triangle_first_[b + 1] += body_triangle_first_[b];
        std::vector<uint32_t> next(body_triangle_first_.begin(), body_triangle_first_.end() - 1);
        for (uint32_t t = 0; t < s.triangle_count; ++t) body_triangles_[next[body_of_plane[set_.plane_of_triangle[t]]]++] = t;
        for (uint32_t b = 0; b < set_.bodies.size(); ++b) {
            const roberts::Body& body = set_.bodies[b];
            trace_front_polygons(b, trace);
            const uint32_t front = body_views_[b].exact.front_count;
            trace.emit({.type = "body", .face = set_.plane_face[body.first_plane], .object = body.object,
                        .phase = "back-faces"},
                       russian_ ? "тело %u: %u граней; к наблюдателю обращены %u, остальные %u — нелицевые, их удаляем"
                                : "body %u: %u planes, %u of them facing the eye; the %u back faces are removed",
                       body.object, body.plane_count, front, body.plane_count - front);
        }
    }

    roberts::BodyBuilder builder_;
    roberts::BodySet set_;
    roberts::ParametricTest test_;
    View view_;
    std::vector<double> eye_weight_;         // per plane: w = E · V
    std::vector<double> shrunk_weight_;      // per plane: w of the plane moved inward by its body's shrink
    std::vector<uint8_t> plane_is_back_;     // per plane: turned away from the eye (or edge-on)
    std::vector<uint32_t> ordered_planes_;   // each body's planes: front, edge-on, back (by eye_weight_)
    std::vector<uint32_t> ordered_shrunk_;   // the same by shrunk_weight_
    std::vector<BodyView> body_views_;
    struct Screen {  // what the pre-tests need of one body
        double depth_min;
        glm::dvec2 window_min, window_max;
        uint32_t body;
    };
    std::vector<Screen> screens_;            // nearest body first
    std::vector<Interval> pieces_, next_pieces_;
    std::vector<roberts::PenetrationLine> penetration_lines_;
    // Steps only: the language of their texts, and each body's triangles (body_triangles_ from
    // body_triangle_first_[b] to body_triangle_first_[b + 1]).
    bool russian_ = false;
    const hsr_scene* scene_ = nullptr;
    std::vector<uint32_t> body_triangle_first_, body_triangles_;
};

}  // namespace

HSR_EXPORT_PLUGIN(Roberts)
