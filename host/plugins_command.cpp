// hsr plugins: every plugin found, with its parameters, and the folders searched; also the plugin
// search the other commands share (commands.hpp).
#include "commands.hpp"

#include "hsr/params.hpp"
#include "hsr/plugin_registry.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/program_options.hpp>
#include <fmt/format.h>

#include <iostream>
#include <string>
#include <vector>

namespace po = boost::program_options;
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

int hsr::host::run_plugins(const std::vector<std::string>& args) {
    po::options_description options("hsr plugins: list every plugin found");
    std::vector<std::string> plugin_dirs;
    options.add_options()("help,h", "show this help")(
        "plugin-path", po::value(&plugin_dirs)->composing(), "extra folder to search for plugins (repeatable)");
    po::variables_map vm;
    std::vector<std::string> unexpected;
    po::options_description hidden;
    hidden.add_options()("unexpected", po::value(&unexpected));
    po::options_description all;
    all.add(options).add(hidden);
    po::positional_options_description positional;
    positional.add("unexpected", -1);
    po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
    po::notify(vm);
    if (!unexpected.empty()) throw UsageError("plugins: unexpected argument '{}'", unexpected.front());
    if (vm.count("help")) {
        std::cout << options;
        return 0;
    }
    hsr::PluginRegistry registry = scan_plugins(plugin_dirs);
    std::string dirs;
    for (const fs::path& d : registry.searched()) dirs += "  " + d.string() + "\n";
    std::cout << "searched:\n" << dirs << "\n";
    std::cout << describe_plugins(registry, "");
    if (registry.plugins().empty()) std::cout << "no plugins found\n";
    for (const hsr::RejectedLibrary& r : registry.rejected()) std::cout << "refused: " << r.reason << "\n";
    return 0;
}
