// hsr bench's reusable parts (see bench.hpp): scenes, the timing loop, statistics and reports.
#include "hsr/bench.hpp"

#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
#include "hsr/scene_file.hpp"
#include "hsr/subdivide.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <ostream>
#include <set>

namespace hsr::bench {
namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 4> mesh_extensions = {".obj", ".off", ".ply", ".stl"};
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

// ms with a precision that suits its size: 0.412, 4.12, 41.2, 412.
std::string format_ms(double ms) {
    const double a = std::fabs(ms);
    if (a < 1.0) return fmt::format("{:.3f}", ms);
    if (a < 10.0) return fmt::format("{:.2f}", ms);
    if (a < 100.0) return fmt::format("{:.1f}", ms);
    return fmt::format("{:.0f}", ms);
}

std::string thousands(uint64_t n) {
    std::string digits = std::to_string(n), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

std::string xml(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        default: out += c;
        }
    }
    return out;
}

template <class T>
std::size_t index_of(std::vector<T>& list, const T& value) {
    auto it = std::find(list.begin(), list.end(), value);
    if (it != list.end()) return std::size_t(it - list.begin());
    list.push_back(value);
    return list.size() - 1;
}

}  // namespace

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
        spec.layers = *layers;
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
    if (is_scene_file(spec.file)) {
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

hsr_camera make_bench_camera(const BenchScene& scene, uint32_t width, uint32_t height) {
    CameraSettings settings = scene.camera;
    settings.width = width;
    settings.height = height;
    try {
        return make_orbit_camera(scene.scene.bounds_min, scene.scene.bounds_max, settings);
    } catch (const Error& e) {
        throw Error("model '{}': {}", scene.name, e.what());
    }
}

// ---------------------------------------------------------------------------------------------
// Timing

FrameTimer::FrameTimer(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                       LightingModel& lighting, const hsr_shading_context& context, const TimingSettings& settings)
    : scene_(scene), camera_(camera), remover_(remover), lighting_(lighting), context_(context), settings_(settings) {
    if (settings.repetitions == 0) throw Error("repetitions must be at least 1");
    // Plugins built before instances see the copied-out triangles; done once, before any timing.
    if (needs_flat_scene(remover.plugin(), scene) || needs_flat_scene(lighting.plugin(), scene)) {
        flat_ = flatten_instances(scene);
        scene_ = flat_->view();
    }
}

CallTiming FrameTimer::call() {
    // One frame's buffers serve every call (as an application's would): no page faults from fresh
    // allocations in between. The counters are this call's alone.
    Frame& frame = frame_;
    frame.counters.clear();
    resolve_visibility(scene_, camera_, remover_, frame, false);
    shade_frame(scene_, lighting_, context_, settings_.frame, frame);
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
// Results and reports

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
    return r;
}

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

void write_csv(std::ostream& out, const std::vector<Result>& results) {
    std::vector<std::string> counters;  // every counter any result has, in the order first seen
    for (const Result& r : results)
        for (const auto& c : r.counters) index_of(counters, c.first);
    out << "algorithm,model,width,height,faces,stored_faces,instances,layers,zoom,depth_complexity,"
           "depth_complexity_max,warmup,repetitions";
    for (const char* what : {"visibility", "shading", "total"})
        for (const char* stat : {"median", "min", "q1", "q3", "max"}) out << ',' << what << '_' << stat << "_ms";
    out << ",build_ms,build_calls";
    for (const std::string& c : counters) out << ',' << csv_field(c);
    out << '\n';
    for (const Result& r : results) {
        out << csv_field(r.algorithm) << ',' << csv_field(r.model) << ',' << r.width << ',' << r.height << ','
            << r.faces << ',' << r.stored_faces << ',' << r.instances << ',' << r.layers << ','
            << fmt::format("{:.4g}", r.zoom) << ',';
        if (r.depth_complexity) out << fmt::format("{:.4f},{}", *r.depth_complexity, r.depth_complexity_max);
        else out << ',';
        out << ',' << r.warmup << ',' << r.repetitions;
        for (const Summary* s : {&r.visibility, &r.shading, &r.total})
            out << fmt::format(",{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}", s->median, s->min, s->q1, s->q3, s->max);
        out << fmt::format(",{:.4f},{}", r.build_ms, r.build_calls);
        for (const std::string& name : counters) {
            out << ',';
            for (const auto& [n, v] : r.counters)
                if (n == name) {
                    out << v;
                    break;
                }
        }
        out << '\n';
    }
}

std::string format_table(const std::vector<Result>& results) {
    std::vector<std::pair<uint32_t, uint32_t>> sizes;
    std::vector<std::string> models, algorithms;
    for (const Result& r : results) {
        index_of(sizes, std::make_pair(r.width, r.height));
        index_of(models, r.model);
        index_of(algorithms, r.algorithm);
    }
    auto find = [&](const std::string& a, const std::string& m, std::pair<uint32_t, uint32_t> size) -> const Result* {
        for (const Result& r : results)
            if (r.algorithm == a && r.model == m && r.width == size.first && r.height == size.second) return &r;
        return nullptr;
    };

    std::string out;
    for (const auto& size : sizes) {
        // Rows of cells: a label column, then one per model.
        std::vector<std::vector<std::string>> rows;
        auto add_row = [&](const std::string& label, const std::function<std::string(const Result&)>& cell,
                           const std::vector<std::string>& which) {
            for (const std::string& a : which) {
                std::vector<std::string> row{a.empty() ? label : a};
                bool any = false;
                for (const std::string& m : models) {
                    const Result* r = nullptr;
                    if (a.empty()) {
                        for (const std::string& alg : algorithms)
                            if ((r = find(alg, m, size))) break;
                    } else {
                        r = find(a, m, size);
                    }
                    row.push_back(r ? cell(*r) : "");
                    any = any || (r && !row.back().empty());
                }
                if (any) rows.push_back(std::move(row));
            }
        };
        auto separator = [&] { rows.push_back({}); };
        auto heading = [&](const std::string& text) { rows.push_back({"#" + text}); };

        unsigned reps = 0, warmup = 0;
        bool any_build = false;
        for (const Result& r : results)
            if (r.width == size.first && r.height == size.second) {
                reps = std::max(reps, r.repetitions);
                warmup = std::max(warmup, r.warmup);
                any_build = any_build || r.build_ms > 0;
            }
        std::vector<std::string> header{""};
        header.insert(header.end(), models.begin(), models.end());
        rows.push_back(header);
        add_row("faces", [](const Result& r) { return thousands(r.faces); }, {""});
        add_row("depth complexity",
                [](const Result& r) { return r.depth_complexity ? fmt::format("{:.2f}", *r.depth_complexity) : "-"; },
                {""});
        separator();
        add_row("", [](const Result& r) {
            return fmt::format("{} [{}-{}]", format_ms(r.visibility.median), format_ms(r.visibility.min),
                               format_ms(r.visibility.max));
        }, algorithms);
        if (any_build) {
            heading("build time, ms (once per scene, reported by the plugin; not in the times above)");
            std::vector<std::string> builders;  // only the algorithms that build something
            for (const Result& r : results)
                if (r.width == size.first && r.height == size.second && r.build_ms > 0) index_of(builders, r.algorithm);
            add_row("", [](const Result& r) { return r.build_ms > 0 ? format_ms(r.build_ms) : "-"; }, builders);
        }
        heading("shading, ms (median)");
        add_row("", [](const Result& r) { return format_ms(r.shading.median); }, algorithms);
        heading("total = visibility + shading, ms (median)");
        add_row("", [](const Result& r) { return format_ms(r.total.median); }, algorithms);

        std::vector<std::size_t> width(models.size() + 1, 0);
        for (const auto& row : rows)
            if (!row.empty() && row[0].rfind('#', 0) != 0)
                for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
        out += fmt::format("{}x{}: visibility time, ms (hidden-surface plugin, build excluded): median [min-max] of {} "
                           "run{} after {} warm-up\n",
                           size.first, size.second, reps, reps == 1 ? "" : "s", warmup);
        for (const auto& row : rows) {
            if (row.empty()) {
                std::size_t total = 0;
                for (std::size_t w : width) total += w + 2;
                out += std::string(total - 2, '-') + "\n";
                continue;
            }
            if (row[0].rfind('#', 0) == 0) {
                out += row[0].substr(1) + "\n";
                continue;
            }
            std::string line = fmt::format("{:<{}}", row[0], width[0]);
            for (std::size_t c = 1; c < row.size(); ++c) line += fmt::format("  {:>{}}", row[c], width[c]);
            while (!line.empty() && line.back() == ' ') line.pop_back();
            out += line + "\n";
        }
        out += "\n";
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// SVG plot

std::vector<double> decade_ticks(double lo, double hi) {
    std::vector<double> ticks;
    if (!(lo > 0) || !(hi > 0) || !std::isfinite(lo) || !std::isfinite(hi)) return ticks;
    int a = int(std::floor(std::log10(lo) + 1e-9)), b = int(std::ceil(std::log10(hi) - 1e-9));
    if (b <= a) b = a + 1;
    for (int e = a; e <= b; ++e) ticks.push_back(std::pow(10.0, e));
    return ticks;
}

std::string tick_label(double v) {
    auto g = [](double x) {
        std::string s = fmt::format("{:.6g}", x);
        return s;
    };
    if (v >= 1e9) return g(v / 1e9) + "G";
    if (v >= 1e6) return g(v / 1e6) + "M";
    if (v >= 1e3) return g(v / 1e3) + "k";
    return g(v);
}

namespace {

// One plot's elements, offset down by `dy` (for stacked plots).
void write_panel(std::ostream& out, const LogLogPlot& plot, double dy) {
    static const std::array<const char*, 10> palette = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                                        "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};
    const double W = plot.width, H = plot.height;
    const double left = 78, right = W - 210, top = 70, bottom = H - 62;

    double xmin = std::numeric_limits<double>::infinity(), xmax = 0, ymin = xmin, ymax = 0;
    for (const PlotSeries& s : plot.series)
        for (auto [x, y] : s.points) {
            if (!(x > 0) || !(y > 0)) continue;
            xmin = std::min(xmin, x), xmax = std::max(xmax, x);
            ymin = std::min(ymin, y), ymax = std::max(ymax, y);
        }
    if (!(xmax > 0)) xmin = 1, xmax = 10;
    if (!(ymax > 0)) ymin = 1, ymax = 10;
    const std::vector<double> xt = decade_ticks(xmin, xmax), yt = decade_ticks(ymin, ymax);
    const double lx0 = std::log10(xt.front()), lx1 = std::log10(xt.back());
    const double ly0 = std::log10(yt.front()), ly1 = std::log10(yt.back());
    auto X = [&](double x) { return left + (std::log10(x) - lx0) / (lx1 - lx0) * (right - left); };
    auto Y = [&](double y) { return bottom - (std::log10(y) - ly0) / (ly1 - ly0) * (bottom - top); };
    auto num = [](double v) { return fmt::format("{:.1f}", v); };

    out << fmt::format("<g transform=\"translate(0,{})\">\n", num(dy));
    out << fmt::format(R"(<text x="{}" y="28" font-size="18" font-weight="bold" text-anchor="middle">{}</text>)" "\n",
                       num((left + right) / 2), xml(plot.title));
    if (!plot.subtitle.empty())
        out << fmt::format(R"(<text x="{}" y="48" font-size="12" fill="#555" text-anchor="middle">{}</text>)" "\n",
                           num((left + right) / 2), xml(plot.subtitle));

    // Grid: decades, and 2..9 within each decade (labelled too at 2 and 5 when the axis is short).
    out << "<g class=\"grid\">\n";
    auto minor_ticks = [](const std::vector<double>& decades, auto&& f) {
        for (std::size_t i = 0; i + 1 < decades.size(); ++i)
            for (int m = 2; m <= 9; ++m) f(decades[i] * m, m);
    };
    const bool label_x_minor = xt.size() <= 3, label_y_minor = yt.size() <= 3;
    minor_ticks(xt, [&](double x, int) {
        out << fmt::format(R"(<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#eeeeee"/>)" "\n", num(X(x)), num(top), num(bottom));
    });
    minor_ticks(yt, [&](double y, int) {
        out << fmt::format(R"(<line x1="{1}" y1="{0}" x2="{2}" y2="{0}" stroke="#eeeeee"/>)" "\n", num(Y(y)), num(left), num(right));
    });
    for (double x : xt)
        out << fmt::format(R"(<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#cccccc"/>)" "\n", num(X(x)), num(top), num(bottom));
    for (double y : yt)
        out << fmt::format(R"(<line x1="{1}" y1="{0}" x2="{2}" y2="{0}" stroke="#cccccc"/>)" "\n", num(Y(y)), num(left), num(right));
    out << "</g>\n";

    // Guides: which model sits where.
    out << "<g class=\"guides\" font-size=\"11\" fill=\"#555\">\n";
    double last_top = -1e9;
    std::vector<PlotGuide> guides = plot.guides;
    std::sort(guides.begin(), guides.end(), [](const PlotGuide& a, const PlotGuide& b) { return a.x < b.x; });
    for (const PlotGuide& g : guides) {
        if (!(g.x > 0)) continue;
        const double x = X(g.x);
        out << fmt::format(R"(<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#999" stroke-dasharray="2 3"/>)" "\n",
                           num(x), num(top), num(bottom));
        // Labels read upward, left of their line, at the top; one too close to the previous goes
        // to the bottom instead.
        if (x - left < 15) {  // at the left frame: right of the line
            out << fmt::format(R"~(<text transform="translate({},{}) rotate(-90)" text-anchor="end" )~"
                               R"(stroke="white" stroke-width="3" paint-order="stroke">{}</text>)" "\n",
                               num(x + 11), num(top + 4), xml(g.label));
            last_top = x + 14;
        } else if (x - last_top >= 15) {
            out << fmt::format(R"~(<text transform="translate({},{}) rotate(-90)" text-anchor="end" )~"
                               R"(stroke="white" stroke-width="3" paint-order="stroke">{}</text>)" "\n",
                               num(x - 3), num(top + 4), xml(g.label));
            last_top = x;
        } else {
            out << fmt::format(R"~(<text transform="translate({},{}) rotate(-90)" text-anchor="start" )~"
                               R"(stroke="white" stroke-width="3" paint-order="stroke">{}</text>)" "\n",
                               num(x + 11), num(bottom - 4), xml(g.label));
        }
    }
    out << "</g>\n";

    // Axes, ticks, labels.
    out << fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#333"/>)" "\n", num(left),
                       num(top), num(right - left), num(bottom - top));
    out << "<g class=\"ticks\" font-size=\"12\" fill=\"#222\">\n";
    for (double x : xt) {
        out << fmt::format(R"(<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#333"/>)" "\n", num(X(x)), num(bottom), num(bottom + 6));
        out << fmt::format(R"(<text x="{}" y="{}" text-anchor="middle">{}</text>)" "\n", num(X(x)), num(bottom + 20), tick_label(x));
    }
    minor_ticks(xt, [&](double x, int m) {
        out << fmt::format(R"(<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#333"/>)" "\n", num(X(x)), num(bottom), num(bottom + 3));
        if (label_x_minor && (m == 2 || m == 5))
            out << fmt::format(R"(<text x="{}" y="{}" text-anchor="middle" font-size="10" fill="#555">{}</text>)" "\n",
                               num(X(x)), num(bottom + 18), tick_label(x));
    });
    for (double y : yt) {
        out << fmt::format(R"(<line x1="{1}" y1="{0}" x2="{2}" y2="{0}" stroke="#333"/>)" "\n", num(Y(y)), num(left - 6), num(left));
        out << fmt::format(R"(<text x="{}" y="{}" text-anchor="end">{}</text>)" "\n", num(left - 9), num(Y(y) + 4), fmt::format("{:.6g}", y));
    }
    minor_ticks(yt, [&](double y, int m) {
        out << fmt::format(R"(<line x1="{1}" y1="{0}" x2="{2}" y2="{0}" stroke="#333"/>)" "\n", num(Y(y)), num(left - 3), num(left));
        if (label_y_minor && (m == 2 || m == 5))
            out << fmt::format(R"(<text x="{}" y="{}" text-anchor="end" font-size="10" fill="#555">{}</text>)" "\n",
                               num(left - 8), num(Y(y) + 4), fmt::format("{:.6g}", y));
    });
    out << "</g>\n";
    out << fmt::format(R"(<text x="{}" y="{}" font-size="13" text-anchor="middle">{}</text>)" "\n",
                       num((left + right) / 2), num(H - 18), xml(plot.x_label));
    out << fmt::format(R"~(<text transform="translate({},{}) rotate(-90)" font-size="13" text-anchor="middle">{}</text>)~" "\n",
                       num(22), num((top + bottom) / 2), xml(plot.y_label));

    // A slope-1 reference: what linear growth in the face count looks like on these axes.
    std::optional<std::pair<double, double>> anchor;
    if (plot.linear_reference && !plot.series.empty())
        for (auto p : plot.series.front().points)
            if (p.first > 0 && p.second > 0 && (!anchor || p.first > anchor->first)) anchor = p;
    if (anchor) {  // clipped to the plot here rather than with clipPath, which not every viewer honours
        const double c = std::log10(anchor->second) - std::log10(anchor->first);  // log y = log x + c
        const double a = std::max(lx0, ly0 - c), b = std::min(lx1, ly1 - c);
        if (b > a) {
            const double x0 = std::pow(10.0, a), x1 = std::pow(10.0, b);
            out << fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#888" stroke-width="1.2" )"
                               R"(stroke-dasharray="8 5"/>)" "\n",
                               num(X(x0)), num(Y(x0 * std::pow(10.0, c))), num(X(x1)),
                               num(Y(x1 * std::pow(10.0, c))));
        } else {
            anchor.reset();
        }
    }

    // The series.
    std::vector<std::string> colors;
    for (std::size_t i = 0; i < plot.series.size(); ++i)
        colors.push_back(plot.series[i].color.empty() ? palette[i % palette.size()] : plot.series[i].color);
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
        const PlotSeries& s = plot.series[i];
        std::vector<std::pair<double, double>> points;
        for (auto p : s.points)
            if (p.first > 0 && p.second > 0) points.push_back(p);
        std::sort(points.begin(), points.end());
        out << fmt::format("<g class=\"series\"><title>{}</title>\n", xml(s.label));
        std::string path;
        for (auto [x, y] : points) path += fmt::format("{}{},{}", path.empty() ? "" : " ", num(X(x)), num(Y(y)));
        out << fmt::format(R"(<polyline points="{}" fill="none" stroke="{}" stroke-width="2"{}/>)" "\n", path, colors[i],
                           s.dash.empty() ? "" : fmt::format(R"( stroke-dasharray="{}")", s.dash));
        for (auto [x, y] : points)
            out << (s.hollow ? fmt::format(R"(<circle cx="{}" cy="{}" r="3.5" fill="white" stroke="{}" stroke-width="1.8"/>)" "\n",
                                           num(X(x)), num(Y(y)), colors[i])
                             : fmt::format(R"(<circle cx="{}" cy="{}" r="3.5" fill="{}" stroke="white" stroke-width="0.8"/>)" "\n",
                                           num(X(x)), num(Y(y)), colors[i]));
        out << "</g>\n";
    }

    // Legend, right of the plot.
    const double lx = right + 18;
    double ly = top + 8;
    out << "<g class=\"legend\" font-size=\"12\">\n";
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
        const PlotSeries& s = plot.series[i];
        if (!s.in_legend) continue;
        out << fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{}" stroke-width="2"{}/>)" "\n", num(lx),
                           num(ly), num(lx + 28), num(ly), colors[i],
                           s.dash.empty() ? "" : fmt::format(R"( stroke-dasharray="{}")", s.dash));
        out << (s.hollow ? fmt::format(R"(<circle cx="{}" cy="{}" r="3.5" fill="white" stroke="{}" stroke-width="1.8"/>)" "\n",
                                       num(lx + 14), num(ly), colors[i])
                         : fmt::format(R"(<circle cx="{}" cy="{}" r="3.5" fill="{}"/>)" "\n", num(lx + 14), num(ly), colors[i]));
        out << fmt::format(R"(<text x="{}" y="{}">{}</text>)" "\n", num(lx + 36), num(ly + 4), xml(s.label));
        ly += 20;
    }
    if (!plot.notes.empty()) ly += 8;
    for (const LegendNote& note : plot.notes) {
        out << fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#444" stroke-width="2"{}/>)" "\n", num(lx),
                           num(ly), num(lx + 28), num(ly),
                           note.dash.empty() ? "" : fmt::format(R"( stroke-dasharray="{}")", note.dash));
        out << (note.hollow ? fmt::format(R"(<circle cx="{}" cy="{}" r="3.5" fill="white" stroke="#444" stroke-width="1.8"/>)" "\n",
                                          num(lx + 14), num(ly))
                            : fmt::format(R"(<circle cx="{}" cy="{}" r="3.5" fill="#444"/>)" "\n", num(lx + 14), num(ly)));
        out << fmt::format(R"(<text x="{}" y="{}" fill="#444">{}</text>)" "\n", num(lx + 36), num(ly + 4), xml(note.label));
        ly += 20;
    }
    if (anchor) {
        if (plot.notes.empty()) ly += 8;
        out << fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#888" stroke-width="1.2" stroke-dasharray="8 5"/>)" "\n",
                           num(lx), num(ly), num(lx + 28), num(ly));
        out << fmt::format(R"(<text x="{}" y="{}" fill="#555">linear in faces</text>)" "\n", num(lx + 36), num(ly + 4));
    }
    out << "</g>\n</g>\n";
}

}  // namespace

void write_svg(std::ostream& out, const std::vector<LogLogPlot>& plots) {
    int width = 0, height = 0;
    for (const LogLogPlot& p : plots) width = std::max(width, p.width), height += p.height;
    if (plots.empty()) width = height = 100;
    out << fmt::format(R"(<svg xmlns="http://www.w3.org/2000/svg" width="{0}" height="{1}" viewBox="0 0 {0} {1}" )"
                       R"(font-family="DejaVu Sans, Helvetica, Arial, sans-serif">)" "\n",
                       width, height);
    out << fmt::format(R"(<rect x="0" y="0" width="{}" height="{}" fill="white"/>)" "\n", width, height);
    double dy = 0;
    for (const LogLogPlot& p : plots) {
        write_panel(out, p, dy);
        dy += p.height;
    }
    out << "</svg>\n";
}

void write_svg(std::ostream& out, const LogLogPlot& plot) { write_svg(out, std::vector<LogLogPlot>{plot}); }

std::vector<LogLogPlot> plot_results(const std::vector<Result>& results) {
    static const std::array<const char*, 10> palette = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                                        "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};
    std::vector<std::pair<uint32_t, uint32_t>> sizes;
    std::vector<std::string> algorithms;
    for (const Result& r : results) {
        index_of(sizes, std::make_pair(r.width, r.height));
        index_of(algorithms, r.algorithm);
    }
    std::vector<LogLogPlot> plots;
    for (const auto& size : sizes) {
        LogLogPlot plot;
        unsigned reps = 0;
        bool any_deep = false, any_single = false;
        for (const Result& r : results)
            if (std::make_pair(r.width, r.height) == size) {
                reps = std::max(reps, r.repetitions);
                (r.instances > 0 ? any_deep : any_single) = true;
            }
        plot.title = fmt::format("Render time against face count, {}x{}", size.first, size.second);
        plot.subtitle = fmt::format("visibility (hidden-surface plugin), build excluded; median of {} run{}", reps,
                                    reps == 1 ? "" : "s");
        plot.x_label = "faces drawn (log scale)";
        plot.y_label = "render time, ms (log scale)";
        for (bool deep : {false, true})
            for (std::size_t a = 0; a < algorithms.size(); ++a) {
                PlotSeries series;
                series.label = deep ? algorithms[a] + ", deep scenes" : algorithms[a];
                series.color = palette[a % palette.size()];
                series.dash = deep ? "6 4" : "";
                series.hollow = deep;
                series.in_legend = !deep || !any_single;
                for (const Result& r : results)
                    if (r.algorithm == algorithms[a] && std::make_pair(r.width, r.height) == size &&
                        (r.instances > 0) == deep)
                        series.points.emplace_back(double(r.faces), std::max(r.visibility.median, 1e-3));
                if (!series.points.empty()) plot.series.push_back(std::move(series));
            }
        if (any_deep && any_single) {
            plot.notes.push_back({"", false, "single models"});
            plot.notes.push_back({"6 4", true, "deep scenes"});
        }
        std::map<uint64_t, std::string> guides;
        for (const Result& r : results) {
            if (std::make_pair(r.width, r.height) != size) continue;
            std::string& label = guides[r.faces];
            if (label.find(r.model) == std::string::npos) label += (label.empty() ? "" : ", ") + r.model;
        }
        for (const auto& [faces, label] : guides) plot.guides.push_back({double(faces), label});
        plots.push_back(std::move(plot));
    }
    return plots;
}

}  // namespace hsr::bench
