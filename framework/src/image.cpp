#include "hsr/image.hpp"

#include "hsr/atomic_file.hpp"
#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <cairo.h>
#include <fmt/format.h>
#include <isa-l/crc.h>
#include <isa-l/igzip_lib.h>
#include <png.h>

#include <algorithm>
#include <array>
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

void append_big_endian(std::vector<uint8_t>& out, uint32_t value) {
    const uint8_t bytes[4] = {uint8_t(value >> 24), uint8_t(value >> 16), uint8_t(value >> 8), uint8_t(value)};
    out.insert(out.end(), bytes, bytes + 4);
}

// A PNG chunk: length, type, data, and the CRC-32 of type and data.
void append_chunk(std::vector<uint8_t>& out, const char (&type)[5], std::span<const uint8_t> data) {
    append_big_endian(out, uint32_t(data.size()));
    const size_t type_at = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data.begin(), data.end());
    append_big_endian(out, crc32_gzip_refl(0, out.data() + type_at, out.size() - type_at));
}

// Working memory of compress_rows, kept by each thread between images up to kKeptBytes: a fresh
// megabyte a frame costs the viewer's 512x512 frame half a millisecond of page faults.
class ScratchBuffer {
public:
    static constexpr size_t kKeptBytes = size_t(16) << 20;
    uint8_t* get(size_t size) {
        if (size > size_) {
            bytes_.reset();
            bytes_ = std::make_unique_for_overwrite<uint8_t[]>(size);  // uninitialised: written before read
            size_ = size;
        }
        return bytes_.get();
    }
    void release_if_large() {
        if (size_ > kKeptBytes) {
            bytes_.reset();
            size_ = 0;
        }
    }

private:
    std::unique_ptr<uint8_t[]> bytes_;
    size_t size_ = 0;
};

// The image's zlib stream, compressed in one call by ISA-L's igzip at its level 1: on the bunny at
// 512x512 it takes a fifth of the CPU time of zlib's level 1, in 6 % fewer bytes; libdeflate's
// level 1 was only 1.4 times as fast as zlib's (docs/measurements/viewer.md). Every row is
// filtered by the row above (PNG's Up): on renders smaller than Sub at the same speed, and the loop
// vectorises. bytes_per_sample 1, or 2 for 16-bit samples stored big-endian (PNG's order).
std::vector<uint8_t> compress_rows(uint32_t width, uint32_t height, int channels, int bytes_per_sample,
                                   std::span<const uint8_t> pixels) {
    const size_t stride = size_t(width) * size_t(channels) * size_t(bytes_per_sample);
    const size_t filtered_size = (stride + 1) * height;
    if (filtered_size > std::numeric_limits<uint32_t>::max())
        throw Error("encode_png: a {}x{}x{} image is too large for one PNG here", width, height, channels);
    thread_local ScratchBuffer filtered_rows, level_memory, output;
    struct ReleaseLarge {
        ~ReleaseLarge() {
            for (ScratchBuffer* b : {&filtered_rows, &level_memory, &output}) b->release_if_large();
        }
    } release_large;
    uint8_t* const filtered = filtered_rows.get(filtered_size);
    for (uint32_t y = 0; y < height; ++y) {
        uint8_t* __restrict out = filtered + size_t(y) * (stride + 1);
        const uint8_t* __restrict row = pixels.data() + size_t(y) * stride;
        *out++ = 2;  // Up
        if (y == 0) {
            std::memcpy(out, row, stride);
        } else {
            const uint8_t* __restrict above = row - stride;
            for (size_t i = 0; i < stride; ++i) out[i] = uint8_t(row[i] - above[i]);
        }
    }
    constexpr uint32_t level_buffer_size = ISAL_DEF_LVL1_DEFAULT;
    uint8_t* const level_buffer = level_memory.get(level_buffer_size);
    // Room for the stream when nothing compresses: stored blocks cost 5 bytes per 64 KiB.
    size_t room = std::min<size_t>(filtered_size + filtered_size / 1024 + 1024, std::numeric_limits<uint32_t>::max());
    for (;;) {
        uint8_t* const compressed = output.get(room);
        isal_zstream stream{};  // zeroed: the init leaves fields that igzip reads (valgrind saw them)
        isal_deflate_stateless_init(&stream);
        stream.gzip_flag = IGZIP_ZLIB;
        stream.level = 1;
        stream.level_buf = level_buffer;
        stream.level_buf_size = level_buffer_size;
        stream.next_in = filtered;
        stream.avail_in = uint32_t(filtered_size);
        stream.next_out = compressed;
        stream.avail_out = uint32_t(room);
        stream.end_of_stream = 1;
        stream.flush = NO_FLUSH;
        const int status = isal_deflate_stateless(&stream);
        if (status == COMP_OK) return std::vector<uint8_t>(compressed, compressed + stream.total_out);
        if (status != STATELESS_OVERFLOW || room >= std::numeric_limits<uint32_t>::max())
            throw Error("cannot encode a PNG: igzip failed (status {})", status);
        room = std::min<size_t>(2 * room, std::numeric_limits<uint32_t>::max());
    }
}

std::vector<uint8_t> encode_png_image(uint32_t width, uint32_t height, int channels, std::span<const uint8_t> pixels,
                                      bool srgb, int bytes_per_sample = 1) {
    if (pixels.size() != size_t(width) * height * channels * bytes_per_sample)
        throw Error("encode_png: {} bytes for a {}x{}x{} image", pixels.size(), width, height, channels);
    uint8_t color_type = 2;
    switch (channels) {
    case 1: color_type = 0; break;  // grey
    case 3: color_type = 2; break;  // RGB
    case 4: color_type = 6; break;  // RGB and alpha
    default: throw Error("encode_png: {} channels are not supported", channels);
    }
    constexpr uint32_t max_png_side = 0x7fffffff;
    if (width == 0 || height == 0 || width > max_png_side || height > max_png_side)
        throw Error("encode_png: a {}x{} image", width, height);
    const std::vector<uint8_t> zlib_stream = compress_rows(width, height, channels, bytes_per_sample, pixels);

    static constexpr uint8_t signature[8] = {137, 'P', 'N', 'G', '\r', '\n', 26, '\n'};
    std::vector<uint8_t> out(std::begin(signature), std::end(signature));
    out.reserve(zlib_stream.size() + 128);
    std::vector<uint8_t> header;
    append_big_endian(header, width);
    append_big_endian(header, height);
    // bit depth, colour type, compression (deflate), filter method (adaptive), interlace (none)
    header.insert(header.end(), {uint8_t(8 * bytes_per_sample), color_type, 0, 0, 0});
    append_chunk(out, "IHDR", header);
    if (srgb) append_chunk(out, "sRGB", std::array<uint8_t, 1>{0});  // rendering intent: perceptual
    constexpr size_t max_chunk = size_t(1) << 30;  // a chunk holds less than 2^31 bytes
    for (size_t at = 0; at < zlib_stream.size(); at += max_chunk)
        append_chunk(out, "IDAT", std::span(zlib_stream).subspan(at, std::min(max_chunk, zlib_stream.size() - at)));
    append_chunk(out, "IEND", {});
    return out;
}

}  // namespace

std::vector<uint8_t> encode_png(uint32_t width, uint32_t height, int channels, std::span<const uint8_t> pixels) {
    return encode_png_image(width, height, channels, pixels, false);
}

// Encoded as encode_png does, tagged sRGB: the pixels are sRGB values.
std::vector<uint8_t> encode_picture_png(uint32_t width, uint32_t height, int channels,
                                        std::span<const uint8_t> pixels) {
    return encode_png_image(width, height, channels, pixels, true);
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
    const std::vector<uint8_t> png = encode_png_image(width, height, channels, big_endian, false, 2);
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
