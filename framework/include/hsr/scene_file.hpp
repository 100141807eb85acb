// The `.scene` text format (docs/scene-format.md), and light specifications shared by scene files
// and the command line.
#pragma once

#include "hsr/abi.h"
#include "hsr/scene.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

namespace hsr {

// A light as the user writes it (docs/scene-format.md, "Lights"). Camera-space vectors use x right,
// y up, z toward the viewer, with the eye at the origin; resolve_light() in camera.hpp turns a spec
// into a world-space hsr_light.
struct LightSpec {
    hsr_light_type type = HSR_LIGHT_DIRECTIONAL;
    glm::vec3 vector{0.0f, 0.0f, 1.0f};  // POINT: position; DIRECTIONAL: unit direction toward the light
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    bool camera_space = true;
};

// "point:1,2,3" or "dir:0,0,1", then optionally ",intensity=0.8", ",color=1/0.9/0.8" (or #rrggbb),
// ",space=world" (default camera). Throws hsr::Error naming the text on any mistake.
LightSpec parse_light_spec(std::string_view text);

// An eye at a given point looking at a target, as in the textbooks' worked examples (an eye at
// (40, 40, 40) looking at the origin), instead of an orbit around the scene: `--eye` on the command
// line, `camera look-at` in a .scene file, make_look_at_camera() in camera.hpp.
struct LookAt {
    glm::vec3 eye{0, 0, 1};
    std::optional<glm::vec3> target;  // unset: the centre of the scene's bounds
    glm::vec3 up{0, 1, 0};            // any vector not along the line of sight; +y stays up on screen
};

// A parsed `.scene` file. Optional fields are unset when the file does not mention them; the
// command line overrides what the file says.
struct SceneFile {
    SceneData scene;
    std::optional<glm::vec3> background;
    bool pixel_camera = false;             // `camera pixel`: see make_pixel_camera()
    std::optional<uint32_t> width, height; // `size W H`; with `camera pixel` always set (derived
                                           // from the scene's bounds when `size` is absent)
    std::optional<float> yaw_degrees, pitch_degrees, zoom, fov_y_degrees;  // `camera orbit ...`
    std::optional<LookAt> look_at;                                         // `camera look-at ...`
    std::optional<bool> orthographic;
    std::optional<uint32_t> samples;       // `samples N`: supersampling (FrameSettings::samples)
    std::vector<LightSpec> lights;
    std::vector<glm::vec4> clip_planes;  // `clip-plane a b c d` and `section z`, in file order
};

// Throws hsr::Error "file:line: message" on any mistake, including problems with the meshes it
// names (relative paths resolve against the scene file's folder).
SceneFile load_scene_file(const std::filesystem::path& file);
bool is_scene_file(const std::filesystem::path& file);  // extension ".scene", any case

}  // namespace hsr
