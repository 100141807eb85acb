// Edge extraction and classification for line drawings (hsr/edges.hpp), and the host side of a
// hidden-line plugin call (hsr/lines.hpp) with the plain-C test plugin.
#include "hsr/edges.hpp"
#include "hsr/lines.hpp"
#include "hsr/surface.hpp"
#include "line_test_support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <sstream>

using line_tests::model;
using line_tests::orbit;

namespace {

uint32_t count_flag(const hsr::EdgeList& edges, uint32_t flag) {
    return uint32_t(std::count_if(edges.flags.begin(), edges.flags.end(), [&](uint32_t f) { return (f & flag) != 0; }));
}

}  // namespace

TEST_CASE("edges: a cube has 12 edges, all creases, and seen from a corner 6 are silhouettes", "[edges]") {
    const hsr::SceneData& cube = model("cube.obj");
    REQUIRE(cube.triangle_count() == 12);
    const hsr_scene scene = cube.view();
    for (bool ortho : {false, true}) {
        INFO("orthographic " << ortho);
        const hsr_camera camera = orbit(cube, 35, 25, 1, ortho, 256);
        const hsr::EdgeList all = hsr::classify_edges(scene, camera, 40, hsr::EdgeSelection::kAll);
        const hsr::EdgeList features = hsr::classify_edges(scene, camera, 40, hsr::EdgeSelection::kFeatures);
        CHECK(all.size() == 12);  // the 6 face diagonals are left out
        CHECK(features.size() == 12);
        CHECK(count_flag(all, HSR_EDGE_CREASE) == 12);
        CHECK(count_flag(all, HSR_EDGE_BOUNDARY) == 0);
        // Three faces toward the eye: the silhouette is a hexagon, 3 edges lie between two front
        // faces and 3 between two back faces.
        CHECK(count_flag(all, HSR_EDGE_SILHOUETTE) == 6);
        CHECK(count_flag(all, HSR_EDGE_BACK) == 3);
        for (size_t e = 0; e < all.size(); ++e) {
            CHECK(all.faces[2 * e] != HSR_NO_FACE);
            CHECK(all.faces[2 * e + 1] != HSR_NO_FACE);
            CHECK(all.vertices[2 * e] != all.vertices[2 * e + 1]);
        }
        // A crease angle of 100 degrees makes no edge of the cube a crease: only the silhouette is left.
        const hsr::EdgeList sharp = hsr::classify_edges(scene, camera, 100, hsr::EdgeSelection::kFeatures);
        CHECK(sharp.size() == 6);
    }
}

TEST_CASE("edges: a smooth mesh gives far fewer feature edges than edges", "[edges]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr_scene scene = bunny.view();
    const hsr_camera camera = orbit(bunny, 20, 10, 1, false, 256);
    const hsr::EdgeList all = hsr::classify_edges(scene, camera, 40, hsr::EdgeSelection::kAll);
    const hsr::EdgeList features = hsr::classify_edges(scene, camera, 40, hsr::EdgeSelection::kFeatures);
    // A closed triangle mesh has 3/2 edges per triangle; the bunny has a few holes (boundaries).
    CHECK(all.size() > bunny.triangle_count());
    CHECK(all.size() <= 3 * size_t(bunny.triangle_count()) / 2 + 100);
    CHECK(features.size() * 5 < all.size());
    CHECK(count_flag(features, HSR_EDGE_SILHOUETTE) > 100);
    // Every feature edge is a silhouette, crease or boundary, and silhouettes join a front and a back face.
    const std::vector<uint8_t> front = hsr::front_facing_faces(scene, camera);
    for (size_t e = 0; e < features.size(); ++e) {
        const uint32_t f = features.flags[e];
        CHECK((f & (HSR_EDGE_SILHOUETTE | HSR_EDGE_CREASE | HSR_EDGE_BOUNDARY)) != 0);
        if (f & HSR_EDGE_SILHOUETTE) CHECK(front[features.faces[2 * e]] != front[features.faces[2 * e + 1]]);
    }
}

TEST_CASE("lines: the host collects a plugin's segments and writes its trace as JSON lines", "[edges][lines]") {
    const hsr::SceneData& cube = model("cube.obj");
    const hsr_scene scene = cube.view();
    const hsr_camera camera = orbit(cube, 35, 25, 1, false, 200);
    hsr::HiddenLineRemover remover(line_tests::plugin("handmade-lines", HSR_TEST_PLUGIN_DIR, ""), {});
    std::ostringstream trace;
    hsr::LineSettings settings;
    settings.edges = hsr::EdgeSelection::kAll;
    settings.trace = &trace;
    const hsr::LineDrawing d = hsr::render_lines(scene, camera, remover, settings);
    REQUIRE(d.edges.size() == 12);
    REQUIRE(d.segments.size() == 12);  // the test plugin hides nothing
    CHECK(d.trace_events == 12);
    CHECK(d.counter("edges-in") == 12);
    CHECK(d.counter("edges-requested") == 12);
    std::istringstream lines(trace.str());
    std::string first;
    std::getline(lines, first);
    CHECK(first == "{\"type\":\"edge-begin\",\"edge\":0,\"qi\":0,\"t0\":0}");
    // The plugin's end points are the projected vertices (the reference's projection agrees).
    const glm::dmat4 vp = line_reference::view_projection(camera);
    for (const hsr::LineSegment& s : d.segments) {
        const glm::dvec2 a = line_reference::to_window(camera, vp, line_reference::position(scene, d.edges.vertices[2 * s.edge]));
        CHECK(std::abs(a.x - s.a.x) < 1e-3);
        CHECK(std::abs(a.y - s.a.y) < 1e-3);
    }
}

TEST_CASE("lines: the trace's JSON leaves out empty fields and escapes text", "[lines]") {
    hsr_trace_event e{};
    e.struct_size = sizeof e;
    e.type = "say \"hi\"\n";
    e.edge = HSR_NO_EDGE;
    e.face = 7;
    e.object = HSR_NO_OBJECT;
    e.qi = -1;
    e.t0 = 0.25;
    e.t1 = std::numeric_limits<double>::quiet_NaN();
    CHECK(hsr::trace_event_json(e) == "{\"type\":\"say \\\"hi\\\"\\u000a\",\"face\":7,\"t0\":0.25}");
}

TEST_CASE("edges: on a surface grid, --edges all keeps every grid line, flat or not, and no diagonal", "[edges]") {
    // z = max(x, 0) on 9 x 5 samples: flat for x <= 0, a plane for x >= 0, a crease at x = 0.
    hsr::SurfaceRange range;
    range.x0 = -1;
    range.x1 = 1;
    range.columns = 9;
    range.rows = 5;
    const hsr::SceneData surface = hsr::make_formula_surface("max(x, 0)", range);
    const hsr_scene scene = surface.view();
    hsr::CameraSettings settings;
    settings.pitch_degrees = 30;
    const hsr_camera camera = hsr::make_orbit_camera(surface.bounds_min, surface.bounds_max, settings);
    const hsr::EdgeList all = hsr::classify_edges(scene, camera, 40, hsr::EdgeSelection::kAll);
    // Grid lines: 5 rows of 8 edges and 9 columns of 4 edges.
    CHECK(all.size() == 5 * 8 + 9 * 4);
    for (size_t e = 0; e < all.size(); ++e) {
        const uint32_t a = std::min(all.vertices[2 * e], all.vertices[2 * e + 1]);
        const uint32_t b = std::max(all.vertices[2 * e], all.vertices[2 * e + 1]);
        CHECK(((b - a == 1 && a / 9 == b / 9) || b - a == 9));
    }
}
