// Cameras: an orbit camera that frames a model's bounds automatically, a look-at camera with its eye
// at a given point, and the pixel-space orthographic camera of textbook raster exercises. Each
// fills every field of hsr_camera.
#pragma once

#include "hsr/abi.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hsr {

// An eye at a given point looking at a target, as in the textbooks' worked examples (an eye at
// (40, 40, 40) looking at the origin), instead of an orbit around the scene: `--eye` on the command
// line, `camera look-at` in a .scene file, make_look_at_camera() below.
struct LookAt {
    glm::vec3 eye{0, 0, 1};
    std::optional<glm::vec3> target;  // unset: the centre of the scene's bounds
    glm::vec3 up{0, 1, 0};            // any vector not along the line of sight; +y stays up on screen
};

// A light as the user writes it (docs/scene-format.md, "Lights"). Camera-space vectors use x right,
// y up, z toward the viewer, with the eye at the origin; resolve_light() below turns a spec
// into a world-space hsr_light; parse_light_spec() in scene_file.hpp reads one from text.
struct LightSpec {
    hsr_light_type type = HSR_LIGHT_DIRECTIONAL;
    glm::vec3 vector{0.0f, 0.0f, 1.0f};  // POINT: position; DIRECTIONAL: unit direction toward the light
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    bool camera_space = true;
};

struct CameraSettings {
    float yaw_degrees = 0, pitch_degrees = 0, zoom = 1;
    bool orthographic = false;
    uint32_t width = 1024, height = 1024;
    float fov_y_degrees = 35;  // perspective only; at zoom z the field of view is narrowed z times
    std::optional<LookAt> look_at;  // set: make_camera() looks from its eye; yaw and pitch are unused
    // Orbit and look-at cameras: the near plane at this view-space distance instead of just in front
    // of the bounds, so that it can cut into the model. Must be positive and nearer than the far plane.
    std::optional<float> near_plane;
    // Sections (hsr_camera.clip_planes): world-space planes (a, b, c, d) keeping a*x + b*y + c*z + d >= 0.
    std::vector<glm::vec4> clip_planes;
    // Orthographic only: half the window's height in world units instead of fitting the bounds (a
    // glTF camera's ymag); zoom still divides it.
    std::optional<double> ortho_half_height;
};

// A camera a model file gives (glTF 2.0 cameras), placed in world space by its node.
struct ModelCamera {
    std::string name;          // the file's name for it, or "camera N"
    bool orthographic = false;
    float yfov_radians = 0;    // perspective: the vertical field of view
    float aspect_ratio = 0;    // perspective: width / height, 0 when the file leaves it open
    float xmag = 0, ymag = 0;  // orthographic: half the window's width and height
    float znear = 0;           // distance of the near plane
    glm::vec3 eye{0}, forward{0, 0, -1}, up{0, 1, 0};
};

// The clip plane of the textbook's section "cut at z <= z_section": keeps world z <= z_section, the
// part away from the default camera (which looks along -z).
glm::vec4 section_plane(float z_section);

// make_look_at_camera() when settings.look_at is set, else make_orbit_camera().
hsr_camera make_camera(glm::vec3 bounds_min, glm::vec3 bounds_max, const CameraSettings& settings);

// Looks at the centre of the bounds' bounding sphere, which fills the smaller image dimension (with a
// 5% margin) at zoom 1; zoom 2 makes everything twice as large. Yaw 0, pitch 0 looks from +z toward
// -z with +y up (the front of an OBJ model); positive yaw moves the eye toward +x around the
// vertical axis, positive pitch raises it (looking down on the model). The near and far planes
// enclose the bounding sphere closely. Throws hsr::Error for unusable settings or bounds.
hsr_camera make_orbit_camera(glm::vec3 bounds_min, glm::vec3 bounds_max, const CameraSettings& settings);

// The eye, target and up of settings.look_at, with the field of view and zoom of `settings`; an
// orthographic window fits the bounds' bounding sphere at zoom 1. The near and far planes enclose
// that sphere as seen from the eye. Throws hsr::Error for an eye on the target, an up vector along
// the line of sight, or numbers that are not finite.
hsr_camera make_look_at_camera(glm::vec3 bounds_min, glm::vec3 bounds_max, const CameraSettings& settings);

// Orthographic camera in pixel units: world (x, y, z) lands at window (x, H - y), so pixel column
// floor(x) and image row H - 1 - floor(y) (origin bottom left, y up); the viewer is on +z looking
// toward -z, so a larger z is nearer (smaller depth, linear in z). z in [z_min, z_max] lies inside
// the clip volume with some room to spare.
hsr_camera make_pixel_camera(uint32_t width, uint32_t height, float z_min, float z_max,
                             const std::vector<glm::vec4>& clip_planes = {});

// A light spec in world space for this camera: camera-space vectors (x right, y up, z toward the
// viewer, eye at the origin) are carried through the inverse view matrix. Throws hsr::Error when the
// result does not fit a float (a point light near the largest float).
hsr_light resolve_light(const LightSpec& light, const hsr_camera& camera);

}  // namespace hsr
