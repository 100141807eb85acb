// A hidden-surface plugin that misbehaves as a careless or hostile one would, where its parameters
// say: `fault` (none, segfault, abort, exit, throw, allocate, loop) in `when` (create, render).
// Written against abi.h without the SDK, so that `throw` really leaves the extern "C" function.
// MISBEHAVING_NAME, MISBEHAVING_FAULT and MISBEHAVING_WHEN set the name and the defaults, so that
// one source makes a plugin that crashes wherever it is loaded and created (crashes-in-create) or
// hangs in every render (hangs-in-render).
#include "hsr/abi.h"

#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>

#ifndef MISBEHAVING_NAME
#define MISBEHAVING_NAME "misbehaving"
#endif
#ifndef MISBEHAVING_FAULT
#define MISBEHAVING_FAULT "none"
#endif
#ifndef MISBEHAVING_WHEN
#define MISBEHAVING_WHEN "render"
#endif

namespace {

// The order of the `fault` choices.
enum class Fault { none, segfault, abort, exit, throw_, allocate, loop };
enum class When { create, render };

char* volatile kept = nullptr;

struct Instance {
    Fault fault = Fault::none;
    When when = When::render;
};

// Not instrumented: the sanitizer build would otherwise stop at the null store with its own report,
// and the point is what the host does when the plugin really crashes.
__attribute__((no_sanitize("address", "undefined"), noinline)) void misbehave(Fault fault) {
    switch (fault) {
    case Fault::none: return;
    case Fault::segfault: {
        volatile int* volatile nowhere = nullptr;
        *nowhere = 1;
        return;
    }
    case Fault::abort: std::abort();
    case Fault::exit: std::exit(0);
    case Fault::throw_: throw std::runtime_error("misbehaving: thrown across the C ABI");
    case Fault::allocate: {
        // As careless code does: no check of what malloc returned.
        constexpr size_t ten_gib = size_t(10) << 30;
        char* memory = static_cast<char*>(std::malloc(ten_gib));
        std::memset(memory, 1, ten_gib);
        kept = memory;  // never freed: the writes must not be dead
        return;
    }
    case Fault::loop: {
        volatile bool forever = true;
        while (forever) {
        }
        return;
    }
    }
}

hsr_status create(const hsr_param_value* params, uint32_t count, void** instance, hsr_error*) {
    Instance settings;
    for (uint32_t i = 0; i < count; ++i) {
        const hsr_param_value& p = *HSR_ELEMENT(hsr_param_value, params, i);
        if (std::strcmp(p.name, "fault") == 0) settings.fault = static_cast<Fault>(p.number);
        if (std::strcmp(p.name, "when") == 0) settings.when = static_cast<When>(p.number);
    }
    if (settings.when == When::create) misbehave(settings.fault);
    *instance = new Instance(settings);
    return HSR_OK;
}

void destroy(void* instance) { delete static_cast<Instance*>(instance); }

hsr_status render(void* instance, const hsr_scene*, const hsr_camera*, hsr_visibility_buffer* target,
                  const hsr_counter_sink*, hsr_error*) {
    const Instance& settings = *static_cast<const Instance*>(instance);
    if (settings.when == When::render) misbehave(settings.fault);
    const size_t pixels = size_t(target->width) * target->height;
    for (size_t i = 0; i < pixels; ++i) {
        target->face[i] = HSR_NO_FACE;
        target->depth[i] = std::numeric_limits<float>::infinity();
    }
    return HSR_OK;
}

const hsr_param_desc params[] = {
    {sizeof(hsr_param_desc), "fault", HSR_PARAM_ENUM, MISBEHAVING_FAULT, 0, 0,
     "none|segfault|abort|exit|throw|allocate|loop", "how to misbehave"},
    {sizeof(hsr_param_desc), "when", HSR_PARAM_ENUM, MISBEHAVING_WHEN, 0, 0, "create|render", "in which call"},
};

const IHiddenSurfaceRemover table = {sizeof(IHiddenSurfaceRemover), create, destroy, render, nullptr, nullptr, nullptr};

const hsr_plugin_descriptor descriptor = {
    sizeof(hsr_plugin_descriptor), HSR_API_NAME, HSR_ABI_MAJOR, HSR_ABI_MINOR, HSR_KIND_HIDDEN_SURFACE_REMOVER,
    MISBEHAVING_NAME, "0.1.0", "crashes, aborts, exits, throws, allocates or loops on request (test plugin)",
    params, sizeof params / sizeof params[0], &table, nullptr, 0, nullptr, 0};

}  // namespace

extern "C" HSR_EXPORT const hsr_plugin_descriptor* hsr_plugin_entry(uint32_t index) {
    return index == 0 ? &descriptor : nullptr;
}
