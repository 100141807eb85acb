// One line drawing: the edges of a flat scene classified for the camera (hsr/edges.hpp), handed to a
// hidden-line plugin through the C ABI (1.2), and the visible (and hidden) pieces it returns, with
// its counters and, on request, its step events written as JSON lines.
#pragma once

#include "hsr/abi.h"
#include "hsr/edges.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/step_outline.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace hsr {

struct LineSegment {
    glm::vec2 a, b;  // window coordinates: x right, y down, pixels
    uint32_t edge;   // index into the drawing's edges, or HSR_NO_EDGE (a penetration line)
    uint32_t flags;  // HSR_EDGE_* bits
    int32_t qi;      // 0 visible; n > 0 behind n faces; -1 hidden, count unknown
};

// One trace event (hsr_trace_event), copied.
struct TraceEventRecord {
    uint64_t index = 0;  // 1-based
    std::string type;
    uint32_t edge = HSR_NO_EDGE, face = HSR_NO_FACE, object = HSR_NO_OBJECT;
    int32_t qi = -1;
    double t0 = 0, t1 = 0;  // NaN when not given
    std::string text;       // the plugin's (ABI 1.3), or empty
    std::string phase;      // one of the plugin's phases (ABI 1.5), or empty
    std::vector<float> lines;     // the plugin's, 4 per line: x0, y0, x1, y1 in window coordinates
    std::vector<uint32_t> roles;  // an hsr_step_role per line
};

struct LineDrawing {
    uint32_t width = 0, height = 0;
    EdgeList edges;  // what was asked for
    std::vector<LineSegment> segments;
    std::vector<std::pair<std::string, uint64_t>> counters;
    uint64_t trace_events = 0;  // counted when the events were asked for (LineSettings)
    // With LineSettings::stop_after_event k: event k, unless the plugin sent fewer than k.
    std::optional<TraceEventRecord> stopped_at;
    double lines_ms = 0;  // time inside the plugin

    uint64_t counter(const std::string& name) const;  // 0 when absent
};

struct LineSettings {
    EdgeSelection edges = EdgeSelection::kFeatures;
    double crease_angle_degrees = 40.0;
    bool want_hidden = false;
    std::ostream* trace = nullptr;  // when set, every step event as one JSON object per line
    // A viewer's step k of the algorithm (k >= 1; 0: off): keep only the segments emitted before
    // trace event k + 1, and record event k (LineDrawing::stopped_at). The plugin still runs to the
    // end, so trace_events is the number of steps of the whole drawing.
    uint64_t stop_after_event = 0;
    // With stop_after_event past the plugin's last event: record the last event instead, with every
    // segment (the last step, as a viewer shows a step past the end).
    bool past_end_is_last = false;
    // The language step texts are asked in (hsr_trace_sink.language): "en", "ru"; empty: English.
    std::string language;
    // Set: every trace event is added to it (level HSR_NO_LEVEL; the plugin's text, or empty).
    StepOutline* outline = nullptr;
};

// The scene must have no instances (flatten_instances first). Throws hsr::Error with the plugin's
// message when it fails, or when it returns a segment with non-finite coordinates or an edge index
// it was not given.
LineDrawing render_lines(const hsr_scene& scene, const hsr_camera& camera, HiddenLineRemover& remover,
                         const LineSettings& settings);

// One trace event as a JSON object (no newline): fields that hold their "none" value are left out,
// and the text unless with_text (the plugin claims ABI 1.3 and the event's struct_size covers it).
std::string trace_event_json(const hsr_trace_event& event, bool with_text = false, bool with_phase = false);

}  // namespace hsr
