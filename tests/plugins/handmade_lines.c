/* A hidden-line plugin (ABI 1.2) written in plain C against abi.h alone: it projects every requested
 * edge and returns it whole as visible (QI 0), hiding nothing, in batches of at most 3 segments so
 * that the host's batch handling is exercised; one "edge-begin" trace event per edge. With
 * HANDMADE_LINES_MINOR it claims another minor version. */
#include "hsr/abi.h"

#include <math.h>

#ifndef HANDMADE_LINES_MINOR
#define HANDMADE_LINES_MINOR HSR_ABI_MINOR
#endif

static int instance_token;

static hsr_status create(const hsr_param_value* params, uint32_t count, void** instance, hsr_error* error) {
    (void)params;
    (void)count;
    (void)error;
    *instance = &instance_token;
    return HSR_OK;
}

static void destroy(void* instance) { (void)instance; }

static void project(const hsr_camera* c, const float* p, float* out) {
    const float* m = c->view_projection;
    float x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
    float y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
    float w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
    out[0] = (x / w + 1.0f) * 0.5f * (float)c->width;
    out[1] = (1.0f - y / w) * 0.5f * (float)c->height;
}

static hsr_status render_lines(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                               const hsr_line_request* request, const hsr_segment_sink* segments,
                               const hsr_trace_sink* trace, const hsr_counter_sink* counters, hsr_error* error) {
    float points[12];
    uint32_t edges[3], flags[3];
    int32_t qi[3];
    uint32_t n = 0, e;
    hsr_segment_batch batch;
    (void)instance;
    (void)error;
    for (e = 0; e < request->edge_count; ++e) {
        if (trace != 0) {
            /* Zero-initialised: the fields a newer header appends stay NULL and 0 (no text, no lines). */
            hsr_trace_event event = {.struct_size = sizeof(hsr_trace_event)};
            event.type = "edge-begin";
            event.edge = e;
            event.face = HSR_NO_FACE;
            event.object = HSR_NO_OBJECT;
            event.qi = 0;
            event.t0 = 0.0;
            event.t1 = NAN;
            trace->event(trace->context, &event);
        }
        project(camera, scene->positions + 3 * request->edge_vertices[2 * e], points + 4 * n);
        project(camera, scene->positions + 3 * request->edge_vertices[2 * e + 1], points + 4 * n + 2);
        edges[n] = e;
        flags[n] = request->edge_flags[e];
        qi[n] = 0;
        if (++n == 3 || e + 1 == request->edge_count) {
            hsr_status status;
            batch.struct_size = sizeof batch;
            batch.count = n;
            batch.points = points;
            batch.edge = edges;
            batch.flags = flags;
            batch.qi = qi;
            status = segments->emit(segments->context, &batch);
            if (status != HSR_OK) return status;
            n = 0;
        }
    }
    if (counters) counters->report(counters->context, "edges-in", request->edge_count);
    return HSR_OK;
}

static const IHiddenLineRemover table = {sizeof(IHiddenLineRemover), create, destroy, render_lines, 0};

static const hsr_plugin_descriptor descriptor = {
    sizeof(hsr_plugin_descriptor), HSR_API_NAME, HSR_ABI_MAJOR, HANDMADE_LINES_MINOR,
    HSR_KIND_HIDDEN_LINE_REMOVER, "handmade-lines", "0.1.0", "hidden-line test plugin written in C (hides nothing)",
    0, 0, &table, 0, 0, 0, 0};

HSR_EXPORT const hsr_plugin_descriptor* hsr_plugin_entry(uint32_t index) {
    return index == 0 ? &descriptor : 0;
}
