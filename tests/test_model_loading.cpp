// OBJ files read by hsr's own parser and mesh building against OpenMesh's OBJ reader, the
// independent answer: the same vertices in the same order, the same triangles, neighbours and
// non-manifold faces, for every model, every fuzz-corpus file and hand-written cases of number
// formats, relative indices, polygons, repeated corners and lines OpenMesh skips; and the same
// one-line refusals, for OFF and PLY too. OpenMesh cuts every polygon into a fan, hsr only a convex
// one (test_polygon_faces checks the others), so files with other polygons are compared only when
// they are refused.
#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/scene_builder.hpp"

#include "../framework/src/malformed_models.hpp"
#include "../framework/src/polygon_triangulation.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;
using Object = hsr::SceneBuilder::Object;

// What a load gives: the object, or the message it was refused with.
using Loaded = std::variant<Object, std::string>;

Loaded load_with_hsr(const fs::path& file) {
    try {
        hsr::SceneBuilder builder;
        builder.add_model_file(file);
        return builder.objects().at(0);
    } catch (const hsr::Error& e) {
        return std::string(e.what());
    }
}

// The file checked, then read by OpenMesh's own OBJ reader; the triangles walked as half-edges.
Loaded load_with_openmesh(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string cleaned;
    try {
        cleaned = hsr::obj_text_for_openmesh(file, text);
    } catch (const hsr::Error& e) {
        return std::string(e.what());
    }
    TriMesh mesh;
    mesh.request_face_status();
    std::istringstream stream(cleaned);
    OpenMesh::IO::Options options;
    std::ostringstream chatter;
    std::streambuf* saved = std::cerr.rdbuf(chatter.rdbuf());
    const bool read = OpenMesh::IO::read_mesh(mesh, stream, ".obj", options);
    omerr().flush();
    std::cerr.rdbuf(saved);
    REQUIRE(read);
    if (chatter.str().find("invalid vertex index") != std::string::npos)
        return file.string() + ": some faces refer to vertices that do not exist";
    Object object;
    for (TriMesh::VertexHandle v : mesh.vertices())
        object.positions.emplace_back(mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2]);
    for (TriMesh::FaceHandle f : mesh.faces()) {
        if (mesh.status(f).fixed_nonmanifold()) ++object.separated_faces;
        TriMesh::HalfedgeHandle h = mesh.halfedge_handle(f);
        for (int k = 0; k < 3; ++k, h = mesh.next_halfedge_handle(h)) {
            object.indices.push_back(static_cast<uint32_t>(mesh.from_vertex_handle(h).idx()));
            const TriMesh::HalfedgeHandle across = mesh.opposite_halfedge_handle(h);
            object.neighbors.push_back(mesh.is_boundary(across) ? -1 : mesh.face_handle(across).idx());
        }
    }
    if (object.indices.empty()) return file.string() + ": the model has no faces";
    return object;
}

// Whether hsr cuts the face (its corners, repeats left out) into the fan from its first corner.
bool cut_as_fan(const std::vector<glm::vec3>& corners) {
    if (corners.size() <= 3) return true;
    std::vector<uint32_t> triangles, fan;
    hsr::triangulate_face(corners, triangles);
    for (uint32_t k = 1; k + 1 < corners.size(); ++k) fan.insert(fan.end(), {0, k, k + 1});
    return triangles == fan;
}

// Whether a face's corners, a corner repeated right after itself left out, repeat one: OpenMesh
// leaves every repeat out, hsr keeps those (a keyhole's bridge), so such faces differ.
bool repeats_a_corner_later(std::vector<int32_t> corners) {
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    while (corners.size() > 1 && corners.front() == corners.back()) corners.pop_back();
    std::vector<int32_t> sorted = corners;
    std::sort(sorted.begin(), sorted.end());
    return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
}

// Whether hsr cuts every face of an OBJ text as OpenMesh does (true when the text is refused).
bool every_face_a_fan(const fs::path& file, const std::string& text) {
    hsr::ModelContents contents;
    try {
        contents = hsr::check_obj_text(file, text);
    } catch (const hsr::Error&) {
        return true;
    }
    uint32_t begin = 0;
    for (uint32_t end : contents.face_ends) {
        std::vector<int32_t> listed;
        std::vector<glm::vec3> corners;
        if (repeats_a_corner_later({contents.corners.begin() + begin, contents.corners.begin() + end})) return false;
        for (uint32_t c = begin; c < end; ++c) {
            const int32_t v = contents.corners[c];
            if (std::find(listed.begin(), listed.end(), v) != listed.end()) continue;
            listed.push_back(v);
            corners.emplace_back(contents.positions[v][0], contents.positions[v][1], contents.positions[v][2]);
        }
        begin = end;
        if (!cut_as_fan(corners)) return false;
    }
    return true;
}

void require_same_load(const fs::path& file) {
    INFO(file.string());
    const Loaded ours = load_with_hsr(file);
    const Loaded theirs = load_with_openmesh(file);
    if (const auto* message = std::get_if<std::string>(&theirs)) {
        REQUIRE(std::holds_alternative<std::string>(ours));
        CHECK(std::get<std::string>(ours) == *message);
        return;
    }
    std::ifstream in(file, std::ios::binary);
    if (!every_face_a_fan(file, std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>())))
        return;
    REQUIRE(std::holds_alternative<Object>(ours));
    const Object& a = std::get<Object>(ours);
    const Object& b = std::get<Object>(theirs);
    REQUIRE(a.positions.size() == b.positions.size());
    for (std::size_t v = 0; v < a.positions.size(); ++v)  // bit for bit: -0 and denormals too
        REQUIRE(std::memcmp(&a.positions[v], &b.positions[v], sizeof(glm::vec3)) == 0);
    CHECK(a.indices == b.indices);
    CHECK(a.neighbors == b.neighbors);
    CHECK(a.separated_faces == b.separated_faces);
}

// A scratch folder of each test process's own, removed at its end: ctest runs the cases side by side,
// and other checkouts' tests may run at the same time.
struct ScratchFolder {
    fs::path dir = fs::temp_directory_path() / fmt::format("hsr-test-model-loading-{}", ::getpid());
    ScratchFolder() { fs::create_directories(dir); }
    ~ScratchFolder() {
        std::error_code ignored;
        fs::remove_all(dir, ignored);
    }
};

fs::path write_file(const std::string& name, const std::string& text) {
    static const ScratchFolder scratch;
    const fs::path file = scratch.dir / name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
}

}  // namespace

TEST_CASE("OBJ: every model and fuzz-corpus file loads as OpenMesh's reader loads it", "[model-loading]") {
    std::vector<fs::path> files;
    for (const fs::path& dir : {fs::path(HSR_MODELS_DIR), fs::path(HSR_SOURCE_DIR) / "fuzz" / "corpus" / "obj",
                                fs::path(HSR_SOURCE_DIR) / "tests" / "data" / "bad"})
        for (const fs::directory_entry& e : fs::directory_iterator(dir))
            if (e.path().extension() == ".obj") files.push_back(e.path());
    REQUIRE(files.size() >= 20);
    for (const fs::path& file : files) require_same_load(file);
}

TEST_CASE("OBJ: number formats read to the same floats as OpenMesh's operator>>", "[model-loading]") {
    const std::vector<std::string> numbers = {
        "0", "-0", "+1.5", ".5", "5.", "-.25", "1e3", "1E+05", "2.5e-3", "0001.2500", "0.1", "0.3", "1e-38",
        "1e-40", "1.4e-45", "7e-46", "1e-50", "-1e-320", "3.40282347e+38", "-3.4028234e38",
        "16777217", "0.100000001490116119384765625", "1.00000005960464477539062500001",
        "123456789012345678901234567890", "0.000000000000000000000000000000000000011754943508"};
    std::string text;
    for (std::size_t i = 0; i + 2 < numbers.size(); ++i)
        text += fmt::format("v {} {} {}\n", numbers[i], numbers[i + 1], numbers[i + 2]);
    text += "v 1 1 1\nv 2 1 1\nv 1 2 1\nf -3 -2 -1\n";
    require_same_load(write_file("numbers.obj", text));
}

TEST_CASE("OBJ: polygons, relative and forward references, repeated corners, non-manifold edges",
          "[model-loading]") {
    const std::string grid =  // 3x3 vertices
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 0 2 0\nv 1 2 0\nv 2 2 0\n";
    require_same_load(write_file("quads.obj", grid + "f 1 2 5 4\nf 2 3 6 5\nf 4 5 8 7\nf 5/1 6/2/3 9//4 8\n"));
    require_same_load(write_file("pentagon.obj", grid + "f 1 2 3 6 5\nf 5 6 9 8 7 4\n"));
    require_same_load(write_file("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\n"));
    require_same_load(write_file("forward.obj", "f 1 2 3\nf 2 4 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"));
    require_same_load(write_file("repeated-corners.obj", grid + "f 1 2 2 5\nf 4 5 8 4\nf 2 3 3\nf 6 6 6 9 8\n"));
    require_same_load(write_file("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                                            "f 1 2 3\nf 2 1 4\nf 1 2 5\nf 2 1 5\nf 1 2 3\n"));
    require_same_load(write_file("fan-fails-last.obj", grid + "f 1 2 5\nf 1 2 5 4\nf 5 2 1 4\n"));
}

TEST_CASE("OBJ: random triangle soups and shuffled grids, non-manifold and re-linked, as OpenMesh adds them",
          "[model-loading]") {
    std::mt19937 random(18);
    for (int soup = 0; soup < 300; ++soup) {
        const int vertices = 4 + static_cast<int>(random() % 9);
        std::string text;
        std::vector<glm::vec3> positions;
        for (int v = 0; v < vertices; ++v) {
            positions.emplace_back(random() % 7, random() % 7, random() % 7);
            text += fmt::format("v {} {} {}\n", positions.back().x, positions.back().y, positions.back().z);
        }
        const int faces = 3 + static_cast<int>(random() % 40);
        for (int f = 0; f < faces; ++f) {
            const int corners = random() % 8 == 0 ? 4 : 3;
            std::vector<uint32_t> face;
            for (int c = 0; c < corners; ++c) face.push_back(random() % vertices);
            // A quad hsr does not cut into a fan loses its last corner (see the top of the file).
            std::vector<uint32_t> distinct;
            std::vector<glm::vec3> distinct_positions;
            for (uint32_t v : face)
                if (std::find(distinct.begin(), distinct.end(), v) == distinct.end()) {
                    distinct.push_back(v);
                    distinct_positions.push_back(positions[v]);
                }
            if (!cut_as_fan(distinct_positions)) face.pop_back();
            // A corner visited again later is kept by hsr, left out by OpenMesh: only the first visit.
            if (repeats_a_corner_later({face.begin(), face.end()})) face = distinct;
            text += "f";
            for (uint32_t v : face) text += fmt::format(" {}", 1 + v);
            text += "\n";
        }
        require_same_load(write_file(fmt::format("soup-{}.obj", soup), text));
    }
    // A grid's triangles in random order and orientation: faces meet their neighbours along every
    // kind of boundary (fans closing around a vertex, patches re-linked).
    for (int grid = 0; grid < 40; ++grid) {
        const int side = 3 + grid % 6;
        std::string text;
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) text += fmt::format("v {} {} 0\n", x, y);
        std::vector<std::array<int, 3>> triangles;
        for (int y = 0; y + 1 < side; ++y)
            for (int x = 0; x + 1 < side; ++x) {
                const int a = 1 + y * side + x, b = a + 1, c = a + side, d = c + 1;
                triangles.push_back({a, b, d});
                triangles.push_back({a, d, c});
            }
        std::shuffle(triangles.begin(), triangles.end(), random);
        for (std::array<int, 3> t : triangles) {
            if (random() % 5 == 0) std::swap(t[1], t[2]);
            text += fmt::format("f {} {} {}\n", t[0], t[1], t[2]);
        }
        require_same_load(write_file(fmt::format("grid-{}.obj", grid), text));
    }
}

TEST_CASE("OBJ: comments, keywords hsr does not use, byte-order mark, CRLF and lines OpenMesh skips",
          "[model-loading]") {
    require_same_load(write_file("keywords.obj",
                                 "\xEF\xBB\xBF# made by hand\r\nmtllib x.mtl\r\no thing\r\ng part\r\nusemtl red\r\n"
                                 "v 0 0 0 1 0 0 # red\r\nv 1 0 0 0 1 0\r\nv 0 1 0 0 0 1\r\nv 1 1 0\r\n"
                                 "vt 0.5\r\nvt 0 1\r\nvn 0 0 1\r\ns off\r\n"
                                 "f 1/1/1 2/2/1 3/1/1#c\r\n  f 2 4 3   # indented\r\n\t\r\n"));
    // A line that starts (after spaces) with a vertical tab or a form feed: OpenMesh's reader skips
    // it, so the vertices it counts differ from the checks' count.
    require_same_load(write_file("skipped-lines.obj", "v 0 0 0\nv 1 0 0\n \vv 5 5 5\nv 0 1 0\nv 1 1 0\n"
                                                      "f 1 2 3\n\ff 9 9 9\nf -3 -1 -2\n"));
    require_same_load(write_file("long-line.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0" + std::string(5'000'000, ' ') +
                                                  "7 8 9\nf 1" + std::string(1'000'000, '\t') + "2 3\n"));
    require_same_load(write_file("skipped-vertex-missing.obj", "v 0 0 0\nv 1 0 0\n\vv 0 1 0\nf 1 2 3\n"));
}

TEST_CASE("OBJ: refusals are one line naming the file and the line, before anything is built",
          "[model-loading]") {
    struct Case {
        const char* name;
        std::string text;
        const char* message;
    };
    const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    const std::vector<Case> cases = {
        {"out-of-range.obj", triangle + "f 1 2 4\n", ":4: vertex index 4 is out of range (the file has 3 vertices)"},
        {"huge-index.obj", triangle + "f 1 2 1099511627776\n",
         ":4: vertex index 1099511627776 is out of range (the file has 3 vertices)"},
        {"before-first.obj", triangle + "f 1 2 -4\n", ":4: vertex reference -4 goes before the first vertex"},
        {"zero.obj", triangle + "f 1 2 0\n", ":4: '0' is not a vertex reference"},
        {"nan.obj", "v 0 nan 0\n", ":1: vertex coordinate 'nan' is not a finite number"},
        {"overflow.obj", "v 0 1e39 0\n", ":1: vertex coordinate '1e39' is not a finite number"},
        {"two-signs.obj", "v 0 +-1 0\n", ":1: vertex coordinate '+-1' is not a number"},
        {"two-signs-index.obj", triangle + "f 1 2 +-1\n", ":4: '+-1' is not a vertex reference"},
        {"hex.obj", "v 0x10 0 0\n", ":1: vertex coordinate '0x10' is not a number"},
        {"short-face.obj", triangle + "f 1 2\n", ":4: a face needs at least 3 vertices"},
        {"no-faces.obj", triangle + "# nothing else\n", ": the model has no faces"},
        {"long-line-refused.obj", triangle + "f 1 2" + std::string(5'000'000, ' ') + "3 x\n",
         ":4: 'x' is not a vertex reference"},
    };
    for (const Case& c : cases) {
        const fs::path file = write_file(c.name, c.text);
        INFO(c.name);
        const Loaded loaded = load_with_hsr(file);
        REQUIRE(std::holds_alternative<std::string>(loaded));
        const std::string& message = std::get<std::string>(loaded);
        CHECK(message == file.string() + c.message);
        CHECK(message.find('\n') == std::string::npos);
        require_same_load(file);
    }
}

// The contents, or the refusal, of checking `text` in pieces of piece_bytes.
std::variant<hsr::ModelContents, std::string> check_in_pieces(const fs::path& file, const std::string& text,
                                                            std::size_t piece_bytes) {
    try {
        return hsr::check_obj_text(file, text, piece_bytes);
    } catch (const hsr::Error& e) {
        return std::string(e.what());
    }
}

TEST_CASE("OBJ: checked in pieces of any size, the contents or the first refusal are a whole check's",
          "[model-loading]") {
    std::vector<std::pair<fs::path, std::string>> files;
    for (const fs::path& dir : {fs::path(HSR_MODELS_DIR), fs::path(HSR_SOURCE_DIR) / "fuzz" / "corpus" / "obj",
                                fs::path(HSR_SOURCE_DIR) / "tests" / "data" / "bad"})
        for (const fs::directory_entry& e : fs::directory_iterator(dir))
            if (e.path().extension() == ".obj") {
                std::ifstream in(e.path(), std::ios::binary);
                files.emplace_back(e.path(), std::string(std::istreambuf_iterator<char>(in), {}));
            }
    // Each of these goes wrong, or counts differently, only late in the file, so that pieces after
    // the first must know what the lines before them held.
    const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    const std::vector<std::string> texts = {
        "\xEF\xBB\xBF" + triangle + "f 1 2 3\n" + triangle + "f -3 -2 -1\nf 1 5 -1\n",
        triangle + "f 1 2 3\n \vv 5 5 5\n\ff 9 9 9\nv 1 1 0\nf -3 -1 -2\n# c\n\n\tf 1 2 4 # quad\r\n",
        triangle + "f 1 2 3\n" + triangle + "f 1 2 7\n",                  // out of range, found at the end
        triangle + "f 1 2 3\n" + triangle + "f 1 2 3\nf 1 2 -7\n",      // before the first vertex
        triangle + "f 1 2 3\n" + triangle + "f 1 2 3\nf 1 2 -6\n",      // just not before it
        triangle + "f 1 2 3\n" + triangle + "f 1 2 x\nf 1 2 9\n",       // the first of two errors
        triangle + "f 1 2 3\n" + triangle + "f 9 2 3\nf 1 2 0\n",       // out of range, then a bad line
        triangle + "\vv 1 1 1\nf 1 2 3\nf 2 3 4\n",                      // a vertex OpenMesh does not have
        triangle + "f 1 2 3 1 2 3\nv 1 1 1\nf 1 2 3 4\nfx 1 2\nv# 2 2 2\nf#\nf 1 2 4",
        "mtllib a.mtl b.mtl\nusemtl a\n" + triangle + "f 1 2 3\nf 1 3 2\nusemtl b\nf 2 3 1\nmtllib c.mtl\nusemtl\nf 1 2 3\n",
    };
    for (std::size_t k = 0; k < texts.size(); ++k) files.emplace_back(fmt::format("case-{}.obj", k), texts[k]);
    for (const auto& [file, text] : files) {
        INFO(file.string());
        const auto whole = check_in_pieces(file, text, std::size_t(-1));
        if (const auto* message = std::get_if<std::string>(&whole)) {  // the refusal of the reference check
            try {
                hsr::obj_text_for_openmesh(file, text);
                FAIL("the reference check takes it");
            } catch (const hsr::Error& e) {
                CHECK(*message == e.what());
            }
        }
        for (std::size_t piece_bytes : {1, 2, 3, 17, 100, 4096}) {
            INFO("pieces of " << piece_bytes << " bytes");
            const auto pieces = check_in_pieces(file, text, piece_bytes);
            REQUIRE(pieces.index() == whole.index());
            if (const auto* message = std::get_if<std::string>(&whole)) {
                CHECK(std::get<std::string>(pieces) == *message);
                continue;
            }
            const hsr::ModelContents& a = std::get<hsr::ModelContents>(pieces);
            const hsr::ModelContents& b = std::get<hsr::ModelContents>(whole);
            REQUIRE(a.positions.size() == b.positions.size());
            CHECK((a.positions.empty() ||  // memcmp takes no null pointer, even for no bytes
                   std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof a.positions[0]) == 0));
            CHECK(a.corners == b.corners);
            CHECK(a.face_ends == b.face_ends);
            CHECK(a.material_libraries == b.material_libraries);
            REQUIRE(a.material_uses.size() == b.material_uses.size());
            for (std::size_t u = 0; u < a.material_uses.size(); ++u) {
                CHECK(a.material_uses[u].first_face == b.material_uses[u].first_face);
                CHECK(a.material_uses[u].name == b.material_uses[u].name);
            }
        }
    }
}

TEST_CASE("OBJ: the stored-triangles limit stops the check at the same line in pieces as whole",
          "[model-loading]") {
    std::string text;
    for (int k = 0; k < 50; ++k) text += fmt::format("v {} 0 0\nv {} 1 0\nv {} 0 1\nf -3 -2 -1\nf -1 -2 -3 -1\n", k, k, k);
    const hsr::Limits defaults = hsr::limits();
    hsr::Limits small = defaults;
    for (uint64_t limit : {uint64_t(1), uint64_t(2), uint64_t(37), uint64_t(149), uint64_t(150)}) {
        INFO("at most " << limit << " triangles");
        small.stored_triangles = limit;
        hsr::set_limits(small);
        const auto whole = check_in_pieces("limit.obj", text, std::size_t(-1));
        CHECK(std::holds_alternative<std::string>(whole) == (limit < 150));
        for (std::size_t piece_bytes : {1, 5, 64, 333}) {
            const auto pieces = check_in_pieces("limit.obj", text, piece_bytes);
            REQUIRE(pieces.index() == whole.index());
            if (const auto* message = std::get_if<std::string>(&whole)) CHECK(std::get<std::string>(pieces) == *message);
        }
    }
    hsr::set_limits(defaults);
}

TEST_CASE("OFF and PLY: a claim of 2^40 faces or a NaN is refused in one line, without a large allocation",
          "[model-loading]") {
    struct Case {
        const char* name;
        std::string text;
        const char* message;
    };
    const std::string ply_header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                   "property float z\n";
    const std::vector<Case> cases = {
        {"claims.off", "OFF\n3 1099511627776 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         ": ends early: the header promises 3 vertices and 1099511627776 faces"},
        {"claims.ply", ply_header + "element face 1099511627776\nproperty list uchar int vertex_indices\nend_header\n"
                                    "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         ": ends early while reading the 'face' elements"},
        {"nan.off", "OFF\n3 1\n0 nan 0\n1 0 0\n0 1 0\n3 0 1 2\n", ":3: vertex coordinate 'nan' is not a finite number"},
        {"nan.ply", ply_header + "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                 "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
         ":11: vertex 1 has a coordinate that is not a finite number"},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        const fs::path file = write_file(c.name, c.text);
        rusage before{};
        getrusage(RUSAGE_SELF, &before);
        const Loaded loaded = load_with_hsr(file);
        rusage after{};
        getrusage(RUSAGE_SELF, &after);
        REQUIRE(std::holds_alternative<std::string>(loaded));
        CHECK(std::get<std::string>(loaded) == file.string() + c.message);
        CHECK(after.ru_maxrss - before.ru_maxrss < 64 * 1024);  // kilobytes
    }
}
