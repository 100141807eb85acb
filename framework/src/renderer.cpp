// The renderer (renderer.hpp): a scene loaded once, then views, lights and plugins resolved against
// what the request sets, what the .scene file says and the defaults, in that order.
#include "hsr/renderer.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"
#include "hsr/random_triangles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

namespace fs = std::filesystem;

namespace hsr {
namespace {

SceneData load_source(const SceneSource& source, const ReadPolicy& policy, std::optional<SceneFile>& file,
                      std::vector<ModelCamera>& cameras) {
    if (source.random_triangles) return make_random_triangles(source.random_triangles->count, source.random_triangles->seed);
    if (source.formula) return make_formula_surface(source.formula->text, source.formula->range, source.formula->color);
    const fs::path path = source.path();
    if (!policy.allows(path))
        throw Error("'{}' lies outside {}", printable(path.string(), kMaxQuotedPathChars), policy.description());
    if (!source.heightmap.empty()) return make_heightmap_surface(source.heightmap, source.heightmap_options);
    if (is_scene_file(path)) {
        file = load_scene_file(path, policy, source.language);
        SceneData scene = std::move(file->scene);
        file->scene = {};
        return scene;
    }
    return load_model(path, source.mesh, &cameras);
}

// The model's camera that --camera names: by name, else by index.
const ModelCamera& find_model_camera(const LoadedScene& scene, const std::string& wanted) {
    const std::vector<ModelCamera>& cameras = scene.cameras();
    const std::string file = printable(scene.source_name(), kMaxQuotedPathChars);
    if (cameras.empty()) throw UsageError("--camera {}: {} has no cameras", printable(wanted, 100), file);
    for (const ModelCamera& camera : cameras)
        if (camera.name == wanted) return camera;
    if (!wanted.empty() && wanted.size() < 10 && std::all_of(wanted.begin(), wanted.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
        std::stoul(wanted) < cameras.size())
        return cameras[std::stoul(wanted)];
    std::string known;
    for (std::size_t c = 0; c < cameras.size(); ++c)
        known += fmt::format("{}{} '{}'", c == 0 ? "" : ", ", c, printable(cameras[c].name, 100));
    throw UsageError("--camera {}: no such camera in {} (its cameras: {})", printable(wanted, 100), file, known);
}

// The view through a model's camera; what the request sets besides still wins.
void apply_model_camera(const ModelCamera& camera, const ViewRequest& request, CameraSettings& view) {
    LookAt look;
    look.eye = camera.eye;
    look.target = camera.eye + camera.forward;
    look.up = camera.up;
    view.look_at = look;
    if (!request.near_plane && camera.znear > 0) view.near_plane = camera.znear;
    if (camera.orthographic) {
        if (!request.orthographic) view.orthographic = true;
        if (camera.ymag > 0) view.ortho_half_height = camera.ymag;
        const float aspect = camera.ymag > 0 ? camera.xmag / camera.ymag : 0;
        if (aspect > 0 && std::isfinite(aspect) && !request.width)
            view.width = std::max(1u, uint32_t(std::lround(double(view.height) * aspect)));
    } else {
        if (!request.fov_y_degrees && camera.yfov_radians > 0 && camera.yfov_radians < 3.14159f)
            view.fov_y_degrees = glm::degrees(camera.yfov_radians);
        if (camera.aspect_ratio > 0 && std::isfinite(camera.aspect_ratio) && !request.width)
            view.width = std::max(1u, uint32_t(std::lround(double(view.height) * camera.aspect_ratio)));
    }
}

// The .scene file's size and view, where the request leaves them open.
void apply_scene_file_view(const SceneFile& file, const ViewRequest& request, CameraSettings& view) {
    if (file.width && !request.width) view.width = *file.width;
    if (file.height && !request.height) view.height = *file.height;
    if (file.yaw_degrees && !request.yaw_degrees) view.yaw_degrees = *file.yaw_degrees;
    if (file.pitch_degrees && !request.pitch_degrees) view.pitch_degrees = *file.pitch_degrees;
    if (file.zoom && !request.zoom) view.zoom = *file.zoom;
    if (file.fov_y_degrees && !request.fov_y_degrees) view.fov_y_degrees = *file.fov_y_degrees;
    if (file.look_at && !view.look_at && !request.orbit_given) view.look_at = file.look_at;
    if (file.orthographic && !request.orthographic) view.orthographic = *file.orthographic;
}

std::string camera_bytes(const hsr_camera& camera) {
    std::string bytes(sizeof camera, '\0');
    std::memcpy(bytes.data(), &camera, sizeof camera);
    return bytes;
}

}  // namespace

glm::vec3 default_background_color() {
    const hsr_param_desc desc{sizeof(hsr_param_desc), "background", HSR_PARAM_COLOR, "", 0, 1, nullptr, ""};
    const hsr_param_value v = parse_param_value(desc, default_background);
    return {v.color[0], v.color[1], v.color[2]};
}

fs::path SceneSource::path() const {
    if (random_triangles) return "random-triangles";
    return !model.empty() ? model : !heightmap.empty() ? heightmap : fs::path("surface");
}

std::shared_ptr<LoadedScene> LoadedScene::load(const SceneSource& source, const ReadPolicy& policy) {
    auto loaded = std::make_shared<LoadedScene>();
    SceneData& scene = loaded->scene_;
    scene = load_source(source, policy, loaded->file_, loaded->cameras_);
    loaded->source_name_ = source.path().string();
    const fs::path path = source.path();
    if (source.opacity) {
        if (is_scene_file(path))
            throw UsageError("--opacity is for a single model: give the objects of '{}' `opacity` lines",
                             printable(path.string(), kMaxQuotedPathChars));
        if (*source.opacity < 1.0f) scene.object_opacity.assign(scene.object_names.size(), *source.opacity);
    }
    if (source.repeat) {
        if (!scene.instances.empty())
            throw UsageError("--repeat: '{}' already places copies of its meshes (a 'repeat' line, or glTF nodes "
                             "sharing a mesh); use one or the other",
                             printable(path.string(), kMaxQuotedPathChars));
        try {
            scene = make_instance_grid(scene, *source.repeat);
        } catch (const Error& e) {
            rethrow_with_message(e, fmt::format("--repeat {}: {}", source.repeat_text, e.what()));
        }
    }
    return loaded;
}

std::shared_ptr<LoadedScene> LoadedScene::of(SceneData scene, std::string source_name) {
    auto loaded = std::make_shared<LoadedScene>();
    loaded->scene_ = std::move(scene);
    loaded->source_name_ = std::move(source_name);
    return loaded;
}

const SceneData& LoadedScene::flat_scene() const {
    if (scene_.instances.empty()) return scene_;
    std::call_once(flat_once_, [this] { flat_ = flatten_instances(scene_); });
    return *flat_;
}

uint64_t LoadedScene::memory() const {
    const auto size = [](const SceneData& d) {
        return d.positions.size() * 4 + d.indices.size() * 4 + d.face_normals.size() * 4 + d.corner_normals.size() * 4 +
               d.face_colors.size() * 4 + d.edge_neighbors.size() * 4 + d.face_object.size() * 4 +
               d.instances.size() * sizeof(hsr_instance);
    };
    return size(scene_) + (flat_ ? size(*flat_) : 0);
}

Renderer::Renderer(std::shared_ptr<const LoadedScene> scene) : scene_(std::move(scene)) {}

hsr_camera Renderer::camera(const ViewRequest& request) const {
    CameraSettings view;
    if (request.width) view.width = *request.width;
    if (request.height) view.height = *request.height;
    if (request.yaw_degrees) view.yaw_degrees = *request.yaw_degrees;
    if (request.pitch_degrees) view.pitch_degrees = *request.pitch_degrees;
    if (request.zoom) view.zoom = *request.zoom;
    if (request.fov_y_degrees) view.fov_y_degrees = *request.fov_y_degrees;
    view.orthographic = request.orthographic.value_or(false);
    view.near_plane = request.near_plane;
    view.look_at = request.look_at;
    bool pixel_camera = false;
    if (const std::optional<SceneFile>& file = scene_->file()) {
        pixel_camera = file->pixel_camera;
        apply_scene_file_view(*file, request, view);
        if (pixel_camera && request.pixel_camera_keeps_size) {
            view.width = *file->width;
            view.height = *file->height;
        }
        view.clip_planes = file->clip_planes;
    }
    if (!request.model_camera.empty()) apply_model_camera(find_model_camera(*scene_, request.model_camera), request, view);
    if (request.yaw_turn_degrees != 0) view.yaw_degrees = float(double(view.yaw_degrees) + request.yaw_turn_degrees);
    check_image_size(view.width, view.height);
    check_image_pixels(view.width, view.height);
    view.clip_planes.insert(view.clip_planes.end(), request.clip_planes.begin(), request.clip_planes.end());
    if (view.clip_planes.size() > HSR_MAX_CLIP_PLANES)
        throw UsageError("{} sections and clip planes: at most {} (a .scene file's count too)", view.clip_planes.size(),
                         HSR_MAX_CLIP_PLANES);
    if (pixel_camera && view.near_plane) throw UsageError("--near does not apply to a .scene file with 'camera pixel'");
    const SceneData& scene = scene_->scene();
    return pixel_camera ? make_pixel_camera(view.width, view.height, scene.bounds_min.z, scene.bounds_max.z,
                                            view.clip_planes)
                        : make_camera(scene.bounds_min, scene.bounds_max, view);
}

std::vector<hsr_light> Renderer::lights(const std::vector<LightSpec>& requested, const hsr_camera& camera) const {
    std::vector<LightSpec> specs = requested;
    if (specs.empty() && scene_->file()) specs = scene_->file()->lights;
    if (specs.empty()) specs.push_back(parse_light_spec(default_light));
    std::vector<hsr_light> lights;
    for (const LightSpec& spec : specs) lights.push_back(resolve_light(spec, camera));
    return lights;
}

uint64_t Renderer::count_steps(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                               StepProgress* progress) {
    const std::string key = remover.key() + '\n' + camera_bytes(camera);
    {
        std::lock_guard lock(caches_mutex_);
        if (auto known = step_totals_.find(key); known != step_totals_.end()) return known->second;
    }
    Frame counted;
    resolve_visibility_steps(scene, camera, remover, counted, 0, false, false, progress);
    const uint64_t total = counted.steps ? counted.steps->taken : 0;
    keep_step_total(key, total);
    return total;
}

void Renderer::keep_step_total(const std::string& key, uint64_t total) {
    constexpr std::size_t kept_totals = 256;
    std::lock_guard lock(caches_mutex_);
    if (step_totals_.size() >= kept_totals) step_totals_.clear();
    step_totals_[key] = total;
}

StepOutline Renderer::step_outline(const ViewRequest& view, HiddenSurfaceRemover& remover, const std::string& language,
                                   StepProgress* progress) {
    const hsr_camera camera = this->camera(view);
    const hsr_scene scene = scene_->scene().view();
    StepOutline outline;
    Frame frame;
    resolve_visibility_steps(scene, camera, remover, frame, 0, false, false, progress, language, &outline);
    keep_step_total(remover.key() + '\n' + camera_bytes(camera), outline.total);
    return outline;
}

Picture Renderer::picture(const PictureRequest& request, HiddenSurfaceRemover& remover, LightingModel& lighting) {
    Picture picture;
    picture.camera = camera(request.view);
    picture.scene = scene_->scene().view();
    const std::optional<SceneFile>& file = scene_->file();
    FrameSettings settings;
    settings.background = request.background       ? *request.background
                          : file && file->background ? *file->background
                                                     : default_background_color();
    settings.coverage_alpha = request.transparent_background;
    settings.threads = request.threads;
    settings.count_depth_tests = request.count_depth_tests;
    settings.samples = request.samples ? *request.samples : file && file->samples ? *file->samples : 1u;
    picture.samples = settings.samples;
    check_image_pixels(picture.camera.width, picture.camera.height, settings.samples);
    if (request.step) {
        uint64_t step = *request.step;
        if (request.step_context) {
            picture.step_total = count_steps(picture.scene, picture.camera, remover, request.step_progress);
            if (request.step_progress != nullptr) request.step_progress->total.store(picture.step_total);
            step = std::min(step, picture.step_total);
            settings.keep_step_before = true;
        }
        settings.stop_after_step = step;
        settings.step_progress = request.step_progress;
        settings.step_language = request.step_language;
        picture.step_shown = step;
    }
    const std::vector<hsr_light> world_lights = lights(request.lights, picture.camera);
    const hsr_shading_context context = make_shading_context(picture.camera, world_lights);
    picture.frame = render_supersampled_frame(picture.scene, picture.camera, remover, lighting, context, settings);
    std::vector<float>().swap(picture.frame.bary);  // 8 bytes a pixel, needed only for shading
    if (picture.frame.steps && picture.frame.steps->before) {
        VisibilityState& before = *picture.frame.steps->before;
        picture.before.depth = std::move(before.depth);
        picture.before.face = std::move(before.face);
        picture.before.instance = std::move(before.instance);
        picture.before.depth_tests = std::move(before.depth_tests);
        picture.frame.steps->before.reset();
    }
    if (request.depth_complexity) {
        std::optional<PixelRegion> region = request.depth_complexity_region;
        const uint32_t width = picture.camera.width, height = picture.camera.height;
        if (region) {  // clipped to the picture
            region->width = region->x < width ? std::min(region->width, width - region->x) : 0;
            region->height = region->y < height ? std::min(region->height, height - region->y) : 0;
        }
        if (!region || (region->width > 0 && region->height > 0))
            picture.depth_complexity = kept_depth_complexity(picture.camera, region);
    }
    return picture;
}

LinePicture Renderer::lines(const LineRequest& request, HiddenLineRemover& remover) const {
    LinePicture picture;
    picture.camera = camera(request.view);
    picture.scene = scene_->flat_scene().view();
    LineSettings settings = request.settings;
    if (request.step) {
        settings.stop_after_event = *request.step;
        settings.past_end_is_last = true;
    }
    picture.drawing = render_lines(picture.scene, picture.camera, remover, settings);
    return picture;
}

DepthComplexity Renderer::depth_complexity(const hsr_camera& camera) const {
    return measure_depth_complexity(scene_->scene().view(), camera);
}

std::shared_ptr<const DepthComplexity> Renderer::kept_depth_complexity(const hsr_camera& camera,
                                                                       const std::optional<PixelRegion>& region) {
    std::string key = camera_bytes(camera);
    if (region) key += fmt::format(" {} {} {} {}", region->x, region->y, region->width, region->height);
    {
        std::lock_guard lock(caches_mutex_);
        for (const auto& [known, complexity] : depth_complexities_)
            if (known == key) return complexity;
    }
    auto complexity =
        std::make_shared<const DepthComplexity>(measure_depth_complexity(scene_->scene().view(), camera, region));
    constexpr std::size_t kept_complexities = 4;
    std::lock_guard lock(caches_mutex_);
    depth_complexities_.emplace_front(key, complexity);
    if (depth_complexities_.size() > kept_complexities) depth_complexities_.pop_back();
    return complexity;
}

FrameLoop::FrameLoop(const hsr_scene& scene, const hsr_camera& camera, const hsr_shading_context& context,
                     const FrameSettings& settings, HiddenSurfaceRemover& remover, LightingModel& lighting)
    : scene_(scene),
      camera_(camera),
      lights_(context.lights, context.lights + context.light_count),
      context_(context),
      settings_(settings),
      remover_(remover),
      lighting_(lighting) {
    context_.lights = lights_.data();
    if (needs_flat_scene(remover.plugin(), scene) || needs_flat_scene(lighting.plugin(), scene)) {
        flat_ = flatten_instances(scene);
        scene_ = flat_->view();
    }
}

const Frame& FrameLoop::render() {
    Frame& frame = frame_;
    frame.counters.clear();
    if (remover_.has_fragments()) {
        resolve_fragments(scene_, camera_, remover_, frame, fragments_, false);
        shade_fragments(scene_, lighting_, context_, settings_, fragments_, frame);
    } else {
        resolve_visibility(scene_, camera_, remover_, frame, false);
        shade_frame(scene_, lighting_, context_, settings_, frame);
    }
    return frame;
}

}  // namespace hsr
