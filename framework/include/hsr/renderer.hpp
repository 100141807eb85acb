// The one place where a render is assembled: a scene loaded once (a mesh, a .scene file, a surface,
// a height map or random triangles, then made transparent or repeated), and for any view, plugins
// and their parameters the frame, its buffers, its statistics, or the picture at step N with what
// step N changed. hsr render (--views, --jobs), hsr bench and hsr view all render through it; the
// front ends only turn their options or requests into the structs below and write what comes back.
//
// What is set in a request wins; what is left unset is taken from the .scene file, then from the
// defaults (hsr/defaults.hpp), so that a command line, a viewer request and a Python call mean the
// same thing.
#pragma once

#include "hsr/abi.h"
#include "hsr/camera.hpp"
#include "hsr/defaults.hpp"
#include "hsr/fragment_lists.hpp"
#include "hsr/language.hpp"
#include "hsr/instancing.hpp"
#include "hsr/lines.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/read_policy.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"
#include "hsr/surface.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace hsr {

// default_background (hsr/defaults.hpp) as a colour.
glm::vec3 default_background_color();

// Where a scene comes from: exactly one of a model file (a mesh, or a .scene file), a formula, a
// height map and random triangles; then optionally made transparent and repeated into a grid.
struct SceneSource {
    std::filesystem::path model;
    struct Formula {
        std::string text;  // z = f(x, y), muParser syntax
        SurfaceRange range;
        glm::vec3 color{0.8f};
    };
    std::optional<Formula> formula;
    std::filesystem::path heightmap;  // a greyscale PNG
    HeightmapOptions heightmap_options;
    struct RandomTriangles {
        uint64_t count = 0, seed = 1;
    };
    std::optional<RandomTriangles> random_triangles;
    MeshOptions mesh;               // a mesh file's crease angle and colour
    std::optional<float> opacity;   // of a single model (a .scene file gives its objects their own)
    std::optional<InstanceGrid> repeat;
    std::string repeat_text;        // the grid as the user wrote it, for messages
    Language language = Language::english;  // of a .scene file's error messages (load_scene_file)

    // The file the scene comes from, or "surface" or "random-triangles": its stem names outputs.
    std::filesystem::path path() const;
};

// A scene as loaded, with what a .scene file says besides its meshes. Loaded once, it serves any
// number of frames, from several threads.
class LoadedScene {
public:
    // Reads and builds the scene; only files the policy allows are read. Throws hsr::Error (a
    // UsageError for options that do not go together), with the reader's file and line.
    static std::shared_ptr<LoadedScene> load(const SceneSource& source, const ReadPolicy& policy = {});
    // A scene built elsewhere (hsr bench's subdivided and deep scenes, Python's arrays), with no
    // .scene file; source_name names it in messages.
    static std::shared_ptr<LoadedScene> of(SceneData scene, std::string source_name = {});

    const SceneData& scene() const { return scene_; }
    // A .scene file's lights, camera, size... (its scene moved into scene()); unset for other sources.
    const std::optional<SceneFile>& file() const { return file_; }
    // The cameras the model file gives (glTF), and the file's name for messages.
    const std::vector<ModelCamera>& cameras() const { return cameras_; }
    const std::string& source_name() const { return source_name_; }
    // The scene with its instances copied out, for hidden-line plugins: made on first use.
    const SceneData& flat_scene() const;
    // About what it holds in memory, for a cache's bound.
    uint64_t memory() const;

private:
    SceneData scene_;
    std::optional<SceneFile> file_;
    std::vector<ModelCamera> cameras_;
    std::string source_name_;
    mutable std::once_flag flat_once_;
    mutable std::optional<SceneData> flat_;
};

// The view of one frame. Unset fields take the .scene file's value, then CameraSettings' default.
struct ViewRequest {
    std::optional<uint32_t> width, height;
    std::optional<float> yaw_degrees, pitch_degrees, zoom, fov_y_degrees;
    std::optional<bool> orthographic;
    std::optional<LookAt> look_at;   // unset: the .scene file's, unless orbit_given
    bool orbit_given = false;        // yaw, pitch or a turntable asked for: the file's look-at is not used
    double yaw_turn_degrees = 0;     // a turntable's turn, added to the yaw
    std::optional<float> near_plane;
    std::vector<glm::vec4> clip_planes;  // world space, after the .scene file's
    // A .scene file with `camera pixel` keeps its own size whatever width and height say.
    bool pixel_camera_keeps_size = false;
    // A camera of the model file (glTF), by name or index: its eye, direction, field of view or
    // window and near plane; the width follows from its aspect ratio unless given.
    std::string model_camera;
};

// A shaded picture: a hidden-surface plugin and a lighting model.
struct PictureRequest {
    ViewRequest view;
    std::vector<LightSpec> lights;          // empty: the .scene file's, else default_light
    std::optional<glm::vec3> background;    // unset: the .scene file's, else default_background
    bool transparent_background = false;    // instead of a background colour: Frame::alpha (frame.hpp)
    std::optional<uint32_t> samples;        // unset: the .scene file's, else 1
    unsigned threads = 0;                   // shading threads; 0: as tbb::global_control allows
    bool count_depth_tests = false;         // Frame::depth_tests
    bool depth_complexity = false;          // Picture::depth_complexity
    // Depth complexity over this rectangle only, clipped to the picture (none when nothing of it
    // is left); unset: over the whole picture.
    std::optional<PixelRegion> depth_complexity_region;
    // Stop the algorithm after this step (1-based) and give the picture as that step left it.
    std::optional<uint64_t> step;
    // With step: also the visibility buffers as the step before left them (Picture::before) and
    // the number of steps of the whole run (Picture::step_total), which is counted once per view,
    // plugin and parameters and then kept; the step then is one run of the plugin.
    bool step_context = false;
    StepProgress* step_progress = nullptr;  // with step: how far the counting and the run have got
    std::string step_language;  // with step: the language of step texts (ABI 1.5); empty: English
};

struct Picture {
    Frame frame;  // shaded: its barycentrics (Frame::bary) are let go
    hsr_camera camera{};
    hsr_scene scene{};  // what was rendered; valid while the LoadedScene lives
    uint32_t samples = 1;
    std::shared_ptr<const DepthComplexity> depth_complexity;  // shared with the renderer's cache
    // With PictureRequest::step_context: the step shown (the last one when the request asked for a
    // step past the end), the steps of the whole run, and the visibility buffers (depth, face,
    // instance, depth tests) after the step before it: empty arrays before step 2.
    uint64_t step_shown = 0, step_total = 0;
    Frame before;
};

// A line drawing: a hidden-line plugin, which edges it is given and, for a viewer, a step.
struct LineRequest {
    ViewRequest view;
    LineSettings settings;
    // Keep the segments up to this trace event (1-based) and record it; past the end: the last.
    std::optional<uint64_t> step;
};

struct LinePicture {
    LineDrawing drawing;
    hsr_camera camera{};
    hsr_scene scene{};  // the flat scene drawn; valid while the LoadedScene lives
};

class Renderer {
public:
    explicit Renderer(std::shared_ptr<const LoadedScene> scene);

    const LoadedScene& loaded() const { return *scene_; }
    const std::shared_ptr<const LoadedScene>& shared_scene() const { return scene_; }

    // The camera of a view of this scene. Throws hsr::Error (UsageError for options that do not
    // go together) for a size over the limits or a view no camera can make.
    hsr_camera camera(const ViewRequest& view) const;
    // The lights of a request in world space, for this camera.
    std::vector<hsr_light> lights(const std::vector<LightSpec>& requested, const hsr_camera& camera) const;

    // One shaded frame (supersampled when asked for). Not to be called concurrently with the same
    // plugin instances.
    Picture picture(const PictureRequest& request, HiddenSurfaceRemover& remover, LightingModel& lighting);
    // One line drawing of the flat scene.
    LinePicture lines(const LineRequest& request, HiddenLineRemover& remover) const;
    // The outline of the steps of this view with the remover (step_outline.hpp), in one whole run
    // step by step with texts in `language`; its total is kept as a step request's
    // (PictureRequest::step_context), so that a step request of the same view counts no steps again.
    // progress, when given, counts the run's steps.
    StepOutline step_outline(const ViewRequest& view, HiddenSurfaceRemover& remover, const std::string& language,
                             StepProgress* progress = nullptr);
    // How many triangles cover each pixel centre (pipeline.hpp), for this view.
    DepthComplexity depth_complexity(const hsr_camera& camera) const;

private:
    // depth_complexity(), measured once per camera and region and kept (the last few), since it depends on
    // nothing else: a viewer switching plugins or comparing two keeps its camera.
    std::shared_ptr<const DepthComplexity> kept_depth_complexity(const hsr_camera& camera,
                                                                 const std::optional<PixelRegion>& region);
    uint64_t count_steps(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                         StepProgress* progress);
    void keep_step_total(const std::string& key, uint64_t total);

    std::shared_ptr<const LoadedScene> scene_;
    std::mutex caches_mutex_;
    std::map<std::string, uint64_t> step_totals_;  // by plugin, parameters and camera
    std::list<std::pair<std::string, std::shared_ptr<const DepthComplexity>>> depth_complexities_;  // newest first
};

// One view and its plugins rendered again and again into the same buffers, as a benchmark or an
// animation renders: the scene is copied out once for plugins built before instances (ABI 1.0), and
// no buffer is allocated again between frames. The scene, the camera and the plugins must outlive
// the loop; the context's lights are copied.
class FrameLoop {
public:
    FrameLoop(const hsr_scene& scene, const hsr_camera& camera, const hsr_shading_context& context,
              const FrameSettings& settings, HiddenSurfaceRemover& remover, LightingModel& lighting);
    FrameLoop(const FrameLoop&) = delete;
    FrameLoop& operator=(const FrameLoop&) = delete;

    // One frame: visibility, then shading (fragment lists composited for a plugin that returns
    // them). The frame's counters are this call's alone.
    const Frame& render();
    const hsr_scene& scene() const { return scene_; }

private:
    std::optional<SceneData> flat_;
    hsr_scene scene_{};
    const hsr_camera& camera_;
    std::vector<hsr_light> lights_;
    hsr_shading_context context_{};
    FrameSettings settings_;
    HiddenSurfaceRemover& remover_;
    LightingModel& lighting_;
    Frame frame_;
    FragmentLists fragments_;
};

}  // namespace hsr
