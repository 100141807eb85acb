// The `.scene` text format (docs/scene-format.md), and the light syntax scene files share with the
// command line.
#pragma once

#include "hsr/abi.h"
#include "hsr/camera.hpp"
#include "hsr/language.hpp"
#include "hsr/read_policy.hpp"
#include "hsr/scene.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

namespace hsr {

// "point:1,2,3" or "dir:0,0,1", then optionally ",intensity=0.8", ",color=1/0.9/0.8" (or #rrggbb),
// ",space=world" (default camera). Throws hsr::Error naming the text on any mistake, in `language`.
LightSpec parse_light_spec(std::string_view text, Language language = Language::english);

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
// names (relative paths resolve against the scene file's folder), and a mesh the policy does not
// allow ("mesh 'x' lies outside <the policy's folders>"). The messages are in `language`, but for
// what a mesh file's own reader says about its contents, which stays English inside a frame in
// `language` ("не удалось прочитать модель: ...").
SceneFile load_scene_file(const std::filesystem::path& file, const ReadPolicy& policy = {},
                          Language language = Language::english);
bool is_scene_file(const std::filesystem::path& file);  // extension ".scene", any case

}  // namespace hsr
