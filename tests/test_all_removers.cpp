// Every hidden-surface plugin against the ray caster, the exact reference: on the cube, the monkey,
// the bunny and the intersecting boxes, in perspective and orthographic views, each shows the
// surface a ray through the pixel centre meets first, except where the two may rightly differ: a
// pixel centre within a rounding distance of a triangle's edge (the rasterizers snap corners to a
// 1/256-pixel grid), or two surfaces at the same depth (a tie). Anything else is a failure.
#include "surface_test_support.hpp"

#include "hsr/sdk.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using surface_tests::model;
using surface_tests::orbit;
using surface_tests::render;

// The window position of triangle t of placement `instance`.
std::vector<glm::dvec2> window_corners(const hsr_scene& raw, const hsr_camera& camera, uint32_t t, uint32_t instance) {
    const hsr::sdk::Scene scene(raw);
    const hsr::sdk::Placement p = scene.placement(scene.instance_count() > 0 ? instance : 0);
    const glm::dmat4 clip_from_object = glm::dmat4(hsr::sdk::load_matrix(camera.view_projection)) * glm::dmat4(p.transform);
    std::vector<glm::dvec2> corners;
    for (int c = 0; c < 3; ++c) {
        const glm::dvec4 clip = clip_from_object * glm::dvec4(scene.corner_position(t, c), 1.0);
        corners.push_back({(clip.x / clip.w + 1.0) * 0.5 * camera.width, (1.0 - clip.y / clip.w) * 0.5 * camera.height});
    }
    return corners;
}

// Whether pixel (x, y)'s centre lies within `distance` pixels of an edge of the triangle.
bool centre_near_edge(const std::vector<glm::dvec2>& corners, uint32_t x, uint32_t y, double distance) {
    const glm::dvec2 centre(x + 0.5, y + 0.5);
    for (int k = 0; k < 3; ++k) {
        const glm::dvec2 a = corners[k], b = corners[(k + 1) % 3];
        const glm::dvec2 edge = b - a;
        const double length = glm::length(edge);
        if (!(length > 0.0)) return true;
        const double along = glm::dot(centre - a, edge) / (length * length);
        const glm::dvec2 nearest = a + std::clamp(along, 0.0, 1.0) * edge;
        if (glm::length(centre - nearest) <= distance) return true;
    }
    return false;
}

struct Disagreement {
    uint64_t covered = 0, edges = 0, ties = 0, other = 0;
    std::string first_other;
};

Disagreement against_raycast(const std::string& name, const hsr_scene& scene, const hsr_camera& camera) {
    const hsr::Frame exact = render("raycast", scene, camera);
    const hsr::Frame frame = render(name.substr(0, name.find(':')), scene, camera,
                                    name.find(':') == std::string::npos
                                        ? surface_tests::Settings{}
                                        : surface_tests::Settings{{name.substr(name.find(':') + 1, name.find('=') - name.find(':') - 1),
                                                                   name.substr(name.find('=') + 1)}});
    Disagreement d;
    constexpr double kSnap = 1.0 / 128.0;  // two grid steps of the rasterizers' 1/256-pixel snapping
    for (uint32_t y = 0; y < camera.height; ++y)
        for (uint32_t x = 0; x < camera.width; ++x) {
            const size_t p = size_t(y) * camera.width + x;
            const uint32_t a = exact.face[p], b = frame.face[p];
            const uint32_t ia = exact.instance.empty() ? 0 : exact.instance[p];
            const uint32_t ib = frame.instance.empty() ? 0 : frame.instance[p];
            if (a != HSR_NO_FACE) ++d.covered;
            if (a == b && ia == ib) continue;
            if (a != HSR_NO_FACE && b != HSR_NO_FACE &&
                std::abs(exact.depth[p] - frame.depth[p]) <= 4 * std::numeric_limits<float>::epsilon() * exact.depth[p]) {
                ++d.ties;
                continue;
            }
            const bool near_edge = (a != HSR_NO_FACE && centre_near_edge(window_corners(scene, camera, a, ia), x, y, kSnap)) ||
                                   (b != HSR_NO_FACE && centre_near_edge(window_corners(scene, camera, b, ib), x, y, kSnap));
            if (near_edge) {
                ++d.edges;
                continue;
            }
            if (++d.other == 1)
                d.first_other = "pixel " + std::to_string(x) + "," + std::to_string(y) + ": raycast face " +
                                std::to_string(a) + ", " + name + " face " + std::to_string(b);
        }
    return d;
}

std::vector<std::string> removers() {
    std::vector<std::string> names = {"zbuffer", "scanline-zbuffer", "hierarchical-zbuffer", "octree-zbuffer",
                                      "painter", "bsp", "bsp:order=front-to-back", "warnock", "weiler-atherton",
                                      "a-buffer"};
    if (std::filesystem::exists(std::string(HSR_PLUGIN_DIR) + "/hsr-embree.so")) names.push_back("embree");
    return names;
}

void check_models(const std::vector<const char*>& files) {
    for (const char* file : files) {
        const hsr::SceneData& data = model(file);
        for (const auto& [yaw, pitch, ortho] : {std::tuple{30.0f, 20.0f, false}, std::tuple{-50.0f, 35.0f, true}}) {
            const hsr_camera camera = orbit(data, yaw, pitch, 1, ortho, 160);
            for (const std::string& name : removers()) {
                const Disagreement d = against_raycast(name, data.view(), camera);
                INFO(name << " on " << file << (ortho ? ", orthographic" : ", perspective") << ": " << d.covered
                          << " covered, " << d.edges << " on edges, " << d.ties << " ties; " << d.first_other);
                CHECK(d.covered > 1000);
                CHECK(d.other == 0);
                // Ties are left to each algorithm's order (the boxes have coplanar faces); edges are rare.
                CHECK(double(d.edges) <= 0.01 * double(d.covered));
            }
        }
    }
}

}  // namespace

TEST_CASE("all removers: the committed models agree with raycast", "[all-removers]") {
    check_models({"cube.obj", "boxes.scene"});
}

TEST_CASE("all removers: monkey and bunny agree with raycast", "[all-removers][slow]") {
    test_models::require_fetched();
    check_models({"monkey.obj", "bunny.obj"});
}
