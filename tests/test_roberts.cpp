// The roberts hidden-line plugin (Roberts 1963, convex bodies). Every answer is checked against
// something the plugin does not compute itself: the ray-casting reference of line_reference.hpp for
// mesh edges; for penetration lines the intersection of the two bodies' triangles, found here
// triangle by triangle, with visibility again by ray casting; for the ends of pieces of mesh edges
// the crossings of the projected edges and the points where edges pierce other bodies' triangles,
// computed here; hand-computed end points; the host's own edge classification for a single body.
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/lines.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "line_test_support.hpp"

#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using line_tests::model;
using line_tests::orbit;

namespace {

hsr::LineDrawing draw(const hsr::SceneData& data, const hsr_camera& camera, bool want_hidden,
                      std::ostream* trace = nullptr) {
    const hsr_scene scene = data.view();
    hsr::LineSettings settings;
    settings.edges = hsr::EdgeSelection::kAll;
    settings.want_hidden = want_hidden;
    settings.trace = trace;
    return line_tests::draw("roberts", scene, camera, settings);
}

// Box from the cube model: scaled, turned about `axis`, then moved.
glm::mat4 box_transform(glm::vec3 centre, glm::vec3 half_size, float degrees = 0, glm::vec3 axis = {0, 1, 0}) {
    glm::mat4 m = glm::translate(glm::mat4(1.0f), centre);
    if (degrees != 0) m = glm::rotate(m, glm::radians(degrees), glm::normalize(axis));
    return glm::scale(m, half_size);
}

void add_box(hsr::SceneBuilder& builder, glm::vec3 centre, glm::vec3 half_size, float degrees = 0,
             glm::vec3 axis = {0, 1, 0}) {
    hsr::MeshOptions options;
    options.transform = box_transform(centre, half_size, degrees, axis);
    builder.add_model_file(std::string(HSR_MODELS_DIR) + "/cube.obj", options);
}

// Separate boxes, boxes that intersect each other, and one that pierces a floor slab.
const hsr::SceneData& box_scene() {
    static const hsr::SceneData scene = [] {
        hsr::SceneBuilder b;
        add_box(b, {0, -1.2f, 0}, {3, 0.3f, 3}, 5, {0, 1, 0});                // floor slab
        add_box(b, {-1.8f, 0, -1}, {0.5f, 0.5f, 0.5f}, 25, {0, 1, 0});        // alone
        add_box(b, {0.8f, 0.3f, 0.5f}, {0.6f, 0.6f, 0.6f}, 30, {1, 1, 0});    // these two
        add_box(b, {1.2f, 0.4f, 0.9f}, {0.4f, 0.9f, 0.4f}, 15, {0, 0, 1});    // intersect
        add_box(b, {-0.5f, -1.0f, 1.2f}, {0.3f, 0.8f, 0.3f}, 10, {1, 0, 0});  // through the slab
        add_box(b, {0.3f, 0.5f, -2.8f}, {0.7f, 0.7f, 0.7f}, 40, {0.3f, 1, 0.2f}); // behind
        return b.build();
    }();
    return scene;
}

// Twelve boxes of random sizes and turns, thrown into a small space: many intersect.
const hsr::SceneData& random_box_scene() {
    static const hsr::SceneData scene = [] {
        std::mt19937 random(1963);
        std::uniform_real_distribution<float> place(-1.2f, 1.2f), half(0.15f, 0.7f), angle(0, 360), axis(-1, 1);
        hsr::SceneBuilder b;
        for (int k = 0; k < 12; ++k) {
            const glm::vec3 centre(place(random), place(random), place(random));
            const glm::vec3 size(half(random), half(random), half(random));
            const float degrees = angle(random);
            const glm::vec3 turn(axis(random), axis(random), axis(random) + 0.01f);
            add_box(b, centre, size, degrees, turn);
        }
        return b.build();
    }();
    return scene;
}

// The other convex models of models/, pushed into each other and into a cube.
const hsr::SceneData& solids_scene() {
    static const hsr::SceneData scene = [] {
        hsr::SceneBuilder b;
        const auto add = [&](const char* file, glm::vec3 centre, float scale, float degrees, glm::vec3 axis) {
            hsr::MeshOptions options;
            options.transform = box_transform(centre, glm::vec3(scale), degrees, axis);
            b.add_model_file(std::string(HSR_MODELS_DIR) + "/" + file, options);
        };
        add("octahedron.ply", {0, 0, 0}, 1.2f, 20, {1, 0.5f, 0});
        add("tetrahedron.off", {0.9f, 0.3f, 0.2f}, 0.7f, 35, {0, 1, 0.3f});
        add("pyramid.stl", {-0.6f, -0.7f, 0.4f}, 0.8f, 15, {0.2f, 0, 1});
        add("cube.obj", {0.3f, 0.9f, -0.6f}, 0.5f, 50, {1, 1, 1});
        return b.build();
    }();
    return scene;
}

struct View {
    float yaw, pitch;
    bool ortho;
};
const View kViews[] = {{35, 25, false}, {35, 25, true},  {-60, 15, false}, {150, 40, true},
                       {200, -20, false}, {80, 60, true}, {-130, 35, false}, {10, 5, true}};

// The views above and 16 more from pseudo-random eye points, half of them orthographic.
std::vector<View> many_views() {
    std::vector<View> views(std::begin(kViews), std::end(kViews));
    std::mt19937 random(315);
    std::uniform_real_distribution<float> yaw(-180, 180), pitch(-75, 75);
    for (int k = 0; k < 16; ++k) views.push_back({yaw(random), pitch(random), k % 2 == 1});
    return views;
}

void check_against_ray_casting(const hsr::SceneData& data, const hsr_camera& camera) {
    const hsr::LineDrawing d = draw(data, camera, false);
    const hsr_scene scene = data.view();
    const line_reference::Comparison c =
        line_reference::compare(scene, camera, d.edges, line_tests::reference_segments(d), 0.25, 0.5);
    INFO(c.first);
    CHECK(c.checked > c.samples / 2);
    CHECK(c.disagreements == 0);
    CHECK(c.reference_visible > 0);
}

// --- penetration lines, found independently: triangle against triangle --------------------------

glm::dvec3 vertex(const hsr_scene& s, uint32_t t, int corner) {
    return line_reference::position(s, s.indices[3 * t + corner]);
}

// Where segment p->q crosses triangle (a, b, c), if it does (barycentrics and segment parameter
// inside with a small slack).
bool segment_crosses(glm::dvec3 p, glm::dvec3 q, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3& hit) {
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double dp = glm::dot(n, p - a), dq = glm::dot(n, q - a);
    if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0) || dp == dq) return false;
    const glm::dvec3 x = p + (q - p) * (dp / (dp - dq));
    const double area = glm::dot(n, n), slack = -1e-12;
    const double u = glm::dot(glm::cross(c - b, x - b), n) / area;
    const double v = glm::dot(glm::cross(a - c, x - c), n) / area;
    const double w = 1.0 - u - v;
    if (u < slack || v < slack || w < slack) return false;
    hit = x;
    return true;
}

struct Curve {
    glm::dvec3 a, b;           // on both surfaces
    uint32_t triangle0, triangle1;
};

std::vector<Curve> surface_intersections(const hsr_scene& s) {
    std::vector<Curve> out;
    for (uint32_t t = 0; t < s.triangle_count; ++t)
        for (uint32_t u = t + 1; u < s.triangle_count; ++u) {
            if (s.face_object[t] == s.face_object[u]) continue;
            std::vector<glm::dvec3> points;
            glm::dvec3 hit;
            for (int i = 0; i < 3; ++i) {
                if (segment_crosses(vertex(s, t, i), vertex(s, t, (i + 1) % 3), vertex(s, u, 0), vertex(s, u, 1),
                                    vertex(s, u, 2), hit))
                    points.push_back(hit);
                if (segment_crosses(vertex(s, u, i), vertex(s, u, (i + 1) % 3), vertex(s, t, 0), vertex(s, t, 1),
                                    vertex(s, t, 2), hit))
                    points.push_back(hit);
            }
            double longest = 0;
            Curve best{};
            for (size_t i = 0; i < points.size(); ++i)
                for (size_t j = i + 1; j < points.size(); ++j)
                    if (glm::length(points[i] - points[j]) > longest) {
                        longest = glm::length(points[i] - points[j]);
                        best = {points[i], points[j], t, u};
                    }
            if (!(longest > 1e-9)) continue;
            // A piece along an edge of either triangle is where one body's edge lies in the other's
            // face (the red and green bars of boxes.scene share their z faces): the surfaces touch
            // there and the line drawn is that mesh edge, not a penetration line.
            bool along_edge = false;
            for (const uint32_t tri : {t, u})
                for (int i = 0; i < 3; ++i) {
                    const glm::dvec3 p = vertex(s, tri, i), q = vertex(s, tri, (i + 1) % 3);
                    const glm::dvec3 d = glm::normalize(q - p);
                    const auto off = [&](glm::dvec3 x) { return glm::length(glm::cross(x - p, d)); };
                    if (off(best.a) < 1e-6 && off(best.b) < 1e-6) along_edge = true;
                }
            if (!along_edge) out.push_back(best);
        }
    return out;
}

double distance_to_segment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 d = b - a;
    const double len2 = glm::dot(d, d);
    const double u = len2 > 0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    return glm::length(a + u * d - p);
}

struct PenetrationCheck {
    uint64_t plugin_segments = 0, endpoints_off_curve = 0;
    uint64_t samples = 0, checked = 0, uncovered = 0, disagreements = 0, reference_visible = 0;
    std::string first;
};

// The plugin's penetration segments against the triangle-by-triangle intersection of the bodies:
// their end points lie on the projected curve (within 0.01 px); every sample of the curve away
// from changes of visibility is covered by one of them, and by a visible one exactly when ray
// casting from the 3D point to the eye meets no triangle.
PenetrationCheck check_penetration(const hsr::SceneData& data, const hsr_camera& camera, const hsr::LineDrawing& d) {
    const hsr_scene s = data.view();
    const glm::dmat4 vp = line_reference::view_projection(camera);
    const std::vector<Curve> curves = surface_intersections(s);
    std::vector<hsr::LineSegment> plugin;
    for (const hsr::LineSegment& seg : d.segments)
        if (seg.flags & HSR_EDGE_PENETRATION) {
            CHECK(seg.edge == HSR_NO_EDGE);
            plugin.push_back(seg);
        }
    PenetrationCheck out;
    out.plugin_segments = plugin.size();
    std::vector<std::pair<glm::dvec2, glm::dvec2>> projected;
    for (const Curve& c : curves)
        projected.emplace_back(line_reference::to_window(camera, vp, c.a), line_reference::to_window(camera, vp, c.b));
    for (const hsr::LineSegment& seg : plugin)
        for (const glm::dvec2 end : {glm::dvec2(seg.a), glm::dvec2(seg.b)}) {
            double nearest = 1e30;
            for (const auto& [a, b] : projected) nearest = std::min(nearest, distance_to_segment(end, a, b));
            if (nearest > 0.01) ++out.endpoints_off_curve;
        }
    for (size_t k = 0; k < curves.size(); ++k) {
        const Curve& c = curves[k];
        const auto [wa, wb] = projected[k];
        const glm::dvec2 along = glm::normalize(wb - wa);
        const int n = std::max(8, int(std::ceil(glm::length(wb - wa) / 0.25)));
        std::vector<int> reference(n + 1);
        std::vector<glm::dvec2> window(n + 1);
        for (int i = 0; i <= n; ++i) {
            const glm::dvec3 p = c.a + (c.b - c.a) * ((i + 0.5) / (n + 1.0));
            window[i] = line_reference::to_window(camera, vp, p);
            reference[i] = line_reference::occluders(s, camera, p, c.triangle0, c.triangle1) == 0 ? 1 : 0;
        }
        for (int i = 0; i <= n; ++i) {
            ++out.samples;
            bool near_change = glm::length(window[i] - wa) < 0.5 || glm::length(window[i] - wb) < 0.5;
            for (int j = std::max(0, i - 3); j < std::min(n, i + 3); ++j)
                if (reference[j] != reference[j + 1] && glm::length(0.5 * (window[j] + window[j + 1]) - window[i]) <= 0.5)
                    near_change = true;
            for (const hsr::LineSegment& seg : plugin)
                if (glm::length(glm::dvec2(seg.a) - window[i]) <= 0.5 || glm::length(glm::dvec2(seg.b) - window[i]) <= 0.5)
                    near_change = true;
            // Another piece of curve over this one in the picture (two lines on a face seen nearly
            // edge-on): the window alone cannot tell whose segment is whose.
            for (size_t other = 0; other < curves.size() && !near_change; ++other)
                if (other != k && distance_to_segment(window[i], projected[other].first, projected[other].second) < 0.1)
                    near_change = true;
            if (near_change) continue;
            ++out.checked;
            out.reference_visible += reference[i];
            bool covered = false, visible = false;
            for (const hsr::LineSegment& seg : plugin) {
                const glm::dvec2 a(seg.a), b(seg.b);
                if (distance_to_segment(window[i], a, b) > 0.02) continue;
                // Along the same line, not merely crossing it.
                if (glm::length(b - a) > 1e-9 && std::abs(along.x * (b - a).y - along.y * (b - a).x) > 1e-3 * glm::length(b - a))
                    continue;
                covered = true;
                if (seg.qi == 0) visible = true;
            }
            if (!covered) ++out.uncovered;
            if (visible != (reference[i] == 1)) {
                if (out.disagreements == 0)
                    out.first = "curve " + std::to_string(k) + " sample " + std::to_string(i) + " at (" +
                                std::to_string(window[i].x) + ", " + std::to_string(window[i].y) + "): ray casting says " +
                                (reference[i] ? "visible" : "hidden");
                ++out.disagreements;
            }
        }
    }
    return out;
}

// --- end points of hidden intervals, found independently ---------------------------------------

// How far (in pixels) each end of a piece of a mesh edge lies from where it should be: the
// projection of one of the edge's vertices, the crossing of the edge with another edge in the
// picture (computed here in double: a silhouette edge of the hiding body), or the projection of
// the point where the edge pierces a triangle of another object. The worst over all pieces.
struct EndPointCheck {
    double worst = 0;  // pixels
    uint64_t ends = 0, crossings = 0;
    std::string first;
};

EndPointCheck check_end_points(const hsr::SceneData& data, const hsr_camera& camera, const hsr::LineDrawing& d) {
    const hsr_scene s = data.view();
    const glm::dmat4 vp = line_reference::view_projection(camera);
    const size_t edge_count = d.edges.size();
    std::vector<glm::dvec3> p0(edge_count), p1(edge_count);
    std::vector<glm::dvec2> w0(edge_count), w1(edge_count);
    for (size_t e = 0; e < edge_count; ++e) {
        p0[e] = line_reference::position(s, d.edges.vertices[2 * e]);
        p1[e] = line_reference::position(s, d.edges.vertices[2 * e + 1]);
        w0[e] = line_reference::to_window(camera, vp, p0[e]);
        w1[e] = line_reference::to_window(camera, vp, p1[e]);
    }
    const auto cross2 = [](glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; };
    EndPointCheck out;
    for (const hsr::LineSegment& seg : d.segments) {
        if (seg.edge == HSR_NO_EDGE) continue;
        const uint32_t e = seg.edge;
        const uint32_t object = s.face_object[d.edges.faces[2 * e]];
        for (const glm::dvec2 end : {glm::dvec2(seg.a), glm::dvec2(seg.b)}) {
            ++out.ends;
            double nearest = std::min(glm::length(end - w0[e]), glm::length(end - w1[e]));
            if (nearest < 1e-3) continue;
            ++out.crossings;
            const glm::dvec2 d0 = w1[e] - w0[e];
            for (size_t f = 0; f < edge_count; ++f) {
                const glm::dvec2 d1 = w1[f] - w0[f];
                const double denominator = cross2(d0, d1);
                if (f == e || std::abs(denominator) < 1e-12 * glm::dot(d0, d0) * glm::dot(d1, d1)) continue;
                const double u = cross2(w0[f] - w0[e], d1) / denominator, v = cross2(w0[f] - w0[e], d0) / denominator;
                if (u < -1e-9 || u > 1 + 1e-9 || v < -1e-9 || v > 1 + 1e-9) continue;
                nearest = std::min(nearest, glm::length(w0[e] + u * d0 - end));
            }
            glm::dvec3 hit;
            for (uint32_t t = 0; t < s.triangle_count; ++t)
                if (s.face_object[t] != object &&
                    segment_crosses(p0[e], p1[e], vertex(s, t, 0), vertex(s, t, 1), vertex(s, t, 2), hit))
                    nearest = std::min(nearest, glm::length(line_reference::to_window(camera, vp, hit) - end));
            if (nearest > out.worst) {
                out.worst = nearest;
                out.first = "edge " + std::to_string(e) + " end (" + std::to_string(end.x) + ", " +
                            std::to_string(end.y) + ") is " + std::to_string(nearest) + " px from the nearest crossing";
            }
        }
    }
    return out;
}

// The "object N ... vertex V ... lies X outside ... triangle T" numbers of a refusal.
struct Refusal {
    unsigned object = 0, vertex = 0, triangle = 0;
    double outside = 0;
    bool parsed = false;
};
Refusal parse_refusal(const std::string& message) {
    Refusal r;
    const size_t at = message.find("object ");
    if (at == std::string::npos) return r;
    double x, y, z;
    char tail[64];
    r.parsed = std::sscanf(message.c_str() + at,
                           "object %u is not convex: vertex %u at (%lf, %lf, %lf) lies %lf outside the plane of the face "
                           "containing triangle %u%63s",
                           &r.object, &r.vertex, &x, &y, &z, &r.outside, &r.triangle, tail) == 8;
    return r;
}

std::string refusal_of(const hsr::SceneData& data) {
    const hsr_camera camera = orbit(data, 30, 20, 1, false, 128);
    try {
        draw(data, camera, false);
    } catch (const hsr::Error& e) {
        // A mesh roberts cannot take is input it refuses, the asker's to fix.
        const auto* refused = dynamic_cast<const hsr::PluginError*>(&e);
        CHECK((refused != nullptr && refused->status == HSR_ERROR_INVALID_ARGUMENT));
        CHECK(hsr::is_client_error(e));
        return e.what();
    }
    return "";
}

void add_quad(std::vector<uint32_t>& indices, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    indices.insert(indices.end(), {a, b, c, a, c, d});
}

// The unit cube's 8 corners and 12 triangles, counter-clockwise from outside, moved by `offset`.
void append_cube(std::vector<glm::vec3>& positions, std::vector<uint32_t>& indices, glm::vec3 offset) {
    const uint32_t base = uint32_t(positions.size());
    for (int k = 0; k < 8; ++k) positions.push_back(offset + glm::vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
    const auto q = [&](int a, int b, int c, int d) { add_quad(indices, base + a, base + b, base + c, base + d); };
    q(0, 2, 3, 1);  // z = 0, normal -z
    q(4, 5, 7, 6);  // z = 1
    q(0, 1, 5, 4);  // y = 0
    q(2, 6, 7, 3);  // y = 1
    q(0, 4, 6, 2);  // x = 0
    q(1, 3, 7, 5);  // x = 1
}

}  // namespace

TEST_CASE("roberts: the cube agrees with ray casting from general eye points", "[roberts]") {
    const hsr::SceneData& cube = model("cube.obj");
    for (const View& v : many_views()) {
        INFO("yaw " << v.yaw << " pitch " << v.pitch << " orthographic " << v.ortho);
        check_against_ray_casting(cube, orbit(cube, v.yaw, v.pitch, 1, v.ortho, 300));
    }
}

TEST_CASE("roberts: boxes.scene (three intersecting boxes) agrees with ray casting", "[roberts]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    REQUIRE(boxes.object_names.size() == 3);
    for (const View& v : many_views()) {
        INFO("yaw " << v.yaw << " pitch " << v.pitch << " orthographic " << v.ortho);
        check_against_ray_casting(boxes, orbit(boxes, v.yaw, v.pitch, 1.3f, v.ortho, 400));
    }
}

TEST_CASE("roberts: separate and intersecting boxes and other solids agree with ray casting", "[roberts]") {
    for (const hsr::SceneData* scene : {&box_scene(), &random_box_scene(), &solids_scene()})
        for (const View& v : many_views()) {
            INFO((scene == &box_scene() ? "built" : scene == &solids_scene() ? "solids" : "random")
                 << ": yaw " << v.yaw << " pitch " << v.pitch << " orthographic " << v.ortho);
            check_against_ray_casting(*scene, orbit(*scene, v.yaw, v.pitch, 1, v.ortho, 400));
        }
}

TEST_CASE("roberts: penetration lines lie on both bodies and their visibility agrees with ray casting", "[roberts]") {
    for (const std::string which : {"boxes.scene", "built", "random", "solids"}) {
        const hsr::SceneData& data = which == "built"    ? box_scene()
                                     : which == "random" ? random_box_scene()
                                     : which == "solids" ? solids_scene()
                                                         : model("boxes.scene");
        for (const View& v : many_views()) {
            INFO(which << ": yaw " << v.yaw << " pitch " << v.pitch << " orthographic " << v.ortho);
            const hsr_camera camera = orbit(data, v.yaw, v.pitch, 1.2f, v.ortho, 400);
            const hsr::LineDrawing d = draw(data, camera, true);
            CHECK(d.counter("penetration-lines") > 0);
            const PenetrationCheck c = check_penetration(data, camera, d);
            INFO(c.first);
            CHECK(c.plugin_segments > 0);
            CHECK(c.endpoints_off_curve == 0);
            CHECK(c.checked > c.samples / 3);  // the rest lie near corners, ends, or overlap in the picture
            CHECK(c.uncovered == 0);
            CHECK(c.disagreements == 0);
            // Without hidden pieces, the same visible penetration lines come back.
            const hsr::LineDrawing visible_only = draw(data, camera, false);
            uint64_t visible_with = 0, visible_without = 0, hidden_without = 0;
            for (const auto& s : d.segments) visible_with += (s.flags & HSR_EDGE_PENETRATION) && s.qi == 0;
            for (const auto& s : visible_only.segments) {
                visible_without += (s.flags & HSR_EDGE_PENETRATION) && s.qi == 0;
                hidden_without += s.qi != 0;
            }
            CHECK(visible_with == visible_without);
            CHECK(hidden_without == 0);
        }
    }
}

TEST_CASE("roberts: hidden pieces end exactly where the edge crosses the hiding silhouette", "[roberts]") {
    // Touching and coplanar faces must not hide each other, but the bodies are not shrunk for the
    // end points: they are the exact crossings in the picture, to the float window coordinates'
    // rounding (about 3e-5 px at these sizes).
    for (const std::string which : {"boxes.scene", "built", "random", "solids"}) {
        const hsr::SceneData& data = which == "built"    ? box_scene()
                                     : which == "random" ? random_box_scene()
                                     : which == "solids" ? solids_scene()
                                                         : model("boxes.scene");
        for (const View& v : kViews) {
            INFO(which << ": yaw " << v.yaw << " pitch " << v.pitch << " orthographic " << v.ortho);
            const hsr_camera camera = orbit(data, v.yaw, v.pitch, 1, v.ortho, 640);
            const EndPointCheck c = check_end_points(data, camera, draw(data, camera, true));
            INFO(c.first);
            CHECK(c.crossings > 0);
            CHECK(c.worst <= 1e-4);
        }
    }
}

TEST_CASE("roberts: boxes that only touch have no penetration lines", "[roberts]") {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    append_cube(positions, indices, {0, 0, 0});
    hsr::SceneBuilder builder;
    builder.add_triangles(positions, indices);
    // A second unit cube standing on the first, shifted half a unit: its bottom lies in the first's top.
    positions.clear();
    indices.clear();
    append_cube(positions, indices, {0.5f, 1, 0.25f});
    builder.add_triangles(positions, indices);
    const hsr::SceneData data = builder.build();
    for (const View& v : kViews) {
        if (v.pitch < 0) continue;  // seen from above the contact
        INFO("yaw " << v.yaw << " pitch " << v.pitch << " orthographic " << v.ortho);
        const hsr_camera camera = orbit(data, v.yaw, v.pitch, 1, v.ortho, 300);
        const hsr::LineDrawing d = draw(data, camera, true);
        CHECK(d.counter("penetration-lines") == 0);
        check_against_ray_casting(data, camera);
    }
}

TEST_CASE("roberts: a single convex body shows exactly its front edges, whole", "[roberts]") {
    hsr::SceneBuilder builder;
    add_box(builder, {0.2f, -0.1f, 0.3f}, {1.0f, 0.6f, 0.4f}, 33, {1, 2, 0.5f});
    const hsr::SceneData box = builder.build();
    for (const hsr::SceneData* data : {&model("cube.obj"), &box})
        for (const View& v : kViews) {
            INFO("yaw " << v.yaw << " pitch " << v.pitch << " orthographic " << v.ortho);
            const hsr_camera camera = orbit(*data, v.yaw, v.pitch, 1, v.ortho, 256);
            const hsr::LineDrawing d = draw(*data, camera, true);
            const hsr_scene scene = data->view();
            const glm::dmat4 vp = line_reference::view_projection(camera);
            REQUIRE(d.edges.size() == 12);
            for (uint32_t e = 0; e < d.edges.size(); ++e) {
                std::vector<hsr::LineSegment> pieces;
                for (const auto& s : d.segments)
                    if (s.edge == e) pieces.push_back(s);
                REQUIRE(pieces.size() == 1);
                // The host's classification: every face of a back edge is turned away.
                const bool back = (d.edges.flags[e] & HSR_EDGE_BACK) != 0;
                CHECK(pieces[0].qi == (back ? -1 : 0));
                const glm::dvec2 a = line_reference::to_window(camera, vp, line_reference::position(scene, d.edges.vertices[2 * e]));
                const glm::dvec2 b = line_reference::to_window(camera, vp, line_reference::position(scene, d.edges.vertices[2 * e + 1]));
                CHECK(glm::length(glm::dvec2(pieces[0].a) - a) < 1e-3);
                CHECK(glm::length(glm::dvec2(pieces[0].b) - b) < 1e-3);
            }
            // Three faces turned away (or, in perspective, possibly four): the host counts the same.
            uint32_t host_back = 0;
            for (uint32_t flags : d.edges.flags) host_back += (flags & HSR_EDGE_BACK) != 0;
            CHECK(d.counter("edges-back") == host_back);
            CHECK((host_back == 3 || host_back == 5));
            CHECK(d.counter("penetration-lines") == 0);
            CHECK(d.counter("bodies") == 1);
            CHECK(d.counter("planes") == 6);
        }
}

TEST_CASE("roberts: a box hides part of an edge of another (end points by hand)", "[roberts]") {
    // Pixel camera: world (x, y, z) lands at window (x, 100 - y), the viewer looks along -z.
    // Body 0, behind: a frustum with its small face toward the viewer, z = 0, x and y in [20, 60], and
    // its large face at z = -20, x and y in [10, 70]; all five faces but the large one face the viewer.
    // Body 1, in front: the box x in [40, 80], y in [30, 50], z in [10, 20].
    // The small face's right edge, x = 60 from y = 20 to y = 60 at z = 0, passes behind the box
    // (40 < 60 < 80) where 30 < y < 50: visible from window (60, 80) to (60, 70) and from (60, 50)
    // to (60, 40), hidden between.
    std::vector<glm::vec3> frustum = {{20, 20, 0},  {60, 20, 0},  {60, 60, 0},  {20, 60, 0},
                                      {10, 10, -20}, {70, 10, -20}, {70, 70, -20}, {10, 70, -20}};
    std::vector<uint32_t> indices;
    add_quad(indices, 0, 1, 2, 3);  // front, +z
    add_quad(indices, 4, 7, 6, 5);  // back, -z
    add_quad(indices, 1, 5, 6, 2);  // right
    add_quad(indices, 0, 3, 7, 4);  // left
    add_quad(indices, 3, 2, 6, 7);  // top
    add_quad(indices, 0, 4, 5, 1);  // bottom
    hsr::SceneBuilder builder;
    builder.add_triangles(frustum, indices);
    add_box(builder, {60, 40, 15}, {20, 10, 5});
    const hsr::SceneData data = builder.build();
    const hsr_camera camera = hsr::make_pixel_camera(100, 100, -30, 30);

    const hsr::LineDrawing d = draw(data, camera, true);
    // The requested edge from (60, 20, 0) to (60, 60, 0), whichever way round the host lists it.
    const hsr_scene scene = data.view();
    uint32_t edge = HSR_NO_EDGE;
    for (uint32_t e = 0; e < d.edges.size(); ++e) {
        const glm::dvec3 a = line_reference::position(scene, d.edges.vertices[2 * e]);
        const glm::dvec3 b = line_reference::position(scene, d.edges.vertices[2 * e + 1]);
        const glm::dvec3 lo = glm::min(a, b), hi = glm::max(a, b);
        if (lo == glm::dvec3(60, 20, 0) && hi == glm::dvec3(60, 60, 0)) edge = e;
    }
    REQUIRE(edge != HSR_NO_EDGE);
    std::vector<std::pair<double, double>> visible, hidden;  // window y ranges, top first
    for (const auto& s : d.segments) {
        if (s.edge != edge) continue;
        CHECK(std::abs(s.a.x - 60) < 1e-5);
        CHECK(std::abs(s.b.x - 60) < 1e-5);
        (s.qi == 0 ? visible : hidden).emplace_back(std::min(s.a.y, s.b.y), std::max(s.a.y, s.b.y));
    }
    std::sort(visible.begin(), visible.end());
    REQUIRE(visible.size() == 2);
    // Exact to the float window coordinates' rounding (the box is not shrunk for the end points).
    const auto exactly = [](double value) { return Approx(value).epsilon(0).margin(1e-5); };
    CHECK(visible[0].first == exactly(40));
    CHECK(visible[0].second == exactly(50));
    CHECK(visible[1].first == exactly(70));
    CHECK(visible[1].second == exactly(80));
    REQUIRE(hidden.size() == 1);
    CHECK(hidden[0].first == exactly(50));
    CHECK(hidden[0].second == exactly(70));
    CHECK(d.counter("bodies") == 2);
    CHECK(d.counter("penetration-lines") == 0);

    // Without hidden pieces: the same two visible ones only.
    const hsr::LineDrawing v = draw(data, camera, false);
    uint64_t pieces = 0;
    for (const auto& s : v.segments) {
        CHECK(s.qi == 0);
        pieces += s.edge == edge;
    }
    CHECK(pieces == 2);
}

TEST_CASE("roberts: a non-convex body is refused with a message naming it", "[roberts]") {
    SECTION("the monkey") {
        const std::string message = refusal_of(model("monkey.obj"));
        INFO(message);
        CHECK(message.find("roberts: object 0 is not convex") != std::string::npos);
    }
    SECTION("an L-shaped prism, second object of the scene") {
        // The L: (0,0) (2,0) (2,1) (1,1) (1,2) (0,2), from z = 0 to z = 1; its reflex corner is (1, 1).
        const glm::vec2 outline[6] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
        std::vector<glm::vec3> positions;
        for (float z : {0.0f, 1.0f})
            for (const glm::vec2 p : outline) positions.push_back({p.x + 5, p.y, z});
        std::vector<uint32_t> indices;
        for (uint32_t k = 1; k + 1 < 6; ++k) {  // caps: fans from corner 0 (the L is star-shaped from it)
            indices.insert(indices.end(), {0, k + 1, k});      // z = 0, facing -z
            indices.insert(indices.end(), {6, 6 + k, 7 + k});  // z = 1, facing +z
        }
        for (uint32_t k = 0; k < 6; ++k) add_quad(indices, k, (k + 1) % 6, 6 + (k + 1) % 6, 6 + k);
        hsr::SceneBuilder builder;
        add_box(builder, {0, 0, 0}, {1, 1, 1});
        builder.add_triangles(positions, indices);
        const hsr::SceneData data = builder.build();
        const std::string message = refusal_of(data);
        INFO(message);
        CHECK(message.find("roberts: object 1 is not convex") != std::string::npos);
        CHECK(message.find("convex part") != std::string::npos);
        // The numbers in the message: the vertex lies that far outside that triangle's plane.
        const Refusal r = parse_refusal(message);
        REQUIRE(r.parsed);
        CHECK(r.object == 1);
        const hsr_scene scene = data.view();
        REQUIRE(r.triangle < scene.triangle_count);
        REQUIRE(r.vertex < scene.vertex_count);
        CHECK(scene.face_object[r.triangle] == 1);
        const glm::dvec3 a = vertex(scene, r.triangle, 0);
        const glm::dvec3 n = glm::normalize(glm::cross(vertex(scene, r.triangle, 1) - a, vertex(scene, r.triangle, 2) - a));
        const double outside = glm::dot(n, line_reference::position(scene, r.vertex) - a);
        CHECK(outside == Approx(r.outside).epsilon(1e-4));
        CHECK(outside == Approx(1.0));  // across the reflex edge the other wall is 1 away
    }
    SECTION("two boxes given as one object") {
        std::vector<glm::vec3> positions;
        std::vector<uint32_t> indices;
        append_cube(positions, indices, {0, 0, 0});
        append_cube(positions, indices, {3, 0, 0});
        hsr::SceneBuilder builder;
        builder.add_triangles(positions, indices);
        const std::string message = refusal_of(builder.build());
        INFO(message);
        CHECK(message.find("roberts: object 0 is not one convex body") != std::string::npos);
    }
    SECTION("an open box") {
        std::vector<glm::vec3> positions;
        std::vector<uint32_t> indices;
        append_cube(positions, indices, {0, 0, 0});
        indices.resize(indices.size() - 6);  // no x = 1 side
        hsr::SceneBuilder builder;
        add_box(builder, {5, 0, 0}, {1, 1, 1});
        builder.add_triangles(positions, indices);
        const std::string message = refusal_of(builder.build());
        INFO(message);
        CHECK(message.find("roberts: object 1 is not a closed surface") != std::string::npos);
    }
}

TEST_CASE("roberts: bad input gets a clear message", "[roberts]") {
    const hsr::SceneData& cube = model("cube.obj");
    const hsr_scene scene = cube.view();
    const hsr_camera camera = orbit(cube, 30, 20, 1, false, 128);
    hsr::HiddenLineRemover remover(line_tests::plugin("roberts"), {});
    hsr_segment_sink sink{nullptr, [](void*, const hsr_segment_batch*) { return HSR_OK; }};
    const auto message_of = [&](const hsr_scene& s, const hsr_camera& c, const hsr_line_request& r) -> std::string {
        try {
            remover.render_lines(s, c, r, sink, nullptr, nullptr);
        } catch (const hsr::Error& e) {
            return e.what();
        }
        return "";
    };
    uint32_t vertices[2] = {0, 99}, faces[2] = {0, 1}, flags[1] = {0};
    hsr_line_request request{sizeof(hsr_line_request), 1, vertices, faces, flags, 0};
    CHECK_THAT(message_of(scene, camera, request), Catch::Contains("roberts: edge 0 names vertex 99"));
    vertices[1] = 1;
    faces[1] = 500;
    CHECK_THAT(message_of(scene, camera, request), Catch::Contains("roberts: edge 0 names face 500"));
    faces[1] = 1;
    hsr_camera broken = camera;
    broken.view_projection[5] = std::numeric_limits<float>::quiet_NaN();
    CHECK_THAT(message_of(scene, broken, request), Catch::Contains("roberts: the camera has a matrix"));
    hsr_scene bad_scene = scene;
    std::vector<uint32_t> indices(cube.indices);
    indices[4] = 1000;
    bad_scene.indices = indices.data();
    CHECK_THAT(message_of(bad_scene, camera, request), Catch::Contains("roberts: triangle 1 names vertex 1000"));
    // Nothing asked: only penetration lines could come back, and the cube has none.
    hsr_line_request empty{sizeof(hsr_line_request), 0, nullptr, nullptr, nullptr, 1};
    CHECK(message_of(scene, camera, empty).empty());
}

TEST_CASE("roberts: counters and trace events", "[roberts]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_camera camera = orbit(boxes, 35, 25, 1.3f, false, 400);
    std::ostringstream trace;
    const hsr::LineDrawing d = draw(boxes, camera, true, &trace);
    CHECK(d.counter("bodies") == 3);
    CHECK(d.counter("planes") == 18);
    CHECK(d.counter("edges-in") == 36);
    CHECK(d.counter("edges-back") == 9);
    CHECK(d.counter("body-pairs-overlapping") == 3);
    CHECK(d.counter("penetration-lines") > 0);
    CHECK(d.counter("edge-body-tests") + d.counter("bounds-rejections") + d.counter("depth-rejections") > 0);
    CHECK(d.counter("pieces-visible") + d.counter("pieces-hidden") == d.counter("segments"));
    CHECK(d.counter("segments") == d.segments.size());
    const std::string text = trace.str();
    const auto count = [&](const std::string& needle) {
        size_t n = 0;
        for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
        return n;
    };
    CHECK(count("\"type\":\"edge-begin\"") == 36);
    CHECK(count("\"type\":\"edge-end\"") == 36);
    CHECK(count("\"type\":\"back-edge\"") == 9);
    CHECK(count("\"type\":\"hidden-by\"") == d.counter("hidden-intervals"));
    CHECK(count("\"type\":\"visible\"") == d.counter("pieces-visible"));
    CHECK(count("\"type\":\"penetration-begin\"") == d.counter("penetration-lines"));
    CHECK(d.trace_events > 0);
}

TEST_CASE("roberts: the drawing at step k holds the segments found before step k + 1", "[roberts][trace]") {
    // The SDK hands the host the segments found so far before each trace event, so a drawing
    // stopped at a step grows with k and is, segment for segment, the start of the whole drawing.
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_scene scene = boxes.view();
    const hsr_camera camera = orbit(boxes, 35, 25, 1.3f, false, 400);
    auto at_step = [&](uint64_t k) {
        hsr::LineSettings settings;
        settings.edges = hsr::EdgeSelection::kAll;
        settings.stop_after_event = k;
        return line_tests::draw("roberts", scene, camera, settings);
    };
    hsr::LineSettings plain;
    plain.edges = hsr::EdgeSelection::kAll;
    const hsr::LineDrawing whole = line_tests::draw("roberts", scene, camera, plain);
    const uint64_t total = at_step(1).trace_events;
    REQUIRE(total > 10);
    REQUIRE(whole.segments.size() > 10);
    size_t previous = 0;
    for (uint64_t k : {uint64_t{1}, total / 4, total / 2, 3 * total / 4, total}) {
        INFO("step " << k << " of " << total);
        const hsr::LineDrawing d = at_step(k);
        CHECK(d.segments.size() >= previous);
        REQUIRE(d.segments.size() <= whole.segments.size());
        for (size_t n = 0; n < d.segments.size(); ++n) {
            CHECK(d.segments[n].a == whole.segments[n].a);
            CHECK(d.segments[n].b == whole.segments[n].b);
            CHECK(d.segments[n].edge == whole.segments[n].edge);
        }
        previous = d.segments.size();
        if (k == 1) CHECK(d.segments.empty());  // a body's planes: nothing decided yet
        if (k == total / 2) CHECK((d.segments.size() > 0 && d.segments.size() < whole.segments.size()));
    }
    CHECK(previous == whole.segments.size());
}

TEST_CASE("roberts: steps draw the edge and the hidden interval on it", "[roberts][trace]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_scene scene = boxes.view();
    const hsr_camera camera = orbit(boxes, 35, 25, 1.3f, false, 400);
    std::ostringstream trace;
    const hsr::LineDrawing whole = draw(boxes, camera, false, &trace);
    const glm::dmat4 vp = line_reference::view_projection(camera);
    auto window = [&](glm::dvec3 p) { return line_reference::to_window(camera, vp, p); };
    auto field = [](const std::string& line, const std::string& key) {
        const size_t at = line.find("\"" + key + "\":");
        return at == std::string::npos ? std::string() : line.substr(at + key.size() + 3);
    };
    auto stop_at = [&](uint64_t k) {
        hsr::LineSettings settings;
        settings.edges = hsr::EdgeSelection::kAll;
        settings.stop_after_event = k;
        const hsr::LineDrawing d = line_tests::draw("roberts", scene, camera, settings);
        REQUIRE(d.stopped_at);
        const hsr::TraceEventRecord& e = *d.stopped_at;
        REQUIRE(e.roles.size() * 4 == e.lines.size());
        for (size_t n = 0; n < e.roles.size(); ++n) {
            CHECK(e.roles[n] <= HSR_STEP_CONTEXT);
            for (int c = 0; c < 4; ++c) CHECK(std::isfinite(e.lines[4 * n + c]));
        }
        CHECK_FALSE(e.text.empty());
        return e;
    };
    // The first step: the first body's faces turned toward the eye, as context.
    const hsr::TraceEventRecord first = stop_at(1);
    CHECK(first.type == "body");
    CHECK(first.text.rfind("body ", 0) == 0);
    REQUIRE_FALSE(first.roles.empty());
    for (uint32_t role : first.roles) CHECK(role == HSR_STEP_CONTEXT);
    // Each hidden interval of an edge: the edge in yellow and, in red, exactly the piece t0..t1 of it.
    std::istringstream lines(trace.str());
    std::string line;
    int checked = 0;
    for (uint64_t k = 1; std::getline(lines, line) && checked < 10; ++k) {
        if (line.find("\"type\":\"hidden-by\"") == std::string::npos || field(line, "edge").empty()) continue;
        const uint32_t edge = uint32_t(std::stoul(field(line, "edge")));
        const double t0 = std::stod(field(line, "t0")), t1 = std::stod(field(line, "t1"));
        INFO("event " << k << ": " << line);
        const hsr::TraceEventRecord e = stop_at(k);
        CHECK(e.edge == edge);
        const glm::dvec3 a = line_reference::position(scene, whole.edges.vertices[2 * edge]);
        const glm::dvec3 b = line_reference::position(scene, whole.edges.vertices[2 * edge + 1]);
        const glm::dvec2 p = window(a + t0 * (b - a)), q = window(a + t1 * (b - a));
        const glm::dvec2 wa = window(a), wb = window(b);
        int rejected = 0, subject = 0;
        for (size_t n = 0; n < e.roles.size(); ++n) {
            const glm::dvec2 u(e.lines[4 * n], e.lines[4 * n + 1]), v(e.lines[4 * n + 2], e.lines[4 * n + 3]);
            if (e.roles[n] == HSR_STEP_REJECTED) {
                ++rejected;
                CHECK(glm::length(u - p) < 0.01);
                CHECK(glm::length(v - q) < 0.01);
            } else if (e.roles[n] == HSR_STEP_SUBJECT) {
                ++subject;  // on the edge's line in the picture
                for (const glm::dvec2 end : {u, v}) CHECK(distance_to_segment(end, wa, wb) < 0.01);
            }
        }
        CHECK(rejected == 1);
        CHECK(subject == 1);
        CHECK(e.text.find("hides t") != std::string::npos);
        ++checked;
    }
    CHECK(checked >= 3);
}

TEST_CASE("roberts: times on grids of boxes", "[.][roberts-bench]") {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> angle(0, 360), jitter(-0.3f, 0.3f);
    for (int side : {1, 3, 6, 10, 15, 30}) {
        hsr::SceneBuilder builder;
        for (int i = 0; i < side; ++i)
            for (int j = 0; j < side; ++j)
                add_box(builder, {i * 1.6f + jitter(random), jitter(random), -j * 1.6f + jitter(random)},
                        {0.6f, 0.5f + jitter(random), 0.6f}, angle(random), {jitter(random), 1, jitter(random)});
        const hsr::SceneData data = builder.build();
        for (bool ortho : {false, true}) {
            const hsr_camera camera = orbit(data, 30, 30, 1, ortho, 1024);
            std::vector<double> ms;
            hsr::LineDrawing d;
            for (int run = 0; run < 5; ++run) {
                d = draw(data, camera, false);
                ms.push_back(d.lines_ms);
            }
            std::sort(ms.begin(), ms.end());
            std::cout << side * side << " boxes, " << (ortho ? "orthographic" : "perspective") << ": median " << ms[2]
                      << " ms; edges " << d.counter("edges-in") << ", tests " << d.counter("edge-body-tests")
                      << ", bounds rejections " << d.counter("bounds-rejections") << ", depth rejections "
                      << d.counter("depth-rejections") << ", penetration lines " << d.counter("penetration-lines")
                      << ", segments " << d.segments.size() << "\n";
        }
    }
    for (const char* file : {"cube.obj", "boxes.scene"}) {
        const hsr::SceneData& data = model(file);
        const hsr_camera camera = orbit(data, 35, 25, 1, false, 1024);
        std::vector<double> ms;
        for (int run = 0; run < 21; ++run) ms.push_back(draw(data, camera, false).lines_ms);
        std::sort(ms.begin(), ms.end());
        std::cout << file << ": median " << ms[10] << " ms\n";
    }
}

namespace {

// Cube corners (-1..1 scaled by `half`, moved to `centre`) and its six quads as OBJ lines, the
// vertex numbers starting after `first` earlier vertices.
std::string obj_cube(glm::vec3 centre, float half, int first) {
    std::ostringstream out;
    for (int k = 0; k < 8; ++k) {
        const float x = (k == 1 || k == 2 || k == 5 || k == 6) ? 1.f : -1.f;
        const float y = (k == 2 || k == 3 || k == 6 || k == 7) ? 1.f : -1.f;
        const float z = k >= 4 ? 1.f : -1.f;
        out << "v " << centre.x + half * x << ' ' << centre.y + half * y << ' ' << centre.z + half * z << '\n';
    }
    const int quads[6][4] = {{5, 6, 7, 8}, {1, 4, 3, 2}, {2, 3, 7, 6}, {1, 5, 8, 4}, {4, 8, 7, 3}, {1, 2, 6, 5}};
    for (const auto& q : quads) out << "f " << first + q[0] << ' ' << first + q[1] << ' ' << first + q[2] << ' ' << first + q[3] << '\n';
    return out.str();
}

double visible_length(const hsr::LineDrawing& d) {
    double total = 0;
    for (const hsr::LineSegment& s : d.segments)
        if (s.qi == 0) total += double(glm::length(s.b - s.a));
    return total;
}

const glm::vec3 kCubeA{0, 0, 0}, kCubeB{1.2f, 0.6f, -2.5f};
const float kHalfA = 1, kHalfB = 0.8f;

// The two cubes as two bodies built from cube.obj: the answer an OBJ of two groups should give.
hsr::SceneData two_cube_bodies() {
    hsr::SceneBuilder b;
    hsr::MeshOptions a, c;
    a.transform = box_transform(kCubeA, glm::vec3(kHalfA));
    c.transform = box_transform(kCubeB, glm::vec3(kHalfB));
    b.add_model_file(std::string(HSR_MODELS_DIR) + "/cube.obj", a);
    b.add_model_file(std::string(HSR_MODELS_DIR) + "/cube.obj", c);
    return b.build();
}

hsr::SceneData load_obj_text(const std::string& name, const std::string& text) {
    const std::filesystem::path file = std::filesystem::temp_directory_path() / name;
    std::ofstream(file) << text;
    hsr::SceneBuilder b;
    b.add_model_file(file);
    hsr::SceneData data = b.build();
    std::filesystem::remove(file);
    return data;
}

}  // namespace

TEST_CASE("roberts: an OBJ file's o groups are separate bodies", "[roberts][obj-groups]") {
    const std::string text = "# two cubes\no first\n" + obj_cube(kCubeA, kHalfA, 0) + "o second\n" +
                             obj_cube(kCubeB, kHalfB, 8);
    const hsr::SceneData groups = load_obj_text("hsr_two_cubes_o.obj", text);
    REQUIRE(groups.object_names.size() == 2);
    CHECK(groups.object_names[0] == "hsr_two_cubes_o/first");
    CHECK(groups.object_names[1] == "hsr_two_cubes_o/second");
    const hsr::SceneData bodies = two_cube_bodies();
    for (const View& v : many_views()) {
        INFO("yaw " << v.yaw << " pitch " << v.pitch << " orthographic " << v.ortho);
        const hsr_camera camera = orbit(bodies, v.yaw, v.pitch, 1.3f, v.ortho, 300);
        check_against_ray_casting(groups, camera);
        CHECK(visible_length(draw(groups, camera, false)) ==
              Approx(visible_length(draw(bodies, camera, false))).epsilon(1e-3));
    }
}

TEST_CASE("roberts: an OBJ file's g groups are bodies when it has no o line", "[roberts][obj-groups]") {
    const std::string text = "g left\n" + obj_cube(kCubeA, kHalfA, 0) + "g right\n" + obj_cube(kCubeB, kHalfB, 8);
    const hsr::SceneData groups = load_obj_text("hsr_two_cubes_g.obj", text);
    REQUIRE(groups.object_names.size() == 2);
    CHECK(groups.object_names[1] == "hsr_two_cubes_g/right");
    const hsr_camera camera = orbit(groups, 35, 25, 1.3f, false, 300);
    check_against_ray_casting(groups, camera);

    // With o lines, g lines inside them do not cut a body.
    const std::string nested = "o one\ng a\n" + obj_cube(kCubeA, kHalfA, 0) + "g b\n" + obj_cube(kCubeB, kHalfB, 8);
    CHECK(load_obj_text("hsr_two_cubes_og.obj", nested).object_names.size() == 1);
}
