// The host's commands, which main() (cli/main.cpp) dispatches to: each lives in its own room
// (render/, bench/, view/server/, cli/plugins_command.cpp) and defines its run_ function.
#pragma once

#include <string>
#include <vector>

namespace hsr::host {

// Each takes the arguments after its name and returns the exit status; a mistake is thrown as
// UsageError (or a boost::program_options::error), anything else that fails as hsr::Error.
int run_render(const std::vector<std::string>& args);
int run_plugins(const std::vector<std::string>& args);
int run_bench(const std::vector<std::string>& args);
int run_view(const std::vector<std::string>& args);
// hsr view's worker process (view/server/view_workers.hpp), started by hsr view, not by people.
int run_view_worker(const std::vector<std::string>& args);

}  // namespace hsr::host
