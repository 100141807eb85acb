// One cell of hsr bench's study, timed here (bench_cell.hpp).
#include "bench/bench_cell.hpp"

#include "hsr/error.hpp"
#include "hsr/pipeline.hpp"

#include <new>

namespace hsr::bench {

PreparedModel prepare_model(const ModelSpec& spec, const std::vector<ImageSize>& sizes,
                            const std::function<void(const std::string&)>& warn) {
    PreparedModel model{load_bench_scene(spec), {}, {}};
    model.renderer = std::make_shared<Renderer>(LoadedScene::of(std::move(model.scene.scene)));
    for (const std::string& w : model.renderer->loaded().scene().warnings) warn(w);
    for (const auto& [width, height] : sizes)
        model.cameras.push_back(make_bench_camera(*model.renderer, model.scene, width, height));
    return model;
}

CellOutcome time_cell(const PreparedModel& model, std::size_t size, const Plugin& plugin,
                      const std::vector<Setting>& settings, LightingModel& lighting,
                      const TimingSettings& timing_settings, const std::function<void(unsigned)>& before_call) {
    const hsr_scene view = model.renderer->loaded().scene().view();
    const hsr_camera& camera = model.cameras.at(size);
    const std::vector<hsr_light> lights = model.renderer->lights({}, camera);
    const hsr_shading_context context = make_shading_context(camera, lights);
    CellOutcome outcome;
    try {
        // One remover for all the calls, so that its caches persist, as in an application drawing
        // frame after frame.
        HiddenSurfaceRemover remover(plugin, settings);
        FrameTimer timer(view, camera, remover, lighting, context, timing_settings);
        for (unsigned call = 0; call < timing_settings.warmup + timing_settings.repetitions; ++call) {
            if (before_call) before_call(call);
            timer.call();
        }
        outcome.timing = timer.timing();
    } catch (const Error& e) {
        outcome.refused = e.what();
    } catch (const std::bad_alloc&) {
        outcome.refused = "out of memory";
    }
    return outcome;
}

}  // namespace hsr::bench
