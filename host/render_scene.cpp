// hsr render's scene and camera, from a mesh, a .scene file, a formula, a height map or random
// triangles, optionally repeated into a deep scene (render.hpp).
#include "commands.hpp"
#include "render.hpp"

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
#include "hsr/limits.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/random_triangles.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"
#include "hsr/surface.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

namespace fs = std::filesystem;

namespace {

using hsr::host::RenderOptions;
using hsr::host::UsageError;

// "CxRxL" (columns x rows x layers) for --repeat.
hsr::InstanceGrid parse_repeat(const std::string& text, float gap, float jitter) {
    hsr::InstanceGrid grid;
    unsigned long long c = 0, r = 0, l = 0;
    char x1 = 0, x2 = 0, extra = 0;
    if (text.find_first_not_of("0123456789x") != std::string::npos ||
        std::sscanf(text.c_str(), "%llu%c%llu%c%llu%c", &c, &x1, &r, &x2, &l, &extra) != 5 || x1 != 'x' || x2 != 'x' ||
        c == 0 || r == 0 || l == 0)
        throw UsageError("--repeat '{}': expected COLUMNSxROWSxLAYERS, each at least 1, e.g. 4x3x20", hsr::printable(text));
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

// The scene file's image size and view, where the command line leaves them open.
void apply_scene_file_view(const hsr::SceneFile& file, const RenderOptions& o, hsr::CameraSettings& view) {
    if (file.width && !o.was_given("width")) view.width = *file.width;
    if (file.height && !o.was_given("height")) view.height = *file.height;
    if (file.yaw_degrees && !o.was_given("yaw")) view.yaw_degrees = *file.yaw_degrees;
    if (file.pitch_degrees && !o.was_given("pitch")) view.pitch_degrees = *file.pitch_degrees;
    if (file.zoom && !o.was_given("zoom")) view.zoom = *file.zoom;
    if (file.fov_y_degrees && !o.was_given("fov")) view.fov_y_degrees = *file.fov_y_degrees;
    if (file.look_at && !view.look_at && !o.was_given("yaw") && !o.was_given("pitch") && !o.was_given("views"))
        view.look_at = file.look_at;
    if (file.orthographic && !o.orthographic) view.orthographic = *file.orthographic;
}

}  // namespace

uint64_t hsr::host::parse_seed(const std::string& text) {
    uint64_t seed = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), seed);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size())
        throw UsageError("--seed '{}': expected a whole number from 0 to 18446744073709551615", hsr::printable(text));
    return seed;
}

std::string hsr::host::scene_load_key(const RenderOptions& o) {
    // Every option load_scene reads, a line each (a job's options come from one line, so hold no line
    // break); files by their absolute paths, so that ./a.obj and a.obj share a load.
    std::string key;
    const auto add = [&key](const char* name, const std::string& value) { key += fmt::format("{}={}\n", name, value); };
    const auto file = [](const std::string& path) {
        std::error_code ec;
        const fs::path resolved = path.empty() ? fs::path() : fs::weakly_canonical(fs::absolute(path, ec), ec);
        return ec || resolved.empty() ? path : resolved.string();
    };
    add("model", file(o.model));
    add("random-triangles", o.was_given("random-triangles") ? std::to_string(o.random_triangles) : "");
    add("seed", o.seed);
    add("surface", o.surface);
    add("range", o.range);
    add("heightmap", file(o.heightmap));
    add("heightmap-height", fmt::format("{}", o.heightmap_height));
    add("crease-angle", fmt::format("{}", o.crease_angle));
    add("color", o.color);
    add("opacity", o.was_given("opacity") ? fmt::format("{}", o.opacity) : "");
    add("repeat", o.repeat);
    add("repeat-gap", fmt::format("{}", o.repeat_gap));
    add("repeat-jitter", fmt::format("{}", o.repeat_jitter));
    for (const std::string& limit : o.limits) add("limit", limit);
    return key;
}

const hsr::SceneData& hsr::host::LoadedScene::flat_scene() {
    if (scene.instances.empty()) return scene;
    if (!flat_) flat_ = hsr::flatten_instances(scene);
    return *flat_;
}

hsr::host::LoadedScene hsr::host::load_scene(const RenderOptions& o) {
    LoadedScene loaded;
    const fs::path path = model_path(o);
    if (o.was_given("random-triangles")) {
        loaded.scene = hsr::make_random_triangles(uint64_t(o.random_triangles), parse_seed(o.seed));
    } else if (!o.surface.empty()) {
        const hsr::SurfaceRange range = o.range.empty() ? hsr::SurfaceRange{} : hsr::parse_surface_range(o.range);
        loaded.scene = hsr::make_formula_surface(o.surface, range,
                                                 o.color.empty() ? glm::vec3(0.8f) : parse_color_option(o.color, "color"));
    } else if (!o.heightmap.empty()) {
        hsr::HeightmapOptions heightmap;
        heightmap.height = o.heightmap_height;
        if (!o.color.empty()) heightmap.color = parse_color_option(o.color, "color");
        loaded.scene = hsr::make_heightmap_surface(o.heightmap, heightmap);
    } else if (hsr::is_scene_file(path)) {
        loaded.file = hsr::load_scene_file(path);
        loaded.scene = std::move(loaded.file->scene);
        loaded.file->scene = {};
    } else {
        hsr::MeshOptions mesh_options;
        mesh_options.crease_angle_degrees = o.crease_angle;
        if (!o.color.empty()) mesh_options.color = parse_color_option(o.color, "color");
        loaded.scene = hsr::load_model(path, mesh_options);
    }
    hsr::SceneData& scene = loaded.scene;
    if (o.was_given("opacity")) {
        if (hsr::is_scene_file(path))
            throw UsageError("--opacity is for a single model: give the objects of '{}' `opacity` lines",
                             hsr::printable(path.string(), hsr::kMaxQuotedPathChars));
        if (o.opacity < 1.0f) scene.object_opacity.assign(scene.object_names.size(), o.opacity);
    }
    if (!o.repeat.empty()) {
        if (!scene.instances.empty())
            throw UsageError("--repeat: '{}' already places copies of its meshes (a 'repeat' line); use one or the other",
                             hsr::printable(path.string(), hsr::kMaxQuotedPathChars));
        const hsr::InstanceGrid grid = parse_repeat(o.repeat, o.repeat_gap, o.repeat_jitter);
        try {
            scene = hsr::make_instance_grid(scene, grid);
        } catch (const hsr::Error& e) {
            throw hsr::Error("--repeat {}: {}", o.repeat, e.what());
        }
    }
    for (const std::string& warning : scene.warnings) std::fprintf(stderr, "hsr: warning: %s\n", warning.c_str());
    return loaded;
}

hsr::host::RenderScene hsr::host::make_render_scene(const RenderOptions& o, LoadedScene& loaded, bool line_drawing) {
    RenderScene frame{line_drawing ? loaded.flat_scene() : loaded.scene, {}, {}, {}, {}};
    bool pixel_camera = false;
    hsr::CameraSettings view;
    view.width = static_cast<uint32_t>(o.width);
    view.height = static_cast<uint32_t>(o.height);
    view.yaw_degrees = o.yaw;
    view.pitch_degrees = o.pitch;
    view.zoom = o.zoom;
    view.orthographic = o.orthographic;
    view.fov_y_degrees = o.fov;
    if (o.was_given("near")) view.near_plane = o.near_plane;
    if (!o.eye.empty()) {
        hsr::LookAt look_at;
        look_at.eye = parse_vector_option(o.eye, "eye");
        if (!o.target.empty()) look_at.target = parse_vector_option(o.target, "target");
        if (!o.up.empty()) look_at.up = parse_vector_option(o.up, "up");
        view.look_at = look_at;
    }
    if (loaded.file) {
        const hsr::SceneFile& file = *loaded.file;
        frame.lights = file.lights;
        frame.background = file.background;
        frame.samples = file.samples;
        pixel_camera = file.pixel_camera;
        apply_scene_file_view(file, o, view);
        view.clip_planes = file.clip_planes;
    }
    if (o.yaw_turn != 0) view.yaw_degrees = float(double(view.yaw_degrees) + o.yaw_turn);
    const hsr::SceneData& scene = loaded.scene;
    hsr::check_image_size(view.width, view.height);
    hsr::check_limit(&hsr::Limits::image_pixels, uint64_t(view.width) * view.height,
                     fmt::format("image size {}x{}", view.width, view.height));
    add_clip_plane_options(o, view.clip_planes);
    if (pixel_camera && view.near_plane) throw UsageError("--near does not apply to a .scene file with 'camera pixel'");
    frame.camera = pixel_camera ? hsr::make_pixel_camera(view.width, view.height, scene.bounds_min.z,
                                                         scene.bounds_max.z, view.clip_planes)
                                : hsr::make_camera(scene.bounds_min, scene.bounds_max, view);
    return frame;
}
