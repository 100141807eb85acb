// hsr plugins: every plugin found, with its parameters, and the folders searched.
#include "common/command_line.hpp"
#include "common/commands.hpp"
#include "common/options.hpp"
#include "common/plugins.hpp"

#include "hsr/params.hpp"
#include "hsr/plugin_registry.hpp"

#include <boost/program_options.hpp>
#include <fmt/format.h>

#include <iostream>
#include <string>
#include <vector>

namespace po = boost::program_options;
namespace fs = std::filesystem;

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
    po::command_line_parser parser(args);
    parser.options(all).positional(positional);
    po::store(hsr::host::parse_command_line(parser, options), vm);
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
