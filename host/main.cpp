// hsr: the command-line host. It parses options, loads the scene and the chosen plugins, and hands
// them to the framework's frame pipeline; everything else lives in framework/ and plugins/.
#include "commands.hpp"

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/image.hpp"
#include "hsr/instancing.hpp"
#include "hsr/line_image.hpp"
#include "hsr/lines.hpp"
#include "hsr/params.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"
#include "hsr/surface.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/program_options.hpp>
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace po = boost::program_options;
namespace fs = std::filesystem;

hsr::PluginRegistry hsr::host::scan_plugins(const std::vector<std::string>& extra_dirs) {
    const fs::path executable_dir(boost::dll::program_location().parent_path().string());
    hsr::PluginRegistry registry;
    for (const fs::path& dir : hsr::default_plugin_dirs(executable_dir, extra_dirs)) registry.scan_directory(dir);
    return registry;
}

namespace {

constexpr const char* default_algorithm = "zbuffer";
constexpr const char* default_lighting = "blinn-phong";
constexpr const char* default_light = "dir:-0.5,0.6,1";
constexpr const char* default_background = "0.15/0.15/0.17";

using hsr::host::scan_plugins;
using hsr::host::UsageError;

const char* usage_text =
    "usage: hsr <command> [options]\n"
    "\n"
    "commands:\n"
    "  render MODEL   render a mesh (OBJ, OFF, PLY, STL) or a .scene file to PNG, or draw its\n"
    "                 visible edges to SVG/PNG with a hidden-line plugin (--algorithm appel)\n"
    "  plugins        list the plugins found, with their parameters\n"
    "  bench          time algorithms on models and deep scenes: table, CSV, SVG plot\n"
    "\n"
    "  hsr --version  versions of hsr and of its plugin ABI\n"
    "  hsr <command> --help\n";


std::string describe_plugin(const hsr::Plugin& p, const std::string& indent) {
    const hsr_plugin_descriptor& d = p.descriptor;
    std::string out = fmt::format("{}{:<15} {:<20} v{:<7} ABI {}.{}  {}\n", indent, hsr::kind_name(d.kind), d.name,
                                  d.version ? d.version : "?", d.abi_major, d.abi_minor,
                                  d.description ? d.description : "");
    if (d.param_count == 0) out += indent + "    (no parameters)\n";
    for (uint32_t i = 0; i < d.param_count; ++i) out += indent + "    " + hsr::describe_param(hsr::param_desc(d, i)) + "\n";
    return out;
}

// Hidden-surface plugins first, then hidden-line, then lighting; within a kind in the order found.
std::string describe_plugins(const hsr::PluginRegistry& registry, const std::string& indent) {
    std::string out;
    for (hsr_plugin_kind kind : {HSR_KIND_HIDDEN_SURFACE_REMOVER, HSR_KIND_HIDDEN_LINE_REMOVER, HSR_KIND_LIGHTING_MODEL}) {
        for (const hsr::Plugin& p : registry.plugins())
            if (p.descriptor.kind == kind) out += describe_plugin(p, indent);
    }
    return out;
}

int run_plugins(const std::vector<std::string>& args) {
    po::options_description options("hsr plugins: list every plugin found");
    std::vector<std::string> plugin_dirs;
    options.add_options()("help,h", "show this help")(
        "plugin-path", po::value(&plugin_dirs)->composing(), "extra folder to search for plugins (repeatable)");
    po::variables_map vm;
    std::vector<std::string> unexpected;
    po::options_description hidden;
    hidden.add_options()("unexpected", po::value(&unexpected));
    po::options_description all;
    all.add(options).add(hidden);
    po::positional_options_description positional;
    positional.add("unexpected", -1);
    po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
    po::notify(vm);
    if (!unexpected.empty()) throw UsageError("plugins: unexpected argument '{}'", unexpected.front());
    if (vm.count("help")) {
        std::cout << options;
        return 0;
    }
    hsr::PluginRegistry registry = scan_plugins(plugin_dirs);
    std::string dirs;
    for (const fs::path& d : registry.searched()) dirs += "  " + d.string() + "\n";
    std::cout << "searched:\n" << dirs << "\n";
    std::cout << describe_plugins(registry, "");
    if (registry.plugins().empty()) std::cout << "no plugins found\n";
    for (const hsr::RejectedLibrary& r : registry.rejected()) std::cout << "refused: " << r.reason << "\n";
    return 0;
}

struct RenderOptions {
    std::string model;
    std::string output;
    std::string algorithm = default_algorithm;
    std::string lighting = default_lighting;
    std::vector<std::string> lights;
    std::vector<std::string> plugin_dirs;
    std::string background = default_background;
    std::string color;
    std::string depth_out;
    std::string overdraw_out;
    std::string depth_tests_out;
    std::string repeat;
    std::string edges = "features";
    std::string hidden_lines = "hidden";
    std::string trace;
    std::string surface, range, heightmap;
    double heightmap_height = 0.0;
    float repeat_gap = 0.25f, repeat_jitter = 0.0f;
    float yaw = 0, pitch = 0, zoom = 1, crease_angle = 40;
    bool orthographic = false;
    bool stats = false;
    uint32_t threads = 0;
    int64_t width = 1024, height = 1024;
};

glm::vec3 parse_color_option(const std::string& text, const char* option) {
    hsr_param_desc desc{sizeof(hsr_param_desc), option, HSR_PARAM_COLOR, "", 0, 1, nullptr, ""};
    try {
        hsr_param_value v = hsr::parse_param_value(desc, text);
        return {v.color[0], v.color[1], v.color[2]};
    } catch (const hsr::Error& e) {
        throw UsageError("--{}: {}", option, e.what());
    }
}

// "CxRxL" (columns x rows x layers) for --repeat.
hsr::InstanceGrid parse_repeat(const std::string& text, float gap, float jitter) {
    hsr::InstanceGrid grid;
    unsigned long long c = 0, r = 0, l = 0;
    char x1 = 0, x2 = 0, extra = 0;
    if (text.find_first_not_of("0123456789x") != std::string::npos ||
        std::sscanf(text.c_str(), "%llu%c%llu%c%llu%c", &c, &x1, &r, &x2, &l, &extra) != 5 || x1 != 'x' || x2 != 'x' ||
        c == 0 || r == 0 || l == 0)
        throw UsageError("--repeat '{}': expected COLUMNSxROWSxLAYERS, each at least 1, e.g. 4x3x20", text);
    constexpr unsigned long long max_side = 100000;
    if (c > max_side || r > max_side || l > max_side)
        throw UsageError("--repeat '{}': at most {} along each side", text, max_side);
    if (!(gap >= 0.0f) || !std::isfinite(gap)) throw UsageError("--repeat-gap must be 0 or more");
    if (!(jitter >= 0.0f) || !(jitter <= 180.0f)) throw UsageError("--repeat-jitter must be between 0 and 180 degrees");
    grid.columns = uint32_t(c);
    grid.rows = uint32_t(r);
    grid.layers = uint32_t(l);
    grid.gap = gap;
    grid.yaw_jitter_degrees = jitter;
    return grid;
}

void print_stats(const hsr::Frame& frame, const hsr::HiddenSurfaceRemover& remover,
                 const hsr::LightingModel& lighting, const hsr_scene& scene,
                 const std::optional<hsr::DepthComplexity>& depth_complexity) {
    const uint64_t drawn = hsr::drawn_triangle_count(scene);
    std::fprintf(stderr, "%s + %s, %llu triangles", remover.plugin().descriptor.name, lighting.plugin().descriptor.name,
                 static_cast<unsigned long long>(drawn));
    if (scene.instance_count > 0)
        std::fprintf(stderr, " (%u instances of %u stored)", scene.instance_count, scene.triangle_count);
    std::fprintf(stderr, ", %ux%u\n", frame.width, frame.height);
    const double build_ms = double(frame.counter("build-time-us")) / 1000.0;
    int w = 28;  // the name column: as wide as the longest name a plugin reports
    for (const auto& counter : frame.counters) w = std::max(w, int(counter.first.size()));
    std::fprintf(stderr, "  %-*s %10.2f ms\n", w, "visibility time", frame.visibility_ms);
    if (build_ms > 0.0) {
        std::fprintf(stderr, "    %-*s %10.2f ms\n", w - 2, "of which build", build_ms);
        std::fprintf(stderr, "    %-*s %10.2f ms\n", w - 2, "of which render", frame.visibility_ms - build_ms);
    }
    std::fprintf(stderr, "  %-*s %10.2f ms\n", w, "shading time", frame.shading_ms);
    for (const auto& [name, value] : frame.counters)
        std::fprintf(stderr, "  %-*s %10llu\n", w, name.c_str(), static_cast<unsigned long long>(value));
    if (depth_complexity) {
        std::fprintf(stderr, "  %-*s %10.2f (max %u, over %llu covered pixels)\n", w, "depth complexity",
                     depth_complexity->mean_over_covered(), depth_complexity->max,
                     static_cast<unsigned long long>(depth_complexity->covered_pixels));
        const uint64_t written = frame.counter("pixels-written");
        if (depth_complexity->covered_pixels > 0 && written > 0)
            std::fprintf(stderr, "  %-*s %10.3f\n", w, "overdraw (writes / pixel)",
                         double(written) / double(depth_complexity->covered_pixels));
        const uint64_t tested = frame.counter("pixels-depth-tested");
        if (depth_complexity->fragments > 0)
            std::fprintf(stderr, "  %-*s %10.3f\n", w, "depth tests / surface samples",
                         double(tested) / double(depth_complexity->fragments));
    }
}

int run_render(const std::vector<std::string>& args) {
    RenderOptions o;
    po::options_description general("hsr render MODEL [options]: render a mesh or .scene file to PNG");
    general.add_options()
        ("help,h", "show this help, with every plugin's parameters")
        ("output,o", po::value(&o.output),
         "file to write: PNG for a hidden-surface plugin (default <model name>.png); SVG or PNG for a "
         "hidden-line plugin (default <model name>.svg)")
        ("algorithm,a", po::value(&o.algorithm)->default_value(default_algorithm),
         "hidden-surface or hidden-line plugin: NAME[:key=value,...]")
        ("lighting,l", po::value(&o.lighting)->default_value(default_lighting),
         "lighting plugin: NAME[:key=value,...]")
        ("width", po::value(&o.width)->default_value(1024), "image width in pixels")
        ("height", po::value(&o.height)->default_value(1024), "image height in pixels")
        ("yaw", po::value(&o.yaw)->default_value(0), "turn the model about the vertical axis, degrees")
        ("pitch", po::value(&o.pitch)->default_value(0), "tilt: positive looks from above, degrees")
        ("zoom", po::value(&o.zoom)->default_value(1), "magnification; 1 fits the model to the view")
        ("ortho", po::bool_switch(&o.orthographic), "orthographic instead of perspective projection")
        ("light", po::value(&o.lights)->composing(),
         "light, repeatable: point:x,y,z or dir:x,y,z (toward the light), camera space (x right, y up, "
         "z toward you), optionally followed by ,intensity=I,color=r/g/b (docs/scene-format.md). "
         "Default: dir:-0.5,0.6,1")
        ("background", po::value(&o.background)->default_value(default_background), "background colour r/g/b or #rrggbb")
        ("color", po::value(&o.color), "model colour r/g/b or #rrggbb (a mesh file's faces; default 0.8/0.8/0.8)")
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
        ("heightmap-height", po::value(&o.heightmap_height)->default_value(0.0, "auto"),
         "with --heightmap: the height of a white pixel (pixels are 1 apart); auto = a fifth of the larger side")
        ("stats", po::bool_switch(&o.stats), "print the algorithm's counters and timings to stderr")
        ("threads", po::value(&o.threads)->default_value(0), "shading threads (0 = one per core)")
        ("plugin-path", po::value(&o.plugin_dirs)->composing(), "extra folder to search for plugins (repeatable)");
    po::options_description hidden;
    hidden.add_options()("model", po::value(&o.model));
    po::options_description all;
    all.add(general).add(hidden);
    po::positional_options_description positional;
    positional.add("model", 1);

    po::variables_map vm;
    po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
    po::notify(vm);

    if (vm.count("help")) {
        std::cout << general << "\nplugins (parameters go after the name: --algorithm zbuffer:cull-backfaces=true):\n";
        hsr::PluginRegistry registry = scan_plugins(o.plugin_dirs);
        std::cout << describe_plugins(registry, "  ");
        return 0;
    }
    const int sources = int(!o.model.empty()) + int(!o.surface.empty()) + int(!o.heightmap.empty());
    if (sources == 0) throw UsageError("render: no model given (or --surface FORMULA, or --heightmap FILE.png)");
    if (sources > 1) throw UsageError("render: give one of MODEL, --surface and --heightmap");
    if (!o.range.empty() && o.surface.empty()) throw UsageError("--range goes with --surface");
    if (!vm["heightmap-height"].defaulted() && o.heightmap.empty())
        throw UsageError("--heightmap-height goes with --heightmap");
    if (o.width <= 0 || o.height <= 0 || o.width > hsr::max_image_side || o.height > hsr::max_image_side)
        throw UsageError("image size {}x{}: each side must be between 1 and {}", o.width, o.height, hsr::max_image_side);
    for (const auto& [option, value] :
         {std::pair{"yaw", o.yaw}, {"pitch", o.pitch}, {"zoom", o.zoom}, {"crease-angle", o.crease_angle}})
        if (!std::isfinite(value)) throw UsageError("--{} must be a finite number", option);
    if (!(o.zoom > 0)) throw UsageError("--zoom must be positive");
    const glm::vec3 background = parse_color_option(o.background, "background");

    auto given = [&](const char* option) { return vm.count(option) && !vm[option].defaulted(); };
    if (o.repeat.empty())
        for (const char* option : {"repeat-gap", "repeat-jitter"})
            if (given(option)) throw UsageError("--{} goes with --repeat", option);
    // Plugins first: a typo in a plugin name should not wait for a large mesh to load.
    hsr::PluginRegistry registry = scan_plugins(o.plugin_dirs);
    const hsr::PluginSpec algorithm = hsr::parse_plugin_spec(o.algorithm);
    const bool line_drawing = !registry.contains(HSR_KIND_HIDDEN_SURFACE_REMOVER, algorithm.name) &&
                              registry.find_any({HSR_KIND_HIDDEN_SURFACE_REMOVER, HSR_KIND_HIDDEN_LINE_REMOVER},
                                                algorithm.name).descriptor.kind == HSR_KIND_HIDDEN_LINE_REMOVER;
    std::optional<hsr::LineSettings> line_settings;
    std::optional<hsr::LineStyle> line_style;
    std::unique_ptr<hsr::HiddenLineRemover> line_remover;
    std::unique_ptr<hsr::HiddenSurfaceRemover> surface_remover;
    std::unique_ptr<hsr::LightingModel> lighting;
    if (line_drawing) {
        for (const char* option : {"lighting", "depth-out", "overdraw-out", "depth-tests-out", "threads"})
            if (given(option))
                throw UsageError("--{} is for hidden-surface plugins; '{}' draws lines", option, algorithm.name);
        line_settings.emplace();
        line_style.emplace();
        if (o.edges == "features")
            line_settings->edges = hsr::EdgeSelection::kFeatures;
        else if (o.edges == "all")
            line_settings->edges = hsr::EdgeSelection::kAll;
        else
            throw UsageError("--edges '{}': expected 'all' or 'features'", o.edges);
        if (o.hidden_lines == "hidden")
            line_style->hidden = hsr::HiddenLines::kHidden;
        else if (o.hidden_lines == "dashed")
            line_style->hidden = hsr::HiddenLines::kDashed;
        else
            throw UsageError("--hidden '{}': expected 'dashed' or 'hidden'", o.hidden_lines);
        line_settings->want_hidden = line_style->hidden == hsr::HiddenLines::kDashed;
        line_settings->crease_angle_degrees = o.crease_angle;
        line_remover = std::make_unique<hsr::HiddenLineRemover>(
            registry.find(HSR_KIND_HIDDEN_LINE_REMOVER, algorithm.name), algorithm.settings);
    } else {
        for (const char* option : {"edges", "hidden", "trace"})
            if (given(option))
                throw UsageError("--{} is for hidden-line plugins (appel, roberts, ...); '{}' removes hidden surfaces",
                                 option, algorithm.name);
        const hsr::PluginSpec lighting_spec = hsr::parse_plugin_spec(o.lighting);
        surface_remover = std::make_unique<hsr::HiddenSurfaceRemover>(
            registry.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, algorithm.name), algorithm.settings);
        lighting = std::make_unique<hsr::LightingModel>(registry.find(HSR_KIND_LIGHTING_MODEL, lighting_spec.name),
                                                        lighting_spec.settings);
        if (!o.depth_tests_out.empty() && surface_remover->plugin().descriptor.abi_minor < 1)
            throw hsr::Error("--depth-tests-out: plugin '{}' does not report per-pixel depth tests (ABI 1.0)",
                             algorithm.name);
    }

    // Every file to write, checked before the work: a mistyped folder should not cost a long render.
    const fs::path model_path(!o.model.empty() ? o.model : !o.heightmap.empty() ? o.heightmap : "surface");
    const fs::path output = !o.output.empty() ? fs::path(o.output)
                                              : fs::path(model_path.stem().string() + (line_drawing ? ".svg" : ".png"));
    {
        std::vector<hsr::host::OutputFile> outputs;
        outputs.push_back({"output", output, line_drawing ? std::vector<std::string>{".svg", ".png"}
                                                          : std::vector<std::string>{".png"}});
        for (const auto& [option, path] : {std::pair<const char*, const std::string&>{"depth-out", o.depth_out},
                                           {"overdraw-out", o.overdraw_out},
                                           {"depth-tests-out", o.depth_tests_out}})
            if (!path.empty()) outputs.push_back({option, path, {".png"}});
        if (!o.trace.empty()) outputs.push_back({"trace", o.trace, {}});
        hsr::host::check_outputs(outputs);
    }

    // Scene and camera. What the command line says explicitly wins over what a scene file says.
    hsr::SceneData scene;
    std::vector<hsr::LightSpec> light_specs;
    std::optional<glm::vec3> scene_background;
    bool pixel_camera = false;
    uint32_t width = static_cast<uint32_t>(o.width), height = static_cast<uint32_t>(o.height);
    hsr::CameraSettings settings;
    settings.yaw_degrees = o.yaw;
    settings.pitch_degrees = o.pitch;
    settings.zoom = o.zoom;
    settings.orthographic = o.orthographic;
    if (!o.surface.empty()) {
        const hsr::SurfaceRange range = o.range.empty() ? hsr::SurfaceRange{} : hsr::parse_surface_range(o.range);
        scene = hsr::make_formula_surface(o.surface, range,
                                          o.color.empty() ? glm::vec3(0.8f) : parse_color_option(o.color, "color"));
    } else if (!o.heightmap.empty()) {
        hsr::HeightmapOptions heightmap;
        heightmap.height = o.heightmap_height;
        if (!o.color.empty()) heightmap.color = parse_color_option(o.color, "color");
        scene = hsr::make_heightmap_surface(o.heightmap, heightmap);
    } else if (hsr::is_scene_file(model_path)) {
        hsr::SceneFile file = hsr::load_scene_file(model_path);
        scene = std::move(file.scene);
        light_specs = file.lights;
        scene_background = file.background;
        pixel_camera = file.pixel_camera;
        if (file.width && !given("width")) width = *file.width;
        if (file.height && !given("height")) height = *file.height;
        if (file.yaw_degrees && !given("yaw")) settings.yaw_degrees = *file.yaw_degrees;
        if (file.pitch_degrees && !given("pitch")) settings.pitch_degrees = *file.pitch_degrees;
        if (file.zoom && !given("zoom")) settings.zoom = *file.zoom;
        if (file.orthographic && !o.orthographic) settings.orthographic = *file.orthographic;
    } else {
        hsr::MeshOptions mesh_options;
        mesh_options.crease_angle_degrees = o.crease_angle;
        if (!o.color.empty()) mesh_options.color = parse_color_option(o.color, "color");
        scene = hsr::load_model(model_path, mesh_options);
    }
    if (!o.repeat.empty()) {
        if (!scene.instances.empty())
            throw UsageError("--repeat: '{}' already places copies of its meshes (a 'repeat' line); use one or the other",
                             model_path.string());
        scene = hsr::make_instance_grid(scene, parse_repeat(o.repeat, o.repeat_gap, o.repeat_jitter));
    }
    for (const std::string& warning : scene.warnings) std::fprintf(stderr, "hsr: warning: %s\n", warning.c_str());
    hsr::check_image_size(width, height);
    settings.width = width;
    settings.height = height;
    const hsr_camera camera = pixel_camera
        ? hsr::make_pixel_camera(width, height, scene.bounds_min.z, scene.bounds_max.z)
        : hsr::make_orbit_camera(scene.bounds_min, scene.bounds_max, settings);

    if (line_drawing) {
        if (!scene.instances.empty()) scene = hsr::flatten_instances(scene);
        const hsr_scene scene_view = scene.view();
        std::ofstream trace_file;
        if (!o.trace.empty()) {
            trace_file.open(o.trace, std::ios::binary);
            if (!trace_file) throw hsr::Error("--trace {}: cannot write the file", o.trace);
            line_settings->trace = &trace_file;
        }
        const hsr::LineDrawing drawing = hsr::render_lines(scene_view, camera, *line_remover, *line_settings);
        if (trace_file.is_open()) {
            trace_file.close();
            if (!trace_file) throw hsr::Error("--trace {}: writing failed", o.trace);
        }
        line_style->background = vm["background"].defaulted() ? glm::vec3(1.0f) : background;
        const hsr::LineImageStats drawn = hsr::write_line_drawing(output, drawing, *line_style);
        if (o.stats) {
            std::fprintf(stderr, "%s, %u triangles, %zu edges asked for, %ux%u\n", algorithm.name.c_str(),
                         scene_view.triangle_count, drawing.edges.size(), drawing.width, drawing.height);
            std::fprintf(stderr, "  %-28s %10.2f ms\n", "hidden-line time", drawing.lines_ms);
            for (const auto& [name, value] : drawing.counters)
                std::fprintf(stderr, "  %-28s %10llu\n", name.c_str(), static_cast<unsigned long long>(value));
        }
        if (!o.trace.empty())
            std::fprintf(stderr, "wrote %s (%llu steps)\n", o.trace.c_str(),
                         static_cast<unsigned long long>(drawing.trace_events));
        std::fprintf(stderr, "wrote %s (%ux%u, %llu visible segments%s, %zu edges, %.1f ms)\n",
                     output.string().c_str(), drawing.width, drawing.height,
                     static_cast<unsigned long long>(drawn.visible),
                     line_style->hidden == hsr::HiddenLines::kDashed
                         ? fmt::format(" and {} hidden", drawn.hidden).c_str()
                         : "",
                     drawing.edges.size(), drawing.lines_ms);
        return 0;
    }

    if (!o.lights.empty()) {
        light_specs.clear();
        for (const std::string& text : o.lights) light_specs.push_back(hsr::parse_light_spec(text));
    }
    if (light_specs.empty()) light_specs.push_back(hsr::parse_light_spec(default_light));
    std::vector<hsr_light> lights;
    for (const hsr::LightSpec& spec : light_specs) lights.push_back(hsr::resolve_light(spec, camera));

    hsr::FrameSettings frame_settings;
    frame_settings.background = vm["background"].defaulted() && scene_background ? *scene_background : background;
    frame_settings.threads = o.threads;
    frame_settings.count_depth_tests = !o.depth_tests_out.empty();

    const hsr_scene scene_view = scene.view();
    const hsr_shading_context context = hsr::make_shading_context(camera, lights);
    hsr::HiddenSurfaceRemover& remover = *surface_remover;
    hsr::Frame frame = hsr::render_frame(scene_view, camera, remover, *lighting, context, frame_settings);

    hsr::write_png(output, frame.width, frame.height, 3, frame.rgb);
    if (!o.depth_out.empty()) hsr::write_depth_png(o.depth_out, frame.width, frame.height, frame.depth);
    std::optional<hsr::DepthComplexity> depth_complexity;
    if (o.stats || !o.overdraw_out.empty() || !o.depth_tests_out.empty())
        depth_complexity = hsr::measure_depth_complexity(scene_view, camera);
    if (!o.overdraw_out.empty()) {
        hsr::write_heat_map_png(o.overdraw_out, frame.width, frame.height, depth_complexity->count, depth_complexity->max);
        std::fprintf(stderr, "wrote %s (depth complexity heat map: black 0 ... pale yellow %u)\n",
                     o.overdraw_out.c_str(), depth_complexity->max);
    }
    if (!o.depth_tests_out.empty()) {
        hsr::write_heat_map_png(o.depth_tests_out, frame.width, frame.height, frame.depth_tests, depth_complexity->max);
        std::fprintf(stderr, "wrote %s (depth tests heat map: black 0 ... pale yellow %u)\n",
                     o.depth_tests_out.c_str(), depth_complexity->max);
    }
    if (o.stats) print_stats(frame, remover, *lighting, scene_view, depth_complexity);
    if (frame.counter("fragments-shaded") == 0)
        std::fprintf(stderr, "hsr: warning: no triangle covers a pixel centre: the picture is empty (is the model "
                             "too small, too far away or flat edge-on at this size?)\n");
    std::fprintf(stderr, "wrote %s (%ux%u, %llu triangles, %.1f ms visibility + %.1f ms shading)\n",
                 output.string().c_str(), frame.width, frame.height,
                 static_cast<unsigned long long>(hsr::drawn_triangle_count(scene_view)), frame.visibility_ms,
                 frame.shading_ms);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    try {
        if (args.empty()) {
            std::cerr << usage_text;
            return 2;
        }
        const std::string command = args.front();
        args.erase(args.begin());
        if (command == "--help" || command == "-h" || command == "help") {
            std::cout << usage_text;
            return 0;
        }
        if (command == "--version") {
            std::cout << fmt::format("hsr {} (plugin ABI {}.{})\n", HSR_VERSION, HSR_ABI_MAJOR, HSR_ABI_MINOR);
            return 0;
        }
        if (command == "render") return run_render(args);
        if (command == "plugins") return run_plugins(args);
        if (command == "bench") return hsr::host::run_bench(args);
        throw UsageError("unknown command '{}' (commands: render, plugins, bench)", command);
    } catch (const UsageError& e) {
        std::cerr << "hsr: error: " << e.what() << " (see hsr --help)\n";
        return 2;
    } catch (const po::error& e) {
        std::cerr << "hsr: error: " << e.what() << " (see hsr --help)\n";
        return 2;
    } catch (const hsr::Error& e) {
        std::cerr << "hsr: error: " << e.what() << "\n";
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "hsr: error: out of memory\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "hsr: error: " << e.what() << "\n";
        return 1;
    }
}
