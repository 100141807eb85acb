// Roberts against Appel: two independent hidden-line algorithms (object-space parametric tests on
// convex bodies; quantitative invisibility propagated along edges) must find the same visible pieces
// of every edge of scenes of convex bodies, including bodies that pass through one another. Roberts'
// penetration lines are left out of the comparison (Appel does not build them).
#include "line_test_support.hpp"

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <string>
#include <vector>

using line_tests::draw;
using line_tests::model;
using line_tests::orbit;

namespace {

struct Interval {
    double t0, t1;
};

// The visible pieces of each edge as parameter intervals along its projected line (0 at its first
// vertex, 1 at its second), sorted and with touching pieces merged: two plugins may cut an edge at
// different places where it stays visible.
std::vector<std::vector<Interval>> visible_intervals(const hsr::LineDrawing& d, const hsr_scene& scene,
                                                     const hsr_camera& camera) {
    const glm::dmat4 vp = line_reference::view_projection(camera);
    std::vector<std::vector<Interval>> out(d.edges.size());
    for (const hsr::LineSegment& s : d.segments) {
        if (s.qi != 0 || s.edge == HSR_NO_EDGE) continue;
        const glm::dvec2 w0 = line_reference::to_window(camera, vp, line_reference::position(scene, d.edges.vertices[2 * s.edge]));
        const glm::dvec2 w1 = line_reference::to_window(camera, vp, line_reference::position(scene, d.edges.vertices[2 * s.edge + 1]));
        const glm::dvec2 dir = w1 - w0;
        const double len2 = glm::dot(dir, dir);
        if (!(len2 > 0)) continue;
        double a = glm::dot(glm::dvec2(s.a) - w0, dir) / len2, b = glm::dot(glm::dvec2(s.b) - w0, dir) / len2;
        if (a > b) std::swap(a, b);
        out[s.edge].push_back({a, b});
    }
    for (auto& pieces : out) {
        std::sort(pieces.begin(), pieces.end(), [](const Interval& x, const Interval& y) { return x.t0 < y.t0; });
        std::vector<Interval> merged;
        for (const Interval& p : pieces) {
            if (!merged.empty() && p.t0 <= merged.back().t1 + 1e-7)
                merged.back().t1 = std::max(merged.back().t1, p.t1);
            else
                merged.push_back(p);
        }
        // Pieces shorter than the tolerance are rounding, not geometry.
        merged.erase(std::remove_if(merged.begin(), merged.end(), [](const Interval& p) { return p.t1 - p.t0 < 1e-6; }),
                     merged.end());
        pieces = merged;
    }
    return out;
}

// Both plugins on one scene and camera: the same edges visible, the same pieces, and each piece's end
// points within 1e-6 of the edge parameter (times the edge's length in pixels), plus 1e-4 px for the
// window coordinates' rounding to float on their way through the ABI.
void check_same_lines(const hsr_scene& scene, const hsr_camera& camera, hsr::EdgeSelection edges) {
    hsr::LineSettings settings;
    settings.edges = edges;
    const hsr::LineDrawing roberts = draw("roberts", scene, camera, settings);
    const hsr::LineDrawing appel = draw("appel", scene, camera, settings);
    REQUIRE(roberts.edges.size() == appel.edges.size());
    const auto r = visible_intervals(roberts, scene, camera);
    const auto a = visible_intervals(appel, scene, camera);
    const glm::dmat4 vp = line_reference::view_projection(camera);
    size_t visible_edges = 0, hidden_edges = 0;
    for (size_t e = 0; e < r.size(); ++e) {
        const glm::dvec2 w0 = line_reference::to_window(camera, vp, line_reference::position(scene, roberts.edges.vertices[2 * e]));
        const glm::dvec2 w1 = line_reference::to_window(camera, vp, line_reference::position(scene, roberts.edges.vertices[2 * e + 1]));
        const double length = glm::length(w1 - w0);
        const double tolerance_px = 1e-6 * length + 1e-4;
        INFO("edge " << e << " (" << w0.x << ", " << w0.y << ") - (" << w1.x << ", " << w1.y << ")");
        REQUIRE(r[e].size() == a[e].size());
        (r[e].empty() ? hidden_edges : visible_edges) += 1;
        for (size_t k = 0; k < r[e].size(); ++k) {
            CHECK(std::abs(r[e][k].t0 - a[e][k].t0) * length <= tolerance_px);
            CHECK(std::abs(r[e][k].t1 - a[e][k].t1) * length <= tolerance_px);
        }
    }
    CHECK(visible_edges > 0);
    CHECK(hidden_edges > 0);
}

// Boxes as separate convex bodies: a unit cube scaled, turned and moved.
hsr::SceneData boxes(const std::vector<glm::mat4>& placements) {
    hsr::SceneBuilder builder;
    const glm::vec3 corners[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    const uint32_t faces[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    for (size_t k = 0; k < placements.size(); ++k) {
        hsr::MeshOptions options;
        options.transform = placements[k];
        options.name = "box " + std::to_string(k);
        builder.add_triangles(corners, faces, options);
    }
    return builder.build();
}

glm::mat4 place(glm::vec3 at, glm::vec3 size, float turn_degrees, glm::vec3 axis) {
    return glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), at), glm::radians(turn_degrees), axis), size);
}

}  // namespace

TEST_CASE("roberts and appel: the same visible lines on the intersecting boxes", "[roberts][appel]") {
    const hsr::SceneData& scene = model("boxes.scene");
    for (bool ortho : {false, true})
        for (float yaw : {35.0f, -70.0f, 160.0f}) {
            INFO("yaw " << yaw << (ortho ? " orthographic" : " perspective"));
            check_same_lines(scene.view(), orbit(scene, yaw, 25, 1, ortho, 640), hsr::EdgeSelection::kAll);
        }
}

TEST_CASE("roberts and appel: the same visible lines on separate and intersecting boxes", "[roberts][appel]") {
    const hsr::SceneData scene = boxes({
        place({0, 0, 0}, {1.5f, 0.3f, 0.3f}, 10, {0, 1, 0}),       // a bar ...
        place({0.4f, 0.1f, 0.2f}, {0.3f, 1.2f, 0.3f}, 25, {0, 0, 1}),  // ... crossed by another
        place({-1.2f, 0.5f, -1.5f}, {0.6f, 0.6f, 0.6f}, 40, {1, 1, 0}),  // a cube behind, apart
        place({1.0f, -0.6f, 1.2f}, {0.4f, 0.2f, 0.5f}, -15, {0, 1, 0}),  // a slab in front
    });
    for (bool ortho : {false, true})
        for (float pitch : {15.0f, 50.0f}) {
            INFO("pitch " << pitch << (ortho ? " orthographic" : " perspective"));
            const hsr_camera camera = orbit(scene, 30, pitch, 1, ortho, 800);
            check_same_lines(scene.view(), camera, hsr::EdgeSelection::kAll);
            check_same_lines(scene.view(), camera, hsr::EdgeSelection::kFeatures);
        }
}
