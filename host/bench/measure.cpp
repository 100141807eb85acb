// hsr bench's measurement (see bench.hpp): scenes, cameras, the timing loop and statistics.
#include "bench/measure.hpp"

#include "hsr/fragment_lists.hpp"

#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
#include "hsr/limits.hpp"
#include "hsr/random_triangles.hpp"
#include "hsr/scene_file.hpp"
#include "hsr/subdivide.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <limits>
#include <set>

namespace hsr::bench {
namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 6> mesh_extensions = {".obj", ".off", ".ply", ".stl", ".gltf", ".glb"};
constexpr uint32_t max_layers = 10000;

std::optional<uint32_t> parse_count(std::string_view text) {
    uint32_t value = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

std::string known_models(const fs::path& models_dir) {
    std::set<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(models_dir, ec)) {
        const std::string ext = entry.path().extension().string();
        if (std::find(mesh_extensions.begin(), mesh_extensions.end(), ext) != mesh_extensions.end())
            names.insert(entry.path().stem().string());
    }
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    return list.empty() ? "none" : list;
}

// A "Name:   123 kB" line of /proc/self/status, in bytes; 0 when missing.
uint64_t status_bytes(const char* name) {
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return 0;
    char line[256];
    uint64_t bytes = 0;
    const std::size_t length = std::strlen(name);
    while (std::fgets(line, sizeof line, f)) {
        if (std::strncmp(line, name, length) != 0 || line[length] != ':') continue;
        unsigned long long kb = 0;
        if (std::sscanf(line + length + 1, "%llu", &kb) == 1) bytes = uint64_t(kb) * 1024;
        break;
    }
    std::fclose(f);
    return bytes;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Memory

uint64_t reset_peak_memory() {
#if defined(__GLIBC__)
    // Free heap pages go back to the system first: the resident size is then what is in use, and
    // memory an earlier measurement freed counts again when this one takes it.
    malloc_trim(0);
#endif
    std::FILE* f = std::fopen("/proc/self/clear_refs", "w");
    if (!f) return 0;
    const bool written = std::fputs("5", f) >= 0;
    if (std::fclose(f) != 0 || !written) return 0;
    return status_bytes("VmRSS");
}

uint64_t peak_memory() { return status_bytes("VmHWM"); }

// ---------------------------------------------------------------------------------------------
// Statistics

double quantile(const std::vector<double>& sorted, double p) {
    if (sorted.empty()) throw Error("quantile of no samples");
    const double h = (double(sorted.size()) - 1.0) * std::clamp(p, 0.0, 1.0);
    const std::size_t lo = static_cast<std::size_t>(std::floor(h));
    if (lo + 1 >= sorted.size()) return sorted.back();
    return sorted[lo] + (h - double(lo)) * (sorted[lo + 1] - sorted[lo]);
}

Summary summarize(std::vector<double> samples) {
    if (samples.empty()) throw Error("no samples to summarize");
    for (double s : samples)
        if (!std::isfinite(s)) throw Error("a timing sample is not a finite number");
    std::sort(samples.begin(), samples.end());
    Summary s;
    s.count = samples.size();
    s.min = samples.front();
    s.max = samples.back();
    s.median = quantile(samples, 0.5);
    s.q1 = quantile(samples, 0.25);
    s.q3 = quantile(samples, 0.75);
    return s;
}

// ---------------------------------------------------------------------------------------------
// Scenes

// The deep scenes' layer counts are those whose measured depth complexity is nearest 5, 20 and 50
// (4.7, 20.3, 49.8 at 1024x1024): a monkey counts twice where it covers a pixel, the gaps between
// copies count nothing, and perspective shrinks the far layers.
const std::vector<std::string>& default_models() {
    static const std::vector<std::string> models = {"cube", "monkey", "bunny", "bunny-loop",
                                                    "deep-3", "deep-24", "deep-63"};
    return models;
}

const std::vector<std::string>& quick_models() {
    static const std::vector<std::string> models = {"cube", "octahedron", "cube-loop", "deep-3:cube"};
    return models;
}

ModelSpec parse_model_spec(const std::string& text, const fs::path& models_dir) {
    if (text.empty()) throw Error("an empty model name");
    ModelSpec spec;
    spec.name = text;

    // deep-N[:NAME]
    if (text.rfind("deep-", 0) == 0) {
        const std::size_t colon = text.find(':');
        const std::string count = text.substr(5, colon == std::string::npos ? std::string::npos : colon - 5);
        const std::optional<uint32_t> layers = parse_count(count);
        if (!layers || *layers == 0 || *layers > max_layers)
            throw Error("model '{}': deep-N needs a layer count N between 1 and {} (deep-20, deep-20:bunny)", text,
                        max_layers);
        const std::string base = colon == std::string::npos ? "monkey" : text.substr(colon + 1);
        if (base.rfind("deep-", 0) == 0) throw Error("model '{}': a deep scene of deep scenes", text);
        ModelSpec inner = parse_model_spec(base, models_dir);
        spec.file = inner.file;
        spec.loop_levels = inner.loop_levels;
        spec.random_triangles = inner.random_triangles;
        spec.seed = inner.seed;
        spec.layers = *layers;
        return spec;
    }

    // random-N[:SEED]
    if (text.rfind("random-", 0) == 0) {
        const std::size_t colon = text.find(':');
        const std::string_view count = std::string_view(text).substr(7, colon == std::string::npos ? std::string::npos
                                                                                                  : colon - 7);
        uint64_t n = 0;
        auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), n);
        if (count.empty() || ec != std::errc() || end != count.data() + count.size() || n == 0)
            throw Error("model '{}': random-N[:SEED] needs a triangle count N of at least 1 (random-1000, "
                        "random-1000:7)", text);
        if (colon != std::string::npos) {
            const std::string_view seed = std::string_view(text).substr(colon + 1);
            auto [seed_end, seed_ec] = std::from_chars(seed.data(), seed.data() + seed.size(), spec.seed);
            if (seed.empty() || seed_ec != std::errc() || seed_end != seed.data() + seed.size())
                throw Error("model '{}': the seed after ':' must be a whole number (random-1000:7)", text);
        }
        check_limit(&Limits::stored_triangles, n, fmt::format("model '{}'", text));
        spec.random_triangles = n;
        return spec;
    }

    // A file path.
    const fs::path as_path(text);
    if (text.find('/') != std::string::npos || as_path.has_extension()) {
        std::error_code ec;
        if (!fs::is_regular_file(as_path, ec)) throw Error("model file '{}' does not exist", text);
        spec.file = as_path;
        return spec;
    }

    // NAME-loop[K]
    const std::size_t loop = text.rfind("-loop");
    if (loop != std::string::npos && loop > 0) {
        const std::string digits = text.substr(loop + 5);
        std::optional<uint32_t> levels = digits.empty() ? std::optional<uint32_t>(1) : parse_count(digits);
        if (levels) {
            if (*levels < 1 || *levels > uint32_t(max_loop_levels))
                throw Error("model '{}': Loop levels must be between 1 and {}", text, max_loop_levels);
            ModelSpec inner = parse_model_spec(text.substr(0, loop), models_dir);
            if (inner.loop_levels > 0) throw Error("model '{}': name the levels once (bunny-loop2)", text);
            spec.file = inner.file;
            spec.loop_levels = int(*levels);
            return spec;
        }
    }

    // NAME in the models folder.
    for (const char* ext : mesh_extensions) {
        const fs::path candidate = models_dir / (text + ext);
        std::error_code ec;
        if (fs::is_regular_file(candidate, ec)) {
            spec.file = candidate;
            return spec;
        }
    }
    if (text == "monkey" || text == "bunny")
        throw Error("model '{}': {} is missing (models/fetch-models.sh fetches it)", text,
                    (models_dir / (text + ".obj")).string());
    throw Error("unknown model '{}' (known in folder {}: {}; also NAME-loop, deep-N[:NAME] or a file path)", text,
                (models_dir / "").string(), known_models(models_dir));
}

SceneData make_deep_scene(const SceneData& model, uint32_t layers, const DeepGrid& grid) {
    InstanceGrid g;
    g.rows = std::max(1u, grid.rows);
    g.layers = layers;
    g.gap = grid.gap;
    g.yaw_jitter_degrees = grid.yaw_jitter_degrees;
    g.columns = grid.columns;
    if (g.columns == 0) {  // about as wide as tall: columns * step.x ~ rows * step.y
        const glm::vec3 extent = model.bounds_max - model.bounds_min;
        const float size = std::max({extent.x, extent.y, extent.z});
        const float step_x = extent.x + grid.gap * size, step_y = extent.y + grid.gap * size;
        const double columns = step_x > 0 ? std::round(double(g.rows) * step_y / step_x) : double(g.rows);
        g.columns = static_cast<uint32_t>(std::clamp(columns, 1.0, 64.0));
    }
    return make_instance_grid(model, g);
}

float front_layer_zoom(const SceneData& deep, CameraSettings settings) {
    if (deep.instances.empty()) return settings.zoom;
    // The front layer: every instance whose box reaches within half a copy's depth of the nearest
    // box (make_instance_grid's layers recede along -z, toward the default camera's far side).
    float front = -std::numeric_limits<float>::infinity();
    for (const hsr_instance& i : deep.instances) front = std::max(front, i.bounds_max[2]);
    const float depth = deep.instances.front().bounds_max[2] - deep.instances.front().bounds_min[2];
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (const hsr_instance& i : deep.instances) {
        if (i.bounds_max[2] < front - 0.5f * depth) continue;
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], i.bounds_min[k]);
            hi[k] = std::max(hi[k], i.bounds_max[k]);
        }
    }
    settings.zoom = 1.0f;
    const hsr_camera camera = make_orbit_camera(deep.bounds_min, deep.bounds_max, settings);
    glm::mat4 view_projection;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) view_projection[c][r] = camera.view_projection[4 * c + r];
    float extent_x = 0, extent_y = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec4 p(corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z, 1.0f);
        const glm::vec4 clip = view_projection * p;
        if (!(clip.w > 0)) continue;
        extent_x = std::max(extent_x, std::fabs(clip.x / clip.w));
        extent_y = std::max(extent_y, std::fabs(clip.y / clip.w));
    }
    const float extent = std::min(extent_x, extent_y);  // the layer covers the image: the smaller side fills it
    if (!(extent > 0) || !std::isfinite(extent)) return 1.0f;
    return std::max(1.0f, 1.0f / extent);
}

BenchScene load_bench_scene(const ModelSpec& spec, const DeepGrid& grid) {
    BenchScene out;
    out.name = spec.name;
    out.layers = spec.layers;
    if (spec.random_triangles > 0) {
        out.scene = make_random_triangles(spec.random_triangles, spec.seed);
    } else if (is_scene_file(spec.file)) {
        SceneFile file = load_scene_file(spec.file);
        out.scene = spec.loop_levels > 0 ? loop_subdivide(file.scene, spec.loop_levels) : std::move(file.scene);
        if (file.yaw_degrees) out.camera.yaw_degrees = *file.yaw_degrees;
        if (file.pitch_degrees) out.camera.pitch_degrees = *file.pitch_degrees;
        if (file.zoom) out.camera.zoom = *file.zoom;
        if (file.orthographic) out.camera.orthographic = *file.orthographic;
    } else {
        out.scene = spec.loop_levels > 0 ? load_model_subdivided(spec.file, spec.loop_levels) : load_model(spec.file);
    }
    if (spec.layers > 0) {
        if (!out.scene.instances.empty()) out.scene = flatten_instances(out.scene);
        out.scene = make_deep_scene(out.scene, spec.layers, grid);
        out.camera.zoom = front_layer_zoom(out.scene, out.camera);
    }
    return out;
}

ViewRequest bench_view(const BenchScene& scene, uint32_t width, uint32_t height) {
    const CameraSettings& settings = scene.camera;
    ViewRequest view;
    view.width = width;
    view.height = height;
    view.yaw_degrees = settings.yaw_degrees;
    view.pitch_degrees = settings.pitch_degrees;
    view.zoom = settings.zoom;
    view.fov_y_degrees = settings.fov_y_degrees;
    view.orthographic = settings.orthographic;
    return view;
}

hsr_camera make_bench_camera(const Renderer& renderer, const BenchScene& scene, uint32_t width, uint32_t height) {
    try {
        return renderer.camera(bench_view(scene, width, height));
    } catch (const Error& e) {
        throw Error("model '{}': {}", scene.name, e.what());
    }
}

hsr_camera make_bench_camera(const BenchScene& scene, uint32_t width, uint32_t height) {
    return make_bench_camera(Renderer(LoadedScene::of(scene.scene)), scene, width, height);
}

// ---------------------------------------------------------------------------------------------
// Timing

namespace {

// A timing before its first call: the memory mark reset, so that the loop's copy of the scene for
// a plugin built before instances counts as the measurement's.
Timing started_timing(const TimingSettings& settings) {
    if (settings.repetitions == 0) throw Error("repetitions must be at least 1");
    Timing timing;
    timing.memory.before = reset_peak_memory();
    return timing;
}

}  // namespace

FrameTimer::FrameTimer(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                       LightingModel& lighting, const hsr_shading_context& context, const TimingSettings& settings)
    : settings_(settings), timing_(started_timing(settings)), loop_(scene, camera, context, settings.frame, remover, lighting) {}

CallTiming FrameTimer::call() {
    const Frame& frame = loop_.render();
    CallTiming call;
    call.index = calls_made();
    call.warmup = call.index < settings_.warmup;
    call.visibility_ms = frame.visibility_ms;
    call.build_ms = double(frame.counter("build-time-us")) / 1000.0;
    call.shading_ms = frame.shading_ms;
    if (call.build_ms > 0) {
        ++timing_.build_calls;
        timing_.build_ms = std::max(timing_.build_ms, call.build_ms);
    }
    if (!call.warmup) {
        const double render = std::max(0.0, call.render_ms());
        timing_.render_ms.push_back(render);
        timing_.shading_ms.push_back(call.shading_ms);
        timing_.total_ms.push_back(render + call.shading_ms);
    }
    timing_.counters.clear();
    for (const auto& [name, value] : frame.counters)
        if (name != "build-time-us") timing_.counters.emplace_back(name, value);
    timing_.calls.push_back(call);
    if (timing_.memory.before > 0) timing_.memory.peak = std::max(timing_.memory.peak, peak_memory());
    return call;
}

Timing time_frames(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                   LightingModel& lighting, const hsr_shading_context& context, const TimingSettings& settings,
                   const std::function<void(const CallTiming&)>& after_call) {
    FrameTimer timer(scene, camera, remover, lighting, context, settings);
    for (unsigned i = 0; i < settings.warmup + settings.repetitions; ++i) {
        const CallTiming c = timer.call();
        if (after_call) after_call(c);
    }
    return timer.timing();
}

// ---------------------------------------------------------------------------------------------
// Results

Result make_result(std::string algorithm, std::string model, const hsr_scene& scene, const hsr_camera& camera,
                   const Timing& timing, unsigned warmup, const std::optional<DepthComplexity>& depth_complexity) {
    Result r;
    r.algorithm = std::move(algorithm);
    r.model = std::move(model);
    r.width = camera.width;
    r.height = camera.height;
    r.faces = drawn_triangle_count(scene);
    r.stored_faces = scene.triangle_count;
    r.instances = scene.instance_count;
    if (depth_complexity) {
        r.depth_complexity = depth_complexity->mean_over_covered();
        r.depth_complexity_max = depth_complexity->max;
    }
    r.warmup = warmup;
    r.repetitions = static_cast<unsigned>(timing.render_ms.size());
    r.visibility = summarize(timing.render_ms);
    r.shading = summarize(timing.shading_ms);
    r.total = summarize(timing.total_ms);
    r.build_ms = timing.build_ms;
    r.build_calls = timing.build_calls;
    r.counters = timing.counters;
    r.memory = timing.memory;
    return r;
}

}  // namespace hsr::bench
