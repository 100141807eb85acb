// The steps of hsr render, which render.cpp runs in order: its options, checked; the renderer's
// requests they make (requests.cpp, hsr/renderer.hpp, where every render is assembled); and the
// two ways to write what comes back (render_picture.cpp: a shaded picture; render_line_drawing.cpp:
// the visible edges). A render is a job of one or more frames (frames.hpp); jobs.cpp runs jobs,
// those of a --jobs file or the command line's one.
#pragma once

#include "common/options.hpp"
#include "common/plugins.hpp"
#include "common/threads.hpp"
#include "render/frames.hpp"
#include "render/options.hpp"

#include "hsr/abi.h"
#include "hsr/limits.hpp"
#include "hsr/line_image.hpp"
#include "hsr/lines.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/renderer.hpp"
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

// The renderer's requests for the options: where the scene comes from (a mistake is a
// UsageError), and the view of the options' frame (--yaw, --pitch, its turn); render_picture and
// render_line_drawing make the rest of theirs.
hsr::SceneSource scene_source(const RenderOptions& options);
hsr::ViewRequest view_request(const RenderOptions& options);
// The options scene_source reads, as a key: jobs with equal keys share one load.
std::string scene_load_key(const RenderOptions& options);

// A shaded picture: a hidden-surface plugin and a lighting model.
struct PicturePlugins {
    std::unique_ptr<hsr::HiddenSurfaceRemover> remover;
    std::unique_ptr<hsr::LightingModel> lighting;
};

// What can be checked of the options without plugins or files: one source of the scene, the options
// that go with another, numbers in range, colours. A mistake is a UsageError.
void check_render_options(const RenderOptions& options);

// What --depth-out, --id-out and --normal-out may end with (docs/formats.md, "Outputs").
inline const std::vector<std::string> depth_out_extensions{".png", ".npy", ".pfm", ".exr"};
inline const std::vector<std::string> id_out_extensions{".npy", ".png"};
inline const std::vector<std::string> normal_out_extensions{".npy", ".pfm", ".exr", ".png"};

// Samples per pixel: --samples, else the .scene file's, else 1. Throws a UsageError for an option
// that shows one visibility pass (--depth-out, --id-out, --normal-out, --depth-tests-out, --step)
// with more than 1.
uint32_t picture_samples(const RenderOptions& options, const hsr::LoadedScene* scene);

// The renderer's request for the options' picture of the scene.
hsr::PictureRequest picture_request(const RenderOptions& options, const hsr::LoadedScene& scene);
// Renders the picture, and the depth complexity when the options ask for it.
hsr::Picture render_picture(const RenderOptions& options, hsr::Renderer& renderer, PicturePlugins& plugins);
// Writes the picture to output, with the depth and heat maps the options ask for, and prints what
// was written (and --stats). Reads nothing of the plugins but their names; may run on another
// thread while the next frame renders.
void write_picture(const RenderOptions& options, const hsr::Picture& picture, const PicturePlugins& plugins,
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
void render_line_drawing(const RenderOptions& options, const hsr::Renderer& renderer, LineDrawingPlugin& plugin,
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
    OutputTemplate output, depth_out, id_out, normal_out, overdraw_out, depth_tests_out, trace;
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
// The same for options parsed already (parse_render_options).
RenderJob prepare_render_job(RenderOptions options, PluginRegistries& registries,
                             std::vector<std::filesystem::path>& files);

// The job of the options without its files: the options checked, the frames planned and the plugins
// made from the registry, as prepare_render_job does before it names and checks the files. For a
// front end that keeps what it renders (the Python module); it neither reads nor sets the job's
// --limit options.
RenderJob prepare_render_plugins(RenderOptions options, const hsr::PluginRegistry& registry);

}  // namespace hsr::host
