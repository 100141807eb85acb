// Hidden-line steps that show what hides what, on models/boxes.scene, checked against the scene's
// own geometry: Roberts' step names a face of the hiding body turned toward the eye and draws the
// sides of that body's front polygons (never a triangulation's diagonal, never a box); Appel's QI
// change draws its edge whole and the contour line it passes behind, an edge between a face turned
// toward the eye and one turned away whose image passes through the change; hsr view's figure of a
// step gives the named face as its polygon (the four corners of a box's side) and the edge under test.
#include "line_test_support.hpp"
#include "view/server/view_line_steps.hpp"

#include "hsr/edges.hpp"
#include "hsr/lines.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace {

using line_reference::position;

// One trace event of the JSON lines: its type, edge, face, object (-1 when absent).
struct Event {
    std::string type;
    long edge = -1, face = -1, object = -1;
};

long field(const std::string& line, const std::string& name) {
    const std::string key = "\"" + name + "\":";
    const size_t at = line.find(key);
    return at == std::string::npos ? -1 : std::stol(line.substr(at + key.size()));
}

std::vector<Event> events_of(const std::string& trace) {
    std::vector<Event> events;
    std::istringstream lines(trace);
    std::string line;
    while (std::getline(lines, line)) {
        const size_t start = line.find("\"type\":\"") + 8;
        events.push_back({line.substr(start, line.find('"', start) - start), field(line, "edge"), field(line, "face"),
                          field(line, "object")});
    }
    return events;
}

glm::dvec3 normal_of(const hsr_scene& s, uint32_t t) {
    const glm::dvec3 a = position(s, s.indices[3 * t]), b = position(s, s.indices[3 * t + 1]),
                     c = position(s, s.indices[3 * t + 2]);
    return glm::normalize(glm::cross(b - a, c - a));
}

// The sides of an object's polygons (mesh edges between two triangles that are not coplanar) with
// at least one of their faces turned toward the eye, as window segments.
std::vector<std::pair<glm::dvec2, glm::dvec2>> front_polygon_sides(const hsr_scene& s, const hsr_camera& camera,
                                                                   uint32_t object) {
    const glm::dmat4 vp = line_reference::view_projection(camera);
    const std::vector<uint8_t> front = hsr::front_facing_faces(s, camera);
    std::vector<std::pair<glm::dvec2, glm::dvec2>> sides;
    for (uint32_t t = 0; t < s.triangle_count; ++t) {
        if (s.face_object[t] != object) continue;
        for (int i = 0; i < 3; ++i) {
            const int32_t u = s.edge_neighbors[3 * t + i];
            REQUIRE(u != HSR_NO_NEIGHBOR);  // the boxes are closed
            if (uint32_t(u) < t) continue;  // each side once
            if (glm::dot(normal_of(s, t), normal_of(s, uint32_t(u))) > 0.999) continue;  // a diagonal
            if (!front[t] && !front[uint32_t(u)]) continue;
            sides.emplace_back(line_reference::to_window(camera, vp, position(s, s.indices[3 * t + i])),
                               line_reference::to_window(camera, vp, position(s, s.indices[3 * t + (i + 1) % 3])));
        }
    }
    return sides;
}

bool same_segment(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d, double tolerance) {
    return (glm::length(a - c) < tolerance && glm::length(b - d) < tolerance) ||
           (glm::length(a - d) < tolerance && glm::length(b - c) < tolerance);
}

double distance_to_segment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 d = b - a;
    const double t = glm::clamp(glm::dot(p - a, d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
    return glm::length(p - (a + t * d));
}

struct Setup {
    const hsr::SceneData& data = line_tests::model("boxes.scene");
    hsr_scene scene = data.view();
    hsr_camera camera = line_tests::orbit(data, 35.0f, 25.0f, 1.2f, false, 320, 320);
};

hsr::LineDrawing at_step(const std::string& plugin, const Setup& setup, uint64_t k, std::ostream* trace = nullptr) {
    hsr::LineSettings settings;
    settings.stop_after_event = k;
    settings.trace = trace;
    return line_tests::draw(plugin, setup.scene, setup.camera, settings);
}

}  // namespace

TEST_CASE("line steps: roberts names a front face of the hiding body and draws that body's polygons",
          "[roberts][trace][view]") {
    const Setup setup;
    const hsr_scene& s = setup.scene;
    std::ostringstream trace;
    const hsr::LineDrawing whole = at_step("roberts", setup, 0, &trace);
    const std::vector<Event> events = events_of(trace.str());
    const std::vector<uint8_t> front = hsr::front_facing_faces(s, setup.camera);
    const std::vector<uint32_t> polygon_of = hsr::host::polygon_faces(s);
    const glm::dmat4 vp = line_reference::view_projection(setup.camera);
    int checked = 0;
    for (size_t k = 0; k < events.size() && checked < 6; ++k) {
        if (events[k].type != "hidden-by" || events[k].edge < 0) continue;
        INFO("event " << k + 1);
        const hsr::LineDrawing d = at_step("roberts", setup, k + 1);
        REQUIRE(d.stopped_at);
        const hsr::TraceEventRecord& e = *d.stopped_at;
        REQUIRE(e.face < s.triangle_count);
        CHECK(s.face_object[e.face] == e.object);  // a face of the hiding body
        CHECK(front[e.face]);                       // turned toward the eye
        CHECK(polygon_of[e.face] == e.face);        // named as the viewer numbers faces
        CHECK(e.object != s.face_object[whole.edges.faces[2 * e.edge]]);
        // Its context lines are exactly the sides of the body's front polygons.
        const auto expected = front_polygon_sides(s, setup.camera, e.object);
        std::vector<std::pair<glm::dvec2, glm::dvec2>> drawn;
        for (size_t n = 0; n < e.roles.size(); ++n)
            if (e.roles[n] == HSR_STEP_CONTEXT)
                drawn.emplace_back(glm::dvec2(e.lines[4 * n], e.lines[4 * n + 1]),
                                   glm::dvec2(e.lines[4 * n + 2], e.lines[4 * n + 3]));
        CHECK(drawn.size() == expected.size());
        for (const auto& [a, b] : drawn) {
            bool found = false;
            for (const auto& [c, d2] : expected) found = found || same_segment(a, b, c, d2, 0.05);
            CHECK(found);
        }

        // The viewer's figure: the face as its polygon, the four corners of that side of the box.
        const nlohmann::json figure = hsr::host::line_step_figure(s, setup.camera, d, e, glm::vec3(1.0f));
        REQUIRE(figure["face"].is_object());
        CHECK(figure["face"]["index"] == e.face);
        REQUIRE(figure["face"]["loops"].size() == 1);
        const nlohmann::json& loop = figure["face"]["loops"][0];
        CHECK(loop.size() == 4);
        const glm::dvec3 n = normal_of(s, e.face), on = position(s, s.indices[3 * e.face]);
        std::vector<glm::dvec2> corners;  // the body's vertices in the face's plane
        for (uint32_t v = 0; v < s.vertex_count; ++v) {
            bool of_body = false;
            for (uint32_t t = 0; t < s.triangle_count && !of_body; ++t)
                of_body = s.face_object[t] == e.object &&
                          (s.indices[3 * t] == v || s.indices[3 * t + 1] == v || s.indices[3 * t + 2] == v);
            if (of_body && std::abs(glm::dot(position(s, v) - on, n)) < 1e-4)
                corners.push_back(line_reference::to_window(setup.camera, vp, position(s, v)));
        }
        for (const nlohmann::json& p : loop) {
            bool found = false;
            for (const glm::dvec2 c : corners) found = found || glm::length(c - glm::dvec2(p[0].get<double>(), p[1].get<double>())) < 0.05;
            CHECK(found);
        }
        // The edge under test, whole.
        REQUIRE(figure["edge"].is_object());
        CHECK(figure["edge"]["index"] == e.edge);
        const nlohmann::json& line = figure["edge"]["lines"][0];
        const glm::dvec2 w0 = line_reference::to_window(setup.camera, vp, position(s, whole.edges.vertices[2 * e.edge]));
        const glm::dvec2 w1 = line_reference::to_window(setup.camera, vp, position(s, whole.edges.vertices[2 * e.edge + 1]));
        CHECK(same_segment(glm::dvec2(line[0].get<double>(), line[1].get<double>()),
                           glm::dvec2(line[2].get<double>(), line[3].get<double>()), w0, w1, 0.05));
        ++checked;
    }
    CHECK(checked > 0);
}

TEST_CASE("line steps: appel's QI change draws its edge and the contour line it passes behind", "[appel][trace][view]") {
    const Setup setup;
    const hsr_scene& s = setup.scene;
    std::ostringstream trace;
    const hsr::LineDrawing whole = at_step("appel", setup, 0, &trace);
    const std::vector<Event> events = events_of(trace.str());
    const std::vector<uint8_t> front = hsr::front_facing_faces(s, setup.camera);
    const std::vector<uint32_t> polygon_of = hsr::host::polygon_faces(s);
    const glm::dmat4 vp = line_reference::view_projection(setup.camera);
    int checked = 0, contours = 0;
    for (size_t k = 0; k < events.size() && checked < 12; ++k) {
        if (events[k].type != "qi-change") continue;
        INFO("event " << k + 1);
        const hsr::LineDrawing d = at_step("appel", setup, k + 1);
        REQUIRE(d.stopped_at);
        const hsr::TraceEventRecord& e = *d.stopped_at;
        REQUIRE(e.edge < whole.edges.size());
        const glm::dvec3 p0 = position(s, whole.edges.vertices[2 * e.edge]);
        const glm::dvec3 p1 = position(s, whole.edges.vertices[2 * e.edge + 1]);
        const glm::dvec2 w0 = line_reference::to_window(setup.camera, vp, p0);
        const glm::dvec2 w1 = line_reference::to_window(setup.camera, vp, p1);
        const glm::dvec2 at = line_reference::to_window(setup.camera, vp, p0 + e.t0 * (p1 - p0));
        REQUIRE(e.face < s.triangle_count);
        CHECK(polygon_of[e.face] == e.face);  // named as the viewer numbers faces
        int subjects = 0;
        for (size_t n = 0; n < e.roles.size(); ++n) {
            const glm::dvec2 u(e.lines[4 * n], e.lines[4 * n + 1]), v(e.lines[4 * n + 2], e.lines[4 * n + 3]);
            if (e.roles[n] == HSR_STEP_SUBJECT) {
                ++subjects;
                CHECK(same_segment(u, v, w0, w1, 0.05));
            } else if (e.roles[n] == HSR_STEP_CONTEXT) {
                // A contour edge of the scene: its faces, one turned toward the eye and one away.
                bool contour = false;
                for (uint32_t t = 0; t < s.triangle_count && !contour; ++t)
                    for (int i = 0; i < 3 && !contour; ++i) {
                        const int32_t other = s.edge_neighbors[3 * t + i];
                        if (other == HSR_NO_NEIGHBOR || front[t] == front[uint32_t(other)]) continue;
                        const glm::dvec2 c0 = line_reference::to_window(setup.camera, vp, position(s, s.indices[3 * t + i]));
                        const glm::dvec2 c1 =
                            line_reference::to_window(setup.camera, vp, position(s, s.indices[3 * t + (i + 1) % 3]));
                        contour = same_segment(u, v, c0, c1, 0.05);
                    }
                CHECK(contour);
                CHECK(distance_to_segment(at, u, v) < 0.05);  // the edge changes QI where it passes behind it
                ++contours;
            }
        }
        CHECK(subjects == 1);
        ++checked;
    }
    CHECK(checked > 0);
    CHECK(contours > 0);
}

TEST_CASE("line steps: the faces of boxes.scene are the six sides of each box, numbered by their lowest triangle",
          "[view]") {
    const Setup setup;
    const hsr_scene& s = setup.scene;
    const std::vector<uint32_t> polygon_of = hsr::host::polygon_faces(s);
    std::vector<uint32_t> polygons;
    for (uint32_t t = 0; t < s.triangle_count; ++t) {
        CHECK(polygon_of[t] <= t);
        if (polygon_of[t] == t) polygons.push_back(t);
    }
    CHECK(polygons.size() == 6 * s.object_count);
    for (const uint32_t p : polygons) {
        const auto loops = hsr::host::polygon_loops(s, polygon_of, p);
        REQUIRE(loops.size() == 1);
        CHECK(loops[0].size() == 4);
    }
}
