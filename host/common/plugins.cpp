// The plugin search and description the commands share (plugins.hpp).
#include "common/plugins.hpp"

#include "hsr/params.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <fmt/format.h>

namespace fs = std::filesystem;

hsr::PluginRegistry hsr::host::scan_plugins(const std::vector<std::string>& extra_dirs) {
    const fs::path executable_dir(boost::dll::program_location().parent_path().string());
    hsr::PluginRegistry registry;
    for (const fs::path& dir : hsr::default_plugin_dirs(executable_dir, extra_dirs)) registry.scan_directory(dir);
    return registry;
}

namespace {

std::string describe_plugin(const hsr::Plugin& p, const std::string& indent) {
    const hsr_plugin_descriptor& d = p.descriptor;
    std::string out = fmt::format("{}{:<15} {:<20} v{:<7} ABI {}.{}  {}\n", indent, hsr::kind_name(d.kind), d.name,
                                  d.version ? d.version : "?", d.abi_major, d.abi_minor,
                                  d.description ? d.description : "");
    if (d.param_count == 0) out += indent + "    (no parameters)\n";
    for (uint32_t i = 0; i < d.param_count; ++i) out += indent + "    " + hsr::describe_param(hsr::param_desc(d, i)) + "\n";
    return out;
}

}  // namespace

std::string hsr::host::describe_plugins(const hsr::PluginRegistry& registry, const std::string& indent) {
    std::string out;
    for (hsr_plugin_kind kind : {HSR_KIND_HIDDEN_SURFACE_REMOVER, HSR_KIND_HIDDEN_LINE_REMOVER, HSR_KIND_LIGHTING_MODEL}) {
        for (const hsr::Plugin& p : registry.plugins())
            if (p.descriptor.kind == kind) out += describe_plugin(p, indent);
    }
    return out;
}

