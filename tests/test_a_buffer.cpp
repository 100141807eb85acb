// The a-buffer plugin and the host's fragment lists (ABI 1.4): the visibility buffer against
// zbuffer, coverage masks against exact geometry and a per-sample ray cast, anti-aliased edges and
// transparency against hand-computed colours, independence of input order, and refusals.
#include "cli_support.hpp"
#include "ray_reference.hpp"
#include "surface_test_support.hpp"

#include "hsr/error.hpp"
#include "hsr/fragment_lists.hpp"
#include "hsr/limits.hpp"
#include "hsr/sdk.hpp"

#include <catch2/catch.hpp>

#include <bit>
#include <string>
#include <vector>

namespace {

using surface_tests::Agreement;
using surface_tests::check_against_zbuffer;
using surface_tests::model;
using surface_tests::orbit;
using surface_tests::plugin;

struct FragmentFrame {
    hsr::Frame frame;
    hsr::FragmentLists lists;
};

FragmentFrame resolve(const hsr_scene& scene, const hsr_camera& camera, const surface_tests::Settings& settings = {}) {
    hsr::HiddenSurfaceRemover remover(plugin("a-buffer"), settings);
    FragmentFrame f;
    hsr::resolve_fragments(scene, camera, remover, f.frame, f.lists);
    return f;
}

// The shaded, composited picture of a .scene text with the facecolor lighting (unlit face colours).
hsr::Frame picture(const std::string& scene_text, const std::string& name) {
    const auto path = cli::write_file(name, scene_text);
    hsr::SceneFile file = hsr::load_scene_file(path);
    const hsr_scene scene = file.scene.view();
    const hsr_camera camera = hsr::make_pixel_camera(*file.width, *file.height, file.scene.bounds_min.z,
                                                     file.scene.bounds_max.z);
    hsr::HiddenSurfaceRemover remover(plugin("a-buffer"), {});
    hsr::LightingModel lighting(plugin("facecolor"), {});
    hsr::FrameSettings settings;
    settings.background = file.background.value_or(glm::vec3(1.0f));
    return hsr::render_frame(scene, camera, remover, lighting, hsr::make_shading_context(camera, {}), settings);
}

glm::ivec3 rgb_at(const hsr::Frame& f, uint32_t x, uint32_t y) {
    const size_t p = 3 * (size_t(y) * f.width + x);
    return {f.rgb[p], f.rgb[p + 1], f.rgb[p + 2]};
}

// Sample k of a pixel, in window coordinates: column k % 8 at (2c + 1) / 16, row k / 8 at (2r + 1) / 8.
glm::dvec2 sample_point(uint32_t x, uint32_t y, int k) {
    return {x + (2 * (k % 8) + 1) / 16.0, y + (2 * (k / 8) + 1) / 8.0};
}

std::pair<uint32_t, uint32_t> nearest(const hsr_scene& scene, const hsr_camera& camera, glm::dvec2 w) {
    return ray_reference::nearest_surface(scene, camera, w.x, w.y);
}

struct SampleComparison {
    uint64_t samples = 0, ambiguous = 0, mismatches = 0;
};

// For every sample of every pixel: the first fragment of the pixel's list covering it against a ray
// cast through it. A sample whose neighbours 0.002 pixel away see another surface is ambiguous.
SampleComparison compare_samples(const hsr_scene& scene, const hsr_camera& camera, const hsr::FragmentLists& lists) {
    SampleComparison c;
    constexpr double d = 0.002;
    for (uint32_t y = 0; y < camera.height; ++y)
        for (uint32_t x = 0; x < camera.width; ++x)
            for (int k = 0; k < HSR_COVERAGE_SAMPLES; ++k) {
                const glm::dvec2 w = sample_point(x, y, k);
                const auto truth = nearest(scene, camera, w);
                if (nearest(scene, camera, w + glm::dvec2(d, d)) != truth ||
                    nearest(scene, camera, w - glm::dvec2(d, d)) != truth ||
                    nearest(scene, camera, w + glm::dvec2(d, -d)) != truth) {
                    ++c.ambiguous;
                    continue;
                }
                ++c.samples;
                const size_t p = size_t(y) * camera.width + x;
                std::pair<uint32_t, uint32_t> seen{HSR_NO_FACE, 0};
                for (uint32_t f = lists.first[p]; f < lists.first[p + 1]; ++f)
                    if (lists.coverage[f] & (1u << k)) {
                        seen = {lists.face[f], lists.instance.empty() ? 0 : lists.instance[f]};
                        break;
                    }
                c.mismatches += seen != truth ? 1 : 0;
            }
    return c;
}

}  // namespace

TEST_CASE("a-buffer: its visibility buffer is zbuffer's, bit for bit", "[a-buffer]") {
    test_models::require_fetched();
    Agreement agreement;
    agreement.plugin = "a-buffer";
    agreement.label = "a-buffer";
    for (const char* name : {"monkey.obj", "boxes.scene"})
        for (bool ortho : {false, true}) {
            const hsr::SceneData& m = model(name);
            const auto picture = check_against_zbuffer(agreement, m.view(), orbit(m, 30, 20, 1, ortho, 96));
            CHECK(picture.comparison.ties == 0);
            // render_fragments fills the same visibility buffer as render.
            const FragmentFrame f = resolve(m.view(), orbit(m, 30, 20, 1, ortho, 96));
            CHECK(f.frame.face == picture.frame.face);
            CHECK(f.frame.depth == picture.frame.depth);
            CHECK(f.frame.bary == picture.frame.bary);
        }
}

TEST_CASE("a-buffer: an edge at x = 10.3 covers exactly the samples left of it", "[a-buffer]") {
    // Pixel 10 spans x in [10, 11); its sample columns lie at 10 + (2c + 1) / 16, so columns 0 and
    // 1 (10.0625, 10.1875) are left of 10.3 and column 2 (10.3125) is not: mask 0x03030303.
    const std::string scene = "camera pixel\nsize 16 4\nbackground 1 1 1\npolygon\n  color 1 0 0\n"
                              "  vertex 0 0 0\n  vertex 10.3 0 0\n  vertex 10.3 4 0\n  vertex 0 4 0\n";
    const auto path = cli::write_file("edge.scene", scene);
    hsr::SceneFile file = hsr::load_scene_file(path);
    const hsr_camera camera = hsr::make_pixel_camera(16, 4, 0.0f, 0.0f);
    const FragmentFrame f = resolve(file.scene.view(), camera);
    for (uint32_t y = 0; y < 4; ++y) {
        auto union_mask = [&](uint32_t x) {
            uint32_t mask = 0;
            const size_t p = size_t(y) * 16 + x;
            for (uint32_t i = f.lists.first[p]; i < f.lists.first[p + 1]; ++i) mask |= f.lists.coverage[i];
            return mask;
        };
        CHECK(union_mask(9) == 0xFFFFFFFFu);
        CHECK(union_mask(10) == 0x03030303u);
        CHECK(union_mask(11) == 0u);
    }
    // Shaded: a quarter red over white. 0.75 * 255 = 191.25.
    const hsr::Frame shaded = picture(scene, "edge-shaded.scene");
    CHECK(rgb_at(shaded, 9, 1) == glm::ivec3(255, 0, 0));
    CHECK(rgb_at(shaded, 10, 1) == glm::ivec3(255, 191, 191));
    CHECK(rgb_at(shaded, 11, 1) == glm::ivec3(255, 255, 255));
}

TEST_CASE("a-buffer: every sample shows what a ray cast through it sees", "[a-buffer]") {
    SECTION("the cube: no surfaces cross, every unambiguous sample agrees") {
        const hsr::SceneData& cube = model("cube.obj");
        const hsr_camera camera = orbit(cube, 30, 25, 1, false, 24);
        const FragmentFrame f = resolve(cube.view(), camera);
        const SampleComparison c = compare_samples(cube.view(), camera, f.lists);
        INFO(c.samples << " samples, " << c.ambiguous << " ambiguous, " << c.mismatches << " differ");
        CHECK(c.samples > 24 * 24 * 32 / 3);
        CHECK(c.mismatches == 0);
    }
    SECTION("boxes through one another: only where surfaces cross inside a pixel") {
        // A fragment has one depth (at its centroid), so where two surfaces intersect within a
        // pixel, its samples take one order: a few samples next to the intersection lines.
        const hsr::SceneData& boxes = model("boxes.scene");
        const hsr_camera camera = orbit(boxes, 35, 25, 1, false, 32);
        const FragmentFrame f = resolve(boxes.view(), camera);
        const SampleComparison c = compare_samples(boxes.view(), camera, f.lists);
        INFO(c.samples << " samples, " << c.ambiguous << " ambiguous, " << c.mismatches << " differ");
        CHECK(c.samples > 32 * 32 * 32 / 3);
        CHECK(double(c.mismatches) < 0.005 * double(c.samples));
    }
}

TEST_CASE("a-buffer: transparency composites in depth order, whatever the order of input", "[a-buffer]") {
    // A half-opaque red square in front of an opaque blue one (larger z is nearer with `camera
    // pixel`); where they overlap: 0.5 red + 0.5 blue; red alone over the white background: 0.5 red
    // + 0.5 white.
    const std::string red = "polygon\n  color 1 0 0\n  opacity 0.5\n  vertex 0 0 1\n  vertex 8 0 1\n"
                            "  vertex 8 8 1\n  vertex 0 8 1\n";
    const std::string blue = "polygon\n  color 0 0 1\n  vertex 4 0 0\n  vertex 12 0 0\n  vertex 12 8 0\n"
                             "  vertex 4 8 0\n";
    const std::string head = "camera pixel\nsize 12 8\nbackground 1 1 1\n";
    const hsr::Frame red_first = picture(head + red + blue, "red-first.scene");
    const hsr::Frame blue_first = picture(head + blue + red, "blue-first.scene");
    CHECK(red_first.rgb == blue_first.rgb);
    CHECK(rgb_at(red_first, 6, 4) == glm::ivec3(128, 0, 128));    // 0.5 * 255 = 127.5, rounded up
    CHECK(rgb_at(red_first, 2, 4) == glm::ivec3(255, 128, 128));
    CHECK(rgb_at(red_first, 10, 4) == glm::ivec3(0, 0, 255));
    // Opacity 0: the red square vanishes.
    std::string invisible = red;
    invisible.replace(invisible.find("opacity 0.5"), 11, "opacity 0.0");
    const hsr::Frame gone = picture(head + invisible + blue, "invisible.scene");
    CHECK(rgb_at(gone, 2, 4) == glm::ivec3(255, 255, 255));
    CHECK(rgb_at(gone, 6, 4) == glm::ivec3(0, 0, 255));
}

TEST_CASE("a-buffer: an opaque fragment hides what lies wholly behind it", "[a-buffer]") {
    test_models::require_fetched();
    const hsr::SceneData& monkey = model("monkey.obj");
    const FragmentFrame f = resolve(monkey.view(), orbit(monkey, 0, 0, 1, false, 64));
    // In each list, no fragment's samples are all covered by the opaque fragments before it.
    for (size_t p = 0; p + 1 < f.lists.first.size(); ++p) {
        uint32_t closed = 0;
        for (uint32_t i = f.lists.first[p]; i < f.lists.first[p + 1]; ++i) {
            CHECK((f.lists.coverage[i] & ~closed) != 0);
            if (i > f.lists.first[p]) CHECK(f.lists.depth[i] >= f.lists.depth[i - 1]);
            closed |= f.lists.coverage[i];
        }
    }
    CHECK(f.frame.counter("fragments-hidden") > 0);
    CHECK(f.frame.counter("fragments-made") == f.frame.counter("fragments-hidden") + f.frame.counter("fragments-kept"));
    CHECK(f.frame.counter("fragments-kept") == f.lists.size());
}

TEST_CASE("a-buffer: clip planes, steps and refusals", "[a-buffer]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    hsr_camera camera = orbit(boxes, 35, 25, 1, false, 48);
    camera.clip_plane_count = 1;
    const float plane[4] = {0.0f, 0.0f, -1.0f, 0.1f};
    std::copy(plane, plane + 4, camera.clip_planes[0]);
    Agreement agreement;
    agreement.plugin = "a-buffer";
    agreement.label = "a-buffer";
    check_against_zbuffer(agreement, boxes.view(), camera);

    // Steps run to the end leave the buffer render() leaves.
    hsr::HiddenSurfaceRemover remover(plugin("a-buffer"), {});
    hsr::Frame stepped, plain;
    hsr::resolve_visibility_steps(boxes.view(), camera, remover, stepped, 0);
    hsr::resolve_visibility(boxes.view(), camera, remover, plain);
    CHECK(stepped.face == plain.face);
    CHECK(stepped.depth == plain.depth);
    // A step per triangle, then one per row of pixels resolving the lists.
    CHECK(stepped.steps->taken == hsr::drawn_triangle_count(boxes.view()) + camera.height);
    CHECK(stepped.steps->last.type == "row");
    CHECK(stepped.steps->last.phase == "resolve");

    CHECK_THROWS_WITH(resolve(boxes.view(), orbit(boxes, 35, 25, 1, false, 256), {{"max-fragments", "1024"}}),
                      Catch::Contains("a-buffer: the frame needs more than max-fragments=1024 fragments"));

    // The host's own limit on the lists it takes is the asker's to raise: a LimitError.
    struct DefaultLimitsAfter {
        ~DefaultLimitsAfter() { hsr::set_limits({}); }
    } restore;
    hsr::Limits few;
    few.fragments = 100;
    hsr::set_limits(few);
    try {
        resolve(boxes.view(), orbit(boxes, 35, 25, 1, false, 64));
        FAIL("the fragments limit was not hit");
    } catch (const hsr::LimitError& e) {
        CHECK_THAT(e.what(), Catch::Contains("over the limit of 100 (raise it with --limit fragments=N)"));
    }
}

TEST_CASE("a-buffer: the command line", "[a-buffer][cli]") {
    using cli::require_one_line_error;
    using cli::run_hsr;
    const std::string cube = std::string(HSR_MODELS_DIR) + "/cube.obj";
    const std::string out = (cli::scratch_dir() / "opacity.png").string();
    require_one_line_error(run_hsr("render " + cube + " --opacity 0.5 -o " + out, "opacity-zbuffer"),
                           "transparency needs fragment lists (-a a-buffer)");
    require_one_line_error(run_hsr("render " + cube + " --opacity 1.5 -a a-buffer -o " + out, "opacity-range"),
                           "--opacity must be between 0 and 1");
    require_one_line_error(run_hsr("render " + std::string(HSR_MODELS_DIR) + "/boxes.scene --opacity 0.5 -a a-buffer -o " + out,
                                   "opacity-scene"),
                           "--opacity is for a single model");
    CHECK(run_hsr("render " + cube + " --opacity 0.5 -a a-buffer --width 32 --height 32 -o " + out, "opacity-ok").status == 0);
    const auto bad = cli::write_file("bad-opacity.scene", "mesh " + cube + "\n  opacity 2\n");
    require_one_line_error(run_hsr("render " + bad.string() + " -o " + out, "opacity-bad-scene"), "opacity must be within [0, 1]");
}

TEST_CASE("a-buffer: the resolve steps' coverage is the share of samples a ray finds a surface through",
          "[a-buffer][steps]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_scene scene = boxes.view();
    const hsr_camera camera = orbit(boxes, 35, 25, 1, false, 40, 30);
    hsr::HiddenSurfaceRemover remover(plugin("a-buffer"), {});
    hsr::Frame stepped;
    // Stopped after the last step, whose buffers the host keeps: a step per triangle, then per row.
    const uint64_t last_step = hsr::drawn_triangle_count(scene) + camera.height;
    hsr::resolve_visibility_steps(scene, camera, remover, stepped, last_step);
    REQUIRE(stepped.steps.has_value());
    const hsr::StepRecord& last = stepped.steps->last;
    CHECK(last.index == last_step);
    CHECK(last.phase == "resolve");
    REQUIRE(last.buffers.size() == 1);
    const hsr::StepBuffer& coverage = last.buffers[0];
    CHECK(coverage.name == "coverage");
    REQUIRE(coverage.values.size() == size_t(camera.width) * camera.height);
    constexpr double d = 0.002;
    auto hits = [&](glm::dvec2 w) { return nearest(scene, camera, w).first != HSR_NO_FACE; };
    uint64_t edge_pixels = 0, wrong = 0;
    for (uint32_t y = 0; y < camera.height; ++y)
        for (uint32_t x = 0; x < camera.width; ++x) {
            int seen = 0, ambiguous = 0;
            for (int k = 0; k < HSR_COVERAGE_SAMPLES; ++k) {
                const glm::dvec2 w = sample_point(x, y, k);
                const bool hit = hits(w);
                if (hits(w + glm::dvec2(d, d)) != hit || hits(w - glm::dvec2(d, d)) != hit ||
                    hits(w + glm::dvec2(d, -d)) != hit)
                    ++ambiguous;
                else
                    seen += hit ? 1 : 0;
            }
            const double covered = coverage.values[size_t(y) * camera.width + x] * HSR_COVERAGE_SAMPLES;
            INFO("pixel " << x << "," << y << ": " << covered << " samples covered, rays see " << seen << " (+"
                          << ambiguous << " ambiguous)");
            edge_pixels += covered > 0 && covered < HSR_COVERAGE_SAMPLES ? 1 : 0;
            const bool agrees = covered >= seen && covered <= seen + ambiguous;
            if (!agrees && wrong++ == 0) CHECK(agrees);  // the first disagreement, with its pixel
        }
    CHECK(edge_pixels > 0);  // the silhouettes are partly covered pixels
    CHECK(wrong == 0);
}
