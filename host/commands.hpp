// What the host's subcommands share. Each subcommand lives in its own file (main.cpp: render and
// plugins; bench.cpp: bench); main() dispatches.
#pragma once

#include "hsr/error.hpp"
#include "hsr/plugin_registry.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace hsr::host {

// A usage mistake: printed with a hint to --help, exit status 2.
struct UsageError : hsr::Error {
    using hsr::Error::Error;
};

// Every plugin in the default folders (beside the executable, $HSR_PLUGIN_PATH) and extra_dirs.
hsr::PluginRegistry scan_plugins(const std::vector<std::string>& extra_dirs);

// A file a command will write, named by the option that gave it. Extensions: what its name may end
// with (".png"), any when empty.
struct OutputFile {
    std::string option;
    std::filesystem::path path;
    std::vector<std::string> extensions;
};

// Checked before any work, so that a mistyped path does not cost a long render or a whole benchmark:
// each name ends in one of its extensions (any case), is not a folder, lies in a folder that exists
// and can be written (and, if the file exists, can itself be written), and no two outputs are the
// same file. Throws UsageError for a wrong name, hsr::Error for a folder or file that cannot be
// written. Nothing is created.
void check_outputs(const std::vector<OutputFile>& outputs);

int run_bench(const std::vector<std::string>& args);

}  // namespace hsr::host
