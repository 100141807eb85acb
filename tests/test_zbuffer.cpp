// The zbuffer plugin loaded through the real ABI and checked against answers worked out here without
// its code: plane equations of hand-built scenes, analytic ray casts (in double) through every pixel
// centre, and fill-rule coverage counted by hand.
#include "hsr/abi.h"
#include "hsr/error.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "ray_reference.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using surface_tests::barycentric_2d;
using surface_tests::look;
using surface_tests::make_camera;
using surface_tests::plugin;
using surface_tests::Settings;
using surface_tests::window_depth;
using ray_reference::Hit;
using ray_reference::intersect;
using ray_reference::Ray;
using ray_reference::window_ray;
constexpr float kInfinity = std::numeric_limits<float>::infinity();

// ---------------------------------------------------------------------------------------------- //
// Scene, camera, buffer and counters built by hand

// An indexed triangle mesh; raw() fills in flat normals and the rest of the arrays (in a SceneData,
// which owns what hsr_scene points to).
struct TestMesh {
    std::vector<float> positions;
    std::vector<uint32_t> indices;
    mutable hsr::SceneData data;  // filled by raw()

    uint32_t add_vertex(glm::dvec3 p) {
        positions.insert(positions.end(), {float(p.x), float(p.y), float(p.z)});
        return uint32_t(positions.size() / 3 - 1);
    }
    void add_face(uint32_t a, uint32_t b, uint32_t c) { indices.insert(indices.end(), {a, b, c}); }
    void add_triangle(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
        const uint32_t ia = add_vertex(a), ib = add_vertex(b), ic = add_vertex(c);
        add_face(ia, ib, ic);
    }
    uint32_t triangle_count() const { return uint32_t(indices.size() / 3); }
    glm::dvec3 corner(uint32_t t, int k) const {
        const uint32_t v = indices[3 * t + k];
        return {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
    }
    // The same vertices with only triangle t.
    TestMesh only(uint32_t t) const {
        TestMesh m;
        m.positions = positions;
        m.indices.assign(indices.begin() + 3 * t, indices.begin() + 3 * t + 3);
        return m;
    }

    hsr_scene raw() const {
        const uint32_t n = triangle_count();
        data.positions = positions;
        data.indices = indices;
        data.face_normals.assign(3 * n, 0.0f);
        data.corner_normals.assign(9 * n, 0.0f);
        data.face_colors.assign(3 * n, 0.5f);
        data.edge_neighbors.assign(3 * n, HSR_NO_NEIGHBOR);
        data.face_object.assign(n, 0);
        data.object_names = {"test"};
        for (uint32_t t = 0; t < n; ++t) {
            glm::dvec3 normal = glm::cross(corner(t, 1) - corner(t, 0), corner(t, 2) - corner(t, 0));
            const double length = glm::length(normal);
            normal = length > 0 && std::isfinite(length) ? normal / length : glm::dvec3(0, 0, 1);
            for (int k = 0; k < 3; ++k) {
                data.face_normals[3 * t + k] = float(normal[k]);
                for (int c = 0; c < 3; ++c) data.corner_normals[9 * t + 3 * c + k] = float(normal[k]);
            }
        }
        data.bounds_min = glm::vec3(kInfinity);
        data.bounds_max = glm::vec3(-kInfinity);
        for (size_t v = 0; v < positions.size() / 3; ++v) {
            const glm::vec3 p(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
            data.bounds_min = glm::min(data.bounds_min, p);
            data.bounds_max = glm::max(data.bounds_max, p);
        }
        return data.view();
    }
};

// Orthographic camera looking down -z from z = 10 whose window coordinates are world units:
// window x = world x, window y = height - world y, window depth = (9 - world z) / 19.
hsr_camera pixel_camera(uint32_t width, uint32_t height) {
    return make_camera(width, height, HSR_PROJECTION_ORTHOGRAPHIC,
                       glm::ortho(0.0f, float(width), 0.0f, float(height), 1.0f, 20.0f), {0, 0, 10}, {0, 0, 0},
                       {0, 1, 0}, 1.0f, 20.0f);
}
double pixel_camera_depth(double world_z) { return (9.0 - world_z) / 19.0; }

// A visibility buffer cleared the way the host clears it.
struct Frame {
    uint32_t width, height;
    std::vector<float> depth;
    std::vector<uint32_t> face;
    std::vector<float> bary;

    Frame(uint32_t w, uint32_t h)
        : width(w), height(h), depth(size_t(w) * h, kInfinity), face(size_t(w) * h, HSR_NO_FACE),
          bary(2 * size_t(w) * h, 0.0f) {}
    hsr_visibility_buffer raw() {
        return {sizeof(hsr_visibility_buffer), width, height, depth.data(), face.data(), bary.data()};
    }
    size_t at(uint32_t x, uint32_t y) const { return size_t(y) * width + x; }
    uint32_t face_at(uint32_t x, uint32_t y) const { return face[at(x, y)]; }
    float depth_at(uint32_t x, uint32_t y) const { return depth[at(x, y)]; }
    glm::dvec2 bary_at(uint32_t x, uint32_t y) const { return {bary[2 * at(x, y)], bary[2 * at(x, y) + 1]}; }
};

using CounterValues = std::map<std::string, uint64_t>;

hsr_counter_sink sink_into(CounterValues& values) {
    return {&values, [](void* context, const char* name, uint64_t value) {
                (*static_cast<CounterValues*>(context))[name] = value;
            }};
}

struct Render {
    Frame frame;
    CounterValues counters;
};

Render render(const TestMesh& mesh, const hsr_camera& camera, const Settings& settings = {}) {
    hsr::HiddenSurfaceRemover zbuffer(plugin("zbuffer"), settings);
    Render out{Frame(camera.width, camera.height), {}};
    const hsr_scene scene = mesh.raw();
    hsr_visibility_buffer buffer = out.frame.raw();
    const hsr_counter_sink sink = sink_into(out.counters);
    zbuffer.render(scene, camera, buffer, &sink);
    return out;
}

// How many triangles cover each pixel, each triangle rendered alone into its own buffer.
std::vector<int> coverage_counts(const TestMesh& mesh, const hsr_camera& camera) {
    std::vector<int> counts(size_t(camera.width) * camera.height, 0);
    hsr::HiddenSurfaceRemover zbuffer(plugin("zbuffer"), {});
    for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
        const TestMesh single = mesh.only(t);
        const hsr_scene scene = single.raw();
        Frame frame(camera.width, camera.height);
        hsr_visibility_buffer buffer = frame.raw();
        zbuffer.render(scene, camera, buffer, nullptr);
        for (size_t p = 0; p < counts.size(); ++p) counts[p] += frame.face[p] != HSR_NO_FACE ? 1 : 0;
    }
    return counts;
}

// Every pixel either untouched (face NO_FACE, depth +inf, bary 0) or a finite depth in [0, 1] and
// finite barycentrics.
bool frame_is_clean(const Frame& frame) {
    for (size_t p = 0; p < frame.face.size(); ++p) {
        const float b1 = frame.bary[2 * p], b2 = frame.bary[2 * p + 1];
        if (frame.face[p] == HSR_NO_FACE) {
            if (frame.depth[p] != kInfinity || b1 != 0.0f || b2 != 0.0f) return false;
        } else if (!(frame.depth[p] >= 0.0f && frame.depth[p] <= 1.0f && std::isfinite(b1) && std::isfinite(b2))) {
            return false;
        }
    }
    return true;
}

// ---------------------------------------------------------------------------------------------- //
// Independent answers: ray casting in double

enum class Expect { covered, empty, ambiguous };

// Coverage of pixel (x, y) by triangle t: ambiguous when the centre is within 0.01 pixel of the
// triangle's outline on screen (edges or near/far cut), where subpixel snapping may decide either way.
Expect expected_coverage(const hsr_camera& camera, const TestMesh& mesh, uint32_t t, uint32_t x, uint32_t y) {
    constexpr double d = 0.01;
    const double offsets[5][2] = {{0, 0}, {d, 0}, {-d, 0}, {0, d}, {0, -d}};
    int hits = 0;
    for (const auto& o : offsets) {
        const Ray ray = window_ray(camera, x + 0.5 + o[0], y + 0.5 + o[1]);
        hits += intersect(ray, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)).hit ? 1 : 0;
    }
    return hits == 5 ? Expect::covered : hits == 0 ? Expect::empty : Expect::ambiguous;
}

struct CoverageComparison {
    int covered = 0;     // pixels expected covered and drawn
    int mismatches = 0;  // unambiguous pixels where the plugin disagrees
    double worst_bary_error = 0;
    double worst_depth_error = 0;
};

// Renders triangle t alone and compares every unambiguous pixel with the ray cast; for covered pixels
// also the barycentrics and the depth.
CoverageComparison compare_with_ray_cast(const TestMesh& mesh, uint32_t t, const Frame& frame,
                                         const hsr_camera& camera) {
    CoverageComparison r;
    for (uint32_t y = 0; y < camera.height; ++y)
        for (uint32_t x = 0; x < camera.width; ++x) {
            const Expect expect = expected_coverage(camera, mesh, t, x, y);
            const bool drawn = frame.face_at(x, y) == t;
            if (expect == Expect::ambiguous) continue;
            if (drawn != (expect == Expect::covered)) {
                ++r.mismatches;
                continue;
            }
            if (!drawn) continue;
            ++r.covered;
            const Hit h = intersect(window_ray(camera, x + 0.5, y + 0.5), mesh.corner(t, 0), mesh.corner(t, 1),
                                    mesh.corner(t, 2));
            const glm::dvec2 b = frame.bary_at(x, y);
            r.worst_bary_error = std::max({r.worst_bary_error, std::abs(b.x - h.b1), std::abs(b.y - h.b2)});
            r.worst_depth_error =
                std::max(r.worst_depth_error, std::abs(double(frame.depth_at(x, y)) - window_depth(camera, h.point)));
        }
    return r;
}

// World point of the pixel camera that lands on window point (wx, wy), at height z.
glm::dvec3 from_window(const hsr_camera& camera, double wx, double wy, double z = 0.0) {
    return {wx, camera.height - wy, z};
}

}  // namespace

// ---------------------------------------------------------------------------------------------- //

TEST_CASE("zbuffer: descriptor lists its parameters", "[zbuffer]") {
    const hsr_plugin_descriptor& d = plugin("zbuffer").descriptor;
    REQUIRE(std::string(d.name) == "zbuffer");
    REQUIRE(d.kind == HSR_KIND_HIDDEN_SURFACE_REMOVER);
    REQUIRE(d.param_count == 2);
    CHECK(std::string(d.params[0].name) == "cull-backfaces");
    CHECK(d.params[0].type == HSR_PARAM_BOOL);
    CHECK(std::string(d.params[0].default_value) == "false");
    CHECK(std::string(d.params[1].name) == "depth-test");
    CHECK(d.params[1].type == HSR_PARAM_ENUM);
    CHECK(std::string(d.params[1].choices) == "less|greater");
    CHECK(std::string(d.params[1].default_value) == "less");
}

TEST_CASE("zbuffer: two intersecting squares match their plane equations at every pixel", "[zbuffer]") {
    // Orthographic pixel camera: window x = world x, window y = 32 - world y, nearer = larger z.
    // Square A lies at z = 0 over x, y in [4, 28]; square B is tilted, z = (x - 16) / 2, over
    // x in [2, 30], y in [6, 26], and pierces A along x = 16. No pixel centre lies on an edge of
    // either square or on the intersection line; centres on a square's diagonal may go to either
    // of its two triangles.
    const uint32_t size = 32;
    const hsr_camera camera = pixel_camera(size, size);
    auto tilted_z = [](double x) { return 0.5 * (x - 16.0); };
    const glm::dvec3 a0{4, 4, 0}, a1{28, 4, 0}, a2{28, 28, 0}, a3{4, 28, 0};
    const glm::dvec3 b0{2, 6, tilted_z(2)}, b1{30, 6, tilted_z(30)}, b2{30, 26, tilted_z(30)}, b3{2, 26, tilted_z(2)};

    for (bool a_first : {true, false}) {
        TestMesh mesh;
        auto add_a = [&] {
            mesh.add_triangle(a0, a1, a2);
            mesh.add_triangle(a0, a2, a3);
        };
        auto add_b = [&] {
            mesh.add_triangle(b0, b1, b2);
            mesh.add_triangle(b0, b2, b3);
        };
        if (a_first) {
            add_a();
            add_b();
        } else {
            add_b();
            add_a();
        }
        const uint32_t first_a = a_first ? 0 : 2, first_b = a_first ? 2 : 0;
        const Render r = render(mesh, camera);

        int mismatches = 0, a_pixels = 0, b_pixels = 0;
        uint64_t a_covers = 0, b_covers = 0, overlap_a_wins = 0, overlap_b_wins = 0;
        double worst_depth = 0, worst_bary = 0;
        for (uint32_t py = 0; py < size; ++py)
            for (uint32_t px = 0; px < size; ++px) {
                const double x = px + 0.5, y = size - (py + 0.5);
                const bool in_a = x > 4 && x < 28 && y > 4 && y < 28;
                const bool in_b = x > 2 && x < 30 && y > 6 && y < 26;
                const bool b_visible = in_b && (!in_a || tilted_z(x) > 0.0);
                a_covers += in_a;
                b_covers += in_b;
                overlap_a_wins += in_a && in_b && !b_visible;
                overlap_b_wins += in_a && in_b && b_visible;
                const uint32_t got = r.frame.face_at(px, py);
                if (!in_a && !in_b) {
                    mismatches += got != HSR_NO_FACE;
                    continue;
                }
                // Which triangle of the square: side of its diagonal (0 = on it, either is right).
                double side;
                uint32_t lower, upper;
                if (b_visible) {
                    ++b_pixels;
                    side = (x - 2) * 20 - (y - 6) * 28;  // > 0: below the diagonal b0-b2
                    lower = first_b, upper = first_b + 1;
                } else {
                    ++a_pixels;
                    side = x - y;  // > 0: below the diagonal a0-a2
                    lower = first_a, upper = first_a + 1;
                }
                const bool ok = side > 0 ? got == lower : side < 0 ? got == upper : (got == lower || got == upper);
                if (!ok) {
                    ++mismatches;
                    continue;
                }
                const double z = b_visible ? tilted_z(x) : 0.0;
                worst_depth = std::max(worst_depth, std::abs(r.frame.depth_at(px, py) - pixel_camera_depth(z)));
                const glm::dvec3 c0 = mesh.corner(got, 0), c1 = mesh.corner(got, 1), c2 = mesh.corner(got, 2);
                const glm::dvec2 expected = barycentric_2d({x, y}, glm::dvec2(c0), glm::dvec2(c1), glm::dvec2(c2));
                const glm::dvec2 b = r.frame.bary_at(px, py);
                worst_bary = std::max({worst_bary, std::abs(b.x - expected.x), std::abs(b.y - expected.y)});
            }
        INFO("A drawn first: " << a_first);
        CHECK(mismatches == 0);
        CHECK(a_pixels > 200);
        CHECK(b_pixels > 200);
        CHECK(worst_depth < 1e-6);
        CHECK(worst_bary < 1e-6);
        CHECK(r.counters.at("triangles-in") == 4);
        CHECK(r.counters.at("triangles-rasterized") == 4);
        // Every covered sample is tested once per square; where they overlap, the square drawn
        // second is written only where it is nearer.
        CHECK(r.counters.at("pixels-depth-tested") == a_covers + b_covers);
        CHECK(r.counters.at("pixels-written") == a_covers + b_covers - (a_first ? overlap_a_wins : overlap_b_wins));
    }
}

TEST_CASE("zbuffer: near-plane clipping with 0, 1, 2 and 3 corners in front", "[zbuffer][clipping]") {
    // Eye at the origin looking down -z, near plane at z = -1. Corners with z > 0 are behind the eye.
    const hsr_camera camera = look({0, 0, 0}, {0, 0, -1}, 1.0f, 50.0f, 64, 64, 90.0f);
    struct Case {
        int in_front;
        glm::dvec3 a, b, c;
    };
    const Case cases[] = {
        {3, {-3, -2, -4}, {3, -2.5, -5}, {0, 3, -6}},
        {2, {-3, -2, -3}, {3, -2, -3}, {0.5, 1, 2}},
        {1, {0.3, -1, -4}, {-4, 1, 0.5}, {4, 2, 1}},
        {0, {-1, -1, -0.5}, {1, -1, 3}, {0, 1, -0.9}},
    };
    for (const Case& c : cases) {
        INFO(c.in_front << " corner(s) in front of the near plane");
        TestMesh mesh;
        mesh.add_triangle(c.a, c.b, c.c);
        const Render r = render(mesh, camera);
        const CoverageComparison cmp = compare_with_ray_cast(mesh, 0, r.frame, camera);
        CHECK(cmp.mismatches == 0);
        CHECK(frame_is_clean(r.frame));
        if (c.in_front == 0) {
            CHECK(cmp.covered == 0);
            CHECK(r.counters.at("triangles-outside") == 1);
            CHECK(r.counters.at("pixels-written") == 0);
        } else {
            CHECK(cmp.covered > 100);
            CHECK(cmp.worst_bary_error < 1e-6);
            CHECK(cmp.worst_depth_error < 1e-6);
            CHECK(r.counters.at("triangles-rasterized") == 1);
        }
        CHECK(r.counters.at("triangles-clipped") == (c.in_front == 1 || c.in_front == 2 ? 1u : 0u));
    }
}

TEST_CASE("zbuffer: fill rule covers shared edges exactly once", "[zbuffer][fill-rule]") {
    SECTION("a square split along either diagonal, every edge through pixel centres") {
        // Window corners (2.5, 2.5) to (18.5, 18.5). Top-left rule: centres on the left edge (x = 2.5)
        // and the top edge (y = 2.5) are inside, those on the right and bottom edges are not.
        const uint32_t size = 24;
        const hsr_camera camera = pixel_camera(size, size);
        const glm::dvec3 tl = from_window(camera, 2.5, 2.5), tr = from_window(camera, 18.5, 2.5),
                         br = from_window(camera, 18.5, 18.5), bl = from_window(camera, 2.5, 18.5);
        for (bool main_diagonal : {true, false}) {
            TestMesh mesh;
            if (main_diagonal) {
                mesh.add_triangle(tl, tr, br);
                mesh.add_triangle(tl, br, bl);
            } else {
                mesh.add_triangle(tr, bl, tl);
                mesh.add_triangle(tr, br, bl);
            }
            const std::vector<int> counts = coverage_counts(mesh, camera);
            int wrong = 0;
            for (uint32_t y = 0; y < size; ++y)
                for (uint32_t x = 0; x < size; ++x) {
                    const int expected = (x >= 2 && x <= 17 && y >= 2 && y <= 17) ? 1 : 0;
                    wrong += counts[size_t(y) * size + x] != expected;
                }
            INFO("main diagonal: " << main_diagonal);
            CHECK(wrong == 0);
        }
    }

    SECTION("a fan of eight triangles around a pixel centre, spokes along rows, columns and diagonals") {
        const uint32_t size = 26;
        const hsr_camera camera = pixel_camera(size, size);
        const glm::dvec2 centre{12.5, 12.5};
        const glm::dvec2 directions[8] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
        std::vector<glm::dvec2> rim;
        for (int k = 0; k < 8; ++k) rim.push_back(centre + (k % 2 == 0 ? 9.0 : 7.0) * directions[k]);
        TestMesh mesh;
        const uint32_t hub = mesh.add_vertex(from_window(camera, centre.x, centre.y));
        std::vector<uint32_t> rim_ids;
        for (glm::dvec2 p : rim) rim_ids.push_back(mesh.add_vertex(from_window(camera, p.x, p.y)));
        for (int k = 0; k < 8; ++k) mesh.add_face(hub, rim_ids[k], rim_ids[(k + 1) % 8]);
        const std::vector<int> counts = coverage_counts(mesh, camera);

        int wrong = 0, inside = 0;
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x) {
                // Position against the convex rim polygon, from cross products (exact here).
                const glm::dvec2 p{x + 0.5, y + 0.5};
                double least = std::numeric_limits<double>::infinity(), most = -least;
                for (int k = 0; k < 8; ++k) {
                    const glm::dvec2 a = rim[k], b = rim[(k + 1) % 8];
                    const double cross = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
                    least = std::min(least, cross);
                    most = std::max(most, cross);
                }
                const bool strictly_inside = least > 0 || most < 0;
                const bool on_outline = !strictly_inside && (least == 0 || most == 0) && (least >= 0 || most <= 0);
                const int count = counts[size_t(y) * size + x];
                if (strictly_inside) {
                    ++inside;
                    wrong += count != 1;
                } else if (on_outline) {
                    wrong += count > 1;
                } else {
                    wrong += count != 0;
                }
            }
        CHECK(inside > 200);
        CHECK(wrong == 0);
        CHECK(counts[size_t(12) * size + 12] == 1);  // the hub, on all eight triangles' corners
    }

    SECTION("a full-screen quad, and a quad far beyond the guard band, cover every pixel once") {
        const uint32_t size = 16;
        const hsr_camera camera = pixel_camera(size, size);
        for (double reach : {0.0, 1e6}) {
            // World (−reach, −reach) .. (size + reach, size + reach); its diagonal runs through the
            // pixel centres with x + y = size in window coordinates.
            TestMesh mesh;
            const double lo = -reach, hi = size + reach;
            mesh.add_triangle({lo, lo, 0}, {hi, lo, 0}, {hi, hi, 0});
            mesh.add_triangle({lo, lo, 0}, {hi, hi, 0}, {lo, hi, 0});
            const std::vector<int> counts = coverage_counts(mesh, camera);
            INFO("reach beyond the screen: " << reach);
            CHECK(std::count(counts.begin(), counts.end(), 1) == int(size * size));
        }
    }

    SECTION("a jittered ground grid crossing the near plane is watertight") {
        const hsr_camera camera = look({0, 0, 0}, {0, -0.6, -1}, 0.5f, 80.0f, 48, 40, 70.0f);
        const int cells = 10;
        const double x0 = -12, x1 = 12, z0 = -40, z1 = 6, ground = -1;
        std::mt19937 random(1234);
        std::uniform_real_distribution<double> jitter(-0.35, 0.35);
        TestMesh mesh;
        std::vector<uint32_t> grid;
        for (int j = 0; j <= cells; ++j)
            for (int i = 0; i <= cells; ++i) {
                const bool border = i == 0 || j == 0 || i == cells || j == cells;
                const double x = x0 + (x1 - x0) * (i + (border ? 0 : jitter(random))) / cells;
                const double z = z0 + (z1 - z0) * (j + (border ? 0 : jitter(random))) / cells;
                grid.push_back(mesh.add_vertex({x, ground, z}));
            }
        auto id = [&](int i, int j) { return grid[size_t(j) * (cells + 1) + i]; };
        for (int j = 0; j < cells; ++j)
            for (int i = 0; i < cells; ++i) {
                mesh.add_face(id(i, j), id(i, j + 1), id(i + 1, j + 1));
                mesh.add_face(id(i, j), id(i + 1, j + 1), id(i + 1, j));
            }
        const std::vector<int> counts = coverage_counts(mesh, camera);

        // Expected from the plane y = -1 and the grid's rectangle, by ray casting.
        TestMesh rectangle;
        rectangle.add_triangle({x0, ground, z0}, {x0, ground, z1}, {x1, ground, z1});
        rectangle.add_triangle({x0, ground, z0}, {x1, ground, z1}, {x1, ground, z0});
        int wrong = 0, inside = 0;
        for (uint32_t y = 0; y < camera.height; ++y)
            for (uint32_t x = 0; x < camera.width; ++x) {
                const Expect e0 = expected_coverage(camera, rectangle, 0, x, y);
                const Expect e1 = expected_coverage(camera, rectangle, 1, x, y);
                const int count = counts[size_t(y) * camera.width + x];
                if (e0 == Expect::covered || e1 == Expect::covered) {
                    ++inside;
                    wrong += count != 1;
                } else if (e0 == Expect::empty && e1 == Expect::empty) {
                    wrong += count != 0;
                } else {
                    wrong += count > 1;
                }
            }
        CHECK(inside > 500);
        CHECK(wrong == 0);
        const Render whole = render(mesh, camera);
        CHECK(whole.counters.at("triangles-clipped") > 0);
        CHECK(frame_is_clean(whole.frame));
    }
}

TEST_CASE("zbuffer: depth-test less keeps the nearest surface, greater the farthest", "[zbuffer]") {
    // Near square at z = 2 over x, y in [2, 10]; far square at z = -3 over x, y in [6, 14].
    const uint32_t size = 16;
    const hsr_camera camera = pixel_camera(size, size);
    for (bool near_first : {true, false}) {
        TestMesh mesh;
        auto add_square = [&](double lo, double hi, double z) {
            mesh.add_triangle({lo, lo, z}, {hi, lo, z}, {hi, hi, z});
            mesh.add_triangle({lo, lo, z}, {hi, hi, z}, {lo, hi, z});
        };
        const double near_range[2] = {2, 10}, far_range[2] = {6, 14};
        const double (&first)[2] = near_first ? near_range : far_range;
        const double (&second)[2] = near_first ? far_range : near_range;
        add_square(first[0], first[1], near_first ? 2.0 : -3.0);
        add_square(second[0], second[1], near_first ? -3.0 : 2.0);
        const uint32_t near_id = near_first ? 0 : 2, far_id = near_first ? 2 : 0;

        for (const char* test : {"less", "greater"}) {
            const bool keep_near = std::string(test) == "less";
            const Render r = render(mesh, camera, {{"depth-test", test}});
            int wrong = 0;
            for (uint32_t py = 0; py < size; ++py)
                for (uint32_t px = 0; px < size; ++px) {
                    const double x = px + 0.5, y = size - (py + 0.5);
                    const bool in_near = x > 2 && x < 10 && y > 2 && y < 10;
                    const bool in_far = x > 6 && x < 14 && y > 6 && y < 14;
                    const uint32_t got = r.frame.face_at(px, py);
                    const float depth = r.frame.depth_at(px, py);
                    if (!in_near && !in_far) {
                        wrong += got != HSR_NO_FACE || depth != kInfinity;
                        continue;
                    }
                    const bool near_wins = in_near && (!in_far || keep_near);
                    const uint32_t square = near_wins ? near_id : far_id;
                    const double z = near_wins ? 2.0 : -3.0;
                    wrong += (got != square && got != square + 1) ||
                             std::abs(depth - pixel_camera_depth(z)) > 1e-6;
                }
            INFO("depth-test=" << test << ", near square first: " << near_first);
            CHECK(wrong == 0);
            CHECK(frame_is_clean(r.frame));
        }
    }
}

TEST_CASE("zbuffer: back-face culling keeps the side facing the camera", "[zbuffer][culling]") {
    // Triangle 0 is counter-clockwise seen from +z, triangle 1 clockwise; both lie in z = 0.
    TestMesh mesh;
    mesh.add_triangle({-2, -1, 0}, {-0.4, -1, 0}, {-1.2, 1, 0});
    mesh.add_triangle({0.4, -1, 0}, {1.2, 1, 0}, {2, -1, 0});
    auto pixels_of = [](const Frame& f, uint32_t face) { return std::count(f.face.begin(), f.face.end(), face); };

    struct View {
        const char* name;
        hsr_camera camera;
        uint32_t front;  // the triangle whose front this camera sees
    };
    const View views[] = {
        {"perspective from +z", look({0, 0, 5}, {0, 0, 0}, 0.1f, 20.0f, 40, 32, 60.0f), 0},
        {"perspective from -z", look({0, 0, -5}, {0, 0, 0}, 0.1f, 20.0f, 40, 32, 60.0f), 1},
        {"perspective from +z, upside down",
         look({0, 0, 5}, {0, 0, 0}, 0.1f, 20.0f, 40, 32, 60.0f, {0, -1, 0}), 0},
        {"orthographic from +z",
         make_camera(40, 32, HSR_PROJECTION_ORTHOGRAPHIC, glm::ortho(-2.5f, 2.5f, -2.0f, 2.0f, 0.1f, 20.0f),
                     {0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.1f, 20.0f),
         0},
        {"orthographic from -z",
         make_camera(40, 32, HSR_PROJECTION_ORTHOGRAPHIC, glm::ortho(-2.5f, 2.5f, -2.0f, 2.0f, 0.1f, 20.0f),
                     {0, 0, -5}, {0, 0, 0}, {0, 1, 0}, 0.1f, 20.0f),
         1},
    };
    for (const View& v : views) {
        INFO(v.name);
        const Render all = render(mesh, v.camera);
        CHECK(pixels_of(all.frame, 0) > 30);
        CHECK(pixels_of(all.frame, 1) > 30);
        CHECK(all.counters.at("triangles-backface-culled") == 0);

        const Render culled = render(mesh, v.camera, {{"cull-backfaces", "true"}});
        CHECK(pixels_of(culled.frame, v.front) == pixels_of(all.frame, v.front));
        CHECK(pixels_of(culled.frame, 1 - v.front) == 0);
        CHECK(culled.counters.at("triangles-backface-culled") == 1);
        CHECK(culled.counters.at("triangles-rasterized") == 1);
    }
}

TEST_CASE("zbuffer: perspective-correct barycentrics and depth match a ray cast", "[zbuffer]") {
    const hsr_camera camera = look({0.3f, 1.2f, 4.0f}, {0, 0, -1}, 0.5f, 30.0f, 96, 64, 60.0f);
    TestMesh mesh;
    mesh.add_triangle({-2.5, -1.5, 2.0}, {3.0, -0.5, -9.0}, {-0.5, 2.5, -3.0});
    const Render r = render(mesh, camera);
    const CoverageComparison cmp = compare_with_ray_cast(mesh, 0, r.frame, camera);
    CHECK(cmp.mismatches == 0);
    CHECK(cmp.covered > 800);
    CHECK(cmp.worst_bary_error < 1e-6);
    CHECK(cmp.worst_depth_error < 1e-6);

    // The tilt is strong enough that screen-space (affine) interpolation would be far off.
    glm::dvec2 window[3];
    glm::dmat4 view_projection;
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) view_projection[c][row] = camera.view_projection[4 * c + row];
    for (int k = 0; k < 3; ++k) {
        const glm::dvec4 clip = view_projection * glm::dvec4(mesh.corner(0, k), 1.0);
        window[k] = {(clip.x / clip.w + 1) / 2 * camera.width, (1 - clip.y / clip.w) / 2 * camera.height};
    }
    double worst_affine = 0;
    for (uint32_t y = 0; y < camera.height; ++y)
        for (uint32_t x = 0; x < camera.width; ++x) {
            if (r.frame.face_at(x, y) != 0) continue;
            const glm::dvec2 affine = barycentric_2d({x + 0.5, y + 0.5}, window[0], window[1], window[2]);
            const glm::dvec2 b = r.frame.bary_at(x, y);
            worst_affine = std::max({worst_affine, std::abs(affine.x - b.x), std::abs(affine.y - b.y)});
        }
    CHECK(worst_affine > 0.05);
}

TEST_CASE("zbuffer: degenerate, behind-the-eye and non-finite triangles draw nothing and no NaN", "[zbuffer]") {
    const hsr_camera camera = look({0, 0, 0}, {0, 0, -1}, 1.0f, 50.0f, 32, 32, 90.0f);
    const double nan = std::numeric_limits<double>::quiet_NaN();

    SECTION("nothing to draw") {
        TestMesh mesh;
        mesh.add_triangle({-1, -1, -5}, {0, 0, -5}, {1, 1, -5});    // collinear
        mesh.add_triangle({-1, -1, -5}, {-1, -1, -5}, {1, 0, -5});  // repeated corner
        mesh.add_triangle({0, 0, -5}, {0, 0, -5}, {0, 0, -5});      // a point
        mesh.add_triangle({-1, -1, 3}, {1, -1, 3}, {0, 1, 3});      // behind the eye
        mesh.add_triangle({-1, -1, 0}, {1, -1, 0}, {0, 1, 0});      // in the eye's plane, w = 0
        mesh.add_triangle({0, 0, 0}, {0, 0, 0}, {0, 0, 0});         // at the eye
        mesh.add_triangle({nan, 0, -5}, {1, 0, -5}, {0, 1, -5});    // not a number
        const Render r = render(mesh, camera);
        CHECK(std::count(r.frame.face.begin(), r.frame.face.end(), HSR_NO_FACE) == 32 * 32);
        CHECK(frame_is_clean(r.frame));
        CHECK(r.counters.at("triangles-in") == 7);
        CHECK(r.counters.at("triangles-rasterized") == 0);
        CHECK(r.counters.at("pixels-written") == 0);
        CHECK(r.counters.at("triangles-degenerate") + r.counters.at("triangles-outside") == 7);
    }

    SECTION("corners at w = 0, at the eye, huge or beyond the far plane: clipped to what a ray cast sees") {
        struct Case {
            const char* name;
            glm::dvec3 a, b, c;
            int least_covered;
        };
        const Case cases[] = {
            {"a corner at w = 0", {2, 0, 0}, {-2, -2, -6}, {1, 2, -4}, 50},
            // Its plane holds the eye, so it is seen edge-on: nothing (or a line of samples) drawn.
            {"a corner at the eye", {0, 0, 0}, {-2, -2, -6}, {2, -1, -4}, 0},
            {"far beyond the guard band", {-1e7, -1e7, -20}, {1e7, -1e7, -20}, {0, 1e7, -20}, 32 * 32},
            {"a corner beyond the far plane", {-3, -3, -2}, {3e6, 1, -1e7}, {-1, 2, -2}, 50},
        };
        for (const Case& c : cases) {
            INFO(c.name);
            TestMesh mesh;
            mesh.add_triangle(c.a, c.b, c.c);
            const Render r = render(mesh, camera);
            const CoverageComparison cmp = compare_with_ray_cast(mesh, 0, r.frame, camera);
            CHECK(frame_is_clean(r.frame));
            CHECK(cmp.mismatches == 0);
            CHECK(cmp.covered >= c.least_covered);
            CHECK(cmp.worst_bary_error < 1e-6);
            CHECK(cmp.worst_depth_error < 1e-6);
        }
    }

    SECTION("a non-finite triangle does not stop the others") {
        TestMesh mesh;
        mesh.add_triangle({nan, nan, nan}, {1, 0, -5}, {0, 1, -5});
        mesh.add_triangle({-2, -2, -5}, {2, -2, -5}, {0, 2, -5});
        const Render r = render(mesh, camera);
        CHECK(r.counters.at("triangles-degenerate") == 1);
        CHECK(r.counters.at("triangles-rasterized") == 1);
        CHECK(compare_with_ray_cast(mesh, 1, r.frame, camera).mismatches == 0);
        CHECK(frame_is_clean(r.frame));
    }
}

TEST_CASE("zbuffer: bad input comes back as hsr::Error with a clear message", "[zbuffer][errors]") {
    TestMesh mesh;
    mesh.add_triangle({1, 1, 0}, {5, 1, 0}, {1, 5, 0});
    const hsr_scene scene = mesh.raw();
    const hsr_camera camera = pixel_camera(16, 12);
    hsr::HiddenSurfaceRemover zbuffer(plugin("zbuffer"), {});

    Frame wrong_size(12, 16);
    hsr_visibility_buffer wrong = wrong_size.raw();
    CHECK_THROWS_WITH(zbuffer.render(scene, camera, wrong, nullptr),
                      Catch::Contains("zbuffer: visibility buffer is 12x16 but the camera is 16x12"));
    CHECK_THROWS_AS(zbuffer.render(scene, camera, wrong, nullptr), hsr::Error);

    TestMesh broken = mesh;
    broken.indices[2] = 7;
    const hsr_scene broken_scene = broken.raw();
    Frame frame(16, 12);
    hsr_visibility_buffer buffer = frame.raw();
    CHECK_THROWS_WITH(zbuffer.render(broken_scene, camera, buffer, nullptr),
                      Catch::Contains("refers to vertex 7") && Catch::Contains("3 vertices"));

    // The instance stays usable after a failed call.
    zbuffer.render(scene, camera, buffer, nullptr);
    CHECK(frame.face_at(2, 12 - 1 - 2) == 0);  // world (2.5, 2.5) is inside the triangle
}
