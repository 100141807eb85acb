// A frame request of hsr view (docs/viewer.md, POST /api/frame) read and checked with the messages
// of hsr render's options, before the model is loaded or a plugin made.
#pragma once

#include "view/server/view_models.hpp"

#include "hsr/camera.hpp"
#include "hsr/edges.hpp"
#include "hsr/line_image.hpp"
#include "hsr/params.hpp"
#include "hsr/plugin_registry.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hsr::host {

// The most pixels along one side of a picture hsr view renders (GET /api/info max_image_side).
constexpr uint32_t view_max_image_side = 4096;

// The per-pixel arrays a frame answer can carry (docs/viewer.md, POST /api/frame `buffers`).
// scene_z: a `camera pixel` scene's own z at each pixel (larger is nearer), null for other cameras.
inline constexpr const char* kBufferNames[] = {"depth", "face", "instance", "object", "depth_tests", "depth_complexity",
                                               "scene_z"};

// Some of the buffers, over the whole picture or over a rectangle of it.
struct BufferSpec {
    std::vector<std::string> names;  // of kBufferNames, each once
    std::optional<std::array<uint32_t, 4>> region;  // x, y, width, height; none: the whole picture
};

// The request, read and checked as far as it can be without the model and the plugins.
struct FrameRequest {
    std::string model, algorithm, lighting;
    std::vector<hsr::Setting> params, lighting_params;
    hsr::CameraSettings view;
    uint32_t width = 512, height = 512;
    std::optional<uint64_t> step;
    std::string language = "en";      // of the step texts: "en" or "ru"
    std::vector<BufferSpec> buffers;  // what the answer carries, in order
    bool buffers_as_list = false;     // asked for as a list: answered as one
    bool picture = true;              // the PNG (false: only the buffers and stats)
    bool wants(const char* buffer) const;
    hsr::EdgeSelection edges = hsr::EdgeSelection::kFeatures;
    hsr::HiddenLines hidden = hsr::HiddenLines::kHidden;
    std::string camera_key;  // the camera and size, for the cache of step totals
};

// Throws ViewError (400, naming the field) for anything wrong with the request on its own.
FrameRequest parse_frame_request(const nlohmann::json& request);

// Each setting checked alone against the plugin's schema, so that the field at fault is known
// ("<field>.<name>"); the message is resolve_params's, as for hsr render. Throws ViewError 400.
void check_settings(const hsr::Plugin& plugin, const std::vector<hsr::Setting>& settings, const char* field);

}  // namespace hsr::host
