// hsr view's frames (view_frames.hpp): a request checked (view_request.cpp), the model's renderer
// (hsr/renderer.hpp) and the plugin instances taken from small caches, one render at a time under a
// mutex, and the response with the picture PNG-encoded (hsr/image.hpp) and base64'd. Over 700 lines:
// frames, step outlines and step ZIPs share the request checking, the caches and that one mutex.
#include "view/server/view_frames.hpp"

#include "common/options.hpp"
#include "view/server/view_line_steps.hpp"
#include "view/server/view_request.hpp"
#include "view/server/view_steps.hpp"
#include "view/server/view_zip.hpp"

#include "hsr/image.hpp"
#include "hsr/language.hpp"
#include "hsr/line_image.hpp"
#include "hsr/lines.hpp"
#include "hsr/params.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/renderer.hpp"

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cstring>
#include <cmath>
#include <list>
#include <map>
#include <mutex>
#include <optional>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using hsr::host::ViewError;

constexpr std::size_t cached_models = 4;
constexpr uint64_t cached_model_bytes = uint64_t(1) << 30;  // of the models kept besides the newest
constexpr std::size_t cached_instances = 16;
constexpr std::size_t max_step_pixels = 20000;
constexpr std::size_t cached_outlines = 4;

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// A model's renderer, with what tells whether its file changed since it was loaded.
struct CachedModel {
    std::shared_ptr<hsr::Renderer> renderer;
    fs::file_time_type modified;
    uint64_t bytes = 0;  // the file's
};

// The model as the renderer loads it; a .scene file reads only meshes inside the folders hsr view
// serves (ModelCatalog::read_policy). A .scene file's mistakes are told in `language` ("en" or "ru"),
// the page's: the scene editor shows them beside the line.
std::shared_ptr<CachedModel> load_model_entry(const hsr::host::ModelEntry& entry, const hsr::ReadPolicy& read_policy,
                                              const std::string& language) {
    auto cached = std::make_shared<CachedModel>();
    std::error_code ec;
    cached->modified = fs::last_write_time(entry.path, ec);
    cached->bytes = entry.bytes;
    hsr::SceneSource source;
    source.model = entry.path;
    source.mesh.crease_angle_degrees = 40;
    source.language = hsr::language_from_code(language);
    try {
        cached->renderer = std::make_shared<hsr::Renderer>(hsr::LoadedScene::load(source, read_policy));
    } catch (const hsr::Error& e) {
        throw ViewError(400, "model", e.what());
    }
    return cached;
}

// The renderer's view of a request: everything the request says wins over a .scene file, but for
// the size of a `camera pixel` scene.
hsr::ViewRequest view_of(const hsr::host::FrameRequest& q) {
    hsr::ViewRequest view;
    view.width = q.width;
    view.height = q.height;
    view.yaw_degrees = q.view.yaw_degrees;
    view.pitch_degrees = q.view.pitch_degrees;
    view.zoom = q.view.zoom;
    view.fov_y_degrees = q.view.fov_y_degrees;
    view.orthographic = q.view.orthographic;
    view.look_at = q.view.look_at;
    view.orbit_given = true;
    view.pixel_camera_keeps_size = true;
    return view;
}

// The arrays of an answer, one after the other, as their bytes: little-endian on every machine
// hsr builds for. Every array here holds 4-byte values, so each starts at a multiple of 4.
struct ArrayBlock {
    std::string bytes;

    // The values of `region` (x, y, width, height) of a picture `picture_width` values wide.
    template <class T>
    json add(const char* type, const std::vector<T>& values, uint32_t picture_width, const std::array<uint32_t, 4>& region) {
        static_assert(sizeof(T) == 4);
        const std::size_t offset = bytes.size();
        const std::size_t row_bytes = std::size_t(region[2]) * sizeof(T);
        bytes.resize(offset + row_bytes * region[3]);
        char* out = bytes.data() + offset;
        for (uint32_t y = 0; y < region[3]; ++y, out += row_bytes)
            std::memcpy(out, values.data() + std::size_t(region[1] + y) * picture_width + region[0], row_bytes);
        return {{"array", type}, {"offset", offset}, {"length", std::size_t(region[2]) * region[3]}};
    }
    template <class T>
    json add_all(const char* type, const std::vector<T>& values, uint32_t width, uint32_t height) {
        return add(type, values, width, {0, 0, width, height});
    }
};

// A `camera pixel` scene's own z at window depth `depth`: make_pixel_camera puts the eye on +z with
// view space world space moved to the eye, and its orthographic projection maps view distances
// near..far onto window depths 0..1, so the map is affine: z = eye.z - near - depth (far - near).
// Nothing drawn (depth +inf) is -inf: behind everything.
double pixel_camera_scene_z(const hsr_camera& camera, float depth) {
    const double near_plane = camera.near_plane, far_plane = camera.far_plane;
    return double(camera.eye[2]) - near_plane - double(depth) * (far_plane - near_plane);
}

bool is_pixel_camera_scene(const hsr::Renderer& renderer) {
    const std::optional<hsr::SceneFile>& file = renderer.loaded().file();
    return file && file->pixel_camera;
}

std::string png_data_url(uint32_t width, uint32_t height, std::span<const uint8_t> rgb) {
    const std::vector<uint8_t> png = hsr::encode_png(width, height, 3, rgb);
    return "data:image/png;base64," + hsr::host::base64(png.data(), png.size());
}

json counters_json(const std::vector<std::pair<std::string, uint64_t>>& counters) {
    json out = json::object();
    for (const auto& [name, value] : counters) out[name] = value;
    return out;
}

// The parts of a frame's answer that pictures and line drawings share: the picture as a PNG data
// URL, its size and kind, and the stats, with the time the PNG took.
struct PictureTimes {
    double visibility_ms = 0, shading_ms = 0;
};
json picture_response(const char* kind, uint32_t width, uint32_t height, std::span<const uint8_t> rgb,
                      const std::vector<std::pair<std::string, uint64_t>>& counters, PictureTimes times,
                      uint64_t triangles, bool picture) {
    const auto encode_start = std::chrono::steady_clock::now();
    json response;
    response["png"] = picture ? json(png_data_url(width, height, rgb)) : json(nullptr);
    const double encode_ms = ms_since(encode_start);
    response["width"] = width;
    response["height"] = height;
    response["kind"] = kind;
    response["stats"] = {{"counters", counters_json(counters)},
                         {"visibility_ms", times.visibility_ms},
                         {"shading_ms", times.shading_ms},
                         {"triangles", triangles},
                         {"encode_ms", encode_ms}};
    return response;
}

}  // namespace

std::string hsr::host::frame_with_arrays_head(const FrameAnswer& answer) {
    const std::string text = answer.body.dump(-1, ' ', false, json::error_handler_t::replace);
    std::string head;
    for (int i = 0; i < 4; ++i) head += char((text.size() >> (8 * i)) & 0xff);
    head += text;
    head.resize((head.size() + 3) / 4 * 4, ' ');
    return head;
}

std::string hsr::host::base64(const void* bytes, std::size_t size) {
    static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const auto* in = static_cast<const unsigned char*>(bytes);
    std::string out((size + 2) / 3 * 4, '=');
    char* o = out.data();
    std::size_t i = 0;
    for (; i + 2 < size; i += 3, o += 4) {
        const uint32_t v = uint32_t(in[i]) << 16 | uint32_t(in[i + 1]) << 8 | in[i + 2];
        o[0] = digits[v >> 18], o[1] = digits[(v >> 12) & 63], o[2] = digits[(v >> 6) & 63], o[3] = digits[v & 63];
    }
    if (i < size) {
        const uint32_t v = uint32_t(in[i]) << 16 | (i + 1 < size ? uint32_t(in[i + 1]) << 8 : 0u);
        o[0] = digits[v >> 18], o[1] = digits[(v >> 12) & 63];
        if (i + 1 < size) o[2] = digits[(v >> 6) & 63];
    }
    return out;
}

struct hsr::host::FrameRenderer::State {
    const hsr::PluginRegistry& registry;
    FindModel find_model;
    hsr::ReadPolicy read_policy;
    std::mutex mutex;  // one frame at a time: plugin instances are never called concurrently
    std::list<std::pair<std::string, std::shared_ptr<CachedModel>>> model_cache;  // most recent first
    std::map<std::string, std::unique_ptr<hsr::HiddenSurfaceRemover>> surface_removers;
    std::map<std::string, std::unique_ptr<hsr::HiddenLineRemover>> line_removers;
    std::map<std::string, std::unique_ptr<hsr::LightingModel>> lighting_models;
    // The last few outlines (POST /api/steps), by the request less what does not change the steps,
    // each with the model it was made of: a model loaded again makes it stale.
    struct KeptOutline {
        std::string key;
        std::weak_ptr<CachedModel> model;
        json answer;
    };
    std::list<KeptOutline> outlines;  // most recent first

    State(const hsr::PluginRegistry& registry, FindModel find_model, hsr::ReadPolicy read_policy)
        : registry(registry), find_model(std::move(find_model)), read_policy(std::move(read_policy)) {}

    // A failed load is not kept, so a scene's error is read again, in the language asked for.
    std::shared_ptr<CachedModel> model(const std::string& id, const std::string& language) {
        for (auto it = model_cache.begin(); it != model_cache.end(); ++it) {
            if (it->first != id) continue;
            std::error_code ec;
            const ModelEntry entry = find_model(id);  // still listed, and unchanged
            if (entry.bytes == it->second->bytes && fs::last_write_time(entry.path, ec) == it->second->modified) {
                model_cache.splice(model_cache.begin(), model_cache, it);
                return model_cache.front().second;
            }
            model_cache.erase(it);
            break;
        }
        std::shared_ptr<CachedModel> loaded = load_model_entry(find_model(id), read_policy, language);
        model_cache.emplace_front(id, loaded);
        // The newest stays; older ones go while there are too many or they hold too much.
        uint64_t held = 0;
        std::size_t kept = 0;
        for (auto it = model_cache.begin(); it != model_cache.end(); ++it, ++kept) {
            held += it == model_cache.begin() ? 0 : it->second->renderer->loaded().memory();
            if (kept >= cached_models || held > cached_model_bytes) {
                model_cache.erase(it, model_cache.end());
                break;
            }
        }
        return loaded;
    }

    template <class Instance>
    Instance& instance(std::map<std::string, std::unique_ptr<Instance>>& cache, const hsr::Plugin& plugin,
                       const std::vector<hsr::Setting>& settings) {
        const std::string key = hsr::settings_key(plugin.path.string() + "|" + plugin.descriptor.name, settings);
        auto it = cache.find(key);
        if (it != cache.end()) return *it->second;
        if (cache.size() >= cached_instances) cache.clear();
        return *cache.emplace(key, std::make_unique<Instance>(plugin, settings)).first->second;
    }

    // The request's camera, checked before anything renders; its mistakes are the camera's fields'.
    static void check_camera(const FrameRequest& q, const hsr::Renderer& renderer) {
        try {
            renderer.camera(view_of(q));
        } catch (const hsr::Error& e) {
            throw ViewError(400, q.view.look_at ? "camera.eye" : "camera", e.what());
        }
    }

    // Which kind the algorithm is: a hidden-surface plugin wins over a hidden-line one of the same
    // name, as in hsr render.
    const hsr::Plugin& algorithm_plugin(const FrameRequest& q) {
        try {
            if (registry.contains(HSR_KIND_HIDDEN_SURFACE_REMOVER, q.algorithm))
                return registry.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, q.algorithm);
            return registry.find_any({HSR_KIND_HIDDEN_SURFACE_REMOVER, HSR_KIND_HIDDEN_LINE_REMOVER}, q.algorithm);
        } catch (const hsr::Error& e) {
            throw ViewError(400, "algorithm", e.what());
        }
    }

    // The outline of a request's steps (POST /api/steps).
    json outline(const json& request, const FrameRequest& q, hsr::StepProgress* progress) {
        const hsr::Plugin& algorithm = algorithm_plugin(q);
        check_settings(algorithm, q.params, "params");
        const std::shared_ptr<CachedModel> model = this->model(q.model, q.language);
        hsr::Renderer& renderer = *model->renderer;
        check_camera(q, renderer);
        json key_fields = request;
        for (const char* field : {"step", "buffers", "picture", "lighting", "lighting_params"}) key_fields.erase(field);
        const std::string key = key_fields.dump(-1, ' ', false, json::error_handler_t::replace);
        for (auto it = outlines.begin(); it != outlines.end(); ++it) {
            if (it->key != key || it->model.lock() != model) continue;
            outlines.splice(outlines.begin(), outlines, it);
            return outlines.front().answer;
        }
        const hsr_camera camera = renderer.camera(view_of(q));
        hsr::StepOutline outline;
        uint64_t triangles = 0;
        if (algorithm.descriptor.kind == HSR_KIND_HIDDEN_LINE_REMOVER) {
            hsr::HiddenLineRemover& remover = instance(line_removers, algorithm, q.params);
            hsr::LineRequest request_lines;
            request_lines.view = view_of(q);
            request_lines.settings.edges = q.edges;
            request_lines.settings.want_hidden = q.hidden == hsr::HiddenLines::kDashed;
            request_lines.settings.crease_angle_degrees = 40;
            request_lines.settings.language = q.language;
            request_lines.settings.outline = &outline;
            triangles = renderer.lines(request_lines, remover).scene.triangle_count;
        } else {
            hsr::HiddenSurfaceRemover& remover = instance(surface_removers, algorithm, q.params);
            if (!remover.has_steps())
                throw ViewError(400, "algorithm", fmt::format("steps: plugin '{}' cannot show its steps", q.algorithm));
            outline = renderer.step_outline(view_of(q), remover, q.language, progress);
            triangles = hsr::drawn_triangle_count(renderer.loaded().scene().view());
        }
        json answer = outline_json(outline);
        answer["width"] = camera.width;
        answer["height"] = camera.height;
        answer["triangles"] = triangles;
        outlines.push_front({key, model, answer});
        if (outlines.size() > cached_outlines) outlines.pop_back();
        return answer;
    }

    static json outline_json(const hsr::StepOutline& outline) {
        json runs = json::array();
        for (const hsr::StepOutline::Run& run : outline.runs) {
            const std::string& phase = outline.phases[run.phase];
            runs.push_back({run.first, run.count, outline.types[run.type], phase.empty() ? json(nullptr) : json(phase),
                            run.level == HSR_NO_LEVEL ? json(nullptr) : json(run.level)});
        }
        json firsts = json::object();
        for (const auto& [name, first] : outline.firsts) {
            const std::string text = first.text.empty() ? name.substr(name.find(':') + 1) : first.text;
            firsts[name] = {{"step", first.step}, {"text", text}};
        }
        return {{"total", outline.total}, {"runs", std::move(runs)}, {"truncated", outline.truncated},
                {"firsts", std::move(firsts)}};
    }

    // A rendered frame and its response; the frame is kept for /api/compare.
    bool draws_lines(const FrameRequest& q) { return algorithm_plugin(q).descriptor.kind == HSR_KIND_HIDDEN_LINE_REMOVER; }

    struct Rendered {
        json response;
        hsr::Frame frame;
    };

    Rendered render(const FrameRequest& q, ArrayBlock& arrays, hsr::StepProgress* progress = nullptr) {
        const hsr::Plugin& algorithm = algorithm_plugin(q);
        check_settings(algorithm, q.params, "params");
        const std::shared_ptr<CachedModel> model = this->model(q.model, q.language);
        hsr::Renderer& renderer = *model->renderer;
        if (algorithm.descriptor.kind == HSR_KIND_HIDDEN_LINE_REMOVER) return render_lines(q, algorithm, renderer);
        const hsr::Plugin* lighting_plugin = nullptr;
        try {
            lighting_plugin = &registry.find(HSR_KIND_LIGHTING_MODEL, q.lighting);
        } catch (const hsr::Error& e) {
            throw ViewError(400, "lighting", e.what());
        }
        check_settings(*lighting_plugin, q.lighting_params, "lighting_params");
        hsr::HiddenSurfaceRemover& remover = instance(surface_removers, algorithm, q.params);
        hsr::LightingModel& lighting = instance(lighting_models, *lighting_plugin, q.lighting_params);
        if (q.step && !remover.has_steps())
            throw ViewError(400, "step", fmt::format("--step: plugin '{}' cannot show its steps ({})", q.algorithm,
                                                     algorithm.descriptor.abi_minor < 3
                                                         ? "it is built against an ABI before 1.3"
                                                         : "it has no render_steps"));
        return render_surface(q, renderer, remover, lighting, arrays, progress);
    }

    Rendered render_surface(const FrameRequest& q, hsr::Renderer& renderer, hsr::HiddenSurfaceRemover& remover,
                            hsr::LightingModel& lighting, ArrayBlock& arrays, hsr::StepProgress* progress) {
        check_camera(q, renderer);
        hsr::PictureRequest request;
        request.view = view_of(q);
        request.samples = 1;
        // Depth-test counts came with ABI 1.1; an older plugin has none (buffers.depth_tests null).
        request.count_depth_tests = (q.wants("depth_tests") || q.step) && remover.plugin().descriptor.abi_minor >= 1;
        request.depth_complexity = q.wants("depth_complexity");
        request.depth_complexity_region = depth_complexity_region(q);
        if (q.step) {
            request.step = *q.step;
            request.step_context = true;
            request.step_progress = progress;
            request.step_language = q.language;
        }
        hsr::Picture picture = renderer.picture(request, remover, lighting);
        hsr::Frame& frame = picture.frame;
        const hsr_scene& scene = picture.scene;
        const hsr_camera& camera = picture.camera;
        json steps = nullptr;
        if (q.step) steps = json{{"total", picture.step_total}, {"current", picture.step_shown}};

        json response = picture_response("surface", frame.width, frame.height, frame.rgb, frame.counters,
                                         {frame.visibility_ms, frame.shading_ms}, hsr::drawn_triangle_count(scene),
                                         q.picture);
        const bool pixel_camera = is_pixel_camera_scene(renderer);
        response["pixel_camera"] = pixel_camera;
        if (q.step) {
            const hsr::StepRecord& last = frame.steps->last;
            const bool any = last.index > 0;
            steps["type"] = any ? last.type : "";
            steps["phase"] = any && !last.phase.empty() ? json(last.phase) : json(nullptr);
            steps["text"] = any ? last.text : no_steps_text(false, q.language);
            steps["face"] = any && last.face != HSR_NO_FACE ? json(last.face) : json(nullptr);
            json lines = json::array();
            for (std::size_t k = 0; k < last.roles.size(); ++k)
                lines.push_back({last.lines[4 * k], last.lines[4 * k + 1], last.lines[4 * k + 2], last.lines[4 * k + 3],
                                 last.roles[k]});
            steps["lines"] = std::move(lines);
            steps["outline"] = any && last.face != HSR_NO_FACE ? triangle_outline(scene, camera, last.face, last.instance)
                                                               : json::array();
            const bool comparable = !hsr::needs_flat_scene(lighting.plugin(), scene);
            const StepPixels pixels =
                comparable && any ? step_pixels(picture.before, frame, max_step_pixels) : StepPixels{nullptr, nullptr};
            steps["written"] = pixels.written;
            steps["rejected"] = pixels.rejected;
            json buffers = json::array();
            for (const hsr::StepBuffer& b : last.buffers)
                buffers.push_back({{"name", b.name},
                                   {"width", b.width},
                                   {"height", b.height},
                                   {"data", arrays.add_all("float32", b.values, b.width, b.height)}});
            steps["buffers"] = std::move(buffers);
        }
        response["steps"] = std::move(steps);
        json buffers = q.buffers_as_list ? json::array() : json(nullptr);
        arrays.bytes.reserve(arrays.bytes.size() + array_bytes(q, frame.face.size()));
        for (const BufferSpec& spec : q.buffers) {
            json one = buffers_answer(spec, frame, scene, picture.depth_complexity.get(),
                                      pixel_camera ? &camera : nullptr, arrays);
            if (q.buffers_as_list) buffers.push_back(std::move(one));
            else buffers = std::move(one);
        }
        response["buffers"] = std::move(buffers);
        return {std::move(response), std::move(frame)};
    }

    // What the request's depth complexity is measured over: the rectangle around the regions that
    // ask for it, unless one asks for the whole picture.
    static std::optional<hsr::PixelRegion> depth_complexity_region(const FrameRequest& q) {
        std::optional<hsr::PixelRegion> around;
        for (const BufferSpec& spec : q.buffers) {
            if (std::find(spec.names.begin(), spec.names.end(), "depth_complexity") == spec.names.end()) continue;
            if (!spec.region) return std::nullopt;
            const auto [x, y, width, height] = *spec.region;
            const uint32_t right = x + std::min(width, view_max_image_side), bottom = y + std::min(height, view_max_image_side);
            if (!around) {
                around = hsr::PixelRegion{x, y, right - x, bottom - y};
                continue;
            }
            const uint32_t left = std::min(around->x, x), top = std::min(around->y, y);
            around = hsr::PixelRegion{left, top, std::max(around->x + around->width, right) - left,
                                      std::max(around->y + around->height, bottom) - top};
        }
        return around;
    }

    // The bytes of the arrays a request asks for, at most (regions are clipped to the picture), for a
    // picture of `pixels`: reserved at once, so that the block is not copied as it grows.
    static std::size_t array_bytes(const FrameRequest& q, std::size_t pixels) {
        std::size_t bytes = 0;
        for (const BufferSpec& spec : q.buffers)
            bytes += spec.names.size() * 4 * (spec.region ? std::size_t((*spec.region)[2]) * (*spec.region)[3] : pixels);
        return bytes;
    }

    // The arrays one BufferSpec asks for: each buffer named, over its region (clipped to the
    // picture), and null for the others and for those the frame does not have.
    // `pixel_camera`: the camera of a `camera pixel` scene, whose depths have a scene_z; else null.
    static json buffers_answer(const BufferSpec& spec, const hsr::Frame& frame, const hsr_scene& scene,
                               const hsr::DepthComplexity* complexity, const hsr_camera* pixel_camera,
                               ArrayBlock& arrays) {
        std::array<uint32_t, 4> r = spec.region.value_or(std::array<uint32_t, 4>{0, 0, frame.width, frame.height});
        if (r[0] >= frame.width || r[1] >= frame.height)
            throw ViewError(400, "buffers.region", fmt::format("buffers.region: ({}, {}) lies outside the {}x{} picture",
                                                               r[0], r[1], frame.width, frame.height));
        r[2] = std::min(r[2], frame.width - r[0]);
        r[3] = std::min(r[3], frame.height - r[1]);
        json out{{"region", r}};
        for (const char* name : kBufferNames) out[name] = nullptr;
        auto wanted = [&](const char* name) { return std::find(spec.names.begin(), spec.names.end(), name) != spec.names.end(); };
        if (wanted("depth")) out["depth"] = arrays.add("float32", frame.depth, frame.width, r);
        if (wanted("face")) out["face"] = arrays.add("uint32", frame.face, frame.width, r);
        if (wanted("instance") && !frame.instance.empty()) out["instance"] = arrays.add("uint32", frame.instance, frame.width, r);
        if (wanted("depth_tests") && !frame.depth_tests.empty())
            out["depth_tests"] = arrays.add("uint32", frame.depth_tests, frame.width, r);
        if (wanted("depth_complexity") && complexity != nullptr)
            out["depth_complexity"] = arrays.add("uint32", complexity->count, complexity->width,
                                                 {r[0] - complexity->x, r[1] - complexity->y, r[2], r[3]});
        if (wanted("scene_z") && pixel_camera != nullptr) {
            std::vector<float> scene_z(std::size_t(r[2]) * r[3]);
            for (uint32_t y = 0; y < r[3]; ++y)
                for (uint32_t x = 0; x < r[2]; ++x)
                    scene_z[std::size_t(y) * r[2] + x] =
                        float(pixel_camera_scene_z(*pixel_camera, frame.depth[std::size_t(r[1] + y) * frame.width + r[0] + x]));
            out["scene_z"] = arrays.add_all("float32", scene_z, r[2], r[3]);
        }
        if (wanted("object")) {
            std::vector<uint32_t> object(std::size_t(r[2]) * r[3], HSR_NO_FACE);
            for (uint32_t y = 0; y < r[3]; ++y)
                for (uint32_t x = 0; x < r[2]; ++x) {
                    const uint32_t face = frame.face[std::size_t(r[1] + y) * frame.width + r[0] + x];
                    if (face < scene.triangle_count) object[std::size_t(y) * r[2] + x] = scene.face_object[face];
                }
            out["object"] = arrays.add_all("uint32", object, r[2], r[3]);
        }
        return out;
    }

    Rendered render_lines(const FrameRequest& q, const hsr::Plugin& algorithm, const hsr::Renderer& renderer) {
        hsr::HiddenLineRemover& remover = instance(line_removers, algorithm, q.params);
        check_camera(q, renderer);
        hsr::LineRequest request;
        request.view = view_of(q);
        request.settings.edges = q.edges;
        request.settings.want_hidden = q.hidden == hsr::HiddenLines::kDashed;
        request.settings.crease_angle_degrees = 40;
        request.step = q.step;
        request.settings.language = q.language;
        const hsr::LinePicture picture = renderer.lines(request, remover);
        const hsr::LineDrawing& drawing = picture.drawing;
        const hsr_scene& scene = picture.scene;
        const hsr_camera& camera = picture.camera;
        hsr::LineStyle style;
        style.hidden = q.hidden;
        hsr::Image image = hsr::draw_line_image(drawing, style);
        json response = picture_response("lines", image.width, image.height, image.pixels, drawing.counters,
                                         {drawing.lines_ms, 0.0}, scene.triangle_count, q.picture);
        response["pixel_camera"] = is_pixel_camera_scene(renderer);
        json steps = nullptr;
        if (q.step) {
            steps = json{{"total", drawing.trace_events}, {"current", drawing.stopped_at ? drawing.stopped_at->index : 0}};
            json lines = json::array(), outline = json::array();
            if (drawing.stopped_at) {
                const hsr::TraceEventRecord& e = *drawing.stopped_at;
                steps["type"] = e.type;
                steps["phase"] = e.phase.empty() ? json(nullptr) : json(e.phase);
                steps["text"] = e.text.empty() ? describe_trace_event(e, q.language) : e.text;
                steps["face"] = e.face < scene.triangle_count ? json(e.face) : json(nullptr);
                for (std::size_t k = 0; k < e.roles.size(); ++k) {
                    const float* p = &e.lines[4 * k];
                    if (std::isfinite(p[0] + p[1] + p[2] + p[3])) lines.push_back({p[0], p[1], p[2], p[3], e.roles[k]});
                }
                // A plugin that draws nothing for its step gets its edge, and the piece t0..t1 of it.
                if (e.roles.empty() && e.edge < drawing.edges.size()) {
                    auto point = [&](uint32_t v) {
                        return glm::vec3(scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]);
                    };
                    const glm::vec3 a = point(drawing.edges.vertices[2 * e.edge]);
                    const glm::vec3 b = point(drawing.edges.vertices[2 * e.edge + 1]);
                    auto add = [&](glm::vec3 from, glm::vec3 to, uint32_t role) {
                        for (const json& line : projected_segment(camera, from, to)) {
                            json with_role = line;
                            with_role.push_back(role);
                            lines.push_back(std::move(with_role));
                        }
                    };
                    add(a, b, HSR_STEP_SUBJECT);
                    if (std::isfinite(e.t0) && std::isfinite(e.t1))
                        add(a + float(e.t0) * (b - a), a + float(e.t1) * (b - a), HSR_STEP_REJECTED);
                }
                steps["figure"] = line_step_figure(scene, camera, drawing, e, style.background);
                steps["figure"]["algorithm"] = q.algorithm;
                // The face's outline is its polygon's, as the figure fills it.
                if (const json& face = steps["figure"]["face"]; face.is_object())
                    for (const json& loop : face["loops"])
                        for (std::size_t k = 0; k < loop.size(); ++k) {
                            const json& p = loop[k];
                            const json& q = loop[(k + 1) % loop.size()];
                            outline.push_back({p[0], p[1], q[0], q[1]});
                        }
            } else {
                steps["type"] = "";
                steps["phase"] = nullptr;
                steps["text"] = no_steps_text(true, q.language);
                steps["face"] = nullptr;
                steps["figure"] = nullptr;
            }
            steps["lines"] = std::move(lines);
            steps["outline"] = std::move(outline);
            steps["written"] = nullptr;
            steps["rejected"] = nullptr;
            steps["buffers"] = json::array();
        }
        response["steps"] = std::move(steps);
        response["buffers"] = nullptr;
        hsr::Frame frame;  // only the picture: what /api/compare compares two line drawings by
        frame.width = image.width;
        frame.height = image.height;
        frame.rgb = std::move(image.pixels);
        return {std::move(response), std::move(frame)};
    }
};

hsr::host::FrameRenderer::FrameRenderer(const hsr::PluginRegistry& registry, FindModel find_model,
                                        hsr::ReadPolicy read_policy)
    : state_(std::make_unique<State>(registry, std::move(find_model), std::move(read_policy))) {}

hsr::host::FrameRenderer::~FrameRenderer() = default;

hsr::host::FrameAnswer hsr::host::FrameRenderer::frame(const json& request, hsr::StepProgress* progress) {
    const FrameRequest q = parse_frame_request(request);
    std::lock_guard lock(state_->mutex);
    ArrayBlock arrays;
    json response = state_->render(q, arrays, progress).response;
    return {std::move(response), std::move(arrays.bytes)};
}

json hsr::host::FrameRenderer::steps(const json& request, hsr::StepProgress* progress) {
    const FrameRequest q = parse_frame_request(request);
    std::lock_guard lock(state_->mutex);
    return state_->outline(request, q, progress);
}

std::string hsr::host::FrameRenderer::steps_zip(const json& request) {
    json frame_request = request;
    const json from_field = request.is_object() ? request.value("from", json()) : json();
    const json to_field = request.is_object() ? request.value("to", json()) : json();
    if (frame_request.is_object()) {
        frame_request.erase("from");
        frame_request.erase("to");
        frame_request["step"] = 1;
    }
    FrameRequest q = parse_frame_request(frame_request);
    const hsr::Language language = hsr::language_from_code(q.language);
    for (const auto* field : {&from_field, &to_field})
        if (!field->is_number_integer() || field->get<int64_t>() < 1)
            throw ViewError(400, field == &from_field ? "from" : "to",
                            hsr::say(language, "steps-zip: 'from' and 'to' are step numbers, from 1",
                                     "архив шагов: «from» и «to» — номера шагов, считая с 1"));
    const uint64_t from = from_field.get<uint64_t>(), to = to_field.get<uint64_t>();
    if (to < from)
        throw ViewError(400, "to", hsr::say(language, "steps-zip: the range {}..{} ends before it starts",
                                            "архив шагов: диапазон {}..{} кончается раньше, чем начинается", from, to));
    const uint64_t count = to - from + 1;
    if (count > kMaxZipSteps)
        throw ViewError(400, "to", hsr::say(language, "steps-zip: {} steps; one archive holds at most {}",
                                            "архив шагов: {} шагов, а в один архив входит не больше {}", count,
                                            kMaxZipSteps));
    const uint64_t pixels = count * q.width * q.height;
    if (pixels > kMaxZipPixels)
        throw ViewError(400, "to", hsr::say(language,
                                            "steps-zip: {} steps of {}x{} are {} pixels, over the limit of {} "
                                            "(fewer steps or a smaller picture)",
                                            "архив шагов: {} шагов по {}x{} — это {} пикселей, больше предела {} "
                                            "(возьмите меньше шагов или картинку меньше)",
                                            count, q.width, q.height, pixels, kMaxZipPixels));
    q.picture = false;
    q.buffers.clear();
    std::vector<ZipEntry> entries;
    entries.reserve(count);
    std::lock_guard lock(state_->mutex);
    for (uint64_t step = from; step <= to; ++step) {
        q.step = step;
        ArrayBlock arrays;
        const hsr::Frame frame = state_->render(q, arrays).frame;
        entries.push_back({fmt::format("step-{:03}.png", step - from + 1),
                           hsr::encode_picture_png(frame.width, frame.height, 3, frame.rgb)});
    }
    return stored_zip(entries);
}

hsr::host::FrameAnswer hsr::host::FrameRenderer::compare(const json& request) {
    if (!request.is_object() || !request.contains("a") || !request.contains("b"))
        throw ViewError(400, "", "compare: expected {\"a\": <frame request>, \"b\": <frame request>}");
    auto parse = [&](const char* side) {
        try {
            return parse_frame_request(request[side]);
        } catch (const ViewError& e) {
            throw ViewError(e.status, fmt::format("{}.{}", side, e.field), e.what());
        }
    };
    const FrameRequest qa = parse("a"), qb = parse("b");
    std::lock_guard lock(state_->mutex);
    ArrayBlock arrays;
    auto render = [&](const FrameRequest& q, const char* side) {
        try {
            return state_->render(q, arrays);
        } catch (const ViewError& e) {
            throw ViewError(e.status, fmt::format("{}.{}", side, e.field), e.what());
        }
    };
    auto draws_lines = [&](const FrameRequest& q, const char* side) {
        try {
            return state_->draws_lines(q);
        } catch (const ViewError& e) {
            throw ViewError(e.status, fmt::format("{}.{}", side, e.field), e.what());
        }
    };
    const bool a_lines = draws_lines(qa, "a"), b_lines = draws_lines(qb, "b");
    if (a_lines != b_lines)
        throw ViewError(400, "b.algorithm",
                        fmt::format("compare: '{}' {} and '{}' {}; compare two hidden-surface plugins or two "
                                    "hidden-line plugins",
                                    qa.algorithm, a_lines ? "draws lines" : "fills surfaces", qb.algorithm,
                                    b_lines ? "draws lines" : "fills surfaces"));
    // Both sides' arrays in one block reserved at once; of a's frame only what the comparison needs
    // is kept while b renders.
    arrays.bytes.reserve(State::array_bytes(qa, std::size_t(qa.width) * qa.height) +
                         State::array_bytes(qb, std::size_t(qb.width) * qb.height));
    State::Rendered a = render(qa, "a");
    std::vector<float>().swap(a.frame.depth);
    std::vector<uint32_t>().swap(a.frame.depth_tests);
    if (!a_lines) std::vector<uint8_t>().swap(a.frame.rgb);
    State::Rendered b = render(qb, "b");
    if (a.frame.width != b.frame.width || a.frame.height != b.frame.height)
        throw ViewError(400, "b.width", fmt::format("compare: the pictures are {}x{} and {}x{}; give both the same size",
                                                    a.frame.width, a.frame.height, b.frame.width, b.frame.height));
    // b's picture dimmed, and magenta where the two disagree on what is visible: for line drawings,
    // where the two pictures' pixels differ.
    std::vector<uint8_t> diff(b.frame.rgb.size());
    uint64_t differing = 0;
    const bool instances = !a.frame.instance.empty() && !b.frame.instance.empty();
    const std::size_t pixels = b.frame.rgb.size() / 3;
    for (std::size_t p = 0; p < pixels; ++p) {
        const bool differs =
            a_lines ? (a.frame.rgb[3 * p] != b.frame.rgb[3 * p] || a.frame.rgb[3 * p + 1] != b.frame.rgb[3 * p + 1] ||
                       a.frame.rgb[3 * p + 2] != b.frame.rgb[3 * p + 2])
                    : (a.frame.face[p] != b.frame.face[p] ||
                       (instances && a.frame.face[p] != HSR_NO_FACE && a.frame.instance[p] != b.frame.instance[p]));
        differing += differs;
        for (int k = 0; k < 3; ++k)
            diff[3 * p + k] = differs ? (k == 1 ? 0 : 255) : uint8_t(b.frame.rgb[3 * p + k] * 2 / 5);
    }
    json response{{"a", std::move(a.response)},
                  {"b", std::move(b.response)},
                  {"diff_png", png_data_url(b.frame.width, b.frame.height, diff)},
                  {"differing_pixels", differing}};
    return {std::move(response), std::move(arrays.bytes)};
}
