// The host's commands, which main() (main.cpp) dispatches to, and what they share. Each command lives
// in its own files: render.cpp (with render.hpp and render_*.cpp), plugins_command.cpp, bench.cpp,
// view.cpp (with view_*.cpp).
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

// One block per plugin (kind, name, version, ABI, description, then its parameters), each line
// prefixed with indent: hidden-surface plugins first, then hidden-line, then lighting; within a kind
// in the order found.
std::string describe_plugins(const hsr::PluginRegistry& registry, const std::string& indent);

// A file a command will write, named by the option that gave it. Extensions: what its name may end
// with (".png"), any when empty.
struct OutputFile {
    std::string option;
    std::filesystem::path path;
    std::vector<std::string> extensions;
};

// Checked before any work, so that a mistyped path does not cost a long render or a whole benchmark:
// each name ends in one of its extensions (any case), is not a folder, lies in a folder that exists
// and can be written (where the file is made: hsr/atomic_file.hpp; for a symbolic link, the folder
// of the file it names), the file itself can be written if it exists, and no two outputs are the
// same file. Throws UsageError for a wrong name, hsr::Error for a folder or file that cannot be
// written. Nothing is created. Returns each output's absolute path, links in it resolved.
std::vector<std::filesystem::path> check_outputs(const std::vector<OutputFile>& outputs);

// Each takes the arguments after its name and returns the exit status; a mistake is thrown as
// UsageError (or a boost::program_options::error), anything else that fails as hsr::Error.
int run_render(const std::vector<std::string>& args);
int run_plugins(const std::vector<std::string>& args);
int run_bench(const std::vector<std::string>& args);
int run_view(const std::vector<std::string>& args);

}  // namespace hsr::host
