// The bsp plugin (BSP tree, Fuchs, Kedem & Naylor 1980) against the plain zbuffer plugin, both
// loaded through the real ABI, in both drawing orders: the same face (and instance) at every
// covered pixel but ties and a few pixel centres on the cuts of split polygons, depth and
// barycentrics within stated bounds; split and node counts of scenes counted by hand; the tree
// built once and reused; clip planes; steps; and the refusal above max-polygons.
#include "hsr/abi.h"
#include "hsr/camera.hpp"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <deque>
#include <tuple>
#include <utility>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

const Agreement kBsp{.plugin = "bsp", .label = "bsp", .bit_identical = false};
const char* const kOrders[] = {"back-to-front", "front-to-back"};

// How a BSP frame may differ from the z-buffer's. A node polygon is drawn as its whole triangle
// (the z-buffer's setup and coverage) at the pixel centres its cuts keep, so every covered pixel
// has the same surfaces to choose from, with the same depth and barycentrics bit for bit where the
// triangle goes to clip space as the z-buffer takes it (no instances: view_projection * p; with
// instances the z-buffer multiplies by clip_from_object, the BSP by view_projection after the
// transform: the last bits differ). The BSP orders surfaces by the exact geometry, the z-buffer
// by the depths at the pixel centre; they can disagree only where a pixel centre lies within
// snapping distance (1/256 pixel, the subpixel grid) of a triangle's edge: the rasterizer covers
// it with the snapped triangle while the true triangle misses it, and the depth there is
// extrapolated across the edge. Every such difference is checked to be one of those.
constexpr double kWorstDepthUlps = 8;   // of the float depth, with instances
constexpr double kWorstBary = 1e-5;     // absolute, with instances
constexpr double kSnapDistance = 1.0 / 256.0;  // pixels
constexpr double kShareOnEdges = 2e-4;  // of the covered pixels

struct Totals {
    uint64_t covered = 0, ties = 0, on_edges = 0;
    double worst_depth_ulps = 0, worst_bary = 0;
};

Totals& totals() {
    static Totals t;
    return t;
}

// The distance in pixels from the centre of pixel (x, y) to the nearest edge of triangle `face`
// (placed as `instance`) projected without snapping; infinity when a corner is behind the eye.
double distance_to_edge(const hsr_scene& scene, const hsr_camera& camera, uint32_t face, uint32_t instance, int x,
                        int y) {
    glm::dmat4 view_projection, world_from_object(1.0);
    for (int c = 0; c < 16; ++c) view_projection[c / 4][c % 4] = camera.view_projection[c];
    if (scene.instance_count > 0)
        for (int c = 0; c < 16; ++c) world_from_object[c / 4][c % 4] = scene.instances[instance].transform[c];
    glm::dvec2 w[3];
    for (int k = 0; k < 3; ++k) {
        const float* p = scene.positions + 3 * size_t(scene.indices[3 * size_t(face) + k]);
        const glm::dvec4 clip = view_projection * (world_from_object * glm::dvec4(p[0], p[1], p[2], 1.0));
        if (!(clip.w > 0.0)) return std::numeric_limits<double>::infinity();
        w[k] = {(clip.x / clip.w + 1.0) * 0.5 * camera.width, (1.0 - clip.y / clip.w) * 0.5 * camera.height};
    }
    const glm::dvec2 centre(x + 0.5, y + 0.5);
    double nearest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const glm::dvec2 a = w[k], b = w[(k + 1) % 3];
        const double t = std::clamp(glm::dot(centre - a, b - a) / std::max(glm::dot(b - a, b - a), 1e-300), 0.0, 1.0);
        nearest = std::min(nearest, glm::length(centre - (a + t * (b - a))));
    }
    return nearest;
}

// The pixels where `frame` shows another surface than the z-buffer's `reference` (not a tie), each
// required to lie within snapping distance of an edge of one of the two triangles. Returns how many.
uint64_t check_differences_on_edges(const hsr_scene& scene, const hsr_camera& camera, const hsr::Frame& frame,
                                    const hsr::Frame& reference) {
    uint64_t on_edges = 0;
    for (size_t p = 0; p < reference.face.size(); ++p) {
        const uint32_t face = frame.face[p], expected = reference.face[p];
        const uint32_t instance = frame.instance.empty() ? 0 : frame.instance[p];
        const uint32_t expected_instance = reference.instance.empty() ? 0 : reference.instance[p];
        if (face == expected && instance == expected_instance) continue;
        if (expected == HSR_NO_FACE) continue;  // compare() holds these to "nothing drawn"
        const float a = frame.depth[p], b = reference.depth[p];
        if (face != HSR_NO_FACE && std::abs(a - b) <= 2 * std::numeric_limits<float>::epsilon() * std::max(a, b))
            continue;  // a tie
        const int x = int(p % reference.width), y = int(p / reference.width);
        const double d = std::min(distance_to_edge(scene, camera, expected, expected_instance, x, y),
                                  face == HSR_NO_FACE ? std::numeric_limits<double>::infinity()
                                                      : distance_to_edge(scene, camera, face, instance, x, y));
        INFO("pixel " << x << "," << y << ": bsp face " << face << ", zbuffer face " << expected << ", " << d
                      << " pixels from an edge");
        CHECK(d <= kSnapDistance);
        ++on_edges;
    }
    return on_edges;
}

// A bsp instance per setting, kept so that its tree is reused while the scene stays the same.
hsr::HiddenSurfaceRemover& bsp_with(const Settings& settings) {
    static std::deque<std::pair<std::string, hsr::HiddenSurfaceRemover>> removers;
    std::string key;
    for (const hsr::Setting& s : settings) key += s.first + "=" + s.second + ",";
    for (auto& [k, remover] : removers)
        if (k == key) return remover;
    return removers.emplace_back(std::piecewise_construct, std::forward_as_tuple(key),
                                 std::forward_as_tuple(plugin("bsp"), settings))
        .second;
}

// Both orders against the z-buffer, and against each other. Returns the back-to-front frame.
hsr::Frame check_agrees(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {},
                        const Settings& zbuffer_settings = {}) {
    const hsr::Frame reference = render("zbuffer", scene, camera, zbuffer_settings);
    hsr::Frame frames[2];
    for (int o = 0; o < 2; ++o) {
        Settings s = settings;
        s.push_back({"order", kOrders[o]});
        frames[o] = render(bsp_with(s), scene, camera);
        const Comparison c = compare(frames[o], reference, kBsp);
        INFO(kOrders[o] << " " << camera.width << "x" << camera.height << ": " << c.first_difference << "; "
                        << c.different << " different, " << c.ties << " ties of " << c.covered);
        const uint64_t on_edges = check_differences_on_edges(scene, camera, frames[o], reference);
        CHECK(c.covered > 0);
        CHECK(c.different == on_edges);
        CHECK(double(on_edges) <= kShareOnEdges * double(c.covered) + 1);
        CHECK(double(c.ties) < 0.001 * double(c.covered));
        if (scene.instance_count == 0) {
            CHECK(c.worst_depth_ulps == 0);
            CHECK(c.worst_bary == 0);
        }
        CHECK(c.worst_depth_ulps <= kWorstDepthUlps);
        CHECK(c.worst_bary <= kWorstBary);
        Totals& t = totals();
        t.covered += c.covered;
        t.ties += c.ties;
        t.on_edges += on_edges;
        t.worst_depth_ulps = std::max(t.worst_depth_ulps, c.worst_depth_ulps);
        t.worst_bary = std::max(t.worst_bary, c.worst_bary);
    }
    // The two orders draw the same pieces at the same pixel centres, each centre by one piece of
    // a triangle: they give the same picture.
    CHECK(frames[0].face == frames[1].face);
    CHECK(frames[0].instance == frames[1].instance);
    CHECK(frames[0].depth == frames[1].depth);
    CHECK(frames[0].bary == frames[1].bary);
    return frames[0];
}

// A scene of raw world-space triangles (counter-clockwise from the front).
hsr::SceneData triangles(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices) {
    hsr::SceneBuilder builder;
    builder.add_triangles(positions, indices);
    return builder.build();
}

}  // namespace

TEST_CASE("bsp: the cube, the monkey and the bunny from several cameras match zbuffer", "[bsp]") {
    test_models::require_fetched();
    for (const char* file : {"cube.obj", "monkey.obj", "bunny.obj"}) {
        INFO(file);
        const hsr::SceneData& data = model(file);
        const hsr_scene scene = data.view();
        check_agrees(scene, orbit(data, 0, 0, 1, false, 160));
        check_agrees(scene, orbit(data, 120, 35, 1.3f, false, 144));
        check_agrees(scene, orbit(data, -60, -20, 1, true, 160));  // orthographic
        check_agrees(scene, orbit(data, 200, 10, 4, false, 128));  // zoomed in: much off screen
    }
    const Totals& t = totals();
    std::printf("bsp vs zbuffer: %llu covered pixels, %llu ties, %llu other surface on an edge\n",
                (unsigned long long)t.covered, (unsigned long long)t.ties, (unsigned long long)t.on_edges);
}

TEST_CASE("bsp: the intersecting boxes are split, and match zbuffer", "[bsp]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_scene scene = boxes.view();
    const hsr::Frame frame = check_agrees(scene, orbit(boxes, 35, 25, 1, false, 200));
    CHECK(counter(frame, "polygons-split") > 0);
    CHECK(counter(frame, "polygons-after-splits") == counter(frame, "polygons-in") + counter(frame, "polygons-split"));
    check_agrees(scene, orbit(boxes, -100, -30, 1.2f, true, 200));
    check_agrees(scene, orbit(boxes, 10, 80, 1, false, 160), {{"split", "first"}});
    check_agrees(scene, orbit(boxes, 35, 25, 1, false, 160), {{"cull-backfaces", "true"}},
                 {{"cull-backfaces", "true"}});
}

TEST_CASE("bsp: the eye inside the scene's bounds", "[bsp]") {
    test_models::require_fetched();
    for (const char* file : {"monkey.obj", "bunny.obj", "boxes.scene"}) {
        INFO(file);
        const hsr::SceneData& data = model(file);
        const glm::vec3 lo = data.bounds_min, hi = data.bounds_max, middle = 0.5f * (lo + hi);
        const float size = glm::length(hi - lo);
        check_agrees(data.view(),
                     look(middle, middle + glm::vec3(0.3f, -0.2f, -1.0f), 1e-3f * size, 2 * size, 160, 128));
        check_agrees(data.view(), look(glm::mix(lo, hi, 0.8f), lo, 1e-2f * size, 2 * size, 128, 128, 100.0f));
    }
}

TEST_CASE("bsp: two crossing quads, split counted by hand", "[bsp]") {
    // Quad A in the plane z = 0, quad B in the plane x = 0, crossing along the y axis. With the
    // first polygon's plane (A's) at the root, A's other triangle lies in it, and both triangles of
    // B cross it: 2 splits, 4 + 2 polygons, the root and one node on each side (each holding the
    // two pieces of B on its side, all in the plane x = 0): 3 nodes, depth 2.
    const hsr::SceneData quads = triangles({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0},  // A
                                            {0, -1, -1}, {0, 1, -1}, {0, 1, 1}, {0, -1, 1}},  // B
                                           {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7});
    const hsr_camera camera = look({2.0f, 1.5f, 3.0f}, {0, 0, 0}, 0.1f, 20.0f, 128, 128);
    for (const char* split : {"first", "fewest-splits"}) {
        INFO(split);
        const hsr::Frame frame = check_agrees(quads.view(), camera, {{"split", split}});
        CHECK(counter(frame, "polygons-in") == 4);
        CHECK(counter(frame, "polygons-split") == 2);
        CHECK(counter(frame, "polygons-after-splits") == 6);
        CHECK(counter(frame, "bsp-nodes") == 3);
        CHECK(counter(frame, "tree-depth") == 2);
        CHECK(counter(frame, "nodes-visited") == 3);
    }
}

TEST_CASE("bsp: fewest splits cuts less than the first polygon where it matters", "[bsp]") {
    // A wall in the plane x = 0 (two triangles, listed first) below six small triangles in the
    // planes z = 1 .. 6, each reaching across x = 0. The wall's plane cuts all six: 6 splits by
    // hand. None of the small triangles' planes reaches the wall (z <= 0.5) or another small
    // triangle, so a tree with them above the wall needs no cut, and with 8 samples (all eight
    // polygons) fewest-splits finds it.
    std::vector<glm::vec3> positions = {{0, -1, -1}, {0, 1, -1}, {0, 1, 0.5f}, {0, -1, 0.5f}};
    std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
    for (int k = 1; k <= 6; ++k) {
        const uint32_t first = uint32_t(positions.size());
        const float z = float(k), y = -1.0f + 0.3f * float(k);
        positions.insert(positions.end(), {{-1, y, z}, {1, y, z}, {0, y + 0.5f, z}});
        indices.insert(indices.end(), {first, first + 1, first + 2});
    }
    const hsr::SceneData scene = triangles(positions, indices);
    const hsr_camera camera = look({3.0f, 0.5f, 9.0f}, {0, 0, 2}, 0.1f, 40.0f, 128, 128);
    const hsr::Frame first = check_agrees(scene.view(), camera, {{"split", "first"}});
    const hsr::Frame fewest = check_agrees(scene.view(), camera, {{"split", "fewest-splits"}});
    CHECK(counter(first, "polygons-split") == 6);
    CHECK(counter(first, "polygons-after-splits") == 14);
    CHECK(counter(fewest, "polygons-split") == 0);
    CHECK(counter(fewest, "polygons-after-splits") == 8 + counter(fewest, "polygons-split"));
    // On the bunny, too.
    test_models::require_fetched();
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr_camera bunny_camera = orbit(bunny, 0, 0, 1, false, 64);
    CHECK(counter(render("bsp", bunny.view(), bunny_camera, {{"split", "fewest-splits"}}), "polygons-split") <
          counter(render("bsp", bunny.view(), bunny_camera, {{"split", "first"}}), "polygons-split"));
}

TEST_CASE("bsp: clip planes agree with zbuffer given the same planes", "[bsp]") {
    test_models::require_fetched();
    for (const char* file : {"monkey.obj", "bunny.obj", "boxes.scene"}) {
        INFO(file);
        const hsr::SceneData& data = model(file);
        const glm::vec3 middle = 0.5f * (data.bounds_min + data.bounds_max);
        hsr_camera camera = orbit(data, 30, 20, 1, false, 160);
        // One plane through the middle, keeping x >= middle.x; then also a slanted one.
        camera.clip_plane_count = 1;
        const float planes[2][4] = {{1, 0, 0, -middle.x}, {0.3f, 0.6f, -0.74f, 0}};
        std::memcpy(camera.clip_planes[0], planes[0], sizeof planes[0]);
        check_agrees(data.view(), camera);
        camera.clip_plane_count = 2;
        std::memcpy(camera.clip_planes[1], planes[1], sizeof planes[1]);
        camera.clip_planes[1][3] = -(0.3f * middle.x + 0.6f * middle.y - 0.74f * middle.z);
        check_agrees(data.view(), camera);
        check_agrees(data.view(), orbit(data, -150, -10, 1, true, 160));
    }
}

TEST_CASE("bsp: counters add up, and front to back writes each pixel once", "[bsp]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_camera camera = orbit(boxes, 35, 25, 1, false, 200);
    const hsr::Frame zbuffer = render("zbuffer", boxes.view(), camera);
    uint64_t covered_by_zbuffer = 0;
    for (uint32_t f : zbuffer.face) covered_by_zbuffer += f != HSR_NO_FACE;
    const hsr::Frame back = render("bsp", boxes.view(), camera, {{"order", "back-to-front"}}, true);
    const hsr::Frame front = render("bsp", boxes.view(), camera, {{"order", "front-to-back"}}, true);
    uint64_t paints = 0, tests = 0, covered = 0;
    for (size_t p = 0; p < back.depth_tests.size(); ++p) {
        paints += back.depth_tests[p];
        tests += front.depth_tests[p];
        covered += front.face[p] != HSR_NO_FACE;
        CHECK(back.depth_tests[p] == front.depth_tests[p]);  // the same pieces cover the same centres
    }
    CHECK(paints == counter(back, "pixels-painted"));
    CHECK(tests == counter(front, "pixels-painted") + counter(front, "pixels-skipped-covered"));
    CHECK(counter(front, "pixels-painted") == covered);
    CHECK(covered == covered_by_zbuffer);
    CHECK(paints == counter(zbuffer, "pixels-depth-tested"));
    CHECK(counter(front, "polygons-drawn") == counter(back, "polygons-drawn"));
    CHECK(counter(front, "nodes-visited") == counter(front, "bsp-nodes"));
    // Every node holds at least one polygon and every polygon is in one node.
    CHECK(counter(front, "bsp-nodes") <= counter(front, "polygons-after-splits"));
}

TEST_CASE("bsp: built once, reused, rebuilt for another scene", "[bsp]") {
    test_models::require_fetched();
    const hsr::SceneData& cube = model("cube.obj");
    const hsr::SceneData& monkey = model("monkey.obj");
    hsr::HiddenSurfaceRemover bsp(plugin("bsp"), {});
    const hsr_camera camera = orbit(monkey, 10, 10, 1, false, 160);
    const hsr::Frame first = render(bsp, monkey.view(), camera);
    const hsr::Frame second = render(bsp, monkey.view(), camera);
    CHECK(counter(first, "build-time-us") > 0);
    CHECK(counter(second, "build-time-us") == 0);
    CHECK(counter(second, "bsp-nodes") == counter(first, "bsp-nodes"));
    CHECK(second.face == first.face);
    CHECK(second.depth == first.depth);
    // Another camera: the same tree.
    const hsr_camera behind = orbit(monkey, 190, -20, 1, true, 160);
    const hsr::Frame third = render(bsp, monkey.view(), behind);
    CHECK(counter(third, "build-time-us") == 0);
    CHECK(check_differences_on_edges(monkey.view(), behind, third, render("zbuffer", monkey.view(), behind)) <= 4);

    // Another scene through the same instance: rebuilt, and right.
    const hsr_camera cube_camera = orbit(cube, -30, 15, 1, false, 160);
    const hsr::Frame other = render(bsp, cube.view(), cube_camera);
    CHECK(counter(other, "build-time-us") > 0);
    CHECK(counter(other, "polygons-in") == 12);
    CHECK(compare(other, render("zbuffer", cube.view(), cube_camera), kBsp).different == 0);
    // A copy of the monkey at another address is recognised as another scene, too.
    const hsr::SceneData copy = monkey;
    const hsr::Frame again = render(bsp, copy.view(), camera);
    CHECK(counter(again, "build-time-us") > 0);
    CHECK(counter(again, "bsp-nodes") == counter(first, "bsp-nodes"));
    CHECK(again.face == first.face);
}

TEST_CASE("bsp: instances, including one moved between frames", "[bsp]") {
    test_models::require_fetched();
    hsr::SceneData grid = hsr::make_instance_grid(model("monkey.obj"), {3, 2, 2, 0.0f, 40.0f});
    const hsr_camera camera = orbit(grid, 25, 15, 1, false, 192);
    const hsr::Frame frame = check_agrees(grid.view(), camera);
    CHECK(counter(frame, "polygons-in") == 12 * 3936);
    check_agrees(grid.view(), orbit(grid, 0, 0, 1, true, 160));
    const glm::vec3 lo = grid.bounds_min, hi = grid.bounds_max, middle = 0.5f * (lo + hi);
    const float size = glm::length(hi - lo);
    check_agrees(grid.view(), look(middle, middle - glm::vec3(0.2f, 0.1f, 1.0f), 1e-3f * size, 2 * size, 160, 160));

    hsr::HiddenSurfaceRemover bsp(plugin("bsp"), {{"order", "front-to-back"}});
    (void)render(bsp, grid.view(), camera);
    CHECK(counter(render(bsp, grid.view(), camera), "build-time-us") == 0);
    // Move one instance in place (same arrays, same counts): the plugin must notice.
    hsr_instance& moved = grid.instances.at(5);
    moved.transform[12] += 0.7f;
    moved.transform[13] += 0.3f;
    for (int a = 0; a < 2; ++a) {
        moved.bounds_min[a] += a == 0 ? 0.7f : 0.3f;
        moved.bounds_max[a] += a == 0 ? 0.7f : 0.3f;
    }
    const hsr::Frame after = render(bsp, grid.view(), camera);
    CHECK(counter(after, "build-time-us") > 0);
    const Comparison c = compare(after, render("zbuffer", grid.view(), camera), kBsp);
    INFO(c.first_difference);
    CHECK(double(c.different) == 0);
}

TEST_CASE("bsp: steps to the end equal render, a stop leaves a prefix of the drawing", "[bsp]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_camera camera = orbit(boxes, 35, 25, 1, false, 96);
    for (const char* order : kOrders) {
        INFO(order);
        const Settings settings = {{"order", order}};
        const hsr::Frame plain = render("bsp", boxes.view(), camera, settings, true);
        auto run = [&](uint64_t stop_after) {
            hsr::HiddenSurfaceRemover remover(plugin("bsp"), settings);
            REQUIRE(remover.has_steps());
            hsr::Frame frame;
            hsr::resolve_visibility_steps(boxes.view(), camera, remover, frame, stop_after, true);
            REQUIRE(frame.steps.has_value());
            return frame;
        };
        const hsr::Frame all = run(0);
        CHECK(all.depth == plain.depth);
        CHECK(all.face == plain.face);
        CHECK(all.bary == plain.bary);
        CHECK(all.instance == plain.instance);
        CHECK(all.depth_tests == plain.depth_tests);
        const uint64_t steps = all.steps->taken;
        // One step for the tree, then one per node visited and per node polygon.
        CHECK(steps == 1 + counter(plain, "nodes-visited") + counter(plain, "polygons-after-splits"));
        const bool front_to_back = std::string(order) == "front-to-back";
        hsr::Frame previous = run(1);
        for (uint64_t k = 2; k <= steps; k += std::max<uint64_t>(1, steps / 12)) {
            INFO("step " << k);
            const hsr::Frame now = run(k);
            uint64_t changed = 0;
            for (size_t p = 0; p < now.face.size(); ++p) {
                if (now.face[p] == previous.face[p] && now.depth[p] == previous.depth[p]) continue;
                ++changed;
                // Front to back, a covered pixel is never written again.
                if (front_to_back) CHECK(previous.face[p] == HSR_NO_FACE);
            }
            CHECK(changed <= counter(now, "pixels-painted") - counter(previous, "pixels-painted"));
            if (front_to_back)
                for (size_t p = 0; p < now.face.size(); ++p)
                    if (now.face[p] != HSR_NO_FACE) CHECK(plain.face[p] == now.face[p]);
            previous = now;
        }
    }
}

TEST_CASE("bsp: a scene needing more polygons than max-polygons is refused in one line", "[bsp]") {
    test_models::require_fetched();
    const hsr::SceneData& monkey = model("monkey.obj");
    const hsr_camera camera = orbit(monkey, 0, 0, 1, false, 64);
    // The monkey needs 3936 + (several thousand splits): refused while splitting.
    hsr::HiddenSurfaceRemover bsp(plugin("bsp"), {{"max-polygons", "5000"}});
    try {
        (void)render(bsp, monkey.view(), camera);
        FAIL("not refused");
    } catch (const std::exception& e) {
        const std::string message = e.what();
        INFO(message);
        CHECK(message.find("bsp: more than max-polygons=5000 polygons after splits") != std::string::npos);
        CHECK(message.find('\n') == std::string::npos);
    }
    // The same instance still takes a scene within the limit.
    const hsr::SceneData& cube = model("cube.obj");
    const hsr_camera cube_camera = orbit(cube, 20, 20, 1, false, 64);
    const hsr::Frame cube_frame = render(bsp, cube.view(), cube_camera);
    CHECK(compare(cube_frame, render("zbuffer", cube.view(), cube_camera), kBsp).different == 0);

    // models/deep-monkeys.scene: 480 monkeys, 1.9 million triangles before any split, over the
    // default limit: refused before the tree is built.
    const hsr::SceneData& deep = model("deep-monkeys.scene");
    CHECK_THROWS_WITH(render("bsp", deep.view(), orbit(deep, 0, 0, 3.2f, false, 64)),
                      Catch::Contains("bsp: more than max-polygons=1000000 polygons after splits "
                                      "(1889280 triangles before any split); raise max-polygons"));
}
