// The plugin handshake and the C boundary: version checks, struct sizes, missing symbols,
// exceptions turned into status codes.
#include "hsr/error.hpp"
#include "hsr/plugin_registry.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

std::string test_plugin(const char* name) { return std::string(HSR_TEST_PLUGIN_DIR) + "/" + name + ".so"; }

std::string load_error(const std::string& path) {
    try {
        hsr::load_plugin_library(path);
    } catch (const hsr::Error& e) {
        return e.what();
    }
    return "";
}

// A one-triangle scene and matching buffers, enough to call render().
struct TinyFrame {
    float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t indices[3] = {0, 1, 2};
    float face_normals[3] = {0, 0, 1};
    float corner_normals[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    float face_colors[3] = {1, 1, 1};
    int32_t neighbors[3] = {-1, -1, -1};
    uint32_t objects[1] = {0};
    std::vector<float> depth = std::vector<float>(16, std::numeric_limits<float>::infinity());
    std::vector<uint32_t> face = std::vector<uint32_t>(16, HSR_NO_FACE);
    std::vector<float> bary = std::vector<float>(32, 0.0f);
    hsr_scene scene{};
    hsr_camera camera{};
    hsr_visibility_buffer target{};

    TinyFrame() {
        scene = {sizeof(hsr_scene), 3, 1, 1, positions, indices, face_normals, corner_normals, face_colors,
                 neighbors, objects, {0, 0, 0}, {1, 1, 0}};
        camera.struct_size = sizeof camera;
        camera.width = camera.height = 4;
        target = {sizeof target, 4, 4, depth.data(), face.data(), bary.data()};
    }
};

void collect(void* context, const char* name, uint64_t value) {
    static_cast<std::vector<std::pair<std::string, uint64_t>>*>(context)->emplace_back(name, value);
}

// handmade.c's plugins create, render (face 0 at depth 0.5 everywhere) and report one counter.
void require_handmade_renders(const hsr::Plugin& plugin) {
    hsr::HiddenSurfaceRemover remover(plugin, {{"level", "7"}});
    TinyFrame f;
    std::vector<std::pair<std::string, uint64_t>> counters;
    hsr_counter_sink sink{&counters, &collect};
    remover.render(f.scene, f.camera, f.target, &sink);
    CHECK(f.face[5] == 0u);
    CHECK(f.depth[5] == 0.5f);
    REQUIRE(counters.size() == 1);
    CHECK(counters[0] == std::pair<std::string, uint64_t>{"pixels-written", 16});
}

}  // namespace

TEST_CASE("a plugin built for another ABI major is refused with the reason", "[abi]") {
    const std::string message = load_error(test_plugin("wrong-major"));
    CHECK_THAT(message, Catch::Contains("wrong-major.so"));
    CHECK_THAT(message, Catch::Contains("built for ABI " + std::to_string(HSR_ABI_MAJOR + 1) + "."));
    CHECK_THAT(message, Catch::Contains("major versions must match"));
}

TEST_CASE("a plugin that needs a newer minor than the host is refused", "[abi]") {
    const std::string message = load_error(test_plugin("newer-minor"));
    CHECK_THAT(message, Catch::Contains("needs ABI 1." + std::to_string(HSR_ABI_MINOR + 1)));
    CHECK_THAT(message, Catch::Contains("update hsr"));
}

TEST_CASE("a plugin built against an older minor is accepted by a newer host", "[abi]") {
    // frozen-1.0.so is compiled against the ABI 1.0 header kept in tests/plugins/abi-1.0.
    auto plugins = hsr::load_plugin_library(test_plugin("frozen-1.0"));
    REQUIRE(plugins.size() == 1);
    const hsr_plugin_descriptor& d = plugins[0].descriptor;
    CHECK(d.abi_major == 1);
    CHECK(d.abi_minor == 0);
    CHECK(d.struct_size <= sizeof(hsr_plugin_descriptor));
    require_handmade_renders(plugins[0]);

    // The policy itself, for versions that do not exist yet (a simulated 1.9 host).
    CHECK(hsr::check_descriptor(d, 1, 9).empty());
    CHECK_THAT(hsr::check_descriptor(d, 2, 0), Catch::Contains("major versions must match"));
    hsr_plugin_descriptor newer = d;
    newer.abi_minor = 10;
    CHECK_THAT(hsr::check_descriptor(newer, 1, 9), Catch::Contains("needs ABI 1.10"));
}

TEST_CASE("fields beyond a table's struct_size are never read", "[abi]") {
    // short-tables' remover table stops before `extension` and leaves garbage there; the host must
    // treat the field as absent and still create and run the plugin.
    auto plugins = hsr::load_plugin_library(test_plugin("short-tables"));
    REQUIRE(plugins.size() == 1);
    require_handmade_renders(plugins[0]);
}

TEST_CASE("a library without the entry symbol is refused", "[abi]") {
    const std::string message = load_error(test_plugin("no-entry"));
    CHECK_THAT(message, Catch::Contains("not an hsr plugin"));
    CHECK_THAT(message, Catch::Contains("hsr_plugin_entry"));
}

TEST_CASE("a file that is not a library is refused, not crashed on", "[abi]") {
    CHECK_THAT(load_error(std::string(HSR_SOURCE_DIR) + "/README.md"), Catch::Contains("cannot load library"));
    CHECK_THAT(load_error("/nonexistent/plugin.so"), Catch::Contains("cannot load library"));
}

TEST_CASE("exceptions inside a plugin come back as errors", "[abi]") {
    auto plugins = hsr::load_plugin_library(test_plugin("throwing"));
    REQUIRE(plugins.size() == 1);
    TinyFrame f;

    SECTION("from render") {
        hsr::HiddenSurfaceRemover remover(plugins[0], {{"throw-in", "render"}});
        try {
            remover.render(f.scene, f.camera, f.target, nullptr);
            FAIL("render should have failed");
        } catch (const hsr::Error& e) {
            CHECK_THAT(e.what(), Catch::Contains("deliberate failure inside the plugin"));
            CHECK_THAT(e.what(), Catch::Contains("status 4"));
        }
    }
    SECTION("from create") {
        CHECK_THROWS_WITH((hsr::HiddenSurfaceRemover(plugins[0], {{"throw-in", "create"}})),
                          Catch::Contains("create") && Catch::Contains("deliberate failure"));
    }
    SECTION("an invalid argument keeps its status") {
        hsr::HiddenSurfaceRemover remover(plugins[0], {{"what", "invalid-argument"}});
        CHECK_THROWS_WITH(remover.render(f.scene, f.camera, f.target, nullptr),
                          Catch::Contains("status 1") && Catch::Contains("deliberate invalid argument"));
    }
    SECTION("a non-std exception") {
        hsr::HiddenSurfaceRemover remover(plugins[0], {{"what", "int"}});
        CHECK_THROWS_WITH(remover.render(f.scene, f.camera, f.target, nullptr), Catch::Contains("unknown exception"));
    }
    SECTION("out of memory") {
        hsr::HiddenSurfaceRemover remover(plugins[0], {{"what", "bad-alloc"}});
        CHECK_THROWS_WITH(remover.render(f.scene, f.camera, f.target, nullptr),
                          Catch::Contains("status 3") && Catch::Contains("out of memory"));
    }
    SECTION("counters reported before a failure-free call come through the sink") {
        hsr::HiddenSurfaceRemover remover(plugins[0], {{"throw-in", "nowhere"}});
        std::vector<std::pair<std::string, uint64_t>> counters;
        hsr_counter_sink sink{&counters, &collect};
        remover.render(f.scene, f.camera, f.target, &sink);
        CHECK(counters == std::vector<std::pair<std::string, uint64_t>>{{"calls", 1}});
    }
}

TEST_CASE("a lighting plugin cannot be used as a hidden-surface remover", "[abi]") {
    auto plugins = hsr::load_plugin_library(test_plugin("throwing"));
    CHECK_THROWS_WITH((hsr::LightingModel(plugins[0], {})), Catch::Contains("not a lighting model"));
}

TEST_CASE("the registry explains where it looked when a plugin is missing", "[abi]") {
    hsr::PluginRegistry registry;
    registry.scan_directory(HSR_TEST_PLUGIN_DIR);
    registry.scan_directory("/nonexistent-dir");
    // handmade (short-tables), frozen-1.0 and throwing load; the others are refused with reasons.
    CHECK(registry.plugins().size() == 3);
    CHECK(registry.rejected().size() == 3);
    try {
        registry.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, "octree-zbuffer");
        FAIL("find should have failed");
    } catch (const hsr::Error& e) {
        const std::string m = e.what();
        CHECK_THAT(m, Catch::Contains("no hidden-surface plugin named 'octree-zbuffer'"));
        CHECK_THAT(m, Catch::Contains(HSR_TEST_PLUGIN_DIR));
        CHECK_THAT(m, Catch::Contains("/nonexistent-dir"));
        CHECK_THAT(m, Catch::Contains("handmade") && Catch::Contains("throwing"));
    }
}
