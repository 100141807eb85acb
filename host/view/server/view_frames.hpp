// hsr view's frames: a JSON request (docs/viewer.md, "The HTTP API") checked with the same code and
// messages as hsr render's options, the model and plugins it names (kept loaded between frames),
// rendered with the framework's pipeline, and answered as JSON with the picture as a PNG data URL.
#pragma once

#include "view/server/view_models.hpp"

#include "hsr/frame.hpp"
#include "hsr/plugin_registry.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>

namespace hsr::host {

// A frame's answer: JSON, and the bytes of the arrays it refers to. An array appears in the JSON as
// {"array": "float32" or "uint32", "offset": bytes into `arrays`, "length": values}, each at a
// multiple of 4 bytes, little-endian.
struct FrameAnswer {
    nlohmann::json body;
    std::string arrays;
};

// The content type of an answer with arrays, and the start of its body: the JSON's length in bytes
// (4 bytes, little-endian), the JSON, spaces up to a multiple of 4 bytes; the arrays follow.
inline constexpr const char* kFrameWithArraysType = "application/vnd.hsr.frame";
std::string frame_with_arrays_head(const FrameAnswer& answer);

// The most steps, and pixels over all of them, one POST /api/steps-zip renders: each step renders
// the algorithm again up to it, and the archive is held in memory.
inline constexpr uint64_t kMaxZipSteps = 200;
inline constexpr uint64_t kMaxZipPixels = kMaxZipSteps * 1024 * 1024;

class FrameRenderer {
public:
    // find_model: the entry of a model id (ViewError 404 for none); read_policy: what a model's
    // .scene file may read besides.
    using FindModel = std::function<ModelEntry(const std::string& id)>;
    FrameRenderer(const hsr::PluginRegistry& registry, FindModel find_model, hsr::ReadPolicy read_policy);
    ~FrameRenderer();
    FrameRenderer(const FrameRenderer&) = delete;
    FrameRenderer& operator=(const FrameRenderer&) = delete;

    // POST /api/frame and POST /api/compare. Throw ViewError for a bad request (status 400 or 404)
    // and hsr::Error for a plugin's failure. Safe to call from several threads: one frame renders at
    // a time, so no plugin instance is ever called concurrently.
    // progress, when given, follows a step request's counting and run.
    FrameAnswer frame(const nlohmann::json& request, hsr::StepProgress* progress = nullptr);
    FrameAnswer compare(const nlohmann::json& request);
    // POST /api/steps: the outline of a frame request's steps (hsr/step_outline.hpp) as JSON, made
    // in one whole run step by step and kept for the last few requests. progress counts the run.
    nlohmann::json steps(const nlohmann::json& request, hsr::StepProgress* progress = nullptr);
    // POST /api/steps-zip: the pictures of steps `from`..`to` of a frame request (its fields
    // "from" and "to"), each rendered as POST /api/frame renders it and encoded as hsr render
    // --step writes it, as a stored ZIP of step-001.png, step-002.png, ... Throws ViewError 400
    // for a range that is not one, over kMaxZipSteps steps or over kMaxZipPixels pixels in all.
    std::string steps_zip(const nlohmann::json& request);


private:
    struct State;
    std::unique_ptr<State> state_;
};

// Standard base64 (RFC 4648, with padding) of bytes, for the PNG data URLs.
std::string base64(const void* bytes, std::size_t size);

}  // namespace hsr::host
