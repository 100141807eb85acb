// PNG files that hsr writes, decoded by libpng's own reader: the pixels come back exactly, in every
// channel layout, and the file says its colours are sRGB.
#include "hsr/error.hpp"
#include "hsr/image.hpp"

#include <catch2/catch.hpp>
#include <png.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Pixels a renderer makes: flat areas, gradients and noise.
std::vector<uint8_t> test_pixels(uint32_t width, uint32_t height, int channels, uint32_t seed) {
    std::mt19937 random(seed);
    std::vector<uint8_t> pixels(std::size_t(width) * height * channels);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c) {
                uint8_t& value = pixels[(std::size_t(y) * width + x) * channels + c];
                if (x < width / 3) value = static_cast<uint8_t>(40 * c);
                else if (x < 2 * width / 3) value = static_cast<uint8_t>((x + y * (c + 1)) & 0xff);
                else value = static_cast<uint8_t>(random());
            }
    return pixels;
}

std::vector<uint8_t> decode(const fs::path& file, uint32_t width, uint32_t height, int channels) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_file(&image, file.c_str()));
    CHECK(image.width == width);
    CHECK(image.height == height);
    image.format = channels == 1 ? PNG_FORMAT_GRAY : channels == 3 ? PNG_FORMAT_RGB : PNG_FORMAT_RGBA;
    std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(image));
    REQUIRE(png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr));
    return pixels;
}

}  // namespace

TEST_CASE("write_png: libpng decodes the pixels written, grey, RGB and RGBA", "[png]") {
    const fs::path dir = fs::temp_directory_path() / "hsr-test-png";
    fs::create_directories(dir);
    for (int channels : {1, 3, 4})
        for (auto [width, height] : {std::pair<uint32_t, uint32_t>{1, 1}, {7, 3}, {512, 512}, {1000, 37}}) {
            INFO(channels << " channels, " << width << "x" << height);
            const std::vector<uint8_t> pixels = test_pixels(width, height, channels, width * 31 + channels);
            const fs::path file = dir / "out.png";
            hsr::write_png(file, width, height, channels, pixels);
            CHECK(decode(file, width, height, channels) == pixels);
            std::ifstream in(file, std::ios::binary);
            const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            CHECK(bytes.find("sRGB") != std::string::npos);
        }
}

TEST_CASE("write_png: a pixel count that does not match the size is refused", "[png]") {
    const std::vector<uint8_t> pixels(11);
    const fs::path file = fs::temp_directory_path() / "hsr-test-png-refused.png";
    CHECK_THROWS_AS(hsr::write_png(file, 2, 2, 3, pixels), hsr::Error);
    CHECK_THROWS_AS(hsr::write_png(file, 2, 2, 2, std::vector<uint8_t>(8)), hsr::Error);
    CHECK_FALSE(fs::exists(file));
}
