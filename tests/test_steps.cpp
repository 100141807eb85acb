// Rendering step by step (ABI 1.3 render_steps) with the four z-buffer plugins, through the host
// (resolve_visibility_steps) and the CLI (hsr render --step N).
//
// Every run is checked against an answer found another way:
//  - run to the end, or stopped after its last step, the visibility buffer (depth, face,
//    barycentrics, instance, per-pixel depth tests) is byte for byte the plain render's;
//  - stopped after step k it is a prefix of the work: for zbuffer, the plain zbuffer render of a
//    scene holding only the first k triangles; for scanline-zbuffer, the plain render's rows above
//    row k and nothing below; for every plugin, step k + 1 changes only pixels of its own triangle
//    (or of its own row), adds exactly its depth tests to the per-pixel counts, and no covered pixel
//    is uncovered or moved farther by a later step;
//  - every step event is well formed: a type and a text, lines finite and inside the image, valid
//    roles, a level where a pyramid decided, buffers of the sizes they claim, and pixel counts that
//    add up to the plugin's counters.
#include "cli_support.hpp"
#include "hsr/abi.h"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <limits>
#include <numeric>
#include <regex>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace surface_tests;

// A scene and a camera to render it with.
struct Case {
    std::string name;
    hsr_scene scene;
    hsr_camera camera;
};

// Two cameras per scene: a perspective one at an odd aspect, and an orthographic one from below.
void add_cases(std::vector<Case>& cases, const std::string& name, const hsr::SceneData& data) {
    cases.push_back({name + " perspective", data.view(), orbit(data, 30.0f, 20.0f, 1.2f, false, 96, 72)});
    cases.push_back({name + " orthographic", data.view(), orbit(data, -110.0f, -35.0f, 1.0f, true, 64, 80)});
}

// The scenes in models/ (cube, boxes.scene) and a grid of instanced cubes.
std::vector<Case> committed_cases() {
    static const hsr::SceneData grid = hsr::make_instance_grid(model("cube.obj"), {3, 2, 4, 0.1f, 25.0f});
    std::vector<Case> cases;
    add_cases(cases, "cube", model("cube.obj"));
    add_cases(cases, "boxes.scene", model("boxes.scene"));
    add_cases(cases, "instanced cubes", grid);
    return cases;
}

// The fetched models (skipped when absent) and a grid of instanced monkeys.
std::vector<Case> fetched_cases() {
    test_models::require_fetched();
    static const hsr::SceneData grid = hsr::make_instance_grid(model("monkey.obj"), {3, 2, 3, 0.05f, 25.0f});
    std::vector<Case> cases;
    add_cases(cases, "monkey", model("monkey.obj"));
    add_cases(cases, "bunny", model("bunny.obj"));
    add_cases(cases, "instanced monkeys", grid);
    return cases;
}

const char* const kPlugins[] = {"zbuffer", "scanline-zbuffer", "hierarchical-zbuffer", "octree-zbuffer"};

// The host's run of `name` step by step, stopped after step stop_after (0: every step), with
// per-pixel depth-test counts.
hsr::Frame run_steps(const std::string& name, const Case& c, uint64_t stop_after) {
    hsr::HiddenSurfaceRemover remover(plugin(name), {});
    REQUIRE(remover.has_steps());
    hsr::Frame frame;
    hsr::resolve_visibility_steps(c.scene, c.camera, remover, frame, stop_after, true);
    REQUIRE(frame.steps.has_value());
    return frame;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void require_same_visibility(const hsr::Frame& a, const hsr::Frame& b) {
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    CHECK(same_bytes(a.depth, b.depth));
    CHECK(same_bytes(a.face, b.face));
    CHECK(same_bytes(a.bary, b.bary));
    CHECK(same_bytes(a.instance, b.instance));
    CHECK(same_bytes(a.depth_tests, b.depth_tests));
}

// The visibility buffer as the host clears it, before any step.
hsr::Frame cleared(const Case& c) {
    hsr::Frame f;
    f.width = c.camera.width;
    f.height = c.camera.height;
    const size_t pixels = size_t(f.width) * f.height;
    f.depth.assign(pixels, std::numeric_limits<float>::infinity());
    f.face.assign(pixels, HSR_NO_FACE);
    f.bary.assign(2 * pixels, 0.0f);
    f.instance.assign(c.scene.instance_count > 0 ? pixels : 0, 0);
    f.depth_tests.assign(pixels, 0);
    return f;
}

uint64_t covered(const hsr::Frame& f) {
    return uint64_t(std::count_if(f.face.begin(), f.face.end(), [](uint32_t t) { return t != HSR_NO_FACE; }));
}

uint64_t total_tests(const hsr::Frame& f) {
    return std::accumulate(f.depth_tests.begin(), f.depth_tests.end(), uint64_t(0));
}

// Pixel p differs between the two frames in anything the visibility buffer holds but the counts.
bool pixel_differs(const hsr::Frame& a, const hsr::Frame& b, size_t p) {
    return a.face[p] != b.face[p] || std::memcmp(&a.depth[p], &b.depth[p], sizeof(float)) != 0 ||
           std::memcmp(&a.bary[2 * p], &b.bary[2 * p], 2 * sizeof(float)) != 0 ||
           (!a.instance.empty() && a.instance[p] != b.instance[p]);
}

// Later is the same render stopped at a later step (or run to the end): every pixel covered in
// `earlier` is covered there too, at a depth no farther; counts of depth tests never go down.
void require_later_work(const hsr::Frame& earlier, const hsr::Frame& later) {
    size_t uncovered = 0, farther = 0, fewer_tests = 0;
    for (size_t p = 0; p < earlier.face.size(); ++p) {
        if (earlier.face[p] != HSR_NO_FACE) {
            if (later.face[p] == HSR_NO_FACE) ++uncovered;
            else if (later.depth[p] > earlier.depth[p]) ++farther;
        }
        if (later.depth_tests[p] < earlier.depth_tests[p]) ++fewer_tests;
    }
    CHECK(uncovered == 0);
    CHECK(farther == 0);
    CHECK(fewer_tests == 0);
    CHECK(covered(later) >= covered(earlier));
}

// Step k + 1 (`after`, which stopped there) against step k (`before`): it changed only pixels that
// now show its own triangle (a triangle step), or none (a node or instance step), or only pixels
// of its row (a scanline step); it added exactly its depth tests, and wrote no more pixels than
// its depth tests passed.
void require_one_step(const hsr::Frame& before, const hsr::Frame& after) {
    const hsr::StepRecord& step = after.steps->last;
    INFO("step " << step.index << ": " << step.text);
    size_t changed = 0, foreign = 0;
    const size_t width = after.width;
    for (size_t p = 0; p < after.face.size(); ++p) {
        if (!pixel_differs(before, after, p)) continue;
        ++changed;
        if (step.type == "scanline") {
            if (p / width != step.index - 1) ++foreign;
        } else if (step.face == HSR_NO_FACE || after.face[p] != step.face ||
                   (!after.instance.empty() && after.instance[p] != step.instance)) {
            ++foreign;
        }
    }
    CHECK(foreign == 0);
    CHECK(changed <= step.pixels_written);
    CHECK(total_tests(after) - total_tests(before) == step.pixels_written + step.pixels_rejected);
}

// The scene drawn up to its k-th triangle in drawing order (placement after placement): the same
// arrays with fewer triangles, or fewer instances, the last one cut short.
struct Prefix {
    hsr_scene scene{};
    std::vector<hsr_instance> instances;
};
void first_triangles(const hsr_scene& scene, uint64_t k, Prefix& out) {
    out.scene = scene;
    if (scene.instance_count == 0) {
        out.scene.triangle_count = uint32_t(std::min<uint64_t>(k, scene.triangle_count));
        return;
    }
    out.instances.clear();
    for (uint32_t i = 0; i < scene.instance_count && k > 0; ++i) {
        hsr_instance instance = *HSR_ELEMENT(hsr_instance, scene.instances, i);
        instance.triangle_count = uint32_t(std::min<uint64_t>(instance.triangle_count, k));
        k -= instance.triangle_count;
        out.instances.push_back(instance);
    }
    out.scene.instance_count = uint32_t(out.instances.size());
    out.scene.instances = out.instances.data();
}

// Plugin-specific: what the picture after step k (of `taken`) must be, found without steps.
void require_prefix(const std::string& name, const Case& c, const hsr::Frame& at_k, const hsr::Frame& full,
                    uint64_t k) {
    if (name == "zbuffer") {
        Prefix prefix;
        first_triangles(c.scene, k, prefix);
        const hsr::Frame expected = render("zbuffer", prefix.scene, c.camera, {}, true);
        require_same_visibility(at_k, expected);
    } else if (name == "scanline-zbuffer") {
        // Rows 0 .. k-1 as in the full render, nothing at or below row k.
        const size_t width = full.width, split = std::min<size_t>(k, full.height) * width;
        size_t wrong_above = 0, written_below = 0;
        for (size_t p = 0; p < full.face.size(); ++p) {
            if (p < split) {
                wrong_above += pixel_differs(at_k, full, p) || at_k.depth_tests[p] != full.depth_tests[p];
            } else {
                written_below += at_k.face[p] != HSR_NO_FACE || at_k.depth_tests[p] != 0 ||
                                 at_k.depth[p] != std::numeric_limits<float>::infinity();
            }
        }
        CHECK(wrong_above == 0);
        CHECK(written_below == 0);
    }
}

// The steps to stop after: the first ones, a few in between, the one before the last.
std::vector<uint64_t> stops_between(uint64_t taken) {
    std::set<uint64_t> ks;
    for (const uint64_t k : {uint64_t(1), uint64_t(2), taken / 5, taken / 3, taken / 2, 2 * taken / 3, taken - 1})
        if (k >= 1 && k < taken) ks.insert(k);
    return {ks.begin(), ks.end()};
}

void check_runs(const std::string& name, const std::vector<Case>& cases) {
    for (const Case& c : cases) {
        INFO(name << " on " << c.name);
        hsr::Frame plain;
        {
            hsr::HiddenSurfaceRemover remover(plugin(name), {});
            hsr::resolve_visibility(c.scene, c.camera, remover, plain, true);
        }
        REQUIRE(covered(plain) > 0);

        const hsr::Frame full = run_steps(name, c, 0);
        const uint64_t taken = full.steps->taken;
        CHECK(taken > 2);
        CHECK_FALSE(full.steps->stopped);
        require_same_visibility(full, plain);
        if (name == "scanline-zbuffer") CHECK(taken == c.camera.height);

        const hsr::Frame last = run_steps(name, c, taken);
        CHECK(last.steps->taken == taken);
        CHECK(last.steps->stopped);
        require_same_visibility(last, plain);

        const hsr::Frame* previous = nullptr;
        std::deque<hsr::Frame> frames;
        for (const uint64_t k : stops_between(taken)) {
            INFO("stopped after step " << k << " of " << taken);
            const hsr::Frame& at_k = frames.emplace_back(run_steps(name, c, k));
            CHECK(at_k.steps->taken == k);
            CHECK(at_k.steps->stopped);
            CHECK(at_k.steps->last.index == k);
            require_prefix(name, c, at_k, full, k);
            require_one_step(k == 1 ? cleared(c) : run_steps(name, c, k - 1), at_k);
            if (previous != nullptr) require_later_work(*previous, at_k);
            previous = &at_k;
        }
        if (previous != nullptr) require_later_work(*previous, full);
    }
}

// ---------------------------------------------------------------------------------------------- //
// Every event of a run, checked as it comes

// Lower-case words (letters, or letters and digits) joined by '-'.
bool is_words(const std::string& text, bool digits) {
    bool word = false;
    for (const char ch : text) {
        if ((ch >= 'a' && ch <= 'z') || (digits && ch >= '0' && ch <= '9')) {
            word = true;
        } else if (ch == '-' && word) {
            word = false;
        } else {
            return false;
        }
    }
    return word;
}

struct EventCheck {
    uint32_t width = 0, height = 0;
    uint32_t triangles = 0, instances = 0;
    uint64_t events = 0, written = 0, rejected = 0;
    uint64_t bad = 0;
    std::string first_bad;
    std::vector<std::string> types;  // one per event
    std::vector<uint32_t> levels;
    std::vector<std::string> texts;

    void fail(const std::string& why, const hsr_step_event& e) {
        if (bad++ == 0) first_bad = "event " + std::to_string(events) + " (" + (e.text ? e.text : "") + "): " + why;
    }

    static uint32_t step(void* context, const hsr_step_event* event) {
        static_cast<EventCheck*>(context)->check(*event);
        return 0;
    }

    void check(const hsr_step_event& e) {
        ++events;
        if (e.struct_size < sizeof(hsr_step_event)) fail("struct_size", e);
        const std::string type = e.type != nullptr ? e.type : "";
        if (!is_words(type, false)) fail("type '" + type + "'", e);
        if (e.text == nullptr || e.text[0] == '\0') fail("no text", e);
        types.push_back(type);
        levels.push_back(e.level);
        texts.push_back(e.text != nullptr ? e.text : "");
        if (e.face != HSR_NO_FACE && e.face >= triangles) fail("face out of range", e);
        if (instances == 0 ? e.instance != 0 : e.instance >= instances) fail("instance out of range", e);
        if (e.line_count > 0 && e.lines == nullptr) fail("line_count without lines", e);
        const float margin = 1.0f;
        for (uint32_t k = 0; k < e.line_count && e.lines != nullptr; ++k) {
            for (int j = 0; j < 4; ++j) {
                const float v = e.lines[4 * k + j];
                const float limit = (j % 2 == 0 ? float(width) : float(height)) + margin;
                if (!std::isfinite(v) || v < -margin || v > limit) {
                    fail("line " + std::to_string(k) + " leaves the image: " + std::to_string(v), e);
                    break;
                }
            }
            if (e.line_roles != nullptr && e.line_roles[k] > HSR_STEP_CONTEXT) fail("role", e);
        }
        for (uint32_t b = 0; b < e.buffer_count; ++b) {
            const hsr_step_buffer& buffer = e.buffers[b];
            const std::string name = buffer.name != nullptr ? buffer.name : "";
            if (!is_words(name, true)) fail("buffer name '" + name + "'", e);
            if (buffer.width == 0 || buffer.height == 0 || buffer.values == nullptr) fail("empty buffer", e);
            // A z-pyramid level k has ceil(size / 2^k) cells a side, each a depth or +infinity.
            if (name.rfind("z-pyramid-", 0) == 0) {
                const int level = std::stoi(name.substr(10));
                const uint32_t cell = 1u << level;
                if (buffer.width != (width + cell - 1) / cell || buffer.height != (height + cell - 1) / cell)
                    fail("pyramid level size of " + name, e);
            }
            for (size_t i = 0; i < size_t(buffer.width) * buffer.height; ++i) {
                const float v = buffer.values[i];
                if (!(v == std::numeric_limits<float>::infinity() || (v >= 0.0f && v <= 1.0f))) {
                    fail("value " + std::to_string(v) + " in " + name, e);
                    break;
                }
            }
        }
        if (e.buffer_count > 0) {  // a pyramid's levels: consecutive, up to one cell
            const hsr_step_buffer& top = e.buffers[e.buffer_count - 1];
            if (top.width != 1 || top.height != 1) fail("the last pyramid level is not one cell", e);
        }
        written += e.pixels_written;
        rejected += e.pixels_rejected;
    }
};

void check_events(const std::string& name, const std::vector<Case>& cases) {
    for (const Case& c : cases) {
        INFO(name << " on " << c.name);
        hsr::HiddenSurfaceRemover remover(plugin(name), {});
        hsr::Frame frame = cleared(c);
        hsr_visibility_buffer target{sizeof(hsr_visibility_buffer), c.camera.width, c.camera.height,
                                     frame.depth.data(),           frame.face.data(), frame.bary.data(),
                                     frame.instance.empty() ? nullptr : frame.instance.data(), nullptr};
        std::vector<std::pair<std::string, uint64_t>> counters;
        const hsr_counter_sink counter_sink{&counters, [](void* context, const char* n, uint64_t v) {
                                                static_cast<decltype(counters)*>(context)->emplace_back(n, v);
                                            }};
        EventCheck check;
        check.width = c.camera.width;
        check.height = c.camera.height;
        check.triangles = c.scene.triangle_count;
        check.instances = c.scene.instance_count;
        const hsr_step_sink sink{&check, &EventCheck::step};
        remover.render_steps(c.scene, c.camera, target, &counter_sink, sink);
        auto counter = [&](const std::string& n) {
            for (const auto& [key, value] : counters)
                if (key == n) return value;
            FAIL("no counter " << n);
            return uint64_t(0);
        };

        INFO(check.first_bad);
        CHECK(check.bad == 0);
        CHECK(check.events == counter("steps"));
        CHECK(check.written == counter("pixels-written"));
        CHECK(check.written + check.rejected == counter("pixels-depth-tested"));

        auto count_type = [&](const std::string& type) {
            return uint64_t(std::count(check.types.begin(), check.types.end(), type));
        };
        uint64_t drawn = c.scene.triangle_count;
        if (c.scene.instance_count > 0) {
            drawn = 0;
            for (uint32_t i = 0; i < c.scene.instance_count; ++i)
                drawn += HSR_ELEMENT(hsr_instance, c.scene.instances, i)->triangle_count;
        }
        if (name == "zbuffer") {
            CHECK(count_type("triangle") == drawn);
            CHECK(check.events == drawn);
        } else if (name == "scanline-zbuffer") {
            CHECK(count_type("scanline") == c.camera.height);
            CHECK(check.events == c.camera.height);
        } else if (name == "hierarchical-zbuffer") {
            CHECK(count_type("triangle") == drawn - counter("triangles-in-skipped-instances"));
            CHECK(count_type("instance-culled") == counter("instances-culled"));
            CHECK(count_type("instance-outside") == counter("instances-outside"));
            CHECK(check.events == count_type("triangle") + count_type("instance-culled") +
                                      count_type("instance-outside"));
        } else if (name == "octree-zbuffer") {
            CHECK(count_type("node-visited") + count_type("node-culled") ==
                  counter("octree-nodes-visited") + counter("instance-nodes-visited"));
            CHECK(count_type("node-culled") == counter("octree-nodes-culled") + counter("octree-nodes-outside") +
                                                   counter("instance-nodes-culled") +
                                                   counter("instance-nodes-outside"));
            CHECK(check.events == count_type("triangle") + count_type("node-visited") + count_type("node-culled"));
        }
        // A rejection by a pyramid names its level.
        for (size_t i = 0; i < check.types.size(); ++i) {
            const std::string& text = check.texts[i];
            if (text.find("z-pyramid at level") != std::string::npos ||
                text.find("z-pyramid level") != std::string::npos) {
                INFO(text);
                CHECK(check.levels[i] != HSR_NO_LEVEL);
                CHECK(text.find("level " + std::to_string(check.levels[i])) != std::string::npos);
            }
        }
    }
}

}  // namespace

TEST_CASE("steps: every plugin of the z-buffer family has steps", "[steps]") {
    for (const char* name : kPlugins) {
        hsr::HiddenSurfaceRemover remover(plugin(name), {});
        CHECK(remover.has_steps());
    }
}

TEST_CASE("steps: zbuffer step by step, on the committed models", "[steps]") {
    check_runs("zbuffer", committed_cases());
}
TEST_CASE("steps: scanline-zbuffer step by step, on the committed models", "[steps]") {
    check_runs("scanline-zbuffer", committed_cases());
}
TEST_CASE("steps: hierarchical-zbuffer step by step, on the committed models", "[steps]") {
    check_runs("hierarchical-zbuffer", committed_cases());
}
TEST_CASE("steps: octree-zbuffer step by step, on the committed models", "[steps]") {
    check_runs("octree-zbuffer", committed_cases());
}

TEST_CASE("steps: zbuffer step by step, on monkey and bunny", "[steps]") {
    check_runs("zbuffer", fetched_cases());
}
TEST_CASE("steps: scanline-zbuffer step by step, on monkey and bunny", "[steps]") {
    check_runs("scanline-zbuffer", fetched_cases());
}
TEST_CASE("steps: hierarchical-zbuffer step by step, on monkey and bunny", "[steps]") {
    check_runs("hierarchical-zbuffer", fetched_cases());
}
TEST_CASE("steps: octree-zbuffer step by step, on monkey and bunny", "[steps]") {
    check_runs("octree-zbuffer", fetched_cases());
}

TEST_CASE("steps: the events of every plugin are well formed and add up, on the committed models", "[steps]") {
    for (const char* name : kPlugins) check_events(name, committed_cases());
}

TEST_CASE("steps: the events of every plugin are well formed and add up, on monkey and bunny", "[steps]") {
    for (const char* name : kPlugins) check_events(name, fetched_cases());
}

// ---------------------------------------------------------------------------------------------- //
// hsr render --step N

namespace {

// The number of steps `hsr render <args>` has, from its answer to a step beyond the last.
uint64_t steps_of(const std::string& args, const std::string& tag) {
    const std::string out = (cli::scratch_dir() / (tag + ".png")).string();
    const cli::Run r = cli::run_hsr(args + " --step 1000000000 -o " + out, tag);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const std::smatch m = [&] {
        std::smatch found;
        std::regex_search(r.err, found, std::regex("ended after step ([0-9]+), before step 1000000000"));
        return found;
    }();
    REQUIRE(m.size() == 2);
    return std::stoull(m[1].str());
}

}  // namespace

TEST_CASE("steps: hsr render --step N of the last step writes the plain render's PNG", "[steps][cli]") {
    const std::string models = std::string(HSR_MODELS_DIR) + "/";
    // Every remover with steps whose plain picture is one surface per pixel (a-buffer's is
    // composited from its fragment lists).
    const char* const removers[] = {"zbuffer", "scanline-zbuffer", "hierarchical-zbuffer", "octree-zbuffer",
                                    "warnock", "weiler-atherton", "raycast", "painter", "painter:mode=naive", "bsp", "bsp:order=front-to-back"};
    for (const char* name : removers) {
        for (const char* model_file : {"cube.obj", "boxes.scene"}) {
            INFO(name << " on " << model_file);
            const std::string tag = std::string("step-") + name + "-" + model_file;
            const std::string args =
                "render " + models + model_file + " --width 72 --height 56 -a " + name;
            const uint64_t last = steps_of(args, tag + "-count");
            const std::filesystem::path stepped = cli::scratch_dir() / (tag + "-last.png");
            const std::filesystem::path plain = cli::scratch_dir() / (tag + "-plain.png");
            const cli::Run a =
                cli::run_hsr(args + " --step " + std::to_string(last) + " -o " + stepped.string(), tag + "-last");
            const cli::Run b = cli::run_hsr(args + " -o " + plain.string(), tag + "-plain");
            INFO(a.err << b.err);
            REQUIRE(a.status == 0);
            REQUIRE(b.status == 0);
            CHECK_THAT(a.err, Catch::StartsWith("step " + std::to_string(last) + ": "));
            const std::string bytes = cli::slurp(stepped);
            CHECK(!bytes.empty());
            CHECK(bytes == cli::slurp(plain));
        }
    }
}

TEST_CASE("steps: hsr render --step refuses 0 and hidden-line plugins with one line and exit 2", "[steps][cli]") {
    const std::string cube = std::string(HSR_MODELS_DIR) + "/cube.obj";
    const std::string out = (cli::scratch_dir() / "refused.png").string();
    const cli::Run zero = cli::run_hsr("render " + cube + " --step 0 -o " + out, "step-zero");
    cli::require_one_line_error(zero, "--step 0");
    CHECK(zero.status == 2);
    const std::string svg = (cli::scratch_dir() / "refused.svg").string();
    const cli::Run lines = cli::run_hsr("render " + cube + " -a roberts --step 3 -o " + svg, "step-lines");
    cli::require_one_line_error(lines, "--step is for hidden-surface plugins");
    CHECK(lines.status == 2);
}

TEST_CASE("steps: hsr render --step A..B writes each step's picture as --step k alone does", "[steps][cli]") {
    const std::string cube = std::string(HSR_MODELS_DIR) + "/cube.obj";
    const std::string args = "render " + cube + " --width 48 --height 40 -a zbuffer";
    const std::filesystem::path folder = cli::scratch_dir() / "step-range";
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    const cli::Run range = cli::run_hsr(args + " --step 1..4 -o " + (folder / "step-%03d.png").string(), "step-range");
    INFO(range.err);
    REQUIRE(range.status == 0);
    // Frames count from 0: the range's k-th picture is step 1 + k.
    std::size_t files = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder)) ++files;
    CHECK(files == 4);
    for (int k = 0; k < 4; ++k) {
        const std::filesystem::path alone = cli::scratch_dir() / ("step-alone-" + std::to_string(1 + k) + ".png");
        const cli::Run single = cli::run_hsr(args + " --step " + std::to_string(1 + k) + " -o " + alone.string(),
                                             "step-alone");
        REQUIRE(single.status == 0);
        char name[32];
        std::snprintf(name, sizeof name, "step-%03d.png", k);
        const std::string bytes = cli::slurp(folder / name);
        INFO(name);
        CHECK(!bytes.empty());
        CHECK(bytes == cli::slurp(alone));
    }
    // Steps 1 and 4 differ (step 2 draws a face), or the comparison above could not tell steps apart.
    CHECK(cli::slurp(folder / "step-000.png") != cli::slurp(folder / "step-003.png"));
}

TEST_CASE("steps: hsr render --step refuses bad ranges with one line and exit 2", "[steps][cli]") {
    const std::string cube = std::string(HSR_MODELS_DIR) + "/cube.obj";
    const std::string out = (cli::scratch_dir() / "range-%03d.png").string();
    const std::pair<const char*, const char*> cases[] = {{"0..3", "steps count from 1"},
                                                          {"5..2", "ends before it starts"},
                                                          {"1..5000", "at most 1000"},
                                                          {"1..99999999999999999999", "expected a step number"},
                                                          {"2..x", "expected a step number"}};
    for (const auto& [range, message] : cases) {
        INFO(range);
        const cli::Run run = cli::run_hsr("render " + cube + " --step " + range + " -o " + out, "step-bad-range");
        cli::require_one_line_error(run, message);
        CHECK(run.status == 2);
    }
    const std::string single = (cli::scratch_dir() / "range-single.png").string();
    const cli::Run unnumbered = cli::run_hsr("render " + cube + " --step 1..2 -o " + single, "step-range-name");
    cli::require_one_line_error(unnumbered, "need a frame number");
    CHECK(unnumbered.status == 2);
}

TEST_CASE("step outline: runs of one type and phase and level with their first steps and caps", "[steps]") {
    hsr::StepOutline outline;
    outline.max_runs = 5;
    int texts = 0;
    auto text = [&texts] { return "text " + std::to_string(++texts); };
    // Steps 1..9: a a a | b | b(q) | b(q, level 2) | a(q, 2) | c c
    for (int i = 0; i < 3; ++i) outline.add("a", "p", 1, text);
    outline.add("b", "p", 1, text);
    outline.add("b", "q", 1, text);
    outline.add("b", "q", 2, text);
    outline.add("a", "q", 2, text);
    outline.add("c", "q", 2, text);
    outline.add("c", "q", 2, text);
    CHECK(outline.total == 9);
    CHECK(outline.truncated);
    REQUIRE(outline.runs.size() == 5);
    const uint64_t firsts[] = {1, 4, 5, 6, 7}, counts[] = {3, 1, 1, 1, 1};
    for (std::size_t k = 0; k < 5; ++k) {
        CHECK(outline.runs[k].first == firsts[k]);
        CHECK(outline.runs[k].count == counts[k]);
    }
    CHECK(outline.types[outline.runs[1].type] == "b");
    CHECK(outline.phases[outline.runs[2].phase] == "q");
    CHECK(outline.runs[3].level == 2);
    // Past the cap the first step of a type is still found: c at step 8.
    CHECK(outline.firsts.at("type:c").step == 8);
    CHECK(outline.firsts.at("type:b").step == 4);
    CHECK(outline.firsts.at("phase:q").step == 5);
    CHECK(outline.firsts.at("phase:q").text == "text 3");
    CHECK(texts == 4);  // asked once for each step that is first of a type or phase: 1, 4, 5 and 8

    // A plugin naming a new type at every step: the names stop growing, and so do the firsts.
    hsr::StepOutline many;
    for (int i = 0; i < 20000; ++i) many.add(std::to_string(i), "", HSR_NO_LEVEL, text);
    CHECK(many.total == 20000);
    CHECK(many.types.size() == hsr::StepOutline::max_names + 1);
    CHECK(many.firsts.size() == hsr::StepOutline::max_names);
}
