// What the host's subcommands share. Each subcommand lives in its own file (main.cpp: render and
// plugins; bench.cpp: bench); main() dispatches.
#pragma once

#include "hsr/error.hpp"
#include "hsr/plugin_registry.hpp"

#include <string>
#include <vector>

namespace hsr::host {

// A usage mistake: printed with a hint to --help, exit status 2.
struct UsageError : hsr::Error {
    using hsr::Error::Error;
};

// Every plugin in the default folders (beside the executable, $HSR_PLUGIN_PATH) and extra_dirs.
hsr::PluginRegistry scan_plugins(const std::vector<std::string>& extra_dirs);

int run_bench(const std::vector<std::string>& args);

}  // namespace hsr::host
