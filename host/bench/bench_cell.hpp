// One cell of hsr bench's study, an algorithm on a model at one size, timed in this process: what
// `hsr bench --in-process` does for every cell and each worker process (bench_worker.hpp) for its
// own. Also the model as both prepare it.
#pragma once

#include "bench/measure.hpp"

#include "hsr/params.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/renderer.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hsr::bench {

using ImageSize = std::pair<uint32_t, uint32_t>;  // width, height

// A model ready to time: loaded into a renderer (the bench scene's mesh moved there), with its
// camera at every size.
struct PreparedModel {
    BenchScene scene;
    std::shared_ptr<Renderer> renderer;
    std::vector<hsr_camera> cameras;  // one per size
};
// Throws hsr::Error naming the model; warn gets each of the loader's warnings.
PreparedModel prepare_model(const ModelSpec& spec, const std::vector<ImageSize>& sizes,
                            const std::function<void(const std::string&)>& warn);

// What one cell came to: a timing, or the reason there is none.
struct CellOutcome {
    Timing timing;                     // when measured
    std::string refused;               // see Result::refused
    std::string fault, fault_detail;   // see Result::fault
    bool measured() const { return refused.empty() && fault.empty(); }
};

// The warm-up and timed calls of one remover of `plugin` on the model at sizes[size], one after the
// other; before_call(i) runs before call i. An error from the plugin, or memory running out, is the
// outcome's refusal.
CellOutcome time_cell(const PreparedModel& model, std::size_t size, const Plugin& plugin,
                      const std::vector<Setting>& settings, LightingModel& lighting,
                      const TimingSettings& timing_settings, const std::function<void(unsigned)>& before_call);

}  // namespace hsr::bench
