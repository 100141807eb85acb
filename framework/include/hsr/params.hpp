// Plugin parameters on the host side: parsing "name:key=value,..." and checking values against a
// plugin's schema before anything is created.
#pragma once

#include "hsr/abi.h"

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hsr {

using Setting = std::pair<std::string, std::string>;  // key, value as typed by the user

// "zbuffer:depth-test=greater,cull-backfaces=true" -> {"zbuffer", {{"depth-test","greater"}, ...}}
struct PluginSpec {
    std::string name;
    std::vector<Setting> settings;
};
PluginSpec parse_plugin_spec(std::string_view text);

// Validated values for every parameter of a schema, in schema order, defaults filled in. Owns the
// storage the hsr_param_value array points into.
class ParamValues {
public:
    const hsr_param_value* data() const { return values_.data(); }
    uint32_t size() const { return static_cast<uint32_t>(values_.size()); }
    const std::vector<hsr_param_value>& values() const { return values_; }

private:
    friend ParamValues resolve_params(const hsr_plugin_descriptor&, const std::vector<Setting>&);
    std::vector<hsr_param_value> values_;
};

// Throws hsr::Error naming the plugin and key for an unknown key, a repeated key, a value of the
// wrong type or out of range, or an unknown choice.
ParamValues resolve_params(const hsr_plugin_descriptor& plugin, const std::vector<Setting>& settings);

// The name and its settings in a canonical order ("name|key=value|..."), as a cache key.
std::string settings_key(const std::string& name, std::vector<Setting> settings);

// One parameter's text value parsed by its type; throws hsr::Error (without the plugin name).
hsr_param_value parse_param_value(const hsr_param_desc& desc, std::string_view text);

// Parameter i of a plugin's schema (the array is stepped by struct_size, see abi.h).
const hsr_param_desc& param_desc(const hsr_plugin_descriptor& plugin, uint32_t i);

// "less|greater" -> {"less", "greater"}
std::vector<std::string> split_choices(const char* choices);

// Human-readable one-line summary of a parameter: "depth-test=less (less|greater): help"
std::string describe_param(const hsr_param_desc& desc);

}  // namespace hsr
