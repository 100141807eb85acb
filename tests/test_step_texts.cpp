// The step texts the host writes itself, in the language a step request asks for: the text of a
// step whose plugin gave none (resolve_visibility_steps, for hidden-surface steps), of a hidden-line
// trace event without one (describe_trace_event, hsr view), and of a step request that got no step.
//
// The answers are written out here from what the plugin does: handmade-steps (tests/plugins/
// handmade.c) fills row y of the picture with face 0 in step y + 1, as an event of type "row" with
// no text, so step k wrote exactly one row of pixels and rejected none.
#include "hsr/pipeline.hpp"
#include "surface_test_support.hpp"
#include "view/server/view_steps.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

namespace {

using namespace surface_tests;

bool has_cyrillic(const std::string& text) {
    // UTF-8 of U+0400..U+04FF starts with 0xD0..0xD3.
    for (unsigned char c : text)
        if (c >= 0xD0 && c <= 0xD3) return true;
    return false;
}

// The text of step `step` of handmade-steps over a 7 x 5 picture of the cube, asked in `language`.
std::string handmade_step_text(uint64_t step, const std::string& language) {
    hsr::HiddenSurfaceRemover remover(plugin("handmade-steps", HSR_TEST_PLUGIN_DIR, ""), {});
    REQUIRE(remover.has_steps());
    const hsr::SceneData& cube = model("cube.obj");
    const hsr_camera camera = orbit(cube, 30.0f, 20.0f, 1.0f, false, 7, 5);
    hsr::Frame frame;
    hsr::resolve_visibility_steps(cube.view(), camera, remover, frame, step, false, false, nullptr, language);
    REQUIRE(frame.steps.has_value());
    REQUIRE(frame.steps->last.index == step);
    return frame.steps->last.text;
}

}  // namespace

TEST_CASE("a step without a text of its own is described in the language asked for", "[steps][language]") {
    CHECK(handmade_step_text(3, "en") == "row 3: triangle 0, 7 pixels written, 0 rejected");
    CHECK(handmade_step_text(3, "") == "row 3: triangle 0, 7 pixels written, 0 rejected");
    const std::string russian = handmade_step_text(3, "ru");
    CHECK(russian == "шаг 3 (row): треугольник 0; записано пикселей: 7, отброшено: 0");
    CHECK(has_cyrillic(russian));
}

TEST_CASE("a hidden-line event without a text is described in the language asked for", "[view][language]") {
    hsr::TraceEventRecord event;
    event.index = 4;
    event.type = "edge-begin";
    event.edge = 3;
    event.face = 5;
    event.qi = 1;
    event.t0 = 0.25;
    event.t1 = 0.5;
    CHECK(hsr::host::describe_trace_event(event, "en") == "edge-begin: edge 3, face 5, qi 1, t 0.25 to 0.5");
    CHECK(hsr::host::describe_trace_event(event, "ru") ==
          "edge-begin: ребро 3, грань 5, количественная невидимость 1, t от 0.25 до 0.5");
    event.face = HSR_NO_FACE;
    event.t1 = std::numeric_limits<double>::quiet_NaN();
    CHECK(hsr::host::describe_trace_event(event, "en") == "edge-begin: edge 3, qi 1, t 0.25");
    CHECK(hsr::host::describe_trace_event(event, "ru") == "edge-begin: ребро 3, количественная невидимость 1, t 0.25");
}

TEST_CASE("a step request that got no step says so in the language asked for", "[view][language]") {
    for (bool plugin_reported_none : {false, true}) {
        const std::string english = hsr::host::no_steps_text(plugin_reported_none, "en");
        const std::string russian = hsr::host::no_steps_text(plugin_reported_none, "ru");
        CHECK(english.rfind("no steps: ", 0) == 0);
        CHECK_FALSE(has_cyrillic(english));
        CHECK(russian.rfind("шагов нет: ", 0) == 0);
        CHECK(has_cyrillic(russian));
    }
    CHECK(hsr::host::no_steps_text(true, "ru") != hsr::host::no_steps_text(false, "ru"));
}
