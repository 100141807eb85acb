// The plugin search every command shares, and the description `hsr plugins` and `--help` print.
#pragma once

#include "hsr/plugin_registry.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace hsr::host {

// That each of extra_dirs (--plugin-path) is a folder: a UsageError says which is not.
void check_plugin_dirs(const std::vector<std::string>& extra_dirs);

// Every plugin in the default folders (beside the executable, $HSR_PLUGIN_PATH) and extra_dirs
// (--plugin-path), checked by check_plugin_dirs first.
hsr::PluginRegistry scan_plugins(const std::vector<std::string>& extra_dirs);

// For a front end that is not the hsr executable (the Python module): the folders scan_plugins
// searches first instead of those beside the executable. Set once, before any scan.
void set_builtin_plugin_dirs(std::vector<std::filesystem::path> dirs);

// One block per plugin (kind, name, version, ABI, description, then its parameters), each line
// prefixed with indent: hidden-surface plugins first, then hidden-line, then lighting; within a kind
// in the order found.
std::string describe_plugins(const hsr::PluginRegistry& registry, const std::string& indent);

}  // namespace hsr::host
