// Limits on the work one command may ask for: triangles to draw, lights, grid samples, pixels, frames.
// Each is checked before the memory it bounds is allocated, and its error names the limit and how
// to raise it (--limit NAME=N). docs/robustness.md ("Limits") has the table.
#pragma once

#include "hsr/language.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hsr {

struct Limits {
    uint64_t triangles = 200'000'000;        // triangles drawn: every instance's triangles counted
    // Triangles stored one by one: a .scene file's meshes and polygons together, or an instanced
    // scene copied out (flatten_instances).
    uint64_t stored_triangles = 5'000'000;
    uint64_t model_bytes = 1u << 29;         // one model or .scene file (512 MiB), before it is read
    uint64_t instances = 1'000'000;          // copies placed by --repeat or a .scene `repeat`
    uint64_t lights = 1'000;
    uint64_t surface_samples = 1u << 20;     // grid samples of --surface and --heightmap
    uint64_t heightmap_pixels = 1u << 24;    // pixels of a --heightmap PNG (4096 x 4096)
    uint64_t image_pixels = 1u << 26;        // width x height x samples of a picture (8192 x 8192 x 1)
    uint64_t upload_bytes = 1u << 26;        // one file sent to hsr view (64 MiB)
    uint64_t fragments = 1u << 25;           // fragment lists of a frame (a-buffer), 32 bytes each
    uint64_t frames = 100'000;               // frames of one hsr render (--views, ranges, a --jobs file)
};

// One limit as the command line and the messages name it.
struct LimitInfo {
    const char* name;        // triangles, stored-triangles, ... as in --limit NAME=N
    uint64_t Limits::*value;
    const char* unit;        // what the count is of, in a message: "triangles to draw"
    const char* bounds;      // what it bounds, for help texts
};
std::span<const LimitInfo> limit_table();

// The limits in force for this process: the defaults until set_limits(). Set them before any work
// starts; they are read, not locked.
const Limits& limits();
void set_limits(const Limits& limits);

// "NAME=N" (N a whole number, at least 1) applied to `limits`. Throws hsr::Error for an unknown name
// (listing the known ones) or a bad number.
void apply_limit_setting(Limits& limits, std::string_view setting);
// The defaults with each setting applied in turn (the values of a command's --limit options).
Limits limits_from_settings(const std::vector<std::string>& settings);
// The help text of --limit: the syntax, then every limit with its default and what it bounds.
std::string describe_limit_option();

// Throws hsr::LimitError when `amount` is over the limit in force:
//   "<what>: <amount> <unit>, over the limit of <limit> (raise it with --limit NAME=N)"
// (without "<what>: " when what is empty); in Russian when `language` says so.
void check_limit(uint64_t Limits::*limit, uint64_t amount, std::string_view what, Language language = Language::english);

}  // namespace hsr
