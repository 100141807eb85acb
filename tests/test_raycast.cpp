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

struct RaycastComparison {
    Comparison c;
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

RaycastComparison check_raycast(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {},
                                const Settings& zbuffer_settings = {}) {
    const hsr::Frame z = render("zbuffer", scene, camera, zbuffer_settings);
    const hsr::Frame ray = render("raycast", scene, camera, settings);
    const RaycastComparison r = compare_with_zbuffer(ray, z, scene, camera);
    INFO(camera.width << "x" << camera.height << ": " << r.first_unexplained << "; covered " << r.c.covered
                      << ", ties " << r.c.ties << ", at edges " << r.on_edges);
    CHECK(r.c.covered > 0);
    CHECK(r.unexplained == 0);
    // Pixel centres within 1/128 pixel of an edge, and ties: a small share of the picture (the
    // deep scene's distant monkeys have many edges per pixel; boxes.scene has coplanar faces).
    CHECK(double(r.on_edges) < 0.02 * double(r.c.covered));
    CHECK(double(r.c.ties) < 0.02 * double(r.c.covered));
    if (std::getenv("HSR_RAYCAST_SUMMARY"))
        std::printf("%ux%u %s: covered %llu, same %llu, ties %llu, at edges %llu, depth ulps %.2f, bary %.2g\n",
                    camera.width, camera.height, camera.projection_type == HSR_PROJECTION_ORTHOGRAPHIC ? "ortho" : "persp",
                    (unsigned long long)r.c.covered, (unsigned long long)(r.c.covered - r.c.ties - r.on_edges),
                    (unsigned long long)r.c.ties, (unsigned long long)r.on_edges, r.c.worst_depth_ulps, r.c.worst_bary);
    CHECK(r.c.worst_depth_ulps <= kDepthUlps);
    CHECK(r.c.worst_bary <= kBaryDifference);
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
