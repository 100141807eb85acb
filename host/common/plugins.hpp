// The plugin search every command shares, and the description `hsr plugins` and `--help` print.
#pragma once

#include "hsr/plugin_registry.hpp"

#include <string>
#include <vector>

namespace hsr::host {

// Every plugin in the default folders (beside the executable, $HSR_PLUGIN_PATH) and extra_dirs.
hsr::PluginRegistry scan_plugins(const std::vector<std::string>& extra_dirs);

// One block per plugin (kind, name, version, ABI, description, then its parameters), each line
// prefixed with indent: hidden-surface plugins first, then hidden-line, then lighting; within a kind
// in the order found.
std::string describe_plugins(const hsr::PluginRegistry& registry, const std::string& indent);

}  // namespace hsr::host
