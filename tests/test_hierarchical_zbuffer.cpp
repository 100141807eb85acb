// The hierarchical-zbuffer plugin (Greene, Kass & Miller 1993, the z-pyramid) and the shared z-pyramid
// it is built on (hsr/zpyramid.hpp).
//
// The pyramid is checked against brute force: the farthest depth over every cell and rectangle
// recomputed from the fine depths, on odd sizes, random depths and random rectangles, for every base
// level, with immediate and deferred updates; it may answer "not hidden" for a hidden rectangle
// (conservative) but never "hidden" for a visible one.
//
// The plugin, loaded through the real ABI, is checked against the plain zbuffer plugin: the same face
// and instance, bit for bit the same depth and barycentrics, at every pixel except exact depth ties
// (fewer than 0.1 % of the covered pixels), on real models, views from inside a model (near-plane
// clipping), odd image sizes, and deep instanced scenes, where it must also cull and test fewer pixels.
#include "hsr/abi.h"
#include "hsr/camera.hpp"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/zpyramid.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace surface_tests;

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// ---------------------------------------------------------------------------------------------- //
// ZPyramid against brute force

struct DepthImage {
    int32_t width, height;
    std::vector<float> depth;
    DepthImage(int32_t w, int32_t h) : width(w), height(h), depth(size_t(w) * h, kInfinity) {}
    float& at(int32_t x, int32_t y) { return depth[size_t(y) * width + x]; }
    // The farthest depth over [x0,x1] x [y0,y1] clamped to the image; -infinity when empty.
    float farthest(int32_t x0, int32_t y0, int32_t x1, int32_t y1) const {
        x0 = std::max(x0, 0);
        y0 = std::max(y0, 0);
        x1 = std::min(x1, width - 1);
        y1 = std::min(y1, height - 1);
        float m = -kInfinity;
        for (int32_t y = y0; y <= y1; ++y)
            for (int32_t x = x0; x <= x1; ++x) m = std::max(m, depth[size_t(y) * width + x]);
        return m;
    }
};

// Every stored cell equals the farthest fine depth of its block.
void check_levels(const hsr::raster::ZPyramid& pyramid, const DepthImage& image) {
    for (int k = pyramid.base_level(); k <= pyramid.top_level(); ++k) {
        REQUIRE(pyramid.level_width(k) == ((image.width + (1 << k) - 1) >> k));
        REQUIRE(pyramid.level_height(k) == ((image.height + (1 << k) - 1) >> k));
        for (int32_t cy = 0; cy < pyramid.level_height(k); ++cy)
            for (int32_t cx = 0; cx < pyramid.level_width(k); ++cx) {
                const float expected =
                    image.farthest(cx << k, cy << k, ((cx + 1) << k) - 1, ((cy + 1) << k) - 1);
                if (pyramid.cell(k, cx, cy) != expected) {
                    FAIL("level " << k << " cell " << cx << "," << cy << " holds " << pyramid.cell(k, cx, cy)
                                  << ", brute force " << expected);
                }
            }
    }
    CHECK(pyramid.level_width(pyramid.top_level()) == 1);
    CHECK(pyramid.level_height(pyramid.top_level()) == 1);
}

// Random rectangles (some reaching outside the image) and depths near those stored: is_hidden must
// never claim "hidden" where brute force finds a pixel that is not nearer; with an unlimited refine
// budget it must be exact. Returns how many hidden answers were checked.
int check_queries(hsr::raster::ZPyramid& pyramid, const DepthImage& image, std::mt19937& random, int count) {
    std::uniform_int_distribution<int32_t> x_pick(-3, image.width + 2), y_pick(-3, image.height + 2);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int hidden = 0;
    for (int q = 0; q < count; ++q) {
        int32_t x0 = x_pick(random), x1 = x_pick(random), y0 = y_pick(random), y1 = y_pick(random);
        if (x0 > x1) std::swap(x0, x1);
        if (y0 > y1) std::swap(y0, y1);
        if (q % 3 == 0) {  // many small rectangles too (the direct path)
            x1 = std::min(x1, x0 + 3);
            y1 = std::min(y1, y0 + 4);
        }
        const float truth = image.farthest(x0, y0, x1, y1);
        // Just above, exactly at, just below the truth, and random.
        float z;
        switch (q % 4) {
            case 0: z = std::isfinite(truth) ? std::nextafter(truth, kInfinity) : 0.5f; break;
            case 1: z = std::isfinite(truth) ? truth : 0.5f; break;
            case 2: z = std::isfinite(truth) ? std::nextafter(truth, -kInfinity) : 0.7f; break;
            default: z = unit(random); break;
        }
        const bool brute = truth < z;  // every pixel strictly nearer (empty rectangle: -inf < z)
        const bool answer = pyramid.is_hidden(x0, y0, x1, y1, z);
        if (answer && !brute)
            FAIL("is_hidden says hidden, brute force visible: [" << x0 << "," << x1 << "]x[" << y0 << "," << y1
                                                                 << "] z " << z << " farthest " << truth);
        hidden += answer ? 1 : 0;
        CHECK(pyramid.farthest(x0, y0, x1, y1) >= truth);
    }
    return hidden;
}

// Depths that only decrease (a nearer-wins z-buffer): random rectangles filled with random depths
// where nearer, then the pyramid told about them.
void draw_random_rectangles(DepthImage& image, hsr::raster::ZPyramid& pyramid, std::mt19937& random, int count,
                            bool deferred) {
    std::uniform_int_distribution<int32_t> x_pick(0, image.width - 1), y_pick(0, image.height - 1);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int r = 0; r < count; ++r) {
        int32_t x0 = x_pick(random), x1 = x_pick(random), y0 = y_pick(random), y1 = y_pick(random);
        if (x0 > x1) std::swap(x0, x1);
        if (y0 > y1) std::swap(y0, y1);
        if (r % 2 == 0) {
            x1 = std::min(x1, x0 + 5);
            y1 = std::min(y1, y0 + 5);
        }
        const float base = unit(random);
        for (int32_t y = y0; y <= y1; ++y)
            for (int32_t x = x0; x <= x1; ++x) {
                const float z = base + 0.1f * unit(random);
                if (z < image.at(x, y)) image.at(x, y) = z;
            }
        if (deferred)
            pyramid.mark_dirty(image.depth.data(), x0, y0, x1, y1);
        else
            pyramid.update(image.depth.data(), x0, y0, x1, y1);
    }
}

// ---------------------------------------------------------------------------------------------- //
// Plugins through the ABI

const Agreement kHierarchical{.plugin = "hierarchical-zbuffer", .label = "hierarchical"};

// Counters that account for triangles the z-pyramid spared drawing.
constexpr std::initializer_list<const char*> kCulled = {"triangles-culled-by-pyramid",
                                                        "triangles-in-skipped-instances"};

// The hierarchical z-buffer and the plain one agree everywhere but at ties; returns the frame.
hsr::Frame check_same_picture(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {},
                              const Settings& zbuffer_settings = {}) {
    Picture picture = check_against_zbuffer(kHierarchical, scene, camera, settings, zbuffer_settings);
    const hsr::Frame &reference = picture.reference, &frame = picture.frame;
    INFO(picture.comparison.first_difference);
    check_triangle_accounting(frame, kCulled);
    CHECK(counter(frame, "triangles-in") == counter(reference, "triangles-in"));
    CHECK(counter(frame, "pixels-depth-tested") <= counter(reference, "pixels-depth-tested"));
    return std::move(picture.frame);
}

}  // namespace

// ---------------------------------------------------------------------------------------------- //

TEST_CASE("ZPyramid: levels hold the farthest depth of their blocks, on odd sizes", "[zpyramid]") {
    std::mt19937 random(7);
    const std::pair<int32_t, int32_t> sizes[] = {{1, 1}, {1, 9}, {13, 1}, {5, 3}, {37, 29}, {64, 64}, {100, 7}, {129, 65}};
    for (const int base : {1, 2, 3, 4, 5}) {
        for (const bool deferred : {false, true}) {
            for (const auto& [w, h] : sizes) {
                INFO("base level " << base << ", " << w << "x" << h << (deferred ? ", deferred" : ", immediate"));
                hsr::raster::ZPyramid pyramid;
                pyramid.set_base_level(base);
                pyramid.reset(uint32_t(w), uint32_t(h));
                REQUIRE(pyramid.base_level() == base);
                DepthImage image(w, h);
                check_levels(pyramid, image);  // all +infinity
                draw_random_rectangles(image, pyramid, random, 40, deferred);
                pyramid.flush();
                check_levels(pyramid, image);
            }
        }
    }
}

TEST_CASE("ZPyramid: is_hidden is never wrong about a visible rectangle", "[zpyramid]") {
    std::mt19937 random(11);
    const std::pair<int32_t, int32_t> sizes[] = {{1, 1}, {3, 17}, {31, 31}, {33, 20}, {97, 61}, {256, 128}};
    int hidden_answers = 0;
    for (const int base : {1, 3, 5}) {
        for (const bool deferred : {false, true}) {
            for (const auto& [w, h] : sizes) {
                INFO("base level " << base << ", " << w << "x" << h << (deferred ? ", deferred" : ", immediate"));
                hsr::raster::ZPyramid pyramid;
                pyramid.set_base_level(base);
                pyramid.reset(uint32_t(w), uint32_t(h));
                DepthImage image(w, h);
                check_queries(pyramid, image, random, 50);  // before anything is drawn
                for (int round = 0; round < 4; ++round) {
                    // Queries between writes see cells that lag behind when deferred.
                    draw_random_rectangles(image, pyramid, random, 15, deferred);
                    hidden_answers += check_queries(pyramid, image, random, 150);
                }
                // Cover everything, so that large rectangles can be hidden too.
                std::uniform_real_distribution<float> unit(0.0f, 0.5f);
                for (float& d : image.depth) d = std::min(d, unit(random));
                if (deferred)
                    pyramid.mark_dirty(image.depth.data(), 0, 0, w - 1, h - 1);
                else
                    pyramid.update(image.depth.data(), 0, 0, w - 1, h - 1);
                hidden_answers += check_queries(pyramid, image, random, 150);
                CHECK(pyramid.is_hidden(-5, -5, w + 5, h + 5, 0.75f));
            }
        }
    }
    CHECK(hidden_answers > 1000);  // the test exercised both answers
}

TEST_CASE("ZPyramid: with an unlimited budget the answer is exact", "[zpyramid]") {
    std::mt19937 random(5);
    for (const auto& [w, h] : {std::pair<int32_t, int32_t>{45, 77}, {128, 128}}) {
        hsr::raster::ZPyramid pyramid;
        pyramid.set_refine_budget(1 << 30);
        pyramid.reset(uint32_t(w), uint32_t(h));
        DepthImage image(w, h);
        draw_random_rectangles(image, pyramid, random, 60, true);
        std::uniform_int_distribution<int32_t> x_pick(0, w - 1), y_pick(0, h - 1);
        for (int q = 0; q < 2000; ++q) {
            int32_t x0 = x_pick(random), x1 = x_pick(random), y0 = y_pick(random), y1 = y_pick(random);
            if (x0 > x1) std::swap(x0, x1);
            if (y0 > y1) std::swap(y0, y1);
            const float truth = image.farthest(x0, y0, x1, y1);
            for (const float z : {std::nextafter(truth, kInfinity), truth, 0.3f, 0.9f})
                REQUIRE(pyramid.is_hidden(x0, y0, x1, y1, z) == (truth < z));
        }
    }
}

TEST_CASE("ZPyramid: a hidden rectangle costs a few cells, sizes and resets", "[zpyramid]") {
    hsr::raster::ZPyramid pyramid;
    pyramid.reset(1000, 700);
    DepthImage image(1000, 700);
    CHECK_FALSE(pyramid.is_hidden(0, 0, 999, 699, 0.5f));  // nothing drawn
    CHECK(pyramid.is_hidden(10, 10, 5, 5, 0.5f));          // empty rectangle
    CHECK(pyramid.is_hidden(2000, 0, 2100, 10, 0.5f));     // outside the image
    std::fill(image.depth.begin(), image.depth.end(), 0.25f);
    pyramid.update(image.depth.data(), 0, 0, 999, 699);
    pyramid.reset_counters();
    CHECK(pyramid.is_hidden(0, 0, 999, 699, 0.5f));
    CHECK(pyramid.is_hidden(100, 200, 612, 455, 0.3f));
    CHECK(pyramid.cells_visited() <= 8);
    CHECK_FALSE(pyramid.is_hidden(0, 0, 999, 699, 0.25f));  // not strictly nearer
    // One pixel far: every rectangle over it is visible, found without reading the whole image.
    image.at(733, 401) = 0.9f;
    pyramid.update(image.depth.data(), 733, 401, 733, 401);
    pyramid.reset_counters();
    CHECK_FALSE(pyramid.is_hidden(0, 0, 999, 699, 0.5f));
    CHECK(pyramid.cells_visited() < 200);
    CHECK(pyramid.is_hidden(0, 0, 732, 699, 0.5f));
    CHECK(pyramid.farthest(0, 0, 999, 699) == 0.9f);
    // Smaller, then larger again: every level is +infinity after a reset.
    pyramid.reset(17, 3);
    CHECK(pyramid.width() == 17);
    CHECK_FALSE(pyramid.is_hidden(0, 0, 16, 2, 1.0f));
    pyramid.reset(1000, 700);
    CHECK_FALSE(pyramid.is_hidden(0, 0, 10, 10, 1.0f));
    CHECK(pyramid.farthest(0, 0, 999, 699) == kInfinity);
}

TEST_CASE("hierarchical-zbuffer: the bunny from several views matches zbuffer", "[hierarchical-zbuffer]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr_scene scene = bunny.view();
    const hsr::Frame front = check_same_picture(scene, orbit(bunny, 0, 0, 1, false, 512, 512));
    CHECK(counter(front, "triangles-culled-by-pyramid") > 0);
    check_same_picture(scene, orbit(bunny, 120, 35, 1.3f, false, 301, 187));  // odd size
    check_same_picture(scene, orbit(bunny, -60, -20, 1, true, 320, 320));
    check_same_picture(scene, orbit(bunny, 200, 10, 4, false, 256, 256));  // zoomed in: large triangles, tiles
    check_same_picture(scene, orbit(bunny, 30, 20, 1, false, 320, 320), {{"cull-backfaces", "true"}},
                       {{"cull-backfaces", "true"}});
    for (const char* tile : {"4", "64"})
        check_same_picture(scene, orbit(bunny, 200, 10, 4, false, 200, 256), {{"tile-size", tile}});
}

TEST_CASE("hierarchical-zbuffer: the monkey and the intersecting boxes match zbuffer", "[hierarchical-zbuffer]") {
    const hsr::SceneData& monkey = model("monkey.obj");
    check_same_picture(monkey.view(), orbit(monkey, 0, 0, 1, false, 400, 400));
    check_same_picture(monkey.view(), orbit(monkey, 160, -30, 2.5f, false, 333, 250));
    const hsr::SceneData& boxes = model("boxes.scene");
    check_same_picture(boxes.view(), orbit(boxes, 35, 25, 1, false, 384, 384));
    check_same_picture(boxes.view(), orbit(boxes, -110, 60, 1.5f, true, 257, 255));
}

TEST_CASE("hierarchical-zbuffer: views from inside a model (near-plane clipping)", "[hierarchical-zbuffer]") {
    for (const char* file : {"bunny.obj", "monkey.obj"}) {
        const hsr::SceneData& data = model(file);
        const hsr_scene scene = data.view();
        const glm::vec3 lo = data.bounds_min, hi = data.bounds_max, centre = 0.5f * (lo + hi);
        const float size = glm::length(hi - lo);
        INFO(file);
        check_same_picture(scene, look(centre, centre + glm::vec3(0, 0, 1), 1e-3f * size, 4 * size, 256, 256, 70));
        check_same_picture(scene, look(lo + 0.15f * (hi - lo), centre, 1e-3f * size, 4 * size, 256, 192, 90));
        check_same_picture(scene, look(hi - 0.1f * (hi - lo), lo, 1e-2f * size, 4 * size, 200, 256, 60));
    }
}

TEST_CASE("hierarchical-zbuffer: per-pixel depth-test counts", "[hierarchical-zbuffer]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr_camera camera = orbit(bunny, 20, 10, 1, false, 256, 256);
    const hsr::Frame reference = render("zbuffer", bunny.view(), camera, {}, true);
    const hsr::Frame frame = render("hierarchical-zbuffer", bunny.view(), camera, {}, true);
    REQUIRE(frame.depth_tests.size() == size_t(256) * 256);
    uint64_t sum = 0;
    bool never_more = true;
    for (size_t p = 0; p < frame.depth_tests.size(); ++p) {
        sum += frame.depth_tests[p];
        never_more = never_more && frame.depth_tests[p] <= reference.depth_tests[p];  // same order, fewer tests
    }
    CHECK(sum == counter(frame, "pixels-depth-tested"));
    CHECK(never_more);
    CHECK(sum < counter(reference, "pixels-depth-tested"));
    // Counting changes nothing in the picture.
    const hsr::Frame plain = render("hierarchical-zbuffer", bunny.view(), camera);
    CHECK(plain.face == frame.face);
    CHECK(plain.depth == frame.depth);
}

TEST_CASE("hierarchical-zbuffer: a wall of instances hides whole instances behind it", "[hierarchical-zbuffer][deep]") {
    // Cubes packed without gaps: the front layer is a solid wall, and the layers behind it are
    // culled whole, before their vertices are transformed.
    const hsr::SceneData wall = hsr::make_instance_grid(model("cube.obj"), {5, 4, 8, 0.0f, 0.0f});
    const hsr_scene scene = wall.view();
    const hsr_camera camera = orbit(wall, 0, 0, 2.5f, false, 256, 256);
    const hsr::Frame frame = check_same_picture(scene, camera);
    CHECK(counter(frame, "instances-culled") > 0);
    CHECK(counter(frame, "triangles-in-skipped-instances") > 0);
    // Drawn back to front (scene order reversed by camera from behind): the same picture.
    check_same_picture(scene, orbit(wall, 180, 0, 2.5f, false, 256, 256));
    check_same_picture(scene, camera, {{"front-to-back", "false"}, {"cull-instances", "false"}});
}

TEST_CASE("hierarchical-zbuffer: a deep scene is culled, and matches zbuffer", "[hierarchical-zbuffer][deep]") {
    const hsr::SceneData deep = hsr::make_instance_grid(model("monkey.obj"), {6, 4, 12, 0.05f, 25.0f});
    const hsr_scene scene = deep.view();
    const hsr_camera camera = orbit(deep, 0, 0, 3.2f, false, 320, 320);
    const Picture picture = check_against_zbuffer(kHierarchical, scene, camera);
    const hsr::Frame &reference = picture.reference, &frame = picture.frame;
    INFO(picture.comparison.first_difference);
    check_triangle_accounting(frame, kCulled);
    for (const auto& [name, value] : frame.counters) UNSCOPED_INFO(name << " " << value);
    CHECK(counter(frame, "triangles-culled-by-pyramid") > 2 * counter(frame, "triangles-rasterized"));
    CHECK(counter(frame, "pixels-depth-tested") * 3 < counter(reference, "pixels-depth-tested"));
    CHECK(counter(frame, "pixels-written") <= counter(reference, "pixels-written"));
    // In scene order (no sorting) the picture is the same.
    const hsr::Frame unsorted = render("hierarchical-zbuffer", scene, camera, {{"front-to-back", "false"}});
    CHECK(compare(unsorted, reference, kHierarchical).different == 0);
    // Small tiles: triangles of the front layer are drawn tile by tile, and tiles get culled.
    const hsr::Frame tiled = render("hierarchical-zbuffer", scene, camera, {{"tile-size", "4"}});
    CHECK(compare(tiled, reference, kHierarchical).different == 0);
    CHECK(counter(tiled, "tiles-culled") > 0);
}

TEST_CASE("ZPyramid: a window over part of the image answers for its pixels only", "[zpyramid]") {
    // A 97 x 61 depth image; pyramids over windows of it. Pixels outside the window are set nearer
    // than anything asked, so a pyramid that looked at them would call visible rectangles hidden.
    std::mt19937 random(5);
    struct Window {
        int32_t x, y, w, h;
    };
    for (const Window window : {Window{0, 0, 97, 61}, Window{32, 8, 40, 24}, Window{64, 32, 33, 29}, Window{5, 3, 1, 1}}) {
        for (const bool deferred : {false, true}) {
            INFO("window " << window.x << "," << window.y << " " << window.w << "x" << window.h
                           << (deferred ? ", deferred" : ", immediate"));
            DepthImage image(97, 61);
            for (int32_t y = 0; y < image.height; ++y)
                for (int32_t x = 0; x < image.width; ++x)
                    if (x < window.x || x >= window.x + window.w || y < window.y || y >= window.y + window.h)
                        image.at(x, y) = -1.0f;
            hsr::raster::ZPyramid pyramid;
            pyramid.set_refine_budget(1 << 30);
            pyramid.reset_window(window.x, window.y, uint32_t(window.w), uint32_t(window.h), uint32_t(image.width));
            std::uniform_int_distribution<int32_t> px(-5, image.width + 4), py(-5, image.height + 4);
            std::uniform_real_distribution<float> depth(0.0f, 1.0f);
            for (int round = 0; round < 60; ++round) {
                // Draw a rectangle inside the window at one depth, nearer-wins.
                int32_t x0 = px(random), x1 = px(random), y0 = py(random), y1 = py(random);
                if (x0 > x1) std::swap(x0, x1);
                if (y0 > y1) std::swap(y0, y1);
                x0 = std::max(x0, window.x);
                y0 = std::max(y0, window.y);
                x1 = std::min(x1, window.x + window.w - 1);
                y1 = std::min(y1, window.y + window.h - 1);
                const float z = depth(random);
                for (int32_t y = y0; y <= y1; ++y)
                    for (int32_t x = x0; x <= x1; ++x) image.at(x, y) = std::min(image.at(x, y), z);
                if (x0 <= x1 && y0 <= y1) {
                    if (deferred)
                        pyramid.mark_dirty(image.depth.data(), x0, y0, x1, y1);
                    else
                        pyramid.update(image.depth.data(), x0, y0, x1, y1);
                }
                // Ask about a random rectangle (image coordinates, may leave the window or the image).
                int32_t qx0 = px(random), qx1 = px(random), qy0 = py(random), qy1 = py(random);
                if (qx0 > qx1) std::swap(qx0, qx1);
                if (qy0 > qy1) std::swap(qy0, qy1);
                const float q = depth(random);
                const float truth = image.farthest(std::max(qx0, window.x), std::max(qy0, window.y),
                                                   std::min(qx1, window.x + window.w - 1),
                                                   std::min(qy1, window.y + window.h - 1));
                INFO("query " << qx0 << "," << qy0 << " - " << qx1 << "," << qy1 << " at " << q);
                CHECK(pyramid.is_hidden(qx0, qy0, qx1, qy1, q) == (truth < q));  // unlimited budget: exact
                CHECK(pyramid.farthest(qx0, qy0, qx1, qy1) >= truth);
            }
            CHECK(pyramid.width() == window.w);
            CHECK(pyramid.height() == window.h);
        }
    }
}

TEST_CASE("hierarchical-zbuffer: screen tiles give zbuffer's buffers, on one thread or two",
          "[hierarchical-zbuffer][tiles]") {
    const hsr::SceneData deep = hsr::make_instance_grid(model("monkey.obj"), {6, 4, 8, 0.05f, 25.0f});
    const hsr::SceneData& bunny = model("bunny.obj");
    const glm::vec3 centre = 0.5f * (bunny.bounds_min + bunny.bounds_max);
    const float size = glm::length(bunny.bounds_max - bunny.bounds_min);
    for (const int threads : {1, 2}) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        for (const char* tile : {"64", "40"}) {
            INFO(threads << " thread(s), screen-tile-size " << tile);
            const Settings settings{{"screen-tile-size", tile}};
            check_against_zbuffer(kHierarchical, deep.view(), orbit(deep, 0, 0, 3.2f, false, 300, 300), settings);
            check_against_zbuffer(kHierarchical, bunny.view(), orbit(bunny, 20, 10, 1, false, 256, 200), settings);
            check_against_zbuffer(kHierarchical, bunny.view(),
                                  look(centre, centre + glm::vec3(1, 0.3f, -0.5f), 1e-3f * size, 4 * size, 256, 192, 90),
                                  settings);
        }
    }
    // Each pixel sees its candidate writes in zbuffer's order, less some: never more depth tests.
    const hsr_camera camera = orbit(bunny, 20, 10, 1, false, 256, 256);
    const hsr::Frame reference = render("zbuffer", bunny.view(), camera, {}, true);
    const hsr::Frame tiled = render("hierarchical-zbuffer", bunny.view(), camera, {{"screen-tile-size", "64"}}, true);
    REQUIRE(tiled.depth_tests.size() == reference.depth_tests.size());
    bool never_more = true;
    for (size_t p = 0; p < tiled.depth_tests.size(); ++p)
        never_more = never_more && tiled.depth_tests[p] <= reference.depth_tests[p];
    CHECK(never_more);
    CHECK(counter(tiled, "triangles-in") == counter(reference, "triangles-in"));
    // The same counters on one thread as on two.
    auto frame_on = [&](int threads) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return render("hierarchical-zbuffer", deep.view(), orbit(deep, 0, 0, 3.2f, false, 300, 300),
                      {{"screen-tile-size", "64"}});
    };
    const hsr::Frame one = frame_on(1), two = frame_on(2);
    for (const auto& [name, value] : one.counters) CHECK(counter(two, name) == value);
}
