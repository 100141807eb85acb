// hsr's own PNG encoder (hsr/image.hpp) against libpng's decoder and zlib's CRC-32: random pixels
// and real renders come back byte for byte in grey, RGB and RGBA, 8 and 16 bits, at odd sizes and
// 1x1; every chunk's CRC is right; flat pictures compress; bad input is refused.
#include "hsr/atomic_file.hpp"
#include "hsr/error.hpp"
#include "hsr/image.hpp"

#include <catch2/catch.hpp>
#include <png.h>
#include <zlib.h>

#include <csetjmp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> random_bytes(std::size_t count, uint32_t seed) {
    std::mt19937 random(seed);
    std::vector<uint8_t> bytes(count);
    for (uint8_t& b : bytes) b = static_cast<uint8_t>(random());
    return bytes;
}

struct Decoded {
    uint32_t width = 0, height = 0;
    int bit_depth = 0, color_type = 0;
    bool srgb = false;
    std::vector<uint8_t> samples;  // rows top to bottom, 16-bit samples big-endian as in the file
};

struct ReadSource {
    const std::vector<uint8_t>* bytes;
    std::size_t at = 0;
};

void read_from_memory(png_structp png, png_bytep out, png_size_t length) {
    auto* source = static_cast<ReadSource*>(png_get_io_ptr(png));
    if (source->at + length > source->bytes->size()) png_error(png, "read past the end");
    std::memcpy(out, source->bytes->data() + source->at, length);
    source->at += length;
}

[[noreturn]] void quiet_error(png_structp png, png_const_charp) { png_longjmp(png, 1); }
void quiet_warning(png_structp, png_const_charp) {}

// libpng's low-level reader with no transformation: the samples exactly as the file stores them.
// Returns false where libpng refuses the file (a bad CRC, a bad zlib stream, ...).
bool libpng_decode(const std::vector<uint8_t>& file, Decoded& out) {
    ReadSource source{&file};
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, quiet_error, quiet_warning);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_set_read_fn(png, &source, read_from_memory);
    png_read_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
    out.width = png_get_image_width(png, info);
    out.height = png_get_image_height(png, info);
    out.bit_depth = png_get_bit_depth(png, info);
    out.color_type = png_get_color_type(png, info);
    int intent = 0;
    out.srgb = png_get_sRGB(png, info, &intent) != 0;
    const std::size_t row_bytes = png_get_rowbytes(png, info);
    png_bytepp rows = png_get_rows(png, info);
    out.samples.clear();
    for (uint32_t y = 0; y < out.height; ++y) out.samples.insert(out.samples.end(), rows[y], rows[y] + row_bytes);
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

int png_color_type(int channels) {
    return channels == 1 ? PNG_COLOR_TYPE_GRAY : channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA;
}

uint32_t big_endian(const uint8_t* p) {
    return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3];
}

// The chunk types in order; checks each chunk's length and its CRC-32 with zlib's.
std::vector<std::string> chunk_types(const std::vector<uint8_t>& file) {
    static constexpr uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    REQUIRE(file.size() >= 8);
    REQUIRE(std::memcmp(file.data(), signature, 8) == 0);
    std::vector<std::string> types;
    std::size_t at = 8;
    while (at < file.size()) {
        REQUIRE(at + 12 <= file.size());
        const uint32_t length = big_endian(&file[at]);
        REQUIRE(at + 12 + length <= file.size());
        const uint32_t crc = uint32_t(crc32(0, &file[at + 4], 4 + length));
        CHECK(big_endian(&file[at + 8 + length]) == crc);
        types.emplace_back(reinterpret_cast<const char*>(&file[at + 4]), 4);
        at += 12 + length;
    }
    CHECK(at == file.size());
    return types;
}

void check_round_trip(uint32_t width, uint32_t height, int channels, const std::vector<uint8_t>& pixels) {
    INFO(channels << " channels, " << width << "x" << height);
    for (bool picture : {false, true}) {
        const std::vector<uint8_t> file = picture ? hsr::encode_picture_png(width, height, channels, pixels)
                                                  : hsr::encode_png(width, height, channels, pixels);
        Decoded decoded;
        REQUIRE(libpng_decode(file, decoded));
        CHECK(decoded.width == width);
        CHECK(decoded.height == height);
        CHECK(decoded.bit_depth == 8);
        CHECK(decoded.color_type == png_color_type(channels));
        CHECK(decoded.srgb == picture);
        CHECK(decoded.samples == pixels);
        const std::vector<std::string> types = chunk_types(file);
        REQUIRE(types.size() >= 3);
        CHECK(types.front() == "IHDR");
        CHECK(types.back() == "IEND");
    }
}

std::vector<uint8_t> read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_CASE("PNG encoder: random pixels come back through libpng, every layout and odd sizes", "[png]") {
    const std::vector<std::pair<uint32_t, uint32_t>> sizes = {{1, 1}, {1, 9}, {9, 1}, {7, 3}, {33, 17}, {511, 5}, {257, 256}};
    for (int channels : {1, 3, 4})
        for (auto [width, height] : sizes)
            check_round_trip(width, height, channels,
                             random_bytes(std::size_t(width) * height * channels, width * 131 + height * 7 + channels));
}

TEST_CASE("PNG encoder: real renders come back byte for byte", "[png]") {
    // Pictures hsr rendered for the docs: shading, flat background, lines and text.
    for (const char* name : {"appel-bunny.png", "antialiasing-supersampling.png", "bench.png", "a-buffer-glass.png"}) {
        const fs::path path = fs::path(HSR_SOURCE_DIR) / "docs" / "images" / name;
        INFO(path);
        REQUIRE(fs::exists(path));
        const hsr::Image image = hsr::read_png_rgb(path);
        check_round_trip(image.width, image.height, 3, image.pixels);
        // The same picture cut to an odd width, as RGBA with a varying alpha, and as grey.
        const uint32_t width = image.width - 1 - image.width % 2, height = image.height;
        std::vector<uint8_t> rgba, grey;
        for (uint32_t y = 0; y < height; ++y)
            for (uint32_t x = 0; x < width; ++x) {
                const uint8_t* p = &image.pixels[(std::size_t(y) * image.width + x) * 3];
                rgba.insert(rgba.end(), {p[0], p[1], p[2], uint8_t(x + y)});
                grey.push_back(p[1]);
            }
        check_round_trip(width, height, 4, rgba);
        check_round_trip(width, height, 1, grey);
        // A render compresses: well under a third of its raw size.
        CHECK(hsr::encode_png(image.width, image.height, 3, image.pixels).size() * 3 < image.pixels.size());
    }
}

TEST_CASE("PNG encoder: a flat picture compresses to a few kilobytes", "[png]") {
    const std::vector<uint8_t> flat(std::size_t(1024) * 1024 * 3, 200);
    const std::vector<uint8_t> file = hsr::encode_png(1024, 1024, 3, flat);
    CHECK(file.size() < 16 * 1024);
    Decoded decoded;
    REQUIRE(libpng_decode(file, decoded));
    CHECK(decoded.samples == flat);
}

TEST_CASE("PNG encoder: noise that does not compress still makes a valid file", "[png]") {
    const std::vector<uint8_t> noise = random_bytes(std::size_t(640) * 480 * 4, 99);
    const std::vector<uint8_t> file = hsr::encode_png(640, 480, 4, noise);
    Decoded decoded;
    REQUIRE(libpng_decode(file, decoded));
    CHECK(decoded.samples == noise);
}

TEST_CASE("PNG encoder: 16-bit samples come back through libpng", "[png]") {
    const fs::path path = fs::temp_directory_path() / "hsr-test-png-encoder-16.png";
    for (int channels : {1, 3, 4})
        for (auto [width, height] : {std::pair<uint32_t, uint32_t>{1, 1}, {13, 7}, {300, 2}}) {
            INFO(channels << " channels, " << width << "x" << height);
            const std::vector<uint8_t> bytes = random_bytes(std::size_t(width) * height * channels * 2, width + channels);
            std::vector<uint16_t> samples(bytes.size() / 2);
            for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = uint16_t(bytes[2 * i] << 8 | bytes[2 * i + 1]);
            {
                hsr::AtomicFile file(path);
                hsr::write_png16(file, width, height, channels, samples);
                file.commit();
            }
            Decoded decoded;
            REQUIRE(libpng_decode(read_file(path), decoded));
            CHECK(decoded.bit_depth == 16);
            CHECK(decoded.color_type == png_color_type(channels));
            CHECK_FALSE(decoded.srgb);
            CHECK(decoded.samples == bytes);  // big-endian in the file, as random_bytes made them
        }
    fs::remove(path);
}

TEST_CASE("PNG encoder: a corrupted byte is caught by the decoder", "[png]") {
    // The independent check that chunk_types and libpng_decode can fail at all.
    const std::vector<uint8_t> pixels = random_bytes(20 * 20 * 3, 5);
    std::vector<uint8_t> file = hsr::encode_png(20, 20, 3, pixels);
    file[file.size() / 2] ^= 0x40;  // inside IDAT
    Decoded decoded;
    CHECK_FALSE((libpng_decode(file, decoded) && decoded.samples == pixels));
}

TEST_CASE("PNG encoder: bad sizes and layouts are refused", "[png]") {
    CHECK_THROWS_AS(hsr::encode_png(2, 2, 3, std::vector<uint8_t>(11)), hsr::Error);
    CHECK_THROWS_AS(hsr::encode_png(2, 2, 2, std::vector<uint8_t>(8)), hsr::Error);
    CHECK_THROWS_AS(hsr::encode_png(0, 5, 3, std::vector<uint8_t>()), hsr::Error);
    CHECK_THROWS_AS(hsr::encode_picture_png(5, 0, 1, std::vector<uint8_t>()), hsr::Error);
}
