// hsr bench: the command line around bench/measure.hpp. Times hidden-surface plugins on models and deep
// scenes at several resolutions, prints the table, writes CSV and a plot (SVG or PNG).
#include "bench/bench_cell.hpp"
#include "bench/bench_llvmpipe.hpp"
#include "bench/measure.hpp"
#include "bench/bench_plot.hpp"
#include "bench/bench_report.hpp"
#include "bench/bench_worker.hpp"
#include "common/command_line.hpp"
#include "common/commands.hpp"
#include "common/options.hpp"
#include "common/outputs.hpp"
#include "common/plugins.hpp"
#include "common/threads.hpp"

#include "hsr/atomic_file.hpp"
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/renderer.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_file.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/program_options.hpp>
#include <fmt/format.h>

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

using hsr::host::UsageError;

// The items of a comma-separated option. An option given with no item ("", ",") is a mistake, not a
// request for the default list.
std::vector<std::string> split_list(const std::string& text, const char* option) {
    std::vector<std::string> items;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t comma = text.find(',', start);
        if (comma == std::string::npos) comma = text.size();
        std::string item = text.substr(start, comma - start);
        while (!item.empty() && item.front() == ' ') item.erase(item.begin());
        while (!item.empty() && item.back() == ' ') item.pop_back();
        if (!item.empty()) items.push_back(item);
        start = comma + 1;
    }
    if (items.empty()) throw UsageError("--{}: the list is empty (leave the option out for the default)", option);
    return items;
}

// Each item once: a repeat would only measure the same thing twice. what(item) names it.
template <class Item, class Describe>
void refuse_repeats(const std::vector<Item>& items, Describe what) {
    for (auto it = items.begin(); it != items.end(); ++it)
        if (std::find(items.begin(), it, *it) != it) throw UsageError("{} is named twice", what(*it));
}

// "1024" (square) or "800x600".
std::pair<uint32_t, uint32_t> parse_size(const std::string& text) {
    unsigned long long w = 0, h = 0;
    char x = 0, extra = 0;
    const int n = std::sscanf(text.c_str(), "%llu%c%llu%c", &w, &x, &h, &extra);
    if (n == 1 && text.find_first_not_of("0123456789") == std::string::npos) h = w;
    else if (!(n == 3 && x == 'x' && text.find_first_not_of("0123456789x") == std::string::npos))
        throw UsageError("--sizes: '{}' is not a size (512 or 800x600)", text);
    if (w == 0 || h == 0 || w > hsr::max_image_side || h > hsr::max_image_side)
        throw UsageError("--sizes: {}: each side must be between 1 and {}", text, hsr::max_image_side);
    hsr::check_limit(&hsr::Limits::image_pixels, w * h, fmt::format("--sizes: {}", text));
    return {uint32_t(w), uint32_t(h)};
}

// The folder that holds cube.obj, monkey.obj, bunny.obj: --models-dir, else ./models, else the
// source tree's models/ beside the build folder, else the installed share/hsr/models.
fs::path find_models_dir(const std::string& given) {
    if (!given.empty()) {
        if (!fs::is_directory(given)) throw UsageError("--models-dir: '{}' is not a folder", given);
        return given;
    }
    const fs::path exe_dir(boost::dll::program_location().parent_path().string());
    for (const fs::path& candidate : {fs::path("models"), exe_dir / ".." / "models", exe_dir / ".." / ".." / "models",
                                      exe_dir / ".." / "share" / "hsr" / "models"}) {
        std::error_code ec;
        if (fs::is_regular_file(candidate / "cube.obj", ec)) return candidate.lexically_normal();
    }
    return "models";
}

// Hidden-surface plugins in the order of the classic study, then any others as found.
std::vector<std::string> all_algorithms(const hsr::PluginRegistry& registry) {
    static const std::vector<std::string> order = {"zbuffer", "scanline-zbuffer", "hierarchical-zbuffer",
                                                   "octree-zbuffer"};
    std::vector<std::string> found;
    for (const hsr::Plugin& p : registry.plugins())
        if (p.descriptor.kind == HSR_KIND_HIDDEN_SURFACE_REMOVER) found.push_back(p.descriptor.name);
    std::stable_sort(found.begin(), found.end(), [&](const std::string& a, const std::string& b) {
        auto rank = [&](const std::string& n) {
            return std::size_t(std::find(order.begin(), order.end(), n) - order.begin());
        };
        return rank(a) < rank(b);
    });
    return found;
}

// Progress on stderr: a bar redrawn in place on a terminal, else one plain line per step.
class Progress {
public:
    Progress(std::size_t total_calls) : total_(total_calls), tty_(isatty(STDERR_FILENO) == 1) {}
    // An error thrown mid-run is then printed on a line of its own, not after the bar.
    ~Progress() { clear(); }

    void loading(const std::string& model) {
        if (tty_) draw(fmt::format("loading {}", model));
        else std::fprintf(stderr, "hsr bench: loading %s\n", model.c_str());
    }
    void measuring(const std::string& what) {
        if (tty_) draw(what);
        else std::fprintf(stderr, "hsr bench: %s\n", what.c_str());
    }
    void show(const std::string& what) {  // what runs now
        if (tty_) draw(what);
    }
    void advance() { ++done_; }
    void row(const std::string& line) {
        ++rows_;
        if (!tty_) std::fprintf(stderr, "hsr bench: %s\n", line.c_str());
    }
    void message(const std::string& line) {  // a warning: keeps the bar below it
        clear();
        std::fprintf(stderr, "%s\n", line.c_str());
    }
    void finish() {
        clear();
        const double s = std::chrono::duration<double>(Clock::now() - start_).count();
        std::fprintf(stderr, "hsr bench: %zu measurement%s in %.1f s\n", rows_, rows_ == 1 ? "" : "s", s);
    }

private:
    using Clock = std::chrono::steady_clock;
    void clear() {
        if (tty_) std::fputs("\r\033[K", stderr);
    }
    void draw(const std::string& what) {
        constexpr int bar = 28;
        const double f = total_ ? double(done_) / double(total_) : 1.0;
        const int filled = int(f * bar + 0.5);
        const double s = std::chrono::duration<double>(Clock::now() - start_).count();
        std::string line = fmt::format("[{}{}] {:3d}% {:5.0f}s  {}", std::string(filled, '#'),
                                       std::string(bar - filled, '.'), int(f * 100 + 0.5), s, what);
        winsize size{};
        const std::size_t columns = ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0 ? size.ws_col : 80;
        if (line.size() >= columns) line.resize(columns - 1);  // a wrapped line could not be redrawn in place
        std::fprintf(stderr, "\r\033[K%s", line.c_str());
        std::fflush(stderr);
    }
    std::size_t total_, done_ = 0, rows_ = 0;
    bool tty_;
    Clock::time_point start_ = Clock::now();
};

std::string ms(double v) { return fmt::format("{:.{}f}", v, v < 10 ? 2 : 1); }

using hsr::bench::PreparedModel;
using Size = hsr::bench::ImageSize;

// A cell may run this long by default: 6x the slowest cell of the default study (raycast on deep-63,
// about 20 s on the project's machine), so that only a plugin that hangs meets it.
constexpr double kDefaultCellTimeLimitSeconds = 120;
constexpr double kMaxCellTimeLimitSeconds = 7 * 24 * 3600;

// The command line as given, with --quick's defaults for what it leaves out.
struct BenchOptions {
    std::string algorithms_list, models_list, sizes_list = "1024", lighting_text = "blinn-phong";
    std::vector<std::string> algorithm_specs, plugin_dirs, limit_settings;
    std::string csv_path, svg_path, png_path, models_dir_text;
    int64_t repetitions = 5, warmup = 1, threads = 0;
    double cell_time_limit = kDefaultCellTimeLimitSeconds;
    bool quick = false, vs_llvmpipe = false, in_process = false;
    po::variables_map vm;

    // Whether the option is on the command line (not just at its default).
    bool given(const char* option) const { return vm.count(option) && !vm[option].defaulted(); }
};

// The options of hsr bench, each stored in its field of o.
po::options_description describe_options(BenchOptions& o) {
    po::options_description options(
        "hsr bench [options]: time hidden-surface plugins on models and deep scenes\n"
        "(render time = the hidden-surface plugin's visibility call, without loading, camera setup,\n"
        "image writing, or the acceleration-structure build a plugin reports; medians over repetitions)");
    options.add_options()
        ("help,h", "show this help")
        ("algorithms", po::value(&o.algorithms_list),
         "hidden-surface plugins, comma-separated (default: every one found)")
        ("algorithm,a", po::value(&o.algorithm_specs)->composing(),
         "one more, with parameters: NAME[:key=value,...] (repeatable)")
        ("models", po::value(&o.models_list),
         "comma-separated: cube, monkey, bunny, NAME-loop (Loop-subdivided), deep-N[:NAME] (N layers of "
         "NAME, default monkey), random-N[:SEED] (N random triangles, seed 1 unless given), or file paths "
         "(default: cube,monkey,bunny,bunny-loop,deep-3,deep-24,deep-63, the deep ones at depth complexity "
         "4.7, 20.3, 49.8)")
        ("sizes", po::value(&o.sizes_list)->default_value("1024"), "image sizes, comma-separated: 512,1024 or 800x600")
        ("repetitions,r", po::value(&o.repetitions)->default_value(5), "timed runs of each measurement")
        ("warmup,w", po::value(&o.warmup)->default_value(1), "untimed runs first (caches, acceleration structures)")
        ("lighting,l", po::value(&o.lighting_text)->default_value("blinn-phong"), "lighting plugin: NAME[:key=value,...]")
        ("csv", po::value(&o.csv_path), "write every number to this CSV file")
        ("svg", po::value(&o.svg_path), "plot render time against face count to this SVG file")
        ("png", po::value(&o.png_path), "the same plot as a PNG image")
        ("quick", po::bool_switch(&o.quick),
         "a small fast run: cube, octahedron, cube-loop, deep-3:cube at 128x128, 3 repetitions")
        ("threads", po::value(&o.threads)->default_value(0), "threads for loading, visibility and shading (0 = one per core)")
        ("cell-time-limit", po::value(&o.cell_time_limit)->default_value(kDefaultCellTimeLimitSeconds),
         "seconds one algorithm may take on one model at one size, its calls and its start together; "
         "one that takes longer is stopped and its cell reads 'timed out', and the algorithm's cells at "
         "least as large (triangles and pixels) read 'skipped'")
        ("in-process", po::bool_switch(&o.in_process),
         "time every cell in this process rather than in worker processes: a plugin that crashes or "
         "hangs then ends or holds the whole run (for a debugger or profiler on one process)")
        ("vs-llvmpipe", po::bool_switch(&o.vs_llvmpipe),
         "also draw each scene with Mesa's llvmpipe (build/hsr-llvmpipe, -DHSR_LLVMPIPE=ON) and print both "
         "frame times and their ratio (zbuffer + blinn-phong; default algorithm zbuffer only)")
        ("models-dir", po::value(&o.models_dir_text), "folder of the named models (default: ./models or the source tree's)")
        ("plugin-path", po::value(&o.plugin_dirs)->composing(), "extra folder to search for plugins (repeatable)")
        ("limit", po::value(&o.limit_settings)->composing(), hsr::describe_limit_option().c_str());
    return options;
}

// The command line read; nullopt once --help has printed the options.
std::optional<BenchOptions> parse_options(const std::vector<std::string>& args) {
    BenchOptions o;
    const po::options_description options = describe_options(o);
    po::command_line_parser parser(args);
    parser.options(options);
    const po::parsed_options parsed = hsr::host::parse_command_line(parser, options);
    po::store(parsed, o.vm);
    po::notify(o.vm);
    if (o.vm.count("help")) {
        std::cout << options;
        return std::nullopt;
    }
    // Words that are not options: program_options would drop them silently and run the default study.
    for (const std::string& word : po::collect_unrecognized(parsed.options, po::include_positional))
        throw UsageError("bench: unexpected argument '{}' (models go in --models)", word);
    if (o.quick) {
        if (!o.given("sizes")) o.sizes_list = "128";
        if (!o.given("repetitions")) o.repetitions = 3;
    }
    return o;
}

// The numbers, limits, sizes and output files checked; returns the sizes.
std::vector<Size> check_settings(const BenchOptions& o) {
    if (o.repetitions < 1 || o.repetitions > 100000) throw UsageError("--repetitions must be between 1 and 100000");
    if (o.warmup < 0 || o.warmup > 100000) throw UsageError("--warmup must be between 0 and 100000");
    if (o.threads < 0 || o.threads > hsr::host::kMaxThreads)
        throw UsageError("--threads must be between 0 and {}", hsr::host::kMaxThreads);
    if (!(o.cell_time_limit > 0 && o.cell_time_limit <= kMaxCellTimeLimitSeconds))
        throw UsageError("--cell-time-limit must be more than 0 and at most {:g} seconds", kMaxCellTimeLimitSeconds);
    if (o.in_process && o.given("cell-time-limit"))
        throw UsageError("--cell-time-limit needs worker processes (leave out --in-process)");
    try {
        hsr::set_limits(hsr::limits_from_settings(o.limit_settings));
    } catch (const hsr::Error& e) {
        throw UsageError("{}", e.what());
    }
    std::vector<Size> sizes;
    for (const std::string& s : split_list(o.sizes_list, "sizes")) sizes.push_back(parse_size(s));
    refuse_repeats(sizes, [](const auto& size) { return fmt::format("size {}x{}", size.first, size.second); });
    std::vector<hsr::host::OutputFile> outputs;
    if (o.given("csv")) outputs.push_back({"csv", o.csv_path, {".csv"}});
    if (o.given("svg")) outputs.push_back({"svg", o.svg_path, {".svg"}});
    if (o.given("png")) outputs.push_back({"png", o.png_path, {".png"}});
    hsr::host::check_outputs(outputs);
    return sizes;
}

// The algorithms as shown: each name, with its parameters when given.
std::vector<std::string> algorithm_labels(const BenchOptions& o, const hsr::PluginRegistry& registry) {
    std::vector<std::string> labels = o.given("algorithms") ? split_list(o.algorithms_list, "algorithms")
                                                            : std::vector<std::string>{};
    labels.insert(labels.end(), o.algorithm_specs.begin(), o.algorithm_specs.end());
    if (labels.empty()) labels = o.vs_llvmpipe ? std::vector<std::string>{"zbuffer"} : all_algorithms(registry);
    if (labels.empty()) throw hsr::Error("no hidden-surface plugins found (see hsr plugins)");
    refuse_repeats(labels, [](const std::string& label) { return fmt::format("algorithm '{}'", label); });
    return labels;
}

// The plugins the labels name, with their parameters. Unknown names and bad parameters fail here,
// before any model is loaded, checked against the plugins' descriptors: no instance is made, as a
// plugin that crashes in create() would take this process with it.
std::vector<hsr::PluginSpec> algorithm_specs(const std::vector<std::string>& labels,
                                             const hsr::PluginRegistry& registry) {
    std::vector<hsr::PluginSpec> algorithms;
    for (const std::string& label : labels) {
        algorithms.push_back(hsr::parse_plugin_spec(label));
        const hsr::Plugin& plugin = registry.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, algorithms.back().name);
        hsr::resolve_params(plugin.descriptor, algorithms.back().settings);
    }
    return algorithms;
}

// The models to time, and the folder of the named ones.
struct ModelChoice {
    fs::path models_dir;
    std::vector<hsr::bench::ModelSpec> models;
};

ModelChoice model_specs(const BenchOptions& o) {
    const std::vector<std::string> model_names = o.given("models") ? split_list(o.models_list, "models")
                                                 : o.quick              ? hsr::bench::quick_models()
                                                                        : hsr::bench::default_models();
    refuse_repeats(model_names, [](const std::string& name) { return fmt::format("model '{}'", name); });
    ModelChoice choice{find_models_dir(o.models_dir_text), {}};
    for (const std::string& name : model_names)
        choice.models.push_back(hsr::bench::parse_model_spec(name, choice.models_dir));
    return choice;
}

// Every model is loaded and its cameras made before any timing, so that a bad file fails in a
// moment rather than after the models before it have been timed. Holding them all is cheap: the
// peak is Loop-subdividing the bunny (96 MB alone), the loaded meshes are a few MB and a deep
// scene stores its mesh once (`hsr bench -r 1 -w 0`: 110 MB peak). Each is dropped once measured.
std::vector<PreparedModel> prepare_models(const std::vector<hsr::bench::ModelSpec>& models,
                                          const std::vector<Size>& sizes, Progress& progress) {
    std::vector<PreparedModel> prepared;
    for (const hsr::bench::ModelSpec& spec : models) {
        progress.loading(spec.name);
        prepared.push_back(hsr::bench::prepare_model(
            spec, sizes, [&](const std::string& warning) { progress.message("hsr: warning: " + warning); }));
    }
    return prepared;
}

// Where the cells are timed: in worker processes (bench_worker.hpp), each told `job` with its model
// filled in, or in this process with `lighting` (--in-process).
struct CellPlace {
    hsr::bench::WorkerJob job;
    double cell_time_limit = kDefaultCellTimeLimitSeconds;
    hsr::LightingModel* lighting = nullptr;  // not null: here
};

// The measurements, model after model, size after size, algorithm after algorithm: one row of
// results each, shown as progress.
class Study {
public:
    Study(const hsr::PluginRegistry& registry, const std::vector<hsr::PluginSpec>& algorithms,
          const std::vector<std::string>& labels, CellPlace& place, const hsr::bench::TimingSettings& settings,
          Progress& progress, std::size_t scenes)
        : registry_(registry), algorithms_(algorithms), labels_(labels), place_(place), settings_(settings),
          progress_(progress), scenes_(scenes), rows_(scenes * algorithms.size()) {}

    // Every size of the model; the model is dropped once measured.
    void measure(PreparedModel& model, const std::string& model_name, const std::vector<Size>& sizes) {
        const hsr_scene view = model.renderer->loaded().scene().view();
        std::vector<std::optional<hsr::DepthComplexity>> depth_complexity;
        for (std::size_t size = 0; size < sizes.size(); ++size) {
            progress_.measuring(fmt::format("depth complexity of {} at {}x{}", model.scene.name, sizes[size].first,
                                            sizes[size].second));
            depth_complexity.push_back(model.renderer->depth_complexity(model.cameras[size]));
        }
        const uint64_t triangles = hsr::drawn_triangle_count(view);
        auto pixels = [&](std::size_t size) { return uint64_t(sizes[size].first) * sizes[size].second; };
        auto finished = [&](const hsr::bench::Cell& cell, const hsr::bench::CellOutcome& outcome) {
            for (; advanced_in_cell_ < settings_.warmup + settings_.repetitions; ++advanced_in_cell_) progress_.advance();
            advanced_in_cell_ = 0;
            if (outcome.fault == "timed out")
                timed_out_.push_back({cell.algorithm, triangles, pixels(cell.size),
                                      fmt::format("{} at {}x{}", model.scene.name, sizes[cell.size].first,
                                                  sizes[cell.size].second)});
            add_row(cell, model, view, outcome, depth_complexity[cell.size]);
        };
        // A cell no smaller than one its algorithm ran out of time on, in triangles and in pixels,
        // would only spend the limit again.
        auto skip = [&](const hsr::bench::Cell& cell) -> std::optional<std::string> {
            for (const TimedOut& t : timed_out_)
                if (t.algorithm == cell.algorithm && t.triangles <= triangles && t.pixels <= pixels(cell.size))
                    return fmt::format("timed out on {} (a cell no larger)", t.where);
            return std::nullopt;
        };
        if (place_.lighting != nullptr) {
            // Each algorithm makes all its calls in a row, warm-up first, as an application
            // rendering frame after frame would, with the processor caches its own.
            for (std::size_t size = 0; size < sizes.size(); ++size)
                for (std::size_t a = 0; a < algorithms_.size(); ++a) {
                    const hsr::bench::Cell cell{size, a};
                    finished(cell, hsr::bench::time_cell(
                                       model, size, registry_.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, algorithms_[a].name),
                                       algorithms_[a].settings, *place_.lighting, settings_,
                                       [&](unsigned call) { calling(cell, model.scene.name, sizes, call); }));
                }
        } else {
            place_.job.model = model_name;
            hsr::bench::time_cells_apart(
                place_.job, std::chrono::duration<double>(place_.cell_time_limit),
                [&](const hsr::bench::Cell& cell, unsigned call) { calling(cell, model.scene.name, sizes, call); },
                finished, skip);
        }
        shots_done_ += sizes.size();
        model = {};
    }

    std::vector<hsr::bench::Result>& results() { return results_; }

private:
    void calling(const hsr::bench::Cell& cell, const std::string& model, const std::vector<Size>& sizes,
                 unsigned call) {
        for (; advanced_in_cell_ < call; ++advanced_in_cell_) progress_.advance();
        const bool warm = call < settings_.warmup;
        progress_.show(fmt::format("[{}/{}] {} {}x{}: {}, {} {}/{}", shots_done_ + cell.size + 1, scenes_, model,
                                   sizes[cell.size].first, sizes[cell.size].second, labels_[cell.algorithm],
                                   warm ? "warm-up" : "run", warm ? call + 1 : call + 1 - settings_.warmup,
                                   warm ? settings_.warmup : settings_.repetitions));
    }

    void add_row(const hsr::bench::Cell& cell, const PreparedModel& model, const hsr_scene& view,
                 const hsr::bench::CellOutcome& outcome, const std::optional<hsr::DepthComplexity>& depth_complexity) {
        ++row_;
        const hsr_camera& camera = model.cameras[cell.size];
        const std::string& label = labels_[cell.algorithm];
        const std::string where = fmt::format("[{}/{}] {} on {} {}x{}", row_, rows_, label, model.scene.name,
                                              camera.width, camera.height);
        hsr::bench::Result result;
        if (outcome.measured()) {
            result = hsr::bench::make_result(label, model.scene.name, view, camera, outcome.timing, settings_.warmup,
                                             depth_complexity);
            progress_.row(fmt::format("{}: {} ms [{}-{}]{}", where, ms(result.visibility.median),
                                      ms(result.visibility.min), ms(result.visibility.max),
                                      result.build_ms > 0 ? fmt::format(" + {} ms build", ms(result.build_ms)) : ""));
        } else {
            result.algorithm = label;
            result.model = model.scene.name;
            result.width = camera.width;
            result.height = camera.height;
            result.faces = hsr::drawn_triangle_count(view);
            result.stored_faces = view.triangle_count;
            result.instances = view.instance_count;
            if (depth_complexity) {
                result.depth_complexity = depth_complexity->mean_over_covered();
                result.depth_complexity_max = depth_complexity->max;
            }
            result.refused = outcome.refused;
            result.fault = outcome.fault;
            result.fault_detail = outcome.fault_detail;
            progress_.row(result.refused.empty() ? fmt::format("{}: {}: {}", where, result.fault, result.fault_detail)
                                                 : fmt::format("{}: n/a: {}", where, result.refused));
        }
        result.layers = model.scene.layers;
        result.zoom = model.scene.camera.zoom;
        results_.push_back(std::move(result));
    }

    const hsr::PluginRegistry& registry_;
    const std::vector<hsr::PluginSpec>& algorithms_;
    const std::vector<std::string>& labels_;
    CellPlace& place_;
    const hsr::bench::TimingSettings& settings_;
    Progress& progress_;
    const std::size_t scenes_, rows_;
    std::size_t row_ = 0, shots_done_ = 0;
    unsigned advanced_in_cell_ = 0;  // progress steps of the current cell's calls shown so far
    std::vector<hsr::bench::Result> results_;
    struct TimedOut {
        std::size_t algorithm;
        uint64_t triangles, pixels;
        std::string where;  // "cube at 1024x1024"
    };
    std::vector<TimedOut> timed_out_;
};

// The table on stdout, then the files asked for. Written only once the results are ready, and
// replaced together once all are written: neither a run nor a writer that fails leaves an existing
// file changed. Each shows every cell, those without a time marked as such.
void report(const BenchOptions& o, const std::vector<hsr::bench::Result>& results) {
    std::cout << hsr::bench::format_table(results);
    std::cout.flush();
    hsr::AtomicFileSet files;
    if (o.given("csv")) hsr::bench::write_csv(files.add(o.csv_path).stream(), results);
    const std::vector<hsr::bench::LogLogPlot> plots = hsr::bench::plot_results(results);
    using hsr::bench::PlotFormat;
    if (o.given("svg")) hsr::bench::write_plot(files.add(o.svg_path).stream(), plots, PlotFormat::svg);
    if (o.given("png")) hsr::bench::write_plot(files.add(o.png_path).stream(), plots, PlotFormat::png);
    files.commit();
    for (const auto& [option, path] : {std::pair{"csv", &o.csv_path}, {"svg", &o.svg_path}, {"png", &o.png_path}})
        if (o.given(option)) std::fprintf(stderr, "wrote %s\n", path->c_str());
}

}  // namespace

int hsr::host::run_bench(const std::vector<std::string>& args) {
    const std::optional<BenchOptions> parsed = parse_options(args);
    if (!parsed) return 0;
    const BenchOptions& o = *parsed;
    const std::vector<Size> sizes = check_settings(o);

    // Plugins, then models: every name is checked before anything large is loaded.
    hsr::PluginRegistry registry = scan_plugins(o.plugin_dirs);
    const std::vector<std::string> labels = algorithm_labels(o, registry);
    const std::vector<hsr::PluginSpec> algorithms = algorithm_specs(labels, registry);
    const hsr::PluginSpec lighting_spec = hsr::parse_plugin_spec(o.lighting_text);
    const fs::path llvmpipe_program = o.vs_llvmpipe ? find_llvmpipe_program(labels, o.lighting_text) : fs::path();
    hsr::resolve_params(registry.find(HSR_KIND_LIGHTING_MODEL, lighting_spec.name).descriptor, lighting_spec.settings);
    const ModelChoice choice = model_specs(o);

    hsr::bench::TimingSettings timing_settings;
    timing_settings.warmup = unsigned(o.warmup);
    timing_settings.repetitions = unsigned(o.repetitions);
    timing_settings.frame.threads = unsigned(o.threads);
    const ThreadBound thread_bound(o.threads);
    const std::size_t scenes = choice.models.size() * sizes.size();
    Progress progress(scenes * algorithms.size() * (timing_settings.warmup + timing_settings.repetitions));
    std::vector<PreparedModel> prepared = prepare_models(choice.models, sizes, progress);
    CellPlace place{{"", choice.models_dir, sizes, labels, o.lighting_text, timing_settings, unsigned(o.threads),
                     o.plugin_dirs, o.limit_settings},
                    o.cell_time_limit};
    std::optional<hsr::LightingModel> lighting;
    if (o.in_process) {
        lighting.emplace(registry.find(HSR_KIND_LIGHTING_MODEL, lighting_spec.name), lighting_spec.settings);
        place.lighting = &*lighting;
    }
    Study study(registry, algorithms, labels, place, timing_settings, progress, scenes);
    for (std::size_t m = 0; m < prepared.size(); ++m) study.measure(prepared[m], choice.models[m].name, sizes);
    progress.finish();

    report(o, study.results());
    if (o.vs_llvmpipe)  // last: the table and files above stand even if llvmpipe fails
        print_llvmpipe_comparison(llvmpipe_program, study.results(),
                                  {choice.models_dir, o.lighting_text, unsigned(o.warmup), unsigned(o.repetitions),
                                   unsigned(o.threads), o.plugin_dirs, o.limit_settings},
                                  std::cout);
    return 0;
}
