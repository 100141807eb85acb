// --threads, as every command that renders takes it: one bound on every oneTBB loop of the process
// (loading, visibility, shading, the plugins' own loops), since libtbb is one library shared by the
// host and its plugins (docs/abi.md, section 7).
#pragma once

#include <tbb/global_control.h>

#include <cstddef>
#include <cstdint>
#include <optional>

namespace hsr::host {

inline constexpr int64_t kMaxThreads = 1024;

// The bound while the object lives; none for 0 (every core).
class ThreadBound {
public:
    explicit ThreadBound(int64_t threads) {
        if (threads > 0) bound_.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    }

private:
    std::optional<tbb::global_control> bound_;
};

}  // namespace hsr::host
