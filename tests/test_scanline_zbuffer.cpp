// The scanline-zbuffer plugin (Wylie et al. 1967, Watkins 1970) loaded through the real ABI: small
// scenes whose answer is worked out by hand (pixel camera, exact fill rule), and real models, random
// triangles, near-plane clipping and a deep instanced scene checked against the plain zbuffer
// plugin. Coverage must be the same sample for sample (per-pixel depth-test counts equal); the
// visible face (and instance) the same at every pixel except depth ties.
#include "hsr/abi.h"
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/glm.hpp>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

// Coverage must be the same sample for sample: both frames count their per-pixel depth tests. The
// same surface is enough (depth and barycentrics are measured, not compared bit for bit); ties
// are depths within 4 float steps and may reach 0.1 % of the covered pixels.
const Agreement kScanline{.plugin = "scanline-zbuffer",
                          .label = "scanline",
                          .bit_identical = false,
                          .count_depth_tests = true,
                          .tie_float_steps = 4.0f,
                          .tie_floor = 1e-6f,
                          .ties_may_reach_share = true};

// Barycentric weights of corners 1 and 2 of triangle t of the scene at world point (x, y).
glm::dvec2 barycentric_2d(const hsr::SceneData& scene, uint32_t t, glm::dvec2 p) {
    glm::dvec2 c[3];
    for (int k = 0; k < 3; ++k) {
        const uint32_t v = scene.indices[3 * t + k];
        c[k] = {scene.positions[3 * v], scene.positions[3 * v + 1]};
    }
    return surface_tests::barycentric_2d(p, c[0], c[1], c[2]);
}

// Triangles given by hand (their own vertices each), as a scene of one object.
hsr::SceneData triangles(const std::vector<glm::vec3>& corners) {
    std::vector<uint32_t> indices(corners.size());
    for (uint32_t k = 0; k < indices.size(); ++k) indices[k] = k;
    hsr::SceneBuilder builder;
    builder.add_triangles(corners, indices);
    return builder.build();
}

// The scanline z-buffer and the z-buffer agree: the same samples tested at every pixel, the same
// triangle counters, the same visible surface except at ties (fewer than 0.1 % of the covered
// pixels), and there depth within a few float steps and barycentrics within float rounding.
Comparison check_same_picture(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {}) {
    const Picture picture = check_against_zbuffer(kScanline, scene, camera, settings, settings);
    const hsr::Frame &reference = picture.reference, &scan = picture.frame;
    const Comparison& c = picture.comparison;
    INFO(camera.width << "x" << camera.height << ": " << c.first_difference);
    CHECK(c.coverage_differences == 0);
    CHECK(c.worst_depth_ulps <= 2.0);
    CHECK(c.worst_bary <= 1e-6);
    for (const char* name : {"triangles-in", "triangles-backface-culled", "triangles-clipped", "triangles-outside",
                             "triangles-degenerate", "triangles-rasterized", "pixels-depth-tested"}) {
        INFO(name);
        CHECK(counter(scan, name) == counter(reference, name));
    }
    CHECK(counter(scan, "pixels-written") <= counter(scan, "pixels-depth-tested"));
    check_triangle_accounting(scan);
    return c;
}

// A camera whose near plane cuts a triangle of the model and its neighbours: the eye just above
// the middle triangle, looking along it; in a scene of instances, the triangle as `placed`.
hsr_camera skimming_camera(const hsr::SceneData& data, const glm::mat4& placed = glm::mat4(1.0f)) {
    const float size = glm::length(data.bounds_max - data.bounds_min);
    const uint32_t t = data.triangle_count() / 2;
    glm::vec3 corner[3];
    for (int k = 0; k < 3; ++k) {
        const uint32_t v = data.indices[3 * t + k];
        corner[k] = placed * glm::vec4(data.positions[3 * v], data.positions[3 * v + 1], data.positions[3 * v + 2], 1.0f);
    }
    const glm::vec3 normal = glm::normalize(
        glm::mat3(placed) * glm::vec3(data.face_normals[3 * t], data.face_normals[3 * t + 1], data.face_normals[3 * t + 2]));
    const glm::vec3 eye = (corner[0] + corner[1] + corner[2]) / 3.0f + 1e-4f * size * normal;
    const glm::vec3 along = glm::normalize(corner[1] - corner[0]) + 0.2f * normal;
    return look(eye, eye + along, 1e-3f * size, 4 * size, 256, 256, 80.0f);
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The sweep over bands of rows in parallel (two threads, bands of 1, 5 and 64 rows and the default
// height) against one sweep from the top (band-rows=16384) and the sweep run step by step: every
// buffer byte for byte and every counter the same, with and without per-pixel depth-test counts. With instances, each band
// has a pool of records of its own: polygon-records-max is then the most one band's pool held, at
// most the one sweep's.
void check_bands_equal_one_sweep(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {}) {
    const tbb::global_control two_threads(tbb::global_control::max_allowed_parallelism, 2);
    tbb::task_arena arena(2);
    arena.execute([&] {
        for (const bool count_tests : {false, true}) {
            Settings one_sweep = settings;
            one_sweep.push_back({"band-rows", "16384"});
            const hsr::Frame sweep = render("scanline-zbuffer", scene, camera, one_sweep, count_tests);
            hsr::HiddenSurfaceRemover stepwise(plugin("scanline-zbuffer"), settings);
            hsr::Frame steps;
            hsr::resolve_visibility_steps(scene, camera, stepwise, steps, 0, count_tests);
            std::vector<std::pair<std::string, hsr::Frame>> frames;
            frames.emplace_back("steps", std::move(steps));
            for (const char* rows : {"1", "5", "64", "0"}) {
                Settings banded = settings;
                banded.push_back({"band-rows", rows});
                hsr::HiddenSurfaceRemover remover(plugin("scanline-zbuffer"), banded);
                for (int k = 0; k < 2; ++k)  // a second frame reuses the bands
                    frames.emplace_back(std::string("bands of ") + rows, render(remover, scene, camera, count_tests));
            }
            for (const auto& [label, frame] : frames) {
                INFO(camera.width << "x" << camera.height << ", " << label << ", depth tests counted: " << count_tests);
                CHECK(same_bytes(frame.depth, sweep.depth));
                CHECK(same_bytes(frame.face, sweep.face));
                CHECK(same_bytes(frame.instance, sweep.instance));
                CHECK(same_bytes(frame.bary, sweep.bary));
                CHECK(same_bytes(frame.depth_tests, sweep.depth_tests));
                for (const auto& [name, value] : sweep.counters) {  // a step run has the host's step count too
                    INFO(name);
                    if (name == "polygon-records-max" && scene.instance_count > 0 && label != "steps")
                        CHECK(counter(frame, name) <= value);
                    else
                        CHECK(counter(frame, name) == value);
                }
                CHECK(frame.counters.size() == sweep.counters.size() + (label == "steps" ? 1 : 0));
            }
        }
    });
}

}  // namespace

// ---------------------------------------------------------------------------------------------- //

TEST_CASE("scanline-zbuffer: descriptor lists its parameters", "[scanline-zbuffer]") {
    const hsr_plugin_descriptor& d = plugin("scanline-zbuffer").descriptor;
    REQUIRE(std::string(d.name) == "scanline-zbuffer");
    CHECK(d.kind == HSR_KIND_HIDDEN_SURFACE_REMOVER);
    CHECK(d.abi_minor >= 1);  // writes instance ids
    REQUIRE(d.param_count == 2);
    CHECK(std::string(d.params[0].name) == "cull-backfaces");
    CHECK(d.params[0].type == HSR_PARAM_BOOL);
    CHECK(std::string(d.params[0].default_value) == "false");
    CHECK(std::string(d.params[1].name) == "band-rows");
    CHECK(d.params[1].type == HSR_PARAM_INT);
    CHECK(std::string(d.params[1].default_value) == "0");
}

TEST_CASE("scanline-zbuffer: two intersecting triangles, answered by hand", "[scanline-zbuffer]") {
    // Pixel camera, 8 x 6: world (x, y) lands on window (x, 6 - y); a larger z is nearer. Triangle 0
    // lies flat at z = 0, triangle 1 is tilted, z = x - 4: they cross at x = 4. Both cover the whole
    // image, so at pixel column i (centre x = i + 0.5) triangle 1 is in front exactly when i >= 4.
    const hsr::SceneData scene = triangles({{-1, -1, 0}, {30, -1, 0}, {-1, 30, 0},     // 0: flat
                                            {-1, -1, -5}, {30, -1, 26}, {-1, 30, -5}});  // 1: z = x - 4
    const hsr_camera camera = hsr::make_pixel_camera(8, 6, -6.0f, 27.0f);
    const hsr::Frame frame = render("scanline-zbuffer", scene.view(), camera, {}, true);
    for (uint32_t y = 0; y < 6; ++y)
        for (uint32_t x = 0; x < 8; ++x) {
            INFO("pixel " << x << "," << y);
            const size_t p = size_t(y) * 8 + x;
            const double wx = x + 0.5, wy = 6 - (y + 0.5);  // the world point seen at the centre
            const uint32_t expected = x >= 4 ? 1 : 0;
            CHECK(frame.face[p] == expected);
            CHECK(frame.depth_tests[p] == 2);
            const double z = expected == 1 ? wx - 4 : 0.0;
            CHECK(frame.depth[p] == Approx(window_depth(camera, {wx, wy, z})).margin(1e-6));
            // Barycentrics of the scene's corners 1 and 2 (the scene may start a triangle at any
            // corner): the orthographic view makes them affine in x and y.
            const glm::dvec2 b = barycentric_2d(scene, expected, {wx, wy});
            CHECK(frame.bary[2 * p] == Approx(b.x).margin(1e-6));
            CHECK(frame.bary[2 * p + 1] == Approx(b.y).margin(1e-6));
        }
    CHECK(counter(frame, "triangles-in") == 2);
    CHECK(counter(frame, "triangles-rasterized") == 2);
    CHECK(counter(frame, "pixels-depth-tested") == 2 * 8 * 6);
    // Every pixel passes the depth test at least once (the first span drawn there) and at most
    // twice (the farther triangle first): between 48 and 72 writes to the row buffer.
    CHECK(counter(frame, "pixels-written") >= 48);
    CHECK(counter(frame, "pixels-written") <= 72);
    CHECK(counter(frame, "scanlines") == 6);
    CHECK(counter(frame, "edge-pairs-processed") == 12);
    CHECK(counter(frame, "active-polygons-max") == 2);
}

TEST_CASE("scanline-zbuffer: the fill rule on edges and corners through pixel centres", "[scanline-zbuffer]") {
    // Two triangles sharing the diagonal of the square with window corners (1.5, 1.5) and
    // (5.5, 5.5), all four corners and the diagonal exactly on pixel centres. The upper-left one
    // has a horizontal top edge and a vertical left edge (top and left: centres on them are drawn)
    // and the diagonal as its right edge (not drawn): centres (i + 0.5, j + 0.5) with i, j >= 1 and
    // i + j <= 5, ten of them. The lower-right one has the diagonal as a left edge (drawn), a
    // vertical right edge and a horizontal bottom edge (not drawn): i, j <= 4 and i + j >= 6, six.
    // Window y = 8 - world y.
    auto world = [](double wx, double wy) { return glm::vec3(float(wx), float(8 - wy), 0.0f); };
    const hsr::SceneData scene = triangles({world(1.5, 1.5), world(1.5, 5.5), world(5.5, 1.5),
                                            world(5.5, 1.5), world(1.5, 5.5), world(5.5, 5.5)});
    const hsr_camera camera = hsr::make_pixel_camera(8, 8, -1.0f, 1.0f);
    for (const Settings& settings : {Settings{}, Settings{{"cull-backfaces", "true"}}}) {
        const hsr::Frame frame = render("scanline-zbuffer", scene.view(), camera, settings, true);
        for (uint32_t j = 0; j < 8; ++j)
            for (uint32_t i = 0; i < 8; ++i) {
                INFO("pixel " << i << "," << j);
                const size_t p = size_t(j) * 8 + i;
                uint32_t expected = HSR_NO_FACE;
                if (i >= 1 && j >= 1 && i + j <= 5) expected = 0;
                if (i <= 4 && j <= 4 && i + j >= 6) expected = 1;
                CHECK(frame.face[p] == expected);
                CHECK(frame.depth_tests[p] == (expected == HSR_NO_FACE ? 0u : 1u));
            }
        CHECK(counter(frame, "pixels-depth-tested") == 16);
        CHECK(counter(frame, "pixels-written") == 16);
        CHECK(counter(frame, "triangles-backface-culled") == 0);  // both face the camera
    }
}

TEST_CASE("scanline-zbuffer: random triangles cover exactly what zbuffer covers", "[scanline-zbuffer]") {
    // Small and large, thin and wide triangles, many with corners on pixel centres or pixel corners
    // (horizontal and vertical edges, edges through centres, shared corners), in the pixel camera
    // and in a perspective view that cuts them with the near plane and the guard band.
    std::mt19937 random(20240607);
    auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(random); };
    for (int round = 0; round < 6; ++round) {
        std::vector<glm::vec3> corners;
        for (int t = 0; t < 300; ++t) {
            const double size = t % 3 == 0 ? 40.0 : t % 3 == 1 ? 6.0 : 1.5;
            const glm::dvec2 centre(uniform(-5, 69), uniform(-5, 53));
            for (int k = 0; k < 3; ++k) {
                glm::dvec2 p = centre + glm::dvec2(uniform(-size, size), uniform(-size, size));
                if (t % 4 == 0) p = glm::floor(p) + 0.5;  // on a pixel centre
                if (t % 4 == 1) p = glm::floor(p);        // on a pixel corner
                corners.emplace_back(float(p.x), float(p.y), float(uniform(-10, 10)));
            }
            if (t % 8 == 2) corners[corners.size() - 2].y = corners[corners.size() - 3].y;  // a horizontal edge
            // In front of the pixel camera's near plane (z = 11): clipped, the pieces keep the two
            // corners on the grid.
            if (t % 5 == 3) corners.back().z = 15.0f;
        }
        const hsr::SceneData scene = triangles(corners);
        INFO("round " << round);
        const hsr_camera pixels = hsr::make_pixel_camera(64, 48, -10.0f, 10.0f);
        check_same_picture(scene.view(), pixels);
        CHECK(counter(render("scanline-zbuffer", scene.view(), pixels, {}, true), "triangles-clipped") > 0);
        // The eye just above the soup, looking across it: the near plane cuts many triangles.
        const hsr_camera perspective = look({32, 24, 3}, {60, 40, -4}, 0.05f, 200.0f, 96, 64, 100.0f);
        check_same_picture(scene.view(), perspective);
        CHECK(counter(render("scanline-zbuffer", scene.view(), perspective, {}, true), "triangles-clipped") > 0);
    }
}

TEST_CASE("scanline-zbuffer: the bunny, the monkey and intersecting boxes match zbuffer", "[scanline-zbuffer]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    check_same_picture(bunny.view(), orbit(bunny, 0, 0, 1, false, 1024, 1024));
    check_same_picture(bunny.view(), orbit(bunny, 120, 35, 1.3f, false, 320, 200));
    check_same_picture(bunny.view(), orbit(bunny, -60, -20, 1, true, 300, 333));
    check_same_picture(bunny.view(), orbit(bunny, 200, 10, 4, false, 256, 256));  // much off screen
    check_same_picture(bunny.view(), orbit(bunny, 30, 20, 1, false, 512, 384), {{"cull-backfaces", "true"}});

    const hsr::SceneData& monkey = model("monkey.obj");
    check_same_picture(monkey.view(), orbit(monkey, 0, 0, 1, false, 1024, 1024));
    check_same_picture(monkey.view(), orbit(monkey, 145, -30, 1.5f, true, 256, 300), {{"cull-backfaces", "true"}});

    const hsr::SceneData& boxes = model("boxes.scene");
    check_same_picture(boxes.view(), orbit(boxes, 35, 25, 1, false, 320, 320));
    check_same_picture(boxes.view(), orbit(boxes, -80, 60, 2.5f, false, 256, 256), {{"cull-backfaces", "true"}});
}

TEST_CASE("scanline-zbuffer: the near plane cuts through the model", "[scanline-zbuffer]") {
    // The eye inside each model, inside its bounds looking across it, and skimming one of its
    // triangles (so that the near plane cuts that triangle and its neighbours): triangles crossing
    // the near plane are drawn as clipped pieces, kept whole in the polygon table.
    for (const char* file : {"bunny.obj", "monkey.obj", "boxes.scene"}) {
        const hsr::SceneData& data = model(file);
        const glm::vec3 lo = data.bounds_min, hi = data.bounds_max, centre = 0.5f * (lo + hi);
        const float size = glm::length(hi - lo);
        INFO(file);
        for (const Settings& settings : {Settings{}, Settings{{"cull-backfaces", "true"}}}) {
            if (settings.empty())  // from inside a closed mesh every face is a back face
                check_same_picture(data.view(),
                                   look(centre, centre + glm::vec3(1, 0.3f, -0.5f), 1e-3f * size, 4 * size, 256, 192));
            check_same_picture(data.view(), look(lo + 0.15f * (hi - lo), centre, 2e-2f * size, 4 * size, 200, 256, 90.0f),
                               settings);
            const hsr_camera skimming = skimming_camera(data);
            check_same_picture(data.view(), skimming, settings);
            CHECK(counter(render("scanline-zbuffer", data.view(), skimming, settings, true), "triangles-clipped") > 0);
        }
    }
}

TEST_CASE("scanline-zbuffer: bands swept in parallel give the one sweep's buffers and counters",
          "[scanline-zbuffer][bands]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    check_bands_equal_one_sweep(bunny.view(), orbit(bunny, 30, 15, 1, false, 640, 480));
    check_bands_equal_one_sweep(bunny.view(), orbit(bunny, -60, -20, 1.2f, true, 301, 333), {{"cull-backfaces", "true"}});
    const hsr::SceneData& monkey = model("monkey.obj");
    check_bands_equal_one_sweep(monkey.view(), orbit(monkey, 145, -30, 1.5f, false, 256, 300));
    check_bands_equal_one_sweep(monkey.view(), orbit(monkey, 10, 5, 6, false, 97, 65));  // mostly off the image
    // Pieces of triangles the near plane cuts (kept whole in the polygon table) crossing bands.
    const hsr_camera skimming = skimming_camera(monkey);
    CHECK(counter(render("scanline-zbuffer", monkey.view(), skimming), "triangles-clipped") > 0);
    check_bands_equal_one_sweep(monkey.view(), skimming);
    // One and two rows: fewer rows than a band, and bands of one row each.
    check_bands_equal_one_sweep(monkey.view(), orbit(monkey, 0, 0, 1, false, 64, 1));
    check_bands_equal_one_sweep(monkey.view(), orbit(monkey, 0, 0, 1, false, 3, 2));
    // More rows than 1,024 bands of one row: the bands are made taller.
    check_bands_equal_one_sweep(monkey.view(), orbit(monkey, 0, 0, 1, false, 24, 2100));
}

TEST_CASE("scanline-zbuffer: small instanced scenes in bands give the one sweep's buffers and counters",
          "[scanline-zbuffer][bands][deep]") {
    // A grid of monkeys, some rows off the image, at a size where most triangles are tiny: what the
    // case below checks at length, in seconds under the sanitizers.
    const hsr::SceneData grid = hsr::make_instance_grid(model("monkey.obj"), {3, 8, 4, 0.3f, 35.0f});
    const hsr_camera camera = orbit(grid, 15, 40, 2.5f, false, 96, 128);
    CHECK(counter(render("scanline-zbuffer", grid.view(), camera), "polygons-empty") > 0);
    check_bands_equal_one_sweep(grid.view(), camera);
}

TEST_CASE("scanline-zbuffer: instanced scenes in bands give the one sweep's buffers and counters",
          "[scanline-zbuffer][bands][deep][slow]") {
    // Instances reaching across bands, set up again by each band they reach; rows of instances
    // above and below the image; the eye among them, the near plane cutting some (their pieces
    // carried into the bands below); tiny triangles given by their spans, some on a band's first
    // row after starting on the row above.
    const hsr::SceneData grid = hsr::make_instance_grid(model("monkey.obj"), {3, 8, 4, 0.3f, 35.0f});
    const hsr_scene scene = grid.view();
    check_bands_equal_one_sweep(scene, orbit(grid, 0, 0, 1, false, 256, 384));
    check_bands_equal_one_sweep(scene, orbit(grid, 15, 40, 2.5f, false, 300, 300));
    check_bands_equal_one_sweep(scene, orbit(grid, -25, -20, 3, true, 240, 320), {{"cull-backfaces", "true"}});
    const glm::vec3 lo = grid.bounds_min, hi = grid.bounds_max, middle = 0.5f * (lo + hi);
    const float size = glm::length(hi - lo);
    check_bands_equal_one_sweep(scene, look(middle, middle + glm::vec3(0.1f, 0.8f, -0.6f), 1e-3f * size, 2 * size, 256, 256));
    const hsr_instance& placed = grid.instances[grid.instances.size() / 2];
    const hsr_camera skimming = skimming_camera(grid, glm::make_mat4(placed.transform));
    CHECK(counter(render("scanline-zbuffer", scene, skimming), "triangles-clipped") > 0);
    check_bands_equal_one_sweep(scene, skimming);
    const hsr::SceneData bunnies = hsr::make_instance_grid(model("bunny.obj"), {4, 4, 3, 0.05f, 25.0f});
    const hsr_camera small = orbit(bunnies, 10, 5, 1, false, 160, 120);
    CHECK(counter(render("scanline-zbuffer", bunnies.view(), small), "polygons-empty") > 0);
    check_bands_equal_one_sweep(bunnies.view(), small);
    check_bands_equal_one_sweep(bunnies.view(), orbit(bunnies, 0, 0, 1, false, 64, 1));
    // Layers behind one another: on a band's first row, polygons of instances set up there and
    // of instances set up higher up start on the same scanline, and their order shows in
    // pixels-written.
    const hsr::SceneData deep = hsr::make_instance_grid(model("monkey.obj"), {4, 3, 6, 0.05f, 30.0f});
    check_bands_equal_one_sweep(deep.view(), orbit(deep, 0, 0, 2.5f, false, 384, 288));
    check_bands_equal_one_sweep(deep.view(), orbit(deep, 20, 35, 1.5f, false, 320, 320));
}

TEST_CASE("scanline-zbuffer: counters and buffers reused between frames", "[scanline-zbuffer]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr_scene scene = bunny.view();
    hsr::HiddenSurfaceRemover scanline(plugin("scanline-zbuffer"), {});
    const hsr_camera camera = orbit(bunny, 10, 10, 1, false, 300, 240);
    const hsr::Frame first = render(scanline, scene, camera, true);
    CHECK(counter(first, "triangles-in") == bunny.triangle_count());
    // Every rasterized triangle went through the polygon table (one entry each: no clipping here).
    CHECK(counter(first, "polygons-in-table") >= counter(first, "triangles-rasterized"));
    CHECK(counter(first, "polygons-in-table") <= counter(first, "triangles-in"));
    CHECK(counter(first, "pixels-written") <= counter(first, "pixels-depth-tested"));
    CHECK(counter(first, "pixels-written") >= uint64_t(std::count_if(first.face.begin(), first.face.end(),
                                                                     [](uint32_t f) { return f != HSR_NO_FACE; })));
    uint64_t tests = 0;
    for (uint32_t n : first.depth_tests) tests += n;
    CHECK(tests == counter(first, "pixels-depth-tested"));
    CHECK(counter(first, "scanlines") <= 240);
    CHECK(counter(first, "active-edges-max") == 2 * counter(first, "active-polygons-max"));
    // Every (polygon, scanline) pair computes one span; a polygon is active on one scanline at least.
    CHECK(counter(first, "edge-pairs-processed") >= counter(first, "scanlines"));
    CHECK(counter(first, "edge-pairs-processed") >= counter(first, "active-polygons-max"));

    // Another size, another scene, then the first again: the same instance gives the same frames.
    (void)render(scanline, scene, orbit(bunny, 10, 10, 1, false, 640, 480), true);
    const hsr::SceneData& monkey = model("monkey.obj");
    const hsr_camera monkey_camera = orbit(monkey, -30, 15, 1, false, 200, 150);
    const hsr::Frame other = render(scanline, monkey.view(), monkey_camera, true);
    CHECK(compare(other, render("zbuffer", monkey.view(), monkey_camera, {}, true), kScanline).different == 0);
    const hsr::Frame again = render(scanline, scene, camera, true);
    CHECK(again.face == first.face);
    CHECK(again.depth == first.depth);
    CHECK(again.bary == first.bary);
    // Without per-pixel counts asked for, the same picture.
    const hsr::Frame uncounted = render(scanline, scene, camera, false);
    CHECK(uncounted.depth_tests.empty());
    CHECK(uncounted.face == first.face);
    CHECK(uncounted.depth == first.depth);
}

TEST_CASE("scanline-zbuffer: bad input comes back as hsr::Error with a clear message", "[scanline-zbuffer]") {
    const hsr::SceneData scene = triangles({{1, 1, 0}, {5, 1, 0}, {1, 5, 0}});
    const hsr_scene view = scene.view();
    const hsr_camera camera = hsr::make_pixel_camera(16, 12, -1.0f, 1.0f);
    hsr::HiddenSurfaceRemover scanline(plugin("scanline-zbuffer"), {});
    std::vector<float> depth(16 * 12, std::numeric_limits<float>::infinity()), bary(2 * 16 * 12, 0.0f);
    std::vector<uint32_t> face(16 * 12, HSR_NO_FACE);
    hsr_visibility_buffer wrong{};
    wrong.struct_size = sizeof wrong;
    wrong.width = 12;
    wrong.height = 16;
    wrong.depth = depth.data();
    wrong.face = face.data();
    wrong.bary = bary.data();
    CHECK_THROWS_WITH(scanline.render(view, camera, wrong, nullptr),
                      Catch::Contains("scanline-zbuffer: visibility buffer is 12x16 but the camera is 16x12"));
    CHECK_THROWS_AS(scanline.render(view, camera, wrong, nullptr), hsr::Error);
    // The instance stays usable after a failed call.
    hsr_visibility_buffer right = wrong;
    right.width = 16;
    right.height = 12;
    scanline.render(view, camera, right, nullptr);
    CHECK(face[size_t(12 - 1 - 2) * 16 + 2] == 0);  // world (2.5, 2.5) is inside the triangle
}

TEST_CASE("scanline-zbuffer: a deep scene of instances matches zbuffer", "[scanline-zbuffer][deep]") {
    // Monkeys on a grid, several layers deep and turned: the face and the instance must match.
    const hsr::SceneData grid = hsr::make_instance_grid(model("monkey.obj"), {4, 3, 6, 0.05f, 30.0f});
    REQUIRE(grid.instances.size() == 72);
    const hsr_scene scene = grid.view();
    check_same_picture(scene, orbit(grid, 0, 0, 2.5f, false, 384, 288));
    check_same_picture(scene, orbit(grid, 30, 20, 1, false, 320, 320), {{"cull-backfaces", "true"}});
    check_same_picture(scene, orbit(grid, -20, 10, 1.5f, true, 256, 256));
    // The eye among the instances, the near plane cutting some of them.
    const glm::vec3 lo = grid.bounds_min, hi = grid.bounds_max, middle = 0.5f * (lo + hi);
    const float size = glm::length(hi - lo);
    check_same_picture(scene, look(middle, middle - glm::vec3(0.2f, 0.1f, 1.0f), 1e-3f * size, 2 * size, 256, 256));
    const hsr::Frame frame = render("scanline-zbuffer", scene, orbit(grid, 0, 0, 2.5f, false, 384, 288), {}, true);
    CHECK(counter(frame, "triangles-in") == hsr::drawn_triangle_count(scene));
    CHECK(size_t(std::count(frame.instance.begin(), frame.instance.end(), 0u)) < frame.instance.size());
}

TEST_CASE("scanline-zbuffer: instances are set up lazily, scanline by scanline", "[scanline-zbuffer][deep]") {
    // A tall grid: its rows of instances start on different scanlines, so most are transformed and
    // set up only when the sweep reaches the top of their projected bounds. Some instances lie above
    // or below the image, and in the views from inside the grid the near plane cuts some of them
    // (their bounds reach w = 0: they start on the first scanline).
    const hsr::SceneData grid = hsr::make_instance_grid(model("monkey.obj"), {3, 8, 4, 0.3f, 35.0f});
    const hsr_scene scene = grid.view();
    check_same_picture(scene, orbit(grid, 0, 0, 1, false, 256, 384));
    check_same_picture(scene, orbit(grid, 15, 40, 2.5f, false, 300, 300));  // rows off the image
    check_same_picture(scene, orbit(grid, -25, -20, 3, true, 240, 320), {{"cull-backfaces", "true"}});
    const glm::vec3 lo = grid.bounds_min, hi = grid.bounds_max, middle = 0.5f * (lo + hi);
    const float size = glm::length(hi - lo);
    check_same_picture(scene, look(middle, middle + glm::vec3(0.1f, 0.8f, -0.6f), 1e-3f * size, 2 * size, 256, 256));
    check_same_picture(scene, look(middle, middle + glm::vec3(0.2f, -0.9f, 0.4f), 1e-3f * size, 2 * size, 200, 256));

    // Tiny triangles: most polygons cover at most 2 x 2 pixel centres (drawn from their spans) or
    // none (left out of the table).
    const hsr::SceneData bunnies = hsr::make_instance_grid(model("bunny.obj"), {4, 4, 3, 0.05f, 25.0f});
    const hsr_camera small = orbit(bunnies, 10, 5, 1, false, 160, 120);
    check_same_picture(bunnies.view(), small);
    const hsr::Frame tiny = render("scanline-zbuffer", bunnies.view(), small, {}, true);
    CHECK(counter(tiny, "polygons-empty") > 0);
    CHECK(counter(tiny, "polygons-in-table") + counter(tiny, "polygons-empty") >= counter(tiny, "triangles-rasterized"));

    // Records wait only between the top of their instance and their own first scanline, in blocks
    // reused as the sweep goes: fewer at once than polygons in the frame. The same instance gives
    // the same frame again, after another scene.
    hsr::HiddenSurfaceRemover scanline(plugin("scanline-zbuffer"), {});
    const hsr_camera camera = orbit(grid, 0, 0, 1, false, 256, 384);
    const hsr::Frame first = render(scanline, scene, camera, true);
    CHECK(counter(first, "polygon-records-max") < counter(first, "polygons-in-table"));
    CHECK(counter(first, "triangles-in") == hsr::drawn_triangle_count(scene));
    (void)render(scanline, bunnies.view(), small, true);
    const hsr::Frame again = render(scanline, scene, camera, true);
    CHECK(again.face == first.face);
    CHECK(again.instance == first.instance);
    CHECK(again.depth == first.depth);
    CHECK(again.bary == first.bary);
}
