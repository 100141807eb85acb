// Image output: 8-bit (and 16-bit data) PNG, compressed by ISA-L's igzip (read back through libpng), into an AtomicFile (hsr/atomic_file.hpp) that the caller
// commits, or, given a path, into a file of its own committed at once, or into memory.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace hsr {

class AtomicFile;

// channels: 1 (grey), 3 (RGB) or 4 (RGBA); rows top to bottom; compressed as encode_png compresses,
// marked as sRGB. Throws hsr::Error if the file cannot be written.
void write_png(AtomicFile& file, uint32_t width, uint32_t height, int channels, std::span<const uint8_t> pixels);
void write_png(const std::filesystem::path& path, uint32_t width, uint32_t height, int channels,
               std::span<const uint8_t> pixels);

// The bytes write_png writes, for standard output.
std::vector<uint8_t> encode_picture_png(uint32_t width, uint32_t height, int channels,
                                        std::span<const uint8_t> pixels);

// 16-bit samples (channels 1, 3 or 4), rows top to bottom, not tagged as colour (they are data:
// the --id-out PNG).
void write_png16(AtomicFile& file, uint32_t width, uint32_t height, int channels, std::span<const uint16_t> samples);

// The PNG file's bytes, for a server: each row filtered by the one above (PNG's Up), compressed
// by ISA-L's igzip at level 1 in one pass. The bunny at 512x512 takes a fifth of the CPU time of
// libpng at zlib level 1 with the Sub filter, in 6 % fewer bytes (docs/measurements/viewer.md).
// Throws hsr::Error as write_png does.
std::vector<uint8_t> encode_png(uint32_t width, uint32_t height, int channels, std::span<const uint8_t> pixels);

struct Image {
    uint32_t width = 0;
    uint32_t height = 0;
    int channels = 0;
    std::vector<uint8_t> pixels;  // rows top to bottom
};
// Reads any PNG as 8-bit RGB (channels 3); throws hsr::Error if it cannot.
Image read_png_rgb(const std::filesystem::path& path);

// Depth buffer as greyscale: nearest covered depth white, farthest covered depth dark grey (64),
// uncovered pixels black. Only finite values count.
void write_depth_png(AtomicFile& file, uint32_t width, uint32_t height,
                     std::span<const float> depth);

// Per-pixel counts (depth complexity, depth tests) as a heat map: 0 black, then dark blue through
// red and orange to yellow-white at scale_max (counts above it saturate). Below the image, a strip
// heat_map_legend_height pixels high shows the ramp from 0 (left) to scale_max (right), labelled
// with counts, so pictures with the same scale_max compare directly.
constexpr uint32_t heat_map_legend_height = 28;
void write_heat_map_png(AtomicFile& file, uint32_t width, uint32_t height, std::span<const uint32_t> counts,
                        uint32_t scale_max);

}  // namespace hsr
