// The appel hidden-line plugin (Appel 1967, quantitative invisibility): its visible pieces checked
// against ray casting (tests/support/line_reference.hpp) on the models, and against answers worked
// out by hand on small scenes: convex bodies, one box hiding part of an edge of another, QI values
// behind stacked plates, contour vertices lying exactly on an edge; its trace against its segments;
// its refusals.
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/lines.hpp"
#include "hsr/scene_builder.hpp"
#include "line_test_support.hpp"

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

using line_tests::model;
using line_tests::orbit;

namespace {

hsr::LineDrawing draw(const hsr_scene& scene, const hsr_camera& camera, hsr::EdgeSelection edges, bool want_hidden,
                      const std::vector<hsr::Setting>& params = {}, std::ostream* trace = nullptr) {
    hsr::LineSettings settings;
    settings.edges = edges;
    settings.want_hidden = want_hidden;
    settings.trace = trace;
    return line_tests::draw("appel", scene, camera, settings, params);
}

glm::dvec2 window_of(const hsr_scene& scene, const hsr_camera& camera, uint32_t vertex) {
    return line_reference::to_window(camera, line_reference::view_projection(camera),
                                     line_reference::position(scene, vertex));
}

// The request's edge between the vertices at two world positions (either direction).
uint32_t find_edge(const hsr_scene& scene, const hsr::EdgeList& edges, glm::dvec3 a, glm::dvec3 b) {
    auto at = [&](uint32_t v, glm::dvec3 p) { return glm::length(line_reference::position(scene, v) - p) < 1e-6; };
    for (uint32_t e = 0; e < edges.size(); ++e) {
        const uint32_t v0 = edges.vertices[2 * e], v1 = edges.vertices[2 * e + 1];
        if ((at(v0, a) && at(v1, b)) || (at(v0, b) && at(v1, a))) return e;
    }
    return HSR_NO_EDGE;
}

std::vector<hsr::LineSegment> segments_of(const hsr::LineDrawing& d, uint32_t edge) {
    std::vector<hsr::LineSegment> out;
    for (const hsr::LineSegment& s : d.segments)
        if (s.edge == edge) out.push_back(s);
    return out;
}

// The pieces of one edge along a horizontal window line, sorted left to right, as (x from, x to, qi).
struct Piece {
    double x0, x1;
    int32_t qi;
};
std::vector<Piece> pieces_along_x(const std::vector<hsr::LineSegment>& segments) {
    std::vector<Piece> out;
    for (const hsr::LineSegment& s : segments)
        out.push_back({std::min(s.a.x, s.b.x), std::max(s.a.x, s.b.x), s.qi});
    std::sort(out.begin(), out.end(), [](const Piece& p, const Piece& q) { return p.x0 < q.x0; });
    return out;
}

// A box [lo, hi] as 8 corners and 12 triangles, counter-clockwise seen from outside.
void add_box(hsr::SceneBuilder& builder, glm::vec3 lo, glm::vec3 hi) {
    const std::array<glm::vec3, 8> p = {glm::vec3{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                                        {lo.x, hi.y, lo.z},          {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                                        {hi.x, hi.y, hi.z},          {lo.x, hi.y, hi.z}};
    const std::array<uint32_t, 36> faces = {4, 5, 6, 4, 6, 7,   // +z
                                            0, 3, 2, 0, 2, 1,   // -z
                                            1, 2, 6, 1, 6, 5,   // +x
                                            0, 4, 7, 0, 7, 3,   // -x
                                            3, 7, 6, 3, 6, 2,   // +y
                                            0, 1, 5, 0, 5, 4};  // -y
    builder.add_triangles(p, faces);
}

// A perspective camera at (0, 0, 10) looking down -z with a 90 degree field of view, 200x200 pixels:
// world (x, y, z) lands at window (100 + 100 x / (10 - z), 100 - 100 y / (10 - z)).
hsr_camera simple_perspective_camera() {
    const glm::dvec3 eye(0, 0, 10);
    const glm::dmat4 view = glm::lookAt(eye, glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0));
    const glm::dmat4 projection = glm::perspective(glm::radians(90.0), 1.0, 1.0, 100.0);
    const glm::dmat4 vp = projection * view;
    hsr_camera c{};
    c.struct_size = sizeof c;
    c.width = c.height = 200;
    c.projection_type = HSR_PROJECTION_PERSPECTIVE;
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) {
            c.view[4 * col + row] = float(view[col][row]);
            c.projection[4 * col + row] = float(projection[col][row]);
            c.view_projection[4 * col + row] = float(vp[col][row]);
        }
    c.eye[0] = 0, c.eye[1] = 0, c.eye[2] = 10;
    c.view_direction[0] = 0, c.view_direction[1] = 0, c.view_direction[2] = -1;
    c.near_plane = 1;
    c.far_plane = 100;
    return c;
}

void check_against_ray_casting(const hsr_scene& scene, const hsr_camera& camera, hsr::EdgeSelection edges,
                               uint32_t edge_stride, double step_px, double min_checked_fraction) {
    const hsr::LineDrawing d = draw(scene, camera, edges, false);
    const line_reference::Comparison c = line_reference::compare(scene, camera, d.edges, line_tests::reference_segments(d),
                                                                 step_px, 0.5, edge_stride);
    INFO(c.first);
    INFO(c.samples << " samples, " << c.checked << " checked, " << c.reference_visible << " visible by ray casting, "
                   << c.plugin_visible << " by appel; " << d.counter("contour-edges") << " contour edges, "
                   << d.counter("piercings") << " piercings, " << d.counter("seeds-ambiguous") << " ambiguous seeds");
    CHECK(c.disagreements == 0);
    CHECK(double(c.checked) >= min_checked_fraction * double(c.samples));
    // Something is visible and something hidden.
    CHECK(c.reference_visible > c.samples / 10);
    CHECK(c.reference_visible < c.samples - c.samples / 10);
    CHECK(d.counter("qi-conflicts") == 0);
}

// One trace event, from the host's JSON line (flat object of numbers and one string).
struct Event {
    std::string type;
    int64_t edge = -1, face = -1, object = -1, qi = -1;
    double t0 = std::nan("");
};
std::vector<Event> parse_trace(const std::string& text) {
    std::vector<Event> out;
    std::istringstream lines(text);
    std::string line;
    auto number = [&](const std::string& key) -> std::string {
        const std::string tag = "\"" + key + "\":";
        const size_t at = line.find(tag);
        if (at == std::string::npos) return {};
        const size_t start = at + tag.size();
        return line.substr(start, line.find_first_of(",}", start) - start);
    };
    while (std::getline(lines, line)) {
        Event e;
        const size_t type_at = line.find("\"type\":\"") + 8;
        e.type = line.substr(type_at, line.find('"', type_at) - type_at);
        if (auto v = number("edge"); !v.empty()) e.edge = std::stoll(v);
        if (auto v = number("face"); !v.empty()) e.face = std::stoll(v);
        if (auto v = number("object"); !v.empty()) e.object = std::stoll(v);
        if (auto v = number("qi"); !v.empty()) e.qi = std::stoll(v);
        if (auto v = number("t0"); !v.empty()) e.t0 = std::stod(v);
        out.push_back(e);
    }
    return out;
}

}  // namespace

// ------------------------------------------------------------------------------------------------ //
// Against ray casting

TEST_CASE("appel: the cube agrees with ray casting", "[appel][reference]") {
    const hsr_scene scene = model("cube.obj").view();
    for (bool ortho : {false, true})
        for (auto edges : {hsr::EdgeSelection::kAll, hsr::EdgeSelection::kFeatures}) {
            INFO("orthographic " << ortho << ", edges " << (edges == hsr::EdgeSelection::kAll ? "all" : "features"));
            check_against_ray_casting(scene, orbit(model("cube.obj"), 35, 25, 1, ortho, 256), edges, 1, 0.25, 0.9);
        }
}

TEST_CASE("appel: the monkey (open, three parts) agrees with ray casting", "[appel][reference]") {
    const hsr::SceneData& monkey = model("monkey.obj");
    const hsr_scene scene = monkey.view();
    for (bool ortho : {false, true})
        for (auto edges : {hsr::EdgeSelection::kAll, hsr::EdgeSelection::kFeatures}) {
            INFO("orthographic " << ortho << ", edges " << (edges == hsr::EdgeSelection::kAll ? "all" : "features"));
            const uint32_t stride = edges == hsr::EdgeSelection::kAll ? 5 : 1;
            check_against_ray_casting(scene, orbit(monkey, 30, -15, 1, ortho, 512), edges, stride, 0.5, 0.5);
        }
}

TEST_CASE("appel: the bunny agrees with ray casting", "[appel][reference][slow]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr_scene scene = bunny.view();
    for (bool ortho : {false, true})
        for (auto edges : {hsr::EdgeSelection::kAll, hsr::EdgeSelection::kFeatures}) {
            INFO("orthographic " << ortho << ", edges " << (edges == hsr::EdgeSelection::kAll ? "all" : "features"));
            const uint32_t stride = edges == hsr::EdgeSelection::kAll ? 301 : 13;
            check_against_ray_casting(scene, orbit(bunny, 20, 10, 1, ortho, 1024), edges, stride, 0.5, 0.3);
        }
}

TEST_CASE("appel: three intersecting boxes agree with ray casting", "[appel][reference]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_scene scene = boxes.view();
    for (bool ortho : {false, true})
        for (auto edges : {hsr::EdgeSelection::kAll, hsr::EdgeSelection::kFeatures}) {
            INFO("orthographic " << ortho << ", edges " << (edges == hsr::EdgeSelection::kAll ? "all" : "features"));
            check_against_ray_casting(scene, orbit(boxes, 35, 25, 1, ortho, 400), edges, 1, 0.25, 0.9);
            // Edges pass through the other boxes' faces.
            CHECK(draw(scene, orbit(boxes, 35, 25, 1, ortho, 400), edges, false).counter("piercings") > 0);
        }
}

// ------------------------------------------------------------------------------------------------ //
// Worked out by hand

TEST_CASE("appel: a convex body shows exactly its front edges, whole, and hides its back edges", "[appel][hand]") {
    for (const char* file : {"cube.obj", "octahedron.ply"}) {
        const hsr::SceneData& body = model(file);
        const hsr_scene scene = body.view();
        for (bool ortho : {false, true}) {
            INFO(file << ", orthographic " << ortho);
            const hsr_camera camera = orbit(body, 35, 25, 1, ortho, 256);
            const hsr::LineDrawing d = draw(scene, camera, hsr::EdgeSelection::kAll, true);
            uint32_t front = 0, back = 0;
            for (uint32_t e = 0; e < d.edges.size(); ++e) {
                INFO("edge " << e << ", flags " << d.edges.flags[e]);
                const glm::dvec2 a = window_of(scene, camera, d.edges.vertices[2 * e]);
                const glm::dvec2 b = window_of(scene, camera, d.edges.vertices[2 * e + 1]);
                const std::vector<hsr::LineSegment> pieces = segments_of(d, e);
                REQUIRE(pieces.size() == 1);  // nothing changes along an edge of a convex body
                const hsr::LineSegment& s = pieces[0];
                CHECK(glm::length(glm::dvec2(s.a) - a) < 1e-3);
                CHECK(glm::length(glm::dvec2(s.b) - b) < 1e-3);
                if (d.edges.flags[e] & HSR_EDGE_BACK) {
                    ++back;
                    CHECK(s.qi == 1);  // behind exactly one front face
                } else {
                    ++front;
                    CHECK(s.qi == 0);
                }
            }
            CHECK(front > 0);
            CHECK(back > 0);
        }
    }
}

TEST_CASE("appel: a box hides the right part of an edge of a box behind it (perspective, by hand)", "[appel][hand]") {
    hsr::SceneBuilder builder;
    add_box(builder, {-4, 0.5f, -2}, {4, 2, 0});  // behind (no face in a plane through the eye)
    add_box(builder, {1, -1, 1}, {6, 4, 3});   // in front, to the right
    const hsr::SceneData data = builder.build();
    const hsr_scene scene = data.view();
    const hsr_camera camera = simple_perspective_camera();
    const hsr::LineDrawing d = draw(scene, camera, hsr::EdgeSelection::kAll, true);
    // The back box's top front edge, y = 2, z = 0, x from -4 to 4, is at window y 100 - 100 * 2/10 = 80,
    // x from 60 to 140. The front box's image reaches left to its back left edge x = 1, z = 1, at window
    // x 100 + 100 * 1/9; at z = 0 that is x = 10/9. Behind the front box the line of sight passes its
    // back face and its left or front face: QI 2.
    const uint32_t e = find_edge(scene, d.edges, {-4, 2, 0}, {4, 2, 0});
    REQUIRE(e != HSR_NO_EDGE);
    const std::vector<Piece> pieces = pieces_along_x(segments_of(d, e));
    REQUIRE(pieces.size() == 2);
    CHECK(pieces[0].x0 == Approx(60).margin(1e-3));
    CHECK(pieces[0].x1 == Approx(100.0 + 100.0 / 9.0).margin(1e-3));
    CHECK(pieces[0].qi == 0);
    CHECK(pieces[1].x0 == Approx(100.0 + 100.0 / 9.0).margin(1e-3));
    CHECK(pieces[1].x1 == Approx(140).margin(1e-3));
    CHECK(pieces[1].qi == 2);
    for (const hsr::LineSegment& s : segments_of(d, e)) {
        CHECK(s.a.y == Approx(80).margin(1e-3));
        CHECK(s.b.y == Approx(80).margin(1e-3));
    }
    // And the whole picture agrees with ray casting.
    const line_reference::Comparison c = line_reference::compare(scene, camera, d.edges, line_tests::reference_segments(d));
    INFO(c.first);
    CHECK(c.disagreements == 0);
}

TEST_CASE("appel: QI counts the plates in front of an edge, whichever way they face", "[appel][hand][qi]") {
    // Pixel camera: world (x, y) at window (x, 100 - y), the viewer on +z.
    hsr::SceneBuilder builder;
    const std::array<glm::vec3, 4> back = {glm::vec3{10, 10, 0}, {90, 10, 0}, {90, 50, 0}, {10, 50, 0}};
    const std::array<glm::vec3, 4> plate1 = {glm::vec3{30, 40, 5}, {70, 40, 5}, {70, 60, 5}, {30, 60, 5}};
    const std::array<glm::vec3, 4> plate2 = {glm::vec3{50, 45, 10}, {50, 70, 10}, {80, 70, 10}, {80, 45, 10}};  // facing away
    builder.add_polygon(back, {1, 1, 1});
    builder.add_polygon(plate1, {1, 0, 0});
    builder.add_polygon(plate2, {0, 1, 0});
    const hsr::SceneData data = builder.build();
    const hsr_scene scene = data.view();
    const hsr_camera camera = hsr::make_pixel_camera(100, 100, 0, 10);
    for (auto edges : {hsr::EdgeSelection::kAll, hsr::EdgeSelection::kFeatures}) {
        const hsr::LineDrawing d = draw(scene, camera, edges, true);
        // The back rectangle's top edge, window y 50: free, behind plate 1, behind both, behind plate 2, free.
        const uint32_t e = find_edge(scene, d.edges, {10, 50, 0}, {90, 50, 0});
        REQUIRE(e != HSR_NO_EDGE);
        const std::vector<Piece> pieces = pieces_along_x(segments_of(d, e));
        const std::vector<Piece> expected = {{10, 30, 0}, {30, 50, 1}, {50, 70, 2}, {70, 80, 1}, {80, 90, 0}};
        REQUIRE(pieces.size() == expected.size());
        for (size_t k = 0; k < expected.size(); ++k) {
            INFO("piece " << k);
            CHECK(pieces[k].x0 == Approx(expected[k].x0).margin(1e-4));
            CHECK(pieces[k].x1 == Approx(expected[k].x1).margin(1e-4));
            CHECK(pieces[k].qi == expected[k].qi);
        }
        // Plate 1's top edge (y 60) is behind plate 2 from x 50 to 70.
        const uint32_t top1 = find_edge(scene, d.edges, {30, 60, 5}, {70, 60, 5});
        REQUIRE(top1 != HSR_NO_EDGE);
        const std::vector<Piece> top = pieces_along_x(segments_of(d, top1));
        REQUIRE(top.size() == 2);
        CHECK(top[0].x1 == Approx(50).margin(1e-4));
        CHECK(top[0].qi == 0);
        CHECK(top[1].qi == 1);
    }
}

TEST_CASE("appel: contour vertices exactly on an edge (Appel's vertex rules)", "[appel][hand][qi]") {
    // The back rectangle's top edge (window y 50) passes exactly through the left and right corners
    // of a diamond (hidden between them), and touches the apex of a triangle hanging above it (no
    // change there). Exact coordinates: every tie in the geometry is really zero.
    hsr::SceneBuilder builder;
    const std::array<glm::vec3, 4> back = {glm::vec3{10, 10, 0}, {90, 10, 0}, {90, 50, 0}, {10, 50, 0}};
    builder.add_polygon(back, {1, 1, 1});
    const std::array<glm::vec3, 4> diamond = {glm::vec3{30, 50, 5}, {40, 40, 5}, {50, 50, 5}, {40, 60, 5}};
    const std::array<uint32_t, 6> diamond_faces = {0, 1, 3, 1, 2, 3};  // the diagonal 40,40 - 40,60
    builder.add_triangles(diamond, diamond_faces);
    const std::array<glm::vec3, 3> apex = {glm::vec3{70, 50, 5}, {80, 65, 5}, {60, 65, 5}};
    builder.add_polygon(apex, {1, 0, 0});
    const hsr::SceneData data = builder.build();
    const hsr_scene scene = data.view();
    const hsr_camera camera = hsr::make_pixel_camera(100, 100, 0, 5);
    const hsr::LineDrawing d = draw(scene, camera, hsr::EdgeSelection::kAll, true, {{"check-all-edges", "true"}});
    const uint32_t e = find_edge(scene, d.edges, {10, 50, 0}, {90, 50, 0});
    REQUIRE(e != HSR_NO_EDGE);
    const std::vector<Piece> pieces = pieces_along_x(segments_of(d, e));
    std::string listing;
    for (const Piece& p : pieces) listing += " [" + std::to_string(p.x0) + ", " + std::to_string(p.x1) + "] qi " + std::to_string(p.qi);
    INFO(listing);
    REQUIRE(pieces.size() == 3);
    CHECK(pieces[0].x1 == Approx(30).margin(1e-4));
    CHECK(pieces[0].qi == 0);
    CHECK(pieces[1].x1 == Approx(50).margin(1e-4));
    CHECK(pieces[1].qi == 1);
    CHECK(pieces[2].x1 == Approx(90).margin(1e-4));
    CHECK(pieces[2].qi == 0);
    CHECK(d.counter("qi-conflicts") == 0);
}

TEST_CASE("appel: a non-convex prism seen from many sides: concave vertices where contours start and end", "[appel][qi]") {
    // An L-shaped cross-section (concave corner at 1,1) extruded along z: from most directions a
    // silhouette edge ends at, or an edge disappears behind, the concave edge and its end vertices.
    const std::array<glm::vec2, 6> outline = {glm::vec2{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}};
    std::vector<glm::vec3> positions;
    for (float z : {0.0f, 1.0f})
        for (const glm::vec2& p : outline) positions.push_back({p, z});
    std::vector<uint32_t> faces;
    const uint32_t cap[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
    for (const auto& t : cap) faces.insert(faces.end(), {6 + t[0], 6 + t[1], 6 + t[2], t[0], t[2], t[1]});  // top, bottom
    for (uint32_t i = 0; i < 6; ++i) {
        const uint32_t j = (i + 1) % 6;
        faces.insert(faces.end(), {i, j, 6 + j, i, 6 + j, 6 + i});
    }
    hsr::SceneBuilder builder;
    builder.add_triangles(positions, faces);
    const hsr::SceneData data = builder.build();
    const hsr_scene scene = data.view();
    uint64_t hidden_samples = 0;
    for (int k = 0; k < 24; ++k) {
        const float yaw = 15.0f * k + 7.3f, pitch = float((k * 41) % 150) - 74.7f;
        const bool ortho = k % 2 == 0;
        INFO("yaw " << yaw << ", pitch " << pitch << ", orthographic " << ortho);
        const hsr_camera camera = orbit(data, yaw, pitch, 1, ortho, 256);
        const hsr::LineDrawing d = draw(scene, camera, hsr::EdgeSelection::kAll, true, {{"check-all-edges", "true"}});
        const line_reference::Comparison c = line_reference::compare(scene, camera, d.edges, line_tests::reference_segments(d));
        INFO(c.first);
        CHECK(c.disagreements == 0);
        CHECK(d.counter("qi-conflicts") == 0);
        hidden_samples += c.samples - c.reference_visible;
    }
    CHECK(hidden_samples > 0);
}

// ------------------------------------------------------------------------------------------------ //
// The trace, the parameters, the refusals

TEST_CASE("appel: a QI change's step draws the edge, its pieces up to the change and after it", "[appel][trace]") {
    hsr::SceneBuilder builder;
    add_box(builder, {-4, 0.5f, -2}, {4, 2, 0});
    add_box(builder, {1, -1, 1}, {6, 4, 3});
    const hsr::SceneData data = builder.build();
    const hsr_scene scene = data.view();
    const hsr_camera camera = simple_perspective_camera();
    std::ostringstream text;
    const hsr::LineDrawing d = draw(scene, camera, hsr::EdgeSelection::kAll, false, {}, &text);
    const std::vector<Event> events = parse_trace(text.str());
    const glm::dmat4 vp = line_reference::view_projection(camera);
    auto stop_at = [&](uint64_t k) {
        hsr::LineSettings settings;
        settings.edges = hsr::EdgeSelection::kAll;
        settings.stop_after_event = k;
        const hsr::LineDrawing part = line_tests::draw("appel", scene, camera, settings);
        REQUIRE(part.stopped_at);
        const hsr::TraceEventRecord& e = *part.stopped_at;
        REQUIRE(e.roles.size() * 4 == e.lines.size());
        for (size_t n = 0; n < e.roles.size(); ++n) {
            CHECK(e.roles[n] <= HSR_STEP_CONTEXT);
            for (int c = 0; c < 4; ++c) {
                CHECK(std::isfinite(e.lines[4 * n + c]));
                CHECK(e.lines[4 * n + c] > -2.0f);
                CHECK(e.lines[4 * n + c] < float(camera.width) + 2.0f);
            }
        }
        return e;
    };
    // The first seed's step shows the contour edges, as many as the counter says.
    const hsr::TraceEventRecord seed = stop_at(1);
    CHECK(seed.type == "component-seed");
    CHECK(seed.text.find(std::to_string(d.counter("contour-edges")) + " contour edges") != std::string::npos);
    CHECK(uint64_t(std::count(seed.roles.begin(), seed.roles.end(), uint32_t(HSR_STEP_CONTEXT))) ==
          d.counter("contour-edges"));
    uint64_t changes = 0;
    for (size_t k = 0; k < events.size(); ++k) {
        if (events[k].type != "qi-change") continue;
        INFO("event " << k + 1 << ", edge " << events[k].edge);
        const hsr::TraceEventRecord e = stop_at(k + 1);
        CHECK(e.text.find("to " + std::to_string(events[k].qi) + " at t") != std::string::npos);
        // Both pieces meet at the change, the point at t0 along the edge.
        const uint32_t edge = uint32_t(events[k].edge);
        const glm::dvec3 p0 = line_reference::position(scene, d.edges.vertices[2 * edge]);
        const glm::dvec3 p1 = line_reference::position(scene, d.edges.vertices[2 * edge + 1]);
        const glm::dvec2 at = line_reference::to_window(camera, vp, p0 + events[k].t0 * (p1 - p0));
        const glm::dvec2 w0 = line_reference::to_window(camera, vp, p0), w1 = line_reference::to_window(camera, vp, p1);
        // The whole edge as the subject; a piece ends at the change and the next starts there,
        // shown as visible or hidden by the QI after the change.
        int subjects = 0, ending = 0, starting = 0;
        for (size_t n = 0; n < e.roles.size(); ++n) {
            const glm::dvec2 u(e.lines[4 * n], e.lines[4 * n + 1]), v(e.lines[4 * n + 2], e.lines[4 * n + 3]);
            if (e.roles[n] == HSR_STEP_SUBJECT) {
                ++subjects;
                CHECK(std::min(glm::length(u - w0) + glm::length(v - w1), glm::length(u - w1) + glm::length(v - w0)) < 0.02);
            } else if (e.roles[n] != HSR_STEP_CONTEXT) {
                ending += glm::length(v - at) < 0.01 ? 1 : 0;
                if (glm::length(u - at) < 0.01) {
                    ++starting;
                    CHECK(e.roles[n] == (events[k].qi == 0 ? HSR_STEP_WRITTEN : HSR_STEP_REJECTED));
                }
            }
        }
        CHECK(subjects == 1);
        CHECK(ending == 1);
        CHECK(starting == 1);
        ++changes;
    }
    CHECK(changes > 0);
}

TEST_CASE("appel: the trace's QI changes are where the segments change", "[appel][trace]") {
    hsr::SceneBuilder builder;
    add_box(builder, {-4, 0.5f, -2}, {4, 2, 0});
    add_box(builder, {1, -1, 1}, {6, 4, 3});
    const hsr::SceneData data = builder.build();
    const hsr_scene scene = data.view();
    const hsr_camera camera = simple_perspective_camera();
    std::ostringstream text;
    const hsr::LineDrawing d = draw(scene, camera, hsr::EdgeSelection::kAll, true, {}, &text);
    const std::vector<Event> events = parse_trace(text.str());
    REQUIRE(!events.empty());
    CHECK(d.trace_events == events.size());
    const auto seeds = std::count_if(events.begin(), events.end(), [](const Event& e) { return e.type == "component-seed"; });
    CHECK(uint64_t(seeds) == d.counter("seeds"));
    CHECK(d.counter("seeds") == 2);

    // Per edge: edge-begin, the QI changes, edge-end; the QI sequence and the change points are the
    // segments', in order along the edge.
    const glm::dmat4 vp = line_reference::view_projection(camera);
    uint64_t changes = 0;
    for (size_t k = 0; k < events.size(); ++k) {
        if (events[k].type != "edge-begin") continue;
        const uint32_t edge = uint32_t(events[k].edge);
        INFO("edge " << edge);
        const glm::dvec3 p0 = line_reference::position(scene, d.edges.vertices[2 * edge]);
        const glm::dvec3 p1 = line_reference::position(scene, d.edges.vertices[2 * edge + 1]);
        // The segments of this edge ordered along it, from the event's starting end.
        std::vector<hsr::LineSegment> pieces = segments_of(d, edge);
        const glm::dvec2 start = line_reference::to_window(camera, vp, events[k].t0 == 0.0 ? p0 : p1);
        auto distance_from_start = [&](const hsr::LineSegment& s) {
            return std::min(glm::length(glm::dvec2(s.a) - start), glm::length(glm::dvec2(s.b) - start));
        };
        std::sort(pieces.begin(), pieces.end(),
                  [&](const hsr::LineSegment& x, const hsr::LineSegment& y) { return distance_from_start(x) < distance_from_start(y); });
        REQUIRE(!pieces.empty());
        CHECK(pieces[0].qi == events[k].qi);
        size_t piece = 0;
        for (++k; k < events.size() && events[k].type == "qi-change"; ++k) {
            ++changes;
            ++piece;
            REQUIRE(piece < pieces.size());
            CHECK(pieces[piece].qi == events[k].qi);
            CHECK(events[k].face >= 0);
            const glm::dvec2 at = line_reference::to_window(camera, vp, p0 + events[k].t0 * (p1 - p0));
            CHECK(distance_from_start(pieces[piece]) == Approx(glm::length(at - start)).margin(1e-3));
        }
        REQUIRE(k < events.size());
        CHECK(events[k].type == "edge-end");
        CHECK(events[k].edge == int64_t(edge));
        CHECK(piece + 1 == pieces.size());
        CHECK(events[k].qi == pieces.back().qi);
    }
    CHECK(changes > 0);
}

TEST_CASE("appel: the screen grid finds every crossing that testing all contour edges finds", "[appel]") {
    const hsr::SceneData& monkey = model("monkey.obj");
    const hsr_scene scene = monkey.view();
    for (bool ortho : {false, true}) {
        const hsr_camera camera = orbit(monkey, 30, -15, 1, ortho, 512);
        const hsr::LineDrawing grid = draw(scene, camera, hsr::EdgeSelection::kAll, true, {{"prefilter", "grid"}});
        const hsr::LineDrawing all = draw(scene, camera, hsr::EdgeSelection::kAll, true, {{"prefilter", "none"}});
        REQUIRE(grid.segments.size() == all.segments.size());
        for (size_t k = 0; k < grid.segments.size(); ++k) {
            CHECK(grid.segments[k].edge == all.segments[k].edge);
            CHECK(grid.segments[k].qi == all.segments[k].qi);
            CHECK(grid.segments[k].a == all.segments[k].a);
            CHECK(grid.segments[k].b == all.segments[k].b);
        }
        CHECK(grid.counter("crossings") == all.counter("crossings"));
        CHECK(grid.counter("crossing-tests") * 20 < all.counter("crossing-tests"));
    }
}

TEST_CASE("appel: every vertex gets the same QI along every edge that reaches it", "[appel]") {
    for (const char* file : {"cube.obj", "monkey.obj", "bunny.obj", "boxes.scene"})
        for (bool ortho : {false, true}) {
            INFO(file << ", orthographic " << ortho);
            const hsr::SceneData& data = model(file);
            const hsr::LineDrawing d = draw(data.view(), orbit(data, 30, 20, 1, ortho, 512), hsr::EdgeSelection::kFeatures,
                                            false, {{"check-all-edges", "true"}});
            CHECK(d.counter("edges-walked") == d.counter("edges-in"));
            CHECK(d.counter("qi-conflicts") == 0);
            CHECK(d.counter("seeds-ambiguous") == 0);
        }
}

TEST_CASE("appel: counters", "[appel]") {
    const hsr::SceneData& cube = model("cube.obj");
    const hsr::LineDrawing d = draw(cube.view(), orbit(cube, 35, 25, 1, false, 256), hsr::EdgeSelection::kFeatures, true);
    CHECK(d.counter("triangles-in") == 12);
    CHECK(d.counter("edges-in") == 18);
    CHECK(d.counter("edges-requested") == 12);
    CHECK(d.counter("contour-edges") == 6);  // the hexagonal silhouette
    CHECK(d.counter("seeds") == 1);
    CHECK(d.counter("segments") == 12);
    CHECK(d.counter("crossings") == 0);
}

TEST_CASE("appel: refuses what it cannot handle, with a message", "[appel][errors]") {
    const hsr::SceneData& cube = model("cube.obj");
    SECTION("an adjacency that is not that of a manifold mesh") {
        hsr::SceneData broken = cube;
        // Triangle 0 claims the neighbour of a side that does not name it back.
        const int32_t n = broken.edge_neighbors[0];
        const int32_t other = n == 5 ? 6 : 5;
        broken.edge_neighbors[0] = other;
        CHECK_THROWS_WITH(draw(broken.view(), orbit(cube, 35, 25, 1, false, 128), hsr::EdgeSelection::kAll, false),
                          Catch::Contains("not that of a manifold mesh"));
    }
    SECTION("a perspective camera inside the scene") {
        hsr_camera camera = simple_perspective_camera();
        hsr::SceneBuilder builder;
        add_box(builder, {-1, -1, 5}, {1, 1, 12});  // reaches behind the eye at z = 10
        const hsr::SceneData data = builder.build();
        CHECK_THROWS_WITH(draw(data.view(), camera, hsr::EdgeSelection::kAll, false),
                          Catch::Contains("not in front of the eye"));
    }
}

TEST_CASE("appel: time on the models", "[.][appel][timing][slow]") {
    for (const char* file : {"cube.obj", "monkey.obj", "bunny.obj", "boxes.scene"})
        for (bool ortho : {false, true})
            for (auto edges : {hsr::EdgeSelection::kAll, hsr::EdgeSelection::kFeatures}) {
                const hsr::SceneData& data = model(file);
                const hsr_camera camera = orbit(data, 30, 20, 1, ortho, 1024);
                std::vector<double> times;
                hsr::LineDrawing d;
                for (int k = 0; k < 15; ++k) {
                    d = draw(data.view(), camera, edges, true);
                    times.push_back(d.lines_ms);
                }
                std::sort(times.begin(), times.end());
                std::printf("%-12s %-12s %-8s %7zu edges %8llu walked %9llu crossing tests %6llu crossings %9llu "
                            "piercing tests: median %8.2f ms (min %.2f)\n",
                            file, ortho ? "orthographic" : "perspective", edges == hsr::EdgeSelection::kAll ? "all" : "features",
                            d.edges.size(), (unsigned long long)d.counter("edges-walked"),
                            (unsigned long long)d.counter("crossing-tests"), (unsigned long long)d.counter("crossings"),
                            (unsigned long long)d.counter("piercing-tests"), times[times.size() / 2], times[0]);
            }
}

TEST_CASE("appel: many views of many models agree with ray casting", "[.][appel][stress][slow]") {
    const char* files[] = {"cube.obj", "boxes.scene", "monkey.obj", "octahedron.ply", "tetrahedron.off", "pyramid.stl", "three-polygons.scene", "bunny.obj"};
    int failures = 0;
    for (const char* file : files) {
        const hsr::SceneData& data = model(file);
        const hsr_scene scene = data.view();
        const bool big = std::string(file) == "bunny.obj";
        for (int k = 0; k < (big ? 6 : 40); ++k) {
            const float yaw = float((k * 73) % 360) + 0.123f, pitch = float((k * 37) % 170) - 84.877f;
            const bool ortho = k % 2 == 1;
            const hsr_camera camera = orbit(data, yaw, pitch, 1, ortho, 300);
            const hsr::LineDrawing d = draw(scene, camera, hsr::EdgeSelection::kAll, false, {{"check-all-edges", "true"}});
            const auto c = line_reference::compare(scene, camera, d.edges, line_tests::reference_segments(d), 0.5, 0.5,
                                                   big ? 401 : (std::string(file) == "monkey.obj" ? 13 : 1));
            if (c.disagreements != 0 || d.counter("qi-conflicts") != 0 || d.counter("seeds-ambiguous") != 0) {
                ++failures;
                std::printf("%s yaw %g pitch %g ortho %d: %llu disagreements of %llu checked, %llu conflicts, %llu ambiguous seeds; %s\n",
                            file, yaw, pitch, int(ortho), (unsigned long long)c.disagreements, (unsigned long long)c.checked,
                            (unsigned long long)d.counter("qi-conflicts"), (unsigned long long)d.counter("seeds-ambiguous"), c.first.c_str());
            }
        }
    }
    CHECK(failures == 0);
}
