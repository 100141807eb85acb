// Hostile model files: counts that overflow, indices at the edge of long long, elements that
// bound no loop, and lines that make OpenMesh's readers slow. Each must be refused with one line
// naming the file and the problem (or, where valid, read as written), quickly, and without reading
// out of bounds (the ASan+UBSan build runs these too). The small files are in tests/data/bad/; the
// large ones are made here.
#include "hsr/error.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/stat.h>

namespace fs = std::filesystem;

namespace {

const fs::path bad_dir = fs::path(HSR_SOURCE_DIR) / "tests" / "data" / "bad";

struct Refusal {
    std::string message;
    double seconds = 0;
};

// Loads `file`, which must throw hsr::Error; returns its message and how long the refusal took.
Refusal refusal_of(const fs::path& file) {
    const auto start = std::chrono::steady_clock::now();
    Refusal refusal;
    bool threw = false;
    try {
        hsr::load_model(file);
    } catch (const hsr::Error& e) {
        refusal.message = e.what();
        threw = true;
    }
    refusal.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    INFO(file.string());
    REQUIRE(threw);
    CHECK(refusal.message.find('\n') == std::string::npos);
    CHECK_THAT(refusal.message, Catch::Contains(file.filename().string()));
    return refusal;
}

fs::path scratch_dir() {
    const fs::path dir = fs::path(HSR_BINARY_DIR) / "test-bad-models-scratch";
    fs::create_directories(dir);
    return dir;
}

fs::path write_scratch(const std::string& name, const std::string& text) {
    const fs::path file = scratch_dir() / name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
}

const std::string triangle_obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

}  // namespace

TEST_CASE("bad models: OFF counts near 2^63 are compared with the lines there are", "[bad-models]") {
    const Refusal counts = refusal_of(bad_dir / "off-count-overflow.off");
    CHECK_THAT(counts.message, Catch::Contains("ends early") &&
                                   Catch::Contains("9223372036854775807 vertices and 9223372036854775807 faces"));
    const Refusal corners = refusal_of(bad_dir / "off-corner-count-overflow.off");
    CHECK_THAT(corners.message, Catch::Contains("off-corner-count-overflow.off:6:"));
}

TEST_CASE("bad models: OBJ index -2^63 goes before the first vertex", "[bad-models]") {
    CHECK_THAT(refusal_of(bad_dir / "obj-index-min.obj").message,
               Catch::Contains("obj-index-min.obj:4:") &&
                   Catch::Contains("vertex reference -9223372036854775808 goes before the first vertex"));
}

TEST_CASE("bad models: a PLY element without properties may not have entries", "[bad-models]") {
    const Refusal r = refusal_of(bad_dir / "ply-element-without-properties.ply");
    CHECK_THAT(r.message, Catch::Contains("element 'junk' has 9223372036854775807 entries but no properties"));
    CHECK(r.seconds < 5);
}

TEST_CASE("bad models: echoed text is printable and short", "[bad-models]") {
    const Refusal r = refusal_of(bad_dir / "obj-control-bytes.obj");
    CHECK_THAT(r.message, Catch::Contains("obj-control-bytes.obj:4: '\\x01\\x1b[31m' is not a vertex reference"));
    for (char c : r.message) CHECK((c >= 0x20 && c < 0x7f));

    const std::string long_token(100000, 'x');
    const Refusal long_one = refusal_of(write_scratch("long-token.obj", triangle_obj + "f 1 2 " + long_token + "\n"));
    std::string shortened(80, 'x');
    shortened += "...'";
    CHECK_THAT(long_one.message, Catch::Contains(shortened));
    CHECK(long_one.message.size() < 300);
}

// OpenMesh's OBJ reader cuts a vertex reference at each '/' with a copy of the rest (quadratic: 1 MB
// of slashes took 12 s, 2 MB 45 s); the check refuses more than two, at about 10 ms for 2 MB.
TEST_CASE("bad models: an OBJ vertex reference with a long run of slashes", "[bad-models]") {
    const fs::path file = write_scratch("slashes.obj", triangle_obj + "f 1 2 3" + std::string(2 << 20, '/') + "\n");
    const Refusal r = refusal_of(file);
    CHECK_THAT(r.message, Catch::Contains("slashes.obj:4:") && Catch::Contains("more than two '/'"));
    CHECK(r.seconds < 5);

    // OpenMesh reads a comment after a face's corners as more corners: it may not hide the slashes.
    const std::string commented_slashes = "f 1 2 3 #" + std::string(2 << 20, '/') + "\n";
    const auto start = std::chrono::steady_clock::now();
    CHECK(hsr::load_model(write_scratch("commented-slashes.obj", triangle_obj + commented_slashes)).indices.size() == 3);
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 5);
}

// OpenMesh splits a polygon into a fan in time quadratic in its corners (100,000 corners: 35 s).
TEST_CASE("bad models: faces with more than 1000 corners, in OBJ, OFF and PLY", "[bad-models]") {
    constexpr int corners = 1001;
    std::string vertices, obj_vertices, obj_face = "f", off_face = std::to_string(corners);
    for (int i = 0; i < corners; ++i) {
        vertices += fmt::format("{} {} 0\n", i % 100, i / 100);
        obj_vertices += fmt::format("v {} {} 0\n", i % 100, i / 100);
        obj_face += fmt::format(" {}", i + 1);
        off_face += fmt::format(" {}", i);
    }
    const std::string count = std::to_string(corners);

    const Refusal obj = refusal_of(write_scratch("corners.obj", obj_vertices + obj_face + "\n"));
    CHECK_THAT(obj.message, Catch::Contains("corners.obj:1002:") && Catch::Contains("more than 1000 vertices"));
    const Refusal off = refusal_of(write_scratch("corners.off", "OFF\n" + count + " 1 0\n" + vertices + off_face + "\n"));
    CHECK_THAT(off.message, Catch::Contains("corners.off:1004:") && Catch::Contains("more than 1000 vertices"));
    const Refusal ply = refusal_of(write_scratch(
        "corners.ply", "ply\nformat ascii 1.0\nelement vertex " + count +
                           "\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
                           "property list ushort int vertex_indices\nend_header\n" + vertices + off_face + "\n"));
    CHECK_THAT(ply.message, Catch::Contains("corners.ply:") && Catch::Contains("more than 1000 vertices"));

    // 1000 corners are still read: a regular polygon, triangulated as a fan.
    std::string polygon = "OFF\n1000 1 0\n", face = "1000";
    for (int i = 0; i < 1000; ++i) {
        const double angle = 2 * 3.141592653589793 * i / 1000;
        polygon += fmt::format("{} {} 0\n", std::cos(angle), std::sin(angle));
        face += fmt::format(" {}", i);
    }
    const hsr::SceneData scene = hsr::load_model(write_scratch("polygon.off", polygon + face + "\n"));
    CHECK(scene.indices.size() == 3 * 998);
}

// Text in UTF-16 (assimp's OBJ/box_UTF16BE.obj) reads as no faces at all to an ASCII reader; a
// UTF-8 byte-order mark in front of `v` or `OFF` would hide the first word.
TEST_CASE("bad models: UTF-16 text is refused, a UTF-8 byte-order mark is skipped", "[bad-models]") {
    CHECK_THAT(refusal_of(bad_dir / "obj-utf16.obj").message,
               Catch::Contains("is UTF-16 text") && Catch::Contains("save it as ASCII or UTF-8"));
    const std::string mark = "\xEF\xBB\xBF";
    CHECK(hsr::load_model(write_scratch("mark.obj", mark + triangle_obj + "f 1 2 3\n")).indices.size() == 3);
    CHECK(hsr::load_model(write_scratch("mark.off", mark + "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"))
              .indices.size() == 3);
}

// A pipe named like a model would be waited on for ever, /dev/zero read until memory runs out.
TEST_CASE("bad models: pipes and devices are not read as models or scenes", "[bad-models]") {
    const fs::path dir = scratch_dir();
    for (const char* name : {"pipe.obj", "pipe.scene"}) {
        const fs::path pipe = dir / name;
        fs::remove(pipe);
        REQUIRE(::mkfifo(pipe.c_str(), 0600) == 0);
    }
    for (const char* name : {"zero.ply", "zero.scene"}) {
        fs::remove(dir / name);
        fs::create_symlink("/dev/zero", dir / name);
    }
    CHECK_THAT(refusal_of(dir / "pipe.obj").message, Catch::Contains("is not a regular file"));
    CHECK_THAT(refusal_of(dir / "zero.ply").message, Catch::Contains("is not a regular file"));
    for (const char* name : {"pipe.scene", "zero.scene"}) {
        INFO(name);
        CHECK_THROWS_WITH(hsr::load_scene_file(dir / name),
                          Catch::Contains(name) && Catch::Contains("is not a regular file"));
    }
}

// OpenMesh refuses a whole file for `vt u` (v and w may be left out), as in assimp's
// OBJ/multiple_spaces.obj cut after its first `vt` value; hsr reads no texture coordinates.
TEST_CASE("bad models: an OBJ texture coordinate with one value", "[bad-models]") {
    const std::string one_value = triangle_obj + "vt 0.5\nvt 0.25\nvt 1\nf 1/1 2/2 3/3\n";
    CHECK(hsr::load_model(write_scratch("one-texture-value.obj", one_value)).indices.size() == 3);
}

// OpenMesh takes an STL for binary only when its size is exactly that of its triangles, and reads
// anything else as ASCII, finding no faces in a binary file with bytes to spare.
TEST_CASE("bad models: a binary STL with bytes after its triangles", "[bad-models]") {
    CHECK_THAT(refusal_of(bad_dir / "stl-binary-trailing-bytes.stl").message,
               Catch::Contains("binary STL has 1 byte after its 3 triangles"));
}

TEST_CASE("bad models: an OFF face's colour is not read as the next face", "[bad-models]") {
    // Two faces with colours after their indices, the second a colour-map index of -1: read as the
    // next face's corner count, that asks for four billion corners.
    const fs::path file = write_scratch("face-colour.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                                                           "3 0 1 2 1 0 0\n3 0 2 3 -1\n");
    const hsr::SceneData scene = hsr::load_model(file);  // a hang here is the bug (ctest's timeout)
    CHECK(scene.indices.size() == 2 * 3);  // the file's two triangles, both kept
}
