// hsr render's options: their descriptions (--help), their parsing, and the clip planes and model
// path read from them (options.hpp).
#include "render/options.hpp"

#include "common/command_line.hpp"
#include "common/plugins.hpp"
#include "common/threads.hpp"

#include "hsr/camera.hpp"
#include "hsr/limits.hpp"

#include <boost/program_options.hpp>
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <set>

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
    po::options_description general(
        "hsr render MODEL... [options]: render a mesh or .scene file to PNG, each MODEL in turn (MODEL '-': "
        "standard input, with --format)");
    general.add_options()
        ("help,h", "show this help, with every plugin's parameters")
        ("output,o", po::value(&o.output),
         "file to write: PNG for a hidden-surface plugin (default <model name>.png); SVG or PNG for a "
         "hidden-line plugin (default <model name>.svg). With several frames, a frame number goes in every "
         "file name: %d, or %03d for 000, 001, ... (frames count from 0; %% is a % sign; default "
         "<model name>-%03d.png). {stem} is the model's file name without its extension, which several models need "
         "(-o '{stem}.png'). '-' writes the PNG to standard output (one frame; messages stay on stderr)")
        ("format", po::value(&o.format),
         "with MODEL '-': the format of the model read from standard input: obj, off, ply, stl, gltf or glb "
         "(docs/formats.md)")
        ("jobs", po::value(&o.jobs),
         "FILE: run the renders of FILE, one line each of the options of hsr render (# starts a comment "
         "line); each model is loaded once for all the lines that name it. The files a line reads are taken "
         "from FILE's folder, those it writes from the current folder; options after --jobs FILE go to every "
         "line that does not give them (docs/many-frames.md)")
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
        ("camera", po::value(&o.camera), "NAME|INDEX: look through a camera of the model file (glTF): its eye, "
         "direction, field of view or window, near plane and aspect ratio")
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
        ("background", po::value(&o.background)->default_value(default_background),
         "background colour r/g/b or #rrggbb; 'none': an RGBA PNG whose alpha is each pixel's coverage (straight, "
         "not premultiplied colour)")
        ("opacity", po::value(&o.opacity),
         "opacity of the model, 0 (invisible) to 1 (opaque; the default); a .scene file gives each object an "
         "`opacity` line. Needs an algorithm that returns fragment lists (a-buffer)")
        ("color", po::value(&o.color), "model colour r/g/b or #rrggbb, over the file's own colours (default: the file's, else 0.8/0.8/0.8)")
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
        ("depth-out", po::value(&o.depth_out),
         "also write the depth buffer: .png greyscale (near = white); .npy, .pfm or .exr float32 camera-space "
         "distance along the view axis in the model's units, +inf where nothing is drawn (docs/formats.md)")
        ("id-out", po::value(&o.id_out),
         "also write which face each pixel shows: .npy int32 (height, width, 3) of object, face within the object, "
         "instance (-1 where nothing is drawn); .png 16-bit RGBA of the same (docs/formats.md)")
        ("normal-out", po::value(&o.normal_out),
         "also write the visible face's unit normal in camera space (x right, y up, z toward the eye): .npy, .pfm "
         "or .exr float32, 0 where nothing is drawn; .png 8-bit, (n + 1) / 2 (docs/formats.md)")
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
        ("step", po::value(&o.step_text),
         "hidden-surface plugins: stop the algorithm after its step N (1 = the first) and write the "
         "picture as that step left it; prints what the step did. A..B writes one picture per step, "
         "A to B, to a name with a frame number (-o step-%03d.png), at most 1000 steps")
        ("stats", po::bool_switch(&o.stats), "print the algorithm's counters and timings to stderr")
        ("threads", po::value(&o.threads)->default_value(0),
         fmt::format("threads for loading, visibility and shading, at most {} (0 = one per core)", kMaxThreads).c_str())
        ("limit", po::value(&o.limits)->composing(), hsr::describe_limit_option().c_str())
        ("plugin-path", po::value(&o.plugin_dirs)->composing(), "extra folder to search for plugins (repeatable)");
    return general;
}

}  // namespace

namespace {

// Parses args as hsr render's words: each option with its words as given (MODEL's named "model"),
// bound to o's fields for po::store.
po::parsed_options parse_render_words(const std::vector<std::string>& args, RenderOptions& o,
                                      po::options_description& all) {
    const po::options_description shown = render_option_descriptions(o);
    po::options_description hidden;
    hidden.add_options()("model", po::value(&o.models));
    all.add(shown).add(hidden);
    po::positional_options_description positional;
    positional.add("model", -1);
    po::command_line_parser parser(args);
    parser.options(all).positional(positional);
    return hsr::host::parse_command_line(parser, shown);
}

// The options of a command line that name files it reads, and so are taken from a jobs file's folder.
bool reads_a_file(const std::string& option) {
    return option == "model" || option == "heightmap" || option == "plugin-path";
}

}  // namespace

hsr::host::RenderOptions hsr::host::parse_render_options(const std::vector<std::string>& args) {
    RenderOptions o;
    po::options_description all;
    po::variables_map vm;
    po::store(parse_render_words(args, o, all), vm);
    po::notify(vm);
    for (const auto& [name, value] : vm)
        if (!value.defaulted()) o.given.insert(name);
    o.help = vm.count("help") > 0;
    if (!o.models.empty()) o.model = o.models.front();
    return o;
}

std::vector<std::string> hsr::host::job_line_arguments(const std::vector<std::string>& line, const fs::path& folder,
                                                       const std::vector<std::string>& defaults) {
    RenderOptions unused;  // the words are only parsed, not stored
    po::options_description line_options, default_options;
    std::vector<std::string> words;
    std::set<std::string> given;
    for (const po::option& option : parse_render_words(line, unused, line_options).options) {
        given.insert(option.string_key);
        const bool relative = option.value.size() == 1 && !option.value.front().empty() &&
                              option.value.front() != "-" && fs::path(option.value.front()).is_relative();
        if (reads_a_file(option.string_key) && relative && !folder.empty())
            words.push_back("--" + option.string_key + "=" +
                            (folder / option.value.front()).lexically_normal().string());
        else
            words.insert(words.end(), option.original_tokens.begin(), option.original_tokens.end());
    }
    for (const po::option& option : parse_render_words(defaults, unused, default_options).options)
        if (option.string_key != "jobs" && given.count(option.string_key) == 0)
            words.insert(words.end(), option.original_tokens.begin(), option.original_tokens.end());
    return words;
}

std::string hsr::host::with_model_stem(const std::string& text, const RenderOptions& options) {
    std::string result;
    std::size_t from = 0;
    for (std::size_t at = text.find(stem_placeholder); at != std::string::npos;
         at = text.find(stem_placeholder, from)) {
        result.append(text, from, at - from);
        for (char c : model_path(options).stem().string()) result += c == '%' ? "%%" : std::string(1, c);
        from = at + stem_placeholder.size();
    }
    return result + text.substr(from);
}

void hsr::host::print_render_help(const std::vector<std::string>& plugin_dirs) {
    RenderOptions unused;  // the descriptions need somewhere to store values; none are parsed here
    std::cout << render_option_descriptions(unused)
              << "\nplugins (parameters go after the name: --algorithm zbuffer:cull-backfaces=true):\n";
    hsr::PluginRegistry registry = hsr::host::scan_plugins(plugin_dirs);
    std::cout << hsr::host::describe_plugins(registry, "  ");
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

std::string hsr::host::stdin_model_format_list() {
    std::string list;
    const std::size_t n = std::size(stdin_model_formats);
    for (std::size_t i = 0; i < n; ++i)
        list += std::string(i == 0 ? "" : i + 1 == n ? " or " : ", ") + stdin_model_formats[i];
    return list;
}

fs::path hsr::host::model_path(const RenderOptions& o) {
    if (o.was_given("random-triangles")) return "random-triangles";
    if (o.model == "-") return "stdin";
    return fs::path(!o.model.empty() ? o.model : !o.heightmap.empty() ? o.heightmap : "surface");
}

