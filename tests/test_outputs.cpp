// hsr render's outputs beyond the 8-bit picture (docs/formats.md, "Outputs"): coverage alpha,
// depth, ids and normals as .npy, .pfm, .exr and 16-bit PNG, each read back here by readers of the
// test's own; and standard input and output ("Standard input and output").
#include "cli_support.hpp"
#include "surface_test_support.hpp"
#include "test_models.hpp"

#include "hsr/pixel_data.hpp"
#include "hsr/renderer.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <catch2/catch.hpp>
#include <png.h>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using cli::require_one_line_error;
using cli::run_hsr;
using cli::scratch_dir;
using cli::slurp;
using cli::write_file;

std::string model(const char* name) { return std::string(HSR_MODELS_DIR) + "/" + name; }
std::string scratch(const std::string& name) { return (scratch_dir() / name).string(); }

// `hsr <args> < input`, its stdout and stderr kept apart.
cli::Run run_hsr_with_input(const std::string& args, const std::string& input, const std::string& tag) {
    const fs::path out = scratch_dir() / (tag + ".out"), err = scratch_dir() / (tag + ".err");
    const std::string command = "timeout 60 " + std::string(HSR_BINARY_DIR) + "/hsr " + args + " > " + out.string() +
                                " 2> " + err.string() + " < " + input;
    const int raw = std::system(command.c_str());
    cli::Run r;
    r.status = WIFEXITED(raw) && WEXITSTATUS(raw) != 124 ? WEXITSTATUS(raw) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

void require_success(const cli::Run& r) {
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);
}

// An .npy file as the format says: magic, version 1.0, a header padded to 64 bytes, then the data.
template <typename T>
struct Npy {
    std::string descr;
    std::vector<std::size_t> shape;
    std::vector<T> values;
};

template <typename T>
Npy<T> read_npy(const std::string& path) {
    const std::string bytes = slurp(path);
    REQUIRE(bytes.size() >= 10);
    REQUIRE(bytes.compare(0, 6, "\x93NUMPY") == 0);
    REQUIRE(bytes[6] == 1);
    REQUIRE(bytes[7] == 0);
    const std::size_t header_length = uint8_t(bytes[8]) | std::size_t(uint8_t(bytes[9])) << 8;
    REQUIRE((10 + header_length) % 64 == 0);
    const std::string header = bytes.substr(10, header_length);
    REQUIRE(header.back() == '\n');
    Npy<T> npy;
    const std::size_t descr = header.find("'descr': '");
    REQUIRE(descr != std::string::npos);
    npy.descr = header.substr(descr + 10, 3);
    CHECK(header.find("'fortran_order': False") != std::string::npos);
    const std::size_t open = header.find("'shape': (");
    REQUIRE(open != std::string::npos);
    const std::size_t close = header.find(')', open);
    std::string dims = header.substr(open + 10, close - open - 10);
    for (std::size_t at = 0; at < dims.size();) {
        const std::size_t end = dims.find(',', at);
        const std::string dim = dims.substr(at, end - at);
        if (dim.find_first_not_of(' ') != std::string::npos) npy.shape.push_back(std::stoul(dim));
        if (end == std::string::npos) break;
        at = end + 1;
    }
    std::size_t count = 1;
    for (std::size_t d : npy.shape) count *= d;
    REQUIRE(bytes.size() == 10 + header_length + count * sizeof(T));
    npy.values.resize(count);
    std::memcpy(npy.values.data(), bytes.data() + 10 + header_length, count * sizeof(T));
    return npy;
}

// A PFM file, its rows put back top to bottom.
std::vector<float> read_pfm(const std::string& path, uint32_t& width, uint32_t& height, int& channels) {
    const std::string bytes = slurp(path);
    std::size_t at = 0;
    const auto line = [&] {
        const std::size_t end = bytes.find('\n', at);
        std::string text = bytes.substr(at, end - at);
        at = end + 1;
        return text;
    };
    const std::string kind = line();
    REQUIRE((kind == "Pf" || kind == "PF"));
    channels = kind == "PF" ? 3 : 1;
    REQUIRE(std::sscanf(line().c_str(), "%u %u", &width, &height) == 2);
    CHECK(std::stod(line()) < 0);  // little-endian
    const std::size_t row = std::size_t(width) * channels;
    REQUIRE(bytes.size() - at == row * height * sizeof(float));
    std::vector<float> values(row * height);
    for (uint32_t y = 0; y < height; ++y)  // the file's first row is the picture's bottom row
        std::memcpy(&values[(height - 1 - y) * row], bytes.data() + at + y * row * sizeof(float), row * sizeof(float));
    return values;
}

// An OpenEXR file's float channels, interleaved in the order asked for.
std::vector<float> read_exr(const std::string& path, const std::vector<std::string>& names, uint32_t& width,
                            uint32_t& height) {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    width = uint32_t(window.max.x - window.min.x + 1);
    height = uint32_t(window.max.y - window.min.y + 1);
    for (const std::string& name : names) {
        const Imf::Channel* channel = file.header().channels().findChannel(name);
        REQUIRE(channel != nullptr);
        CHECK(channel->type == Imf::FLOAT);
    }
    std::vector<float> values(std::size_t(width) * height * names.size());
    Imf::FrameBuffer frame_buffer;
    for (std::size_t c = 0; c < names.size(); ++c)
        frame_buffer.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data() + c),
                                                 sizeof(float) * names.size(), sizeof(float) * names.size() * width));
    file.setFrameBuffer(frame_buffer);
    file.readPixels(window.min.y, window.max.y);
    return values;
}

// A PNG's samples as stored (8 or 16 bits, no transformation), 16-bit ones as numbers.
struct RawPng {
    uint32_t width = 0, height = 0;
    int channels = 0, bit_depth = 0;
    std::vector<uint32_t> samples;
};

RawPng read_png_raw(const std::string& path) {
    FILE* file = std::fopen(path.c_str(), "rb");
    REQUIRE(file != nullptr);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    RawPng raw;
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        std::fclose(file);
        FAIL("cannot read " << path);
        return raw;
    }
    png_init_io(png, file);
    png_read_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
    raw.width = png_get_image_width(png, info);
    raw.height = png_get_image_height(png, info);
    raw.channels = png_get_channels(png, info);
    raw.bit_depth = png_get_bit_depth(png, info);
    png_bytepp rows = png_get_rows(png, info);
    const std::size_t per_row = std::size_t(raw.width) * raw.channels;
    for (uint32_t y = 0; y < raw.height; ++y)
        for (std::size_t i = 0; i < per_row; ++i)
            raw.samples.push_back(raw.bit_depth == 16 ? uint32_t(rows[y][2 * i]) << 8 | rows[y][2 * i + 1]
                                                      : rows[y][i]);
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(file);
    return raw;
}

// Equal as bits: +inf equals +inf, and no tolerance.
void require_same_floats(const std::vector<float>& a, const std::vector<float>& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        INFO("value " << i);
        REQUIRE(std::memcmp(&a[i], &b[i], sizeof(float)) == 0);
    }
}

// A square from (-1, -1, z) to (1, 1, z) facing +z, two triangles.
std::string square_at(float z) {
    const std::string name = "square-" + std::to_string(int(z * 100)) + ".obj";
    const std::string zs = std::to_string(z);
    return write_file(name, "v -1 -1 " + zs + "\nv 1 -1 " + zs + "\nv 1 1 " + zs + "\nv -1 1 " + zs +
                                "\nf 1 2 3\nf 1 3 4\n")
        .string();
}

// The pixel-camera scene of the coverage tests: an 8x8 picture, a red rectangle over x in [0, 4.3]
// and the full height, so that pixel column 4 is covered from 4.0 to 4.3 of its [4, 5].
std::string edge_scene() {
    return write_file("edge.scene",
                      "camera pixel\nsize 8 8\npolygon\ncolor 1 0 0\nvertex 0 0 5\nvertex 4.3 0 5\nvertex 4.3 8 5\n"
                      "vertex 0 8 5\n")
        .string();
}

uint32_t alpha_at(const RawPng& png, uint32_t x, uint32_t y) { return png.samples[(std::size_t(y) * png.width + x) * 4 + 3]; }

}  // namespace

TEST_CASE("outputs: --background none gives alpha 255 where a face is drawn and 0 elsewhere", "[outputs]") {
    require_success(run_hsr("render " + edge_scene() + " -l facecolor --background none -o " + scratch("alpha1.png"),
                            "alpha1"));
    const RawPng png = read_png_raw(scratch("alpha1.png"));
    REQUIRE(png.channels == 4);
    REQUIRE(png.bit_depth == 8);
    for (uint32_t y = 0; y < 8; ++y)
        for (uint32_t x = 0; x < 8; ++x) {
            INFO("pixel " << x << ", " << y);
            CHECK(alpha_at(png, x, y) == (x < 4 ? 255u : 0u));  // the centre of column 4 is at 4.5 > 4.3
            const std::size_t i = (std::size_t(y) * 8 + x) * 4;
            if (x < 4) CHECK((png.samples[i] == 255 && png.samples[i + 1] == 0 && png.samples[i + 2] == 0));
        }
}

TEST_CASE("outputs: --background none with --samples 4 gives the fraction of samples covered", "[outputs]") {
    // The rotated grid's x offsets are -3/8, -1/8, 1/8 and 3/8 of a pixel: in column 4 (centre 4.5)
    // only the sample at 4.125 lies left of the edge at 4.3, so 1 of 4: alpha 255 / 4, rounded.
    require_success(run_hsr("render " + edge_scene() + " -l facecolor --background none --samples 4 -o " +
                                scratch("alpha4.png"),
                            "alpha4"));
    const RawPng png = read_png_raw(scratch("alpha4.png"));
    REQUIRE(png.channels == 4);
    for (uint32_t y = 0; y < 8; ++y) {
        INFO("row " << y);
        CHECK(alpha_at(png, 3, y) == 255);
        CHECK(alpha_at(png, 4, y) == 64);
        CHECK(alpha_at(png, 5, y) == 0);
        // Straight alpha: the colour of what covers the pixel, not darkened by the part that is empty.
        const std::size_t i = (std::size_t(y) * 8 + 4) * 4;
        CHECK((png.samples[i] == 255 && png.samples[i + 1] == 0 && png.samples[i + 2] == 0));
    }
}

TEST_CASE("outputs: --background none with the a-buffer gives its fractional coverage", "[outputs]") {
    require_success(run_hsr("render " + edge_scene() + " -a a-buffer -l facecolor --background none -o " +
                                scratch("alpha-abuffer.png"),
                            "alpha-abuffer"));
    const RawPng png = read_png_raw(scratch("alpha-abuffer.png"));
    REQUIRE(png.channels == 4);
    for (uint32_t y = 0; y < 8; ++y) {
        INFO("row " << y);
        CHECK(alpha_at(png, 3, y) == 255);
        CHECK(alpha_at(png, 5, y) == 0);
        // 0.3 of the pixel, to within the a-buffer's sampling of it.
        CHECK(std::abs(int(alpha_at(png, 4, y)) - 77) <= 255 / 8);
        const std::size_t i = (std::size_t(y) * 8 + 4) * 4;
        CHECK((png.samples[i] == 255 && png.samples[i + 1] == 0 && png.samples[i + 2] == 0));
    }
}

TEST_CASE("outputs: .npy depth is the camera-space distance along the view axis", "[outputs]") {
    // The eye at z = 10 looking down -z at a square at z = 0.5: every covered pixel is 9.5 away along
    // the axis, in perspective as in orthographic projection.
    const std::string square = square_at(0.5f);
    for (const char* projection : {"", "--ortho"}) {
        INFO("projection " << projection);
        const std::string npy = scratch(std::string("depth") + projection + ".npy");
        require_success(run_hsr("render " + square + " --eye 0,0,10 --target 0,0,0 " + projection +
                                    " --width 40 --height 30 -o " + scratch("depth.png") + " --depth-out " + npy,
                                "depth-npy"));
        const Npy<float> depth = read_npy<float>(npy);
        CHECK(depth.descr == "<f4");
        REQUIRE(depth.shape == std::vector<std::size_t>{30, 40});
        std::size_t covered = 0, background = 0;
        for (float d : depth.values) {
            if (std::isinf(d)) {
                CHECK(d > 0);
                ++background;
            } else {
                CHECK(d == Approx(9.5).epsilon(1e-4));
                ++covered;
            }
        }
        CHECK(covered >= 50);
        CHECK(background >= 50);
        CHECK(std::isfinite(depth.values[15 * 40 + 20]));  // the middle
        CHECK(std::isinf(depth.values[0]));                 // a corner, beyond the square
    }
}

TEST_CASE("outputs: .pfm and .exr hold the same depth and normals as .npy", "[outputs]") {
    const std::string base = "render " + model("cube.obj") + " --yaw 30 --pitch 20 --width 48 --height 36 -o " +
                             scratch("same.png");
    for (const char* ext : {"npy", "pfm", "exr"})
        require_success(run_hsr(base + " --depth-out " + scratch(std::string("same-depth.") + ext) + " --normal-out " +
                                    scratch(std::string("same-normal.") + ext),
                                std::string("same-") + ext));
    const Npy<float> depth = read_npy<float>(scratch("same-depth.npy"));
    const Npy<float> normal = read_npy<float>(scratch("same-normal.npy"));
    REQUIRE(normal.shape == std::vector<std::size_t>{36, 48, 3});
    uint32_t width = 0, height = 0;
    int channels = 0;
    require_same_floats(read_pfm(scratch("same-depth.pfm"), width, height, channels), depth.values);
    CHECK((width == 48 && height == 36 && channels == 1));
    require_same_floats(read_pfm(scratch("same-normal.pfm"), width, height, channels), normal.values);
    CHECK(channels == 3);
    require_same_floats(read_exr(scratch("same-depth.exr"), {"Z"}, width, height), depth.values);
    CHECK((width == 48 && height == 36));
    require_same_floats(read_exr(scratch("same-normal.exr"), {"R", "G", "B"}, width, height), normal.values);
}

TEST_CASE("outputs: normals of the cube's faces in camera space", "[outputs]") {
    // From (10, 10, 10) toward the origin with +y up, camera right is (1, 0, -1)/sqrt 2, camera up
    // (-1, 2, -1)/sqrt 6 and toward the eye (1, 1, 1)/sqrt 3: the three faces turned to the eye.
    require_success(run_hsr("render " + model("cube.obj") + " --eye 10,10,10 --target 0,0,0 --width 64 --height 64 -o " +
                                scratch("normals.png") + " --normal-out " + scratch("normals.npy") + " --id-out " +
                                scratch("normals-ids.npy"),
                            "normals"));
    const Npy<float> normal = read_npy<float>(scratch("normals.npy"));
    const Npy<int32_t> ids = read_npy<int32_t>(scratch("normals-ids.npy"));
    const double s2 = std::sqrt(2.0), s3 = std::sqrt(3.0), s6 = std::sqrt(6.0);
    const std::vector<std::array<double, 3>> expected{
        {1 / s2, -1 / s6, 1 / s3}, {0, 2 / s6, 1 / s3}, {-1 / s2, -1 / s6, 1 / s3}};  // +x, +y, +z
    std::set<std::size_t> seen;
    for (std::size_t p = 0; p < 64 * 64; ++p) {
        const float* n = &normal.values[3 * p];
        if (ids.values[3 * p] < 0) {
            CHECK((n[0] == 0 && n[1] == 0 && n[2] == 0));
            continue;
        }
        bool matched = false;
        for (std::size_t k = 0; k < expected.size(); ++k)
            if (std::abs(n[0] - expected[k][0]) < 1e-5 && std::abs(n[1] - expected[k][1]) < 1e-5 &&
                std::abs(n[2] - expected[k][2]) < 1e-5) {
                matched = true;
                seen.insert(k);
            }
        INFO("pixel " << p << ": " << n[0] << ", " << n[1] << ", " << n[2]);
        CHECK(matched);
    }
    CHECK(seen.size() == 3);
}

TEST_CASE("outputs: ids name the object, the face within it and the instance", "[outputs]") {
    // Two squares side by side in a pixel camera, each its own object of two triangles.
    const std::string scene = write_file("ids.scene",
                                         "camera pixel\nsize 16 8\n"
                                         "polygon\nvertex 1 1 5\nvertex 7 1 5\nvertex 7 7 5\nvertex 1 7 5\n"
                                         "polygon\nvertex 9 1 5\nvertex 15 1 5\nvertex 15 7 5\nvertex 9 7 5\n")
                                  .string();
    require_success(run_hsr("render " + scene + " -o " + scratch("ids.png") + " --id-out " + scratch("ids.npy"),
                            "ids-npy"));
    require_success(run_hsr("render " + scene + " -o " + scratch("ids.png") + " --id-out " + scratch("ids-16.png"),
                            "ids-png"));
    const Npy<int32_t> ids = read_npy<int32_t>(scratch("ids.npy"));
    CHECK(ids.descr == "<i4");
    REQUIRE(ids.shape == std::vector<std::size_t>{8, 16, 3});
    std::set<int32_t> faces[2];
    for (uint32_t y = 0; y < 8; ++y)
        for (uint32_t x = 0; x < 16; ++x) {
            const int32_t* id = &ids.values[3 * (std::size_t(y) * 16 + x)];
            INFO("pixel " << x << ", " << y);
            // Pixel centres inside [1, 7] or [9, 15] in x and [1, 7] in y are covered.
            const bool inside_y = y >= 1 && y <= 6;
            const int expected_object = !inside_y ? -1 : x >= 1 && x <= 6 ? 0 : x >= 9 && x <= 14 ? 1 : -1;
            CHECK(id[0] == expected_object);
            if (expected_object < 0) {
                CHECK((id[1] == -1 && id[2] == -1));
            } else {
                CHECK((id[1] == 0 || id[1] == 1));  // each object's own count, not the scene's
                CHECK(id[2] == 0);
                faces[expected_object].insert(id[1]);
            }
        }
    CHECK(faces[0].size() == 2);
    CHECK(faces[1].size() == 2);
    // The 16-bit PNG holds the same: R, G the face (high, low), B the object, A the instance.
    const RawPng png = read_png_raw(scratch("ids-16.png"));
    REQUIRE((png.channels == 4 && png.bit_depth == 16 && png.width == 16 && png.height == 8));
    for (std::size_t p = 0; p < 16 * 8; ++p) {
        const uint32_t* s = &png.samples[4 * p];
        CHECK(int32_t(s[0] << 16 | s[1]) == ids.values[3 * p + 1]);
        CHECK(int32_t(s[2] == 0xffff ? -1 : int32_t(s[2])) == ids.values[3 * p]);
        CHECK(int32_t(s[3] == 0xffff ? -1 : int32_t(s[3])) == ids.values[3 * p + 2]);
    }
}

TEST_CASE("outputs: ids of instances", "[outputs]") {
    require_success(run_hsr("render " + model("cube.obj") + " --repeat 2x1x1 --width 64 --height 32 -o " +
                                scratch("instances.png") + " --id-out " + scratch("instances.npy"),
                            "instances"));
    const Npy<int32_t> ids = read_npy<int32_t>(scratch("instances.npy"));
    std::set<int32_t> instances;
    for (std::size_t p = 0; p < 64 * 32; ++p)
        if (ids.values[3 * p] >= 0) {
            CHECK(ids.values[3 * p] == 0);
            CHECK((ids.values[3 * p + 1] >= 0 && ids.values[3 * p + 1] < 12));
            instances.insert(ids.values[3 * p + 2]);
        }
    CHECK(instances == std::set<int32_t>{0, 1});
}

TEST_CASE("outputs: a model from standard input renders as its file does", "[outputs]") {
    for (const char* name : {"cube.obj", "tetrahedron.off", "octahedron.ply", "pyramid.stl"}) {
        INFO(name);
        const std::string extension = fs::path(name).extension().string().substr(1);
        const std::string options = " --yaw 20 --pitch 10 --width 64 --height 48 --depth-out ";
        require_success(run_hsr("render " + model(name) + options + scratch("from-file.npy") + " -o " +
                                    scratch("from-file.png"),
                                "from-file"));
        require_success(run_hsr_with_input("render - --format " + extension + options + scratch("from-stdin.npy") +
                                               " -o " + scratch("from-stdin.png"),
                                           model(name), "from-stdin"));
        CHECK(slurp(scratch("from-stdin.png")) == slurp(scratch("from-file.png")));
        CHECK(slurp(scratch("from-stdin.npy")) == slurp(scratch("from-file.npy")));
    }
}

TEST_CASE("outputs: -o - writes the picture's bytes to standard output and nothing else", "[outputs]") {
    const std::string base = "render " + model("cube.obj") + " --yaw 30 --width 64 --height 48";
    require_success(run_hsr(base + " -o " + scratch("to-file.png"), "to-file"));
    const cli::Run r = run_hsr(base + " --stats -o -", "to-stdout");
    require_success(r);
    CHECK(r.out == slurp(scratch("to-file.png")));
    CHECK_THAT(r.err, Catch::Contains("standard output"));
    // RGBA too, and the other outputs still go to their files.
    require_success(run_hsr(base + " --background none -o " + scratch("to-file-rgba.png"), "to-file-rgba"));
    const cli::Run rgba = run_hsr(base + " --background none --depth-out " + scratch("beside.npy") + " -o -", "rgba");
    require_success(rgba);
    CHECK(rgba.out == slurp(scratch("to-file-rgba.png")));
    CHECK(fs::exists(scratch("beside.npy")));
}

TEST_CASE("outputs: mistakes are one line and leave existing outputs alone", "[outputs]") {
    const std::string kept = scratch("kept.png");
    write_file("kept.png", "an earlier picture");
    const std::string keep_depth = scratch("kept.npy");
    write_file("kept.npy", "an earlier depth");
    const std::string outputs = " -o " + kept + " --depth-out " + keep_depth;

    require_one_line_error(run_hsr_with_input("render -" + outputs, model("cube.obj"), "no-format"), "--format");
    require_one_line_error(
        run_hsr_with_input("render - --format obj --limit model-bytes=100" + outputs, model("cube.obj"), "too-large"),
        "standard input: more than 100 bytes");
    require_one_line_error(run_hsr_with_input("render - --format fbx" + outputs, model("cube.obj"), "bad-format"),
                           "obj, off, ply, stl, gltf or glb");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --format obj" + outputs, "format-for-file"),
                           "--format goes with MODEL '-'");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -o " + kept + " --depth-out " + scratch("d.txt"),
                                   "depth-extension"),
                           ".png, .npy, .pfm or .exr");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -o " + kept + " --id-out " + scratch("i.exr"),
                                   "id-extension"),
                           ".npy or .png");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -o " + kept + " --normal-out " + scratch("n.tif"),
                                   "normal-extension"),
                           ".npy, .pfm, .exr or .png");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --views 3 -o -", "stdout-frames"),
                           "standard output takes one picture");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -o - --depth-out -", "stdout-twice"),
                           "--depth-out -");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --samples 4 --id-out " + scratch("i.npy") +
                                       " -o " + kept,
                                   "ids-samples"),
                           "--id-out");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -a appel --background none -o " + kept,
                                   "lines-none"),
                           "--background none");
    const fs::path stdout_jobs = write_file("stdout-line.jobs", model("cube.obj") + " -o -\n");
    require_one_line_error(run_hsr("render --jobs " + stdout_jobs.string(), "jobs-stdout"), "standard output");
    CHECK(slurp(kept) == "an earlier picture");
    CHECK(slurp(keep_depth) == "an earlier depth");
}

TEST_CASE("outputs: ids agree with the face buffer of the frame", "[outputs]") {
    // boxes.scene has several objects; each object's triangles follow the one before's.
    hsr::SceneSource source;
    source.model = test_models::path("boxes.scene");
    hsr::Renderer renderer(hsr::LoadedScene::load(source));
    hsr::HiddenSurfaceRemover remover(surface_tests::plugin("zbuffer"), {});
    hsr::LightingModel lighting(surface_tests::plugin("facecolor"), {});
    hsr::PictureRequest request;
    request.view.width = 96;
    request.view.height = 64;
    request.view.yaw_degrees = 25.0f;
    request.view.pitch_degrees = 15.0f;
    const hsr::Picture picture = renderer.picture(request, remover, lighting);
    const hsr_scene& scene = picture.scene;
    REQUIRE(scene.object_count > 1);
    std::vector<uint32_t> triangles_before(scene.object_count + 1, 0);  // triangles of the objects before each
    for (uint32_t t = 0; t < scene.triangle_count; ++t) ++triangles_before[scene.face_object[t] + 1];
    for (uint32_t k = 1; k <= scene.object_count; ++k) triangles_before[k] += triangles_before[k - 1];

    const std::vector<int32_t> ids = hsr::pixel_ids(picture.frame, scene);
    std::set<int32_t> objects;
    for (std::size_t p = 0; p < picture.frame.face.size(); ++p) {
        const uint32_t face = picture.frame.face[p];
        INFO("pixel " << p);
        if (face == HSR_NO_FACE) {
            CHECK((ids[3 * p] == -1 && ids[3 * p + 1] == -1 && ids[3 * p + 2] == -1));
            continue;
        }
        const uint32_t object = scene.face_object[face];
        CHECK(ids[3 * p] == int32_t(object));
        CHECK(uint32_t(ids[3 * p + 1]) + triangles_before[object] == face);
        CHECK(ids[3 * p + 2] == 0);
        objects.insert(ids[3 * p]);
    }
    CHECK(objects.size() > 1);
}
