// Random triangles (--random-triangles, bench model random-N): reproducible from the seed, inside
// the default camera's view volume, a colour each, and refused beyond the limits.
#include "cli_support.hpp"
#include "bench/measure.hpp"
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/image.hpp"
#include "hsr/limits.hpp"
#include "hsr/random_triangles.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <cmath>
#include <cstring>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Every array the scene hands to plugins, as bytes.
std::string scene_bytes(const hsr::SceneData& s) {
    std::string bytes;
    auto add = [&](const auto& v) {
        bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
    };
    add(s.positions);
    add(s.indices);
    add(s.face_normals);
    add(s.corner_normals);
    add(s.face_colors);
    add(s.edge_neighbors);
    add(s.face_object);
    return bytes;
}

glm::vec3 corner(const hsr::SceneData& s, uint32_t t, int k) {
    const uint32_t v = s.indices[3 * t + k];
    return {s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]};
}

}  // namespace

TEST_CASE("random triangles: the same seed gives the same scene, another seed another", "[random-triangles]") {
    const hsr::SceneData a = hsr::make_random_triangles(200, 7);
    const hsr::SceneData b = hsr::make_random_triangles(200, 7);
    const hsr::SceneData c = hsr::make_random_triangles(200, 8);
    REQUIRE(a.triangle_count() == 200);
    CHECK(scene_bytes(a) == scene_bytes(b));
    CHECK(scene_bytes(a) != scene_bytes(c));
    CHECK(a.positions != c.positions);
    CHECK(a.face_colors != c.face_colors);
    // A longer list starts with the shorter one's triangles: each triangle's numbers come in turn.
    const hsr::SceneData longer = hsr::make_random_triangles(300, 7);
    CHECK(std::equal(a.positions.begin(), a.positions.end(), longer.positions.begin()));
}

TEST_CASE("random triangles: inside the cube and the default camera's view volume, each its own colour",
          "[random-triangles]") {
    const hsr::SceneData s = hsr::make_random_triangles(500, 12345);
    REQUIRE(s.triangle_count() == 500);
    const hsr_camera camera = hsr::make_camera(s.bounds_min, s.bounds_max, hsr::CameraSettings{});
    glm::mat4 view_projection;
    std::memcpy(&view_projection[0][0], camera.view_projection, sizeof camera.view_projection);
    std::set<std::tuple<float, float, float>> colors;
    float smallest = 1e9f, largest = 0;
    for (uint32_t t = 0; t < s.triangle_count(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = corner(s, t, k);
            for (int axis = 0; axis < 3; ++axis) {
                CHECK(std::fabs(p[axis]) <= hsr::random_triangles_extent);
            }
            const glm::vec4 clip = view_projection * glm::vec4(p, 1.0f);
            REQUIRE(clip.w > 0);
            for (int axis = 0; axis < 3; ++axis) CHECK(std::fabs(clip[axis]) <= clip.w);
        }
        const glm::vec3 a = corner(s, t, 0), b = corner(s, t, 1), c = corner(s, t, 2);
        const float longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        const float height = glm::length(glm::cross(b - a, c - a)) / longest;
        CHECK(height > 0.09f * longest);  // no slivers
        smallest = std::min(smallest, longest);
        largest = std::max(largest, longest);
        const float* rgb = &s.face_colors[3 * t];
        for (int k = 0; k < 3; ++k) CHECK((rgb[k] >= 0.0f && rgb[k] <= 1.0f));
        colors.insert({rgb[0], rgb[1], rgb[2]});
    }
    CHECK(colors.size() == s.triangle_count());
    CHECK(largest > 4 * smallest);  // a mix of sizes
}

TEST_CASE("random triangles: zero, and more than the limits allow, are errors", "[random-triangles]") {
    CHECK_THROWS_AS(hsr::make_random_triangles(0, 1), hsr::Error);
    hsr::Limits limits;
    limits.stored_triangles = 100;
    hsr::set_limits(limits);
    CHECK_THROWS_WITH(hsr::make_random_triangles(101, 1), Catch::Contains("stored-triangles"));
    CHECK(hsr::make_random_triangles(100, 1).triangle_count() == 100);
    hsr::set_limits(hsr::Limits{});
}

TEST_CASE("random triangles: bench model names random-N and random-N:SEED", "[random-triangles][bench]") {
    const hsr::bench::ModelSpec plain = hsr::bench::parse_model_spec("random-50", HSR_MODELS_DIR);
    CHECK(plain.random_triangles == 50);
    CHECK(plain.seed == 1);
    const hsr::bench::ModelSpec seeded = hsr::bench::parse_model_spec("random-50:99", HSR_MODELS_DIR);
    CHECK(seeded.seed == 99);
    const hsr::bench::BenchScene scene = hsr::bench::load_bench_scene(seeded);
    CHECK(scene_bytes(scene.scene) == scene_bytes(hsr::make_random_triangles(50, 99)));
    const hsr::bench::ModelSpec deep = hsr::bench::parse_model_spec("deep-2:random-20", HSR_MODELS_DIR);
    CHECK(hsr::bench::load_bench_scene(deep).scene.instances.size() > 0);
    for (const char* bad : {"random-", "random-0", "random-x", "random-5:", "random-5:-1", "random-5:x"})
        CHECK_THROWS_AS(hsr::bench::parse_model_spec(bad, HSR_MODELS_DIR), hsr::Error);
}

TEST_CASE("cli: --random-triangles renders a scene of many colours, the same for the same seed",
          "[random-triangles][cli]") {
    const fs::path dir = cli::scratch_dir();
    const std::string common = "render --random-triangles 40 -l facecolor --width 96 --height 96 ";
    REQUIRE(cli::run_hsr(common + "--seed 5 -o " + (dir / "rt5.png").string(), "rt5").status == 0);
    REQUIRE(cli::run_hsr(common + "--seed 5 -o " + (dir / "rt5b.png").string(), "rt5b").status == 0);
    REQUIRE(cli::run_hsr(common + "--seed 6 -o " + (dir / "rt6.png").string(), "rt6").status == 0);
    CHECK(cli::slurp(dir / "rt5.png") == cli::slurp(dir / "rt5b.png"));
    CHECK(cli::slurp(dir / "rt5.png") != cli::slurp(dir / "rt6.png"));
    const hsr::Image image = hsr::read_png_rgb(dir / "rt5.png");
    std::set<std::tuple<uint8_t, uint8_t, uint8_t>> colors;
    for (size_t p = 0; p < image.pixels.size(); p += 3)
        colors.insert({image.pixels[p], image.pixels[p + 1], image.pixels[p + 2]});
    CHECK(colors.size() >= 15);

    const cli::Run r = cli::run_hsr("render --random-triangles 10 -a appel -o " + (dir / "rt.svg").string(), "rt-lines");
    CHECK(r.status == 0);
}

TEST_CASE("cli: --random-triangles mistakes are one-line errors", "[random-triangles][cli]") {
    using cli::require_one_line_error;
    using cli::run_hsr;
    const std::string cube = std::string(HSR_MODELS_DIR) + "/cube.obj";
    require_one_line_error(run_hsr("render --random-triangles 0 -o x.png", "rt-zero"), "--random-triangles");
    require_one_line_error(run_hsr("render --random-triangles -3 -o x.png", "rt-negative"), "--random-triangles");
    require_one_line_error(run_hsr("render " + cube + " --random-triangles 5 -o x.png", "rt-and-model"),
                           "--random-triangles");
    require_one_line_error(run_hsr("render --surface x --random-triangles 5 -o x.png", "rt-and-surface"),
                           "--random-triangles");
    require_one_line_error(run_hsr("render " + cube + " --seed 3 -o x.png", "rt-seed-alone"), "--seed");
    require_one_line_error(run_hsr("render --random-triangles 5 --seed -1 -o x.png", "rt-seed-negative"), "--seed");
    require_one_line_error(run_hsr("render --random-triangles 5 --color 1/0/0 -o x.png", "rt-color"), "--color");
    require_one_line_error(run_hsr("render --random-triangles 1000 --limit stored-triangles=999 -o x.png", "rt-limit"),
                           "stored-triangles");
    require_one_line_error(run_hsr("bench --models random-0 -r 1 -w 0", "rt-bench-zero"), "random-0");
}
