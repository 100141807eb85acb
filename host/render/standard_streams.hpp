// hsr render's standard streams: a model read from standard input (MODEL '-') into a private
// temporary file that the ordinary readers open, and the picture written to standard output
// (-o -) with every other byte anyone writes kept off it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace hsr::host {

// Standard input, read whole (at most the model-bytes limit, hsr/limits.hpp; more is a LimitError)
// into "stdin.<format>" in a fresh folder of its own under the temporary folder; the folder is
// removed with the object.
class StdinModel {
public:
    explicit StdinModel(const std::string& format);
    ~StdinModel();
    StdinModel(const StdinModel&) = delete;
    StdinModel& operator=(const StdinModel&) = delete;

    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path folder_, path_;
};

// Keeps standard output for the picture: from now on file descriptor 1 is standard error, so that
// nothing a library or plugin prints lands in the PNG, and a closed pipe is an error (EPIPE), not
// SIGPIPE, so that the other outputs' temporaries are removed.
void reserve_standard_output();
// Writes the bytes to the standard output kept by reserve_standard_output (else to descriptor 1).
// Throws hsr::Error when it cannot.
void write_standard_output(std::span<const uint8_t> bytes);

}  // namespace hsr::host
