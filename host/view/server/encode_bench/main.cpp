// hsr-bench-png FILE.png... [--repetitions N]: times what the viewer does with each frame it sends
// (host/view/server/view_frames.cpp: PNG, then base64 for a data URL) on the pixels of each file,
// with hsr's encoder (hsr::encode_png) and, as the yardstick, libpng at zlib level 1 with the Sub
// filter. The two run in turns, so that a busy machine slows both alike; medians and min-max of
// wall time and of the thread's CPU time (less disturbed by other processes), and the sizes. The pixels of every file hsr's encoder wrote are checked with libpng.
#include "hsr/image.hpp"
#include "view/server/view_frames.hpp"

#include <png.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

namespace {

void append_bytes(png_structp png, png_bytep data, png_size_t length) {
    auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
    out->insert(out->end(), data, data + length);
}

void flush_nothing(png_structp) {}

// libpng at zlib level 1, every row Sub-filtered, 8-bit RGB: the viewer's encoder before hsr's own.
std::vector<uint8_t> libpng_level1_sub(const hsr::Image& image) {
    std::vector<uint8_t> out;
    out.reserve(image.pixels.size() / 4);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        std::fprintf(stderr, "hsr-bench-png: error: libpng failed\n");
        std::exit(1);
    }
    png_set_write_fn(png, &out, append_bytes, flush_nothing);
    png_set_compression_level(png, 1);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    std::vector<png_bytep> rows(image.height);
    for (uint32_t y = 0; y < image.height; ++y)
        rows[y] = const_cast<png_bytep>(image.pixels.data() + std::size_t(y) * image.width * 3);
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return out;
}

bool decodes_to(const std::vector<uint8_t>& file, const hsr::Image& image) {
    png_image decoded{};
    decoded.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&decoded, file.data(), file.size())) return false;
    decoded.format = PNG_FORMAT_RGB;
    std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(decoded));
    if (!png_image_finish_read(&decoded, nullptr, pixels.data(), 0, nullptr)) return false;
    return decoded.width == image.width && decoded.height == image.height && pixels == image.pixels;
}

double thread_cpu_ms() {
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return double(now.tv_sec) * 1e3 + double(now.tv_nsec) * 1e-6;
}

struct Timing {
    std::vector<double> ms, cpu_ms;
    std::size_t bytes = 0;
    std::string summary() {
        std::sort(ms.begin(), ms.end());
        std::sort(cpu_ms.begin(), cpu_ms.end());
        char text[128];
        std::snprintf(text, sizeof text, "%7.2f ms [%.2f-%.2f]  CPU %5.2f ms [%.2f-%.2f]  %8zu bytes", ms[ms.size() / 2],
                      ms.front(), ms.back(), cpu_ms[cpu_ms.size() / 2], cpu_ms.front(), cpu_ms.back(), bytes);
        return text;
    }
};

// The viewer's work on one frame: the PNG, then its data URL.
void time_frame(Timing& timing, const std::function<std::vector<uint8_t>()>& encode) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = thread_cpu_ms();
    const std::vector<uint8_t> png = encode();
    const std::string url = "data:image/png;base64," + hsr::host::base64(png.data(), png.size());
    timing.cpu_ms.push_back(thread_cpu_ms() - cpu_start);
    timing.ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    timing.bytes = png.size();
}

}  // namespace

int main(int argc, char** argv) {
    int repetitions = 51;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        if ((word == "--repetitions" || word == "-r") && i + 1 < argc) repetitions = std::atoi(argv[++i]);
        else if (!word.empty() && word[0] != '-') files.push_back(word);
        else {
            std::fprintf(stderr, "usage: hsr-bench-png FILE.png... [--repetitions N]\n");
            return 2;
        }
    }
    if (files.empty() || repetitions < 1 || repetitions > 100000) {
        std::fprintf(stderr, "usage: hsr-bench-png FILE.png... [--repetitions N] (N from 1 to 100000)\n");
        return 2;
    }
    try {
        for (const std::string& file : files) {
            const hsr::Image image = hsr::read_png_rgb(file);
            if (!decodes_to(hsr::encode_png(image.width, image.height, 3, image.pixels), image)) {
                std::fprintf(stderr, "hsr-bench-png: error: %s: libpng does not read back the pixels\n", file.c_str());
                return 1;
            }
            Timing libpng, hsr_encoder;
            for (int warmup = 0; warmup < 3; ++warmup) libpng_level1_sub(image), hsr::encode_png(image.width, image.height, 3, image.pixels);
            for (int r = 0; r < repetitions; ++r) {
                time_frame(libpng, [&] { return libpng_level1_sub(image); });
                time_frame(hsr_encoder, [&] { return hsr::encode_png(image.width, image.height, 3, image.pixels); });
            }
            std::printf("%s (%ux%u), PNG + base64, median [min-max] of %d:\n", file.c_str(), image.width, image.height,
                        repetitions);
            std::printf("  libpng, zlib level 1, Sub   %s\n", libpng.summary().c_str());
            std::printf("  hsr::encode_png (igzip, Up) %s\n", hsr_encoder.summary().c_str());
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "hsr-bench-png: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
