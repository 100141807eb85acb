// One frame: visibility by a hidden-surface plugin, then shading of every visible pixel, exactly
// once, in batches by a lighting plugin. Plugins meet only here, through the C ABI.
#pragma once

#include "hsr/abi.h"
#include "hsr/fragment_lists.hpp"
#include "hsr/frame.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/step_outline.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hsr {

// Largest image the host allocates: each side at most this many pixels.
constexpr uint32_t max_image_side = 16384;
// Throws hsr::Error for a zero or absurd size, before anything is allocated.
void check_image_size(uint32_t width, uint32_t height);
// Checks the pixels rendered for a picture, width x height x samples (each sample is a whole frame),
// against the image-pixels limit (limits.hpp).
void check_image_pixels(uint32_t width, uint32_t height, uint32_t samples = 1);

// The sample positions of a pixel for supersampling, as offsets from its centre in pixels (x right,
// y down): the standard multisample patterns of Direct3D 10.1+ and Vulkan (standardSampleLocations)
// for 1, 2, 4, 8 and 16 samples; 4 is the rotated grid (RGSS). Throws hsr::Error for another count.
std::vector<glm::vec2> sample_offsets(uint32_t samples);
bool is_sample_count(uint32_t samples);  // 1, 2, 4, 8 or 16
// The camera that sees at each pixel centre what `camera` sees at that centre plus offset (pixels,
// x right, y down): its projection shifted in NDC, so that any hidden-surface plugin samples there.
hsr_camera offset_camera(const hsr_camera& camera, glm::vec2 offset);

// Clears and fills a visibility buffer of camera.width x camera.height with the remover. Throws
// hsr::Error when the scene has instances and the remover predates them (ABI 1.0): render_frame()
// copies the instances out for such plugins, see needs_flat_scene().
void resolve_visibility(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                        Frame& frame, bool count_depth_tests = false);
// The same step by step (ABI 1.3; throws hsr::Error for a plugin without steps): stops after step
// stop_after (0: every step), and sets frame.steps; with keep_before, frame.steps->before too, read
// from the buffers while the plugin reports step stop_after - 1 (abi.h: render_steps).
// progress, when given, has its `steps` set at each step. language: the step texts' (ABI 1.5,
// hsr_step_sink.language), "en" or "ru"; empty: English. outline, when given, gets every step.
void resolve_visibility_steps(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                              Frame& frame, uint64_t stop_after, bool count_depth_tests = false,
                              bool keep_before = false, StepProgress* progress = nullptr,
                              const std::string& language = {}, StepOutline* outline = nullptr);

// True when a plugin was built before instancing (ABI 1.0) and the scene has instances: it must be
// given flatten_instances(scene) instead.
bool needs_flat_scene(const Plugin& plugin, const hsr_scene& scene);
// Throws hsr::Error when the camera has clip planes (sections) and the plugin predates them (ABI
// 1.4): it would ignore them and draw what they cut away.
void check_clip_planes_known(const Plugin& plugin, const hsr_camera& camera);

// Resolves visibility with a remover's render_fragments: frame's visibility buffer as render()
// fills it, and the fragment lists. Throws hsr::Error for a remover without fragment lists.
void resolve_fragments(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                       Frame& frame, FragmentLists& lists, bool count_depth_tests = false);

// Shades every covered pixel of frame's visibility buffer; uncovered pixels get the background.
void shade_frame(const hsr_scene& scene, LightingModel& lighting, const hsr_shading_context& context,
                 const FrameSettings& settings, Frame& frame);

// Whether an object of the scene is less than opaque (hsr_scene.object_opacity, ABI 1.4).
bool has_transparency(const hsr_scene& scene);

// A shaded frame. A remover with fragment lists (ABI 1.4, FragmentLists) gives an anti-aliased
// picture with transparency; any other one a picture of one surface per pixel, and a scene with
// transparent objects is an error for it. Rendering step by step uses one surface per pixel.
Frame render_frame(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                   LightingModel& lighting, const hsr_shading_context& context, const FrameSettings& settings);

// render_frame() once per sample of settings.samples, each with the camera offset to the sample
// (offset_camera), for any remover: rgb is the mean of the samples' colours, the counters and times
// are their sums, and depth, face, bary and instance are the first sample's (at an offset from the
// pixel centres). With 1 sample it is render_frame(). Steps and depth-test counts are of one pass:
// asked for with more samples, they are an hsr::Error.
Frame render_supersampled_frame(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                                LightingModel& lighting, const hsr_shading_context& context,
                                const FrameSettings& settings);

// Depth complexity: how many triangles cover each pixel centre (all of them, front- and
// back-facing, before any depth test), counted with the same rasterization rules as the z-buffer
// plugins. An independent measure of the scene, not of an algorithm.
// Measured over a rectangle of the picture, or over all of it; the totals are the rectangle's.
struct PixelRegion {
    uint32_t x = 0, y = 0, width = 0, height = 0;
    bool operator==(const PixelRegion&) const = default;
};
struct DepthComplexity {
    uint32_t x = 0, y = 0;          // the measured rectangle's corner in the picture
    uint32_t width = 0, height = 0; // and its size
    std::vector<uint32_t> count;    // per pixel of the rectangle, row by row
    uint64_t fragments = 0;         // sum of count
    uint64_t covered_pixels = 0;    // pixels with count > 0
    uint32_t max = 0;
    double mean_over_covered() const { return covered_pixels ? double(fragments) / double(covered_pixels) : 0.0; }
};
// region: a rectangle inside the picture (an hsr::Error if it is empty or reaches outside); none:
// the whole picture.
DepthComplexity measure_depth_complexity(const hsr_scene& scene, const hsr_camera& camera,
                                         const std::optional<PixelRegion>& region = std::nullopt);

// Triangles drawn: the sum over instances, or the mesh's count when there are none.
uint64_t drawn_triangle_count(const hsr_scene& scene);

// The shading context for a camera: where the viewer is, and the lights (already in world space).
hsr_shading_context make_shading_context(const hsr_camera& camera, const std::vector<hsr_light>& lights);

}  // namespace hsr
