// Orbit and pixel cameras (see camera.hpp). Computed in double precision, stored as float.
//
// Framing: a sphere of radius r seen from distance d covers a cone of half-angle asin(r / d), whose
// image has radius r / sqrt(d^2 - r^2) on the plane at distance 1. Setting that to
// tan(half field of view) / margin gives d = r * sqrt(1 + (margin / tan)^2). Zoom narrows the
// field of view (or the orthographic window) instead of moving the eye, so "twice as big" is exact.
#include "hsr/camera.hpp"

#include "hsr/error.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace hsr {
namespace {

constexpr double frame_margin = 1.05;

void store(float (&out)[16], const glm::dmat4& m) {
    glm::mat4 f(m);
    std::memcpy(out, glm::value_ptr(f), sizeof out);
}

void store(float (&out)[3], const glm::dvec3& v) {
    for (int k = 0; k < 3; ++k) out[k] = static_cast<float>(v[k]);
}

hsr_camera assemble(uint32_t width, uint32_t height, hsr_projection type, const glm::dmat4& view,
                    const glm::dmat4& projection, const glm::dvec3& eye, const glm::dvec3& direction,
                    double near_plane, double far_plane) {
    hsr_camera camera{};
    camera.struct_size = sizeof(hsr_camera);
    camera.width = width;
    camera.height = height;
    camera.projection_type = type;
    store(camera.view, view);
    store(camera.projection, projection);
    store(camera.view_projection, projection * view);
    store(camera.eye, eye);
    store(camera.view_direction, glm::normalize(direction));
    camera.near_plane = static_cast<float>(near_plane);
    camera.far_plane = static_cast<float>(far_plane);
    return camera;
}

void check_size(uint32_t width, uint32_t height) {
    if (width == 0 || height == 0) throw Error("image size {}x{}: both must be at least 1 pixel", width, height);
}

bool finite3(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool is_finite(const hsr_camera& c) {
    auto all_finite = [](const float* v, size_t n) { return std::all_of(v, v + n, [](float x) { return std::isfinite(x); }); };
    return all_finite(c.view, 16) && all_finite(c.projection, 16) && all_finite(c.view_projection, 16) &&
           all_finite(c.eye, 3) && all_finite(c.view_direction, 3) && std::isfinite(c.near_plane) &&
           std::isfinite(c.far_plane);
}

void set_clip_planes(hsr_camera& camera, const std::vector<glm::vec4>& planes) {
    if (planes.size() > HSR_MAX_CLIP_PLANES)
        throw Error("{} clip planes: at most {} are supported", planes.size(), HSR_MAX_CLIP_PLANES);
    camera.clip_plane_count = uint32_t(planes.size());
    for (size_t k = 0; k < planes.size(); ++k) {
        const glm::vec4& p = planes[k];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w)))
            throw Error("clip plane {}: the numbers must be finite", k + 1);
        if (p.x == 0.0f && p.y == 0.0f && p.z == 0.0f)
            throw Error("clip plane {}: its normal (a, b, c) is zero", k + 1);
        for (int c = 0; c < 4; ++c) camera.clip_planes[k][c] = p[c];
    }
}

}  // namespace

glm::vec4 section_plane(float z_section) { return {0.0f, 0.0f, -1.0f, z_section}; }

namespace {

void check_view_settings(glm::vec3 bounds_min, glm::vec3 bounds_max, const CameraSettings& s) {
    check_size(s.width, s.height);
    if (!(std::isfinite(s.zoom) && s.zoom > 0.0f)) throw Error("zoom {} must be a number greater than 0", s.zoom);
    if (!(s.fov_y_degrees > 0.0f && s.fov_y_degrees < 180.0f))
        throw Error("field of view {} degrees must be between 0 and 180", s.fov_y_degrees);
    if (!finite3(bounds_min) || !finite3(bounds_max) || glm::any(glm::greaterThan(bounds_min, bounds_max)))
        throw Error("the scene bounds are not a valid box");
}

struct Sphere {
    glm::dvec3 centre;
    double radius;
};

Sphere bounding_sphere(glm::vec3 bounds_min, glm::vec3 bounds_max) {
    const glm::dvec3 lo(bounds_min), hi(bounds_max);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    double radius = 0.5 * glm::length(hi - lo);
    // A scene too small to tell from a point beside its distance from the origin (float positions
    // carry 7 digits) is framed as a point; anything larger, however small, fills the view.
    if (!(radius > std::max(1e-9 * glm::length(centre), 1e-20))) radius = std::max(1.0, 1e-3 * glm::length(centre));
    return {centre, radius};
}

// Perspective: the field of view narrowed `zoom` times. Orthographic: a window that fits a sphere
// of `radius` (with the margin) at zoom 1.
glm::dmat4 projection_matrix(const CameraSettings& s, double radius, double near_plane, double far_plane) {
    const double aspect = static_cast<double>(s.width) / static_cast<double>(s.height);
    const double zoom = s.zoom;
    if (s.orthographic) {
        const double half = radius * frame_margin / zoom;  // half of the smaller image dimension
        double half_x = aspect >= 1.0 ? half * aspect : half;
        double half_y = aspect >= 1.0 ? half : half / aspect;
        if (s.ortho_half_height) {
            half_y = *s.ortho_half_height / zoom;
            half_x = half_y * aspect;
        }
        return glm::ortho(-half_x, half_x, -half_y, half_y, near_plane, far_plane);
    }
    const double tan_half_y = std::tan(glm::radians(static_cast<double>(s.fov_y_degrees)) / 2.0);
    const double fov_y = 2.0 * std::atan(tan_half_y / zoom);
    return glm::perspective(fov_y, aspect, near_plane, far_plane);
}

// The near plane: the settings' own, or `automatic` (just in front of the bounds).
double choose_near_plane(const CameraSettings& s, double automatic, double far_plane) {
    if (!s.near_plane) return automatic;
    const double near_plane = *s.near_plane;
    if (!(std::isfinite(near_plane) && near_plane > 0.0))
        throw Error("near plane {} must be a distance greater than 0", near_plane);
    if (!(near_plane < far_plane))
        throw Error("near plane {} lies beyond the far plane at {:.6g}: the whole model would be cut away", near_plane,
                    far_plane);
    return near_plane;
}

// Throws `too_large` when a number of the camera does not fit a float.
hsr_camera finish(const CameraSettings& s, const glm::dmat4& view, const glm::dmat4& projection,
                  const glm::dvec3& eye, const glm::dvec3& direction, double near_plane, double far_plane,
                  const std::string& too_large) {
    hsr_camera camera =
        assemble(s.width, s.height, s.orthographic ? HSR_PROJECTION_ORTHOGRAPHIC : HSR_PROJECTION_PERSPECTIVE, view,
                 projection, eye, direction, near_plane, far_plane);
    if (!is_finite(camera)) throw Error("{}", too_large);
    set_clip_planes(camera, s.clip_planes);
    return camera;
}

std::string too_large_scene(double radius) {
    return fmt::format("the scene is too large to view in single precision (its bounding sphere has radius {:.3g})",
                       radius);
}

}  // namespace

hsr_camera make_orbit_camera(glm::vec3 bounds_min, glm::vec3 bounds_max, const CameraSettings& s) {
    check_view_settings(bounds_min, bounds_max, s);
    if (!std::isfinite(s.yaw_degrees) || !std::isfinite(s.pitch_degrees))
        throw Error("yaw and pitch must be finite numbers");
    const auto [centre, radius] = bounding_sphere(bounds_min, bounds_max);

    const double yaw = glm::radians(static_cast<double>(s.yaw_degrees));
    const double pitch = glm::radians(static_cast<double>(s.pitch_degrees));
    const glm::dvec3 toward_eye(std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch));
    const glm::dvec3 up(-std::sin(pitch) * std::sin(yaw), std::cos(pitch), -std::sin(pitch) * std::cos(yaw));

    const double aspect = static_cast<double>(s.width) / static_cast<double>(s.height);
    const double tan_half_y = std::tan(glm::radians(static_cast<double>(s.fov_y_degrees)) / 2.0);
    const double tan_half_min = tan_half_y * std::min(1.0, aspect);
    const double distance = radius * std::sqrt(1.0 + (frame_margin / tan_half_min) * (frame_margin / tan_half_min));
    const glm::dvec3 eye = centre + distance * toward_eye;

    // Tight around the sphere; never at or behind the eye.
    const double far_plane = distance + 1.02 * radius;
    const double near_plane = choose_near_plane(s, std::max(distance - 1.02 * radius, 1e-3 * far_plane), far_plane);

    const glm::dmat4 view = glm::lookAt(eye, centre, up);
    return finish(s, view, projection_matrix(s, radius, near_plane, far_plane), eye, -toward_eye, near_plane,
                  far_plane, too_large_scene(radius));
}

hsr_camera make_look_at_camera(glm::vec3 bounds_min, glm::vec3 bounds_max, const CameraSettings& s) {
    check_view_settings(bounds_min, bounds_max, s);
    if (!s.look_at) throw Error("internal error: a look-at camera without an eye");
    const LookAt& look = *s.look_at;
    const auto [centre, radius] = bounding_sphere(bounds_min, bounds_max);
    const glm::dvec3 eye(look.eye);
    const glm::dvec3 target = look.target ? glm::dvec3(*look.target) : centre;
    const glm::dvec3 up(look.up);
    if (!finite3(look.eye) || !finite3(glm::vec3(target)) || !finite3(look.up))
        throw Error("look-at camera: the eye, target and up must be finite numbers");
    const glm::dvec3 direction = target - eye;
    if (!(glm::length(direction) > 0.0)) throw Error("look-at camera: the eye and the target are the same point");
    if (!(glm::length(glm::cross(glm::normalize(direction), up)) > 1e-6 * glm::length(up)))
        throw Error("look-at camera: the up vector ({}, {}, {}) is zero or along the line of sight", look.up.x,
                    look.up.y, look.up.z);

    // Around the scene's bounding sphere as seen from the eye; an eye inside it sees from near the eye.
    const double distance = glm::length(centre - eye);
    const double far_plane = distance + 1.02 * radius;
    const double near_plane = choose_near_plane(s, std::max(distance - 1.02 * radius, 1e-3 * far_plane), far_plane);
    const glm::dmat4 view = glm::lookAt(eye, target, up);
    return finish(s, view, projection_matrix(s, radius, near_plane, far_plane), eye, direction, near_plane,
                  far_plane,
                  distance > 1e6 * radius ? fmt::format("look-at camera: the eye is too far from the scene for single "
                                                        "precision ({:.3g} away, the scene's radius is {:.3g})",
                                                        distance, radius)
                                          : too_large_scene(radius));
}

hsr_camera make_camera(glm::vec3 bounds_min, glm::vec3 bounds_max, const CameraSettings& settings) {
    return settings.look_at ? make_look_at_camera(bounds_min, bounds_max, settings)
                            : make_orbit_camera(bounds_min, bounds_max, settings);
}

hsr_camera make_pixel_camera(uint32_t width, uint32_t height, float z_min, float z_max,
                             const std::vector<glm::vec4>& clip_planes) {
    check_size(width, height);
    if (!std::isfinite(z_min) || !std::isfinite(z_max) || z_min > z_max)
        throw Error("pixel camera: depth range [{}, {}] is not valid", z_min, z_max);
    // The eye sits above the image centre, in front of the nearest z; view space is world space
    // shifted there, so the projection maps x in [0, W] and y in [0, H] onto the whole window.
    const double pad = std::max(1.0, 1e-3 * (static_cast<double>(z_max) - z_min));
    const double w = width, h = height;
    const glm::dvec3 eye(w / 2.0, h / 2.0, static_cast<double>(z_max) + 2.0 * pad);
    const double near_plane = pad;
    const double far_plane = eye.z - z_min + pad;
    const glm::dmat4 view = glm::translate(glm::dmat4(1.0), -eye);
    const glm::dmat4 projection = glm::ortho(-w / 2.0, w / 2.0, -h / 2.0, h / 2.0, near_plane, far_plane);
    hsr_camera camera = assemble(width, height, HSR_PROJECTION_ORTHOGRAPHIC, view, projection, eye,
                                       glm::dvec3(0, 0, -1), near_plane, far_plane);
    if (!is_finite(camera)) throw Error("pixel camera: depth range [{}, {}] is too large for single precision", z_min, z_max);
    set_clip_planes(camera, clip_planes);
    return camera;
}

hsr_light resolve_light(const LightSpec& light, const hsr_camera& camera) {
    glm::vec3 vector = light.vector;
    if (light.camera_space) {
        glm::mat4 view;
        std::memcpy(glm::value_ptr(view), camera.view, sizeof camera.view);
        const glm::mat4 camera_to_world = glm::inverse(view);
        vector = light.type == HSR_LIGHT_POINT ? glm::vec3(camera_to_world * glm::vec4(vector, 1.0f))
                                               : glm::mat3(camera_to_world) * vector;
    }
    if (light.type == HSR_LIGHT_DIRECTIONAL) vector = glm::normalize(vector);
    if (!finite3(vector))
        throw Error("a light at {}, {}, {} ({} space) is too far away for single precision", light.vector.x,
                    light.vector.y, light.vector.z, light.camera_space ? "camera" : "world");
    hsr_light out{};
    out.struct_size = sizeof out;
    out.type = light.type;
    for (int k = 0; k < 3; ++k) {
        out.vector[k] = vector[k];
        out.color[k] = light.color[k];
    }
    out.intensity = light.intensity;
    return out;
}

}  // namespace hsr
