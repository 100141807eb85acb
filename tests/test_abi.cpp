// The plugin handshake and the C boundary: version checks, struct sizes, missing symbols,
// exceptions turned into status codes.
#include "hsr/error.hpp"
#include "hsr/plugin_registry.hpp"

#include <catch2/catch.hpp>

#include <cstddef>
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

TEST_CASE("a plugin frozen at ABI 1.2 loads and renders, without steps", "[abi]") {
    // frozen-1.2.so is compiled against the ABI 1.2 header kept in tests/plugins/abi-1.2, from
    // before render_steps (1.3): its table ends at extension.
    auto plugins = hsr::load_plugin_library(test_plugin("frozen-1.2"));
    REQUIRE(plugins.size() == 1);
    CHECK(plugins[0].descriptor.abi_minor == 2);
    CHECK(static_cast<const IHiddenSurfaceRemover*>(plugins[0].descriptor.interface_table)->struct_size ==
          offsetof(IHiddenSurfaceRemover, render_steps));
    require_handmade_renders(plugins[0]);
    hsr::HiddenSurfaceRemover remover(plugins[0], {});
    CHECK_FALSE(remover.has_steps());
    TinyFrame f;
    const hsr_step_sink never{nullptr, [](void*, const hsr_step_event*) -> uint32_t { return 0; }};
    CHECK_THROWS_WITH(remover.render_steps(f.scene, f.camera, f.target, nullptr, never),
                      Catch::Contains("'frozen-1.2' cannot show its steps") && Catch::Contains("ABI 1.2"));
}

namespace {

// Steps seen by a sink that stops after step `stop_after` (0: never).
struct StepLog {
    uint64_t stop_after = 0;
    std::vector<std::string> types;
    std::vector<float> last_line;

    static uint32_t step(void* context, const hsr_step_event* e) {
        auto& log = *static_cast<StepLog*>(context);
        log.types.emplace_back(e->type);
        log.last_line.assign(e->lines, e->lines + 4 * e->line_count);
        return log.types.size() == log.stop_after ? 1 : 0;
    }
};

}  // namespace

TEST_CASE("a 1.3 plugin stops after the step the host asks for, leaving the buffer as it was then", "[abi]") {
    // handmade.c built against this header fills row y of the image in step y + 1.
    auto plugins = hsr::load_plugin_library(test_plugin("handmade-steps"));
    REQUIRE(plugins.size() == 1);
    hsr::HiddenSurfaceRemover remover(plugins[0], {});
    REQUIRE(remover.has_steps());
    for (uint64_t stop_after : {1, 2, 3, 4, 0}) {
        INFO("stop after step " << stop_after);
        TinyFrame f;
        StepLog log;
        log.stop_after = stop_after;
        const hsr_step_sink sink{&log, &StepLog::step};
        remover.render_steps(f.scene, f.camera, f.target, nullptr, sink);
        const uint64_t rows = stop_after == 0 ? 4 : stop_after;
        CHECK(log.types == std::vector<std::string>(rows, "row"));
        CHECK(log.last_line == std::vector<float>{0.0f, rows - 0.5f, 4.0f, rows - 0.5f});
        for (uint32_t p = 0; p < 16; ++p) CHECK(f.face[p] == (p / 4 < rows ? 0u : HSR_NO_FACE));
    }
}

TEST_CASE("a plugin frozen at ABI 1.1 still loads and runs in a newer host", "[abi]") {
    // frozen-1.1.so is compiled against the ABI 1.1 header kept in tests/plugins/abi-1.1, from
    // before hidden-line removers (1.2) were added.
    auto plugins = hsr::load_plugin_library(test_plugin("frozen-1.1"));
    REQUIRE(plugins.size() == 1);
    const hsr_plugin_descriptor& d = plugins[0].descriptor;
    CHECK(d.abi_major == 1);
    CHECK(d.abi_minor == 1);
    CHECK(HSR_ABI_MINOR >= 2);
    require_handmade_renders(plugins[0]);
}

namespace {

struct CollectedLines {
    std::vector<float> points;
    std::vector<uint32_t> edge, flags;
    std::vector<int32_t> qi;
    uint32_t batches = 0;
    std::vector<std::string> events;
};

hsr_status collect_segments(void* context, const hsr_segment_batch* batch) {
    auto& out = *static_cast<CollectedLines*>(context);
    ++out.batches;
    out.points.insert(out.points.end(), batch->points, batch->points + 4 * batch->count);
    out.edge.insert(out.edge.end(), batch->edge, batch->edge + batch->count);
    out.flags.insert(out.flags.end(), batch->flags, batch->flags + batch->count);
    out.qi.insert(out.qi.end(), batch->qi, batch->qi + batch->count);
    return HSR_OK;
}

hsr_status refuse_segments(void*, const hsr_segment_batch*) { return HSR_ERROR_OUT_OF_MEMORY; }

void collect_event(void* context, const hsr_trace_event* e) {
    static_cast<CollectedLines*>(context)->events.push_back(std::string(e->type) + " " + std::to_string(e->edge));
}

}  // namespace

TEST_CASE("a hidden-line plugin (ABI 1.2) returns segments in batches, with trace events", "[abi]") {
    auto plugins = hsr::load_plugin_library(test_plugin("handmade-lines"));
    REQUIRE(plugins.size() == 1);
    CHECK(plugins[0].descriptor.kind == HSR_KIND_HIDDEN_LINE_REMOVER);
    CHECK(std::string(hsr::kind_name(plugins[0].descriptor.kind)) == "hidden-line");
    hsr::HiddenLineRemover remover(plugins[0], {});

    // The tiny triangle seen by an identity camera on a 4 x 4 image: clip = world.
    TinyFrame f;
    for (int k = 0; k < 16; ++k) f.camera.view_projection[k] = (k % 5 == 0) ? 1.0f : 0.0f;
    const uint32_t vertices[] = {0, 1, 1, 2, 2, 0, 0, 1};
    const uint32_t faces[] = {0, HSR_NO_FACE, 0, HSR_NO_FACE, 0, HSR_NO_FACE, 0, HSR_NO_FACE};
    const uint32_t flags[] = {HSR_EDGE_BOUNDARY, HSR_EDGE_BOUNDARY, HSR_EDGE_BOUNDARY | HSR_EDGE_SILHOUETTE,
                              HSR_EDGE_BOUNDARY};
    hsr_line_request request{sizeof request, 4, vertices, faces, flags, 0};
    CollectedLines lines;
    hsr_segment_sink sink{&lines, &collect_segments};
    hsr_trace_sink trace{&lines, &collect_event};
    std::vector<std::pair<std::string, uint64_t>> counters;
    hsr_counter_sink counter_sink{&counters, &collect};
    remover.render_lines(f.scene, f.camera, request, sink, &trace, &counter_sink);

    CHECK(lines.batches == 2);  // 3 + 1
    REQUIRE(lines.edge == std::vector<uint32_t>{0, 1, 2, 3});
    CHECK(lines.flags[2] == (HSR_EDGE_BOUNDARY | HSR_EDGE_SILHOUETTE));
    CHECK(lines.qi == std::vector<int32_t>{0, 0, 0, 0});
    // Edge 0 runs from world (0,0) = window (2,2) to world (1,0) = window (4,2).
    CHECK(lines.points[0] == 2.0f);
    CHECK(lines.points[1] == 2.0f);
    CHECK(lines.points[2] == 4.0f);
    CHECK(lines.points[3] == 2.0f);
    CHECK(lines.events == std::vector<std::string>{"edge-begin 0", "edge-begin 1", "edge-begin 2", "edge-begin 3"});
    REQUIRE(counters.size() == 1);
    CHECK(counters[0] == std::pair<std::string, uint64_t>{"edges-in", 4});

    // Without a trace sink it still runs; a sink that refuses a batch stops it with an error.
    CollectedLines untraced;
    hsr_segment_sink untraced_sink{&untraced, &collect_segments};
    remover.render_lines(f.scene, f.camera, request, untraced_sink, nullptr, nullptr);
    CHECK(untraced.edge.size() == 4);
    hsr_segment_sink refusing{nullptr, &refuse_segments};
    CHECK_THROWS_WITH(remover.render_lines(f.scene, f.camera, request, refusing, nullptr, nullptr),
                      Catch::Contains("handmade-lines") && Catch::Contains("render_lines"));
    // It is not a hidden-surface remover.
    CHECK_THROWS_WITH(hsr::HiddenSurfaceRemover(plugins[0], {}), Catch::Contains("not a hidden-surface remover"));
}

TEST_CASE("a hidden-line plugin claiming an ABI before 1.2 is refused", "[abi]") {
    const std::string message = load_error(test_plugin("lines-claiming-1.1"));
    CHECK_THAT(message, Catch::Contains("hidden-line plugins came with ABI 1.2"));
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
    // handmade (short-tables), handmade-steps, frozen-1.0, frozen-1.1, frozen-1.2, frozen-1.3,
    // handmade-lines and throwing load; the others (wrong-major, newer-minor, no-entry,
    // lines-claiming-1.1) are refused with reasons.
    CHECK(registry.plugins().size() == 8);
    CHECK(registry.rejected().size() == 4);
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
