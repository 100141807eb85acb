// Benchmarking hidden-surface plugins (`hsr bench`): the benchmark scenes and their cameras, the
// timing loop and the statistics. The host's bench command is the command line around these, and
// writes the reports (bench_report.hpp: table and CSV; bench_plot.hpp: the plot).
#pragma once

#include "hsr/camera.hpp"
#include "hsr/fragment_lists.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/renderer.hpp"
#include "hsr/scene.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hsr::bench {

using Counters = std::vector<std::pair<std::string, uint64_t>>;

// ---------------------------------------------------------------------------------------------
// Statistics

// Median and spread of a set of samples. Quartiles interpolate linearly between order statistics
// (Hyndman & Fan type 7, what R and NumPy do by default), so q1 and q3 of {1, 2, 3, 4} are 1.75 and
// 3.25, and the median of an even count is the mean of the two middle samples.
struct Summary {
    std::size_t count = 0;
    double median = 0, min = 0, max = 0, q1 = 0, q3 = 0;
    double iqr() const { return q3 - q1; }
};
// Throws hsr::Error for no samples or a sample that is not a finite number.
Summary summarize(std::vector<double> samples);
// The p-quantile (0 <= p <= 1) of samples sorted ascending, type 7 as above.
double quantile(const std::vector<double>& sorted, double p);

// ---------------------------------------------------------------------------------------------
// Scenes

// The models `hsr bench` runs by default, mirroring the classic course study: three meshes of
// increasing size, the bunny made 4x finer by Loop subdivision, and deep scenes of 3, 24 and 63
// layers of monkeys (measured depth complexity 4.7, 20.3 and 49.8 at 1024x1024: docs/bench.md).
const std::vector<std::string>& default_models();
// A small, fast set for smoke tests; only uses models committed to the repository.
const std::vector<std::string>& quick_models();

// A model as `hsr bench --models` names it:
//   NAME            models/NAME.obj (or .off, .ply, .stl, .gltf, .glb) in the models folder: cube, monkey, bunny, ...
//   NAME-loop[K]    that model with K levels of Loop subdivision (default 1): bunny-loop
//   deep-N[:NAME]   NAME (default monkey) placed on a DeepGrid with N layers: deep-20
//   random-N[:SEED] N random triangles (hsr/random_triangles.hpp), seed 1 unless given: random-1000:7
//   a file path     anything with a '/' or an extension: a mesh file or a .scene file
struct ModelSpec {
    std::string name;              // as given; shown in tables and plots
    std::filesystem::path file;    // the mesh or .scene file
    int loop_levels = 0;
    uint32_t layers = 0;           // 0: the model alone; else a deep scene of that many layers
    uint64_t random_triangles = 0; // not 0: random triangles instead of a file
    uint64_t seed = 1;             // of the random triangles
};
// Throws hsr::Error for an unknown name or a file that does not exist.
ModelSpec parse_model_spec(const std::string& text, const std::filesystem::path& models_dir);

// The grid behind deep-N: the model columns x rows across and N layers deep, each copy turned a
// little so that the layers do not line up exactly (as in models/deep-monkeys.scene).
struct DeepGrid {
    uint32_t columns = 0;  // 0: as many as make each layer about as wide as it is tall
    uint32_t rows = 4;
    float gap = 0.05f;
    float yaw_jitter_degrees = 25.0f;
};

struct BenchScene {
    std::string name;
    SceneData scene;
    CameraSettings camera;  // width and height are set per run
    uint32_t layers = 0;    // deep scenes: the layer count
};
BenchScene load_bench_scene(const ModelSpec& spec, const DeepGrid& grid = {});
// The scene's orbit camera at one image size, as a Renderer's view: the BenchScene's camera
// settings, nothing of a .scene file but what load_bench_scene took from it.
ViewRequest bench_view(const BenchScene& scene, uint32_t width, uint32_t height);
// bench_view's camera, made by a Renderer of the scene's mesh. Throws hsr::Error naming the model
// when no camera can view it (coordinates so large, ~1e38, that its matrices would overflow).
hsr_camera make_bench_camera(const Renderer& renderer, const BenchScene& scene, uint32_t width, uint32_t height);
// The same while the BenchScene still holds its mesh (a Renderer made for a copy of it).
hsr_camera make_bench_camera(const BenchScene& scene, uint32_t width, uint32_t height);

// The deep scene of `layers` layers, and the zoom at which its front layer fills the view (the
// nearest copies touch the image border; farther ones recede toward the centre).
SceneData make_deep_scene(const SceneData& model, uint32_t layers, const DeepGrid& grid = {});
float front_layer_zoom(const SceneData& deep, CameraSettings settings);

// ---------------------------------------------------------------------------------------------
// Timing

struct TimingSettings {
    unsigned warmup = 1;       // untimed calls first (a plugin typically builds its caches here)
    unsigned repetitions = 5;  // timed calls, at least 1
    FrameSettings frame;
};

// The process's resident memory around one measurement, in bytes (Linux /proc; 0 = unknown). The
// FrameTimer's constructor returns free heap pages to the system (glibc's malloc_trim), resets the
// kernel's high-water mark to the current resident size (writing 5 to /proc/self/clear_refs) and
// records that size as `before`; after each call `peak` is VmHWM from /proc/self/status. So `peak`
// is the whole process at its largest during the measurement: every scene the bench holds (all
// models are loaded before the first measurement), the frame's buffers, the plugin's structures
// (its build included, made in the first call) and the shading's; `peak - before` is what the
// measurement added. Unknown when the mark cannot be reset (not Linux, or clear_refs not
// writable): a peak since the process started would mislead.
struct PeakMemory {
    uint64_t before = 0, peak = 0;
    bool known() const { return peak > 0; }
    uint64_t added() const { return peak > before ? peak - before : 0; }
};
// Resets the high-water mark; returns the resident size then (0 when the mark cannot be reset).
uint64_t reset_peak_memory();
// VmHWM: the largest resident size since the last reset, or since the process started.
uint64_t peak_memory();

// One call: visibility (hidden-surface plugin, build time included as measured), the build time
// the plugin reported (counter build-time-us), and shading.
struct CallTiming {
    unsigned index = 0;  // 0-based, warm-up calls first
    bool warmup = false;
    double visibility_ms = 0, build_ms = 0, shading_ms = 0;
    double render_ms() const { return visibility_ms - build_ms; }
};

struct Timing {
    std::vector<CallTiming> calls;  // every call, warm-up included
    std::vector<double> render_ms;  // timed calls: visibility minus that call's build time
    std::vector<double> shading_ms;
    std::vector<double> total_ms;   // render + shading
    double build_ms = 0;            // largest build time any call reported, warm-up included
    unsigned build_calls = 0;       // how many calls reported one (1 when caches persist)
    Counters counters;              // the last call's counters, without build-time-us
    PeakMemory memory;              // of the process while this timer ran (see PeakMemory)
};

// Times one remover on one scene, one frame per call of a FrameLoop (hsr/renderer.hpp): the same
// remover and lighting instances (so a plugin's caches persist between calls) and the same buffers. Only the plugin calls are timed (Frame::visibility_ms, Frame::shading_ms, steady
// clock): no loading, camera setup or image writing. A remover built before instances (ABI 1.0) is
// given the scene with its instances copied out, once, in the constructor. The first
// settings.warmup calls are warm-up calls; the scene, camera, instances and context must outlive
// the timer.
class FrameTimer {
public:
    FrameTimer(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
               LightingModel& lighting, const hsr_shading_context& context, const TimingSettings& settings);
    CallTiming call();                  // one frame
    unsigned calls_made() const { return static_cast<unsigned>(timing_.calls.size()); }
    const Timing& timing() const { return timing_; }

private:
    TimingSettings settings_;
    Timing timing_;
    FrameLoop loop_;
};

// warmup + repetitions calls of one FrameTimer in a row, as hsr bench makes them; after_call runs
// after every call.
Timing time_frames(const hsr_scene& scene, const hsr_camera& camera, HiddenSurfaceRemover& remover,
                   LightingModel& lighting, const hsr_shading_context& context, const TimingSettings& settings,
                   const std::function<void(const CallTiming&)>& after_call = {});

// ---------------------------------------------------------------------------------------------
// Results

struct Result {
    std::string algorithm, model;
    uint32_t width = 0, height = 0;
    uint64_t faces = 0;                 // triangles drawn (instances counted)
    uint32_t stored_faces = 0;          // triangles stored
    uint32_t instances = 0;
    uint32_t layers = 0;                // deep scenes
    float zoom = 1;                     // the orbit camera's (hsr render --zoom shows the same view)
    std::optional<double> depth_complexity;  // mean over covered pixels, when measured
    uint32_t depth_complexity_max = 0;
    unsigned warmup = 0, repetitions = 0;
    Summary visibility, shading, total; // ms; visibility excludes the build time
    double build_ms = 0;
    unsigned build_calls = 0;
    Counters counters;
    PeakMemory memory;
    // Not empty: the plugin refused this scene (an error from one of its calls), and this is its
    // one-line reason; nothing was timed.
    std::string refused;
    // Not empty: the process timing this cell ended or was ended before the cell's last call,
    // "crashed (SIGSEGV)", "aborted (SIGABRT)", "exited (status 0)" or "timed out", and fault_detail
    // says by what (the plugin's own line when it wrote one); nothing was timed.
    std::string fault, fault_detail;
    bool measured() const { return refused.empty() && fault.empty(); }
};
Result make_result(std::string algorithm, std::string model, const hsr_scene& scene, const hsr_camera& camera,
                   const Timing& timing, unsigned warmup, const std::optional<DepthComplexity>& depth_complexity);

}  // namespace hsr::bench
