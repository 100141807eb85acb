// The exception types the framework throws for anything a user can cause: the host prints what() as
// a one-line error and exits non-zero (2 for a UsageError). printable() makes user text safe to quote
// in one.
#pragma once

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

// Text from a file, an option or a formula, fit to quote in a one-line message: control characters
// (C0, DEL, C1, the line and paragraph separators) and bytes that are not UTF-8 written as \xNN or
// \uNNNN, and text longer than max_chars characters cut there with "..." after it. Backslashes are
// kept as they are, so printable(printable(t)) == printable(t) when nothing is cut.
inline constexpr std::size_t kMaxQuotedChars = 80;
inline constexpr std::size_t kMaxQuotedPathChars = 240;  // for paths, which run longer
std::string printable(std::string_view text, std::size_t max_chars = kMaxQuotedChars);

}  // namespace hsr
