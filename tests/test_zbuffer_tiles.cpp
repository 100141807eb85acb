// The z-buffer's fast paths against its step-by-step path (render step by step run to the end: every
// triangle drawn in scene order, each set up alone): with two threads (tbb::global_control) the
// parallel one (triangles binned to screen tiles, tiles drawn in parallel), with one the in-order
// one that sets triangles up in batches. Every buffer (depth, face, instance, barycentrics,
// per-pixel depth-test counts) byte for byte and every counter equal, on meshes, instanced and deep
// scenes, clip planes, near-plane clipping, depth-test=greater, back-face culling, and image sizes
// from 1x1 to odd strips whose tiles are cut by the image border.
#include "hsr/pipeline.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <cstring>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The counters a remover reports (the host adds none to resolve_visibility's frame).
std::vector<std::pair<std::string, uint64_t>> remover_counters(const hsr::Frame& frame) {
    std::vector<std::pair<std::string, uint64_t>> out;
    for (const auto& c : frame.counters)
        if (c.first.rfind("triangles-", 0) == 0 || c.first.rfind("pixels-", 0) == 0) out.push_back(c);
    return out;
}

// Renders with zbuffer in parallel and step by step, on 1 and 2 threads, and compares.
void check_tiles_equal_serial(const hsr::SceneData& data, const hsr_camera& camera, const Settings& settings = {}) {
    const hsr_scene scene = data.view();
    for (const bool count_tests : {false, true}) {
        hsr::HiddenSurfaceRemover serial_remover(plugin("zbuffer"), settings);
        hsr::Frame serial;
        hsr::resolve_visibility_steps(scene, camera, serial_remover, serial, 0, count_tests);
        REQUIRE(serial.steps.has_value());
        CHECK_FALSE(serial.steps->stopped);
        for (const int threads : {1, 2}) {
            INFO(camera.width << "x" << camera.height << ", " << threads << " thread(s), depth tests counted: "
                               << count_tests);
            const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
            hsr::HiddenSurfaceRemover remover(plugin("zbuffer"), settings);
            for (int frame_index = 0; frame_index < 2; ++frame_index) {  // a second frame reuses the bins
                const hsr::Frame tiled = render(remover, scene, camera, count_tests);
                CHECK(same_bytes(tiled.depth, serial.depth));
                CHECK(same_bytes(tiled.face, serial.face));
                CHECK(same_bytes(tiled.instance, serial.instance));
                CHECK(same_bytes(tiled.bary, serial.bary));
                CHECK(same_bytes(tiled.depth_tests, serial.depth_tests));
                CHECK(remover_counters(tiled) == remover_counters(serial));
            }
        }
    }
}

// Adds a world-space clip plane (a, b, c, d): the camera keeps a x + b y + c z + d >= 0.
void add_clip_plane(hsr_camera& camera, float a, float b, float c, float d) {
    const float plane[4] = {a, b, c, d};
    for (int k = 0; k < 4; ++k) camera.clip_planes[camera.clip_plane_count][k] = plane[k];
    ++camera.clip_plane_count;
}

}  // namespace

TEST_CASE("zbuffer tiles: the bunny and the monkey as drawn in order", "[slow]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    check_tiles_equal_serial(bunny, orbit(bunny, 30.0f, 15.0f, 1.0f, false, 1024));
    const hsr::SceneData& monkey = model("monkey.obj");
    check_tiles_equal_serial(monkey, orbit(monkey, -40.0f, 10.0f, 1.3f, false, 640, 480));
    check_tiles_equal_serial(monkey, orbit(monkey, 10.0f, -20.0f, 1.0f, true, 300));
}

TEST_CASE("zbuffer tiles: parameters, clip planes and the near plane", "[slow]") {
    const hsr::SceneData& monkey = model("monkey.obj");
    const hsr_camera camera = orbit(monkey, 20.0f, 10.0f, 1.0f, false, 513, 385);
    check_tiles_equal_serial(monkey, camera, {{"depth-test", "greater"}});
    check_tiles_equal_serial(monkey, camera, {{"cull-backfaces", "true"}});
    hsr_camera sectioned = camera;
    add_clip_plane(sectioned, 1.0f, 0.2f, 0.0f, 0.1f);
    add_clip_plane(sectioned, 0.0f, -1.0f, 0.3f, 0.4f);
    check_tiles_equal_serial(monkey, sectioned);
    // The near plane through the middle of the cube and of the monkey: clipped pieces.
    for (const char* file : {"cube.obj", "monkey.obj"}) {
        INFO(file);
        const hsr::SceneData& scene = model(file);
        const glm::vec3 centre = 0.5f * (scene.bounds_min + scene.bounds_max);
        const float size = glm::length(scene.bounds_max - scene.bounds_min);
        const glm::vec3 eye = centre + size * glm::vec3(0.3f, 0.2f, 1.5f);
        const hsr_camera cut = look(eye, centre, glm::length(eye - centre), 4.0f * size, 400, 300, 40.0f);
        CHECK(counter(render("zbuffer", scene.view(), cut), "triangles-clipped") > 0);
        check_tiles_equal_serial(scene, cut);
    }
}

TEST_CASE("zbuffer tiles: instanced and deep scenes", "[slow]") {
    for (const char* file : {"boxes.scene", "deep-monkeys.scene", "zbuffer-exercise.scene"}) {
        INFO(file);
        const hsr::SceneData& scene = model(file);
        check_tiles_equal_serial(scene, orbit(scene, 25.0f, 20.0f, 1.0f, false, 320, 240));
        check_tiles_equal_serial(scene, orbit(scene, -60.0f, 5.0f, 2.5f, false, 257, 129), {{"depth-test", "greater"}});
    }
}

TEST_CASE("zbuffer tiles: tiny and odd image sizes") {
    const hsr::SceneData& monkey = model("monkey.obj");
    for (const auto& [width, height] : {std::pair{1u, 1u}, {3u, 1000u}, {1023u, 17u}, {1u, 700u}, {65u, 64u}, {2u, 3u}}) {
        check_tiles_equal_serial(monkey, orbit(monkey, 35.0f, 25.0f, 1.0f, false, width, height));
        check_tiles_equal_serial(monkey, orbit(monkey, 35.0f, 25.0f, 3.0f, true, width, height));
    }
}

TEST_CASE("zbuffer tiles: large triangles across many tiles and their borders") {
    // A few big triangles through the cube and the octahedron, and random triangles larger than
    // a tile, seen close up.
    for (const char* file : {"cube.obj", "octahedron.ply", "three-polygons.scene"}) {
        INFO(file);
        const hsr::SceneData& scene = model(file);
        check_tiles_equal_serial(scene, orbit(scene, 30.0f, 30.0f, 1.0f, false, 700, 500));
        check_tiles_equal_serial(scene, orbit(scene, 200.0f, -30.0f, 4.0f, false, 700, 500));
    }
}
