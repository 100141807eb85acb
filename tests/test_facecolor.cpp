// facecolor's palettes (by=face, by=object) through the real ABI: faces that share an edge differ,
// objects differ, and by=given is the scene's own colours.
#include "face_colors.hpp"

#include "hsr/abi.h"
#include "hsr/instancing.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace {

std::vector<glm::vec3> colors_by(const std::string& by, const hsr::SceneData& scene, uint32_t instance = 0) {
    return test_colors::face_colors(scene, by, instance);
}

hsr::SceneData model(const char* name) { return hsr::load_model(std::string(HSR_MODELS_DIR) + "/" + name); }

}  // namespace

TEST_CASE("facecolor by=face: faces that share an edge differ, on the cube and the monkey", "[facecolor]") {
    for (const char* name : {"cube.obj", "octahedron.ply", "monkey.obj"}) {
        INFO(name);
        const hsr::SceneData scene = model(name);
        const std::vector<glm::vec3> colors = colors_by("face", scene);
        uint64_t edges = 0;
        for (uint32_t t = 0; t < scene.triangle_count(); ++t)
            for (int e = 0; e < 3; ++e) {
                const int32_t other = scene.edge_neighbors[3 * t + e];
                if (other < 0) continue;
                ++edges;
                CHECK(colors[t] != colors[uint32_t(other)]);
            }
        CHECK(edges > 0);
        std::set<std::tuple<float, float, float>> distinct;
        for (const glm::vec3& c : colors) distinct.insert({c.r, c.g, c.b});
        CHECK(distinct.size() >= std::min<size_t>(scene.triangle_count(), 4));
    }
    // The cube's 12 triangles take 12 different colours.
    const std::vector<glm::vec3> cube = colors_by("face", model("cube.obj"));
    std::set<std::tuple<float, float, float>> distinct;
    for (const glm::vec3& c : cube) distinct.insert({c.r, c.g, c.b});
    CHECK(distinct.size() == 12);
}

TEST_CASE("facecolor: the palette's 20 colours are far apart", "[facecolor]") {
    // 20 separate triangles: no neighbours, so face t takes palette colour t.
    hsr::SceneBuilder builder;
    for (int t = 0; t < 20; ++t) {
        const glm::vec3 corners[] = {{float(t), 0, 0}, {float(t) + 1, 0, 0}, {float(t), 1, 0}};
        builder.add_polygon(corners, glm::vec3(0.5f));
    }
    const std::vector<glm::vec3> colors = colors_by("face", builder.build());
    for (size_t a = 0; a < colors.size(); ++a)
        for (size_t b = a + 1; b < colors.size(); ++b) {
            INFO(a << " and " << b);
            CHECK(glm::length(colors[a] - colors[b]) > 0.08f);
        }
}

TEST_CASE("facecolor by=object: the boxes differ from each other, each box in one colour", "[facecolor]") {
    const hsr::SceneFile file = hsr::load_scene_file(std::string(HSR_MODELS_DIR) + "/boxes.scene");
    const hsr::SceneData& scene = file.scene;
    REQUIRE(scene.object_names.size() == 3);
    const std::vector<glm::vec3> colors = colors_by("object", scene);
    std::vector<std::set<std::tuple<float, float, float>>> per_object(3);
    for (uint32_t t = 0; t < scene.triangle_count(); ++t)
        per_object[scene.face_object[t]].insert({colors[t].r, colors[t].g, colors[t].b});
    for (const auto& set : per_object) CHECK(set.size() == 1);
    CHECK(*per_object[0].begin() != *per_object[1].begin());
    CHECK(*per_object[1].begin() != *per_object[2].begin());
    CHECK(*per_object[0].begin() != *per_object[2].begin());
    // None of them is the scene's own colour: the palette replaces it.
    CHECK(colors[0] != glm::vec3(scene.face_colors[0], scene.face_colors[1], scene.face_colors[2]));
}

TEST_CASE("facecolor by=object: each placed copy of an object in its own colour", "[facecolor]") {
    const hsr::SceneData grid = hsr::make_instance_grid(model("cube.obj"), {3, 1, 1, 0.5f, 0.0f});
    REQUIRE(grid.instances.size() == 3);
    std::set<std::tuple<float, float, float>> copies;
    for (uint32_t k = 0; k < 3; ++k) {
        const std::vector<glm::vec3> colors = colors_by("object", grid, k);
        for (const glm::vec3& c : colors) CHECK(c == colors[0]);
        copies.insert({colors[0].r, colors[0].g, colors[0].b});
    }
    CHECK(copies.size() == 3);
}

TEST_CASE("facecolor by=given, and no parameter, is the scene's own colour", "[facecolor]") {
    const hsr::SceneFile file = hsr::load_scene_file(std::string(HSR_MODELS_DIR) + "/boxes.scene");
    const hsr::SceneData& scene = file.scene;
    for (const std::string by : {"", "given"}) {
        const std::vector<glm::vec3> colors = colors_by(by, scene);
        for (uint32_t t = 0; t < scene.triangle_count(); ++t)
            CHECK(colors[t] == glm::vec3(scene.face_colors[3 * t], scene.face_colors[3 * t + 1],
                                         scene.face_colors[3 * t + 2]));
    }
}

TEST_CASE("facecolor: an unknown by= is refused", "[facecolor]") {
    CHECK_THROWS(hsr::LightingModel(test_colors::facecolor(), {{"by", "vertex"}}));
}
