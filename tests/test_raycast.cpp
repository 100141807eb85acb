// The raycast plugin (Appel 1968 ray casting over a binned-SAH BVH, watertight ray/triangle test),
// loaded through the real ABI, against independent answers: the plain zbuffer plugin's frames
// (the same surface at every covered pixel, except pixel centres the z-buffer's 1/256-pixel vertex
// snapping puts on the other side of an edge, each of which is located and checked here), depth and
// barycentrics of hand-made triangles computed in long double, a closed mesh seen from inside, and
// its own frames with other threads, tile sizes, precision and steps.
#include "hsr/abi.h"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/sdk.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

// A tie: another surface within 2 float steps of depth.
const Agreement kRaycast{.plugin = "raycast", .label = "raycast", .bit_identical = false};

glm::dmat4 matrix(const float (&m)[16]) {
    glm::dmat4 r;
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) r[c][row] = m[4 * c + row];
    return r;
}

// The world-space corners of triangle `face` as placement `instance` draws it.
void world_corners(const hsr_scene& raw, uint32_t face, uint32_t instance, glm::dvec3 (&out)[3]) {
    const hsr::sdk::Scene scene(raw);
    const glm::dmat4 m = scene.instance_count() > 0 ? glm::dmat4(scene.placement(instance).transform) : glm::dmat4(1.0);
    for (int c = 0; c < 3; ++c) out[c] = glm::dvec3(m * glm::dvec4(glm::dvec3(scene.corner_position(face, c)), 1.0));
}

// Distance in pixels from the pixel centre (x + 0.5, y + 0.5) to the nearest edge of the triangle's
// window-space outline (infinite when a corner is behind the eye).
double distance_to_outline(const hsr_scene& raw, const hsr_camera& camera, uint32_t face, uint32_t instance,
                           uint32_t x, uint32_t y) {
    glm::dvec3 world[3];
    world_corners(raw, face, instance, world);
    const glm::dmat4 vp = matrix(camera.view_projection);
    glm::dvec2 w[3];
    for (int c = 0; c < 3; ++c) {
        const glm::dvec4 clip = vp * glm::dvec4(world[c], 1.0);
        if (!(clip.w > 0.0)) return std::numeric_limits<double>::infinity();
        w[c] = {(clip.x / clip.w + 1.0) * 0.5 * camera.width, (1.0 - clip.y / clip.w) * 0.5 * camera.height};
    }
    const glm::dvec2 p(x + 0.5, y + 0.5);
    double best = std::numeric_limits<double>::infinity();
    for (int e = 0; e < 3; ++e) {
        const glm::dvec2 a = w[e], b = w[(e + 1) % 3];
        const double len2 = glm::dot(b - a, b - a);
        const double s = len2 > 0.0 ? std::clamp(glm::dot(p - a, b - a) / len2, 0.0, 1.0) : 0.0;
        best = std::min(best, glm::length(p - (a + s * (b - a))));
    }
    return best;
}

// The z-buffer snaps window coordinates to 1/256 pixel (each corner moves up to 1/512 in x and y),
// so its edges lie up to ~0.003 pixel from the exact ones; a pixel centre closer than this to an
// edge of either frame's triangle may fall on either side.
constexpr double kSnapReach = 1.0 / 128.0;

// Distance from the surface point a frame holds at pixel p to the nearest clip plane, relative to the
// scene's size (infinite without planes or surface).
double distance_to_cut(const hsr::Frame& frame, size_t p, const hsr_scene& scene, const hsr_camera& camera) {
    if (frame.face[p] == HSR_NO_FACE || camera.clip_plane_count == 0) return std::numeric_limits<double>::infinity();
    glm::dvec3 c[3];
    world_corners(scene, frame.face[p], frame.instance.empty() ? 0 : frame.instance[p], c);
    const glm::dvec3 point = c[0] + double(frame.bary[2 * p]) * (c[1] - c[0]) + double(frame.bary[2 * p + 1]) * (c[2] - c[0]);
    const double size = glm::length(glm::dvec3(scene.bounds_max[0] - scene.bounds_min[0], scene.bounds_max[1] - scene.bounds_min[1],
                                               scene.bounds_max[2] - scene.bounds_min[2]));
    double best = std::numeric_limits<double>::infinity();
    for (uint32_t k = 0; k < camera.clip_plane_count; ++k) {
        const glm::dvec3 n(camera.clip_planes[k][0], camera.clip_planes[k][1], camera.clip_planes[k][2]);
        best = std::min(best, std::abs(glm::dot(n, point) + camera.clip_planes[k][3]) / glm::length(n) / size);
    }
    return best;
}

// The z-buffer clips polygons by the clip planes in clip space, rounding where the cut crosses an
// edge; a surface point this close to a plane (relative to the scene's size) may fall on either side.
constexpr double kCutReach = 1e-5;

struct RaycastComparison {
    Comparison c;
    uint64_t at_cuts = 0;      // different surfaces, explained by a surface point on a clip plane
    uint64_t on_edges = 0;     // different surfaces, explained by a pixel centre at an edge
    uint64_t unexplained = 0;  // different surfaces otherwise
    std::string first_unexplained;
};

// Compares the raycast frame with zbuffer's, explaining each pixel where the surfaces differ.
RaycastComparison compare_with_zbuffer(const hsr::Frame& ray, const hsr::Frame& z, const hsr_scene& scene,
                                       const hsr_camera& camera) {
    RaycastComparison r;
    r.c = compare(ray, z, kRaycast);
    for (size_t p = 0; p < z.face.size(); ++p) {
        const bool same = ray.face[p] == z.face[p] && (z.instance.empty() || ray.instance[p] == z.instance[p]);
        const float a = ray.depth[p], b = z.depth[p];
        const bool tie = ray.face[p] != HSR_NO_FACE && z.face[p] != HSR_NO_FACE &&
                         std::abs(a - b) <= kRaycast.tie_float_steps * std::numeric_limits<float>::epsilon() *
                                                std::max(a, b);
        if (same || tie) continue;  // ties: counted by compare()
        const uint32_t x = uint32_t(p % z.width), y = uint32_t(p / z.width);
        double distance = std::numeric_limits<double>::infinity();
        if (ray.face[p] != HSR_NO_FACE)
            distance = distance_to_outline(scene, camera, ray.face[p], z.instance.empty() ? 0 : ray.instance[p], x, y);
        if (z.face[p] != HSR_NO_FACE)
            distance = std::min(distance, distance_to_outline(scene, camera, z.face[p],
                                                              z.instance.empty() ? 0 : z.instance[p], x, y));
        if (distance <= kSnapReach) {
            ++r.on_edges;
        } else if (std::min(distance_to_cut(ray, p, scene, camera), distance_to_cut(z, p, scene, camera)) <= kCutReach) {
            ++r.at_cuts;
        } else if (++r.unexplained == 1) {
            r.first_unexplained = "pixel " + std::to_string(x) + "," + std::to_string(y) + ": raycast face " +
                                  std::to_string(ray.face[p]) + " depth " + std::to_string(double(ray.depth[p]) - z.depth[p]) +
                                  ", zbuffer face " + std::to_string(z.face[p]) + " depth " +
                                  std::to_string(z.depth[p]) + ", " + std::to_string(distance) + " px from an edge";
        }
    }
    return r;
}

// Bounds on the same surface. The z-buffer computes depth and barycentrics from the unsnapped
// corners in double (hsr/triangle_setup.hpp) and rounds them to float once, as raycast does, so
// the two differ only where their double values round to neighbouring floats.
constexpr double kDepthUlps = 1.0;
constexpr double kBaryDifference = 1e-6;

// With clip planes the z-buffer rasterizes the clipped polygon's fan triangles, whose depth and
// barycentrics come from the clipped corners: further from the exact values.
constexpr double kClippedDepthUlps = 512.0;
constexpr double kClippedBaryDifference = 1e-3;

RaycastComparison check_raycast(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {},
                                const Settings& zbuffer_settings = {}) {
    const bool clipped = camera.clip_plane_count > 0;
    const hsr::Frame z = render("zbuffer", scene, camera, zbuffer_settings);
    const hsr::Frame ray = render("raycast", scene, camera, settings);
    const RaycastComparison r = compare_with_zbuffer(ray, z, scene, camera);
    INFO(camera.width << "x" << camera.height << ": " << r.first_unexplained << "; covered " << r.c.covered
                      << ", ties " << r.c.ties << ", at edges " << r.on_edges << ", at cuts " << r.at_cuts);
    CHECK(r.c.covered > 0);
    CHECK(r.unexplained == 0);
    // Pixel centres within 1/128 pixel of an edge, and ties (mostly the same: a shared edge, where
    // both triangles have the same depth): a small share of the picture (the deep scene's distant
    // monkeys have many edges per pixel).
    CHECK(double(r.on_edges) < 0.02 * double(r.c.covered));
    CHECK(double(r.c.ties) < 0.005 * double(r.c.covered));
    CHECK(double(r.at_cuts) < 0.002 * double(r.c.covered));
    if (std::getenv("HSR_RAYCAST_SUMMARY"))
        std::printf("%ux%u %s: covered %llu, same %llu, ties %llu, at edges %llu, at cuts %llu, depth ulps %.2f, "
                    "bary %.2g\n",
                    camera.width, camera.height, camera.projection_type == HSR_PROJECTION_ORTHOGRAPHIC ? "ortho" : "persp",
                    (unsigned long long)r.c.covered, (unsigned long long)(r.c.covered - r.c.ties - r.on_edges - r.at_cuts),
                    (unsigned long long)r.c.ties, (unsigned long long)r.on_edges, (unsigned long long)r.at_cuts,
                    r.c.worst_depth_ulps, r.c.worst_bary);
    CHECK(r.c.worst_depth_ulps <= (clipped ? kClippedDepthUlps : kDepthUlps));
    CHECK(r.c.worst_bary <= (clipped ? kClippedBaryDifference : kBaryDifference));
    return r;
}

}  // namespace

TEST_CASE("raycast: the cube, monkey and bunny from several cameras agree with zbuffer", "[raycast]") {
    test_models::require_fetched();
    for (const char* file : {"cube.obj", "monkey.obj", "bunny.obj"}) {
        const hsr::SceneData& data = model(file);
        const hsr_scene scene = data.view();
        INFO(file);
        check_raycast(scene, orbit(data, 0, 0, 1, false, 256));
        check_raycast(scene, orbit(data, 120, 35, 1.3f, false, 200));
        check_raycast(scene, orbit(data, -60, -20, 1, true, 200));
        check_raycast(scene, orbit(data, 200, 10, 4, false, 160));  // zoomed in: much off screen
        check_raycast(scene, orbit(data, 30, 20, 1, false, 200), {{"cull-backfaces", "true"}},
                      {{"cull-backfaces", "true"}});
    }
}

TEST_CASE("raycast: boxes.scene and deep-monkeys.scene agree with zbuffer", "[raycast]") {
    test_models::require_fetched();
    for (const char* file : {"boxes.scene", "deep-monkeys.scene"}) {
        const hsr::SceneData& data = model(file);
        const hsr_scene scene = data.view();
        INFO(file);
        check_raycast(scene, orbit(data, 35, 25, 1, false, 256));
        check_raycast(scene, orbit(data, -70, 10, 3.2f, false, 200));
        check_raycast(scene, orbit(data, 10, -30, 1, true, 200));
    }
}

namespace {

// A scene of raw triangles (world space, counter-clockwise seen from the front).
hsr::SceneData triangles(const std::vector<glm::vec3>& corners) {
    std::vector<uint32_t> indices(corners.size());
    for (uint32_t k = 0; k < indices.size(); ++k) indices[k] = k;
    hsr::SceneBuilder builder;
    hsr::MeshOptions options;
    options.crease_angle_degrees = 0.0f;
    builder.add_triangles(corners, indices, options);
    return builder.build();
}

// A unit sphere around the origin: an octahedron split `levels` times, corners pushed out to the
// sphere; closed (every edge shared by two triangles), counter-clockwise seen from outside.
hsr::SceneData sphere(int levels) {
    std::vector<glm::vec3> tris = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 0}, {-1, 0, 0}, {0, 0, 1},
                                   {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0, -1, 0}, {1, 0, 0}, {0, 0, 1},
                                   {0, 1, 0}, {1, 0, 0}, {0, 0, -1}, {-1, 0, 0}, {0, 1, 0}, {0, 0, -1},
                                   {0, -1, 0}, {-1, 0, 0}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
    for (int l = 0; l < levels; ++l) {
        std::vector<glm::vec3> finer;
        for (size_t t = 0; t < tris.size(); t += 3) {
            const glm::vec3 a = tris[t], b = tris[t + 1], c = tris[t + 2];
            const glm::vec3 ab = glm::normalize(a + b), bc = glm::normalize(b + c), ca = glm::normalize(c + a);
            finer.insert(finer.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
        }
        tris = std::move(finer);
    }
    // Shared corners must be bit-identical: the builder welds nothing, so index them ourselves.
    std::vector<glm::vec3> unique;
    std::vector<uint32_t> indices;
    for (const glm::vec3& p : tris) {
        uint32_t k = 0;
        while (k < unique.size() && unique[k] != p) ++k;
        if (k == unique.size()) unique.push_back(p);
        indices.push_back(k);
    }
    hsr::SceneBuilder builder;
    builder.add_triangles(unique, indices);
    return builder.build();
}

using LongVec3 = glm::tvec3<long double>;
using LongVec4 = glm::tvec4<long double>;
using LongMat4 = glm::tmat4x4<long double>;

LongMat4 long_matrix(const float (&m)[16]) {
    LongMat4 r;
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) r[c][row] = m[4 * c + row];
    return r;
}

long double det3(LongVec3 a, LongVec3 b, LongVec3 c) { return glm::dot(a, glm::cross(b, c)); }

// The exact answer at a pixel centre, in long double: the nearest triangle the ray meets within the
// view volume, its window depth and barycentrics, and how close (barycentrically) it passes to an
// edge of that triangle.
struct Exact {
    uint32_t face = HSR_NO_FACE;
    long double depth = 0, b1 = 0, b2 = 0, edge = 0;
};

Exact exact_hit(const hsr::SceneData& data, const hsr_camera& camera, uint32_t x, uint32_t y) {
    const LongMat4 vp = long_matrix(camera.view_projection);
    const LongMat4 inverse = glm::inverse(vp);
    const long double nx = 2.0L * (x + 0.5L) / camera.width - 1.0L, ny = 1.0L - 2.0L * (y + 0.5L) / camera.height;
    const LongVec4 n = inverse * LongVec4(nx, ny, -1.0L, 1.0L), f = inverse * LongVec4(nx, ny, 1.0L, 1.0L);
    const LongVec3 origin = LongVec3(n) / n.w, direction = LongVec3(f) / f.w - origin;
    Exact best;
    long double best_t = std::numeric_limits<long double>::infinity();
    for (uint32_t t = 0; t < data.triangle_count(); ++t) {
        LongVec3 p[3];
        for (int c = 0; c < 3; ++c) {
            const uint32_t v = data.indices[3 * t + c];
            p[c] = LongVec3(data.positions[3 * v], data.positions[3 * v + 1], data.positions[3 * v + 2]);
        }
        // origin + s * direction = p0 + b1 (p1 - p0) + b2 (p2 - p0), by Cramer's rule.
        const LongVec3 e1 = p[1] - p[0], e2 = p[2] - p[0], r = origin - p[0];
        const long double d = det3(e1, e2, -direction);
        if (d == 0.0L) continue;
        const long double b1 = det3(r, e2, -direction) / d, b2 = det3(e1, r, -direction) / d;
        const long double s = det3(e1, e2, r) / d;
        if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || s < 0 || s > 1 || s >= best_t) continue;
        const LongVec3 point = p[0] + b1 * e1 + b2 * e2;
        const LongVec4 clip = vp * LongVec4(point, 1.0L);
        best_t = s;
        best = {t, (clip.z / clip.w + 1.0L) / 2.0L, b1, b2, std::min({b1, b2, 1.0L - b1 - b2})};
    }
    return best;
}

// |value - exact| in float steps at the exact value (at least at 2^-30, for values near 0).
double float_steps(float value, long double exact) {
    const long double scale = std::max(std::abs(exact), 0x1p-30L);
    return double(std::abs((long double)value - exact) / (scale * std::numeric_limits<float>::epsilon()));
}

}  // namespace

TEST_CASE("raycast: depth and barycentrics in double are the exact ones, rounded", "[raycast]") {
    // Tilted triangles at awkward coordinates, overlapping and crossing one another.
    const hsr::SceneData data =
        triangles({{-1.3f, -0.7f, -0.2f}, {1.1f, -0.9f, 0.4f}, {0.1f, 1.2f, -0.6f},
                   {-0.9f, 0.8f, 0.5f}, {-0.2f, -1.1f, -0.9f}, {1.2f, 0.6f, 0.1f},
                   {-0.31f, -0.17f, 0.93f}, {0.77f, 0.05f, 0.11f}, {0.13f, 0.71f, 0.37f}});
    const hsr_scene scene = data.view();
    for (const hsr_camera& camera :
         {look({0.3f, 0.4f, 3.1f}, {0.05f, -0.02f, 0.0f}, 0.37f, 9.3f, 96, 80, 53.0f),
          make_camera(72, 90, HSR_PROJECTION_ORTHOGRAPHIC, glm::ortho(-1.7f, 1.6f, -1.9f, 1.5f, 0.5f, 7.0f),
                      {1.1f, 0.7f, 2.9f}, {0.0f, 0.1f, 0.0f}, {0, 1, 0}, 0.5f, 7.0f)}) {
        const hsr::Frame frame = render("raycast", scene, camera);
        uint64_t checked = 0;
        double worst_depth = 0, worst_bary = 0;
        for (uint32_t y = 0; y < camera.height; ++y)
            for (uint32_t x = 0; x < camera.width; ++x) {
                const size_t p = size_t(y) * camera.width + x;
                const Exact e = exact_hit(data, camera, x, y);
                INFO("pixel " << x << "," << y);
                if (e.face == HSR_NO_FACE || e.edge < 1e-9L) {  // on an edge either answer is right
                    if (e.edge >= 1e-9L) CHECK(frame.face[p] == HSR_NO_FACE);
                    continue;
                }
                REQUIRE(frame.face[p] == e.face);
                worst_depth = std::max(worst_depth, float_steps(frame.depth[p], e.depth));
                worst_bary = std::max({worst_bary, float_steps(frame.bary[2 * p], e.b1),
                                       float_steps(frame.bary[2 * p + 1], e.b2)});
                ++checked;
            }
        CHECK(checked > camera.width * camera.height / 8);
        // Rounded to the nearest float: within half a step, plus the double arithmetic before it.
        CHECK(worst_depth <= 1.0);
        CHECK(worst_bary <= 1.0);
    }
}

TEST_CASE("raycast: a closed mesh seen from inside covers every pixel", "[raycast]") {
    // Rays through shared edges and corners must hit one of the triangles there (watertight test).
    const hsr::SceneData ball = sphere(4);
    const hsr::SceneData& cube = model("cube.obj");
    for (const char* precision : {"double", "float"}) {
        INFO(precision);
        const Settings settings{{"precision", precision}};
        // From the cube's centre straight at a face: the image's diagonals run along the faces'
        // diagonal edges, exactly through pixel centres.
        for (const hsr_camera& camera : {look({0, 0, 0}, {0, 0, 1}, 0.01f, 10.0f, 64, 64, 90.0f),
                                         look({0, 0, 0}, {1, 1, 1}, 0.01f, 10.0f, 64, 64, 100.0f)}) {
            const hsr::Frame frame = render("raycast", cube.view(), camera, settings);
            CHECK(std::count(frame.face.begin(), frame.face.end(), HSR_NO_FACE) == 0);
        }
        for (const hsr_camera& camera : {look({0.1f, 0.2f, -0.05f}, {0.5f, 0.3f, 1}, 0.01f, 10.0f, 96, 96, 120.0f),
                                         look({0, 0, 0}, {0, 1, 0}, 0.01f, 10.0f, 64, 48, 100.0f, {0, 0, 1}),
                                         look({0.3f, -0.4f, 0.2f}, {-1, 0.2f, 0.3f}, 0.01f, 10.0f, 80, 80, 90.0f)}) {
            const hsr::Frame frame = render("raycast", ball.view(), camera, settings);
            CHECK(std::count(frame.face.begin(), frame.face.end(), HSR_NO_FACE) == 0);
        }
    }
}

TEST_CASE("raycast: float and double agree but at a few counted pixels", "[raycast]") {
    test_models::require_fetched();
    for (const char* file : {"bunny.obj", "monkey.obj", "deep-monkeys.scene"}) {
        const hsr::SceneData& data = model(file);
        const hsr_scene scene = data.view();
        const hsr_camera camera = orbit(data, 40, 20, 1, false, 256);
        const hsr::Frame exact = render("raycast", scene, camera);
        const hsr::Frame rounded = render("raycast", scene, camera, {{"precision", "float"}});
        uint64_t covered = 0, other_surface = 0;
        double worst_depth = 0, worst_bary = 0;
        for (size_t p = 0; p < exact.face.size(); ++p) {
            if (exact.face[p] == HSR_NO_FACE && rounded.face[p] == HSR_NO_FACE) continue;
            ++covered;
            const bool same = exact.face[p] == rounded.face[p] &&
                              (exact.instance.empty() || exact.instance[p] == rounded.instance[p]);
            if (!same) {
                ++other_surface;
                continue;
            }
            worst_depth = std::max(worst_depth, float_steps(rounded.depth[p], exact.depth[p]));
            worst_bary = std::max({worst_bary, std::abs(double(rounded.bary[2 * p]) - exact.bary[2 * p]),
                                   std::abs(double(rounded.bary[2 * p + 1]) - exact.bary[2 * p + 1])});
        }
        INFO(file << ": " << other_surface << " of " << covered << " pixels show another surface, depth within "
                  << worst_depth << " float steps");
        CHECK(double(other_surface) < 0.002 * double(covered));
        CHECK(worst_depth <= 32.0);
        CHECK(worst_bary <= 1e-3);
        if (std::getenv("HSR_RAYCAST_SUMMARY"))
            std::printf("float vs double, %s: %llu of %llu pixels differ, depth within %.2f float steps, "
                        "barycentrics within %.2g\n",
                        file, (unsigned long long)other_surface, (unsigned long long)covered, worst_depth, worst_bary);
    }
}

TEST_CASE("raycast: any number of threads and any tile size give the same buffers", "[raycast]") {
    test_models::require_fetched();
    const hsr::SceneData& data = model("deep-monkeys.scene");
    const hsr_scene scene = data.view();
    const hsr_camera camera = orbit(data, 10, 10, 3.2f, false, 203, 157);
    const hsr::Frame one = render("raycast", scene, camera, {{"threads", "1"}}, true);
    for (const Settings& settings : {Settings{{"threads", "4"}}, Settings{{"threads", "3"}, {"tile-size", "7"}},
                                     Settings{{"threads", "0"}, {"tile-size", "300"}}}) {
        const hsr::Frame many = render("raycast", scene, camera, settings, true);
        CHECK(many.face == one.face);
        CHECK(many.instance == one.instance);
        CHECK(std::memcmp(many.depth.data(), one.depth.data(), one.depth.size() * sizeof(float)) == 0);
        CHECK(std::memcmp(many.bary.data(), one.bary.data(), one.bary.size() * sizeof(float)) == 0);
        CHECK(many.depth_tests == one.depth_tests);
        for (const char* name : {"rays", "hits", "triangle-tests", "nodes-visited"})
            CHECK(counter(many, name) == counter(one, name));
    }
}

TEST_CASE("raycast: clip planes cut as zbuffer's do, and hits behind a cut are found", "[raycast]") {
    test_models::require_fetched();
    for (const char* file : {"bunny.obj", "monkey.obj"}) {
        const hsr::SceneData& data = model(file);
        const glm::vec3 middle = 0.5f * (data.bounds_min + data.bounds_max);
        hsr_camera camera = orbit(data, 30, 15, 1, false, 200);
        // One plane through the middle, then a second slanted one.
        const glm::vec3 n0 = glm::normalize(glm::vec3(0.3f, 0.1f, -1.0f)), n1 = glm::normalize(glm::vec3(-1, 0.4f, 0.2f));
        const float planes[2][4] = {{n0.x, n0.y, n0.z, -glm::dot(n0, middle)},
                                    {n1.x, n1.y, n1.z, -glm::dot(n1, middle + 0.1f * (data.bounds_max - middle))}};
        for (uint32_t count = 1; count <= 2; ++count) {
            camera.clip_plane_count = count;
            std::memcpy(camera.clip_planes, planes, sizeof planes);
            INFO(file << ", " << count << " planes");
            check_raycast(data.view(), camera);
        }
    }
    // A square at z = 0 in front of one at z = -1; a plane keeping z <= -0.5 cuts the front one away.
    const hsr::SceneData squares = triangles({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, -1, 0}, {1, 1, 0}, {-1, 1, 0},
                                              {-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, -1, -1}, {1, 1, -1}, {-1, 1, -1}});
    hsr_camera camera = look({0.1f, 0.2f, 3}, {0, 0, 0}, 0.5f, 10.0f, 32, 32, 30.0f);
    const hsr::Frame uncut = render("raycast", squares.view(), camera);
    camera.clip_plane_count = 1;
    const float keep_back[4] = {0, 0, -1, -0.5f};
    std::memcpy(camera.clip_planes[0], keep_back, sizeof keep_back);
    const hsr::Frame cut = render("raycast", squares.view(), camera);
    const size_t centre = 16 * 32 + 16;
    CHECK(uncut.face[centre] < 2);
    CHECK(cut.face[centre] >= 2);
    CHECK(cut.depth[centre] > uncut.depth[centre]);
    check_raycast(squares.view(), camera);
}

TEST_CASE("raycast: steps, the hierarchy then one per tile, run to the end equal render", "[raycast][steps]") {
    test_models::require_fetched();
    const hsr::SceneData& data = model("monkey.obj");
    const hsr_scene scene = data.view();
    const hsr_camera camera = orbit(data, 20, 10, 1, false, 100, 70);
    const Settings settings{{"tile-size", "16"}};
    const hsr::Frame plain = render("raycast", scene, camera, settings, true);
    const uint64_t tiles = 7 * 5;
    const uint64_t steps = 1 + tiles;  // the hierarchy, then the tiles
    for (uint64_t stop : {uint64_t(0), steps, uint64_t(1), uint64_t(2), uint64_t(12)}) {
        INFO("stop after " << stop);
        hsr::HiddenSurfaceRemover remover(plugin("raycast"), settings);
        REQUIRE(remover.has_steps());
        hsr::Frame frame;
        hsr::resolve_visibility_steps(scene, camera, remover, frame, stop, true);
        REQUIRE(frame.steps.has_value());
        const uint64_t taken = stop == 0 ? steps : stop;
        const uint64_t tiles_cast = taken - 1;
        CHECK(frame.steps->taken == taken);
        CHECK(frame.steps->last.type == (taken == 1 ? "build" : "tile"));
        CHECK(frame.steps->last.phase == (taken == 1 ? "build" : "cast"));
        CHECK(counter(frame, "rays") <= counter(plain, "rays"));
        // The tiles stepped through hold the plain render's pixels; the others are as cleared.
        for (uint32_t y = 0; y < camera.height; ++y)
            for (uint32_t x = 0; x < camera.width; ++x) {
                const size_t p = size_t(y) * camera.width + x;
                const uint64_t tile = (y / 16) * 7 + x / 16;
                if (tile < tiles_cast) {
                    REQUIRE(frame.face[p] == plain.face[p]);
                    REQUIRE(std::memcmp(&frame.depth[p], &plain.depth[p], sizeof(float)) == 0);
                    REQUIRE(std::memcmp(&frame.bary[2 * p], &plain.bary[2 * p], 2 * sizeof(float)) == 0);
                    REQUIRE(frame.depth_tests[p] == plain.depth_tests[p]);
                } else {
                    REQUIRE(frame.face[p] == HSR_NO_FACE);
                    REQUIRE(frame.depth_tests[p] == 0);
                }
            }
        if (tiles_cast == tiles)
            for (const char* name : {"rays", "hits", "triangle-tests", "nodes-visited"})
                CHECK(counter(frame, name) == counter(plain, name));
    }
}

namespace {
// Corner c of the scene's first triangle, x and y (the builder may start a triangle at another corner).
glm::dvec2 corner_2d(const hsr::SceneData& data, int c) {
    const uint32_t v = data.indices[c];
    return {data.positions[3 * v], data.positions[3 * v + 1]};
}
}  // namespace

TEST_CASE("raycast: counters on one triangle, counted by hand", "[raycast]") {
    // Orthographic, window x = world x, window y = 16 - world y: the triangle (2,2) (12,2) (2,12)
    // has pixel centres (x + 0.5, 15.5 - y) inside where both are >= 2 and their sum < 14. Centres
    // on the long edge x + y = 14 are not drawn: on the screen it is a right edge, and the fill
    // rule (top-left) leaves them out. Seen from behind, the picture mirrored, it is a left edge.
    const hsr::SceneData data = triangles({{2, 2, 0}, {12, 2, 0}, {2, 12, 0}});
    const hsr_camera camera = make_camera(16, 16, HSR_PROJECTION_ORTHOGRAPHIC, glm::ortho(0.0f, 16.0f, 0.0f, 16.0f, 1.0f, 20.0f),
                                          {0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 1.0f, 20.0f);
    uint64_t inside = 0, inside_from_behind = 0, in_box = 0;
    for (uint32_t y = 0; y < 16; ++y)
        for (uint32_t x = 0; x < 16; ++x) {
            const double cx = x + 0.5, cy = 15.5 - y;
            if (cx >= 2 && cy >= 2 && cx <= 12 && cy <= 12) ++in_box;
            if (cx >= 2 && cy >= 2 && cx + cy < 14) ++inside;
            if (cx >= 2 && cy >= 2 && cx + cy <= 14) ++inside_from_behind;
        }
    CHECK(inside_from_behind - inside == 10);  // the centres (2.5, 11.5) .. (11.5, 2.5)
    const hsr::Frame frame = render("raycast", data.view(), camera, {}, true);
    CHECK(counter(frame, "rays") == 256);
    CHECK(counter(frame, "hits") == inside);
    CHECK(std::count(frame.face.begin(), frame.face.end(), 0u) == int64_t(inside));
    CHECK(counter(frame, "bvh-nodes") == 2);  // the triangle's leaf and the placement's
    CHECK(counter(frame, "triangle-tests") == in_box);
    CHECK(counter(frame, "nodes-visited") == 2 * in_box);
    uint64_t sum = 0;
    for (uint32_t n : frame.depth_tests) sum += n;
    CHECK(sum == in_box);
    // Depth of world z = 0 from the camera's matrix; the corners' weights are affine in x and y.
    const size_t p = size_t(15 - 4) * 16 + 3;  // centre (3.5, 4.5)
    CHECK(frame.depth[p] == float(window_depth(camera, {3.5, 4.5, 0})));
    const glm::dvec2 weights = barycentric_2d({3.5, 4.5}, corner_2d(data, 0), corner_2d(data, 1), corner_2d(data, 2));
    CHECK(frame.bary[2 * p] == float(weights.x));
    CHECK(frame.bary[2 * p + 1] == float(weights.y));
    // Back-face culling: the camera sees the triangle counter-clockwise, from the front.
    CHECK(counter(render("raycast", data.view(), camera, {{"cull-backfaces", "true"}}), "hits") == inside);
    const hsr_camera behind = make_camera(16, 16, HSR_PROJECTION_ORTHOGRAPHIC, glm::ortho(-16.0f, 0.0f, 0.0f, 16.0f, 1.0f, 20.0f),
                                          {0, 0, -10}, {0, 0, 0}, {0, 1, 0}, 1.0f, 20.0f);
    CHECK(counter(render("raycast", data.view(), behind), "hits") == inside_from_behind);
    CHECK(counter(render("raycast", data.view(), behind, {{"cull-backfaces", "true"}}), "hits") == 0);
}

TEST_CASE("raycast: built once, reused, rebuilt for another scene", "[raycast]") {
    test_models::require_fetched();
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr::SceneData& monkey = model("monkey.obj");
    hsr::HiddenSurfaceRemover raycast(plugin("raycast"), {});
    const hsr_camera camera = orbit(bunny, 10, 10, 1, false, 160);
    const hsr::Frame first = render(raycast, bunny.view(), camera, true);
    const hsr::Frame second = render(raycast, bunny.view(), camera, true);
    CHECK(counter(first, "build-time-us") > 0);
    CHECK(counter(second, "build-time-us") == 0);
    CHECK(second.face == first.face);
    CHECK(second.depth == first.depth);
    uint64_t sum = 0;
    for (uint32_t n : second.depth_tests) sum += n;
    CHECK(sum == counter(second, "triangle-tests"));

    const hsr_camera monkey_camera = orbit(monkey, -30, 15, 1, false, 160);
    const hsr::Frame other = render(raycast, monkey.view(), monkey_camera);
    CHECK(counter(other, "build-time-us") > 0);
    const RaycastComparison r =
        compare_with_zbuffer(other, render("zbuffer", monkey.view(), monkey_camera), monkey.view(), monkey_camera);
    CHECK(r.unexplained == 0);
    // A copy of the bunny at another address is another scene, too.
    const hsr::SceneData copy = bunny;
    const hsr::Frame again = render(raycast, copy.view(), camera);
    CHECK(counter(again, "build-time-us") > 0);
    CHECK(counter(again, "bvh-nodes") == counter(first, "bvh-nodes"));
    CHECK(again.face == first.face);
}

TEST_CASE("raycast: instances, including one moved between frames", "[raycast]") {
    test_models::require_fetched();
    hsr::SceneData grid = hsr::make_instance_grid(model("monkey.obj"), {3, 2, 4, 0.0f, 40.0f});
    const hsr_camera camera = orbit(grid, 25, 15, 1, false, 200);
    check_raycast(grid.view(), camera);
    check_raycast(grid.view(), orbit(grid, 0, 0, 1, true, 200));
    check_raycast(grid.view(), camera, {{"cull-backfaces", "true"}, {"leaf-triangles", "16"}},
                  {{"cull-backfaces", "true"}});
    // The eye among the instances.
    const glm::vec3 lo = grid.bounds_min, hi = grid.bounds_max, middle = 0.5f * (lo + hi);
    const float size = glm::length(hi - lo);
    check_raycast(grid.view(), look(middle, middle - glm::vec3(0.2f, 0.1f, 1.0f), 1e-3f * size, 2 * size, 200, 200));

    hsr::HiddenSurfaceRemover raycast(plugin("raycast"), {});
    const hsr::Frame before = render(raycast, grid.view(), camera);
    // Move one instance in place (same arrays, same counts): the plugin must notice.
    hsr_instance& moved = grid.instances.at(5);
    moved.transform[12] += 0.7f;
    moved.transform[13] += 0.3f;
    for (int a = 0; a < 2; ++a) {
        moved.bounds_min[a] += a == 0 ? 0.7f : 0.3f;
        moved.bounds_max[a] += a == 0 ? 0.7f : 0.3f;
    }
    const hsr::Frame after = render(raycast, grid.view(), camera);
    CHECK(counter(after, "build-time-us") > 0);
    CHECK(counter(after, "bvh-nodes") == counter(before, "bvh-nodes"));
    CHECK(after.face != before.face);
    const RaycastComparison r = compare_with_zbuffer(after, render("zbuffer", grid.view(), camera), grid.view(), camera);
    INFO(r.first_unexplained);
    CHECK(r.unexplained == 0);
}

TEST_CASE("raycast: a camera that cannot be inverted gives an empty picture", "[raycast]") {
    const hsr::SceneData data = triangles({{2, 2, 0}, {12, 2, 0}, {2, 12, 0}});
    hsr_camera camera = look({0, 0, 10}, {0, 0, 0}, 1.0f, 20.0f, 16, 16);
    std::memset(camera.view_projection, 0, sizeof camera.view_projection);
    const hsr::Frame frame = render("raycast", data.view(), camera);
    CHECK(counter(frame, "rays") == 256);
    CHECK(counter(frame, "hits") == 0);
}
