// What hsr view shows of one step of an algorithm besides the picture: the step's triangle or edge
// projected to the window, the pixels the step wrote and rejected, and a line of text for a
// hidden-line plugin's trace event (view_frames.cpp puts them into the response).
#pragma once

#include "hsr/abi.h"
#include "hsr/lines.hpp"
#include "hsr/pipeline.hpp"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace hsr::host {

// [[x0, y0, x1, y1], ...]: the outline of triangle `face` (placed by `instance` when the scene has
// instances) in window coordinates, cut at the near plane and clipped to the image. Empty when the
// face does not exist or lies outside.
nlohmann::json triangle_outline(const hsr_scene& scene, const hsr_camera& camera, uint32_t face, uint32_t instance);

// The segment from world point a to b the same way: [] or [[x0, y0, x1, y1]].
nlohmann::json projected_segment(const hsr_camera& camera, glm::vec3 a, glm::vec3 b);

// The pixels one step wrote and those it tested and rejected, as [[x, y], ...] each, or null when
// over `cap` or unknown (no depth-test counts). before: the visibility buffer after the step
// before (empty arrays: nothing drawn yet); after: after the step. A pixel counts as written when its
// face, instance or depth changed, as rejected when its depth-test count rose and nothing changed.
struct StepPixels {
    nlohmann::json written, rejected;
};
StepPixels step_pixels(const hsr::Frame& before, const hsr::Frame& after, std::size_t cap);

// "edge-begin: edge 12, face 3, qi 1, t 0.25 to 0.5" from the fields the event has, for an event
// without a text of its own; language "ru" writes it in Russian, anything else in English.
std::string describe_trace_event(const hsr::TraceEventRecord& event, const std::string& language = "en");

// The step text of a step request that got no step: the plugin reported none (a hidden-line
// plugin), or the algorithm had nothing to do (an empty picture). language as above.
std::string no_steps_text(bool plugin_reported_none, const std::string& language);

}  // namespace hsr::host
