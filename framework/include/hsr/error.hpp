// The exception types the framework throws for anything a user can cause: the host prints what() as
// a one-line error and exits non-zero (2 for a UsageError). printable() makes user text safe to quote
// in one.
#pragma once

#include "hsr/abi.h"

#include <fmt/format.h>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace hsr {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
    template <class... Args>
    explicit Error(fmt::format_string<Args...> format, Args&&... args)
        : std::runtime_error(fmt::format(format, std::forward<Args>(args)...)) {}
};

// A mistake in what was asked (an option, a request's field), as opposed to something that failed
// while doing it: hsr prints it with a hint to --help and exits with status 2.
struct UsageError : Error {
    using Error::Error;
};

// A request over one of the limits on work (limits.hpp): "..., over the limit of N (raise it with
// --limit NAME=N)".
struct LimitError : Error {
    using Error::Error;
};

// A plugin call that returned a status other than HSR_OK; what() holds the plugin's message.
struct PluginError : Error {
    PluginError(hsr_status status, const std::string& message) : Error(message), status(status) {}
    hsr_status status;
};

// Whether the plugin refused its input (HSR_ERROR_INVALID_ARGUMENT: a scene or parameter it cannot
// take; HSR_ERROR_UNSUPPORTED: something asked of it that it does not do), as opposed to failing.
bool plugin_refused_input(hsr_status status);

// Whether the error is the asker's to fix: a UsageError, a LimitError, or a PluginError for input
// the plugin refused. A server answers these with a 4xx status, anything else with a 500.
bool is_client_error(const Error& error);

// Throws an error of the same type as `error` (a LimitError stays one, a PluginError keeps its
// status) with another message: for adding where it happened ("FILE: ...") to a message.
[[noreturn]] void rethrow_with_message(const Error& error, const std::string& message);

// Text from a file, an option or a formula, fit to quote in a one-line message: control characters
// (C0, DEL, C1, the line and paragraph separators) and bytes that are not UTF-8 written as \xNN or
// \uNNNN, and text longer than max_chars characters cut there with "..." after it. Backslashes are
// kept as they are, so printable(printable(t)) == printable(t) when nothing is cut.
inline constexpr std::size_t kMaxQuotedChars = 80;
inline constexpr std::size_t kMaxQuotedPathChars = 240;  // for paths, which run longer
std::string printable(std::string_view text, std::size_t max_chars = kMaxQuotedChars);

}  // namespace hsr
