// Per-pixel data as files for other programs: NumPy's .npy (float32 or int32), PFM and OpenEXR
// (float32), each into an AtomicFile (hsr/atomic_file.hpp) that the caller commits. Pixels are
// interleaved (channel fastest), rows top to bottom, as in every buffer of a frame (frame.hpp).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace hsr {

class AtomicFile;

// NPY format 1.0: the magic, a header dict padded so that the data starts at a multiple of 64
// bytes, then the values little-endian in C order, shape (height, width) for one channel and
// (height, width, channels) for more.
void write_npy(AtomicFile& file, uint32_t width, uint32_t height, uint32_t channels, std::span<const float> values);
void write_npy(AtomicFile& file, uint32_t width, uint32_t height, uint32_t channels, std::span<const int32_t> values);

// Portable float map: "Pf" (1 channel) or "PF" (3), a negative scale for little-endian, rows
// bottom to top as the format has them.
void write_pfm(AtomicFile& file, uint32_t width, uint32_t height, uint32_t channels, std::span<const float> values);

// OpenEXR, one float32 channel per name (e.g. "Z", or "R", "G", "B"), ZIP-compressed (lossless).
void write_exr(AtomicFile& file, uint32_t width, uint32_t height, const std::vector<std::string>& channel_names,
               std::span<const float> values);

}  // namespace hsr
