/* A hidden-surface plugin written in plain C against abi.h alone, without the C++ SDK, so that the
 * tests can give it any version number or struct size. It marks every pixel as covered by face 0 at
 * depth 0.5.
 *   HANDMADE_NAME                     its plugin name (default "handmade")
 *   HANDMADE_MAJOR / HANDMADE_MINOR   the ABI version it claims (default: the header's)
 *   HANDMADE_SHORT_TABLES             its tables end before the optional `extension` field, as a plugin
 *                                     built against an older minor would
 * Built against ABI 1.3 or later it also renders step by step: step y fills row y, so a render
 * stopped after step k has covered exactly the rows 0 to k - 1. */
#include "hsr/abi.h"

#ifndef HANDMADE_MAJOR
#define HANDMADE_MAJOR HSR_ABI_MAJOR
#endif
#ifndef HANDMADE_NAME
#define HANDMADE_NAME "handmade"
#endif
#ifndef HANDMADE_MINOR
#define HANDMADE_MINOR HSR_ABI_MINOR
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

static hsr_status render(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                         hsr_visibility_buffer* target, const hsr_counter_sink* counters, hsr_error* error) {
    (void)instance;
    (void)scene;
    (void)camera;
    (void)error;
    uint32_t n = target->width * target->height;
    for (uint32_t i = 0; i < n; ++i) {
        target->face[i] = 0;
        target->depth[i] = 0.5f;
    }
    if (counters) counters->report(counters->context, "pixels-written", n);
    return HSR_OK;
}

#if HSR_ABI_MINOR >= 3 && !defined(HANDMADE_SHORT_TABLES)
static hsr_status render_steps(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                               hsr_visibility_buffer* target, const hsr_counter_sink* counters,
                               const hsr_step_sink* steps, hsr_error* error) {
    uint32_t x, y, written = 0;
    (void)instance;
    (void)scene;
    (void)camera;
    (void)error;
    for (y = 0; y < target->height; ++y) {
        float line[4];
        uint32_t role = HSR_STEP_WRITTEN;
        hsr_step_event event = {0};
        for (x = 0; x < target->width; ++x) {
            target->face[y * target->width + x] = 0;
            target->depth[y * target->width + x] = 0.5f;
        }
        written += target->width;
        line[0] = 0.0f;
        line[1] = line[3] = (float)y + 0.5f;
        line[2] = (float)target->width;
        event.struct_size = sizeof event;
        event.type = "row";
        event.face = 0;
        event.level = HSR_NO_LEVEL;
        event.line_count = 1;
        event.lines = line;
        event.line_roles = &role;
        event.pixels_written = target->width;
        if (steps->step(steps->context, &event) != 0) break;
    }
    if (counters) counters->report(counters->context, "pixels-written", written);
    return HSR_OK;
}
#endif

/* Designated initializers: the same lines fill the table of every minor's header. */
static const IHiddenSurfaceRemover table = {
#ifdef HANDMADE_SHORT_TABLES
    .struct_size = offsetof(IHiddenSurfaceRemover, extension),
    .extension = (const void* (*)(const char*))0x1, /* beyond struct_size: never read or called */
#else
    .struct_size = sizeof(IHiddenSurfaceRemover),
#endif
#if HSR_ABI_MINOR >= 3 && !defined(HANDMADE_SHORT_TABLES)
    .render_steps = render_steps,
#endif
    .create = create,
    .destroy = destroy,
    .render = render,
};

static const hsr_param_desc params[] = {
    {sizeof(hsr_param_desc), "level", HSR_PARAM_INT, "3", 0, 10, 0, "an integer parameter"},
};

static const hsr_plugin_descriptor descriptor = {
    sizeof(hsr_plugin_descriptor), HSR_API_NAME, HANDMADE_MAJOR, HANDMADE_MINOR,
    HSR_KIND_HIDDEN_SURFACE_REMOVER, HANDMADE_NAME, "0.1.0", "test plugin written in C",
    params, 1, &table,
#if HSR_ABI_MINOR >= 5
    0, 0,
#endif
#if HSR_ABI_MINOR >= 6
    0, 0,
#endif
};

HSR_EXPORT const hsr_plugin_descriptor* hsr_plugin_entry(uint32_t index) {
    return index == 0 ? &descriptor : 0;
}
