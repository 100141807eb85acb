// A plugin that throws where its `throw-in` parameter says, to check that the SDK turns every
// exception into a status code and a message instead of letting it cross the C ABI.
#include "hsr/sdk.hpp"

#include <stdexcept>

class ThrowingRemover final : public hsr::sdk::HiddenSurfaceRemover {
public:
    static constexpr hsr::sdk::PluginInfo info{"throwing", "0.1.0", "throws on purpose (test plugin)"};
    static inline const hsr::sdk::ParamSpec params[] = {
        hsr::sdk::ParamSpec::choice("throw-in", "render", "create|render|nowhere", "where to throw"),
        hsr::sdk::ParamSpec::choice("what", "runtime-error", "runtime-error|invalid-argument|int|bad-alloc",
                                    "what to throw"),
    };
    explicit ThrowingRemover(const hsr::sdk::Params& p) : where_(p.choice("throw-in")), what_(p.choice("what")) {
        if (where_ == 0) throw_it();
    }
    void render(const hsr::sdk::Scene&, const hsr_camera&, hsr::sdk::VisibilityBuffer&,
                hsr::sdk::Counters& counters) override {
        counters.add("calls", 1);
        if (where_ == 1) throw_it();
    }

private:
    void throw_it() const {
        switch (what_) {
        case 0: throw std::runtime_error("deliberate failure inside the plugin");
        case 1: throw hsr::sdk::InvalidArgument("deliberate invalid argument");
        case 2: throw 42;
        default: throw std::bad_alloc();
        }
    }
    int where_, what_;
};

HSR_EXPORT_PLUGIN(ThrowingRemover)
