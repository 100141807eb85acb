// glTF 2.0 models: small files made here (JSON with a base64 data URI, or a GLB put together by
// hand) read back with known triangles, bounds, placements and colours, rendered through the same
// camera as the equivalent plain scene, and refused with one line when they are broken or hostile.
#include "cli_support.hpp"
#include "face_colors.hpp"
#include "surface_test_support.hpp"

#include "hsr/abi.h"
#include "hsr/renderer.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <glm/glm.hpp>
#include <sys/stat.h>

#include <algorithm>
#include <cstring>
#include <tuple>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using surface_tests::plugin;

namespace {

std::string base64(const std::string& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
        for (int k = 3; k >= 0; --k) out += digits[v >> (6 * k) & 63];
    }
    if (i + 1 == bytes.size()) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        out += digits[v >> 18 & 63];
        out += digits[v >> 12 & 63];
        out += "==";
    } else if (i + 2 == bytes.size()) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8;
        out += digits[v >> 18 & 63];
        out += digits[v >> 12 & 63];
        out += digits[v >> 6 & 63];
        out += '=';
    }
    return out;
}

template <class T>
std::string bytes_of(const std::vector<T>& values) {
    std::string out(values.size() * sizeof(T), '\0');
    std::memcpy(out.data(), values.data(), out.size());
    return out;
}

// One buffer of views and accessors, then the JSON around it.
struct Gltf {
    std::string bin;
    std::vector<std::string> views, accessors;

    int view(const std::string& bytes, int stride = 0) {
        while (bin.size() % 4) bin += '\0';
        views.push_back("{\"buffer\":0,\"byteOffset\":" + std::to_string(bin.size()) + ",\"byteLength\":" +
                        std::to_string(bytes.size()) + (stride ? ",\"byteStride\":" + std::to_string(stride) : "") + "}");
        bin += bytes;
        return int(views.size() - 1);
    }
    // An accessor: `fields` is the rest of its JSON object ("componentType", "count", "type", ...).
    int accessor(const std::string& fields) {
        accessors.push_back("{" + fields + "}");
        return int(accessors.size() - 1);
    }
    int floats(const std::vector<float>& values, int components = 3) {
        const int v = view(bytes_of(values));
        return accessor("\"bufferView\":" + std::to_string(v) + ",\"componentType\":5126,\"count\":" +
                        std::to_string(values.size() / components) + ",\"type\":\"VEC" + std::to_string(components) + "\"");
    }
    template <class T>
    int indices(const std::vector<T>& values, int component_type) {
        const int v = view(bytes_of(values));
        return accessor("\"bufferView\":" + std::to_string(v) + ",\"componentType\":" + std::to_string(component_type) +
                        ",\"count\":" + std::to_string(values.size()) + ",\"type\":\"SCALAR\"");
    }

    static std::string join(const std::vector<std::string>& items) {
        std::string out;
        for (const std::string& item : items) out += (out.empty() ? "" : ",") + item;
        return out;
    }
    // The whole document; `rest` holds meshes, nodes, scenes and whatever else, as JSON members.
    std::string json(const std::string& rest, const std::string& buffer_uri = "") const {
        const std::string uri = buffer_uri.empty() ? "data:application/octet-stream;base64," + base64(bin) : buffer_uri;
        return "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) +
               (buffer_uri == "glb" ? "" : ",\"uri\":\"" + uri + "\"") + "}],\"bufferViews\":[" + join(views) +
               "],\"accessors\":[" + join(accessors) + "]," + rest + "}";
    }
    // The same as a GLB: the JSON chunk (buffer without uri) and the BIN chunk.
    std::string glb(const std::string& rest) const {
        std::string text = json(rest, "glb");
        while (text.size() % 4) text += ' ';
        std::string data = bin;
        while (data.size() % 4) data += '\0';
        std::string out = "glTF";
        const auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
        u32(2);
        u32(uint32_t(12 + 8 + text.size() + 8 + data.size()));
        u32(uint32_t(text.size()));
        u32(0x4E4F534Au);
        out += text;
        u32(uint32_t(data.size()));
        u32(0x004E4942u);
        out += data;
        return out;
    }
};

// One mesh of one primitive, placed by one node.
std::string one_mesh(const std::string& primitive, const std::string& extra = "") {
    return "\"meshes\":[{\"primitives\":[{" + primitive + "}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]" +
           extra;
}

const std::vector<float> unit_quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};

fs::path write(const std::string& name, const std::string& bytes) { return cli::write_file(name, bytes); }

hsr::SceneData load(const fs::path& file) {
    hsr::SceneSource source;
    source.model = file;
    return hsr::LoadedScene::load(source)->scene();
}

glm::vec3 position(const hsr::SceneData& scene, uint32_t vertex) {
    return {scene.positions[3 * vertex], scene.positions[3 * vertex + 1], scene.positions[3 * vertex + 2]};
}

// Triangle corners turned to start at the smallest (x, then y, then z) but not reversed: the same
// triangle with the same front, whichever corner a reader lists first.
std::vector<glm::vec3> turned(std::vector<glm::vec3> corners) {
    const auto smallest = std::min_element(corners.begin(), corners.end(), [](const glm::vec3& p, const glm::vec3& q) {
        return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
    });
    std::rotate(corners.begin(), smallest, corners.end());
    return corners;
}

// The corners of triangle t, as positions, turned.
std::vector<glm::vec3> corners(const hsr::SceneData& scene, uint32_t t) {
    return turned({position(scene, scene.indices[3 * t]), position(scene, scene.indices[3 * t + 1]),
                   position(scene, scene.indices[3 * t + 2])});
}

}  // namespace

TEST_CASE("glTF: a unit cube from a data URI and from a GLB: 12 triangles, exact bounds", "[gltf]") {
    Gltf g;
    const std::vector<float> cube = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    const std::vector<uint16_t> faces = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                         3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    const int p = g.floats(cube);
    const int i = g.indices(faces, 5123);
    const std::string rest = one_mesh("\"attributes\":{\"POSITION\":" + std::to_string(p) + "},\"indices\":" + std::to_string(i));
    for (const fs::path& file : {write("cube.gltf", g.json(rest)), write("cube.glb", g.glb(rest))}) {
        INFO(file);
        const hsr::SceneData scene = load(file);
        CHECK(scene.triangle_count() == 12);
        CHECK(scene.instances.empty());
        CHECK(scene.bounds_min == glm::vec3(0, 0, 0));
        CHECK(scene.bounds_max == glm::vec3(1, 1, 1));
        CHECK(scene.object_names.size() == 1);
    }
}

TEST_CASE("glTF: indices of u8, u16 and u32 give the same triangles", "[gltf]") {
    const std::vector<uint32_t> quad = {0, 1, 2, 0, 2, 3};
    std::vector<std::vector<glm::vec3>> first;
    for (int type : {5121, 5123, 5125}) {
        INFO(type);
        Gltf g;
        const int p = g.floats(unit_quad);
        const int i = type == 5121   ? g.indices(std::vector<uint8_t>(quad.begin(), quad.end()), type)
                      : type == 5123 ? g.indices(std::vector<uint16_t>(quad.begin(), quad.end()), type)
                                     : g.indices(quad, type);
        const hsr::SceneData scene = load(write("quad-" + std::to_string(type) + ".gltf",
                                                g.json(one_mesh("\"attributes\":{\"POSITION\":" + std::to_string(p) +
                                                                "},\"indices\":" + std::to_string(i)))));
        REQUIRE(scene.triangle_count() == 2);
        CHECK(corners(scene, 0) == turned(std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}));
        CHECK(corners(scene, 1) == turned(std::vector<glm::vec3>{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
    }
}

TEST_CASE("glTF: a triangle strip and a triangle fan become triangles in the specification's order", "[gltf]") {
    Gltf g;
    // Strip 0 1 2 3 over the quad's corners in zig-zag: triangles (0 1 2) and (2 1 3).
    const int strip = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    // Fan around (0, 0, 5): (1 2 0), (2 3 0) as the specification numbers them.
    const int fan = g.floats({0, 0, 5, 1, 0, 5, 1, 1, 5, 0, 1, 5});
    const std::string meshes = "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(strip) +
                               "},\"mode\":5},{\"attributes\":{\"POSITION\":" + std::to_string(fan) +
                               "},\"mode\":6}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]";
    const hsr::SceneData scene = load(write("strip-fan.gltf", g.json(meshes)));
    REQUIRE(scene.triangle_count() == 4);
    CHECK(corners(scene, 0) == turned(std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
    CHECK(corners(scene, 1) == turned(std::vector<glm::vec3>{{0, 1, 0}, {1, 0, 0}, {1, 1, 0}}));
    CHECK(corners(scene, 2) == turned(std::vector<glm::vec3>{{1, 0, 5}, {1, 1, 5}, {0, 0, 5}}));
    CHECK(corners(scene, 3) == turned(std::vector<glm::vec3>{{1, 1, 5}, {0, 1, 5}, {0, 0, 5}}));
}

TEST_CASE("glTF: normalized u8 positions and a sparse accessor", "[gltf]") {
    SECTION("normalized unsigned bytes: 255 is 1, 51 is 0.2") {
        Gltf g;
        // VEC3 of u8, each element padded to 4 bytes as the specification asks.
        const std::string bytes = std::string("\0\0\0\0", 4) + std::string("\xff\0\0\0", 4) + std::string("\0\x33\0\0", 4);
        const int v = g.view(bytes, 4);
        const int p = g.accessor("\"bufferView\":" + std::to_string(v) +
                                 ",\"componentType\":5121,\"normalized\":true,\"count\":3,\"type\":\"VEC3\"");
        const hsr::SceneData scene = load(write("normalized.gltf", g.json(one_mesh("\"attributes\":{\"POSITION\":" + std::to_string(p) + "}"))));
        REQUIRE(scene.triangle_count() == 1);
        CHECK(corners(scene, 0) == turned(std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, float(51 / 255.0), 0}}));
    }
    SECTION("sparse: no buffer view (all zero), two of three vertices substituted") {
        Gltf g;
        const int index_view = g.view(bytes_of(std::vector<uint16_t>{1, 2}));
        const int value_view = g.view(bytes_of(std::vector<float>{2, 0, 0, 0, 3, 0}));
        const int p = g.accessor("\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"sparse\":{\"count\":2,"
                                 "\"indices\":{\"bufferView\":" + std::to_string(index_view) +
                                 ",\"componentType\":5123},\"values\":{\"bufferView\":" + std::to_string(value_view) + "}}");
        const hsr::SceneData scene = load(write("sparse.gltf", g.json(one_mesh("\"attributes\":{\"POSITION\":" + std::to_string(p) + "}"))));
        REQUIRE(scene.triangle_count() == 1);
        CHECK(corners(scene, 0) == turned(std::vector<glm::vec3>{{0, 0, 0}, {2, 0, 0}, {0, 3, 0}}));
    }
}

namespace {

// The zbuffer's face ids (with instance ids) of a scene file through one camera.
struct Ids {
    std::vector<uint32_t> face, instance;
};
Ids render_ids(const fs::path& file, uint32_t side) {
    hsr::SceneSource source;
    source.model = file;
    hsr::Renderer renderer(hsr::LoadedScene::load(source));
    hsr::HiddenSurfaceRemover remover(plugin("zbuffer"), {});
    hsr::LightingModel lighting(plugin("facecolor"), {});
    hsr::PictureRequest request;
    request.view.width = side;
    request.view.height = side;
    request.view.yaw_degrees = 30.0f;
    request.view.pitch_degrees = 20.0f;
    const hsr::Picture picture = renderer.picture(request, remover, lighting);
    return {picture.frame.face, picture.frame.instance};
}

}  // namespace

TEST_CASE("glTF: a mesh used by two nodes is stored once and drawn as 2 instances, as two copies are", "[gltf]") {
    Gltf g;
    const std::vector<float> cube = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    const std::vector<uint16_t> faces = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                         3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    const int p = g.floats(cube);
    const int i = g.indices(faces, 5123);
    const std::string primitive = "{\"attributes\":{\"POSITION\":" + std::to_string(p) + "},\"indices\":" + std::to_string(i) + "}";
    // The second placement names mesh `second`: the same mesh again, or its copy.
    const auto nodes = [](const char* second) {
        return std::string("\"nodes\":[{\"children\":[1,2]},{\"mesh\":0,\"translation\":[0.5,0.25,-1.5]},{\"mesh\":") +
               second + ",\"translation\":[-1,0,0],\"scale\":[0.5,0.5,0.5]}],\"scenes\":[{\"nodes\":[0]}]";
    };
    const std::string shared_nodes = nodes("0"), separate_nodes = nodes("1");
    const fs::path shared = write("shared.gltf", g.json("\"meshes\":[{\"primitives\":[" + primitive + "]}]," + shared_nodes));
    const fs::path separate = write("separate.gltf", g.json("\"meshes\":[{\"primitives\":[" + primitive +
                                                            "]},{\"primitives\":[" + primitive + "]}]," + separate_nodes));
    const hsr::SceneData instanced = load(shared);
    CHECK(instanced.triangle_count() == 12);
    CHECK(instanced.object_names.size() == 1);
    REQUIRE(instanced.instances.size() == 2);
    const hsr::SceneData copies = load(separate);
    CHECK(copies.triangle_count() == 24);
    CHECK(copies.instances.empty());
    CHECK(instanced.bounds_min == copies.bounds_min);
    CHECK(instanced.bounds_max == copies.bounds_max);

    const Ids a = render_ids(shared, 96), b = render_ids(separate, 96);
    REQUIRE(a.face.size() == b.face.size());
    REQUIRE(a.instance.size() == a.face.size());
    uint64_t drawn = 0, same = 0;
    for (std::size_t px = 0; px < a.face.size(); ++px) {
        const uint32_t expected = a.face[px] == HSR_NO_FACE ? HSR_NO_FACE : a.instance[px] * 12 + a.face[px];
        if (b.face[px] != HSR_NO_FACE) ++drawn;
        if (b.face[px] == expected) ++same;
    }
    CHECK(drawn > 1000);
    CHECK(same == a.face.size());
}

namespace {

std::vector<glm::vec3> given_colors(const hsr::SceneData& scene) { return test_colors::face_colors(scene); }

}  // namespace

TEST_CASE("glTF: base colour factors and COLOR_0 are the faces' colours", "[gltf][facecolor]") {
    Gltf g;
    const int p = g.floats(unit_quad);
    const int shifted = g.floats({0, 0, 1, 1, 0, 1, 1, 1, 1});
    const int i = g.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, 5123);
    // Corner colours: each face's mean is exact, (0.25, 0.25, 0) and (0, 0.25, 0.25).
    const int c = g.floats({0, 0, 0, 0.75f, 0, 0, 0, 0.75f, 0, 0, 0, 0.75f});
    const std::string rest =
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.25,0.5,0.75,1]}}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(p) + ",\"COLOR_0\":" + std::to_string(c) +
        "},\"indices\":" + std::to_string(i) + "},{\"attributes\":{\"POSITION\":" + std::to_string(shifted) +
        "},\"material\":0}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]";
    const hsr::SceneData scene = load(write("colours.gltf", g.json(rest)));
    REQUIRE(scene.triangle_count() == 3);
    const std::vector<glm::vec3> colors = given_colors(scene);
    CHECK(colors[0] == glm::vec3(0.25f, 0.25f, 0.0f));
    CHECK(colors[1] == glm::vec3(0.0f, 0.25f, 0.25f));
    CHECK(colors[2] == glm::vec3(0.25f, 0.5f, 0.75f));
}

namespace {

// A unit quad seen by a perspective camera at (0.5, 0.5, 3) and an orthographic one at (0.5, 0.5, 2).
std::string with_cameras() {
    Gltf g;
    const int p = g.floats(unit_quad);
    const int i = g.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, 5123);
    return g.json("\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(p) +
                  "},\"indices\":" + std::to_string(i) + "}]}],"
                  "\"cameras\":[{\"name\":\"front\",\"type\":\"perspective\",\"perspective\":{\"yfov\":0.5,\"znear\":0.25,"
                  "\"aspectRatio\":2}},{\"name\":\"flat\",\"type\":\"orthographic\",\"orthographic\":{\"xmag\":1,"
                  "\"ymag\":1,\"znear\":0.5,\"zfar\":10}}],"
                  "\"nodes\":[{\"mesh\":0},{\"camera\":0,\"translation\":[0.5,0.5,3]},{\"camera\":1,\"translation\":[0.5,0.5,2]}],"
                  "\"scenes\":[{\"nodes\":[0,1,2]}]");
}

}  // namespace

TEST_CASE("glTF: --camera looks through the file's camera, as the same camera given explicitly", "[gltf][cli]") {
    const fs::path model = write("cameras.gltf", with_cameras());
    const fs::path dir = cli::scratch_dir();
    const std::string m = model.string();
    const cli::Run by_name = cli::run_hsr("render " + m + " --camera front --height 32 -o " + (dir / "by-name.png").string(), "cam-name");
    REQUIRE(by_name.status == 0);
    const cli::Run by_index = cli::run_hsr("render " + m + " --camera 0 --height 32 -o " + (dir / "by-index.png").string(), "cam-index");
    REQUIRE(by_index.status == 0);
    // yfov 0.5 rad, aspect 2 at height 32: width 64.
    const cli::Run explicit_camera =
        cli::run_hsr("render " + m + " --eye 0.5,0.5,3 --target 0.5,0.5,2 --up 0,1,0 --fov " +
                         fmt::format("{}", glm::degrees(0.5f)) + " --near 0.25 --width 64 --height 32 -o " +
                         (dir / "explicit.png").string(),
                     "cam-explicit");
    REQUIRE(explicit_camera.status == 0);
    CHECK(cli::slurp(dir / "by-name.png") == cli::slurp(dir / "explicit.png"));
    CHECK(cli::slurp(dir / "by-index.png") == cli::slurp(dir / "explicit.png"));

    const cli::Run ortho = cli::run_hsr("render " + m + " --camera flat --height 32 -o " + (dir / "flat.png").string(), "cam-flat");
    CHECK(ortho.status == 0);

    cli::require_one_line_error(cli::run_hsr("render " + m + " --camera back -o " + (dir / "x.png").string(), "cam-unknown"),
                                "its cameras: 0 'front', 1 'flat'");
    const fs::path no_cameras = write("no-cameras.gltf", [] {
        Gltf g;
        const int p = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0});
        return g.json(one_mesh("\"attributes\":{\"POSITION\":" + std::to_string(p) + "}"));
    }());
    cli::require_one_line_error(
        cli::run_hsr("render " + no_cameras.string() + " --camera 0 -o " + (dir / "x.png").string(), "cam-none"),
        "has no cameras");
}

TEST_CASE("glTF: broken and hostile files are refused with one line", "[gltf][cli]") {
    const fs::path dir = cli::scratch_dir();
    const fs::path sub = dir / "refusals";
    fs::remove_all(sub);
    fs::create_directories(sub / "inner");
    Gltf g;
    const int p = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const auto refuse = [&](const fs::path& file, const std::string& expected, const std::string& extra = "") {
        INFO(file);
        cli::require_one_line_error(
            cli::run_hsr("render " + file.string() + extra + " -o " + (dir / "refused.png").string(), file.stem().string(), 20),
            expected);
        CHECK_FALSE(fs::exists(dir / "refused.png"));
    };
    const std::string triangle = one_mesh("\"attributes\":{\"POSITION\":" + std::to_string(p) + "}");

    // Draco, required.
    std::string draco = g.json(triangle + ",\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
                                          "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"]");
    refuse(write("refusals/draco.gltf", draco), "KHR_draco_mesh_compression");

    // Buffers outside the model's folder: a path with .., an absolute path, a link leading out, a URL.
    std::ofstream(dir / "outside.bin", std::ios::binary) << g.bin;
    const auto external = [&](const std::string& uri) {
        std::string text = g.json(triangle, uri);
        return text;
    };
    refuse(write("refusals/inner/dotdot.gltf", external("../../outside.bin")), "'..' leads out");
    refuse(write("refusals/inner/absolute.gltf", external((dir / "outside.bin").string())), "not a relative path");
    fs::create_symlink(dir / "outside.bin", sub / "inner" / "link.bin");
    refuse(write("refusals/inner/link.gltf", external("link.bin")), "leads out of the model's folder");
    refuse(write("refusals/inner/http.gltf", external("http://example.com/x.bin")), "not URIs");
    REQUIRE(::mkfifo((sub / "inner" / "fifo.bin").c_str(), 0600) == 0);
    refuse(write("refusals/inner/fifo.gltf", external("fifo.bin")), "not a regular file");
    // A buffer beside the model is read.
    fs::copy_file(dir / "outside.bin", sub / "inner" / "beside.bin");
    const cli::Run beside = cli::run_hsr("render " + write("refusals/inner/beside.gltf", external("beside.bin")).string() +
                                             " --width 32 --height 32 -o " + (dir / "beside.png").string(),
                                         "beside");
    CHECK(beside.status == 0);

    // An accessor that claims far more elements than its buffer view holds, under the limits and over them.
    Gltf huge;
    const int small = huge.view(bytes_of(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
    const int claimed = huge.accessor("\"bufferView\":" + std::to_string(small) +
                                      ",\"componentType\":5126,\"count\":3000000000,\"type\":\"VEC3\"");
    const std::string huge_json = huge.json(one_mesh("\"attributes\":{\"POSITION\":" + std::to_string(claimed) + "}"));
    refuse(write("refusals/huge.gltf", huge_json), "over the limit");
    refuse(write("refusals/huge-raised.gltf", huge_json), "run past the end of buffer view",
           " --limit stored-triangles=4000000000 --limit model-bytes=100000000000");

    // A node graph with a cycle.
    refuse(write("refusals/cycle.gltf", g.json("\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" +
                                               std::to_string(p) + "}}]}],\"nodes\":[{\"children\":[1]},"
                                               "{\"mesh\":0,\"children\":[0]}],\"scenes\":[{\"nodes\":[0]}]")),
           "reached twice");

    // A GLB cut short, and a JSON nested without end.
    Gltf cut;
    const int cp = cut.floats({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const std::string glb = cut.glb(one_mesh("\"attributes\":{\"POSITION\":" + std::to_string(cp) + "}"));
    refuse(write("refusals/cut.glb", glb.substr(0, glb.size() / 2)), "claims");
    refuse(write("refusals/deep.gltf", std::string(100000, '[')), "nests deeper");
    // Points only.
    refuse(write("refusals/points.gltf", g.json(one_mesh("\"attributes\":{\"POSITION\":" + std::to_string(p) + "},\"mode\":0"))),
           "only points and lines");
}

TEST_CASE("glTF: a .scene file's mesh line adds every placed mesh as one object", "[gltf][scene]") {
    Gltf g;
    const int p = g.floats(unit_quad);
    const int i = g.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, 5123);
    write("placed.glb", g.glb("\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(p) +
                              "},\"indices\":" + std::to_string(i) + "}]}],\"nodes\":[{\"mesh\":0},{\"mesh\":0,"
                              "\"translation\":[0,0,-2]}],\"scenes\":[{\"nodes\":[0,1]}]"));
    const hsr::SceneData scene = load(write("placed.scene", "mesh placed.glb\n"));
    CHECK(scene.triangle_count() == 4);
    CHECK(scene.instances.empty());
    CHECK(scene.object_names.size() == 1);
    CHECK(scene.bounds_min == glm::vec3(0, 0, -2));
    CHECK(scene.bounds_max == glm::vec3(1, 1, 0));
}
