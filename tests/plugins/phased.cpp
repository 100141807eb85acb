// A plugin whose steps name its two phases in turn, "visit" and "write", with a theory page beside
// its library (tests/browser/fixtures/phased.md), so that the viewer's theory pane can be checked
// to mark the shown step's phase (tests/browser/theory.checks.mjs). It draws nothing.
#include "hsr/sdk.hpp"

#include <array>

class PhasedRemover final : public hsr::sdk::HiddenSurfaceRemover {
public:
    static constexpr hsr::sdk::PluginInfo info{"phased", "0.1.0", "steps in two phases, draws nothing (test plugin)"};
    static inline const std::array<hsr::sdk::ParamSpec, 0> params{};
    static inline const hsr::sdk::PhaseSpec phases[] = {{"visit", "visit a triangle"}, {"write", "write its pixels"}};
    explicit PhasedRemover(const hsr::sdk::Params&) {}
    void render(const hsr::sdk::Scene&, const hsr_camera&, hsr::sdk::VisibilityBuffer&, hsr::sdk::Counters&) override {}
    void render_steps(const hsr::sdk::Scene&, const hsr_camera&, hsr::sdk::VisibilityBuffer&, hsr::sdk::Counters&,
                      hsr::sdk::Steps& steps) {
        for (int i = 1; i <= 4; ++i) {
            steps.step({.type = "visit", .phase = "visit"}, steps.russian() ? "обход %d" : "visit %d", i);
            steps.step({.type = "write", .phase = "write"}, steps.russian() ? "запись %d" : "write %d", i);
        }
    }
};

HSR_EXPORT_PLUGIN(PhasedRemover)
