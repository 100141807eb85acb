// The warnock plugin (area subdivision, Warnock 1969) against independent answers: the plain
// zbuffer plugin's frame, byte for byte, on real models and scenes from several cameras (with and
// without clip planes); a hand-made scene whose windows were counted by hand, case by case; and its
// steps, whose run to the end is the plain render and whose every prefix is the render's picture
// inside the windows decided so far and the cleared buffer elsewhere.
#include "hsr/abi.h"
#include "hsr/image.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

const Agreement kWarnock{.plugin = "warnock", .label = "warnock"};

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Warnock's frame is the zbuffer's byte for byte: both keep, at each pixel centre, the first
// triangle in scene order of the nearest float depth, from the same setups. So no pixel is a tie.
void check_same_frame(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {},
                      const Settings& zbuffer_settings = {}) {
    const Picture picture = check_against_zbuffer(kWarnock, scene, camera, settings, zbuffer_settings);
    CHECK(picture.comparison.ties == 0);
    CHECK(same_bytes(picture.frame.depth, picture.reference.depth));
    CHECK(same_bytes(picture.frame.face, picture.reference.face));
    CHECK(same_bytes(picture.frame.bary, picture.reference.bary));
    CHECK(same_bytes(picture.frame.instance, picture.reference.instance));
    // Every covered pixel is written once: by a drawn or filled window, or a one-pixel window.
    CHECK(counter(picture.frame, "pixels-written") == picture.comparison.covered);
    check_triangle_accounting(picture.frame);
}

// An 8 x 8 orthographic view down -z in which world (x, y) is window (x, y): pixel (i, j) has its
// centre at (i + 0.5, j + 0.5).
hsr_camera pixel_camera() {
    return make_camera(8, 8, HSR_PROJECTION_ORTHOGRAPHIC, glm::ortho(0.0f, 8.0f, 8.0f, 0.0f, 0.5f, 20.0f),
                       {0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 0.5f, 20.0f);
}

// Three triangles on the 8 x 8 view, in scene order:
//  0 "back", farthest: every pixel of rows 0..3 (its lower edge on y = 4);
//  1 "front", nearer: every pixel of columns 0..3 (its right edge on x = 4);
//  2 "small", nearest: pixels (6, 2), (7, 2), (6, 3) (corners (6.2, 2.2), (8, 2.2), (6.2, 4)).
hsr::SceneData three_triangles() {
    hsr::SceneBuilder builder;
    const glm::vec3 back[] = {{-20, 4, 0}, {30, 4, 0}, {5, -30, 0}};
    const glm::vec3 front[] = {{4, -20, 2}, {4, 30, 2}, {-30, 5, 2}};
    const glm::vec3 small[] = {{6.2f, 2.2f, 4}, {8, 2.2f, 4}, {6.2f, 4, 4}};
    builder.add_polygon(back, {0.5f, 0.5f, 0.5f}, "back");
    builder.add_polygon(front, {0.8f, 0.2f, 0.2f}, "front");
    builder.add_polygon(small, {0.2f, 0.8f, 0.2f}, "small");
    return builder.build();
}

}  // namespace

TEST_CASE("warnock: cube, monkey and boxes.scene match zbuffer byte for byte", "[warnock]") {
    const hsr::SceneData& cube = model("cube.obj");
    check_same_frame(cube.view(), orbit(cube, 30, 20, 1, false, 128));
    check_same_frame(cube.view(), orbit(cube, -45, -35, 1.5f, true, 96, 128));

    test_models::require_fetched();
    const hsr::SceneData& monkey = model("monkey.obj");
    check_same_frame(monkey.view(), orbit(monkey, 0, 0, 1, false, 256));
    check_same_frame(monkey.view(), orbit(monkey, 145, -30, 1.5f, true, 200, 256));
    check_same_frame(monkey.view(), orbit(monkey, 60, 20, 4, false, 192));  // zoomed in: much off screen
    check_same_frame(monkey.view(), orbit(monkey, 30, 20, 1, false, 160), {{"cull-backfaces", "true"}},
                     {{"cull-backfaces", "true"}});

    const hsr::SceneData& boxes = model("boxes.scene");
    check_same_frame(boxes.view(), orbit(boxes, 35, 25, 1, false, 256));
    check_same_frame(boxes.view(), orbit(boxes, -80, 60, 2.5f, false, 200));
    check_same_frame(boxes.view(), orbit(boxes, 35, 25, 1, true, 256, 160));
    const glm::vec3 centre = 0.5f * (boxes.bounds_min + boxes.bounds_max);
    check_same_frame(boxes.view(), look(centre + glm::vec3(0.1f, 0.05f, 0.02f), centre + glm::vec3(1, 0.2f, 0.4f),
                                        1e-3f, 20.0f, 192, 192));
}

TEST_CASE("warnock: the bunny from several views matches zbuffer byte for byte", "[warnock]") {
    test_models::require_fetched();
    const hsr::SceneData& bunny = model("bunny.obj");
    check_same_frame(bunny.view(), orbit(bunny, 0, 0, 1, false, 256));
    check_same_frame(bunny.view(), orbit(bunny, 120, 35, 1.3f, false, 256, 200));
    check_same_frame(bunny.view(), orbit(bunny, -60, -20, 1, true, 256));
    check_same_frame(bunny.view(), orbit(bunny, 200, 10, 4, false, 192));
    // The eye inside the bunny: triangles cut by the near plane.
    const glm::vec3 centre = 0.5f * (bunny.bounds_min + bunny.bounds_max);
    const float size = glm::length(bunny.bounds_max - bunny.bounds_min);
    check_same_frame(bunny.view(), look(centre, centre + glm::vec3(1, 0.3f, -0.5f), 1e-3f * size, 4 * size, 192, 192));
}

TEST_CASE("warnock: clip planes cut the monkey and the bunny as they cut zbuffer's", "[warnock]") {
    test_models::require_fetched();
    for (const char* file : {"monkey.obj", "bunny.obj"}) {
        INFO(file);
        const hsr::SceneData& data = model(file);
        const glm::vec3 centre = 0.5f * (data.bounds_min + data.bounds_max);
        hsr_camera camera = orbit(data, 30, 15, 1, false, 192);
        const hsr::Frame whole = render("warnock", data.view(), camera);
        // Keep x <= centre.x: a section through the middle.
        camera.clip_plane_count = 1;
        const float one[4] = {-1, 0, 0, centre.x};
        std::copy(one, one + 4, camera.clip_planes[0]);
        check_same_frame(data.view(), camera);
        const hsr::Frame cut = render("warnock", data.view(), camera);
        CHECK_FALSE(same_bytes(cut.face, whole.face));  // the plane took something away
        // And a slanted second plane, seen orthographically.
        camera = orbit(data, -40, 25, 1.2f, true, 160);
        camera.clip_plane_count = 2;
        std::copy(one, one + 4, camera.clip_planes[0]);
        const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 1, 0.2f));
        const float two[4] = {n.x, n.y, n.z, -glm::dot(n, centre)};
        std::copy(two, two + 4, camera.clip_planes[1]);
        check_same_frame(data.view(), camera);
    }
}

TEST_CASE("warnock: three triangles, windows counted by hand", "[warnock]") {
    const hsr::SceneData data = three_triangles();
    const hsr_camera camera = pixel_camera();
    const hsr::Frame frame = render("warnock", data.view(), camera, {}, true);
    // Level 0, the image: all three, no surrounder in front -> subdivided.
    // Level 1: rows 0..3 x columns 0..3 hold back and front, both surrounding, front in front ->
    //   filled; columns 4..7 x rows 0..3 hold back and small -> subdivided; columns 0..3 x rows
    //   4..7 hold front only -> drawn; columns 4..7 x rows 4..7 -> empty.
    // Level 2 (columns 4..7, rows 0..3): three 2 x 2 windows hold back only -> drawn; columns 6..7 x
    //   rows 2..3 hold back and small, which does not cover (7, 3) -> subdivided.
    // Level 3: (6, 2), (7, 2), (6, 3) hold back and small -> one pixel each; (7, 3) back only -> drawn.
    CHECK(counter(frame, "windows-subdivided") == 3);
    CHECK(counter(frame, "windows-surrounder-in-front") == 1);
    CHECK(counter(frame, "windows-one-polygon") == 5);
    CHECK(counter(frame, "windows-empty") == 1);
    CHECK(counter(frame, "windows-one-pixel") == 3);
    CHECK(counter(frame, "quadtree-depth") == 3);
    // 3 against the image, 4 x 3 at level 1, 4 x 2 at levels 2 and 3.
    CHECK(counter(frame, "polygon-window-classifications") == 3 + 12 + 8 + 8);
    CHECK(counter(frame, "pixel-depth-comparisons") == 3 * 2);
    CHECK(counter(frame, "pixels-written") == 16 + 16 + 12 + 3 + 1);
    CHECK(counter(frame, "polygons") == 3);

    uint64_t tests = 0;
    for (int32_t y = 0; y < 8; ++y) {
        for (int32_t x = 0; x < 8; ++x) {
            INFO("pixel " << x << "," << y);
            const size_t p = size_t(y) * 8 + size_t(x);
            const bool small = (x == 6 && y == 2) || (x == 7 && y == 2) || (x == 6 && y == 3);
            const uint32_t expected = x < 4 ? 1u : small ? 2u : y < 4 ? 0u : HSR_NO_FACE;
            CHECK(frame.face[p] == expected);
            tests += frame.depth_tests[p];
            // A one-pixel window: 2 classifications, then 2 depth comparisons or 1 paint.
            if (x >= 6 && y >= 2 && y <= 3) CHECK(frame.depth_tests[p] == (small ? 4u : 3u));
        }
    }
    CHECK(tests == 16 + 16 + 12 + 3 * 4 + 3);
    CHECK(counter(frame, "pixels-depth-tested") == tests);
    check_same_frame(data.view(), camera);
}

TEST_CASE("warnock: a surrounder drawn after an equal-depth polygon does not win the tie", "[warnock]") {
    // Two coplanar triangles covering the whole image, the smaller first: the z-buffer keeps the
    // first where both cover a pixel, so the later surrounder may fill only where it is alone.
    hsr::SceneBuilder builder;
    const glm::vec3 first[] = {{-20, 4, 0}, {30, 4, 0}, {5, -30, 0}};
    const glm::vec3 second[] = {{-30, -30, 0}, {60, -30, 0}, {-30, 60, 0}};
    builder.add_polygon(first, {0.5f, 0.5f, 0.5f});
    builder.add_polygon(second, {0.8f, 0.2f, 0.2f});
    const hsr::SceneData data = builder.build();
    const hsr::Frame frame = render("warnock", data.view(), pixel_camera());
    for (size_t p = 0; p < 64; ++p) CHECK(frame.face[p] == (p < 32 ? 0u : 1u));
    check_same_frame(data.view(), pixel_camera());
}

TEST_CASE("warnock: steps run to the end are the render, a stop leaves the windows decided", "[warnock]") {
    test_models::require_fetched();
    struct Case {
        const char* file;
        hsr_camera camera;
    };
    const hsr::SceneData& monkey = model("monkey.obj");
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr::SceneData hand = three_triangles();
    const Case cases[] = {{"monkey.obj", orbit(monkey, 30, 20, 1.2f, false, 96, 72)},
                          {"boxes.scene", orbit(boxes, -110, -35, 1, true, 64, 80)},
                          {"three triangles", pixel_camera()}};
    for (const Case& c : cases) {
        INFO(c.file);
        const hsr_scene scene = std::string(c.file) == "three triangles" ? hand.view() : model(c.file).view();
        hsr::HiddenSurfaceRemover remover(plugin("warnock"), {});
        REQUIRE(remover.has_steps());
        auto run = [&](uint64_t stop_after) {
            hsr::Frame frame;
            hsr::resolve_visibility_steps(scene, c.camera, remover, frame, stop_after, true);
            REQUIRE(frame.steps.has_value());
            return frame;
        };
        const hsr::Frame plain = render(remover, scene, c.camera, true);
        const hsr::Frame full = run(0);
        CHECK(same_bytes(full.depth, plain.depth));
        CHECK(same_bytes(full.face, plain.face));
        CHECK(same_bytes(full.bary, plain.bary));
        CHECK(same_bytes(full.instance, plain.instance));
        CHECK(same_bytes(full.depth_tests, plain.depth_tests));
        uint64_t tests = 0;
        for (const uint32_t t : plain.depth_tests) tests += t;
        CHECK(counter(plain, "pixels-depth-tested") == tests);
        const uint64_t taken = full.steps->taken;
        // One step per window decided.
        CHECK(taken == counter(plain, "windows-empty") + counter(plain, "windows-one-polygon") +
                           counter(plain, "windows-surrounder-in-front") + counter(plain, "windows-one-pixel") +
                           counter(plain, "windows-subdivided"));
        if (std::string(c.file) == "three triangles") CHECK(taken == 13);

        // After step k, each pixel is the plain render's or still cleared, and step k changed only
        // pixels inside its own window box, as many as it says it wrote.
        const size_t pixels = size_t(c.camera.width) * c.camera.height;
        std::vector<uint32_t> previous_face(pixels, HSR_NO_FACE);
        std::vector<uint64_t> stops;
        for (uint64_t k = 1; k <= std::min<uint64_t>(taken, 40); ++k) stops.push_back(k);
        for (uint64_t k = taken / 7; k < taken; k += taken / 7 + 1) stops.push_back(k);
        uint64_t last_stop = 0;
        for (const uint64_t k : stops) {
            if (k <= last_stop) continue;
            INFO("stopped after step " << k);
            const hsr::Frame at_k = run(k);
            REQUIRE(at_k.steps->last.index == k);
            const hsr::StepRecord& step = at_k.steps->last;
            CHECK(step.type == "window");
            CHECK(step.level <= counter(plain, "quadtree-depth"));
            REQUIRE(step.lines.size() == 16);  // the window's box
            const float x0 = std::min(step.lines[0], step.lines[2]), x1 = std::max(step.lines[0], step.lines[2]);
            const float y0 = std::min(step.lines[1], step.lines[7]), y1 = std::max(step.lines[1], step.lines[7]);
            uint64_t changed = 0;
            for (size_t p = 0; p < pixels; ++p) {
                const float x = float(p % c.camera.width) + 0.5f, y = float(p / c.camera.width) + 0.5f;
                const bool cleared = at_k.face[p] == HSR_NO_FACE && at_k.depth[p] == std::numeric_limits<float>::infinity();
                const bool final = at_k.face[p] == plain.face[p] && at_k.depth[p] == plain.depth[p] &&
                                   at_k.bary[2 * p] == plain.bary[2 * p] && at_k.bary[2 * p + 1] == plain.bary[2 * p + 1];
                CHECK((cleared || final));
                if (k == last_stop + 1 && at_k.face[p] != previous_face[p]) {
                    ++changed;
                    CHECK((x > x0 && x < x1 && y > y0 && y < y1));
                }
            }
            if (k == last_stop + 1) CHECK(changed == step.pixels_written);
            previous_face = at_k.face;
            last_stop = k;
        }
    }
}

TEST_CASE("warnock: a scene over max-polygons is refused with one line", "[warnock]") {
    const hsr::SceneData& cube = model("cube.obj");
    const hsr_camera camera = orbit(cube, 30, 20, 1, false, 64);
    try {
        render("warnock", cube.view(), camera, {{"max-polygons", "5"}});
        FAIL("no refusal");
    } catch (const std::exception& e) {
        const std::string message = e.what();
        CHECK(message.find("warnock: the scene draws 12 triangles, more than max-polygons=5") != std::string::npos);
        CHECK(message.find('\n') == std::string::npos);
    }
}

// Writes docs/images/warnock-quadtree.png of the working folder (a hidden case, not run by the
// suite): every window warnock decides on boxes.scene at 128x128 (--yaw 30 --pitch -15), from the
// text of each step, drawn 4 times enlarged: empty windows dark, windows filled by a surrounder in
// front green (lighter nearer), one-pixel windows red, windows drawn with one polygon blue, and
// the outline of every larger window, subdivided ones too.
TEST_CASE("warnock: the picture of the quadtree", "[warnock][.figures]") {
    const hsr::SceneData& data = model("boxes.scene");
    const uint32_t size = 128, scale = 4, side = size * scale;
    const hsr_camera camera = orbit(data, 30, -15, 1, false, size);
    hsr::HiddenSurfaceRemover remover(plugin("warnock"), {});
    auto run = [&](uint64_t stop_after) {
        hsr::Frame frame;
        hsr::resolve_visibility_steps(data.view(), camera, remover, frame, stop_after);
        REQUIRE(frame.steps.has_value());
        return frame;
    };
    const hsr::Frame all = run(0);
    struct Window {
        uint32_t x0, x1, y0, y1;
        std::string kind;
    };
    std::vector<Window> windows;
    float nearest = 1, farthest = 0;
    for (uint64_t k = 1; k <= all.steps->taken; ++k) {
        const std::string text = run(k).steps->last.text;
        Window w{};
        const size_t at = text.find("window x ");
        REQUIRE(at != std::string::npos);
        REQUIRE(std::sscanf(text.c_str() + at, "window x %u..%u, y %u..%u", &w.x0, &w.x1, &w.y0, &w.y1) == 4);
        w.kind = text.find("surrounds") != std::string::npos     ? "surrounder"
                 : text.find("one pixel") != std::string::npos   ? "pixel"
                 : text.find("one polygon") != std::string::npos ? "polygon"
                 : text.find("empty") != std::string::npos       ? "empty"
                                                                 : "subdivided";
        if (w.kind == "surrounder") {
            const float depth = all.depth[size_t(w.y0) * size + w.x0];
            nearest = std::min(nearest, depth);
            farthest = std::max(farthest, depth);
        }
        windows.push_back(w);
    }
    std::vector<uint8_t> rgb(size_t(3) * side * side, 0);
    auto fill = [&](uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, glm::vec3 colour) {
        for (uint32_t y = y0; y < y1; ++y)
            for (uint32_t x = x0; x < x1; ++x)
                for (int c = 0; c < 3; ++c) rgb[3 * (size_t(y) * side + x) + c] = uint8_t(colour[c]);
    };
    fill(0, 0, side, side, {38, 38, 43});
    for (const Window& w : windows) {
        glm::vec3 colour{38, 38, 43};
        if (w.kind == "surrounder") {
            const float depth = all.depth[size_t(w.y0) * size + w.x0];
            const float t = farthest > nearest ? (farthest - depth) / (farthest - nearest) : 1.0f;
            colour = glm::mix(glm::vec3{50, 110, 60}, glm::vec3{130, 230, 140}, t);
        } else if (w.kind == "pixel") {
            colour = {200, 80, 70};
        } else if (w.kind == "polygon") {
            colour = {80, 120, 210};
        }
        if (w.kind != "subdivided") fill(w.x0 * scale, w.y0 * scale, (w.x1 + 1) * scale, (w.y1 + 1) * scale, colour);
    }
    for (const Window& w : windows) {
        if (w.x0 == w.x1 && w.y0 == w.y1) continue;
        const uint32_t x0 = w.x0 * scale, y0 = w.y0 * scale, x1 = (w.x1 + 1) * scale - 1, y1 = (w.y1 + 1) * scale - 1;
        const glm::vec3 line{20, 20, 24};
        fill(x0, y0, x1 + 1, y0 + 1, line);
        fill(x0, y1, x1 + 1, y1 + 1, line);
        fill(x0, y0, x0 + 1, y1 + 1, line);
        fill(x1, y0, x1 + 1, y1 + 1, line);
    }
    hsr::write_png(std::filesystem::path("docs") / "images" / "warnock-quadtree.png", side, side, 3, rgb);
}
