/* Broken plugin libraries, one per case, for tests/test_plugin_hardening.cpp: each is what a careless
 * or hostile third party might put on the plugin path. Without a BAD_* switch this is a valid
 * hidden-surface plugin named BAD_NAME that fills nothing; each switch breaks one thing:
 *   BAD_ENTRY_IS_DATA         hsr_plugin_entry is an array, not a function
 *   BAD_NULL_API, BAD_NULL_NAME, BAD_NULL_PARAMS, BAD_NULL_INTERFACE_TABLE    that pointer is NULL
 *   BAD_WILD_VERSION, BAD_WILD_INTERFACE_TABLE      that pointer points into unmapped memory
 *   BAD_UNTERMINATED_NAME     the name runs on for 8 KiB without a NUL
 *   BAD_HUGE_PARAM_COUNT      param_count says 2^31, the array holds one
 *   BAD_KIND                  kind 99, outside hsr_plugin_kind
 *   BAD_CONSTRUCTOR_SEGFAULT, BAD_CONSTRUCTOR_EXIT, BAD_CONSTRUCTOR_HANG    the library's constructor
 *                             raises SIGSEGV, calls exit(3), or never returns
 *   BAD_UNTERMINATED_ERROR    loads fine; render fails with an error message that fills the whole
 *                             buffer without a NUL */
#include "hsr/abi.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef BAD_NAME
#define BAD_NAME "bad"
#endif

#define WILD_POINTER ((const void*)16)

#if defined(BAD_CONSTRUCTOR_SEGFAULT)
__attribute__((constructor)) static void on_load(void) { raise(SIGSEGV); }
#elif defined(BAD_CONSTRUCTOR_EXIT)
__attribute__((constructor)) static void on_load(void) { exit(3); }
#elif defined(BAD_CONSTRUCTOR_HANG)
__attribute__((constructor)) static void on_load(void) {
    for (;;) pause();
}
#endif

#ifdef BAD_ENTRY_IS_DATA
HSR_EXPORT const char hsr_plugin_entry[64] = "not a function";
#else

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
    (void)target;
    (void)counters;
#ifdef BAD_UNTERMINATED_ERROR
    memset(error->message, 'x', sizeof error->message);
    return HSR_ERROR_INTERNAL;
#else
    (void)error;
    return HSR_OK;
#endif
}

__attribute__((unused)) static const IHiddenSurfaceRemover table = {
    .struct_size = sizeof(IHiddenSurfaceRemover), .create = create, .destroy = destroy, .render = render};

__attribute__((unused)) static const hsr_param_desc params[] = {
    {sizeof(hsr_param_desc), "level", HSR_PARAM_INT, "3", 0, 10, 0, "an integer parameter"},
};

#ifdef BAD_UNTERMINATED_NAME
static char long_name[8192];
__attribute__((constructor)) static void fill_name(void) { memset(long_name, 'a', sizeof long_name); }
#define NAME long_name
#elif defined(BAD_NULL_NAME)
#define NAME 0
#else
#define NAME BAD_NAME
#endif

#ifdef BAD_HUGE_TRANSLATION_COUNT
static const hsr_translation translations[] = {{sizeof(hsr_translation), "ru", "description", "сломан нарочно"}};
#endif

static const hsr_plugin_descriptor descriptor = {
    sizeof(hsr_plugin_descriptor),
#ifdef BAD_NULL_API
    0,
#else
    HSR_API_NAME,
#endif
    HSR_ABI_MAJOR,
    HSR_ABI_MINOR,
#ifdef BAD_KIND
    99,
#else
    HSR_KIND_HIDDEN_SURFACE_REMOVER,
#endif
    NAME,
#ifdef BAD_WILD_VERSION
    WILD_POINTER,
#else
    "0.1.0",
#endif
    "broken on purpose (test plugin)",
#ifdef BAD_NULL_PARAMS
    0,
#else
    params,
#endif
#ifdef BAD_HUGE_PARAM_COUNT
    0x80000000u,
#else
    1,
#endif
#if defined(BAD_NULL_INTERFACE_TABLE)
    0
#elif defined(BAD_WILD_INTERFACE_TABLE)
    WILD_POINTER
#else
    &table
#endif
    ,
#ifdef BAD_HUGE_PHASE_COUNT
    0, 0x80000000u,
#else
    0, 0,
#endif
#ifdef BAD_HUGE_TRANSLATION_COUNT
    translations, 0x80000000u
#else
    0, 0
#endif
};

HSR_EXPORT const hsr_plugin_descriptor* hsr_plugin_entry(uint32_t index) {
    return index == 0 ? &descriptor : 0;
}
#endif
