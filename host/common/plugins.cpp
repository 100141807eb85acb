// The plugin search and description the commands share (plugins.hpp).
#include "common/plugins.hpp"

#include "hsr/error.hpp"
#include "hsr/params.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <optional>
#include <system_error>
#include <utility>

namespace fs = std::filesystem;

namespace {

std::optional<std::vector<fs::path>> builtin_plugin_dirs;

std::string describe_plugin(const hsr::Plugin& p, const std::string& indent) {
    const hsr_plugin_descriptor& d = p.descriptor;
    std::string out = fmt::format("{}{:<15} {:<20} v{:<7} ABI {}.{}  {}\n", indent, hsr::kind_name(d.kind), d.name,
                                  d.version ? d.version : "?", d.abi_major, d.abi_minor,
                                  d.description ? d.description : "");
    if (d.param_count == 0) out += indent + "    (no parameters)\n";
    for (uint32_t i = 0; i < d.param_count; ++i) out += indent + "    " + hsr::describe_param(hsr::param_desc(d, i)) + "\n";
    if (!p.phases.empty()) {
        out += indent + "    phases of its steps:";
        for (std::size_t i = 0; i < p.phases.size(); ++i) out += (i == 0 ? " " : ", ") + p.phases[i].name;
        out += "\n";
    }
    std::vector<std::string> languages;
    for (const hsr::PluginTranslation& t : p.translations)
        if (std::find(languages.begin(), languages.end(), t.language) == languages.end()) languages.push_back(t.language);
    if (!languages.empty()) out += indent + fmt::format("    its texts also in: {}\n", fmt::join(languages, ", "));
    return out;
}

}  // namespace

void hsr::host::set_builtin_plugin_dirs(std::vector<fs::path> dirs) { builtin_plugin_dirs = std::move(dirs); }

void hsr::host::check_plugin_dirs(const std::vector<std::string>& extra_dirs) {
    for (const std::string& dir : extra_dirs) {
        std::error_code ec;
        const fs::file_status status = fs::status(dir, ec);
        const std::string shown = hsr::printable(dir, hsr::kMaxQuotedPathChars);
        if (!fs::exists(status)) throw hsr::UsageError("--plugin-path '{}': no such folder", shown);
        if (!fs::is_directory(status)) throw hsr::UsageError("--plugin-path '{}': is not a folder", shown);
    }
}

hsr::PluginRegistry hsr::host::scan_plugins(const std::vector<std::string>& extra_dirs) {
    check_plugin_dirs(extra_dirs);
    std::vector<fs::path> dirs;
    if (builtin_plugin_dirs) {
        dirs = *builtin_plugin_dirs;
        for (fs::path& dir : hsr::plugin_path_dirs(extra_dirs)) dirs.push_back(std::move(dir));
    } else {
        dirs = hsr::default_plugin_dirs(fs::path(boost::dll::program_location().parent_path().string()), extra_dirs);
    }
    hsr::PluginRegistry registry;
    for (const fs::path& dir : dirs) registry.scan_directory(dir);
    return registry;
}

std::string hsr::host::describe_plugins(const hsr::PluginRegistry& registry, const std::string& indent) {
    std::string out;
    for (hsr_plugin_kind kind : {HSR_KIND_HIDDEN_SURFACE_REMOVER, HSR_KIND_HIDDEN_LINE_REMOVER, HSR_KIND_LIGHTING_MODEL}) {
        for (const hsr::Plugin& p : registry.plugins())
            if (p.descriptor.kind == kind) out += describe_plugin(p, indent);
    }
    return out;
}

