// hsr render: its options, parsed, then checked on their own, then the plugins they name found and
// the files to write checked, all before the scene is loaded and rendered (render.hpp) by jobs.cpp.
#include "commands.hpp"
#include "frames.hpp"
#include "jobs.hpp"
#include "render.hpp"

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"

#include <boost/program_options.hpp>

#include <malloc.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

using hsr::host::RenderOptions;
using hsr::host::UsageError;
using hsr::host::kMaxThreads;


// The options shown by --help; parsing stores their values into o.
po::options_description render_option_descriptions(RenderOptions& o) {
    using hsr::host::default_algorithm;
    using hsr::host::default_background;
    using hsr::host::default_lighting;
    po::options_description general("hsr render MODEL [options]: render a mesh or .scene file to PNG");
    general.add_options()
        ("help,h", "show this help, with every plugin's parameters")
        ("output,o", po::value(&o.output),
         "file to write: PNG for a hidden-surface plugin (default <model name>.png); SVG or PNG for a "
         "hidden-line plugin (default <model name>.svg). With several frames, a frame number goes in every "
         "file name: %d, or %03d for 000, 001, ... (frames count from 0; %% is a % sign; default "
         "<model name>-%03d.png)")
        ("jobs", po::value(&o.jobs),
         "FILE: run the renders of FILE, one line each of the options of hsr render (# starts a comment "
         "line); each model is loaded once for all the lines that name it (docs/many-frames.md)")
        ("algorithm,a", po::value(&o.algorithm)->default_value(default_algorithm),
         "hidden-surface or hidden-line plugin: NAME[:key=value,...]")
        ("lighting,l", po::value(&o.lighting)->default_value(default_lighting),
         "lighting plugin: NAME[:key=value,...]")
        ("width", po::value(&o.width)->default_value(1024), "image width in pixels")
        ("height", po::value(&o.height)->default_value(1024), "image height in pixels")
        ("yaw", po::value(&o.yaw_text)->default_value("0"),
         "turn the model about the vertical axis, degrees; A:B:STEP renders a frame at each of A, A+STEP, ... "
         "up to B")
        ("pitch", po::value(&o.pitch_text)->default_value("0"),
         "tilt: positive looks from above, degrees; A:B:STEP as for --yaw (the outer loop)")
        ("views", po::value(&o.views)->default_value(1),
         "N: a turntable of N frames, the yaw turned by 360/N degrees from one to the next")
        ("zoom", po::value(&o.zoom)->default_value(1), "magnification; 1 fits the model to the view")
        ("ortho", po::bool_switch(&o.orthographic), "orthographic instead of perspective projection")
        ("fov", po::value(&o.fov)->default_value(35), "vertical field of view of the perspective projection, degrees")
        ("eye", po::value(&o.eye), "x,y,z: look from this point (world space) instead of orbiting with --yaw and "
         "--pitch; the picture is not framed to the model, --zoom still magnifies")
        ("target", po::value(&o.target), "x,y,z: the point the --eye looks at (default: the centre of the model's bounds)")
        ("up", po::value(&o.up), "x,y,z: the direction that is up on screen with --eye (default 0,1,0)")
        ("near", po::value(&o.near_plane), "view-space distance of the near plane (default: just in front of the "
                                           "model), so that it can cut into the model")
        ("section", po::value(&o.sections)->composing(),
         "z: cut the model at z (world space) and keep z <= z, the part away from the default view (repeatable)")
        ("clip-plane", po::value(&o.clip_planes)->composing(),
         "a,b,c,d: keep only a*x + b*y + c*z + d >= 0 (world space; repeatable, at most 8 with --section)")
        ("light", po::value(&o.lights)->composing(),
         "light, repeatable: point:x,y,z or dir:x,y,z (toward the light), camera space (x right, y up, "
         "z toward you), optionally followed by ,intensity=I,color=r/g/b (docs/scene-format.md). "
         "Default: dir:-0.5,0.6,1")
        ("background", po::value(&o.background)->default_value(default_background), "background colour r/g/b or #rrggbb")
        ("opacity", po::value(&o.opacity),
         "opacity of the model, 0 (invisible) to 1 (opaque; the default); a .scene file gives each object an "
         "`opacity` line. Needs an algorithm that returns fragment lists (a-buffer)")
        ("color", po::value(&o.color), "model colour r/g/b or #rrggbb (a mesh file's faces; default 0.8/0.8/0.8)")
        ("samples", po::value(&o.samples)->default_value(1),
         "hidden-surface plugins: anti-aliasing by supersampling, 1, 2, 4, 8 or 16 samples per pixel "
         "(4: rotated grid); docs/antialiasing.md")
        ("line-color", po::value(&o.line_color),
         "hidden-line plugins: line colour r/g/b or #rrggbb (default: dark on a light background, light on a "
         "dark one); hidden lines are drawn halfway to the background")
        ("line-width", po::value(&o.line_width)->default_value(1.0, "1"),
         fmt::format("hidden-line plugins: line width in pixels, above 0 and at most {} (the outline is drawn "
                     "twice as wide)", hsr::host::max_line_width).c_str())
        ("crease-angle", po::value(&o.crease_angle)->default_value(40),
         "degrees: shading normals are not smoothed across edges sharper than this (and, for "
         "hidden-line plugins, such edges are creases)")
        ("depth-out", po::value(&o.depth_out), "also write the depth buffer as a greyscale PNG (near = white)")
        ("overdraw-out", po::value(&o.overdraw_out),
         "also write the scene's depth complexity (surfaces over each pixel) as a heat-map PNG")
        ("depth-tests-out", po::value(&o.depth_tests_out),
         "also write where the algorithm made depth tests (per pixel) as a heat map on the same scale "
         "as --overdraw-out: what a hierarchy saves shows as darker")
        ("repeat", po::value(&o.repeat),
         "CxRxL: place the model C across, R up and L layers deep (a deep scene; the mesh is stored once)")
        ("repeat-gap", po::value(&o.repeat_gap)->default_value(0.25f, "0.25"),
         "space between repeated copies, as a fraction of the model's size")
        ("repeat-jitter", po::value(&o.repeat_jitter)->default_value(0.0f, "0"),
         "turn each copy about the vertical by a random angle up to this many degrees")
        ("edges", po::value(&o.edges)->default_value("features"),
         "hidden-line plugins: which edges to draw: 'features' (silhouettes, creases sharper than "
         "--crease-angle, boundaries) or 'all' (every edge but the diagonals inside flat polygons)")
        ("hidden", po::value(&o.hidden_lines)->default_value("hidden"),
         "hidden-line plugins: 'hidden' leaves hidden lines out, 'dashed' draws them dashed")
        ("trace", po::value(&o.trace),
         "hidden-line plugins: write the algorithm's steps to this file, one JSON object per line")
        ("surface", po::value(&o.surface),
         "instead of MODEL: the surface z = f(x, y) of this formula (muparser: sin cos sqrt exp ^ pi ...), "
         "e.g. \"sin(x)*cos(y)\"")
        ("range", po::value(&o.range),
         "with --surface: X0:X1,Y0:Y1[,CxR] (default -1:1,-1:1,64x64), e.g. -3:3,-3:3,80x80")
        ("heightmap", po::value(&o.heightmap),
         "instead of MODEL: a surface from a greyscale PNG, one grid sample per pixel")
        ("random-triangles", po::value(&o.random_triangles),
         "instead of MODEL: N random planar triangles, each in its own colour, of mixed sizes, overlapping "
         "and interpenetrating (the textbook's exercise); the same --seed gives the same scene")
        ("seed", po::value(&o.seed)->default_value("1"), "with --random-triangles: the random seed (a whole number)")
        ("heightmap-height", po::value(&o.heightmap_height)->default_value(0.0, "auto"),
         "with --heightmap: the height of a white pixel (pixels are 1 apart); auto = a fifth of the larger side")
        ("step", po::value(&o.step),
         "hidden-surface plugins: stop the algorithm after its step N (1 = the first) and write the "
         "picture as that step left it; prints what the step did")
        ("stats", po::bool_switch(&o.stats), "print the algorithm's counters and timings to stderr")
        ("threads", po::value(&o.threads)->default_value(0),
         fmt::format("threads for loading, visibility and shading, at most {} (0 = one per core)", kMaxThreads).c_str())
        ("limit", po::value(&o.limits)->composing(), hsr::describe_limit_option().c_str())
        ("plugin-path", po::value(&o.plugin_dirs)->composing(), "extra folder to search for plugins (repeatable)");
    return general;
}

// Malformed options and values of the wrong type are po::error.
RenderOptions parse_render_options(const std::vector<std::string>& args) {
    RenderOptions o;
    po::options_description hidden;
    hidden.add_options()("model", po::value(&o.model));
    po::options_description all;
    all.add(render_option_descriptions(o)).add(hidden);
    po::positional_options_description positional;
    positional.add("model", 1);

    po::variables_map vm;
    po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
    po::notify(vm);
    for (const auto& [name, value] : vm)
        if (!value.defaulted()) o.given.insert(name);
    o.help = vm.count("help") > 0;
    return o;
}

// The options, then every plugin found with its parameters.
void print_render_help(const std::vector<std::string>& plugin_dirs) {
    RenderOptions unused;  // the descriptions need somewhere to store values; none are parsed here
    std::cout << render_option_descriptions(unused)
              << "\nplugins (parameters go after the name: --algorithm zbuffer:cull-backfaces=true):\n";
    hsr::PluginRegistry registry = hsr::host::scan_plugins(plugin_dirs);
    std::cout << hsr::host::describe_plugins(registry, "  ");
}

// What can be checked without plugins or files: one source of the scene, the options that go with
// another, numbers in range, the background colour.
void check_render_options(const RenderOptions& o) {
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
    if (o.was_given("width") || o.was_given("height"))  // else a .scene file may set it (load_render_scene)
        hsr::check_limit(&hsr::Limits::image_pixels, uint64_t(o.width) * uint64_t(o.height),
                         fmt::format("image size {}x{}", o.width, o.height));
    if (o.threads < 0 || o.threads > kMaxThreads)
        throw UsageError("--threads {}: expected 0 (one per core) to {}", o.threads, kMaxThreads);
    if (o.was_given("step") && o.step < 1) throw UsageError("--step {}: steps count from 1", o.step);
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
    if (o.eye.empty()) {
        for (const char* option : {"target", "up"})
            if (o.was_given(option)) throw UsageError("--{} goes with --eye", option);
    } else {
        for (const char* option : {"yaw", "pitch"})
            if (o.was_given(option)) throw UsageError("--eye replaces --{}: give one or the other", option);
        for (const auto& [option, text] : {std::pair{"eye", &o.eye}, {"target", &o.target}, {"up", &o.up}})
            if (!text->empty()) hsr::host::parse_vector_option(*text, option);  // parsed again where it is used
    }
    hsr::host::parse_color_option(o.background, "background");  // parsed again where it is used
    if (!o.color.empty()) hsr::host::parse_color_option(o.color, "color");  // before a long load
    if (!hsr::is_sample_count(o.samples < 0 || o.samples > 16 ? 0u : uint32_t(o.samples)))
        throw UsageError("--samples {}: expected 1, 2, 4, 8 or 16", o.samples);
    if (o.repeat.empty())
        for (const char* option : {"repeat-gap", "repeat-jitter"})
            if (o.was_given(option)) throw UsageError("--{} goes with --repeat", option);
}

// Exactly one of the two is set: --algorithm names a hidden-line plugin (a line drawing) or a
// hidden-surface one (a shaded picture).
struct RenderPlugins {
    std::optional<hsr::host::LineDrawingPlugin> line_drawing;
    std::optional<hsr::host::PicturePlugins> picture;
};

hsr::host::LineDrawingPlugin make_line_drawing_plugin(const RenderOptions& o, const hsr::PluginRegistry& registry,
                                                      const hsr::PluginSpec& algorithm) {
    for (const char* option : {"lighting", "light", "color", "samples", "depth-out", "overdraw-out", "depth-tests-out",
                               "threads", "step"})
        if (o.was_given(option))
            throw UsageError("--{} is for hidden-surface plugins; '{}' draws lines", option, algorithm.name);
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
    std::string output = o.output;
    if (output.empty()) {  // <model name>.png, its % signs kept as they are
        std::string stem;
        for (char c : hsr::host::model_path(o).stem().string()) stem += c == '%' ? "%%" : std::string(1, c);
        output = stem + (frames > 1 ? "-%03d" : "") + (line_drawing ? ".svg" : ".png");
    }
    for (const auto& [option, text, name] :
         {std::tuple<const char*, const std::string&, hsr::host::OutputTemplate&>{"output", output, job.output},
          {"depth-out", o.depth_out, job.depth_out},
          {"overdraw-out", o.overdraw_out, job.overdraw_out},
          {"depth-tests-out", o.depth_tests_out, job.depth_tests_out},
          {"trace", o.trace, job.trace}}) {
        if (text.empty()) continue;
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
        outputs.push_back({"output", o.output, output_extensions});
        for (const auto& [option, path] : {std::pair<const char*, const std::string&>{"depth-out", o.depth_out},
                                           {"overdraw-out", o.overdraw_out},
                                           {"depth-tests-out", o.depth_tests_out}})
            if (!path.empty()) outputs.push_back({option, path, {".png"}});
        if (!o.trace.empty()) outputs.push_back({"trace", o.trace, {}});
    }
    return hsr::host::check_outputs(outputs);
}

}  // namespace

glm::vec3 hsr::host::parse_color_option(const std::string& text, const char* option) {
    hsr_param_desc desc{sizeof(hsr_param_desc), option, HSR_PARAM_COLOR, "", 0, 1, nullptr, ""};
    try {
        hsr_param_value v = hsr::parse_param_value(desc, text);
        return {v.color[0], v.color[1], v.color[2]};
    } catch (const hsr::Error& e) {
        throw UsageError("--{}: {}", option, e.what());
    }
}

namespace {

// "n0,n1,...": `count` finite numbers separated by commas, else a UsageError naming the option.
template <int kCount>
glm::vec<kCount, float> parse_number_list(const std::string& text, const char* option, const char* expected) {
    glm::vec<kCount, float> v{};
    std::size_t start = 0;
    for (int k = 0; k < kCount; ++k) {
        const std::size_t comma = k + 1 < kCount ? text.find(',', start) : text.size();
        const std::string_view part = std::string_view(text).substr(start, comma == std::string::npos ? 0 : comma - start);
        const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), v[k]);
        if (comma == std::string::npos || part.empty() || ec != std::errc() || end != part.data() + part.size() ||
            !std::isfinite(v[k]))
            throw UsageError("--{} '{}': expected {}", option, hsr::printable(text), expected);
        start = comma + 1;
    }
    return v;
}

}  // namespace

glm::vec3 hsr::host::parse_vector_option(const std::string& text, const char* option) {
    return parse_number_list<3>(text, option, "x,y,z (three finite numbers)");
}

glm::vec4 hsr::host::parse_plane_option(const std::string& text, const char* option) {
    const glm::vec4 plane = parse_number_list<4>(text, option, "a,b,c,d (four finite numbers)");
    if (plane.x == 0.0f && plane.y == 0.0f && plane.z == 0.0f)
        throw UsageError("--{} '{}': the plane's normal a,b,c is zero", option, hsr::printable(text));
    return plane;
}

void hsr::host::add_clip_plane_options(const RenderOptions& o, std::vector<glm::vec4>& planes) {
    for (float z : o.sections) {
        if (!std::isfinite(z)) throw UsageError("--section must be a finite number");
        planes.push_back(hsr::section_plane(z));
    }
    for (const std::string& text : o.clip_planes) planes.push_back(parse_plane_option(text, "clip-plane"));
    if (planes.size() > HSR_MAX_CLIP_PLANES)
        throw UsageError("{} sections and clip planes: at most {} (a .scene file's count too)", planes.size(),
                         HSR_MAX_CLIP_PLANES);
}

fs::path hsr::host::model_path(const RenderOptions& o) {
    if (o.was_given("random-triangles")) return "random-triangles";
    return fs::path(!o.model.empty() ? o.model : !o.heightmap.empty() ? o.heightmap : "surface");
}

hsr::host::RenderOptions hsr::host::RenderJob::frame_options(std::size_t k) const {
    RenderOptions o = options;
    o.yaw = frames[k].yaw;
    o.pitch = frames[k].pitch;
    o.yaw_turn = frames[k].yaw_turn;
    o.output = output.name(k);
    for (const auto& [text, name] : {std::pair<std::string&, const OutputTemplate&>{o.depth_out, depth_out},
                                     {o.overdraw_out, overdraw_out},
                                     {o.depth_tests_out, depth_tests_out},
                                     {o.trace, trace}})
        if (!text.empty()) text = name.name(k);
    return o;
}

hsr::host::RenderJob hsr::host::prepare_render_job(const std::vector<std::string>& args, PluginRegistries& registries,
                                                   std::vector<fs::path>& files) {
    RenderJob job;
    job.options = parse_render_options(args);
    RenderOptions& options = job.options;
    if (options.help) throw UsageError("--help goes on a command line of its own");
    if (!options.jobs.empty()) throw UsageError("--jobs: a job cannot run another jobs file");
    try {
        job.limits = hsr::limits_from_settings(options.limits);
    } catch (const hsr::Error& e) {
        throw UsageError("{}", e.what());
    }
    hsr::set_limits(job.limits);
    job.frames = plan_frames(options);
    check_render_options(options);
    auto registry = registries.find(options.plugin_dirs);
    if (registry == registries.end())
        registry = registries.emplace(options.plugin_dirs, scan_plugins(options.plugin_dirs)).first;
    RenderPlugins plugins = make_render_plugins(options, registry->second);
    job.line_drawing = std::move(plugins.line_drawing);
    job.picture = std::move(plugins.picture);
    set_output_templates(job, job.line_drawing.has_value());
    files = check_render_outputs(job, job.line_drawing.has_value());
    return job;
}

namespace {

// A render allocates and frees tens of megabytes once each: the model's text, what is parsed from it,
// the mesh, the scene, the frame's buffers. Served from the heap instead of a fresh mapping each, a
// freed block is used again and the heap grows in large steps, with fewer new pages to fault in:
// about a sixth of the bunny's load time in a new process (docs/speed/loading.md). Bench and view
// keep glibc's defaults, which give memory back (bench measures peak memory).
void reuse_freed_memory() {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    mallopt(M_TOP_PAD, 64 << 20);
}

}  // namespace

int hsr::host::run_render(const std::vector<std::string>& args) {
    reuse_freed_memory();
    const RenderOptions options = parse_render_options(args);
    if (options.help) {
        print_render_help(options.plugin_dirs);
        return 0;
    }
    if (!options.jobs.empty()) {
        for (const std::string& option : options.given)
            if (option != "jobs")
                throw UsageError("--jobs {}: --{} goes on the lines of the file, which hold every option of each render",
                                 hsr::printable(options.jobs), option);
        return run_job_file(options.jobs);
    }
    PluginRegistries registries;
    std::vector<fs::path> files;
    std::vector<RenderJob> jobs;
    jobs.push_back(prepare_render_job(args, registries, files));
    return run_jobs(jobs, JobFailures::kStop);
}
