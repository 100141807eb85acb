// What the fuzz targets share: a scratch folder of this process for the readers that take a path,
// the limits, and the rule for what counts as a finding. Every target feeds its input to the same
// framework entry points that `hsr render` uses; a clean refusal (hsr::Error) is
// the expected answer to bad input, while any other exception escapes to libFuzzer (or to
// replay_main.cpp), which reports it as a crash.
#pragma once

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <unistd.h>

namespace hsr::fuzz {

// A folder of its own under the system's temp folder, made on first use and removed at exit. One
// per process, so that libFuzzer's -jobs/-workers do not share files.
inline const std::filesystem::path& scratch_dir() {
    static const std::filesystem::path dir = [] {
        std::string name = (std::filesystem::temp_directory_path() / "hsr-fuzz-XXXXXX").string();
        if (::mkdtemp(name.data()) == nullptr) {
            std::perror("hsr fuzz: mkdtemp");
            std::abort();
        }
        return std::filesystem::path(name);
    }();
    static const bool cleanup_registered = [] {
        std::atexit([] {
            std::error_code ignored;
            std::filesystem::remove_all(scratch_dir(), ignored);
        });
        return true;
    }();
    (void)cleanup_registered;
    return dir;
}

// Writes `text` to `name` in the scratch folder (truncating what was there) and returns its path.
inline std::filesystem::path write_scratch_file(const std::string& name, std::string_view text) {
    const std::filesystem::path file = scratch_dir() / name;
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out) {
        std::fprintf(stderr, "hsr fuzz: cannot write %s\n", file.c_str());
        std::abort();
    }
    return file;
}

// The limits in force while fuzzing: the defaults (`hsr render` without --limit), except the three
// that bound legitimate bulk work. At their defaults a 6 KB PNG of 1024 x 1024 pixels or a `repeat
// 100 100 100` builds a million samples or instances: under a second in a release build, but 4 to
// 10 s of CPU with ASan, UBSan and coverage, which libFuzzer's 10 s timeout would report on a busy
// machine. Lowered, the same paths and the same refusals run, on less data.
inline hsr::Limits fuzzing_limits() {
    hsr::Limits limits;
    limits.instances = 10'000;
    limits.surface_samples = 1u << 16;
    limits.heightmap_pixels = 1u << 18;
    return limits;
}

// Runs `work` under fuzzing_limits(); hsr::Error is a clean refusal and must be one line.
template <class Work>
int run_one(Work&& work) {
    static const bool limits_set = [] {
        hsr::set_limits(fuzzing_limits());
        return true;
    }();
    (void)limits_set;
    try {
        work();
    } catch (const hsr::Error& e) {
        if (std::string_view(e.what()).find('\n') != std::string_view::npos) {
            std::fprintf(stderr, "hsr fuzz: an error message of more than one line:\n%s\n", e.what());
            std::abort();
        }
    }
    return 0;
}

inline std::string_view as_text(const uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

}  // namespace hsr::fuzz
