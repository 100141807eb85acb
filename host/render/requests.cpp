// hsr render's options as the renderer's requests (render.hpp, hsr/renderer.hpp): the scene's
// source, the view and the picture.
#include "common/options.hpp"
#include "render/render.hpp"

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
        throw UsageError("--repeat '{}': at most {} along each side", hsr::printable(text), max_side);
    if (!(gap >= 0.0f) || !std::isfinite(gap)) throw UsageError("--repeat-gap must be 0 or more");
    if (!(jitter >= 0.0f) || !(jitter <= 180.0f)) throw UsageError("--repeat-jitter must be between 0 and 180 degrees");
    grid.columns = uint32_t(c);
    grid.rows = uint32_t(r);
    grid.layers = uint32_t(l);
    grid.gap = gap;
    grid.yaw_jitter_degrees = jitter;
    return grid;
}

}  // namespace

std::string hsr::host::scene_load_key(const RenderOptions& o) {
    // Every option scene_source reads, a line each (a job's options come from one line, so hold no line
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

hsr::SceneSource hsr::host::scene_source(const RenderOptions& o) {
    hsr::SceneSource source;
    if (o.was_given("random-triangles")) {
        source.random_triangles = hsr::SceneSource::RandomTriangles{uint64_t(o.random_triangles), parse_seed(o.seed)};
    } else if (!o.surface.empty()) {
        hsr::SceneSource::Formula formula;
        formula.text = o.surface;
        if (!o.range.empty()) formula.range = hsr::parse_surface_range(o.range);
        if (!o.color.empty()) formula.color = parse_color_option(o.color, "color");
        source.formula = formula;
    } else if (!o.heightmap.empty()) {
        source.heightmap = o.heightmap;
        source.heightmap_options.height = o.heightmap_height;
        if (!o.color.empty()) source.heightmap_options.color = parse_color_option(o.color, "color");
    } else {
        source.model = o.model;
        source.mesh.crease_angle_degrees = o.crease_angle;
        if (!o.color.empty()) {
            source.mesh.color = parse_color_option(o.color, "color");
            source.mesh.color_given = true;  // over the file's own colours
        }
    }
    if (o.was_given("opacity")) source.opacity = o.opacity;
    if (!o.repeat.empty()) {
        source.repeat = parse_repeat(o.repeat, o.repeat_gap, o.repeat_jitter);
        source.repeat_text = o.repeat;
    }
    return source;
}

hsr::ViewRequest hsr::host::view_request(const RenderOptions& o) {
    hsr::ViewRequest view;
    // The defaults of the options are the renderer's; only what was given overrides a .scene file.
    view.width = o.was_given("width") ? std::optional(uint32_t(o.width)) : std::nullopt;
    view.height = o.was_given("height") ? std::optional(uint32_t(o.height)) : std::nullopt;
    view.yaw_degrees = o.was_given("yaw") ? std::optional(o.yaw) : std::nullopt;
    view.pitch_degrees = o.was_given("pitch") ? std::optional(o.pitch) : std::nullopt;
    view.zoom = o.was_given("zoom") ? std::optional(o.zoom) : std::nullopt;
    view.fov_y_degrees = o.was_given("fov") ? std::optional(o.fov) : std::nullopt;
    if (o.orthographic) view.orthographic = true;
    view.orbit_given = o.was_given("yaw") || o.was_given("pitch") || o.was_given("views");
    view.yaw_turn_degrees = o.yaw_turn;
    if (o.was_given("near")) view.near_plane = o.near_plane;
    if (!o.eye.empty()) {
        hsr::LookAt look_at;
        look_at.eye = parse_vector_option(o.eye, "eye");
        if (!o.target.empty()) look_at.target = parse_vector_option(o.target, "target");
        if (!o.up.empty()) look_at.up = parse_vector_option(o.up, "up");
        view.look_at = look_at;
    }
    view.model_camera = o.camera;
    add_clip_plane_options(o, view.clip_planes);
    return view;
}
