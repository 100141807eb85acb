// A hidden-surface plugin written against abi.h without the SDK, whose render lets `throw 42` out
// across the C ABI: the rule plugins must keep (section 8 of docs/abi.md), broken, to check that the
// host survives it.
#include "hsr/abi.h"

namespace {

int instance_token;

hsr_status create(const hsr_param_value*, uint32_t, void** instance, hsr_error*) {
    *instance = &instance_token;
    return HSR_OK;
}

void destroy(void*) {}

hsr_status render(void*, const hsr_scene*, const hsr_camera*, hsr_visibility_buffer*, const hsr_counter_sink*,
                  hsr_error*) {
    throw 42;
}

hsr_status render_steps(void*, const hsr_scene*, const hsr_camera*, hsr_visibility_buffer*, const hsr_counter_sink*,
                        const hsr_step_sink*, hsr_error*) {
    throw 42;
}

const IHiddenSurfaceRemover table = {sizeof(IHiddenSurfaceRemover), create, destroy, render, nullptr, render_steps};

const hsr_plugin_descriptor descriptor = {
    sizeof(hsr_plugin_descriptor), HSR_API_NAME, HSR_ABI_MAJOR, HSR_ABI_MINOR, HSR_KIND_HIDDEN_SURFACE_REMOVER,
    "throws-across-abi", "0.1.0", "lets an int exception out of render (test plugin)", nullptr, 0, &table, nullptr, 0, nullptr, 0};

}  // namespace

extern "C" HSR_EXPORT const hsr_plugin_descriptor* hsr_plugin_entry(uint32_t index) {
    return index == 0 ? &descriptor : nullptr;
}
