// A render job prepared (render.hpp): its options checked on their own, then the plugins they name
// made and the files to write checked, all before jobs.cpp loads the scene and renders it.
#include "render/render.hpp"

#include "common/options.hpp"
#include "common/outputs.hpp"
#include "common/plugins.hpp"
#include "render/frames.hpp"

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"

#include <boost/program_options.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace {

using hsr::host::RenderOptions;
using hsr::host::UsageError;
using hsr::host::kMaxThreads;

}  // namespace

void hsr::host::check_render_options(const RenderOptions& o) {
    const int sources = int(!o.model.empty()) + int(!o.surface.empty()) + int(!o.heightmap.empty()) +
                        int(o.was_given("random-triangles"));
    if (sources == 0)
        throw UsageError("render: no model given (or --surface FORMULA, --heightmap FILE.png or --random-triangles N)");
    if (sources > 1) throw UsageError("render: give one of MODEL, --surface, --heightmap and --random-triangles");
    if (o.was_given("seed") && !o.was_given("random-triangles")) throw UsageError("--seed goes with --random-triangles");
    if (o.was_given("random-triangles")) {
        if (o.random_triangles < 1) throw UsageError("--random-triangles {}: the count must be at least 1", o.random_triangles);
        hsr::host::parse_seed(o.seed);  // parsed again where it is used
        if (o.was_given("color"))
            throw UsageError("--color: random triangles have a colour each (facecolor or any lighting shows them)");
    }
    if (!o.range.empty() && o.surface.empty()) throw UsageError("--range goes with --surface");
    if (o.was_given("heightmap-height") && o.heightmap.empty())
        throw UsageError("--heightmap-height goes with --heightmap");
    if (o.width <= 0 || o.height <= 0 || o.width > hsr::max_image_side || o.height > hsr::max_image_side)
        throw UsageError("image size {}x{}: each side must be between 1 and {}", o.width, o.height, hsr::max_image_side);
    if (o.threads < 0 || o.threads > kMaxThreads)
        throw UsageError("--threads {}: expected 0 (one per core) to {}", o.threads, kMaxThreads);
    hsr::check_limit(&hsr::Limits::lights, o.lights.size(), "--light");
    for (const auto& [option, value] :
         {std::pair{"yaw", o.yaw}, {"pitch", o.pitch}, {"zoom", o.zoom}, {"crease-angle", o.crease_angle}})
        if (!std::isfinite(value)) throw UsageError("--{} must be a finite number", option);
    if (!(o.zoom > 0)) throw UsageError("--zoom must be positive");
    if (o.was_given("opacity") && !(o.opacity >= 0.0f && o.opacity <= 1.0f))
        throw UsageError("--opacity must be between 0 and 1");
    if (o.was_given("near") && !(std::isfinite(o.near_plane) && o.near_plane > 0))
        throw UsageError("--near must be a distance greater than 0");
    std::vector<glm::vec4> planes;
    hsr::host::add_clip_plane_options(o, planes);  // checked here, added again where the camera is made
    if (!(o.fov > 0 && o.fov < 180)) throw UsageError("--fov must be between 0 and 180 degrees");
    if (o.was_given("camera")) {
        if (o.camera.empty()) throw UsageError("--camera needs a camera's name or index");
        for (const char* option : {"eye", "yaw", "pitch", "views"})
            if (o.was_given(option)) throw UsageError("--camera replaces --{}: give one or the other", option);
    }
    if (o.eye.empty()) {
        for (const char* option : {"target", "up"})
            if (o.was_given(option)) throw UsageError("--{} goes with --eye", option);
    } else {
        for (const char* option : {"yaw", "pitch"})
            if (o.was_given(option)) throw UsageError("--eye replaces --{}: give one or the other", option);
        for (const auto& [option, text] : {std::pair{"eye", &o.eye}, {"target", &o.target}, {"up", &o.up}})
            if (!text->empty()) hsr::host::parse_vector_option(*text, option);  // parsed again where it is used
    }
    if (!hsr::host::transparent_background(o))
        hsr::host::parse_color_option(o.background, "background");  // parsed again where it is used
    if (!o.format.empty()) {
        const auto& formats = hsr::host::stdin_model_formats;
        if (std::find(std::begin(formats), std::end(formats), o.format) == std::end(formats))
            throw UsageError("--format '{}': expected {}", hsr::printable(o.format), hsr::host::stdin_model_format_list());
        if (o.model != "-")
            throw UsageError("--format goes with MODEL '-' (standard input); a file's format is its extension");
    } else if (o.model == "-") {
        throw UsageError("MODEL '-' reads standard input: name its format with --format {}",
                         hsr::host::stdin_model_format_list());
    }
    for (const char* standard_input : {"/dev/stdin", "/dev/fd/0", "/proc/self/fd/0"})
        if (o.model == standard_input)
            throw UsageError("MODEL '{}': standard input is read as MODEL '-', with --format {}", o.model,
                             hsr::host::stdin_model_format_list());
    if (!o.color.empty()) hsr::host::parse_color_option(o.color, "color");  // before a long load
    if (!hsr::is_sample_count(o.samples < 0 || o.samples > 16 ? 0u : uint32_t(o.samples)))
        throw UsageError("--samples {}: expected 1, 2, 4, 8 or 16", o.samples);
    // Else a .scene file may set the size or the samples: checked again when its picture is made.
    if (o.was_given("width") || o.was_given("height") || o.was_given("samples"))
        hsr::check_image_pixels(uint32_t(o.width), uint32_t(o.height), uint32_t(o.samples));
    if (o.repeat.empty())
        for (const char* option : {"repeat-gap", "repeat-jitter"})
            if (o.was_given(option)) throw UsageError("--{} goes with --repeat", option);
}

namespace {

// Exactly one of the two is set: --algorithm names a hidden-line plugin (a line drawing) or a
// hidden-surface one (a shaded picture).
struct RenderPlugins {
    std::optional<hsr::host::LineDrawingPlugin> line_drawing;
    std::optional<hsr::host::PicturePlugins> picture;
};

hsr::host::LineDrawingPlugin make_line_drawing_plugin(const RenderOptions& o, const hsr::PluginRegistry& registry,
                                                      const hsr::PluginSpec& algorithm) {
    for (const char* option : {"lighting", "light", "color", "samples", "depth-out", "id-out", "normal-out",
                               "overdraw-out", "depth-tests-out", "threads", "step"})
        if (o.was_given(option))
            throw UsageError("--{} is for hidden-surface plugins; '{}' draws lines", option, algorithm.name);
    if (hsr::host::transparent_background(o))
        throw UsageError("--background none is for hidden-surface pictures; '{}' draws lines", algorithm.name);
    if (o.output == "-")
        throw UsageError("-o -: standard output takes a hidden-surface picture; '{}' draws lines to a file",
                         algorithm.name);
    hsr::host::LineDrawingPlugin plugin;
    plugin.style = hsr::host::make_line_style(o);
    if (o.edges == "features")
        plugin.settings.edges = hsr::EdgeSelection::kFeatures;
    else if (o.edges == "all")
        plugin.settings.edges = hsr::EdgeSelection::kAll;
    else
        throw UsageError("--edges '{}': expected 'all' or 'features'", hsr::printable(o.edges));
    plugin.settings.want_hidden = plugin.style.hidden == hsr::HiddenLines::kDashed;
    plugin.settings.crease_angle_degrees = o.crease_angle;
    plugin.remover = std::make_unique<hsr::HiddenLineRemover>(
        registry.find(HSR_KIND_HIDDEN_LINE_REMOVER, algorithm.name), algorithm.settings);
    return plugin;
}

hsr::host::PicturePlugins make_picture_plugins(const RenderOptions& o, const hsr::PluginRegistry& registry,
                                               const hsr::PluginSpec& algorithm) {
    for (const char* option : {"edges", "hidden", "trace", "line-color", "line-width"})
        if (o.was_given(option))
            throw UsageError("--{} is for hidden-line plugins (appel, roberts, ...); '{}' removes hidden surfaces",
                             option, algorithm.name);
    const hsr::PluginSpec lighting_spec = hsr::parse_plugin_spec(o.lighting);
    hsr::host::PicturePlugins plugins;
    plugins.remover = std::make_unique<hsr::HiddenSurfaceRemover>(
        registry.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, algorithm.name), algorithm.settings);
    plugins.lighting = std::make_unique<hsr::LightingModel>(registry.find(HSR_KIND_LIGHTING_MODEL, lighting_spec.name),
                                                            lighting_spec.settings);
    if (o.was_given("step") && !plugins.remover->has_steps())
        throw hsr::Error("--step: plugin '{}' cannot show its steps ({})", algorithm.name,
                         plugins.remover->plugin().descriptor.abi_minor < 3 ? "it is built against an ABI before 1.3"
                                                                            : "it has no render_steps");
    hsr::host::picture_samples(o, nullptr);
    if (!o.depth_tests_out.empty() && plugins.remover->plugin().descriptor.abi_minor < 1)
        throw hsr::Error("--depth-tests-out: plugin '{}' does not report per-pixel depth tests (ABI 1.0)",
                         algorithm.name);
    return plugins;
}

// The plugins are created, and the options that belong to the other kind refused, before the model is
// loaded: a typo in a plugin name should not wait for a large mesh. A hidden-surface plugin wins over
// a hidden-line plugin of the same name.
RenderPlugins make_render_plugins(const RenderOptions& o, const hsr::PluginRegistry& registry) {
    const hsr::PluginSpec algorithm = hsr::parse_plugin_spec(o.algorithm);
    const bool line_drawing = !registry.contains(HSR_KIND_HIDDEN_SURFACE_REMOVER, algorithm.name) &&
                              registry.find_any({HSR_KIND_HIDDEN_SURFACE_REMOVER, HSR_KIND_HIDDEN_LINE_REMOVER},
                                                algorithm.name).descriptor.kind == HSR_KIND_HIDDEN_LINE_REMOVER;
    RenderPlugins plugins;
    if (line_drawing)
        plugins.line_drawing = make_line_drawing_plugin(o, registry, algorithm);
    else
        plugins.picture = make_picture_plugins(o, registry, algorithm);
    return plugins;
}

// "name-%03d.ext" for "dir/name.ext": where a frame number could go. The folder is left out, as the
// message quotes it already and a long one would cut the example short.
std::string numbered_file_name(const std::string& text) {
    const fs::path path(text);
    return path.stem().string() + "-%03d" + path.extension().string();
}

// The file names of the job's options, each with a frame number when there are several frames; a
// name without one is a UsageError naming the fix.
void set_output_templates(hsr::host::RenderJob& job, bool line_drawing) {
    const RenderOptions& o = job.options;
    const std::size_t frames = job.frames.size();
    if (o.output == "-" && frames > 1)
        throw UsageError("-o -: standard output takes one picture, and this render makes {} frames (write them to "
                         "files named with a frame number)", frames);
    for (const auto& [option, text] : {std::pair<const char*, const std::string&>{"depth-out", o.depth_out},
                                       {"id-out", o.id_out},
                                       {"normal-out", o.normal_out},
                                       {"overdraw-out", o.overdraw_out},
                                       {"depth-tests-out", o.depth_tests_out},
                                       {"trace", o.trace}})
        if (text == "-") throw UsageError("--{} -: only the picture (-o -) can go to standard output", option);
    std::string output = o.output;
    if (output.empty())
        output = std::string(hsr::host::stem_placeholder) + (frames > 1 ? "-%03d" : "") + (line_drawing ? ".svg" : ".png");
    for (const auto& [option, given_text, name] :
         {std::tuple<const char*, const std::string&, hsr::host::OutputTemplate&>{"output", output, job.output},
          {"depth-out", o.depth_out, job.depth_out},
          {"id-out", o.id_out, job.id_out},
          {"normal-out", o.normal_out, job.normal_out},
          {"overdraw-out", o.overdraw_out, job.overdraw_out},
          {"depth-tests-out", o.depth_tests_out, job.depth_tests_out},
          {"trace", o.trace, job.trace}}) {
        if (given_text.empty()) continue;
        const std::string text = hsr::host::with_model_stem(given_text, o);
        name = hsr::host::OutputTemplate(text, option);
        if (frames > 1 && !name.has_number())
            throw UsageError("--{} '{}': {} frames need a frame number in the name, e.g. '{}' (frames count from 0)",
                             option, hsr::printable(text), frames, hsr::printable(numbered_file_name(text)));
    }
}

// Every file of every frame, checked before the work: a mistyped folder should not cost a long
// render. Returns them resolved (check_outputs).
std::vector<fs::path> check_render_outputs(const hsr::host::RenderJob& job, bool line_drawing) {
    std::vector<hsr::host::OutputFile> outputs;
    const std::vector<std::string> output_extensions =
        line_drawing ? std::vector<std::string>{".svg", ".png"} : std::vector<std::string>{".png"};
    for (std::size_t k = 0; k < job.frames.size(); ++k) {
        const RenderOptions o = job.frame_options(k);
        if (o.output != "-") outputs.push_back({"output", o.output, output_extensions});
        for (const auto& [option, path, extensions] :
             {std::tuple<const char*, const std::string&, std::vector<std::string>>{"depth-out", o.depth_out,
                                                                                    hsr::host::depth_out_extensions},
              {"id-out", o.id_out, hsr::host::id_out_extensions},
              {"normal-out", o.normal_out, hsr::host::normal_out_extensions},
              {"overdraw-out", o.overdraw_out, {".png"}},
              {"depth-tests-out", o.depth_tests_out, {".png"}}})
            if (!path.empty()) outputs.push_back({option, path, extensions});
        if (!o.trace.empty()) outputs.push_back({"trace", o.trace, {}});
    }
    return hsr::host::check_outputs(outputs);
}

}  // namespace

hsr::host::RenderOptions hsr::host::RenderJob::frame_options(std::size_t k) const {
    RenderOptions o = options;
    o.yaw = frames[k].yaw;
    o.pitch = frames[k].pitch;
    o.yaw_turn = frames[k].yaw_turn;
    o.step = frames[k].step;
    o.output = output.name(k);
    for (const auto& [text, name] : {std::pair<std::string&, const OutputTemplate&>{o.depth_out, depth_out},
                                     {o.id_out, id_out},
                                     {o.normal_out, normal_out},
                                     {o.overdraw_out, overdraw_out},
                                     {o.depth_tests_out, depth_tests_out},
                                     {o.trace, trace}})
        if (!text.empty()) text = name.name(k);
    return o;
}

hsr::host::RenderJob hsr::host::prepare_render_plugins(RenderOptions options, const hsr::PluginRegistry& registry) {
    RenderJob job;
    job.options = std::move(options);
    if (job.options.help) throw UsageError("--help goes on a command line of its own");
    if (job.options.models.size() > 1)
        throw UsageError("{} models: one render takes one (hsr render MODEL MODEL... renders each of them)",
                         job.options.models.size());
    if (!job.options.jobs.empty()) throw UsageError("--jobs: a job cannot run another jobs file");
    job.frames = plan_frames(job.options);
    check_render_options(job.options);
    RenderPlugins plugins = make_render_plugins(job.options, registry);
    job.line_drawing = std::move(plugins.line_drawing);
    job.picture = std::move(plugins.picture);
    return job;
}

hsr::host::RenderJob hsr::host::prepare_render_job(const std::vector<std::string>& args, PluginRegistries& registries,
                                                   std::vector<fs::path>& files) {
    return prepare_render_job(parse_render_options(args), registries, files);
}

hsr::host::RenderJob hsr::host::prepare_render_job(RenderOptions options, PluginRegistries& registries,
                                                   std::vector<fs::path>& files) {
    hsr::Limits limits;
    try {
        limits = hsr::limits_from_settings(options.limits);
    } catch (const hsr::Error& e) {
        throw UsageError("{}", e.what());
    }
    hsr::set_limits(limits);
    auto registry = registries.find(options.plugin_dirs);
    if (registry == registries.end())
        registry = registries.emplace(options.plugin_dirs, scan_plugins(options.plugin_dirs)).first;
    RenderJob job = prepare_render_plugins(std::move(options), registry->second);
    job.limits = limits;
    set_output_templates(job, job.line_drawing.has_value());
    files = check_render_outputs(job, job.line_drawing.has_value());
    return job;
}
