#include "hsr/image.hpp"

#include "hsr/atomic_file.hpp"
#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <cairo.h>
#include <fmt/format.h>
#include <png.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace hsr {

void write_png(const std::filesystem::path& path, uint32_t width, uint32_t height, int channels,
               std::span<const uint8_t> pixels) {
    AtomicFile file(path);
    write_png(file, width, height, channels, pixels);
    file.commit();
}

namespace {

struct PngMemoryWriter {
    std::vector<uint8_t>* out;
    std::string error;
};

void append_png_bytes(png_structp png, png_bytep data, png_size_t length) {
    auto* writer = static_cast<PngMemoryWriter*>(png_get_io_ptr(png));
    writer->out->insert(writer->out->end(), data, data + length);
}

void flush_nothing(png_structp) {}

[[noreturn]] void png_failed(png_structp png, png_const_charp message) {
    static_cast<PngMemoryWriter*>(png_get_error_ptr(png))->error = message;
    png_longjmp(png, 1);
}

void png_warning_ignored(png_structp, png_const_charp) {}

// The libpng calls of encode_png, apart so that no C++ object with a destructor lives in the frame
// that longjmp leaves. Returns false on failure (writer.error says why).
bool write_png_rows(PngMemoryWriter& writer, uint32_t width, uint32_t height, int bit_depth, int color_type,
                    int zlib_level, bool srgb, const png_bytep* rows) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &writer, png_failed, png_warning_ignored);
    if (png == nullptr) return false;
    png_infop info = png_create_info_struct(png);
    if (info == nullptr || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &writer, append_png_bytes, flush_nothing);
    png_set_compression_level(png, zlib_level);
    // One cheap filter: the adaptive choice among all five costs more time than it saves bytes here.
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_IHDR(png, info, width, height, bit_depth, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    png_write_image(png, const_cast<png_bytepp>(rows));
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

// bytes_per_sample 1, or 2 for 16-bit samples stored big-endian (PNG's order).
std::vector<uint8_t> encode_png_image(uint32_t width, uint32_t height, int channels, std::span<const uint8_t> pixels,
                                      int zlib_level, bool srgb, int bytes_per_sample = 1) {
    if (pixels.size() != size_t(width) * height * channels * bytes_per_sample)
        throw Error("encode_png: {} bytes for a {}x{}x{} image", pixels.size(), width, height, channels);
    int color_type = PNG_COLOR_TYPE_RGB;
    switch (channels) {
    case 1: color_type = PNG_COLOR_TYPE_GRAY; break;
    case 3: color_type = PNG_COLOR_TYPE_RGB; break;
    case 4: color_type = PNG_COLOR_TYPE_RGB_ALPHA; break;
    default: throw Error("encode_png: {} channels are not supported", channels);
    }
    if (width == 0 || height == 0) throw Error("encode_png: a {}x{} image", width, height);
    std::vector<png_bytep> rows(height);
    for (uint32_t y = 0; y < height; ++y)
        rows[y] = const_cast<png_bytep>(pixels.data() + size_t(y) * width * channels * bytes_per_sample);
    std::vector<uint8_t> out;
    out.reserve(pixels.size() / 4 + 1024);
    PngMemoryWriter writer{&out, {}};
    if (!write_png_rows(writer, width, height, 8 * bytes_per_sample, color_type, std::clamp(zlib_level, 0, 9), srgb,
                        rows.data()))
        throw Error("cannot encode a PNG: {}", writer.error.empty() ? "out of memory" : writer.error);
    return out;
}

}  // namespace

std::vector<uint8_t> encode_png(uint32_t width, uint32_t height, int channels, std::span<const uint8_t> pixels,
                                int zlib_level) {
    return encode_png_image(width, height, channels, pixels, zlib_level, false);
}

// Encoded as encode_png does (zlib level 1, Sub filter), tagged sRGB: the pixels are sRGB values.
std::vector<uint8_t> encode_picture_png(uint32_t width, uint32_t height, int channels,
                                        std::span<const uint8_t> pixels) {
    return encode_png_image(width, height, channels, pixels, 1, true);
}

void write_png(AtomicFile& file, uint32_t width, uint32_t height, int channels, std::span<const uint8_t> pixels) {
    const std::vector<uint8_t> png = encode_picture_png(width, height, channels, pixels);
    if (std::fwrite(png.data(), 1, png.size(), file.stdio()) != png.size())
        throw Error("cannot write {}: {}", printable(file.target().string(), kMaxQuotedPathChars), std::strerror(errno));
}

void write_png16(AtomicFile& file, uint32_t width, uint32_t height, int channels, std::span<const uint16_t> samples) {
    std::vector<uint8_t> big_endian(2 * samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        big_endian[2 * i] = uint8_t(samples[i] >> 8);
        big_endian[2 * i + 1] = uint8_t(samples[i] & 0xff);
    }
    const std::vector<uint8_t> png = encode_png_image(width, height, channels, big_endian, 1, false, 2);
    if (std::fwrite(png.data(), 1, png.size(), file.stdio()) != png.size())
        throw Error("cannot write {}: {}", printable(file.target().string(), kMaxQuotedPathChars), std::strerror(errno));
}

Image read_png_rgb(const std::filesystem::path& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path.c_str()))
        throw Error("cannot read {}: {}", printable(path.string(), kMaxQuotedPathChars), image.message);
    image.format = PNG_FORMAT_RGB;
    try {
        check_limit(&Limits::image_pixels, uint64_t(image.width) * image.height, printable(path.string()));
    } catch (...) {
        png_image_free(&image);
        throw;
    }
    Image out;
    out.width = image.width;
    out.height = image.height;
    out.channels = 3;
    out.pixels.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, out.pixels.data(), 0, nullptr)) {
        std::string why = image.message;
        png_image_free(&image);
        throw Error("cannot read {}: {}", printable(path.string(), kMaxQuotedPathChars), why);
    }
    return out;
}

void write_depth_png(AtomicFile& file, uint32_t width, uint32_t height,
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
    write_png(file, width, height, 1, grey);
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

// Counts to label on a ramp from 0 to scale_max that is `width` pixels wide: 0, scale_max, and the
// multiples of a round step (1, 2 or 5 times a power of ten) between them.
std::vector<uint32_t> legend_ticks(uint32_t scale_max, uint32_t width) {
    std::vector<uint32_t> ticks{0};
    if (scale_max == 0) return ticks;
    const double wanted = std::clamp(double(width) / 80.0, 1.0, 6.0);  // labels about 80 pixels apart
    double step = 1.0;
    while (double(scale_max) / step > wanted) {
        for (double factor : {2.0, 2.5, 2.0}) {  // 1, 2, 5, 10, 20, 50, ...
            step *= factor;
            if (double(scale_max) / step <= wanted) break;
        }
    }
    for (double v = step; v < double(scale_max); v += step) ticks.push_back(uint32_t(v));
    ticks.push_back(scale_max);
    return ticks;
}

// White labels and tick marks on black, drawn with Cairo into rows [top, top + rows) of an RGB image.
void draw_legend_labels(std::vector<uint8_t>& rgb, uint32_t width, uint32_t top, uint32_t rows, uint32_t scale_max) {
    std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
        cairo_image_surface_create(CAIRO_FORMAT_A8, int(width), int(rows)), &cairo_surface_destroy);
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(surface.get()), &cairo_destroy);
    if (cairo_status(cr.get()) != CAIRO_STATUS_SUCCESS) return;  // no labels rather than no picture
    cairo_select_font_face(cr.get(), "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr.get(), 11.0);
    const double last = double(std::max<uint32_t>(width, 2) - 1), baseline = double(rows) - 3.0;
    auto text_width = [&](const std::string& text) {
        cairo_text_extents_t extents;
        cairo_text_extents(cr.get(), text.c_str(), &extents);
        return extents.x_advance;
    };
    auto draw = [&](double tick_x, double left, const std::string& text) {
        cairo_rectangle(cr.get(), tick_x, 0.0, 1.0, 3.0);
        cairo_fill(cr.get());
        cairo_move_to(cr.get(), left, baseline);
        cairo_show_text(cr.get(), text.c_str());
    };
    // The ends are aligned inward, 0 at the left and scale_max at the right; a label in between is
    // centred on its tick, and left out where it would come within 6 pixels of a neighbour.
    const std::vector<uint32_t> ticks = legend_ticks(scale_max, width);
    const std::string end_text = fmt::format("{}", ticks.back());
    const double end_left = ticks.size() == 1 ? 1.0 : last + 1.0 - text_width(end_text);
    double taken = -1e9;  // right end of the last label drawn
    for (size_t i = 0; i + 1 < ticks.size(); ++i) {
        const std::string text = fmt::format("{}", ticks[i]);
        const double w = text_width(text), x = last * double(ticks[i]) / double(scale_max);
        const double left = i == 0 ? 1.0 : x - w / 2.0;
        if (i > 0 && (left < taken + 6.0 || left + w + 6.0 > end_left)) continue;
        draw(std::round(x), left, text);
        taken = left + w;
    }
    if (end_left >= taken + 6.0) draw(ticks.size() == 1 ? 0.0 : last - 1.0, end_left, end_text);
    cairo_surface_flush(surface.get());
    const unsigned char* data = cairo_image_surface_get_data(surface.get());
    const int stride = cairo_image_surface_get_stride(surface.get());
    for (uint32_t y = 0; y < rows; ++y)
        for (uint32_t x = 0; x < width; ++x)
            std::fill_n(&rgb[3 * ((size_t(top) + y) * width + x)], 3, data[size_t(y) * size_t(stride) + x]);
}

}  // namespace

void write_heat_map_png(AtomicFile& file, uint32_t width, uint32_t height, std::span<const uint32_t> counts,
                        uint32_t scale_max) {
    if (counts.size() != size_t(width) * height) throw Error("heat map: {} counts for a {}x{} image", counts.size(), width, height);
    // Below the picture: a black gap, the ramp, and the row of labels.
    constexpr uint32_t gap = 3, ramp = 10, labels = heat_map_legend_height - gap - ramp;
    const float scale = float(std::max<uint32_t>(scale_max, 1));
    std::vector<uint8_t> rgb(size_t(width) * (height + heat_map_legend_height) * 3, 0);
    for (size_t i = 0; i < counts.size(); ++i)
        if (counts[i] > 0) heat_color(0.08f + 0.92f * float(counts[i]) / scale, &rgb[3 * i]);
    for (uint32_t y = height + gap; y < height + gap + ramp; ++y) {
        for (uint32_t x = 0; x < width; ++x) {
            const float count = std::round(scale * float(x) / float(std::max<uint32_t>(width - 1, 1)));
            if (count > 0.0f) heat_color(0.08f + 0.92f * count / scale, &rgb[3 * (size_t(y) * width + x)]);
        }
    }
    draw_legend_labels(rgb, width, height + gap + ramp, labels, scale_max);
    write_png(file, width, height + heat_map_legend_height, 3, rgb);
}

}  // namespace hsr
