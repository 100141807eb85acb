// The one exception type the framework throws for anything a user can cause: the host prints
// what() as a one-line error and exits non-zero.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace hsr {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
    template <class... Args>
    explicit Error(fmt::format_string<Args...> format, Args&&... args)
        : std::runtime_error(fmt::format(format, std::forward<Args>(args)...)) {}
};

}  // namespace hsr
