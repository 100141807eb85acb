// Colours that model files give their faces: an OBJ file's materials (mtllib, usemtl, Kd), OFF and
// PLY face and vertex colours, read back through the facecolor lighting model (by=given, the
// scene's own colours) against the values written in the files; a .scene file's colour over them;
// and the material libraries that are not read (outside the model's folder, through a link, a
// pipe, missing), each with its one warning line and without waiting.
#include "face_colors.hpp"

#include "hsr/abi.h"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <glm/glm.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

struct ScratchFolder {
    fs::path path = fs::temp_directory_path() / fmt::format("hsr-test-model-colors-{}", ::getpid());
    ScratchFolder() { fs::create_directories(path / "models"); }
    ~ScratchFolder() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
};

const ScratchFolder& scratch() {
    static const ScratchFolder folder;
    return folder;
}

// A file in the scratch folder's models/ (or at `relative` from it).
fs::path write_file(const std::string& relative, const std::string& text) {
    const fs::path file = scratch().path / "models" / relative;
    std::ofstream(file, std::ios::binary) << text;
    return file;
}

std::vector<glm::vec3> shaded_colors(const hsr::SceneData& scene) { return test_colors::face_colors(scene); }

// Each colour to within float rounding (the files give decimals; /255 is not exact).
void check_colors(const std::vector<glm::vec3>& got, const std::vector<glm::vec3>& expected) {
    REQUIRE(got.size() == expected.size());
    for (std::size_t t = 0; t < got.size(); ++t) {
        INFO("triangle " << t);
        for (int k = 0; k < 3; ++k) CHECK(got[t][k] == Approx(expected[t][k]).margin(1e-6));
    }
}

const glm::vec3 grey = hsr::MeshOptions().color;

// Two triangles side by side and a quad: three faces, four triangles.
constexpr const char* three_faces_obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\nv 3 0 0\nv 3 1 0\nv 2 1 0\n";

std::vector<std::string> warnings_of(const fs::path& model) { return hsr::load_model(model).warnings; }

}  // namespace

TEST_CASE("model colours: an OBJ file's faces take their material's Kd", "[model-loading][colors]") {
    write_file("two.mtl", "# two materials\nnewmtl red\nKa 0 0 0\nKd 0.9 0.1 0.2\nnewmtl sky blue\n"
                          "Kd 0.25 0.5 1\nillum 2\n");
    const fs::path model = write_file("two.obj", std::string("mtllib two.mtl\n") + three_faces_obj +
                                                     "f 1 2 3\nusemtl red\nf 2 4 3\nusemtl sky blue\nf 4 5 6 7\n");
    const hsr::SceneData scene = hsr::load_model(model);
    CHECK(scene.warnings.empty());
    // The first face comes before any usemtl; "sky blue" is the material "sky" (names are one word).
    check_colors(shaded_colors(scene), {grey, {0.9f, 0.1f, 0.2f}, {0.25f, 0.5f, 1.0f}, {0.25f, 0.5f, 1.0f}});
}

TEST_CASE("model colours: a .scene file's colour wins over the file's, none keeps them", "[model-loading][colors]") {
    write_file("one.mtl", "newmtl green\nKd 0 1 0\n");
    write_file("one.obj", "mtllib one.mtl\nusemtl green\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const fs::path scene_file = write_file("one.scene", "mesh one.obj\n  color 1 0 0\nmesh one.obj\n  translate 2 0 0\n");
    const hsr::SceneData scene = hsr::load_scene_file(scene_file).scene;
    check_colors(shaded_colors(scene), {{1, 0, 0}, {0, 1, 0}});
}

TEST_CASE("model colours: OFF face colours (0-255 and 0-1) and vertex colours (the corners' mean)",
          "[model-loading][colors]") {
    const std::string positions = "0 0 0\n1 0 0\n1 1 0\n2 0 0\n";
    const hsr::SceneData faces = hsr::load_model(
        write_file("faces.off", "OFF\n4 3 0\n" + positions + "3 0 1 2 255 0 51\n3 1 3 2 0.5 0.25 1 0.5\n3 0 2 3\n"));
    CHECK(faces.warnings.empty());
    check_colors(shaded_colors(faces), {{1, 0, 0.2f}, {0.5f, 0.25f, 1}, grey});

    const hsr::SceneData corners = hsr::load_model(write_file(
        "corners.off", "COFF\n4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n2 0 0 0 0 0 255\n"
                       "3 0 1 2\n3 1 3 2\n"));
    check_colors(shaded_colors(corners), {{1.0f / 3, 1.0f / 3, 1.0f / 3}, {0, 1.0f / 3, 1.0f / 3}});
}

TEST_CASE("model colours: PLY vertex colours (uchar) and face colours (float)", "[model-loading][colors]") {
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                               "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
                               "element face 2\nproperty list uchar int vertex_indices\n";
    const std::string vertices = "0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n2 0 0 255 255 255\n";
    const hsr::SceneData by_vertex =
        hsr::load_model(write_file("corners.ply", header + "end_header\n" + vertices + "3 0 1 2\n3 1 3 2\n"));
    check_colors(shaded_colors(by_vertex), {{1.0f / 3, 1.0f / 3, 1.0f / 3}, {1.0f / 3, 2.0f / 3, 2.0f / 3}});

    const hsr::SceneData by_face = hsr::load_model(write_file(
        "faces.ply", header + "property float red\nproperty float green\nproperty float blue\nend_header\n" +
                         vertices + "3 0 1 2 0.5 0.75 1\n3 1 3 2 2 -1 0.125\n"));
    check_colors(shaded_colors(by_face), {{0.5f, 0.75f, 1}, {1, 0, 0.125f}});  // clamped to [0, 1]
}

TEST_CASE("model colours: material libraries outside the folder, through a link, or not files are not read",
          "[model-loading][colors]") {
    const fs::path outside = scratch().path / "outside.mtl";
    std::ofstream(outside) << "newmtl red\nKd 1 0 0\n";
    fs::create_symlink(outside, scratch().path / "models" / "link.mtl");
    const fs::path fifo = scratch().path / "models" / "fifo.mtl";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    struct Case {
        std::string mtllib, message;
    };
    const std::string objects = std::string(three_faces_obj) + "usemtl red\nf 1 2 3\n";
    const Case cases[] = {
        {"../outside.mtl", "material library '../outside.mtl' not read: only a file in the model's folder is read"},
        {outside.string(), fmt::format("material library '{}' not read: only a file in the model's folder is read",
                                       outside.string())},
        {"link.mtl", "material library 'link.mtl' not read: it leads out of the model's folder"},
        {"fifo.mtl", "material library 'fifo.mtl' not read: not a regular file (a pipe, device or socket)"},
        {"missing.mtl", "material library 'missing.mtl' not read: no such file"},
    };
    for (const Case& c : cases) {
        INFO(c.mtllib);
        const fs::path model = write_file("refused.obj", "mtllib " + c.mtllib + "\n" + objects);
        const auto start = std::chrono::steady_clock::now();
        const hsr::SceneData scene = hsr::load_model(model);
        CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
        CHECK(scene.warnings == std::vector<std::string>{model.string() + ": " + c.message});
        check_colors(shaded_colors(scene), {grey});
    }
    // /dev/zero is a device, not a regular file; it must not be read until memory runs out.
    fs::create_symlink("/dev/zero", scratch().path / "models" / "zero.mtl");
    const std::vector<std::string> zero = warnings_of(write_file("zero.obj", "mtllib zero.mtl\n" + objects));
    REQUIRE(zero.size() == 1);
    CHECK_THAT(zero[0], Catch::EndsWith("material library 'zero.mtl' not read: it leads out of the model's folder"));
}

TEST_CASE("model colours: missing materials, textures and Kd outside [0, 1] give one warning each",
          "[model-loading][colors]") {
    write_file("odd.mtl", "newmtl bright\nKd 2 0.5 -1\nmap_Kd wood.png\nnewmtl textured\nmap_Kd wood.png\n");
    const fs::path model = write_file("odd.obj", std::string("mtllib odd.mtl\n") + three_faces_obj +
                                                     "usemtl bright\nf 1 2 3\nusemtl nowhere\nf 2 4 3\n"
                                                     "usemtl textured\nf 4 5 6\nusemtl nowhere\nf 4 6 7\n");
    const hsr::SceneData scene = hsr::load_model(model);
    const std::string mtl = (scratch().path / "models" / "odd.mtl").string();
    CHECK(scene.warnings == std::vector<std::string>{
                                mtl + ": Kd values outside [0, 1] clamped to it",
                                model.string() + ": textures (map_Kd and other maps) are not drawn: faces take their "
                                                 "material's Kd colour",
                                model.string() + ": no Kd colour for material 'nowhere' (and 1 more) in the material "
                                                 "libraries read: those faces keep the object's colour"});
    check_colors(shaded_colors(scene), {{1, 0.5f, 0}, grey, grey, grey});
}
