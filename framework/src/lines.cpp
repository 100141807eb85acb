#include "hsr/lines.hpp"

#include "hsr/error.hpp"
#include "hsr/pipeline.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>

namespace hsr {
namespace {

struct Collector {
    LineDrawing* drawing;
    std::string problem;
};

hsr_status collect_segments(void* context, const hsr_segment_batch* batch) {
    auto& c = *static_cast<Collector*>(context);
    if (batch == nullptr || batch->points == nullptr || batch->edge == nullptr || batch->flags == nullptr ||
        batch->qi == nullptr) {
        c.problem = "a segment batch with NULL arrays";
        return HSR_ERROR_INVALID_ARGUMENT;
    }
    const uint32_t edge_count = static_cast<uint32_t>(c.drawing->edges.size());
    for (uint32_t k = 0; k < batch->count; ++k) {
        const float* p = batch->points + 4 * size_t(k);
        if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]) && std::isfinite(p[3]))) {
            c.problem = fmt::format("a segment with non-finite end points (edge {})", batch->edge[k]);
            return HSR_ERROR_INVALID_ARGUMENT;
        }
        if (batch->edge[k] != HSR_NO_EDGE && batch->edge[k] >= edge_count) {
            c.problem = fmt::format("a segment of edge {}, but only {} edges were asked for", batch->edge[k], edge_count);
            return HSR_ERROR_INVALID_ARGUMENT;
        }
        c.drawing->segments.push_back({{p[0], p[1]}, {p[2], p[3]}, batch->edge[k], batch->flags[k], batch->qi[k]});
    }
    return HSR_OK;
}

void collect_counter(void* context, const char* name, uint64_t value) {
    auto* counters = static_cast<std::vector<std::pair<std::string, uint64_t>>*>(context);
    for (auto& [n, v] : *counters)
        if (n == name) {
            v = value;
            return;
        }
    counters->emplace_back(name, value);
}

// Writes the events (when out is set) and counts them; with stop_after set, notes event stop_after
// and how many segments came before event stop_after + 1.
struct TraceWriter {
    std::ostream* out = nullptr;
    bool plugin_has_drawing = false;  // claims ABI 1.3: events may carry text and lines
    bool plugin_has_phases = false;   // claims ABI 1.5: events may name a phase
    uint64_t stop_after = 0;
    bool past_end_is_last = false;
    StepOutline* outline = nullptr;
    const LineDrawing* drawing = nullptr;
    uint64_t events = 0;
    std::optional<TraceEventRecord> stopped_at;
    std::optional<size_t> segments_before_next;
};

constexpr uint32_t kMaxEventLines = 1u << 20;

// A plugin's string, read up to its NUL or max_bytes, whichever comes first.
std::string_view bounded(const char* text, size_t max_bytes) { return {text, strnlen(text, max_bytes)}; }

void write_event(void* context, const hsr_trace_event* event) {
    auto& w = *static_cast<TraceWriter*>(context);
    if (event == nullptr) return;
    const bool has_drawing =
        w.plugin_has_drawing && event->struct_size >= offsetof(hsr_trace_event, line_roles) + sizeof(event->line_roles);
    const bool has_phase = w.plugin_has_phases && event->struct_size >= offsetof(hsr_trace_event, phase) + sizeof(event->phase);
    if (w.out != nullptr) *w.out << trace_event_json(*event, has_drawing, has_phase) << '\n';
    ++w.events;
    if (w.outline != nullptr) {
        const std::string type =
            event->type != nullptr ? printable(std::string_view(event->type, strnlen(event->type, 64)), 64) : "event";
        const std::string phase = has_phase && event->phase != nullptr ? printable(bounded(event->phase, 64), 64) : "";
        w.outline->add(type, phase, HSR_NO_LEVEL, [&] {
            return has_drawing && event->text != nullptr ? printable(bounded(event->text, 1024), 300) : std::string();
        });
    }
    if (w.stop_after == 0) return;
    // Past the end, the last event is the one kept: each is kept until another comes.
    if (w.events == w.stop_after || (w.past_end_is_last && w.events < w.stop_after)) {
        TraceEventRecord& r = w.stopped_at.emplace();
        r.index = w.events;
        r.type = event->type != nullptr ? printable(std::string_view(event->type, strnlen(event->type, 64)), 64) : "event";
        r.edge = event->edge;
        r.face = event->face;
        r.object = event->object;
        r.qi = event->qi;
        r.t0 = event->t0;
        r.t1 = event->t1;
        if (has_phase && event->phase != nullptr) r.phase = printable(bounded(event->phase, 64), 64);
        if (has_drawing) {
            if (event->text != nullptr) r.text = printable(bounded(event->text, 1024), 300);
            const uint32_t lines = event->lines != nullptr ? std::min(event->line_count, kMaxEventLines) : 0;
            r.lines.assign(event->lines, event->lines + 4 * size_t(lines));
            r.roles.assign(lines, HSR_STEP_SUBJECT);
            if (event->line_roles != nullptr)
                for (uint32_t k = 0; k < lines; ++k) r.roles[k] = std::min<uint32_t>(event->line_roles[k], HSR_STEP_CONTEXT);
        }
    } else if (w.events == w.stop_after + 1) {
        w.segments_before_next = w.drawing->segments.size();
    }
}

void append_json_string(std::string& out, const char* text) {
    out += '"';
    for (const char* c = text; *c != '\0'; ++c) {
        const unsigned char u = static_cast<unsigned char>(*c);
        if (u == '"' || u == '\\')
            out += {'\\', char(u)};
        else if (u < 0x20)
            out += fmt::format("\\u{:04x}", u);
        else
            out += char(u);
    }
    out += '"';
}

}  // namespace

uint64_t LineDrawing::counter(const std::string& name) const {
    for (const auto& [n, v] : counters)
        if (n == name) return v;
    return 0;
}

std::string trace_event_json(const hsr_trace_event& e, bool with_text, bool with_phase) {
    std::string out = "{\"type\":";
    append_json_string(out, e.type != nullptr ? e.type : "");
    if (e.edge != HSR_NO_EDGE) out += fmt::format(",\"edge\":{}", e.edge);
    if (e.face != HSR_NO_FACE) out += fmt::format(",\"face\":{}", e.face);
    if (e.object != HSR_NO_OBJECT) out += fmt::format(",\"object\":{}", e.object);
    if (e.qi >= 0) out += fmt::format(",\"qi\":{}", e.qi);
    if (std::isfinite(e.t0)) out += fmt::format(",\"t0\":{}", e.t0);
    if (std::isfinite(e.t1)) out += fmt::format(",\"t1\":{}", e.t1);
    if (with_text && e.text != nullptr) {
        out += ",\"text\":";
        append_json_string(out, printable(bounded(e.text, 1024), 300).c_str());
    }
    if (with_phase && e.phase != nullptr) {
        out += ",\"phase\":";
        append_json_string(out, printable(bounded(e.phase, 64), 64).c_str());
    }
    out += '}';
    return out;
}

LineDrawing render_lines(const hsr_scene& scene, const hsr_camera& camera, HiddenLineRemover& remover,
                         const LineSettings& settings) {
    check_image_size(camera.width, camera.height);
    check_clip_planes_known(remover.plugin(), camera);
    LineDrawing drawing;
    drawing.width = camera.width;
    drawing.height = camera.height;
    drawing.edges = classify_edges(scene, camera, settings.crease_angle_degrees, settings.edges);
    const hsr_line_request request = drawing.edges.request(settings.want_hidden);
    Collector collector{&drawing, {}};
    hsr_segment_sink sink{&collector, &collect_segments};
    TraceWriter writer;
    writer.out = settings.trace;
    writer.plugin_has_drawing = remover.plugin().descriptor.abi_minor >= 3;
    writer.plugin_has_phases = remover.plugin().descriptor.abi_minor >= 5;
    writer.stop_after = settings.stop_after_event;
    writer.past_end_is_last = settings.past_end_is_last;
    writer.outline = settings.outline;
    writer.drawing = &drawing;
    hsr_trace_sink trace{&writer, &write_event, settings.language.empty() ? nullptr : settings.language.c_str()};
    const bool want_events = settings.trace != nullptr || settings.stop_after_event > 0 || settings.outline != nullptr;
    hsr_counter_sink counters{&drawing.counters, &collect_counter};
    const auto start = std::chrono::steady_clock::now();
    try {
        remover.render_lines(scene, camera, request, sink, want_events ? &trace : nullptr, &counters);
    } catch (const Error& e) {
        if (!collector.problem.empty())
            throw Error("hidden-line plugin '{}' returned {}", remover.plugin().descriptor.name, collector.problem);
        throw;
    }
    drawing.lines_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    drawing.trace_events = writer.events;
    drawing.stopped_at = std::move(writer.stopped_at);
    if (writer.segments_before_next) drawing.segments.resize(*writer.segments_before_next);
    drawing.counters.emplace_back("edges-requested", drawing.edges.size());
    return drawing;
}

}  // namespace hsr
