#include "hsr/image.hpp"

#include "hsr/error.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hsr {

void write_png(const std::filesystem::path& path, uint32_t width, uint32_t height, int channels,
               std::span<const uint8_t> pixels) {
    if (pixels.size() != size_t(width) * height * channels)
        throw Error("write_png: {} bytes for a {}x{}x{} image", pixels.size(), width, height, channels);
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = width;
    image.height = height;
    switch (channels) {
    case 1: image.format = PNG_FORMAT_GRAY; break;
    case 3: image.format = PNG_FORMAT_RGB; break;
    case 4: image.format = PNG_FORMAT_RGBA; break;
    default: throw Error("write_png: {} channels are not supported", channels);
    }
    if (!png_image_write_to_file(&image, path.c_str(), 0, pixels.data(), 0, nullptr)) {
        std::string why = image.message;
        png_image_free(&image);
        throw Error("cannot write {}: {}", path.string(), why);
    }
}

Image read_png_rgb(const std::filesystem::path& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path.c_str()))
        throw Error("cannot read {}: {}", path.string(), image.message);
    image.format = PNG_FORMAT_RGB;
    Image out;
    out.width = image.width;
    out.height = image.height;
    out.channels = 3;
    out.pixels.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, out.pixels.data(), 0, nullptr)) {
        std::string why = image.message;
        png_image_free(&image);
        throw Error("cannot read {}: {}", path.string(), why);
    }
    return out;
}

void write_depth_png(const std::filesystem::path& path, uint32_t width, uint32_t height,
                     std::span<const float> depth) {
    float nearest = std::numeric_limits<float>::infinity();
    float farthest = -std::numeric_limits<float>::infinity();
    for (float d : depth) {
        if (!std::isfinite(d)) continue;
        nearest = std::min(nearest, d);
        farthest = std::max(farthest, d);
    }
    const float range = farthest > nearest ? farthest - nearest : 1.0f;
    std::vector<uint8_t> grey(depth.size(), 0);
    for (size_t i = 0; i < depth.size(); ++i) {
        if (!std::isfinite(depth[i])) continue;
        const float t = (depth[i] - nearest) / range;  // 0 nearest .. 1 farthest
        grey[i] = static_cast<uint8_t>(std::lround(255.0f - t * (255.0f - 64.0f)));
    }
    write_png(path, width, height, 1, grey);
}

namespace {

// A black-body-like ramp for t in [0, 1]: black, blue, magenta-red, orange, pale yellow.
void heat_color(float t, uint8_t* rgb) {
    static constexpr float stops[][3] = {
        {0.00f, 0.00f, 0.00f}, {0.10f, 0.05f, 0.45f}, {0.65f, 0.10f, 0.45f},
        {0.95f, 0.45f, 0.10f}, {1.00f, 0.95f, 0.60f}};
    constexpr int segments = 4;
    t = std::clamp(t, 0.0f, 1.0f) * segments;
    const int i = std::min(int(t), segments - 1);
    const float f = t - float(i);
    for (int c = 0; c < 3; ++c)
        rgb[c] = static_cast<uint8_t>(std::lround(255.0f * (stops[i][c] + f * (stops[i + 1][c] - stops[i][c]))));
}

}  // namespace

void write_heat_map_png(const std::filesystem::path& path, uint32_t width, uint32_t height,
                        std::span<const uint32_t> counts, uint32_t scale_max) {
    if (counts.size() != size_t(width) * height) throw Error("heat map: {} counts for a {}x{} image", counts.size(), width, height);
    constexpr uint32_t legend_height = 16;
    const float scale = float(std::max<uint32_t>(scale_max, 1));
    std::vector<uint8_t> rgb(size_t(width) * (height + legend_height) * 3, 0);
    for (size_t i = 0; i < counts.size(); ++i)
        if (counts[i] > 0) heat_color(0.08f + 0.92f * float(counts[i]) / scale, &rgb[3 * i]);
    for (uint32_t y = 0; y < legend_height; ++y) {
        for (uint32_t x = 0; x < width; ++x) {
            uint8_t* out = &rgb[3 * ((size_t(height) + y) * width + x)];
            if (y < 3) continue;  // a black gap between picture and legend
            const float count = std::round(scale * float(x) / float(std::max<uint32_t>(width - 1, 1)));
            if (count > 0.0f) heat_color(0.08f + 0.92f * count / scale, out);
        }
    }
    write_png(path, width, height + legend_height, 3, rgb);
}

}  // namespace hsr
