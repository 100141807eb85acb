// hsr-llvmpipe: the yardstick of `hsr bench --vs-llvmpipe`. Draws a bench model (loaded by
// hsr_framework, so the triangles, corner normals, camera and lights are those of hsr bench and hsr
// render) through Mesa's llvmpipe with per-pixel Blinn-Phong, and times complete frames (clear +
// draw + glFinish) as hsr bench times its frames: warm-up calls, then repetitions, the median.
// --compare also renders the scene with hsr (zbuffer + the same lighting) and reports how far the
// two pictures agree; --check makes that a pass/fail test. docs/speed/llvmpipe.md.
#include "bench/llvmpipe/osmesa_renderer.hpp"
#include "bench/measure.hpp"

#include "hsr/camera.hpp"
#include "hsr/defaults.hpp"
#include "hsr/error.hpp"
#include "hsr/image.hpp"
#include "hsr/instancing.hpp"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/renderer.hpp"
#include "hsr/scene_file.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/program_options.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

struct Options {
    std::string model = "bunny", models_dir, size = "1024", lighting = "blinn-phong", algorithm = "zbuffer";
    std::string png, background = hsr::default_background;
    std::vector<std::string> lights, plugin_dirs, limit_settings;
    std::optional<float> yaw, pitch, zoom, fov;
    bool orthographic = false, machine = false, compare = false, check = false;
    int64_t repetitions = 5, warmup = 1, threads = 0;
};

std::pair<uint32_t, uint32_t> parse_size(const std::string& text) {
    unsigned w = 0, h = 0;
    char x = 0, extra = 0;
    const int n = std::sscanf(text.c_str(), "%u%c%u%c", &w, &x, &h, &extra);
    if (n == 1 && text.find_first_not_of("0123456789") == std::string::npos) h = w;
    else if (!(n == 3 && x == 'x')) throw hsr::Error("--size: '{}' is not a size (512 or 800x600)", text);
    if (w == 0 || h == 0 || w > hsr::max_image_side || h > hsr::max_image_side)
        throw hsr::Error("--size: {}: each side must be between 1 and {}", text, hsr::max_image_side);
    hsr::check_limit(&hsr::Limits::image_pixels, uint64_t{w} * h, fmt::format("--size: {}", text));
    return {w, h};
}

glm::vec3 parse_color(const std::string& text) {
    glm::vec3 c;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%f/%f/%f%c", &c.r, &c.g, &c.b, &extra) != 3 ||
        !glm::all(glm::greaterThanEqual(c, glm::vec3(0.0f))) || !glm::all(glm::lessThanEqual(c, glm::vec3(1.0f))))
        throw hsr::Error("--background: '{}' is not a colour r/g/b with each in [0, 1]", text);
    return c;
}

// The blinn-phong plugin's parameters, defaults filled in, as the plugin reads them: the material
// is the plugin's own by construction.
hsr::llvmpipe::BlinnPhongMaterial read_material(const hsr::PluginRegistry& registry, const std::string& lighting) {
    const hsr::PluginSpec spec = hsr::parse_plugin_spec(lighting);
    if (spec.name != "blinn-phong")
        throw hsr::Error("-l {}: the yardstick draws blinn-phong only", spec.name);
    const hsr::Plugin& plugin = registry.find(HSR_KIND_LIGHTING_MODEL, spec.name);
    const hsr::ParamValues values = hsr::resolve_params(plugin.descriptor, spec.settings);
    hsr::llvmpipe::BlinnPhongMaterial m;
    for (const hsr_param_value& v : values.values()) {
        const std::string name = v.name;
        if (name == "ambient") m.ambient = float(v.number);
        else if (name == "diffuse") m.diffuse = float(v.number);
        else if (name == "specular") m.specular = float(v.number);
        else if (name == "shininess") m.shininess = float(v.number);
        else if (name == "specular-color") m.specular_color = {v.color[0], v.color[1], v.color[2]};
        else if (name == "two-sided") m.two_sided = v.number != 0;
        else if (name == "interpolation" && v.number != 2)
            throw hsr::Error("-l {}: the yardstick interpolates normals per pixel (interpolation=phong) only", lighting);
    }
    return m;
}

struct Agreement {
    uint64_t both = 0, only_hsr = 0, only_llvmpipe = 0;
    int max_difference = 0;           // largest channel difference where both drew, levels of 255
    double mean_difference = 0;       // mean over those pixels of the largest channel difference
    uint64_t differing = 0;           // pixels drawn by both in different colours
    uint64_t over_tolerance = 0;      // of those, differing by more than `tolerance`
    static constexpr int tolerance = 3;
    double coverage_mismatch() const {  // pixels drawn by one only, over pixels drawn by either
        const uint64_t either = both + only_hsr + only_llvmpipe;
        return either ? double(only_hsr + only_llvmpipe) / double(either) : 0.0;
    }
    double colour_mismatch() const { return both ? double(over_tolerance) / double(both) : 0.0; }
};

Agreement compare(const hsr::Frame& hsr_frame, const std::vector<uint8_t>& rgba) {
    Agreement a;
    double sum = 0;
    const size_t pixels = size_t{hsr_frame.width} * hsr_frame.height;
    for (size_t i = 0; i < pixels; ++i) {
        const bool by_hsr = hsr_frame.face[i] != HSR_NO_FACE;
        const bool by_llvmpipe = rgba[4 * i + 3] != 0;
        if (by_hsr != by_llvmpipe) {
            ++(by_hsr ? a.only_hsr : a.only_llvmpipe);
            continue;
        }
        if (!by_hsr) continue;
        ++a.both;
        int d = 0;
        for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(hsr_frame.rgb[3 * i + k]) - int(rgba[4 * i + k])));
        a.max_difference = std::max(a.max_difference, d);
        sum += d;
        if (d > 0) ++a.differing;
        if (d > Agreement::tolerance) ++a.over_tolerance;
    }
    a.mean_difference = a.both ? sum / double(a.both) : 0.0;
    return a;
}

std::string ms(double v) { return fmt::format("{:.{}f}", v, v < 10 ? 2 : 1); }

int run(const std::vector<std::string>& args) {
    Options o;
    po::options_description options(
        "hsr-llvmpipe [options]: the bench model drawn by Mesa's llvmpipe (OSMesa) with per-pixel Blinn-Phong,\n"
        "timed as hsr bench times hsr (complete frames: clear + draw + glFinish; medians)");
    options.add_options()
        ("help,h", "show this help")
        ("model", po::value(&o.model)->default_value(o.model), "a model as hsr bench --models names one")
        ("models-dir", po::value(&o.models_dir), "folder of the named models (default: the source tree's)")
        ("size", po::value(&o.size)->default_value(o.size), "image size: 512 or 800x600")
        ("yaw", po::value<float>(), "degrees (default: the bench scene's)")
        ("pitch", po::value<float>(), "degrees (default: the bench scene's)")
        ("zoom", po::value<float>(), "magnification (default: the bench scene's)")
        ("fov", po::value<float>(), "vertical field of view, degrees (default 35)")
        ("ortho", po::bool_switch(&o.orthographic), "orthographic projection")
        ("lighting,l", po::value(&o.lighting)->default_value(o.lighting), "blinn-phong[:key=value,...]")
        ("light", po::value(&o.lights)->composing(), "as hsr render --light (default: hsr render's)")
        ("background", po::value(&o.background)->default_value(o.background), "r/g/b, for --png")
        ("repetitions,r", po::value(&o.repetitions)->default_value(o.repetitions), "timed frames")
        ("warmup,w", po::value(&o.warmup)->default_value(o.warmup), "untimed frames first")
        ("threads", po::value(&o.threads)->default_value(0), "llvmpipe's threads, LP_NUM_THREADS (0 = one per core)")
        ("png", po::value(&o.png), "write the last frame to this PNG file")
        ("compare", po::bool_switch(&o.compare), "render with hsr too and print how far the pictures agree")
        ("check", po::bool_switch(&o.check),
         "--compare, and fail unless under 1 % of the drawn pixels are drawn by one renderer only and under "
         "1 % of the rest differ by more than 3 levels")
        ("algorithm,a", po::value(&o.algorithm)->default_value(o.algorithm), "hsr's hidden-surface plugin for --compare")
        ("machine", po::bool_switch(&o.machine), "print one line: frame-ms=... threads=... renderer=...")
        ("plugin-path", po::value(&o.plugin_dirs)->composing(), "extra folder to search for plugins")
        ("limit", po::value(&o.limit_settings)->composing(), hsr::describe_limit_option().c_str());
    po::variables_map vm;
    po::store(po::command_line_parser(args).options(options).run(), vm);
    po::notify(vm);
    if (vm.count("help")) {
        std::cout << options;
        return 0;
    }
    if (vm.count("yaw")) o.yaw = vm["yaw"].as<float>();
    if (vm.count("pitch")) o.pitch = vm["pitch"].as<float>();
    if (vm.count("zoom")) o.zoom = vm["zoom"].as<float>();
    if (vm.count("fov")) o.fov = vm["fov"].as<float>();
    if (o.repetitions < 1 || o.repetitions > 100000) throw hsr::Error("--repetitions must be between 1 and 100000");
    if (o.warmup < 0 || o.warmup > 100000) throw hsr::Error("--warmup must be between 0 and 100000");
    if (o.threads < 0 || o.threads > 1024) throw hsr::Error("--threads must be between 0 and 1024");
    o.compare = o.compare || o.check;
    hsr::set_limits(hsr::limits_from_settings(o.limit_settings));
    const auto [width, height] = parse_size(o.size);
    const glm::vec3 background = parse_color(o.background);

    // llvmpipe reads LP_NUM_THREADS when the first context is made.
    const unsigned threads = o.threads > 0 ? unsigned(o.threads) : std::max(1u, std::thread::hardware_concurrency());
    setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);

    const fs::path exe_dir(boost::dll::program_location().parent_path().string());
    hsr::PluginRegistry registry;
    for (const fs::path& dir : hsr::default_plugin_dirs(exe_dir, o.plugin_dirs)) registry.scan_directory(dir);
    const hsr::llvmpipe::BlinnPhongMaterial material = read_material(registry, o.lighting);

    // The scene and camera exactly as hsr bench makes them.
    const fs::path models_dir = o.models_dir.empty() ? fs::path(HSR_SOURCE_MODELS_DIR) : fs::path(o.models_dir);
    hsr::bench::BenchScene bench_scene = hsr::bench::load_bench_scene(hsr::bench::parse_model_spec(o.model, models_dir));
    if (o.yaw) bench_scene.camera.yaw_degrees = *o.yaw;
    if (o.pitch) bench_scene.camera.pitch_degrees = *o.pitch;
    if (o.zoom) bench_scene.camera.zoom = *o.zoom;
    if (o.fov) bench_scene.camera.fov_y_degrees = *o.fov;
    if (o.orthographic) bench_scene.camera.orthographic = true;
    // OSMesa draws plain triangles: the instances copied out, for hsr's frame too.
    if (!bench_scene.scene.instances.empty()) bench_scene.scene = hsr::flatten_instances(bench_scene.scene);
    hsr::Renderer hsr_renderer(hsr::LoadedScene::of(std::move(bench_scene.scene)));
    const hsr_camera camera = hsr::bench::make_bench_camera(hsr_renderer, bench_scene, width, height);
    const hsr_scene scene = hsr_renderer.loaded().scene().view();
    std::vector<hsr::LightSpec> light_specs;
    for (const std::string& spec : o.lights) light_specs.push_back(hsr::parse_light_spec(spec));
    const std::vector<hsr_light> lights = hsr_renderer.lights(light_specs, camera);
    const hsr_shading_context context = hsr::make_shading_context(camera, lights);

    hsr::llvmpipe::OsmesaRenderer renderer(width, height);
    renderer.upload(scene);  // once, as hsr builds its scene once
    renderer.set_view(camera, context, material, background);
    std::vector<double> frame_ms;
    for (int64_t call = 0; call < o.warmup + o.repetitions; ++call) {
        const auto start = std::chrono::steady_clock::now();
        renderer.draw_frame();
        const double elapsed = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        if (call >= o.warmup) frame_ms.push_back(elapsed);
    }
    const hsr::bench::Summary summary = hsr::bench::summarize(frame_ms);
    if (o.machine) {
        std::printf("frame-ms=%.4f threads=%u renderer=%s\n", summary.median, threads, renderer.description().c_str());
    } else {
        std::printf("%s, LP_NUM_THREADS=%u\n", renderer.description().c_str(), threads);
        std::printf("%s %ux%u, %u triangles, %zu vertices: frame %s ms median [%s-%s] over %zu runs after %lld "
                    "warm-up\n",
                    o.model.c_str(), width, height, scene.triangle_count, renderer.vertex_count(), ms(summary.median).c_str(),
                    ms(summary.min).c_str(), ms(summary.max).c_str(), summary.count, (long long)o.warmup);
    }

    const std::vector<uint8_t> rgba = renderer.read_rgba();
    if (!o.png.empty()) {
        std::vector<uint8_t> rgb(3 * size_t{width} * height);
        for (size_t i = 0; i < size_t{width} * height; ++i) std::copy_n(&rgba[4 * i], 3, &rgb[3 * i]);
        hsr::write_png(o.png, width, height, 3, rgb);
    }
    if (!o.compare) return 0;

    const hsr::PluginSpec algorithm = hsr::parse_plugin_spec(o.algorithm);
    const hsr::PluginSpec lighting_spec = hsr::parse_plugin_spec(o.lighting);
    hsr::HiddenSurfaceRemover remover(registry.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, algorithm.name), algorithm.settings);
    hsr::LightingModel lighting(registry.find(HSR_KIND_LIGHTING_MODEL, lighting_spec.name), lighting_spec.settings);
    hsr::PictureRequest request;
    request.view = hsr::bench::bench_view(bench_scene, width, height);
    request.lights = light_specs;
    request.background = background;
    request.samples = 1;
    request.threads = threads;
    const hsr::Frame frame = hsr_renderer.picture(request, remover, lighting).frame;
    const Agreement a = compare(frame, rgba);
    std::printf("compared with hsr %s: %llu pixels drawn by both, %llu by hsr only, %llu by llvmpipe only "
                "(%.3f %% of the drawn pixels)\n",
                o.algorithm.c_str(), (unsigned long long)a.both, (unsigned long long)a.only_hsr,
                (unsigned long long)a.only_llvmpipe, 100.0 * a.coverage_mismatch());
    std::printf("colours where both drew: %llu pixels differ, by %.4f levels on average and %d at most; %llu pixels "
                "(%.3f %%) by more than %d\n",
                (unsigned long long)a.differing, a.mean_difference, a.max_difference,
                (unsigned long long)a.over_tolerance, 100.0 * a.colour_mismatch(), Agreement::tolerance);
    if (o.check && (a.coverage_mismatch() >= 0.01 || a.colour_mismatch() >= 0.01)) {
        std::fprintf(stderr, "hsr-llvmpipe: the pictures differ more than --check allows\n");
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const po::error& e) {
        std::fprintf(stderr, "hsr-llvmpipe: %s (see --help)\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "hsr-llvmpipe: %s\n", e.what());
    }
    return 1;
}
