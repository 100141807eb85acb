// Phases and languages of the steps (ABI 1.5), for every built-in plugin that has steps: each lists
// the phases of its algorithm (well-formed, unique names), and every step it reports, on several
// scenes and cameras, names one of them. Asked for Russian, every text a plugin writes itself is in
// Russian (holds Cyrillic letters); asked for English, none is.
#include "hsr/abi.h"
#include "hsr/edges.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/surface.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

struct Case {
    std::string name;
    hsr_scene scene;
    hsr_camera camera;
};

std::vector<Case> cases_for(const std::string& plugin_name) {
    std::vector<Case> cases;
    if (plugin_name == "floating-horizon") {
        static const hsr::SceneData surface =
            hsr::make_formula_surface("sin(x)*cos(y)", hsr::parse_surface_range("-3:3,-3:3,24x24"));
        cases.push_back({"surface", surface.view(), orbit(surface, 30.0f, 35.0f, 1.1f, false, 96, 72)});
        cases.push_back({"surface from the side", surface.view(), orbit(surface, 80.0f, 15.0f, 1.0f, true, 64, 64)});
        return cases;
    }
    for (const char* file : {"boxes.scene", "three-polygons.scene", "cube.obj"}) {
        // Roberts takes closed convex bodies only: it refuses the open polygons.
        if (plugin_name == "roberts" && std::string(file) == "three-polygons.scene") continue;
        const hsr::SceneData& data = model(file);
        cases.push_back({std::string(file) + " perspective", data.view(), orbit(data, 30.0f, 20.0f, 1.2f, false, 64, 48)});
        cases.push_back({std::string(file) + " orthographic", data.view(), orbit(data, -110.0f, -35.0f, 1.0f, true, 40, 48)});
    }
    return cases;
}

bool has_cyrillic(const std::string& text) {
    // UTF-8 of U+0400..U+04FF starts with 0xD0..0xD3.
    for (unsigned char c : text)
        if (c >= 0xD0 && c <= 0xD3) return true;
    return false;
}

// What the steps of one run named.
struct Seen {
    uint64_t steps = 0;
    std::vector<std::string> phases;  // per step; "" for none
    std::vector<std::string> texts;   // per step, the plugin's own; "" for none
};

uint32_t record_step(void* context, const hsr_step_event* e) {
    auto& seen = *static_cast<Seen*>(context);
    ++seen.steps;
    seen.phases.emplace_back(e->phase != nullptr ? e->phase : "");
    seen.texts.emplace_back(e->text != nullptr ? e->text : "");
    return 0;
}

void record_event(void* context, const hsr_trace_event* e) {
    auto& seen = *static_cast<Seen*>(context);
    ++seen.steps;
    seen.phases.emplace_back(e->phase != nullptr ? e->phase : "");
    seen.texts.emplace_back(e->text != nullptr ? e->text : "");
}

hsr_status accept_segments(void*, const hsr_segment_batch*) { return HSR_OK; }

Seen run_surface(const std::string& name, const Case& c, const char* language) {
    hsr::HiddenSurfaceRemover remover(plugin(name), {});
    REQUIRE(remover.has_steps());
    hsr::Frame frame;
    const size_t pixels = size_t(c.camera.width) * c.camera.height;
    frame.depth.assign(pixels, INFINITY);
    frame.face.assign(pixels, HSR_NO_FACE);
    frame.bary.assign(2 * pixels, 0.0f);
    hsr_visibility_buffer target{sizeof(hsr_visibility_buffer), c.camera.width, c.camera.height, frame.depth.data(),
                                 frame.face.data(), frame.bary.data(), nullptr, nullptr};
    Seen seen;
    const hsr_step_sink sink{&seen, &record_step, language};
    remover.render_steps(c.scene, c.camera, target, nullptr, sink);
    return seen;
}

Seen run_lines(const std::string& name, const Case& c, const char* language) {
    hsr::HiddenLineRemover remover(plugin(name), {});
    const hsr::EdgeList edges = hsr::classify_edges(c.scene, c.camera, 40.0, hsr::EdgeSelection::kFeatures);
    const hsr_line_request request = edges.request(true);
    Seen seen;
    const hsr_segment_sink segments{nullptr, &accept_segments};
    const hsr_trace_sink trace{&seen, &record_event, language};
    remover.render_lines(c.scene, c.camera, request, segments, &trace, nullptr);
    return seen;
}

void check_plugin(const std::string& name, bool lines) {
    const hsr::Plugin& p = plugin(name);
    INFO("plugin " << name);
    CHECK(p.descriptor.abi_minor >= 5);
    REQUIRE_FALSE(p.phases.empty());
    std::set<std::string> listed;
    const std::regex well_formed("[a-z0-9]+(-[a-z0-9]+)*");
    for (const hsr::PluginPhase& phase : p.phases) {
        INFO("phase " << phase.name);
        CHECK(std::regex_match(phase.name, well_formed));
        CHECK_FALSE(phase.title.empty());
        CHECK(listed.insert(phase.name).second);
    }
    std::set<std::string> used;
    for (const Case& c : cases_for(name)) {
        INFO("on " << c.name);
        const Seen english = lines ? run_lines(name, c, "en") : run_surface(name, c, "en");
        const Seen russian = lines ? run_lines(name, c, "ru") : run_surface(name, c, "ru");
        CHECK(english.steps > 0);
        CHECK(russian.steps == english.steps);
        for (uint64_t k = 0; k < english.steps; ++k) {
            INFO("step " << k + 1 << ": " << english.texts[k]);
            CHECK(listed.count(english.phases[k]) == 1);
            if (k < russian.steps) CHECK(russian.phases[k] == english.phases[k]);
            CHECK_FALSE(has_cyrillic(english.texts[k]));
            if (k < russian.steps && !russian.texts[k].empty()) CHECK(has_cyrillic(russian.texts[k]));
            used.insert(english.phases[k]);
        }
    }
    // Most of the listed phases are met on these small scenes; a list of names no step uses would
    // highlight nothing.
    CHECK(used.size() * 2 >= listed.size());
}

}  // namespace

TEST_CASE("phases: every hidden-surface plugin names a listed phase on every step, in both languages", "[phases]") {
    for (const char* name : kBuiltinHiddenSurface) {
        DYNAMIC_SECTION(name) { check_plugin(name, false); }
    }
}

TEST_CASE("phases: every hidden-line plugin names a listed phase on every step, in both languages", "[phases]") {
    for (const char* name : kBuiltinHiddenLine) {
        DYNAMIC_SECTION(name) { check_plugin(name, true); }
    }
}
