// Image output: 8-bit PNG through libpng.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace hsr {

// channels: 1 (grey), 3 (RGB) or 4 (RGBA); rows top to bottom. Throws hsr::Error if the file cannot
// be written.
void write_png(const std::filesystem::path& path, uint32_t width, uint32_t height, int channels,
               std::span<const uint8_t> pixels);

// Depth buffer as greyscale: nearest covered depth white, farthest covered depth dark grey (64),
// uncovered pixels black. Only finite values count.
void write_depth_png(const std::filesystem::path& path, uint32_t width, uint32_t height,
                     std::span<const float> depth);

}  // namespace hsr
