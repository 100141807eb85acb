// The steps of hsr render, which render.cpp runs in order: its options, the scene they describe, and
// the two ways to render it (render_picture.cpp: a shaded picture; render_line_drawing.cpp: the
// visible edges). A render is a job of one or more frames (frames.hpp); jobs.cpp runs jobs, those of
// a --jobs file or the command line's one.
#pragma once

#include "frames.hpp"
#include "threads.hpp"

#include "hsr/abi.h"
#include "hsr/limits.hpp"
#include "hsr/line_image.hpp"
#include "hsr/lines.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_file.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace hsr::host {

constexpr const char* default_algorithm = "zbuffer";
constexpr const char* default_lighting = "blinn-phong";
constexpr const char* default_light = "dir:-0.5,0.6,1";
constexpr const char* default_background = "0.15/0.15/0.17";
constexpr double max_line_width = 64.0;  // --line-width, pixels

// The options of hsr render as the command line gave them, not yet checked.
struct RenderOptions {
    bool help = false;
    std::string jobs;  // --jobs FILE
    std::string model;
    std::string output;
    std::string algorithm = default_algorithm;
    std::string lighting = default_lighting;
    std::vector<std::string> lights;
    std::vector<std::string> plugin_dirs;
    std::vector<std::string> limits;  // NAME=N (limits.hpp)
    std::string background = default_background;
    std::string color;
    std::string line_color;     // hidden-line plugins; empty: contrasting with the background
    double line_width = 1.0;    // hidden-line plugins: pixels
    int64_t samples = 1;        // supersampling (signed, so that a negative number is refused)
    std::string depth_out;
    std::string overdraw_out;
    std::string depth_tests_out;
    std::string repeat;
    std::string edges = "features";
    std::string hidden_lines = "hidden";
    std::string trace;
    std::string surface, range, heightmap;
    int64_t random_triangles = 0;  // --random-triangles N; signed, so that a negative count is refused
    std::string seed = "1";        // --seed S
    double heightmap_height = 0.0;
    float repeat_gap = 0.25f, repeat_jitter = 0.0f;
    std::string yaw_text = "0", pitch_text = "0";  // --yaw and --pitch: degrees, or A:B:STEP (frames.hpp)
    int64_t views = 1;                              // --views N: a turntable (signed, so that -1 is refused)
    float yaw = 0, pitch = 0;  // this frame's (plan_frames, frames.hpp)
    double yaw_turn = 0;       // this frame's turn of the turntable, degrees added to the yaw
    float zoom = 1, crease_angle = 40, fov = 35;
    std::string eye, target, up;  // x,y,z each: a look-at camera
    std::vector<std::string> clip_planes;  // --clip-plane a,b,c,d (repeatable)
    std::vector<float> sections;           // --section z (repeatable)
    float near_plane = 0;                  // --near, when given
    float opacity = 1;                     // --opacity of a single model
    bool orthographic = false;
    bool stats = false;
    int64_t threads = 0;  // signed, so that a negative number is refused rather than wrapped
    int64_t step = 0;     // --step: stop the hidden-surface algorithm after this step (0: not given)
    int64_t width = 1024, height = 1024;
    // The options named on the command line, as opposed to left at their defaults.
    std::set<std::string> given;

    bool was_given(const std::string& option) const { return given.count(option) > 0; }
};

// A colour option's value, "r/g/b" or "#rrggbb"; a mistake is a UsageError naming the option.
glm::vec3 parse_color_option(const std::string& text, const char* option);
// --seed's value: a whole number from 0 to 2^64 - 1; a mistake is a UsageError.
uint64_t parse_seed(const std::string& text);
// A point or vector option's value, "x,y,z" of finite numbers; a mistake is a UsageError naming
// the option.
glm::vec3 parse_vector_option(const std::string& text, const char* option);
// A --clip-plane value, "a,b,c,d" of finite numbers with (a, b, c) not zero.
glm::vec4 parse_plane_option(const std::string& text, const char* option);
// The sections and clip planes the command line asks for, after those of a .scene file (`file`).
void add_clip_plane_options(const RenderOptions& options, std::vector<glm::vec4>& planes);

// The file the scene comes from: MODEL, or --heightmap's PNG, or "surface" for --surface, or
// "random-triangles" for --random-triangles. Its stem names the default output.
std::filesystem::path model_path(const RenderOptions& options);

// A scene as loaded: the jobs and frames that load it with the same options share it.
struct LoadedScene {
    hsr::SceneData scene;
    std::optional<hsr::SceneFile> file;  // a .scene file's lights, camera, size... (its scene moved out)
    // The scene with its instances copied out, for hidden-line plugins: made on first use.
    const hsr::SceneData& flat_scene();

private:
    std::optional<hsr::SceneData> flat_;
};

// Builds the scene (mesh, .scene file, --surface or --heightmap, then --repeat) and prints its
// warnings.
LoadedScene load_scene(const RenderOptions& options);
// The options load_scene reads, as a key: jobs with equal keys share one load.
std::string scene_load_key(const RenderOptions& options);

// The scene to render and the frame's camera, with what a .scene file asks for besides its meshes.
struct RenderScene {
    const hsr::SceneData& scene;
    hsr_camera camera{};
    std::vector<hsr::LightSpec> lights;   // a .scene file's lights
    std::optional<glm::vec3> background;  // a .scene file's background
    std::optional<uint32_t> samples;      // a .scene file's samples
};

// The camera of the options' frame (--yaw, --pitch, its turn) on the loaded scene. What the command
// line gives explicitly wins over what a .scene file says. line_drawing: the flat scene.
RenderScene make_render_scene(const RenderOptions& options, LoadedScene& loaded, bool line_drawing);

// A shaded picture: a hidden-surface plugin and a lighting model.
struct PicturePlugins {
    std::unique_ptr<hsr::HiddenSurfaceRemover> remover;
    std::unique_ptr<hsr::LightingModel> lighting;
};

// Samples per pixel: --samples, else the .scene file's, else 1. Throws a UsageError for an option
// that shows one visibility pass (--depth-out, --depth-tests-out, --step) with more than 1.
uint32_t picture_samples(const RenderOptions& options, const RenderScene* scene);

// A picture rendered, with what its files and messages need: written by write_picture, which may run
// while the next frame renders.
struct RenderedPicture {
    hsr::Frame frame;
    std::optional<hsr::DepthComplexity> depth_complexity;  // when the options ask for it
    uint32_t samples = 1;
    hsr_scene scene_view{};  // of a scene that outlives the writing
};

// Renders the picture, and the depth complexity when the options ask for it.
RenderedPicture render_picture(const RenderOptions& options, const RenderScene& scene, PicturePlugins& plugins);
// Writes the picture to output, with the depth and heat maps the options ask for, and prints what
// was written (and --stats). Reads nothing of the plugins but their names.
void write_picture(const RenderOptions& options, const RenderedPicture& picture, const PicturePlugins& plugins,
                   const std::filesystem::path& output);

// A line drawing: a hidden-line plugin, which edges it is given and how its lines are drawn.
struct LineDrawingPlugin {
    std::unique_ptr<hsr::HiddenLineRemover> remover;
    hsr::LineSettings settings;
    hsr::LineStyle style;
};

// The line style of --hidden, --line-color, --line-width and the background; lines are drawn on
// white unless --background says otherwise (a .scene file's background is for shaded pictures), in
// a colour that contrasts with it unless --line-color says otherwise. A mistake is a UsageError.
hsr::LineStyle make_line_style(const RenderOptions& options);

// Draws the scene's visible edges to output (SVG or PNG), and writes the --trace file.
void render_line_drawing(const RenderOptions& options, const RenderScene& scene, LineDrawingPlugin& plugin,
                         const std::filesystem::path& output);

// One render of one or more frames: its options checked, its plugins made and the files of every
// frame named and checked, all before any scene is loaded.
struct RenderJob {
    std::string origin;  // "FILE:LINE" of a --jobs line; empty for the command line's render
    RenderOptions options;
    hsr::Limits limits;  // --limit, set while this job is checked, loaded and rendered
    std::optional<LineDrawingPlugin> line_drawing;  // exactly one of the two
    std::optional<PicturePlugins> picture;
    std::vector<FrameView> frames;
    // The files' names, a frame number in each when there are several frames.
    OutputTemplate output, depth_out, overdraw_out, depth_tests_out, trace;
    // The options of frame k: its angles and the names of its files.
    RenderOptions frame_options(std::size_t k) const;
};

// The plugin folders scanned so far, each set once (keyed by --plugin-path).
using PluginRegistries = std::map<std::vector<std::string>, hsr::PluginRegistry>;

// Checks the options (parsed from args), makes the plugins and checks every file the job will write.
// Returns the job and the files, resolved (check_outputs). Mistakes are UsageErrors (or
// boost::program_options errors), anything else hsr::Error.
RenderJob prepare_render_job(const std::vector<std::string>& args, PluginRegistries& registries,
                             std::vector<std::filesystem::path>& files);

}  // namespace hsr::host
