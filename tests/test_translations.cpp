// A plugin's own texts in other languages (ABI 1.6, hsr_translation). The host's policy: what a
// translation table may hold, checked on descriptors built here. And every built-in plugin: it gives
// Russian for its description, every parameter's name and help, every choice, every phase and every
// counter, step buffer and step type it reports on the test scenes, each text with Cyrillic letters.
#include "hsr/abi.h"
#include "hsr/edges.hpp"
#include "hsr/params.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/surface.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

bool has_cyrillic(const std::string& text) {
    for (unsigned char c : text)
        if (c >= 0xD0 && c <= 0xD3) return true;
    return false;
}

// ---- the policy ---------------------------------------------------------------------------------

// zbuffer's descriptor with `table` as its translations.
std::string check_with(const std::vector<hsr_translation>& table) {
    hsr_plugin_descriptor d = plugin("zbuffer").descriptor;
    d.translations = table.empty() ? nullptr : table.data();
    d.translation_count = static_cast<uint32_t>(table.size());
    return hsr::check_translations(d);
}

hsr_translation entry(const char* language, const char* key, const char* text) {
    return {sizeof(hsr_translation), language, key, text};
}

}  // namespace

TEST_CASE("translations: the host takes every key the ABI lists for what the plugin has", "[translations]") {
    CHECK(check_with({entry("ru", "description", "z-буфер"), entry("ru", "param:depth-test", "тест глубины"),
                      entry("ru", "help:depth-test", "какую поверхность оставить"),
                      entry("ru", "choice:depth-test:greater", "дальняя"), entry("ru", "phase:cull", "отсечение"),
                      entry("ru", "counter:anything-at-all", "что угодно"), entry("ru", "buffer:z-pyramid", "пирамида"),
                      entry("uk", "description", "z-буфер"), entry("de", "description", "Z-Puffer")})
              .empty());
}

TEST_CASE("translations: the host refuses a malformed table with its reason", "[translations]") {
    CHECK(check_with({entry("ru", "description", "а"), entry("ru", "description", "б")}) ==
          "its translation 'description' (ru) is given twice");
    CHECK(check_with({entry("ru", "param:depth", "глубина")}) ==
          "its translation key 'param:depth' names no parameter of the plugin");
    CHECK(check_with({entry("ru", "help:", "пусто")}) == "its translation key 'help:' is not one the ABI lists");
    CHECK(check_with({entry("ru", "choice:depth-test:nearest", "ближняя")}) ==
          "its translation key 'choice:depth-test:nearest' names no choice of the plugin");
    CHECK(check_with({entry("ru", "choice:cull-backfaces:true", "да")}) ==
          "its translation key 'choice:cull-backfaces:true' names no choice of the plugin");
    CHECK(check_with({entry("ru", "choice:depth-test", "тест")}) ==
          "its translation key 'choice:depth-test' needs choice:<parameter>:<choice>");
    CHECK(check_with({entry("ru", "phase:paint", "рисование")}) ==
          "its translation key 'phase:paint' names no phase of the plugin");
    CHECK(check_with({entry("ru", "title", "заголовок")}) == "its translation key 'title' is not one the ABI lists");
    CHECK(check_with({entry("RU", "description", "z-буфер")}) ==
          "its translation #0 has the language 'RU', not a two- or three-letter code");
    CHECK(check_with({entry("russian", "description", "z-буфер")}) ==
          "its translation #0 has the language 'russian', not a two- or three-letter code");
    CHECK(check_with({entry("ru", "description", "")}) == "its translation 'description' (ru) is empty");
    CHECK(check_with({entry("ru", "description", nullptr)}) == "its translation #0 is malformed");
    CHECK(check_with({entry("ru", nullptr, "текст")}) == "its translation #0 is malformed");

    std::vector<hsr_translation> uneven{entry("ru", "description", "а"), entry("ru", "phase:cull", "б")};
    uneven[1].struct_size = sizeof(hsr_translation) + 8;
    CHECK(check_with(uneven) == "its translation #1 is malformed");

    hsr_plugin_descriptor missing = plugin("zbuffer").descriptor;
    missing.translations = nullptr;
    missing.translation_count = 3;
    CHECK(hsr::check_translations(missing) == "its translation table is missing");
}

TEST_CASE("translations: a plugin of ABI 1.5 has none, whatever lies past its descriptor", "[translations]") {
    hsr_plugin_descriptor d = plugin("zbuffer").descriptor;
    d.abi_minor = 5;
    d.translations = nullptr;
    d.translation_count = 0x80000000u;
    CHECK(hsr::check_descriptor(d).empty());
}

// ---- every built-in plugin in Russian ---------------------------------------------------------------

namespace {

struct Reported {
    std::set<std::string> counters, buffers, step_types;
};

void record_counter(void* context, const char* name, uint64_t) {
    static_cast<Reported*>(context)->counters.insert(name);
}

uint32_t record_step(void* context, const hsr_step_event* e) {
    auto& reported = *static_cast<Reported*>(context);
    if (e->type != nullptr) reported.step_types.insert(e->type);
    for (uint32_t i = 0; i < e->buffer_count; ++i) {
        const hsr_step_buffer& b = *HSR_ELEMENT(hsr_step_buffer, e->buffers, i);
        reported.buffers.insert(b.name);
    }
    return 0;
}

void record_event(void* context, const hsr_trace_event* e) {
    if (e->type != nullptr) static_cast<Reported*>(context)->step_types.insert(e->type);
}

hsr_status accept_segments(void*, const hsr_segment_batch*) { return HSR_OK; }

struct Target {
    explicit Target(const hsr_camera& camera) {
        const size_t pixels = size_t(camera.width) * camera.height;
        frame.depth.assign(pixels, INFINITY);
        frame.face.assign(pixels, HSR_NO_FACE);
        frame.bary.assign(2 * pixels, 0.0f);
        buffer = {sizeof(hsr_visibility_buffer), camera.width, camera.height, frame.depth.data(),
                  frame.face.data(), frame.bary.data(), nullptr, nullptr};
    }
    hsr::Frame frame;
    hsr_visibility_buffer buffer{};
};

// The counters and step buffers a plugin reports on the test scenes, by every call it offers.
Reported reported_by(const std::string& name, bool lines) {
    Reported reported;
    const hsr_counter_sink counters{&reported, &record_counter};
    std::vector<std::pair<hsr_scene, hsr_camera>> cases;
    if (name == "floating-horizon") {
        static const hsr::SceneData surface =
            hsr::make_formula_surface("sin(x)*cos(y)", hsr::parse_surface_range("-3:3,-3:3,24x24"));
        cases.emplace_back(surface.view(), orbit(surface, 30.0f, 35.0f, 1.1f, false, 96, 72));
    } else {
        for (const char* file : {"boxes.scene", "cube.obj", "monkey.obj"}) {
            // Roberts takes closed convex bodies only.
            if (lines && std::string(file) == "monkey.obj") continue;
            const hsr::SceneData& data = model(file);
            cases.emplace_back(data.view(), orbit(data, 30.0f, 20.0f, 1.2f, false, 96, 72));
        }
    }
    for (const auto& [scene, camera] : cases) {
        if (lines) {
            hsr::HiddenLineRemover remover(plugin(name), {});
            const hsr::EdgeList edges = hsr::classify_edges(scene, camera, 40.0, hsr::EdgeSelection::kFeatures);
            const hsr_line_request request = edges.request(true);
            const hsr_segment_sink segments{nullptr, &accept_segments};
            const hsr_trace_sink trace{&reported, &record_event, "ru"};
            remover.render_lines(scene, camera, request, segments, &trace, &counters);
            continue;
        }
        hsr::HiddenSurfaceRemover remover(plugin(name), {});
        Target plain(camera);
        remover.render(scene, camera, plain.buffer, &counters);
        if (remover.has_steps()) {
            Target stepped(camera);
            const hsr_step_sink steps{&reported, &record_step, "ru"};
            remover.render_steps(scene, camera, stepped.buffer, &counters, steps);
        }
    }
    return reported;
}

void check_russian(const std::string& name, bool lines, bool renders) {
    const hsr::Plugin& p = plugin(name);
    INFO("plugin " << name);
    CHECK(p.descriptor.abi_minor >= 6);
    auto check_text = [&](const std::string& key) {
        INFO("key " << key);
        const std::string* text = p.translated("ru", key);
        CHECK(text != nullptr);
        if (text != nullptr) CHECK(has_cyrillic(*text));
    };
    check_text("description");
    const hsr_plugin_descriptor& d = p.descriptor;
    for (uint32_t i = 0; i < d.param_count; ++i) {
        const hsr_param_desc& param = hsr::param_desc(d, i);
        check_text(std::string("param:") + param.name);
        if (param.help != nullptr && param.help[0] != '\0') check_text(std::string("help:") + param.name);
        if (param.type == HSR_PARAM_ENUM)
            for (const std::string& choice : hsr::split_choices(param.choices))
                check_text(std::string("choice:") + param.name + ":" + choice);
    }
    for (const hsr::PluginPhase& phase : p.phases) check_text("phase:" + phase.name);
    if (!renders) return;
    const Reported reported = reported_by(name, lines);
    CHECK_FALSE(reported.counters.empty());
    for (const std::string& counter : reported.counters) check_text("counter:" + counter);
    for (const std::string& type : reported.step_types) check_text("step:" + type);
    for (const std::string& buffer : reported.buffers) {
        INFO("step buffer " << buffer);
        const size_t dash = buffer.find_last_of('-');
        const bool numbered = dash != std::string::npos && dash + 1 < buffer.size() &&
                              buffer.find_first_not_of("0123456789", dash + 1) == std::string::npos;
        CHECK((p.translated("ru", "buffer:" + buffer) != nullptr ||
               (numbered && p.translated("ru", "buffer:" + buffer.substr(0, dash)) != nullptr)));
    }
}

}  // namespace

TEST_CASE("translations: every hidden-surface plugin's texts in Russian", "[translations]") {
    for (const char* name : kBuiltinHiddenSurface) {
        DYNAMIC_SECTION(name) { check_russian(name, false, true); }
    }
}

TEST_CASE("translations: every hidden-line plugin's texts in Russian", "[translations]") {
    for (const char* name : kBuiltinHiddenLine) {
        DYNAMIC_SECTION(name) { check_russian(name, true, true); }
    }
}

TEST_CASE("translations: every lighting model's texts in Russian", "[translations]") {
    for (const char* name : kBuiltinLighting) {
        DYNAMIC_SECTION(name) { check_russian(name, false, false); }
    }
}
