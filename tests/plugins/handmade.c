/* A hidden-surface plugin written in plain C against abi.h alone, without the C++ SDK, so that the
 * tests can give it any version number or struct size. It marks every pixel as covered by face 0 at
 * depth 0.5.
 *   HANDMADE_NAME                     its plugin name (default "handmade")
 *   HANDMADE_MAJOR / HANDMADE_MINOR   the ABI version it claims (default: the header's)
 *   HANDMADE_SHORT_TABLES             its tables end before the optional `extension` field, as a plugin
 *                                     built against an older minor would */
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

static const IHiddenSurfaceRemover table = {
#ifdef HANDMADE_SHORT_TABLES
    offsetof(IHiddenSurfaceRemover, extension),
#else
    sizeof(IHiddenSurfaceRemover),
#endif
    create, destroy, render,
#ifdef HANDMADE_SHORT_TABLES
    (const void* (*)(const char*))0x1 /* beyond struct_size: the host must never read or call it */
#else
    0
#endif
};

static const hsr_param_desc params[] = {
    {sizeof(hsr_param_desc), "level", HSR_PARAM_INT, "3", 0, 10, 0, "an integer parameter"},
};

static const hsr_plugin_descriptor descriptor = {
    sizeof(hsr_plugin_descriptor), HSR_API_NAME, HANDMADE_MAJOR, HANDMADE_MINOR,
    HSR_KIND_HIDDEN_SURFACE_REMOVER, HANDMADE_NAME, "0.1.0", "test plugin written in C",
    params, 1, &table};

HSR_EXPORT const hsr_plugin_descriptor* hsr_plugin_entry(uint32_t index) {
    return index == 0 ? &descriptor : 0;
}
