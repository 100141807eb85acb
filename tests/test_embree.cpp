// The embree plugin (ray casting with Intel Embree 3 as the kernel) against the raycast plugin, its
// exact reference: the same surface at all but a few pixels (edges and ties, where Embree's float
// test may pick the neighbour), depth and barycentrics close, every pixel covered from inside a
// closed mesh, clip planes honoured, instances moved between frames noticed. Skipped when the
// plugin was not built (no libembree-dev).
#include "hsr/abi.h"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene_builder.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <filesystem>
#include <string>

namespace {

using namespace surface_tests;

bool built() { return std::filesystem::exists(std::string(HSR_PLUGIN_DIR) + "/hsr-embree.so"); }

struct Difference {
    uint64_t covered = 0, other_surface = 0;
    uint64_t ties = 0;  // another surface within 4 float steps of depth (coplanar faces, shared edges)
    double worst_depth_steps = 0, worst_bary = 0;
};

// embree's frame against raycast's: pixels showing another surface (or coverage), and how far depth
// (in float steps) and barycentrics are on the same surface.
Difference against_raycast(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {}) {
    const hsr::Frame exact = render("raycast", scene, camera, settings);
    const hsr::Frame frame = render("embree", scene, camera, settings);
    Difference d;
    for (size_t p = 0; p < exact.face.size(); ++p) {
        if (exact.face[p] == HSR_NO_FACE && frame.face[p] == HSR_NO_FACE) continue;
        ++d.covered;
        if (exact.face[p] != frame.face[p] || (!exact.instance.empty() && exact.instance[p] != frame.instance[p])) {
            const bool tie = exact.face[p] != HSR_NO_FACE && frame.face[p] != HSR_NO_FACE &&
                             std::abs(frame.depth[p] - exact.depth[p]) <=
                                 4 * std::numeric_limits<float>::epsilon() * exact.depth[p];
            ++(tie ? d.ties : d.other_surface);
            continue;
        }
        d.worst_depth_steps = std::max(d.worst_depth_steps, std::abs(double(frame.depth[p]) - exact.depth[p]) /
                                                                (std::numeric_limits<float>::epsilon() * exact.depth[p]));
        d.worst_bary = std::max({d.worst_bary, std::abs(double(frame.bary[2 * p]) - exact.bary[2 * p]),
                                 std::abs(double(frame.bary[2 * p + 1]) - exact.bary[2 * p + 1])});
    }
    return d;
}

void check_close(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {}) {
    const Difference d = against_raycast(scene, camera, settings);
    INFO(d.other_surface << " of " << d.covered << " pixels show another surface, " << d.ties
                         << " a tie; depth within " << d.worst_depth_steps << " float steps, barycentrics within "
                         << d.worst_bary);
    CHECK(d.covered > 0);
    // raycast also draws near misses its snapped corners cover (the rasterizers' fill rule); Embree
    // reports only what its own test hits, so a pixel centre within a snapping step of an edge may
    // show the triangle across it: up to 1.4 % of deep-monkeys.scene's pixels, dense with edges.
    CHECK(double(d.other_surface) < 0.02 * double(d.covered));
    // boxes.scene's bars share face planes: there Embree keeps whichever face it meets first.
    CHECK(double(d.ties) < 0.05 * double(d.covered));
    // A float hit test: the corners relative to an origin on the near plane, to 2^-24 of that distance.
    CHECK(d.worst_depth_steps <= 256.0);
    CHECK(d.worst_bary <= 5e-3);
    if (std::getenv("HSR_EMBREE_SUMMARY"))
        std::printf("%ux%u %s: covered %llu, other surface %llu, ties %llu, depth steps %.1f, bary %.2g\n",
                    camera.width, camera.height, camera.projection_type == HSR_PROJECTION_ORTHOGRAPHIC ? "ortho" : "persp",
                    (unsigned long long)d.covered, (unsigned long long)d.other_surface, (unsigned long long)d.ties,
                    d.worst_depth_steps, d.worst_bary);
}

}  // namespace

TEST_CASE("embree: close to raycast on the models and scenes", "[embree]") {
    if (!built()) return;
    test_models::require_fetched();
    for (const char* file : {"cube.obj", "monkey.obj", "bunny.obj", "boxes.scene", "deep-monkeys.scene"}) {
        INFO(file);
        const hsr::SceneData& data = model(file);
        check_close(data.view(), orbit(data, 30, 20, 1, false, 160));
        check_close(data.view(), orbit(data, -70, -10, 1, true, 160));
        check_close(data.view(), orbit(data, 120, 35, 1.3f, false, 160), {{"cull-backfaces", "true"}});
    }
}

TEST_CASE("embree: a closed mesh seen from inside covers every pixel", "[embree]") {
    if (!built()) return;
    const hsr::SceneData& cube = model("cube.obj");
    for (const hsr_camera& camera : {look({0, 0, 0}, {0, 0, 1}, 0.01f, 10.0f, 64, 64, 90.0f),
                                     look({0, 0, 0}, {1, 1, 1}, 0.01f, 10.0f, 64, 64, 100.0f)}) {
        const hsr::Frame frame = render("embree", cube.view(), camera);
        CHECK(std::count(frame.face.begin(), frame.face.end(), HSR_NO_FACE) == 0);
    }
}

TEST_CASE("embree: clip planes, threads, and an instance moved between frames", "[embree]") {
    if (!built()) return;
    test_models::require_fetched();
    const hsr::SceneData& bunny = model("bunny.obj");
    hsr_camera camera = orbit(bunny, 30, 15, 1, false, 160);
    const glm::vec3 middle = 0.5f * (bunny.bounds_min + bunny.bounds_max);
    const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 0.1f, -1.0f));
    const float plane[4] = {n.x, n.y, n.z, -glm::dot(n, middle)};
    camera.clip_plane_count = 1;
    std::memcpy(camera.clip_planes[0], plane, sizeof plane);
    check_close(bunny.view(), camera);

    const hsr_camera plain = orbit(bunny, 10, 10, 1, false, 150, 130);
    const hsr::Frame one = render("embree", bunny.view(), plain, {{"threads", "1"}});
    const hsr::Frame many = render("embree", bunny.view(), plain, {{"threads", "3"}, {"tile-size", "7"}});
    CHECK(one.face == many.face);
    CHECK(one.depth == many.depth);
    CHECK(one.bary == many.bary);

    hsr::SceneData grid = hsr::make_instance_grid(model("monkey.obj"), {3, 2, 4, 0.0f, 40.0f});
    const hsr_camera grid_camera = orbit(grid, 25, 15, 1, false, 160);
    hsr::HiddenSurfaceRemover embree(plugin("embree"), {});
    const hsr::Frame before = render(embree, grid.view(), grid_camera);
    CHECK(render(embree, grid.view(), grid_camera).counter("build-time-us") == 0);
    hsr_instance& moved = grid.instances.at(5);
    moved.transform[12] += 0.7f;
    moved.transform[13] += 0.3f;
    const hsr::Frame after = render(embree, grid.view(), grid_camera);
    CHECK(after.counter("build-time-us") > 0);
    CHECK(after.face != before.face);
    const hsr::Frame exact = render("raycast", grid.view(), grid_camera);
    uint64_t other = 0, covered = 0;
    for (size_t p = 0; p < exact.face.size(); ++p) {
        covered += exact.face[p] != HSR_NO_FACE;
        other += exact.face[p] != after.face[p] || exact.instance[p] != after.instance[p];
    }
    CHECK(double(other) < 0.01 * double(covered));
}

TEST_CASE("embree: hsr exits cleanly after using it, its worker threads still running", "[embree][cli]") {
    if (!built()) return;
    // Embree's TBB threads outlive its devices; the plugin stays loaded until the process ends
    // (linked -z nodelete), or they would crash the process as it exits.
    const std::string hsr = std::string(HSR_BINARY_DIR) + "/hsr";
    const std::string out = std::filesystem::temp_directory_path() / "hsr-embree-exit.png";
    CHECK(std::system((hsr + " render " + HSR_MODELS_DIR + "/cube.obj -a embree --width 64 --height 64 -o " + out +
                       " 2>/dev/null").c_str()) == 0);
    CHECK(std::system((hsr + " bench --quick --algorithms embree > /dev/null 2>&1").c_str()) == 0);
}
