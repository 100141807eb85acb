// Supersampling (--samples): the sample patterns against the Vulkan specification's table, the
// colour of a pixel that an edge crosses against the count of samples on each side of it worked out
// here, with every hidden-surface plugin, and the pixels that no edge crosses unchanged.
#include "cli_support.hpp"
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene_builder.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const hsr::Plugin& plugin(hsr_plugin_kind kind, const std::string& name) {
    static const hsr::PluginRegistry registry = [] {
        hsr::PluginRegistry r;
        r.scan_directory(HSR_PLUGIN_DIR);
        return r;
    }();
    return registry.find(kind, name);
}

// Vulkan 1.3, "Standard sample locations" (VkPhysicalDeviceLimits::standardSampleLocations), in
// pixel coordinates [0, 1) with y down: the pixel centre is (0.5, 0.5).
const std::vector<std::vector<glm::vec2>> vulkan_locations = {
    {{0.5f, 0.5f}},
    {{0.75f, 0.75f}, {0.25f, 0.25f}},
    {{0.375f, 0.125f}, {0.875f, 0.375f}, {0.125f, 0.625f}, {0.625f, 0.875f}},
    {{0.5625f, 0.3125f}, {0.4375f, 0.6875f}, {0.8125f, 0.5625f}, {0.3125f, 0.1875f},
     {0.1875f, 0.8125f}, {0.0625f, 0.4375f}, {0.6875f, 0.9375f}, {0.9375f, 0.0625f}},
    {{0.5625f, 0.5625f}, {0.4375f, 0.3125f}, {0.3125f, 0.625f}, {0.75f, 0.4375f},
     {0.1875f, 0.375f}, {0.625f, 0.8125f}, {0.8125f, 0.6875f}, {0.6875f, 0.1875f},
     {0.375f, 0.875f}, {0.5f, 0.0625f}, {0.25f, 0.125f}, {0.125f, 0.75f},
     {0.0f, 0.5f}, {0.9375f, 0.25f}, {0.875f, 0.9375f}, {0.0625f, 0.0f}},
};

constexpr uint32_t sample_counts[] = {1, 2, 4, 8, 16};

// A white rectangle [x0, x1] x [y0, y1] in the pixel camera's world (x right, y up), z = 1.
hsr::SceneData rectangle(float x0, float y0, float x1, float y1) {
    hsr::SceneBuilder builder;
    const glm::vec3 corners[] = {{x0, y0, 1}, {x1, y0, 1}, {x1, y1, 1}, {x0, y1, 1}};
    builder.add_polygon(corners, glm::vec3(1.0f));
    return builder.build();
}

// The picture of the scene in an 8x8 pixel camera, white faces (facecolor) on black.
hsr::Frame render(const hsr::SceneData& scene, const std::string& algorithm, uint32_t samples,
                  const std::string& lighting = "facecolor") {
    const hsr_scene view = scene.view();
    const hsr_camera camera = hsr::make_pixel_camera(8, 8, 0.0f, 2.0f);
    hsr::HiddenSurfaceRemover remover(plugin(HSR_KIND_HIDDEN_SURFACE_REMOVER, algorithm), {});
    hsr::LightingModel shading(plugin(HSR_KIND_LIGHTING_MODEL, lighting), {});
    const std::vector<hsr_light> lights = {{sizeof(hsr_light), HSR_LIGHT_DIRECTIONAL, {0.3f, 0.4f, 0.866f}, {1, 1, 1}, 1}};
    hsr::FrameSettings settings;
    settings.background = glm::vec3(0.0f);
    settings.samples = samples;
    settings.threads = 1;
    return hsr::render_supersampled_frame(view, camera, remover, shading, hsr::make_shading_context(camera, lights), settings);
}

uint8_t red_at(const hsr::Frame& frame, uint32_t x, uint32_t y) { return frame.rgb[3 * (size_t(y) * frame.width + x)]; }

uint8_t expected_byte(uint32_t covered, uint32_t samples) {
    return uint8_t((covered * 255 + samples / 2) / samples);  // the mean of whole bytes, rounded
}

}  // namespace

TEST_CASE("supersampling: the sample patterns are the standard ones", "[samples]") {
    for (std::size_t i = 0; i < std::size(sample_counts); ++i) {
        const uint32_t n = sample_counts[i];
        INFO(n << " samples");
        const std::vector<glm::vec2> offsets = hsr::sample_offsets(n);
        REQUIRE(offsets.size() == n);
        for (uint32_t k = 0; k < n; ++k) CHECK(offsets[k] + glm::vec2(0.5f) == vulkan_locations[i][k]);
        CHECK(hsr::is_sample_count(n));
    }
    for (uint32_t n : {0u, 3u, 5u, 6u, 12u, 32u}) {
        CHECK_FALSE(hsr::is_sample_count(n));
        CHECK_THROWS_AS(hsr::sample_offsets(n), hsr::Error);
    }
    // 4 is the rotated grid: the four samples fall in four different columns and four different rows.
    const std::vector<glm::vec2> four = hsr::sample_offsets(4);
    for (std::size_t a = 0; a < 4; ++a)
        for (std::size_t b = a + 1; b < 4; ++b) {
            CHECK(four[a].x != four[b].x);
            CHECK(four[a].y != four[b].y);
        }
}

TEST_CASE("supersampling: a pixel an edge crosses has the coverage the pattern predicts, with every remover",
          "[samples]") {
    // Edges at odd multiples of 1/32 pixel from the centre of pixel column 3 (row 3): no sample lies on
    // them, so which side each sample is on is plain.
    for (const char* algorithm : {"zbuffer", "scanline-zbuffer", "hierarchical-zbuffer", "octree-zbuffer"}) {
        for (std::size_t i = 0; i < std::size(sample_counts); ++i) {
            const uint32_t n = sample_counts[i];
            for (int e = -15; e <= 15; e += 4) {
                const float edge = float(e) / 32.0f;  // from the pixel centre
                INFO(algorithm << ", " << n << " samples, edge at " << edge);
                uint32_t left = 0, below = 0;  // samples left of a vertical edge, below a horizontal one
                for (const glm::vec2& location : vulkan_locations[i]) {
                    left += location.x - 0.5f < edge;
                    below += location.y - 0.5f > edge;  // y down: below is larger y
                }
                // Vertical edge: the rectangle covers world x < 3.5 + edge over all rows.
                const hsr::Frame vertical = render(rectangle(-1, -1, 3.5f + edge, 9), algorithm, n);
                CHECK(red_at(vertical, 3, 4) == expected_byte(left, n));
                CHECK(red_at(vertical, 2, 4) == 255);  // wholly inside
                CHECK(red_at(vertical, 4, 4) == 0);    // wholly outside
                // Horizontal edge: window row y is world y from 8 - y - 1 to 8 - y; the rectangle
                // covers window y > 3.5 + edge, i.e. world y < 4.5 - edge.
                const hsr::Frame horizontal = render(rectangle(-1, -1, 9, 4.5f - edge), algorithm, n);
                CHECK(red_at(horizontal, 4, 3) == expected_byte(below, n));
                CHECK(red_at(horizontal, 4, 4) == 255);
                CHECK(red_at(horizontal, 4, 2) == 0);
            }
        }
    }
}

TEST_CASE("supersampling: pixels no edge crosses keep the one-sample colour exactly", "[samples]") {
    // A lit rectangle: orthographic view and a directional light make its colour the same everywhere.
    const hsr::SceneData scene = rectangle(1.3f, 1.7f, 6.6f, 6.2f);
    const hsr::Frame one = render(scene, "zbuffer", 1, "blinn-phong");
    const uint8_t* inside = &one.rgb[3 * (4 * 8 + 4)];
    REQUIRE(inside[0] > 0);
    for (uint32_t n : {2u, 4u, 8u, 16u}) {
        INFO(n << " samples");
        const hsr::Frame many = render(scene, "zbuffer", n, "blinn-phong");
        for (uint32_t y = 0; y < 8; ++y)
            for (uint32_t x = 0; x < 8; ++x) {
                const bool interior = x >= 2 && x <= 5 && y >= 2 && y <= 5;
                const bool outside = x == 0 || x == 7 || y == 0 || y == 7;
                if (!interior && !outside) continue;
                for (int c = 0; c < 3; ++c) CHECK(many.rgb[3 * (8 * y + x) + c] == one.rgb[3 * (8 * y + x) + c]);
            }
        CHECK(many.counter("fragments-shaded") > one.counter("fragments-shaded"));
    }
}

TEST_CASE("supersampling: steps and depth-test counts need one sample", "[samples]") {
    const hsr::SceneData scene = rectangle(1, 1, 6, 6);
    const hsr_scene view = scene.view();
    const hsr_camera camera = hsr::make_pixel_camera(8, 8, 0.0f, 2.0f);
    hsr::HiddenSurfaceRemover remover(plugin(HSR_KIND_HIDDEN_SURFACE_REMOVER, "zbuffer"), {});
    hsr::LightingModel shading(plugin(HSR_KIND_LIGHTING_MODEL, "facecolor"), {});
    hsr::FrameSettings settings;
    settings.samples = 4;
    settings.count_depth_tests = true;
    CHECK_THROWS_WITH(hsr::render_supersampled_frame(view, camera, remover, shading, hsr::make_shading_context(camera, {}), settings),
                      Catch::Contains("1 sample"));
    settings.count_depth_tests = false;
    settings.stop_after_step = 1;
    CHECK_THROWS_WITH(hsr::render_supersampled_frame(view, camera, remover, shading, hsr::make_shading_context(camera, {}), settings),
                      Catch::Contains("1 sample"));
}

TEST_CASE("cli: --samples 1 is byte for byte the picture without it, bad counts are one-line errors",
          "[samples][cli]") {
    const std::string cube = std::string(HSR_MODELS_DIR) + "/cube.obj";
    const fs::path dir = cli::scratch_dir();
    const std::string common = "render " + cube + " --yaw 30 --pitch 20 --width 64 --height 64 ";
    REQUIRE(cli::run_hsr(common + "-o " + (dir / "plain.png").string(), "samples-plain").status == 0);
    REQUIRE(cli::run_hsr(common + "--samples 1 -o " + (dir / "one.png").string(), "samples-one").status == 0);
    REQUIRE(cli::run_hsr(common + "--samples 8 -o " + (dir / "eight.png").string(), "samples-eight").status == 0);
    CHECK(cli::slurp(dir / "plain.png") == cli::slurp(dir / "one.png"));
    CHECK(cli::slurp(dir / "plain.png") != cli::slurp(dir / "eight.png"));

    for (const char* bad : {"3", "0", "-4", "32"})
        cli::require_one_line_error(cli::run_hsr(common + "--samples " + std::string(bad) + " -o x.png", "samples-bad"),
                                    "--samples");
    cli::require_one_line_error(
        cli::run_hsr(common + "--samples 4 --depth-out " + (dir / "d.png").string() + " -o x.png", "samples-depth"),
        "--depth-out");
    cli::require_one_line_error(cli::run_hsr(common + "--samples 4 --step 2 -o x.png", "samples-step"), "--step");
    cli::require_one_line_error(cli::run_hsr("render " + cube + " -a appel --samples 4 -o x.svg", "samples-lines"),
                                "--samples");
}

TEST_CASE("cli: a .scene file's samples line, overridden by --samples", "[samples][cli]") {
    const fs::path dir = cli::scratch_dir();
    const std::string cube = std::string(HSR_MODELS_DIR) + "/cube.obj";
    const fs::path four = cli::write_file("samples-four.scene", "samples 4\nmesh " + cube + "\n");
    const fs::path plain = cli::write_file("samples-none.scene", "mesh " + cube + "\n");
    const std::string size = " --yaw 30 --pitch 20 --width 48 --height 48 -o ";
    REQUIRE(cli::run_hsr("render " + four.string() + size + (dir / "file4.png").string(), "file4").status == 0);
    REQUIRE(cli::run_hsr("render " + plain.string() + " --samples 4" + size + (dir / "cli4.png").string(), "cli4").status == 0);
    REQUIRE(cli::run_hsr("render " + four.string() + " --samples 1" + size + (dir / "file1.png").string(), "file1").status == 0);
    REQUIRE(cli::run_hsr("render " + plain.string() + size + (dir / "plain1.png").string(), "plain1").status == 0);
    CHECK(cli::slurp(dir / "file4.png") == cli::slurp(dir / "cli4.png"));
    CHECK(cli::slurp(dir / "file1.png") == cli::slurp(dir / "plain1.png"));
    CHECK(cli::slurp(dir / "file4.png") != cli::slurp(dir / "file1.png"));

    const fs::path bad = cli::write_file("samples-bad.scene", "samples 3\nmesh " + cube + "\n");
    cli::require_one_line_error(cli::run_hsr("render " + bad.string() + " -o x.png", "samples-bad-file"), "samples '3'");
}
