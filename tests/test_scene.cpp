// Mesh loading, scene building and the .scene format, checked against answers known without the
// loader: the exact geometry of the hand-written models (cube, tetrahedron, octahedron, pyramid),
// analytic sphere normals, areas of polygons worked out by hand, bounds of transformed boxes
// computed with trigonometry, and bad files written here that must give one clear error.
#include "hsr/error.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"
#include "test_models.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path models_dir = HSR_MODELS_DIR;

// A fresh folder under the system temp folder, removed at the end of the test.
struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        std::random_device rd;
        path = fs::temp_directory_path() /
               ("hsr-test-scene-" + std::to_string(rd()) + "-" + std::to_string(counter++));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    fs::path write(const std::string& name, const std::string& content) const {
        fs::path file = path / name;
        fs::create_directories(file.parent_path());
        std::ofstream(file, std::ios::binary) << content;
        return file;
    }
};

// Runs f, which must throw hsr::Error, and returns the message; also checks nothing reached
// std::cerr meanwhile (the host prints a single line).
template <class F>
std::string error_of(F&& f) {
    std::ostringstream leaked;
    std::streambuf* saved = std::cerr.rdbuf(leaked.rdbuf());
    std::string message;
    bool threw = false;
    try {
        f();
    } catch (const hsr::Error& e) {
        message = e.what();
        threw = true;
    } catch (...) {
        std::cerr.rdbuf(saved);
        throw;
    }
    std::cerr.rdbuf(saved);
    CHECK(threw);
    CHECK(leaked.str().empty());
    CHECK(message.find('\n') == std::string::npos);
    return message;
}

glm::vec3 vec3_at(const std::vector<float>& a, std::size_t i) { return {a[3 * i], a[3 * i + 1], a[3 * i + 2]}; }
glm::vec3 position(const hsr::SceneData& s, uint32_t v) { return vec3_at(s.positions, v); }
glm::vec3 corner(const hsr::SceneData& s, uint32_t t, int k) { return position(s, s.indices[3 * t + k]); }
glm::vec3 face_normal(const hsr::SceneData& s, uint32_t t) { return vec3_at(s.face_normals, t); }
glm::vec3 corner_normal(const hsr::SceneData& s, uint32_t t, int k) { return vec3_at(s.corner_normals, 3 * t + k); }
glm::vec3 face_color(const hsr::SceneData& s, uint32_t t) { return vec3_at(s.face_colors, t); }

bool near(glm::vec3 a, glm::vec3 b, float eps = 1e-5f) { return glm::length(a - b) <= eps; }

// Array sizes agree, every number is finite, normals are unit.
void check_consistent(const hsr::SceneData& s) {
    const uint32_t n = s.triangle_count();
    REQUIRE(s.indices.size() == 3 * n);
    REQUIRE(s.face_normals.size() == 3 * n);
    REQUIRE(s.corner_normals.size() == 9 * n);
    REQUIRE(s.face_colors.size() == 3 * n);
    REQUIRE(s.edge_neighbors.size() == 3 * n);
    REQUIRE(s.face_object.size() == n);
    for (float v : s.positions) REQUIRE(std::isfinite(v));
    for (uint32_t i : s.indices) REQUIRE(i < s.vertex_count());
    for (uint32_t t = 0; t < n; ++t) {
        REQUIRE(std::fabs(glm::length(face_normal(s, t)) - 1.0f) < 1e-5f);
        for (int k = 0; k < 3; ++k) REQUIRE(std::fabs(glm::length(corner_normal(s, t, k)) - 1.0f) < 1e-5f);
        REQUIRE(s.face_object[t] < s.object_names.size());
    }
}

// The winding agrees with the stored face normal.
void check_winding(const hsr::SceneData& s) {
    for (uint32_t t = 0; t < s.triangle_count(); ++t) {
        glm::vec3 n = glm::normalize(glm::cross(corner(s, t, 1) - corner(s, t, 0), corner(s, t, 2) - corner(s, t, 0)));
        REQUIRE(near(n, face_normal(s, t), 1e-4f));
    }
}

// Every edge with a neighbour is matched by that neighbour's reversed edge pointing back.
// closed: every edge must have one.
void check_adjacency(const hsr::SceneData& s, bool closed) {
    for (uint32_t t = 0; t < s.triangle_count(); ++t) {
        for (int i = 0; i < 3; ++i) {
            const int32_t u = s.edge_neighbors[3 * t + i];
            if (closed) REQUIRE(u != HSR_NO_NEIGHBOR);
            if (u == HSR_NO_NEIGHBOR) continue;
            REQUIRE(u >= 0);
            REQUIRE(static_cast<uint32_t>(u) < s.triangle_count());
            REQUIRE(static_cast<uint32_t>(u) != t);
            const uint32_t a = s.indices[3 * t + i], b = s.indices[3 * t + (i + 1) % 3];
            int back = -1;
            for (int j = 0; j < 3; ++j)
                if (s.indices[3 * u + j] == b && s.indices[3 * u + (j + 1) % 3] == a) back = j;
            REQUIRE(back >= 0);
            REQUIRE(s.edge_neighbors[3 * u + back] == static_cast<int32_t>(t));
        }
    }
}

double triangle_area(const hsr::SceneData& s, uint32_t t) {
    return 0.5 * glm::length(glm::cross(glm::dvec3(corner(s, t, 1) - corner(s, t, 0)),
                                        glm::dvec3(corner(s, t, 2) - corner(s, t, 0))));
}

// Octahedron subdivided `levels` times onto the unit sphere, vertices shared.
void unit_sphere(int levels, std::vector<glm::vec3>& positions, std::vector<uint32_t>& indices) {
    positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    indices = {0, 2, 4, 1, 4, 2, 0, 4, 3, 0, 5, 2, 1, 3, 4, 1, 2, 5, 0, 3, 5, 1, 5, 3};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
        auto mid = [&](uint32_t a, uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            positions.push_back(glm::normalize(positions[a] + positions[b]));
            return midpoint[key] = static_cast<uint32_t>(positions.size() - 1);
        };
        std::vector<uint32_t> next;
        for (std::size_t t = 0; t < indices.size(); t += 3) {
            uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
            uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            next.insert(next.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
        }
        indices = std::move(next);
    }
}

}  // namespace

TEST_CASE("cube.obj loads as 8 shared vertices and 12 triangles with exact outward normals", "[scene][mesh]") {
    const hsr::SceneData s = hsr::load_model(models_dir / "cube.obj");
    check_consistent(s);
    CHECK(s.vertex_count() == 8);
    REQUIRE(s.triangle_count() == 12);
    REQUIRE(s.object_names == std::vector<std::string>{"cube"});
    CHECK(s.bounds_min == glm::vec3(-1.0f));
    CHECK(s.bounds_max == glm::vec3(1.0f));
    std::map<std::tuple<float, float, float>, int> normals;
    for (uint32_t t = 0; t < 12; ++t) {
        const glm::vec3 n = face_normal(s, t);
        // An exact axis vector...
        CHECK(std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z) == 1.0f);
        // ...pointing out of the cube: every corner of the triangle lies on the face plane n.p = 1.
        for (int k = 0; k < 3; ++k) CHECK(glm::dot(n, corner(s, t, k)) == 1.0f);
        ++normals[{n.x, n.y, n.z}];
        CHECK(face_color(s, t) == glm::vec3(0.8f));
        CHECK(s.face_object[t] == 0);
    }
    CHECK(normals.size() == 6);
    for (auto& [n, count] : normals) CHECK(count == 2);
    check_winding(s);
    check_adjacency(s, true);
}

TEST_CASE("every format: closed hand-written models have mutual neighbours on every edge", "[scene][mesh]") {
    struct Model {
        const char* file;
        uint32_t vertices, triangles;
        double area;  // total surface area worked out by hand
    };
    const double tetra_edge = 2.0 * std::sqrt(2.0);
    const Model models[] = {
        {"cube.obj", 8, 12, 24.0},
        {"tetrahedron.off", 4, 4, 4.0 * std::sqrt(3.0) / 4.0 * tetra_edge * tetra_edge},
        {"octahedron.ply", 6, 8, 8.0 * std::sqrt(3.0) / 4.0 * 2.0},        // edge sqrt(2)
        {"pyramid.stl", 5, 6, 4.0 + 4.0 * 0.5 * 2.0 * std::sqrt(1.0 + 2.25)},  // base 2x2, slant height sqrt(1 + 1.5^2)
    };
    for (const Model& m : models) {
        INFO(m.file);
        const hsr::SceneData s = hsr::load_model(models_dir / m.file);
        check_consistent(s);
        CHECK(s.vertex_count() == m.vertices);
        CHECK(s.triangle_count() == m.triangles);
        double area = 0;
        for (uint32_t t = 0; t < s.triangle_count(); ++t) area += triangle_area(s, t);
        CHECK(area == Approx(m.area).epsilon(1e-6));
        check_winding(s);
        check_adjacency(s, true);
        // Outward: the centroid of the shape is the origin for the cube, tetrahedron and
        // octahedron and (0, 0.375, 0) for the pyramid; every face normal points away from it.
        const glm::vec3 inside = std::string(m.file) == "pyramid.stl" ? glm::vec3(0, 0.375f, 0) : glm::vec3(0);
        for (uint32_t t = 0; t < s.triangle_count(); ++t)
            CHECK(glm::dot(face_normal(s, t), corner(s, t, 0) - inside) > 0.0f);
        CHECK(s.warnings.empty());
    }
}

TEST_CASE("corner normals keep creases and smooth the rest", "[scene][normals]") {
    SECTION("cube at the default 40 degrees: every corner normal is its face normal") {
        const hsr::SceneData s = hsr::load_model(models_dir / "cube.obj");
        for (uint32_t t = 0; t < s.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k) CHECK(near(corner_normal(s, t, k), face_normal(s, t), 1e-6f));
    }
    SECTION("cube smoothed everywhere: angle weighting gives the diagonal at every corner") {
        // Each cube corner gets 90 degrees of angle from each of its three faces however they are
        // split into triangles, so the normal is (+-1, +-1, +-1) / sqrt(3), pointing like the corner.
        hsr::MeshOptions options;
        options.crease_angle_degrees = 180.0f;
        const hsr::SceneData s = hsr::load_model(models_dir / "cube.obj", options);
        for (uint32_t t = 0; t < s.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k) CHECK(near(corner_normal(s, t, k), glm::normalize(corner(s, t, k)), 1e-5f));
    }
    SECTION("a finely subdivided sphere has corner normals close to the radial direction") {
        std::vector<glm::vec3> positions;
        std::vector<uint32_t> indices;
        unit_sphere(4, positions, indices);
        hsr::SceneBuilder builder;
        builder.add_triangles(positions, indices);
        const hsr::SceneData s = builder.build();
        check_consistent(s);
        REQUIRE(s.triangle_count() == 8 * 256);
        check_adjacency(s, true);
        double worst = 1.0;
        for (uint32_t t = 0; t < s.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k)
                worst = std::min(worst, double(glm::dot(corner_normal(s, t, k), glm::normalize(corner(s, t, k)))));
        CHECK(worst > std::cos(glm::radians(1.0)));
    }
    SECTION("crease 0 gives flat facets") {
        std::vector<glm::vec3> positions;
        std::vector<uint32_t> indices;
        unit_sphere(2, positions, indices);
        hsr::SceneBuilder builder;
        hsr::MeshOptions options;
        options.crease_angle_degrees = 0.0f;
        builder.add_triangles(positions, indices, options);
        const hsr::SceneData s = builder.build();
        for (uint32_t t = 0; t < s.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k) CHECK(near(corner_normal(s, t, k), face_normal(s, t), 1e-6f));
    }
}

TEST_CASE("the bunny loads with 69,666 triangles and smooth, mutual, finite data", "[scene][mesh][bunny]") {
    const fs::path bunny = test_models::path("bunny.obj");
    const hsr::SceneData s = hsr::load_model(bunny);
    check_consistent(s);
    REQUIRE(s.triangle_count() == 69666);
    check_winding(s);
    check_adjacency(s, false);
    // Brute force over all triangles for a sample of corners: the angle-weighted average of the
    // normals of the triangles that share the corner's vertex and lie within 40 degrees of its face.
    std::mt19937 random(7);
    std::uniform_int_distribution<uint32_t> pick(0, s.triangle_count() - 1);
    const double limit = std::cos(glm::radians(40.0));
    for (int sample = 0; sample < 40; ++sample) {
        const uint32_t t = pick(random);
        const int k = sample % 3;
        const uint32_t v = s.indices[3 * t + k];
        const glm::dvec3 own(face_normal(s, t));
        glm::dvec3 sum(0.0);
        for (uint32_t u = 0; u < s.triangle_count(); ++u) {
            for (int j = 0; j < 3; ++j) {
                if (s.indices[3 * u + j] != v) continue;
                const glm::dvec3 p(corner(s, u, j)), a(corner(s, u, (j + 1) % 3)), b(corner(s, u, (j + 2) % 3));
                const glm::dvec3 n = glm::normalize(glm::cross(a - p, b - p));
                if (glm::dot(n, own) < limit - 1e-6) continue;
                const double angle = std::acos(std::clamp(glm::dot(glm::normalize(a - p), glm::normalize(b - p)), -1.0, 1.0));
                sum += angle * n;
            }
        }
        INFO("triangle " << t << " corner " << k);
        CHECK(near(corner_normal(s, t, k), glm::vec3(glm::normalize(sum)), 1e-4f));
    }
}

TEST_CASE("Suzanne loads when fetched", "[scene][mesh]") {
    const fs::path monkey = test_models::path("monkey.obj");
    // Triangles counted from the file itself: every face line has three corners.
    std::ifstream in(monkey);
    std::string line;
    uint32_t faces = 0;
    while (std::getline(in, line)) faces += line.rfind("f ", 0) == 0;
    const hsr::SceneData s = hsr::load_model(monkey);
    check_consistent(s);
    CHECK(s.triangle_count() == faces);
    check_winding(s);
    check_adjacency(s, false);
}

namespace {

template <class T>
void put(std::string& out, T value, bool big_endian) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (big_endian) std::reverse(bytes, bytes + sizeof(T));
    out.append(bytes, sizeof(T));
}

// The octahedron of models/octahedron.ply as a binary PLY; `bad_index` replaces the last index.
std::string binary_octahedron(bool big_endian, int32_t bad_index = -1) {
    const float v[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const int32_t f[8][3] = {{0, 2, 4}, {1, 4, 2}, {0, 4, 3}, {0, 5, 2}, {1, 3, 4}, {1, 2, 5}, {0, 3, 5}, {1, 5, 3}};
    std::string out = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 8\nproperty list uchar int vertex_indices\nend_header\n";
    for (auto& p : v)
        for (float c : p) put(out, c, big_endian);
    for (int t = 0; t < 8; ++t) {
        put(out, uint8_t{3}, big_endian);
        for (int k = 0; k < 3; ++k) put(out, t == 7 && k == 2 && bad_index >= 0 ? bad_index : f[t][k], big_endian);
    }
    return out;
}

// Appends `value` as the PLY scalar type `type`, little endian.
void put_as(std::string& out, std::string_view type, double value) {
    if (type == "char" || type == "int8") return put(out, static_cast<int8_t>(value), false);
    if (type == "uchar" || type == "uint8") return put(out, static_cast<uint8_t>(value), false);
    if (type == "short" || type == "int16") return put(out, static_cast<int16_t>(value), false);
    if (type == "ushort" || type == "uint16") return put(out, static_cast<uint16_t>(value), false);
    if (type == "int" || type == "int32") return put(out, static_cast<int32_t>(value), false);
    if (type == "uint" || type == "uint32") return put(out, static_cast<uint32_t>(value), false);
    if (type == "float" || type == "float32") return put(out, static_cast<float>(value), false);
    put(out, value, false);
}

// The octahedron of binary_octahedron moved by (1, 1, 1) so that every corner is a whole number
// >= 0, written with the given types for the coordinates, the list count and the indices, and with
// properties hsr does not use in between (a double colour, an int16 normal component, a list of
// texture coordinates on each face).
std::string typed_octahedron(std::string_view coordinate, std::string_view count, std::string_view index) {
    const int v[6][3] = {{2, 1, 1}, {0, 1, 1}, {1, 2, 1}, {1, 0, 1}, {1, 1, 2}, {1, 1, 0}};
    const int f[8][3] = {{0, 2, 4}, {1, 4, 2}, {0, 4, 3}, {0, 5, 2}, {1, 3, 4}, {1, 2, 5}, {0, 3, 5}, {1, 5, 3}};
    std::string out = fmt::format(
        "ply\nformat binary_little_endian 1.0\nelement vertex 6\nproperty {0} x\nproperty double red\n"
        "property {0} y\nproperty int16 nx\nproperty {0} z\nelement face 8\nproperty list {1} float texcoord\n"
        "property list {1} {2} vertex_indices\nproperty uint16 flags\nend_header\n",
        coordinate, count, index);
    for (auto& p : v) {
        put_as(out, coordinate, p[0]);
        put_as(out, "double", 0.5);
        put_as(out, coordinate, p[1]);
        put_as(out, "int16", -1);
        put_as(out, coordinate, p[2]);
    }
    for (auto& corners : f) {
        put_as(out, count, 2);
        put_as(out, "float", 0.25);
        put_as(out, "float", 0.75);
        put_as(out, count, 3);
        for (int c : corners) put_as(out, index, c);
        put_as(out, "uint16", 7);
    }
    return out;
}

}  // namespace

TEST_CASE("binary PLY in both byte orders and binary STL", "[scene][mesh]") {
    TempDir dir;
    for (bool big : {false, true}) {
        INFO("big endian " << big);
        const hsr::SceneData s = hsr::load_model(dir.write(big ? "be.ply" : "le.ply", binary_octahedron(big)));
        check_consistent(s);
        CHECK(s.vertex_count() == 6);
        CHECK(s.triangle_count() == 8);
        check_adjacency(s, true);
        for (uint32_t t = 0; t < 8; ++t) {  // outward: each face normal is (+-1, +-1, +-1) / sqrt(3)
            const glm::vec3 c = (corner(s, t, 0) + corner(s, t, 1) + corner(s, t, 2)) / 3.0f;
            CHECK(near(face_normal(s, t), glm::normalize(c)));
        }
    }
    using Catch::Contains;
    CHECK_THAT(error_of([&] { hsr::load_model(dir.write("bad.ply", binary_octahedron(false, 6))); }),
               Contains("bad.ply") && Contains("vertex index 6 is out of range"));
    const std::string whole = binary_octahedron(true);
    CHECK_THAT(error_of([&] { hsr::load_model(dir.write("short.ply", whole.substr(0, whole.size() - 5))); }),
               Contains("short.ply") && Contains("ends early"));
    CHECK_THAT(error_of([&] { hsr::load_model(dir.write("binary.off", std::string("OFF BINARY\n") + std::string(12, '\0'))); }),
               Contains("binary.off:1:") && Contains("not supported"));
    CHECK_THAT(error_of([&] { hsr::load_model(dir.write("version.ply", "ply\nformat ascii 2.0\nend_header\n")); }),
               Contains("version.ply:2:"));

    // The pyramid as a binary STL: 6 facets of 12 floats and 2 attribute bytes.
    const float facets[6][9] = {{-1, 0, 1, 1, 0, 1, 0, 1.5f, 0},   {1, 0, 1, 1, 0, -1, 0, 1.5f, 0},
                                {1, 0, -1, -1, 0, -1, 0, 1.5f, 0}, {-1, 0, -1, -1, 0, 1, 0, 1.5f, 0},
                                {-1, 0, -1, 1, 0, -1, 1, 0, 1},    {-1, 0, -1, 1, 0, 1, -1, 0, 1}};
    std::string stl = "solid but really binary" + std::string(57, ' ');
    put(stl, uint32_t{6}, false);
    for (auto& facet : facets) {
        for (int k = 0; k < 3; ++k) put(stl, 0.0f, false);
        for (float c : facet) put(stl, c, false);
        put(stl, uint16_t{0}, false);
    }
    const hsr::SceneData s = hsr::load_model(dir.write("pyramid.stl", stl));
    check_consistent(s);
    CHECK(s.vertex_count() == 5);
    CHECK(s.triangle_count() == 6);
    check_adjacency(s, true);
}

TEST_CASE("binary PLY reads the same mesh whatever the types of its properties", "[scene][mesh]") {
    // OpenMesh's own binary reader converts only some types and reads the rest of the file out of
    // step after one it does not: hsr hands it positions and faces in a single layout.
    TempDir dir;
    const std::vector<std::string> integers = {"char", "uchar", "short", "ushort", "int", "uint",
                                               "int8", "uint8", "int16", "uint16", "int32", "uint32"};
    std::vector<std::string> scalars = integers;
    for (const char* real : {"float", "double", "float32", "float64"}) scalars.emplace_back(real);
    const hsr::SceneData reference = hsr::load_model(dir.write("reference.ply", typed_octahedron("float", "uchar", "int")));
    auto check_same = [&](const std::string& coordinate, const std::string& count, const std::string& index) {
        INFO("coordinates " << coordinate << ", list count " << count << ", indices " << index);
        const hsr::SceneData s = hsr::load_model(dir.write("typed.ply", typed_octahedron(coordinate, count, index)));
        check_consistent(s);
        REQUIRE(s.vertex_count() == 6);
        REQUIRE(s.triangle_count() == 8);
        check_adjacency(s, true);
        for (uint32_t t = 0; t < 8; ++t)
            for (int k = 0; k < 3; ++k) CHECK(corner(s, t, k) == corner(reference, t, k));
    };
    for (const std::string& coordinate : scalars) check_same(coordinate, "uchar", "int");
    for (const std::string& count : integers)
        for (const std::string& index : integers) check_same("float", count, index);
    // The reference itself against the float octahedron centred on the origin (models are centred
    // and scaled to a unit size on loading).
    const hsr::SceneData centred = hsr::load_model(dir.write("centred.ply", binary_octahedron(false)));
    for (uint32_t t = 0; t < 8; ++t)
        for (int k = 0; k < 3; ++k) CHECK(corner(reference, t, k) - glm::vec3(1) == corner(centred, t, k));

    using Catch::Contains;
    const std::string two_faces = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                                  "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                                  "element face 0\nend_header\n";
    CHECK_THAT(error_of([&] { hsr::load_model(dir.write("two.ply", two_faces)); }),
               Contains("two.ply") && Contains("two 'face' elements"));
    const std::string no_z = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                             "end_header\n0 0\n";
    CHECK_THAT(error_of([&] { hsr::load_model(dir.write("no-z.ply", no_z)); }),
               Contains("no-z.ply") && Contains("no z property"));
}

TEST_CASE("bad model files give one clear line naming the file", "[scene][errors]") {
    TempDir dir;
    auto load = [](const fs::path& file) { return [file] { hsr::load_model(file); }; };
    using Catch::Contains;

    SECTION("missing file") {
        const fs::path file = dir.path / "nothing-here.obj";
        const std::string m = error_of(load(file));
        CHECK_THAT(m, Contains(file.string()) && Contains("no such file"));
    }
    SECTION("unsupported extension") {
        const fs::path file = dir.write("points.xyz", "1 2 3\n");
        CHECK_THAT(error_of(load(file)), Contains("points.xyz") && Contains("unsupported"));
    }
    SECTION("garbage OFF") {
        const fs::path file = dir.write("garbage.off", "hello world\nthis is not a mesh\n");
        CHECK_THAT(error_of(load(file)), Contains("garbage.off:1:") && Contains("not an OFF file"));
    }
    SECTION("garbage OBJ has no faces") {
        const fs::path file = dir.write("garbage.obj", "hello world\nthis is not a mesh\n");
        CHECK_THAT(error_of(load(file)), Contains("garbage.obj") && Contains("no faces"));
    }
    SECTION("random bytes") {
        std::string bytes(300, '\0');
        std::mt19937 random(3);
        for (char& c : bytes) c = static_cast<char>(random());
        for (const char* name : {"random.obj", "random.off", "random.ply", "random.stl"}) {
            INFO(name);
            CHECK_THAT(error_of(load(dir.write(name, bytes))), Contains(name));
        }
    }
    SECTION("empty meshes") {
        CHECK_THAT(error_of(load(dir.write("empty.off", "OFF\n0 0 0\n"))), Contains("empty.off") && Contains("no faces"));
        CHECK_THAT(error_of(load(dir.write("empty.obj", ""))), Contains("empty.obj") && Contains("no faces"));
        CHECK_THAT(error_of(load(dir.write("points.obj", "v 0 0 0\nv 1 0 0\n"))), Contains("no faces"));
    }
    SECTION("NaN and infinite coordinates") {
        CHECK_THAT(error_of(load(dir.write("nan.off", "OFF\n3 1 0\n0 0 0\nnan 1 0\n0 1 0\n3 0 1 2\n"))),
                   Contains("nan.off:4:") && Contains("not a finite number"));
        CHECK_THAT(error_of(load(dir.write("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n"))),
                   Contains("inf.obj:3:") && Contains("not a finite number"));
        CHECK_THAT(error_of(load(dir.write("huge.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n"))),
                   Contains("huge.obj:2:") && Contains("not a finite number"));
        const std::string ply_header =
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
        CHECK_THAT(error_of(load(dir.write("nan.ply", ply_header + "0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n"))),
                   Contains("nan.ply:11:") && Contains("not a finite number"));
        CHECK_THAT(error_of(load(dir.write("nan.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                                      "vertex 1 0 0\nvertex 0 1 nan\nendloop\nendfacet\nendsolid s\n"))),
                   Contains("nan.stl:6:") && Contains("not a finite number"));
    }
    SECTION("NaN in a binary STL") {
        std::string bytes(80, ' ');
        const uint32_t count = 1;
        bytes.append(reinterpret_cast<const char*>(&count), 4);
        const float nan = std::nanf("");
        const float facet[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, nan, 0};
        bytes.append(reinterpret_cast<const char*>(facet), sizeof facet);
        bytes.append(2, '\0');
        CHECK_THAT(error_of(load(dir.write("nan-binary.stl", bytes))),
                   Contains("nan-binary.stl") && Contains("not a finite number"));
        CHECK_THAT(error_of(load(dir.write("short-binary.stl", bytes.substr(0, 100)))),
                   Contains("short-binary.stl") && Contains("truncated"));
    }
    SECTION("indices out of range") {
        CHECK_THAT(error_of(load(dir.write("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n"))),
                   Contains("range.off:6:") && Contains("out of range"));
        CHECK_THAT(error_of(load(dir.write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"))),
                   Contains("range.obj:4:") && Contains("out of range"));
        CHECK_THAT(error_of(load(dir.write("negative.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n"))),
                   Contains("negative.obj:3:"));
        const std::string ply_header =
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
        CHECK_THAT(error_of(load(dir.write("range.ply", ply_header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"))),
                   Contains("range.ply:13:") && Contains("out of range"));
    }
    SECTION("inputs that make OpenMesh's readers spin are refused") {
        CHECK_THAT(error_of(load(dir.write("no-end.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"))),
                   Contains("no-end.ply") && Contains("end_header"));
        CHECK_THAT(error_of(load(dir.write("many-corners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n999999999 0 1 2\n"))),
                   Contains("many-corners.off:6:"));
        CHECK_THAT(error_of(load(dir.write("short.off", "OFF\n3 5 0\n0 0 0\n1 0 0\n"))), Contains("short.off") && Contains("ends early"));
        CHECK_THAT(error_of(load(dir.write("bad-type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty blob x\nend_header\n0\n"))),
                   Contains("bad-type.ply:4:"));
    }
    SECTION("a folder is not a model") {
        fs::create_directories(dir.path / "folder.obj");
        CHECK_THAT(error_of(load(dir.path / "folder.obj")), Contains("folder.obj") && Contains("is a folder, not a model file"));
    }
}

TEST_CASE("zero-area and non-manifold triangles never produce NaN", "[scene][mesh]") {
    SECTION("a degenerate triangle is dropped with a warning") {
        const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}};
        const std::vector<uint32_t> i = {0, 1, 2, 1, 0, 3, 1, 3, 4};  // last two collinear
        hsr::SceneBuilder builder;
        builder.add_triangles(p, i);
        const hsr::SceneData s = builder.build();
        check_consistent(s);
        CHECK(s.triangle_count() == 1);
        CHECK(s.vertex_count() == 3);  // vertices used only by dropped triangles are gone
        REQUIRE(s.warnings.size() == 1);
        CHECK_THAT(s.warnings[0], Catch::Contains("2 triangles without area"));
        CHECK(near(face_normal(s, 0), {0, 0, 1}));
    }
    SECTION("a triangle repeated, from any corner, is dropped with a warning; its back face stays") {
        // Vertices 3..5 are copies of 0..2 (as the loader makes for non-manifold faces).
        const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        const std::vector<uint32_t> i = {0, 1, 2, 1, 2, 0, 3, 4, 5, 5, 3, 4, 0, 2, 1};  // last: the back face
        hsr::SceneBuilder builder;
        builder.add_triangles(p, i);
        const hsr::SceneData s = builder.build();
        check_consistent(s);
        REQUIRE(s.triangle_count() == 2);
        CHECK(near(face_normal(s, 0), {0, 0, 1}));
        CHECK(near(face_normal(s, 1), {0, 0, -1}));
        // Besides the loader's warning about the copies it gave their own vertices.
        CHECK(std::count_if(s.warnings.begin(), s.warnings.end(), [](const std::string& w) {
                  return w.find("3 triangles repeating an earlier one dropped") != std::string::npos;
              }) == 1);
    }
    SECTION("a triangle repeating a vertex and a scene of only degenerate triangles") {
        const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
        hsr::SceneBuilder builder;
        builder.add_triangles(p, std::vector<uint32_t>{0, 1, 2, 0, 0, 1});
        CHECK_THAT(error_of([&] { builder.build(); }), Catch::Contains("no triangles"));
    }
    SECTION("three triangles on one edge: all kept, adjacency stays mutual") {
        const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0}, {0.5f, 0, 1}};
        const std::vector<uint32_t> i = {0, 1, 2, 1, 0, 3, 0, 1, 4};
        hsr::SceneBuilder builder;
        builder.add_triangles(p, i);
        const hsr::SceneData s = builder.build();
        check_consistent(s);
        CHECK(s.triangle_count() == 3);
        check_winding(s);
        check_adjacency(s, false);
        CHECK_FALSE(s.warnings.empty());
    }
    SECTION("an OFF face repeating a vertex is dropped, the rest loads") {
        TempDir dir;
        const hsr::SceneData s = hsr::load_model(
            dir.write("repeat.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 1 3\n"));
        check_consistent(s);
        CHECK(s.triangle_count() == 1);
    }
}

TEST_CASE("transforms move positions and normals, and mirrors keep the front outside", "[scene][transform]") {
    const fs::path cube = models_dir / "cube.obj";
    SECTION("translate") {
        hsr::MeshOptions options;
        options.transform = glm::translate(glm::mat4(1.0f), glm::vec3(5, 0, 0));
        const hsr::SceneData s = hsr::load_model(cube, options);
        CHECK(s.bounds_min == glm::vec3(4, -1, -1));
        CHECK(s.bounds_max == glm::vec3(6, 1, 1));
    }
    SECTION("non-uniform scale and rotation: normals follow the inverse transpose") {
        // Shear-free but non-uniform: the cube becomes a 4 x 2 x 2 box rotated 90 degrees about z,
        // so its +x face (normal +x) ends up facing +y.
        hsr::MeshOptions options;
        options.transform = glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 0, 1)) *
                            glm::scale(glm::mat4(1.0f), glm::vec3(2, 1, 1));
        const hsr::SceneData s = hsr::load_model(cube, options);
        CHECK(near(s.bounds_min, {-1, -2, -1}));
        CHECK(near(s.bounds_max, {1, 2, 1}));
        for (uint32_t t = 0; t < s.triangle_count(); ++t)
            CHECK(std::fabs(glm::dot(face_normal(s, t), corner(s, t, 0))) ==
                  Approx(std::fabs(face_normal(s, t).y) > 0.5f ? 2.0 : 1.0).margin(1e-5));
        check_winding(s);
    }
    SECTION("a sheared box gets normals perpendicular to its faces") {
        hsr::MeshOptions options;
        glm::mat4 shear(1.0f);
        shear[1][0] = 0.7f;  // x += 0.7 y
        options.transform = shear;
        const hsr::SceneData s = hsr::load_model(cube, options);
        check_winding(s);
        for (uint32_t t = 0; t < s.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k)  // every edge of the triangle is perpendicular to its normal
                CHECK(std::fabs(glm::dot(face_normal(s, t), corner(s, t, (k + 1) % 3) - corner(s, t, k))) < 1e-5f);
    }
    SECTION("mirror") {
        hsr::MeshOptions options;
        options.transform = glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1));
        const hsr::SceneData s = hsr::load_model(models_dir / "tetrahedron.off", options);
        check_consistent(s);
        check_winding(s);
        check_adjacency(s, true);
        for (uint32_t t = 0; t < s.triangle_count(); ++t) CHECK(glm::dot(face_normal(s, t), corner(s, t, 0)) > 0.0f);
    }
}

TEST_CASE("several objects merge into one scene with offsets, names and colours", "[scene][merge]") {
    hsr::SceneBuilder builder;
    hsr::MeshOptions red;
    red.color = {1, 0, 0};
    builder.add_model_file(models_dir / "cube.obj", red);
    hsr::MeshOptions blue;
    blue.color = {0, 0, 1};
    blue.name = "tetra";
    blue.transform = glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0));
    builder.add_model_file(models_dir / "tetrahedron.off", blue);
    const hsr::SceneData s = builder.build();
    check_consistent(s);
    REQUIRE(s.triangle_count() == 16);
    CHECK(s.vertex_count() == 12);
    CHECK(s.object_names == std::vector<std::string>{"cube", "tetra"});
    for (uint32_t t = 0; t < 16; ++t) {
        const uint32_t object = t < 12 ? 0 : 1;
        CHECK(s.face_object[t] == object);
        CHECK(face_color(s, t) == (object == 0 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1)));
        for (int i = 0; i < 3; ++i) {
            const int32_t u = s.edge_neighbors[3 * t + i];
            CHECK((object == 0 ? (u >= 0 && u < 12) : (u >= 12 && u < 16)));
            CHECK((object == 0 ? s.indices[3 * t + i] < 8 : s.indices[3 * t + i] >= 8));
        }
    }
    check_adjacency(s, true);
    CHECK(s.bounds_min == glm::vec3(-1, -1, -1));
    CHECK(s.bounds_max == glm::vec3(11, 1, 1));

    const hsr_scene v = s.view();
    CHECK(v.struct_size == sizeof(hsr_scene));
    CHECK(v.vertex_count == 12);
    CHECK(v.triangle_count == 16);
    CHECK(v.object_count == 2);
    CHECK(v.positions == s.positions.data());
    CHECK(v.indices == s.indices.data());
    CHECK(v.face_normals == s.face_normals.data());
    CHECK(v.corner_normals == s.corner_normals.data());
    CHECK(v.face_colors == s.face_colors.data());
    CHECK(v.edge_neighbors == s.edge_neighbors.data());
    CHECK(v.face_object == s.face_object.data());
    CHECK(v.bounds_max[0] == 11.0f);
    CHECK(v.bounds_min[2] == -1.0f);

    CHECK_THAT(error_of([] { hsr::SceneBuilder().build(); }), Catch::Contains("no triangles"));
}

TEST_CASE("polygons are triangulated in their plane, concave ones too", "[scene][polygon]") {
    SECTION("an L shape: area 3, four triangles inside it, shared diagonals") {
        // 2 x 2 square minus its top right unit square, in the plane z = 5, counter-clockwise.
        const std::vector<glm::vec3> l = {{0, 0, 5}, {2, 0, 5}, {2, 1, 5}, {1, 1, 5}, {1, 2, 5}, {0, 2, 5}};
        hsr::SceneBuilder builder;
        builder.add_polygon(l, {0.2f, 0.4f, 0.6f}, "ell");
        const hsr::SceneData s = builder.build();
        check_consistent(s);
        REQUIRE(s.triangle_count() == 4);
        CHECK(s.object_names == std::vector<std::string>{"ell"});
        double area = 0;
        int shared = 0;
        for (uint32_t t = 0; t < 4; ++t) {
            area += triangle_area(s, t);
            CHECK(near(face_normal(s, t), {0, 0, 1}));
            for (int k = 0; k < 3; ++k) CHECK(near(corner_normal(s, t, k), {0, 0, 1}));
            CHECK(near(face_color(s, t), {0.2f, 0.4f, 0.6f}));
            const glm::vec3 c = (corner(s, t, 0) + corner(s, t, 1) + corner(s, t, 2)) / 3.0f;
            CHECK_FALSE((c.x > 1 && c.y > 1));  // no triangle covers the missing square
            for (int i = 0; i < 3; ++i) shared += s.edge_neighbors[3 * t + i] != HSR_NO_NEIGHBOR;
        }
        CHECK(area == Approx(3.0));
        CHECK(shared == 6);  // three inner diagonals, seen from both sides
        check_adjacency(s, false);
    }
    SECTION("clockwise order faces the other way; tilted planes work") {
        const std::vector<glm::vec3> square = {{0, 0, 0}, {0, 1, 1}, {1, 1, 1}, {1, 0, 0}};  // clockwise seen from +z
        hsr::SceneBuilder builder;
        builder.add_polygon(square, {1, 1, 1});
        const hsr::SceneData s = builder.build();
        REQUIRE(s.triangle_count() == 2);
        for (uint32_t t = 0; t < 2; ++t) CHECK(near(face_normal(s, t), glm::normalize(glm::vec3(0, 1, -1))));
        CHECK(s.object_names == std::vector<std::string>{"polygon 1"});
    }
    SECTION("collinear extra vertices add no triangles of zero area") {
        const std::vector<glm::vec3> square = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
        hsr::SceneBuilder builder;
        builder.add_polygon(square, {1, 1, 1});
        const hsr::SceneData s = builder.build();
        double area = 0;
        for (uint32_t t = 0; t < s.triangle_count(); ++t) area += triangle_area(s, t);
        CHECK(area == Approx(4.0));
        check_consistent(s);
    }
    SECTION("bad polygons") {
        using Catch::Contains;
        hsr::SceneBuilder builder;
        const std::vector<glm::vec3> bent = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5f}, {0, 1, 0}};
        CHECK_THAT(error_of([&] { builder.add_polygon(bent, {1, 1, 1}, "bent"); }),
                   Contains("polygon 'bent'") && Contains("not planar"));
        const std::vector<glm::vec3> line = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
        CHECK_THAT(error_of([&] { builder.add_polygon(line, {1, 1, 1}); }), Contains("no area"));
        const std::vector<glm::vec3> bow_tie = {{0, 0, 0}, {2, 2, 0}, {2, 0, 0}, {0, 2, 0}, {-1, 1, 0}};
        CHECK_THAT(error_of([&] { builder.add_polygon(bow_tie, {1, 1, 1}); }), Contains("intersects itself"));
        const std::vector<glm::vec3> two = {{0, 0, 0}, {1, 0, 0}};
        CHECK_THAT(error_of([&] { builder.add_polygon(two, {1, 1, 1}); }), Contains("at least 3"));
        const std::vector<glm::vec3> nan = {{0, 0, 0}, {1, 0, 0}, {0, std::nanf(""), 0}};
        CHECK_THAT(error_of([&] { builder.add_polygon(nan, {1, 1, 1}); }), Contains("not a finite number"));
        CHECK(builder.object_count() == 0);
    }
}

TEST_CASE("add_triangles checks its input", "[scene][errors]") {
    using Catch::Contains;
    hsr::SceneBuilder builder;
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    hsr::MeshOptions named;
    named.name = "mine";
    CHECK_THAT(error_of([&] { builder.add_triangles(p, std::vector<uint32_t>{0, 1, 3}, named); }),
               Contains("mine") && Contains("out of range"));
    CHECK_THAT(error_of([&] { builder.add_triangles(p, std::vector<uint32_t>{0, 1}); }), Contains("whole number"));
    hsr::MeshOptions bad_color;
    bad_color.color = {2, 0, 0};
    builder.add_triangles(p, std::vector<uint32_t>{0, 1, 2}, bad_color);
    CHECK_THAT(error_of([&] { builder.build(); }), Contains("outside [0, 1]"));
}

TEST_CASE("light specs", "[scene][lights]") {
    const hsr::LightSpec point = hsr::parse_light_spec("point:1,2,3");
    CHECK(point.type == HSR_LIGHT_POINT);
    CHECK(point.vector == glm::vec3(1, 2, 3));
    CHECK(point.intensity == 1.0f);
    CHECK(point.color == glm::vec3(1));
    CHECK(point.camera_space);

    const hsr::LightSpec dir = hsr::parse_light_spec("dir:0,0,2");
    CHECK(dir.type == HSR_LIGHT_DIRECTIONAL);
    CHECK(dir.vector == glm::vec3(0, 0, 1));

    const hsr::LightSpec full = hsr::parse_light_spec("directional:3,0,-4,intensity=0.5,color=1/0.5/0,space=world");
    CHECK(near(full.vector, {0.6f, 0, -0.8f}));
    CHECK(full.intensity == 0.5f);
    CHECK(full.color == glm::vec3(1, 0.5f, 0));
    CHECK_FALSE(full.camera_space);
    CHECK(near(hsr::parse_light_spec("point:0,0,0,color=#ff8000").color, {1, 128 / 255.0f, 0}));

    using Catch::Contains;
    for (const char* bad : {"spot:1,2,3", "point1,2,3", "point:1,2", "dir:0,0,0", "point:1,2,x", "point:1,2,3,intensity=-1",
                            "point:1,2,3,foo=1", "point:1,2,3,color=2/0/0", "point:1,2,3,space=screen", "point:1,2,3,4"}) {
        INFO(bad);
        CHECK_THAT(error_of([&] { hsr::parse_light_spec(bad); }), Contains(std::string("light '") + bad + "'"));
    }
}

TEST_CASE("scene files: the three-polygon and z-buffer exercises and the boxes", "[scene][file]") {
    CHECK(hsr::is_scene_file("a/b/c.scene"));
    CHECK(hsr::is_scene_file("C.SCENE"));
    CHECK_FALSE(hsr::is_scene_file("cube.obj"));
    CHECK_FALSE(hsr::is_scene_file("scene"));

    SECTION("three-polygons.scene") {
        const hsr::SceneFile f = hsr::load_scene_file(models_dir / "three-polygons.scene");
        const hsr::SceneData& s = f.scene;
        check_consistent(s);
        CHECK(f.pixel_camera);
        CHECK(f.width == 256u);
        CHECK(f.height == 256u);
        REQUIRE(f.background);
        CHECK(*f.background == glm::vec3(1));
        CHECK(f.lights.empty());
        CHECK(s.object_names == std::vector<std::string>{"red", "green", "blue"});
        REQUIRE(s.triangle_count() == 6);
        const glm::vec3 colors[] = {{0.9f, 0.15f, 0.15f}, {0.15f, 0.7f, 0.2f}, {0.2f, 0.3f, 0.9f}};
        for (uint32_t t = 0; t < 6; ++t) {
            CHECK(face_color(s, t) == colors[s.face_object[t]]);
            CHECK(face_normal(s, t).z > 0.5f);  // listed counter-clockwise: all face the viewer
        }
        CHECK(s.bounds_min.z == -20.0f);
        CHECK(s.bounds_max.z == 28.0041f);
        CHECK(s.bounds_min.x == 20.0f);
        CHECK(s.bounds_max.y == 243.6f);
        // The red bar's area: 216 x 40 in x, y, stretched by its tilt (z rises 40 over 216).
        double red_area = 0;
        for (uint32_t t = 0; t < 6; ++t)
            if (s.face_object[t] == 0) red_area += triangle_area(s, t);
        CHECK(red_area == Approx(40.0 * std::hypot(216.0, 40.0)));
    }
    SECTION("zbuffer-exercise.scene") {
        const hsr::SceneFile f = hsr::load_scene_file(models_dir / "zbuffer-exercise.scene");
        const hsr::SceneData& s = f.scene;
        check_consistent(s);
        CHECK(f.pixel_camera);
        CHECK(f.width == 32u);
        CHECK(f.height == 32u);
        CHECK(s.object_names == std::vector<std::string>{"rectangle", "triangle"});
        REQUIRE(s.triangle_count() == 3);
        for (uint32_t t = 0; t < 3; ++t) CHECK(face_normal(s, t).z > 0.5f);  // all face the viewer
        CHECK(s.bounds_min == glm::vec3(10, 5, 5));
        CHECK(s.bounds_max == glm::vec3(30, 25, 15));
    }
    SECTION("boxes.scene") {
        const hsr::SceneFile f = hsr::load_scene_file(models_dir / "boxes.scene");
        const hsr::SceneData& s = f.scene;
        check_consistent(s);
        check_adjacency(s, true);
        CHECK_FALSE(f.pixel_camera);
        CHECK_FALSE(f.width);
        CHECK(f.yaw_degrees == 35.0f);
        CHECK(f.pitch_degrees == 25.0f);
        CHECK_FALSE(f.zoom);
        CHECK(f.lights.size() == 2);
        CHECK(f.lights[1].intensity == 0.35f);
        CHECK(s.object_names == std::vector<std::string>{"red-bar", "green-bar", "blue-bar"});
        CHECK(s.triangle_count() == 36);
        // Extents worked out by hand: red spans x in [-2, 2]; the green bar (0.45 x 1.8, turned
        // 20 degrees about z) reaches y = 0.45 sin 20 + 1.8 cos 20; the blue bar (0.45 x 1.6 deep,
        // turned 30 degrees about y) reaches z = 0.45 sin 30 + 1.6 cos 30.
        const double s20 = std::sin(glm::radians(20.0)), c20 = std::cos(glm::radians(20.0));
        const double s30 = std::sin(glm::radians(30.0)), c30 = std::cos(glm::radians(30.0));
        CHECK(s.bounds_min.x == Approx(-2.0));
        CHECK(s.bounds_max.x == Approx(2.0));
        CHECK(s.bounds_max.y == Approx(0.45 * s20 + 1.8 * c20));
        CHECK(s.bounds_min.y == Approx(-(0.45 * s20 + 1.8 * c20)));
        CHECK(s.bounds_max.z == Approx(0.45 * s30 + 1.6 * c30));
    }
}

TEST_CASE("scene files: transforms apply in the order written, paths resolve next to the file", "[scene][file]") {
    TempDir dir;
    fs::create_directories(dir.path / "parts");
    fs::copy_file(models_dir / "cube.obj", dir.path / "parts" / "box.obj");
    const fs::path file = dir.write("nested/../t.scene",
                                    "# comment line\n"
                                    "mesh parts/box.obj   # trailing comment\n"
                                    "  scale 2\n"
                                    "  translate 5 0 0\n"
                                    "mesh \"parts/box.obj\"\n"
                                    "  translate 5 0 0\n"
                                    "  rotate 90 0 0 1\n"
                                    "  name turned\n"
                                    "  color 0 0.5 1\n"
                                    "  crease 10\n"
                                    "light point:1,2,3,color=#ffffff\n"
                                    "size 64 48\n"
                                    "camera orbit zoom 2 orthographic\n");
    const hsr::SceneFile f = hsr::load_scene_file(file);
    const hsr::SceneData& s = f.scene;
    REQUIRE(s.object_names == std::vector<std::string>{"box", "turned"});
    glm::vec3 lo[2] = {glm::vec3(1e9f), glm::vec3(1e9f)}, hi[2] = {glm::vec3(-1e9f), glm::vec3(-1e9f)};
    for (uint32_t t = 0; t < s.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            lo[s.face_object[t]] = glm::min(lo[s.face_object[t]], corner(s, t, k));
            hi[s.face_object[t]] = glm::max(hi[s.face_object[t]], corner(s, t, k));
        }
    // Scale then translate: [3, 7] x [-2, 2]; translating first would give [8, 12].
    CHECK(near(lo[0], {3, -2, -2}));
    CHECK(near(hi[0], {7, 2, 2}));
    // Translate to x = 5 then turn 90 degrees about z: the box lands around (0, 5, 0).
    CHECK(near(lo[1], {-1, 4, -1}));
    CHECK(near(hi[1], {1, 6, 1}));
    for (uint32_t t = 0; t < s.triangle_count(); ++t)
        if (s.face_object[t] == 1) CHECK(face_color(s, t) == glm::vec3(0, 0.5f, 1));
    CHECK(f.width == 64u);
    CHECK(f.height == 48u);
    CHECK(f.zoom == 2.0f);
    CHECK(f.orthographic == true);
    CHECK_FALSE(f.yaw_degrees);
    REQUIRE(f.lights.size() == 1);
    CHECK(f.lights[0].type == HSR_LIGHT_POINT);
}

TEST_CASE("scene files: camera look-at with eye, target, up, fov and zoom", "[scene][file]") {
    TempDir dir;
    fs::copy_file(models_dir / "cube.obj", dir.path / "cube.obj");
    const fs::path file = dir.write("look.scene", "mesh cube.obj\n"
                                                  "camera look-at eye 40 40 40 target 0 0.5 0 up 0 0 1 fov 20 zoom 1.5\n");
    const hsr::SceneFile f = hsr::load_scene_file(file);
    REQUIRE(f.look_at);
    CHECK(f.look_at->eye == glm::vec3(40, 40, 40));
    REQUIRE(f.look_at->target);
    CHECK(*f.look_at->target == glm::vec3(0, 0.5f, 0));
    CHECK(f.look_at->up == glm::vec3(0, 0, 1));
    CHECK(f.fov_y_degrees == 20.0f);
    CHECK(f.zoom == 1.5f);
    CHECK_FALSE(f.orthographic);

    const fs::path defaults = dir.write("eye-only.scene", "mesh cube.obj\ncamera look-at eye 1 2 3 orthographic\n");
    const hsr::SceneFile g = hsr::load_scene_file(defaults);
    REQUIRE(g.look_at);
    CHECK_FALSE(g.look_at->target);  // the centre of the bounds
    CHECK(g.look_at->up == glm::vec3(0, 1, 0));
    CHECK(g.orthographic == true);
    CHECK_FALSE(g.fov_y_degrees);
}

TEST_CASE("scene files: camera pixel without size covers the scene's bounds", "[scene][file]") {
    TempDir dir;
    const fs::path file = dir.write("p.scene",
                                    "camera pixel\npolygon\n vertex 0 0 0\n vertex 30.5 0 0\n vertex 0 20 0\n");
    const hsr::SceneFile f = hsr::load_scene_file(file);
    CHECK(f.pixel_camera);
    CHECK(f.width == 31u);
    CHECK(f.height == 20u);
    CHECK(face_color(f.scene, 0) == glm::vec3(0.8f));
}

TEST_CASE("scene file mistakes are reported as file:line", "[scene][file][errors]") {
    TempDir dir;
    dir.write("cube.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    using Catch::Contains;
    struct Case {
        const char* text;
        int line;
        const char* says;
    };
    const Case cases[] = {
        {"mesh cube.obj\nfrobnicate 3\n", 2, "unknown statement 'frobnicate'"},
        {"vertex 1 2 3\n", 1, "must follow a mesh or polygon"},
        {"mesh cube.obj\nvertex 1 2 3\n", 2, "belong to a polygon"},
        {"polygon\n vertex 0 0 0\n vertex 1 0 0\n", 1, "needs at least 3"},
        {"polygon\n vertex 0 0 0\n vertex 1 x 0\n vertex 0 1 0\n", 3, "'x' is not a finite number"},
        {"polygon\n vertex 0 0 0\n vertex 1 0 0 4\n", 3, "expected: vertex"},
        {"polygon\n vertex 0 0 0\n vertex 1 0 0\n vertex 1 1 1\n vertex 0 1 0\n", 1, "not planar"},
        {"\n\nmesh missing.obj\n", 3, "no such file"},
        {"mesh cube.obj\n color 1 2 0\n", 2, "outside [0, 1]"},
        {"mesh cube.obj\n color 1 0\n", 2, "expected: color"},
        {"mesh cube.obj\n scale 0\n", 2, "zero"},
        {"mesh cube.obj\n rotate 10 0 0 0\n", 2, "axis is zero"},
        {"mesh cube.obj\n name a\n name b\n", 3, "already has a name"},
        {"polygon\n crease 30\n", 2, "meshes only"},
        {"mesh cube.obj\ncamera pixel\ncamera pixel\n", 3, "already set on line 2"},
        {"mesh cube.obj\ncamera orbit tilt 3\n", 2, "unknown camera setting"},
        {"mesh cube.obj\ncamera orbit zoom 0\n", 2, "greater than 0"},
        {"mesh cube.obj\ncamera orbit eye 1 2 3\n", 2, "unknown camera setting 'eye' (yaw, pitch"},
        {"mesh cube.obj\ncamera orbit fov 180\n", 2, "fov must be between 0 and 180"},
        {"mesh cube.obj\ncamera look-at target 0 0 0\n", 2, "camera look-at needs eye <x y z>"},
        {"mesh cube.obj\ncamera look-at eye 1 2\n", 2, "camera setting 'eye' needs x y z"},
        {"mesh cube.obj\ncamera look-at eye 1 2 nan\n", 2, "eye 'nan' is not a finite number"},
        {"mesh cube.obj\ncamera look-at eye 1 2 3 yaw 4\n", 2, "unknown camera setting 'yaw' (eye, target"},
        {"mesh cube.obj\ncamera look\n", 2, "expected: camera pixel"},
        {"mesh cube.obj\nsize 0 10\n", 2, "size"},
        {"mesh cube.obj\nbackground 1 1\n", 2, "expected: background"},
        {"mesh cube.obj\nlight spot:1,2,3\n", 2, "unknown light type"},
        {"mesh \"cube.obj\n", 1, "unterminated quote"},
        {"mesh a.obj b.obj\n", 1, "expected: mesh"},
        {"mesh cube.obj\nrepeat 2 2\n", 2, "expected: repeat"},
        {"mesh cube.obj\nrepeat 2 0 3\n", 2, "not a whole number"},
        {"mesh cube.obj\nrepeat 2 2 3 gap -1\n", 2, "gap must be 0 or more"},
        {"mesh cube.obj\nrepeat 2 2 3 spin 4\n", 2, "unknown repeat setting"},
        {"mesh cube.obj\nrepeat 2 2 3\nrepeat 1 1 1\n", 3, "repeat is given twice"},
    };
    int index = 0;
    for (const Case& c : cases) {
        INFO(c.text);
        const fs::path file = dir.write("bad" + std::to_string(index++) + ".scene", c.text);
        const std::string m = error_of([&] { hsr::load_scene_file(file); });
        CHECK_THAT(m, Contains(file.string() + ":" + std::to_string(c.line) + ": ") && Contains(c.says));
    }
    SECTION("a broken mesh is reported at its line and by its own name") {
        dir.write("broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
        const fs::path file = dir.write("uses-broken.scene", "background 0 0 0\nmesh broken.off\n");
        CHECK_THAT(error_of([&] { hsr::load_scene_file(file); }),
                   Contains(file.string() + ":2: ") && Contains("broken.off:6: vertex index 7 is out of range"));
    }
    SECTION("whole-file problems") {
        CHECK_THAT(error_of([&] { hsr::load_scene_file(dir.path / "absent.scene"); }), Contains("absent.scene: no such file"));
        const fs::path empty = dir.write("empty.scene", "# nothing\nbackground 1 1 1\n");
        CHECK_THAT(error_of([&] { hsr::load_scene_file(empty); }), Contains("empty.scene: the scene has no mesh or polygon"));
        const fs::path below = dir.write("below.scene", "camera pixel\npolygon\n vertex -5 -5 0\n vertex -1 -5 0\n vertex -1 -1 0\n");
        CHECK_THAT(error_of([&] { hsr::load_scene_file(below); }), Contains("below.scene") && Contains("size W H"));
    }
}

TEST_CASE("scene files: repeat places the whole scene on a grid of instances", "[scene][file][instancing]") {
    TempDir dir;
    fs::copy_file(models_dir / "cube.obj", dir.path / "box.obj");
    const fs::path file = dir.write("deep.scene",
                                    "mesh box.obj\n"
                                    "  color 1 0 0\n"
                                    "polygon\n"
                                    "  vertex 0 0 3\n  vertex 1 0 3\n  vertex 0 1 3\n"
                                    "repeat 3 2 5 gap 0.5 jitter 10\n");
    const hsr::SceneFile f = hsr::load_scene_file(file);
    CHECK(f.scene.triangle_count() == 13);  // stored once: the cube's 12 and the polygon's 1
    REQUIRE(f.scene.instances.size() == 30);
    for (const hsr_instance& i : f.scene.instances) {
        CHECK(i.triangle_count == 13);
        CHECK(i.vertex_count == f.scene.vertex_count());
    }
    // Layers recede along -z, one scene depth (4 units: z from -1 to 3) plus the gap apart.
    CHECK(f.scene.bounds_max.z - f.scene.bounds_min.z > 4 * 5);
}
