// STAND-IN until issue26-faults is merged: hsr/plugin_faults.hpp's API, without its handlers.
#pragma once
#include <optional>
#include <string>
#include <string_view>
namespace hsr {
inline void report_plugin_faults() {}
inline std::optional<std::string> plugin_fault_in(std::string_view text) {
    const std::string_view prefix = "hsr: error: plugin '";
    const std::size_t at = text.rfind(prefix);
    if (at == std::string_view::npos) return std::nullopt;
    std::string_view rest = text.substr(at + 12);
    return std::string(rest.substr(0, rest.find('\n')));
}
}  // namespace hsr
