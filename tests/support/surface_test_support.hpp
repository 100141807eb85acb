// What the z-buffer family's tests share (test_zbuffer, test_scanline_zbuffer,
// test_hierarchical_zbuffer, test_octree_zbuffer): hidden-surface plugins loaded from the build's
// plugin folder, models loaded once, cameras, frames resolved through the host pipeline, counters,
// and the per-pixel comparison of a plugin's frame with the plain zbuffer plugin's frame.
#pragma once

#include "hsr/abi.h"
#include "hsr/camera.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"
#include "test_models.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <deque>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace surface_tests {

// The built-in plugins, by kind.
inline const char* const kBuiltinHiddenSurface[] = {
    "zbuffer", "hierarchical-zbuffer", "octree-zbuffer", "scanline-zbuffer", "a-buffer", "painter",
    "bsp",     "warnock",              "weiler-atherton", "raycast",         "embree"};
inline const char* const kBuiltinHiddenLine[] = {"roberts", "appel", "floating-horizon"};
inline const char* const kBuiltinLighting[] = {"blinn-phong", "facecolor", "gooch", "lambert", "phong"};

using Settings = std::vector<hsr::Setting>;

// ---------------------------------------------------------------------------------------------- //
// Plugins, models, frames, counters

// The plugin <prefix><name>.so of a folder (by default hsr-<name>.so of the build's plugin folder),
// loaded once.
inline const hsr::Plugin& plugin(const std::string& name, const char* dir = HSR_PLUGIN_DIR,
                                 const char* prefix = "hsr-") {
    static std::vector<std::vector<hsr::Plugin>> loaded;
    for (const auto& plugins : loaded)
        if (plugins.at(0).descriptor.name == name) return plugins.at(0);
    loaded.push_back(hsr::load_plugin_library(std::string(dir) + "/" + prefix + name + ".so"));
    return loaded.back().at(0);
}

// models/<file>: a mesh, or a .scene file; loaded once. (A deque: loading another model must not
// move the ones already handed out.)
inline const hsr::SceneData& model(const std::string& file) {
    static std::deque<std::pair<std::string, hsr::SceneData>> cache;
    for (const auto& [name, data] : cache)
        if (name == file) return data;
    const std::string path = test_models::path(file).string();
    cache.emplace_back(file, file.ends_with(".scene") ? hsr::load_scene_file(path).scene : hsr::load_model(path));
    return cache.back().second;
}

// The frame the host resolves with `remover` (per-pixel depth-test counts only when asked for).
inline hsr::Frame render(hsr::HiddenSurfaceRemover& remover, const hsr_scene& scene, const hsr_camera& camera,
                         bool count_tests = false) {
    hsr::Frame frame;
    hsr::resolve_visibility(scene, camera, remover, frame, count_tests);
    return frame;
}

// The same with a fresh instance of the plugin `name`.
inline hsr::Frame render(const std::string& name, const hsr_scene& scene, const hsr_camera& camera,
                         const Settings& settings = {}, bool count_tests = false) {
    hsr::HiddenSurfaceRemover remover(plugin(name), settings);
    return render(remover, scene, camera, count_tests);
}

inline uint64_t counter(const hsr::Frame& frame, const std::string& name) {
    for (const auto& [n, v] : frame.counters)
        if (n == name) return v;
    FAIL("no counter " << name);
    return 0;
}

// Every triangle the scene draws is accounted for exactly once: culled as a back face, outside,
// degenerate or rasterized, or counted by one of the plugin's own `culled` counters.
inline void check_triangle_accounting(const hsr::Frame& frame, std::initializer_list<const char*> culled = {}) {
    uint64_t accounted = counter(frame, "triangles-backface-culled") + counter(frame, "triangles-outside") +
                         counter(frame, "triangles-degenerate") + counter(frame, "triangles-rasterized");
    for (const char* name : culled) accounted += counter(frame, name);
    CHECK(counter(frame, "triangles-in") == accounted);
}

// ---------------------------------------------------------------------------------------------- //
// Cameras and projections

inline hsr_camera make_camera(uint32_t width, uint32_t height, hsr_projection type, const glm::mat4& projection,
                              glm::vec3 eye, glm::vec3 center, glm::vec3 up, float near, float far) {
    const glm::mat4 view = glm::lookAt(eye, center, up);
    const glm::mat4 view_projection = projection * view;
    const glm::vec3 direction = glm::normalize(center - eye);
    hsr_camera c{};
    c.struct_size = sizeof(hsr_camera);
    c.width = width;
    c.height = height;
    c.projection_type = type;
    std::memcpy(c.view, glm::value_ptr(view), sizeof c.view);
    std::memcpy(c.projection, glm::value_ptr(projection), sizeof c.projection);
    std::memcpy(c.view_projection, glm::value_ptr(view_projection), sizeof c.view_projection);
    for (int k = 0; k < 3; ++k) {
        c.eye[k] = eye[k];
        c.view_direction[k] = direction[k];
    }
    c.near_plane = near;
    c.far_plane = far;
    return c;
}

// A perspective camera at `eye` looking at `center`.
inline hsr_camera look(glm::vec3 eye, glm::vec3 center, float near, float far, uint32_t width, uint32_t height,
                       float fovy_degrees = 70.0f, glm::vec3 up = {0, 1, 0}) {
    return make_camera(width, height, HSR_PROJECTION_PERSPECTIVE,
                       glm::perspective(glm::radians(fovy_degrees), float(width) / float(height), near, far), eye,
                       center, up, near, far);
}

// The host's orbit camera around the scene's bounds.
inline hsr_camera orbit(const hsr::SceneData& scene, float yaw, float pitch, float zoom, bool ortho, uint32_t width,
                        uint32_t height) {
    hsr::CameraSettings s;
    s.yaw_degrees = yaw;
    s.pitch_degrees = pitch;
    s.zoom = zoom;
    s.orthographic = ortho;
    s.width = width;
    s.height = height;
    return hsr::make_orbit_camera(scene.bounds_min, scene.bounds_max, s);
}

// The same with a square image.
inline hsr_camera orbit(const hsr::SceneData& scene, float yaw, float pitch, float zoom, bool ortho, uint32_t size) {
    return orbit(scene, yaw, pitch, zoom, ortho, size, size);
}

// Window depth of a world point, from the camera's matrix (double precision).
inline double window_depth(const hsr_camera& camera, glm::dvec3 world) {
    glm::dmat4 view_projection;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) view_projection[c][r] = camera.view_projection[4 * c + r];
    const glm::dvec4 clip = view_projection * glm::dvec4(world, 1.0);
    return (clip.z / clip.w + 1.0) / 2.0;
}

// Barycentric weights of corners b and c at p in the plane (exact for the half-integer inputs used).
inline glm::dvec2 barycentric_2d(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    const double w1 = ((p.x - a.x) * (c.y - a.y) - (c.x - a.x) * (p.y - a.y)) / det;
    const double w2 = ((b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y)) / det;
    return {w1, w2};
}

// ---------------------------------------------------------------------------------------------- //
// A plugin's frame against the zbuffer plugin's frame of the same scene and camera

// How closely a plugin under test must agree with the zbuffer plugin. The defaults ask for the
// same surface with bit for bit the same depth and barycentrics, ties within 2 float steps, and
// ties on strictly fewer than 0.1 % of the covered pixels.
struct Agreement {
    const char* plugin = "";  // the plugin under test, e.g. "octree-zbuffer"
    const char* label = "";   // how messages name its frame, e.g. "octree"
    // The same surface must have the zbuffer's depth and barycentrics bit for bit; otherwise the
    // same surface is enough and Comparison measures how far its depth and barycentrics are.
    bool bit_identical = true;
    // Both frames are rendered with per-pixel depth-test counts, which must be the same size and
    // are compared (Comparison::coverage_differences).
    bool count_depth_tests = false;
    // A tie: another surface at |a - b| <= tie_float_steps * FLT_EPSILON * max(a, b, tie_floor).
    float tie_float_steps = 2.0f;
    float tie_floor = -std::numeric_limits<float>::infinity();
    // Ties may reach 0.1 % of the covered pixels (<=) rather than stay strictly below it (<).
    bool ties_may_reach_share = false;
};

struct Comparison {
    uint64_t covered = 0;    // pixels the reference covers
    uint64_t same = 0;       // the same face and instance (bit_identical: identical depth and barycentrics)
    uint64_t ties = 0;       // another surface at the same depth, up to float rounding
    uint64_t different = 0;  // anything else
    uint64_t coverage_differences = 0;  // pixels whose depth-test counts differ (count_depth_tests)
    double worst_depth_ulps = 0;        // on covered pixels with the same surface
    double worst_bary = 0;
    std::string first_difference;
};

// Compares `frame`, from the plugin under test, with the zbuffer plugin's `reference`.
inline Comparison compare(const hsr::Frame& frame, const hsr::Frame& reference, const Agreement& agreement) {
    Comparison c;
    REQUIRE(frame.face.size() == reference.face.size());
    REQUIRE(frame.instance.size() == reference.instance.size());
    if (agreement.count_depth_tests) {
        REQUIRE(frame.depth_tests.size() == reference.depth_tests.size());
        for (size_t p = 0; p < reference.depth_tests.size(); ++p)
            c.coverage_differences += frame.depth_tests[p] != reference.depth_tests[p] ? 1 : 0;
    }
    for (size_t p = 0; p < reference.face.size(); ++p) {
        const bool covered = reference.face[p] != HSR_NO_FACE;
        if (covered) ++c.covered;
        const bool same_surface = frame.face[p] == reference.face[p] &&
                                  (reference.instance.empty() || frame.instance[p] == reference.instance[p]);
        const float a = frame.depth[p], b = reference.depth[p];
        if (same_surface) {
            if (covered) {
                c.worst_depth_ulps =
                    std::max(c.worst_depth_ulps, std::abs(double(a) - double(b)) /
                                                     (std::numeric_limits<float>::epsilon() * std::max(b, 1e-6f)));
                c.worst_bary = std::max({c.worst_bary, std::abs(double(frame.bary[2 * p]) - reference.bary[2 * p]),
                                         std::abs(double(frame.bary[2 * p + 1]) - reference.bary[2 * p + 1])});
            }
            const bool identical = a == b && frame.bary[2 * p] == reference.bary[2 * p] &&
                                   frame.bary[2 * p + 1] == reference.bary[2 * p + 1];
            // An uncovered pixel must stay as the host cleared it.
            const bool cleared = a == b && frame.bary[2 * p] == 0.0f && frame.bary[2 * p + 1] == 0.0f;
            if (agreement.bit_identical ? identical : covered || cleared) {
                ++c.same;
                continue;
            }
        } else if (covered && frame.face[p] != HSR_NO_FACE &&
                   std::abs(a - b) <= agreement.tie_float_steps * std::numeric_limits<float>::epsilon() *
                                          std::max({a, b, agreement.tie_floor})) {
            ++c.ties;
            continue;
        }
        if (++c.different == 1)
            c.first_difference = "pixel " + std::to_string(p % reference.width) + "," +
                                 std::to_string(p / reference.width) + ": " + agreement.label + " face " +
                                 std::to_string(frame.face[p]) + " depth " + std::to_string(a) + ", zbuffer face " +
                                 std::to_string(reference.face[p]) + " depth " + std::to_string(b);
    }
    return c;
}

struct Picture {
    hsr::Frame reference;  // the zbuffer plugin's
    hsr::Frame frame;      // the plugin under test's
    Comparison comparison;
};

// Renders the scene with the zbuffer plugin and with the plugin under test, and checks that they
// agree: something covered, no pixel different, and few ties. The caller adds its plugin's checks.
inline Picture check_against_zbuffer(const Agreement& agreement, const hsr_scene& scene, const hsr_camera& camera,
                                     const Settings& settings = {}, const Settings& zbuffer_settings = {}) {
    Picture picture;
    picture.reference = render("zbuffer", scene, camera, zbuffer_settings, agreement.count_depth_tests);
    picture.frame = render(agreement.plugin, scene, camera, settings, agreement.count_depth_tests);
    const Comparison& c = picture.comparison = compare(picture.frame, picture.reference, agreement);
    INFO(camera.width << "x" << camera.height << ": " << c.first_difference);
    CHECK(c.covered > 0);
    CHECK(c.different == 0);
    if (agreement.ties_may_reach_share)
        CHECK(double(c.ties) <= 0.001 * double(c.covered));
    else
        CHECK(double(c.ties) < 0.001 * double(c.covered));
    return picture;
}

}  // namespace surface_tests
