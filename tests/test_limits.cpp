// The limits on work (limits.hpp) and the quoting of user text in errors (printable in error.hpp):
// each request too large for a limit is refused with one line naming the limit, before the memory
// is allocated, and goes through once the limit is raised with --limit; user text in a message is
// escaped and cut. The answers are written out by hand: exact messages, counts worked out from the
// inputs, and files (PNG headers, scene files) built here byte by byte.
#include "cli_support.hpp"
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/image.hpp"
#include "hsr/instancing.hpp"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"
#include "hsr/subdivide.hpp"
#include "hsr/surface.hpp"
#include "test_models.hpp"

#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace fs = std::filesystem;

namespace {

using cli::Run;
using cli::require_one_line_error;
using cli::run_hsr;
using cli::scratch_dir;
using cli::slurp;
using cli::write_file;

template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const hsr::Error& e) {
        // An error over a limit is the asker's to fix, whatever added its context on the way.
        if (std::string_view(e.what()).find("over the limit") != std::string_view::npos) {
            INFO(e.what());
            CHECK(dynamic_cast<const hsr::LimitError*>(&e) != nullptr);
        }
        return e.what();
    }
    FAIL("no hsr::Error was thrown");
    return {};
}

// The limits in force while it lives; the defaults again afterwards.
struct ScopedLimits {
    explicit ScopedLimits(const hsr::Limits& limits) { hsr::set_limits(limits); }
    ~ScopedLimits() { hsr::set_limits(hsr::Limits{}); }
};

// ---------------------------------------------------------------------------------------------
// PNG files made here: a real one through write_png, and a bare header that claims any size.

uint32_t crc32(const std::string& bytes) {
    uint32_t crc = 0xFFFFFFFFu;
    for (unsigned char byte : bytes) {
        crc ^= byte;
        for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

std::string big_endian(uint32_t v) {
    return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}

std::string png_chunk(const std::string& type, const std::string& data) {
    return big_endian(uint32_t(data.size())) + type + data + big_endian(crc32(type + data));
}

// A PNG signature and an IHDR for an 8-bit greyscale image of width x height, then one IDAT
// holding a zlib stream of 2 zero bytes (stored), then IEND: a few hundred bytes that claim any size.
fs::path png_header_claiming(uint32_t width, uint32_t height, const std::string& name) {
    const std::string ihdr = big_endian(width) + big_endian(height) + std::string{8, 0, 0, 0, 0};
    const std::string idat = std::string{0x78, 0x01, 0x01, 0x02, 0x00, char(0xFD), char(0xFF), 0x00, 0x00} +
                             big_endian(0x00020001u);  // adler32 of two zero bytes
    return write_file(name, std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr) + png_chunk("IDAT", idat) +
                                png_chunk("IEND", ""));
}

fs::path grey_png(uint32_t width, uint32_t height, const std::string& name) {
    std::vector<uint8_t> pixels(size_t(width) * height);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = uint8_t(i * 7);
    const fs::path path = scratch_dir() / name;
    hsr::write_png(path, width, height, 1, pixels);
    return path;
}

// A unit square in the z = 0 plane as one polygon of 4 vertices: 2 triangles.
std::string square_polygon(float x) {
    return "polygon\n  vertex " + std::to_string(x) + " 0 0\n  vertex " + std::to_string(x + 1) + " 0 0\n  vertex " +
           std::to_string(x + 1) + " 1 0\n  vertex " + std::to_string(x) + " 1 0\n";
}

// ---------------------------------------------------------------------------------------------
// The hsr executable

void require_success(const Run& r) {
    INFO("stderr: " << r.err);
    CHECK(r.status == 0);
    CHECK(r.err.find("error") == std::string::npos);
}

std::string model(const char* name) { return (test_models::dir / name).string(); }

std::string out_png(const std::string& tag) { return " -o " + (scratch_dir() / (tag + ".png")).string(); }

}  // namespace

// ---------------------------------------------------------------------------------------------
// printable

TEST_CASE("printable: control bytes and bytes that are not UTF-8 are escaped, UTF-8 kept", "[limits][printable]") {
    CHECK(hsr::printable("plain text, 1/2") == "plain text, 1/2");
    CHECK(hsr::printable("a\nb\tc\rd") == "a\\x0ab\\x09c\\x0dd");
    CHECK(hsr::printable("\x1b[2Jcleared") == "\\x1b[2Jcleared");
    CHECK(hsr::printable(std::string("nul\0here", 8)) == "nul\\x00here");
    CHECK(hsr::printable("del\x7f") == "del\\x7f");
    // UTF-8: e acute (2 bytes), the euro sign (3), a musical G clef (4) stay as they are.
    CHECK(hsr::printable("caf\xc3\xa9 \xe2\x82\xac \xf0\x9d\x84\x9e") == "caf\xc3\xa9 \xe2\x82\xac \xf0\x9d\x84\x9e");
    // C1 control U+0085 (next line) and U+2028 (line separator) are line breaks too.
    CHECK(hsr::printable("a\xc2\x85z") == "a\\x85z");
    CHECK(hsr::printable("a\xe2\x80\xa8z") == "a\\u2028z");
    // Not UTF-8: a lone continuation byte, an overlong encoding of '/', a surrogate, a cut sequence.
    CHECK(hsr::printable("x\x80y") == "x\\x80y");
    CHECK(hsr::printable("\xc0\xaf") == "\\xc0\\xaf");
    CHECK(hsr::printable("\xed\xa0\x80") == "\\xed\\xa0\\x80");
    CHECK(hsr::printable("end\xe2\x82") == "end\\xe2\\x82");
    // Escaping twice changes nothing more.
    const std::string once = hsr::printable("a\x01\xff b");
    CHECK(hsr::printable(once) == once);
}

TEST_CASE("printable: text longer than the cap is cut with ...", "[limits][printable]") {
    CHECK(hsr::printable(std::string(80, 'a')) == std::string(80, 'a'));
    CHECK(hsr::printable(std::string(81, 'a')) == std::string(80, 'a') + "...");
    CHECK(hsr::printable(std::string(120000, 'q')).size() == 83);
    CHECK(hsr::printable("abcdef", 3) == "abc...");
    // Characters are counted, not bytes: an escape or a multi-byte character is one.
    CHECK(hsr::printable("\x01\x02\x03\x04", 2) == "\\x01\\x02...");
    CHECK(hsr::printable("\xc3\xa9\xc3\xa9\xc3\xa9", 2) == "\xc3\xa9\xc3\xa9...");
}

TEST_CASE("printable: user text in errors is escaped and cut", "[limits][printable]") {
    // A .scene file's word, an option's value, a formula, a plugin parameter.
    const fs::path scene = write_file("control.scene", "frobnicate\x1b[31mred\x07\n");
    const std::string scene_error = error_of([&] { hsr::load_scene_file(scene); });
    CHECK_THAT(scene_error, Catch::Contains("unknown statement 'frobnicate\\x1b[31mred\\x07'"));
    const fs::path long_word = write_file("long-word.scene", "mesh x.obj\n  " + std::string(120000, 'w') + "\n");
    const std::string long_error = error_of([&] { hsr::load_scene_file(long_word); });
    CHECK_THAT(long_error, Catch::Contains("unknown statement '" + std::string(80, 'w') + "...'"));
    CHECK(long_error.size() < 400);

    const std::string formula_error =
        error_of([] { hsr::make_formula_surface("x+" + std::string(120000, 'q'), {-1, 1, -1, 1, 4, 4}); });
    CHECK(formula_error.size() < 600);
    CHECK_THAT(formula_error, Catch::StartsWith("formula \"x+" + std::string(78, 'q') + "...\""));
    CHECK(error_of([] { hsr::parse_surface_range("1:2,3:\x01"); }) == "surface range \"1:2,3:\\x01\": \"\\x01\" is not a number");

    CHECK(error_of([] { hsr::parse_light_spec("dir:1,2,\x1b" "3"); }).find('\x1b') == std::string::npos);
    const hsr_param_desc number{sizeof(hsr_param_desc), "n", HSR_PARAM_FLOAT, "1", 0, 10, nullptr, ""};
    CHECK(error_of([&] { hsr::parse_param_value(number, "1\r\n2"); }) == "'1\\x0d\\x0a2' is not a number");
    CHECK(error_of([] { hsr::parse_plugin_spec("zbuffer:\x01"); }) == "'\\x01' in 'zbuffer:\\x01' is not key=value");
}

// ---------------------------------------------------------------------------------------------
// The limits and --limit NAME=N

TEST_CASE("limits: NAME=N settings, and the message of a limit reached", "[limits]") {
    hsr::Limits limits;
    hsr::apply_limit_setting(limits, "triangles=123");
    hsr::apply_limit_setting(limits, "image-pixels=18446744073709551615");
    CHECK(limits.triangles == 123);
    CHECK(limits.image_pixels == UINT64_MAX);
    CHECK(limits.lights == hsr::Limits{}.lights);
    CHECK_THAT(error_of([&] { hsr::apply_limit_setting(limits, "polygons=5"); }),
               Catch::StartsWith("--limit: unknown limit 'polygons' (limits: triangles, stored-triangles, model-bytes, instances, "
                                 "lights, surface-samples, heightmap-pixels, image-pixels, upload-bytes, fragments, frames)"));
    CHECK_THAT(error_of([&] { hsr::apply_limit_setting(limits, "lights"); }), Catch::Contains("expected NAME=N"));
    for (const char* bad : {"lights=0", "lights=-1", "lights=1e3", "lights=", "lights=18446744073709551616"})
        CHECK(error_of([&] { hsr::apply_limit_setting(limits, bad); }).ends_with("is not a whole number of at least 1"));

    ScopedLimits scoped(limits);
    CHECK_NOTHROW(hsr::check_limit(&hsr::Limits::triangles, 123, "x"));
    CHECK(error_of([] { hsr::check_limit(&hsr::Limits::triangles, 124, "the scene"); }) ==
          "the scene: 124 triangles to draw, over the limit of 123 (raise it with --limit triangles=N)");
    CHECK(error_of([] { hsr::check_limit(&hsr::Limits::lights, 1001, ""); }) ==
          "1001 lights, over the limit of 1000 (raise it with --limit lights=N)");
}

TEST_CASE("limits: the defaults take everything the docs and tests render", "[limits]") {
    const hsr::Limits defaults;
    // docs/algorithms/octree-zbuffer.md: the bunny (69,666 triangles) 4x3x20; bench's deep-63: about
    // 3 million triangles; hierarchical-zbuffer.md: 1920 monkeys.
    CHECK(defaults.triangles >= uint64_t(4 * 3 * 20) * 69666);
    CHECK(defaults.stored_triangles >= 3'000'000);
    CHECK(defaults.model_bytes >= 74'000'000);  // an OBJ of 2 million triangles, written with 6 decimals
    CHECK(defaults.instances >= 8 * 6 * 40);
    // The surface and height-map sizes of before: 4096 x 4096 pixels read, 2^20 samples used.
    CHECK(defaults.surface_samples == uint64_t(1) << 20);
    CHECK(defaults.heightmap_pixels >= uint64_t(4096) * 4096);
    CHECK(defaults.image_pixels >= uint64_t(4096) * 4096);
}

// ---------------------------------------------------------------------------------------------
// Each limit in the framework, checked before the work

TEST_CASE("limits: a height map's header is checked before its pixels are read", "[limits][surface]") {
    // 40000 x 40000 would be 1.6 GB of rows and 6.4 GB of samples. The file holds two bytes of
    // pixels: a message other than the limit's would mean the pixels were being read.
    const fs::path huge = png_header_claiming(40000, 40000, "huge-header.png");
    CHECK(fs::file_size(huge) < 100);
    CHECK_THAT(error_of([&] { hsr::make_heightmap_surface(huge); }),
               Catch::EndsWith("huge-header.png (40000x40000 pixels): 1600000000 pixels, over the limit of 16777216 "
                               "(raise it with --limit heightmap-pixels=N)"));
    // Within the pixel limit, but the grid it makes is over the sample limit: also before reading.
    const fs::path large = png_header_claiming(4096, 4096, "large-header.png");
    CHECK_THAT(error_of([&] { hsr::make_heightmap_surface(large); }),
               Catch::EndsWith("large-header.png (4096x4096 pixels; a step above 1 uses fewer): 4096x4096: 16777216 "
                               "grid samples, over the limit of 1048576 (raise it with --limit surface-samples=N)"));
    hsr::HeightmapOptions every_4th;
    every_4th.step = 4;
    CHECK_THAT(error_of([&] { hsr::make_heightmap_surface(large, every_4th); }),
               Catch::Contains("Not enough image data"));  // 1024 x 1024 samples pass: now it reads

    const fs::path real = grey_png(30, 20, "thirty-by-twenty.png");
    hsr::Limits limits;
    limits.heightmap_pixels = 599;
    {
        ScopedLimits scoped(limits);
        CHECK_THAT(error_of([&] { hsr::make_heightmap_surface(real); }),
                   Catch::Contains("600 pixels, over the limit of 599"));
    }
    limits.heightmap_pixels = 600;
    ScopedLimits scoped(limits);
    CHECK(hsr::make_heightmap_surface(real).vertex_count() == 600);
}

TEST_CASE("limits: surface samples", "[limits][surface]") {
    hsr::Limits limits;
    limits.surface_samples = 99;
    ScopedLimits scoped(limits);
    CHECK(error_of([] { hsr::parse_surface_range("0:1,0:1,10x10"); }) ==
          "surface range \"0:1,0:1,10x10\": 10x10: 100 grid samples, over the limit of 99 (raise it with --limit "
          "surface-samples=N)");
    CHECK(hsr::make_formula_surface("x*y", hsr::parse_surface_range("0:1,0:1,9x11")).vertex_count() == 99);
}

TEST_CASE("limits: an instance grid counts the triangles its copies draw", "[limits][instancing]") {
    const hsr::SceneData cube = hsr::load_model(test_models::path("cube.obj"));
    REQUIRE(cube.triangle_count() == 12);
    hsr::InstanceGrid grid;
    // 3162 x 3162 copies: 9,998,244 instances (1.5 GB of them) for 12 triangles each.
    grid.columns = grid.rows = 3162;
    CHECK(error_of([&] { hsr::make_instance_grid(cube, grid); }) ==
          "3162x3162x1 copies of 12 triangles: 9998244 instances, over the limit of 1000000 (raise it with --limit "
          "instances=N)");
    // 100 x 100 x 100 copies: at the instance limit, but 12 million triangles.
    hsr::Limits limits;
    limits.triangles = 11'999'999;
    {
        ScopedLimits scoped(limits);
        grid.columns = grid.rows = grid.layers = 100;
        CHECK(error_of([&] { hsr::make_instance_grid(cube, grid); }) ==
              "100x100x100 copies of 12 triangles: 12000000 triangles to draw, over the limit of 11999999 (raise it "
              "with --limit triangles=N)");
    }
    limits.triangles = 12 * 6;
    limits.instances = 6;
    ScopedLimits scoped(limits);
    grid.columns = 3, grid.rows = 2, grid.layers = 1;
    CHECK(hsr::make_instance_grid(cube, grid).instances.size() == 6);
    grid.layers = 2;
    CHECK_THAT(error_of([&] { hsr::make_instance_grid(cube, grid); }), Catch::Contains("12 instances, over the limit of 6"));
}

TEST_CASE("limits: instances copied out into plain triangles", "[limits][instancing]") {
    const hsr::SceneData cube = hsr::load_model(test_models::path("cube.obj"));
    hsr::InstanceGrid grid;
    grid.columns = 5, grid.rows = 4, grid.layers = 3;  // 60 copies, 720 triangles
    const hsr::SceneData deep = hsr::make_instance_grid(cube, grid);
    hsr::Limits limits;
    limits.stored_triangles = 719;
    {
        ScopedLimits scoped(limits);
        CHECK(error_of([&] { hsr::flatten_instances(deep); }) ==
              "60 instances copied out into plain triangles: 720 stored triangles, over the limit of 719 (raise it with "
              "--limit stored-triangles=N)");
    }
    limits.stored_triangles = 720;
    ScopedLimits scoped(limits);
    CHECK(hsr::flatten_instances(deep).triangle_count() == 720);
}

TEST_CASE("limits: a .scene file's triangles, counted as each object is added", "[limits][scene]") {
    // 30 squares of 2 triangles, then `repeat 2 2 2`: 8 copies of 2 triangles per square.
    std::string text;
    for (int k = 0; k < 30; ++k) text += square_polygon(float(2 * k));
    text += "repeat 2 2 2\n";
    const fs::path scene = write_file("squares.scene", text);
    CHECK(hsr::load_scene_file(scene).scene.instances.size() == 8);

    hsr::Limits limits;
    limits.triangles = 100;  // the 7th square makes 7 * 2 * 8 = 112 triangles to draw
    {
        ScopedLimits scoped(limits);
        CHECK(error_of([&] { hsr::load_scene_file(scene); }) ==
              scene.string() + ":31: the meshes and polygons up to here (14 triangles) repeated 2x2x2: 112 triangles "
                               "to draw, over the limit of 100 (raise it with --limit triangles=N)");
    }
    limits = {};
    limits.stored_triangles = 41;  // the 21st square makes 42
    {
        ScopedLimits scoped(limits);
        CHECK(error_of([&] { hsr::load_scene_file(scene); }) ==
              scene.string() + ":101: the meshes and polygons up to here: 42 stored triangles, over the limit of 41 "
                               "(raise it with --limit stored-triangles=N)");
    }
    // The repeat line's copies, before any mesh is read.
    const fs::path many = write_file("many-copies.scene", "mesh missing.obj\nrepeat 1000 1000 2\n");
    CHECK(error_of([&] { hsr::load_scene_file(many); }) ==
          many.string() + ":2: 2000000 instances, over the limit of 1000000 (raise it with --limit instances=N)");
}

TEST_CASE("limits: a model file's faces are counted before OpenMesh reads it", "[limits][models]") {
    // Each file holds 4 triangles' worth of faces, written in its format's own way: a quad counts 2.
    const fs::path obj = write_file("four.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                                                "f 1 2 3 4\nf 1 2 5\nf 2 3 5\n");
    const fs::path off = write_file("four.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n"
                                                "4 0 1 2 3\n3 0 1 4\n3 1 2 4\n");
    const fs::path ply = write_file("four.ply", "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                                                "property float y\nproperty float z\nelement face 3\n"
                                                "property list uchar int vertex_indices\nend_header\n"
                                                "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n4 0 1 2 3\n3 0 1 4\n3 1 2 4\n");
    std::string facets;
    for (const char* corners : {"0 0 0\nvertex 1 0 0\nvertex 1 1 0", "0 0 0\nvertex 1 1 0\nvertex 0 1 0",
                                "0 0 0\nvertex 1 0 0\nvertex 0 0 1", "1 0 0\nvertex 1 1 0\nvertex 0 0 1"})
        facets += std::string("facet normal 0 0 1\nouter loop\nvertex ") + corners + "\nendloop\nendfacet\n";
    const fs::path stl = write_file("four.stl", "solid four\n" + facets + "endsolid four\n");
    // A binary STL declaring 4 triangles of 50 bytes each, all zero: the count is read from its header.
    const fs::path binary_stl = write_file("four-binary.stl", std::string(80, ' ') + std::string("\x04\0\0\0", 4) +
                                                                 std::string(200, '\0'));

    hsr::Limits limits;
    limits.stored_triangles = 3;
    {
        ScopedLimits scoped(limits);
        for (const fs::path& file : {obj, off, ply, stl, binary_stl})
            CHECK(error_of([&] { hsr::load_model(file); }) ==
                  file.string() + ": 4 stored triangles, over the limit of 3 (raise it with --limit stored-triangles=N)");
    }
    limits.stored_triangles = 4;
    ScopedLimits scoped(limits);
    for (const fs::path& file : {obj, off, ply, stl}) CHECK(hsr::load_model(file).triangle_count() == 4);
}

TEST_CASE("limits: a model file's size is checked before it is read, and only regular files are read",
          "[limits][models]") {
    const fs::path obj = write_file("triangle.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");  // 32 bytes
    REQUIRE(fs::file_size(obj) == 32);
    hsr::Limits limits;
    limits.model_bytes = 31;
    {
        ScopedLimits scoped(limits);
        CHECK(error_of([&] { hsr::load_model(obj); }) ==
              obj.string() + ": 32 bytes, over the limit of 31 (raise it with --limit model-bytes=N)");
    }
    limits.model_bytes = 32;
    {
        ScopedLimits scoped(limits);
        CHECK(hsr::load_model(obj).triangle_count() == 1);
    }
    // A pipe or a device would be read for ever (or until memory runs out).
    const fs::path pipe = scratch_dir() / "pipe.obj";
    fs::remove(pipe);
    REQUIRE(mkfifo(pipe.c_str(), 0600) == 0);
    CHECK(error_of([&] { hsr::load_model(pipe); }) ==
          pipe.string() + ": is not a regular file (a pipe, device or socket), not a model file");
    const fs::path device = scratch_dir() / "zero.obj";
    fs::remove(device);
    fs::create_symlink("/dev/zero", device);
    CHECK(error_of([&] { hsr::load_model(device); }) ==
          device.string() + ": is not a regular file (a pipe, device or socket), not a model file");

    // A .scene file: the same two checks.
    const fs::path scene = write_file("one-light.scene", "light dir:0,0,1\n");  // 16 bytes
    limits.model_bytes = 15;
    {
        ScopedLimits scoped(limits);
        CHECK(error_of([&] { hsr::load_scene_file(scene); }) ==
              scene.string() + ": 16 bytes, over the limit of 15 (raise it with --limit model-bytes=N)");
    }
    const fs::path scene_device = scratch_dir() / "zero.scene";
    fs::remove(scene_device);
    fs::create_symlink("/dev/zero", scene_device);
    CHECK(error_of([&] { hsr::load_scene_file(scene_device); }) ==
          scene_device.string() + ": is not a regular file, not a scene file");
}

TEST_CASE("limits: Loop subdivision counts the triangles it would make first", "[limits][models]") {
    const fs::path cube = test_models::path("cube.obj");  // 12 triangles: 48, 192, 768 after 1, 2, 3 levels
    hsr::Limits limits;
    limits.stored_triangles = 767;
    {
        ScopedLimits scoped(limits);
        CHECK(error_of([&] { hsr::load_model_subdivided(cube, 3); }) ==
              "Loop subdivision: 3 levels of 12 triangles: 768 stored triangles, over the limit of 767 (raise it "
              "with --limit stored-triangles=N)");
    }
    limits.stored_triangles = 768;
    ScopedLimits scoped(limits);
    CHECK(hsr::load_model_subdivided(cube, 3).triangle_count() == 768);
}

TEST_CASE("limits: a PNG read back is checked against image-pixels from its header", "[limits]") {
    const fs::path huge = png_header_claiming(40000, 40000, "read-back-huge.png");
    CHECK_THAT(error_of([&] { hsr::read_png_rgb(huge); }),
               Catch::EndsWith("read-back-huge.png: 1600000000 pixels, over the limit of 67108864 (raise it with "
                               "--limit image-pixels=N)"));
}

TEST_CASE("limits: a mesh file named many times is read once and copied", "[limits][scene]") {
    const std::string cube = model("cube.obj");
    const fs::path scene = write_file("cubes.scene", "mesh " + cube + "\n  color 1 0 0\nmesh " + cube +
                                                         "\n  name second\n  translate 3 0 0\n  color 0 0 1\n");
    const hsr::SceneData s = hsr::load_scene_file(scene).scene;
    REQUIRE(s.triangle_count() == 24);
    CHECK(s.object_names == std::vector<std::string>{"cube", "second"});
    CHECK(s.face_colors[0] == 1.0f);
    CHECK(s.face_colors[3 * 12 + 2] == 1.0f);
    CHECK(s.bounds_max.x == 4.0f);  // the second cube, from -1..1 moved by 3
}

TEST_CASE("limits: lights", "[limits][scene]") {
    std::string text = "mesh " + model("cube.obj") + "\n";
    for (int k = 0; k < 1001; ++k) text += "light dir:1,1," + std::to_string(k + 1) + "\n";
    const fs::path scene = write_file("lights.scene", text);
    CHECK(error_of([&] { hsr::load_scene_file(scene); }) ==
          scene.string() + ":1002: 1001 lights, over the limit of 1000 (raise it with --limit lights=N)");
    hsr::Limits limits;
    limits.lights = 1001;
    ScopedLimits scoped(limits);
    CHECK(hsr::load_scene_file(scene).lights.size() == 1001);
}

TEST_CASE("lights: a direction near the largest float is a direction, a point light there is refused",
          "[limits][lights]") {
    // Its length overflows a float, but not the direction: (1, 1, 1) / sqrt 3.
    const hsr::LightSpec light = hsr::parse_light_spec("dir:3e38,3e38,3e38");
    for (int k = 0; k < 3; ++k) CHECK(light.vector[k] == Approx(1.0 / std::sqrt(3.0)).epsilon(1e-6));
    // And one so short that its length underflows.
    CHECK(hsr::parse_light_spec("dir:0,-1e-30,0").vector.y == -1.0f);
    CHECK_THAT(error_of([] { hsr::parse_light_spec("dir:0,0,0"); }), Catch::Contains("a direction cannot be zero"));

    hsr::CameraSettings view;
    view.width = view.height = 8;
    view.yaw_degrees = 45;  // the camera's x mixes world x and z: 3e38 cos 45 + 3e38 sin 45 > 3.4e38
    const hsr_camera camera = hsr::make_orbit_camera(glm::vec3(-1), glm::vec3(1), view);
    CHECK_THAT(error_of([&] { hsr::resolve_light(hsr::parse_light_spec("point:3e38,0,3e38"), camera); }),
               Catch::Contains("too far away for single precision"));
    const hsr_light turned = hsr::resolve_light(light, camera);
    CHECK(std::isfinite(turned.vector[0]));
}

// ---------------------------------------------------------------------------------------------
// Through the hsr executable: one line, quickly, and --limit raises each limit

TEST_CASE("cli: --repeat on the bunny is refused by the triangles it draws", "[limits][cli]") {
    test_models::require_fetched();
    const Run r = run_hsr("render " + model("bunny.obj") + " --repeat 100x100x100" + out_png("bunny-deep"), "bunny-deep");
    require_one_line_error(r, "--repeat 100x100x100: 100x100x100 copies of 69666 triangles: 69666000000 triangles to "
                              "draw, over the limit of 200000000 (raise it with --limit triangles=N)");
    require_one_line_error(run_hsr("render " + model("bunny.obj") + " --repeat 2x2x2 -a appel --limit stored-triangles=557327 -o " +
                                       (scratch_dir() / "bunny.svg").string(), "bunny-appel"),
                           "8 instances copied out into plain triangles: 557328 stored triangles");
}

TEST_CASE("cli: --limit raises and lowers each limit", "[limits][cli]") {
    const std::string cube = model("cube.obj");
    const std::string small = " --width 32 --height 24";
    // triangles and instances: 2x2x2 cubes draw 96 triangles.
    require_one_line_error(run_hsr("render " + cube + " --repeat 2x2x2 --limit triangles=95" + small + out_png("t"), "t95"),
                           "96 triangles to draw, over the limit of 95 (raise it with --limit triangles=N)");
    require_success(run_hsr("render " + cube + " --repeat 2x2x2 --limit triangles=96" + small + out_png("t"), "t96"));
    require_one_line_error(run_hsr("render " + cube + " --repeat 2x2x2 --limit instances=7" + small + out_png("i"), "i7"),
                           "8 instances, over the limit of 7");
    require_success(run_hsr("render " + cube + " --repeat 2x2x2 --limit instances=8" + small + out_png("i"), "i8"));
    // stored triangles: a line drawing copies the 96 out.
    const std::string svg = " -o " + (scratch_dir() / "s.svg").string();
    require_one_line_error(run_hsr("render " + cube + " -a appel --repeat 2x2x2 --limit stored-triangles=95" + small + svg, "s95"),
                           "96 stored triangles, over the limit of 95");
    require_success(run_hsr("render " + cube + " -a appel --repeat 2x2x2 --limit stored-triangles=96" + small + svg, "s96"));
    // lights: three --light options.
    const std::string lights = " --light dir:0,0,1 --light dir:1,0,1 --light point:0,3,3";
    require_one_line_error(run_hsr("render " + cube + lights + " --limit lights=2" + small + out_png("l"), "l2"),
                           "--light: 3 lights, over the limit of 2 (raise it with --limit lights=N)");
    require_success(run_hsr("render " + cube + lights + " --limit lights=3" + small + out_png("l"), "l3"));
    // surface samples: 40 x 40.
    const std::string surface = " --surface x*y --range -1:1,-1:1,40x40";
    require_one_line_error(run_hsr("render" + surface + " --limit surface-samples=1599" + small + out_png("g"), "g1599"),
                           "1600 grid samples, over the limit of 1599");
    require_success(run_hsr("render" + surface + " --limit surface-samples=1600" + small + out_png("g"), "g1600"));
    // height-map pixels: 30 x 20.
    const std::string heightmap = " --heightmap " + grey_png(30, 20, "cli-heightmap.png").string();
    require_one_line_error(run_hsr("render" + heightmap + " --limit heightmap-pixels=599" + small + out_png("h"), "h599"),
                           "600 pixels, over the limit of 599 (raise it with --limit heightmap-pixels=N)");
    require_success(run_hsr("render" + heightmap + " --limit heightmap-pixels=600" + small + out_png("h"), "h600"));
    // image pixels: 32 x 24 = 768, from the command line or from a .scene file's size.
    require_one_line_error(run_hsr("render " + cube + " --limit image-pixels=767" + small + out_png("p"), "p767"),
                           "image size 32x24: 768 pixels, over the limit of 767 (raise it with --limit image-pixels=N)");
    require_success(run_hsr("render " + cube + " --limit image-pixels=768" + small + out_png("p"), "p768"));
    const fs::path sized = write_file("sized.scene", "size 32 24\nmesh " + cube + "\n");
    require_one_line_error(run_hsr("render " + sized.string() + " --limit image-pixels=767" + out_png("q"), "q767"),
                           "image size 32x24: 768 pixels");
    // stored triangles of a .scene file: two cubes.
    const fs::path two = write_file("two-cubes.scene", "mesh " + cube + "\nmesh " + cube + "\n  translate 2 0 0\n");
    require_one_line_error(run_hsr("render " + two.string() + " --limit stored-triangles=23" + small + out_png("c"), "c23"),
                           "two-cubes.scene:2: the meshes and polygons up to here: 24 stored triangles");
    require_success(run_hsr("render " + two.string() + " --limit stored-triangles=24" + small + out_png("c"), "c24"));
    // The option itself.
    require_one_line_error(run_hsr("render " + cube + " --limit pixels=5", "bad-name"), "unknown limit 'pixels'");
    require_one_line_error(run_hsr("render " + cube + " --limit lights=-5", "bad-value"), "'-5' is not a whole number");
    const Run help = run_hsr("render --help", "help");
    CHECK(help.status == 0);
    CHECK_THAT(help.out, Catch::Contains("--limit") && Catch::Contains("heightmap-pixels"));
}

TEST_CASE("cli: the default limits refuse the large requests with one line, quickly", "[limits][cli]") {
    // Each of these allocated gigabytes or ran for minutes; the figures are in the commit message.
    const std::string cube = model("cube.obj");
    require_one_line_error(run_hsr("render " + cube + " --repeat 3162x3162x1" + out_png("wide"), "wide"),
                           "9998244 instances, over the limit of 1000000");
    require_one_line_error(run_hsr("render " + cube + " --width 16384 --height 16384" + out_png("big"), "big"),
                           "image size 16384x16384: 268435456 pixels, over the limit of 67108864");
    const fs::path huge = png_header_claiming(40000, 40000, "cli-huge-header.png");
    require_one_line_error(run_hsr("render --heightmap " + huge.string() + out_png("hm"), "huge-heightmap"),
                           "1600000000 pixels, over the limit of 16777216 (raise it with --limit heightmap-pixels=N)");
    std::string lights = "size 16 16\nmesh " + cube + "\n";
    for (int k = 0; k < 200000; ++k) lights += "light point:1,2," + std::to_string(k + 3) + "\n";
    const fs::path many_lights = write_file("200k-lights.scene", lights);
    require_one_line_error(run_hsr("render " + many_lights.string() + out_png("ml"), "200k-lights"),
                           "200k-lights.scene:1003: 1001 lights, over the limit of 1000");
    // 1,001 mesh lines of one file, then a repeat: the file is read once, and the lines stop at the limit.
    std::string meshes;
    for (int k = 0; k < 1001; ++k) meshes += "mesh " + cube + "\n";
    meshes += "repeat 1000 1000 1\n";
    const fs::path many_meshes = write_file("1001-meshes.scene", meshes);
    require_one_line_error(run_hsr("render " + many_meshes.string() + out_png("mm"), "1001-meshes"),
                           "1001-meshes.scene:17: the meshes and polygons up to here (204 triangles) repeated "
                           "1000x1000x1: 204000000 triangles to draw, over the limit of 200000000");
}

TEST_CASE("cli: --threads must be 0 or more, and a long direction is fine", "[limits][cli]") {
    const std::string cube = model("cube.obj");
    require_one_line_error(run_hsr("render " + cube + " --threads -1" + out_png("th"), "threads-negative"),
                           "--threads -1: expected 0 (one per core) to 1024");
    require_one_line_error(run_hsr("render " + cube + " --threads 5000" + out_png("th"), "threads-many"), "--threads 5000");
    require_success(run_hsr("render " + cube + " --threads 2 --width 16 --height 16" + out_png("th"), "threads-2"));
    require_one_line_error(run_hsr("view --threads -1 --listen 127.0.0.1:0", "view-threads-negative"),
                           "--threads -1: expected 0 (one per core) to 1024");
    require_one_line_error(run_hsr("bench --threads 1025", "bench-threads-many"),
                           "--threads must be between 0 and 1024");
    require_success(run_hsr("render " + cube + " --light dir:3e38,3e38,3e38 --width 16 --height 16" + out_png("dir"),
                            "long-direction"));
    // An option's text with a control byte comes back escaped.
    require_one_line_error(run_hsr("render " + cube + " --edges \"$(printf 'a\\033b')\" -a appel", "edges-escape"),
                           "--edges 'a\\x1bb'");
}

TEST_CASE("cli: hsr bench takes --limit too", "[limits][cli]") {
    const std::string bench = "bench --quick --algorithms zbuffer --models-dir " + test_models::dir.string();
    require_one_line_error(run_hsr(bench + " --models cube --sizes 64 -r 1 --limit image-pixels=4095", "bench-pixels"),
                           "--sizes: 64: 4096 pixels, over the limit of 4095 (raise it with --limit image-pixels=N)");
    // Its progress line, then the error.
    const Run deep = run_hsr(bench + " --models deep-3:cube --limit instances=10", "bench-instances");
    CHECK(deep.status == 1);
    CHECK_THAT(deep.err, Catch::EndsWith("\nhsr: error: 4x4x3 copies of 12 triangles: 48 instances, over the limit of "
                                         "10 (raise it with --limit instances=N)\n"));
    require_one_line_error(run_hsr(bench + " --limit bogus=1", "bench-bogus"), "unknown limit 'bogus'");
    const Run r = run_hsr(bench + " --models cube --sizes 64 -r 1 --limit image-pixels=4096", "bench-ok");
    INFO(r.err);
    CHECK(r.status == 0);
}

// ---------------------------------------------------------------------------------------------
// Limits that count the work: the pixels of every sample, and plugins' own bounds

TEST_CASE("cli: supersampling counts every sample's pixels against image-pixels", "[limits][cli]") {
    const std::string cube = model("cube.obj");
    // 8192 x 8192 is the limit itself; 16 samples render 16 such frames.
    require_one_line_error(
        run_hsr("render " + cube + " --samples 16 --width 8192 --height 8192" + out_png("ss16"), "ss16"),
        "image size 8192x8192 at 16 samples per pixel: 1073741824 pixels, over the limit of 67108864 (raise it "
        "with --limit image-pixels=N)");
    // 64 x 64 x 4 = 16384: one pixel over a limit of 16383, exactly at 16384.
    require_one_line_error(
        run_hsr("render " + cube + " --samples 4 --width 64 --height 64 --limit image-pixels=16383" + out_png("ss4"),
                "ss4-over"),
        "image size 64x64 at 4 samples per pixel: 16384 pixels, over the limit of 16383");
    CHECK(run_hsr("render " + cube + " --samples 4 --width 64 --height 64 --limit image-pixels=16384" + out_png("ss4"),
                  "ss4-at")
              .status == 0);
    // A .scene file's size and samples are counted when its picture is made.
    const fs::path scene = write_file("samples.scene", "size 64 64\nsamples 4\nmesh " + cube + "\n");
    require_one_line_error(run_hsr("render " + scene.string() + " --limit image-pixels=16383" + out_png("ss-scene"),
                                   "ss-scene"),
                           "image size 64x64 at 4 samples per pixel: 16384 pixels, over the limit of 16383");
}

TEST_CASE("cli: appel and floating-horizon refuse work past their own bounds, before doing it",
          "[limits][cli][appel][floating-horizon]") {
    // 200,000 random triangles: every edge a contour edge, large triangles over much of the picture;
    // the grids alone would hold about 720 million entries (3.1 GB and minutes without the bound).
    require_one_line_error(run_hsr("render --random-triangles 200000 -a appel -o " +
                                       (cli::scratch_dir() / "rt.svg").string(), "appel-200k"),
                           "over the limit of 250000000 (raise it with max-candidates=N)");
    // 12 random triangles, 36 edges: a bound of 10 is below the grids' entries alone.
    const std::string small = "render --random-triangles 12 -o " + (cli::scratch_dir() / "rt12.svg").string();
    require_one_line_error(run_hsr(small + " -a appel:max-candidates=10", "appel-12"),
                           "appel: the grids of the edges and faces seen would hold ");
    CHECK(run_hsr(small + " -a appel", "appel-12-default").status == 0);

    // A 1024 x 1024 grid with a column at every vertex: each of its 1024 curves spans about a
    // million columns (over 40 s of work); without vertex columns, about 4 per pixel.
    const std::string surface = "render --surface 'sin(x)*cos(y)' --range -3:3,-3:3,1024x1024 -o " +
                                (cli::scratch_dir() / "fh.svg").string();
    require_one_line_error(run_hsr(surface + " -a floating-horizon", "fh-1024"),
                           "horizon columns, over the limit of 500000000 (raise it with max-column-updates=N, or set "
                           "vertex-columns=false");
    CHECK(run_hsr(surface + " -a floating-horizon:vertex-columns=false", "fh-1024-even").status == 0);
    // A 2 x 2 grid, 1 cell: 2 curve edges, 2 cross edges and 1 diagonal visit at least 5 columns.
    const std::string tiny = "render --surface 'x*y' --range 0:1,0:1,2x2 -o " + (cli::scratch_dir() / "fh2.svg").string();
    require_one_line_error(run_hsr(tiny + " -a floating-horizon:max-column-updates=4", "fh-2"),
                           "floating-horizon: the grid's edges would visit ");
    CHECK(run_hsr(tiny + " -a floating-horizon", "fh-2-default").status == 0);
}

TEST_CASE("cli: user text in messages is cut and escaped, and every error is one line", "[limits][cli][printable]") {
    // A mesh path of 5 MB in a .scene file, and one of 100 KB on the command line (an argument's
    // own limit on Linux is 128 KiB): quoted to 240 characters.
    const std::string long_name(5'000'000, 'p');
    const fs::path scene = write_file("long-mesh-path.scene", "mesh " + long_name + ".obj\n");
    const Run from_scene = run_hsr("render " + scene.string() + out_png("lp"), "long-mesh-path");
    require_one_line_error(from_scene, std::string(100, 'p') + "...: no such file");  // after the scene's folder
    CHECK(std::count(from_scene.err.begin(), from_scene.err.end(), 'p') < 240);
    const Run from_argument = run_hsr("render " + std::string(100'000, 'q') + ".obj" + out_png("la"), "long-argument");
    require_one_line_error(from_argument, std::string(240, 'q') + "...: no such file");
    CHECK(from_argument.err.size() < 400);
    const Run output = run_hsr("render " + model("cube.obj") + " -o " + std::string(100'000, 'r') + ".svg", "long-output");
    require_one_line_error(output, std::string(240, 'r') + "...");
    CHECK(output.err.size() < 600);
    // An unknown option is quoted cut short, as other user text is.
    const Run option = run_hsr("render --" + std::string(100'000, 'o'), "long-option");
    require_one_line_error(option, "unknown option --ooo");
    CHECK(option.err.size() < 400);
    // CR and LF in a path, a command and a plugin's name are written as \x0d\x0a (printf in the
    // shell that runs hsr makes them).
    require_one_line_error(run_hsr("render \"$(printf 'a\\r\\nb.obj')\"" + out_png("crlf"), "crlf-path"),
                           "a\\x0d\\x0ab.obj: no such file");
    require_one_line_error(run_hsr("\"$(printf 'x\\r\\ny')\"", "crlf-command"), "unknown command 'x\\x0d\\x0ay'");
    require_one_line_error(
        run_hsr("render " + model("cube.obj") + " -a \"$(printf 'no\\nsuch')\"" + out_png("crlf-plugin"), "crlf-plugin"),
        "plugin named 'no\\x0asuch'");
}

TEST_CASE("cli: a command of more than 4096 words is refused before it is parsed", "[limits][cli]") {
    // Boost.Program_options takes time quadratic in the words: 40,000 took 16 to 20 s.
    std::string words;
    for (int k = 0; k < 2100; ++k) words += " --yaw 1";
    require_one_line_error(run_hsr("render " + model("cube.obj") + words + out_png("words"), "many-words"),
                           "4203 arguments, more than a command may have (4096)");
}
