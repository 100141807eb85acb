// The host's commands, which main() (cli/main.cpp) dispatches to: each lives in its own room
// (render/, bench/, view/server/, cli/plugins_command.cpp) and defines its run_ function.
#pragma once

#include "hsr/error.hpp"

#include <cstddef>
#include <string>
#include <string_view>
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

// The most words a command may be given (a command line after the command's name, or a --jobs
// line). Boost.Program_options takes time quadratic in the count (it erases each option it has
// parsed from the front of its list): 10,000 words take seconds; 4,096 leave room for the 1,000
// --light options the lights limit allows.
inline constexpr std::size_t kMaxArguments = 4096;
inline void check_argument_count(std::size_t count) {
    if (count > kMaxArguments) throw UsageError("{} arguments, more than a command may have ({})", count, kMaxArguments);
}

// An error's text as hsr prints it: one line (control characters written as \xNN) of at most
// kMaxMessageChars characters. Each piece of user text in a message is cut shorter where it is quoted
// (hsr::printable); this holds for text that reaches a message unquoted too, such as a library's.
inline constexpr std::size_t kMaxMessageChars = 1000;
inline std::string message_line(std::string_view what) { return hsr::printable(what, kMaxMessageChars); }

}  // namespace hsr::host
