// hsr bench --vs-llvmpipe: the same frames drawn by Mesa's llvmpipe (the hsr-llvmpipe program of
// llvmpipe/), and the ratio of hsr's frame time to llvmpipe's.
#pragma once

#include "bench/measure.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace hsr::host {

struct LlvmpipeRun {
    std::filesystem::path models_dir;
    std::string lighting;  // as -l gave it
    unsigned warmup = 1, repetitions = 5, threads = 0;
    std::vector<std::string> plugin_dirs;
    std::vector<std::string> limit_settings;  // --limit, as given
};

// The hsr-llvmpipe program: $HSR_LLVMPIPE_PROGRAM, else beside the hsr executable. Throws a one-line
// UsageError when it is not there, or when the run has no plain zbuffer or blinn-phong to compare.
std::filesystem::path find_llvmpipe_program(const std::vector<std::string>& algorithm_labels,
                                            const std::string& lighting);

// Runs the program once per model and size of the zbuffer results, and prints model, size, hsr's
// frame (visibility + shading), llvmpipe's frame and their ratio.
void print_llvmpipe_comparison(const std::filesystem::path& program, const std::vector<bench::Result>& results,
                               const LlvmpipeRun& run, std::ostream& out);

}  // namespace hsr::host
