// zbuffer: the plain depth buffer (Catmull, "A Subdivision Algorithm for Computer Display of Curved
// Surfaces", PhD thesis, University of Utah, 1974). Triangles are drawn one after another in scene
// order; every covered pixel centre compares the triangle's depth with the depth stored for that
// pixel and keeps the nearer (or, with depth-test=greater, the farther) surface.
//
// Rasterization uses the shared helpers of hsr/raster.hpp: near/far and guard-band clipping in
// homogeneous clip space, integer edge functions (Pineda 1988) on a 1/256-pixel grid with the
// top-left fill rule, and perspective-correct barycentrics computed only for pixels that pass the
// depth test. docs/algorithms/zbuffer.md describes the steps and the counters.
#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace {

namespace raster = hsr::raster;
using hsr::sdk::ParamSpec;

class ZBuffer final : public hsr::sdk::StepwiseRemover<ZBuffer> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "zbuffer", "1.0.0", "plain z-buffer (Catmull 1974): per-triangle edge-function rasterization"};
    static inline const ParamSpec params[] = {
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::choice("depth-test", "less", "less|greater",
                          "keep the nearest surface (less) or the farthest one (greater)"),
    };

    explicit ZBuffer(const hsr::sdk::Params& p)
        : cull_backfaces_(p.boolean("cull-backfaces")), keep_farthest_(p.choice("depth-test") == 1) {}

    // render_steps (from StepwiseRemover) takes one step per input triangle, in drawing order.

private:
    struct PixelStats {
        uint64_t depth_tested = 0;
        uint64_t written = 0;
    };

    friend class hsr::sdk::StepwiseRemover<ZBuffer>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        geometry_.begin_frame(scene.raw(), camera, cull_backfaces_);

        const size_t pixel_count = size_t(target.width()) * target.height();
        PixelStats pixels;
        auto finish = [&] {
            if (keep_farthest_) {
                // Uncovered pixels go back to the buffer's "nothing here" depth.
                float* depth = target.depth();
                const uint32_t* face = target.face();
                for (size_t p = 0; p < pixel_count; ++p)
                    if (face[p] == HSR_NO_FACE) depth[p] = std::numeric_limits<float>::infinity();
            }
            geometry_.stats().report(counters);
            counters.set("pixels-depth-tested", pixels.depth_tested);
            counters.set("pixels-written", pixels.written);
        };
        try {
            if (keep_farthest_) {
                // The host clears depth to +infinity; keeping the farthest surface needs -infinity.
                std::fill_n(target.depth(), pixel_count, -std::numeric_limits<float>::infinity());
                draw<false>(scene, target, pixels, steps);
            } else {
                draw<true>(scene, target, pixels, steps);
            }
        } catch (const hsr::sdk::StepLimitReached&) {
            finish();
            throw;
        }
        finish();
    }

    template <bool kKeepNearest, class Steps>
    void draw(const hsr::sdk::Scene& scene, hsr::sdk::VisibilityBuffer& target, PixelStats& pixels, Steps& steps) {
        if (target.depth_tests() == nullptr)
            draw<kKeepNearest, false>(scene, target, pixels, steps);
        else
            draw<kKeepNearest, true>(scene, target, pixels, steps);
    }

    template <bool kKeepNearest, bool kCountTests, class Steps>
    void draw(const hsr::sdk::Scene& scene, hsr::sdk::VisibilityBuffer& target, PixelStats& pixels, Steps& steps) {
        constexpr raster::DepthRule rule = kKeepNearest ? raster::DepthRule::kNearer : raster::DepthRule::kFarther;
        const raster::PixelBuffers buffers(target);
        const uint32_t* indices = scene.raw().indices;
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            geometry_.place(placement);
            const uint32_t end = placement.first_triangle + placement.triangle_count;
            for (uint32_t t = placement.first_triangle; t < end; ++t) {
                const raster::TriangleStats before = geometry_.stats();
                const PixelStats pixels_before = pixels;
                geometry_.process(t, [&](const raster::TriangleSetup& s) {
                    raster::DepthTest<rule, kCountTests> test(buffers, t, placement.instance);
                    raster::for_each_covered_pixel(s, [&](int32_t x, int32_t y, double i, double j) { test(s, x, y, i, j); });
                    pixels.depth_tested += test.tested;
                    pixels.written += test.written;
                });
                if constexpr (Steps::enabled) geometry_.outline_lines(steps, indices + 3 * size_t(t));
                raster::triangle_step(steps, before, geometry_.stats(), t, placement.instance,
                                      pixels.depth_tested - pixels_before.depth_tested,
                                      pixels.written - pixels_before.written);
            }
        }
    }

    bool cull_backfaces_;
    bool keep_farthest_;
    raster::GeometryStage geometry_;  // keeps its vertex buffers between frames
};

}  // namespace

HSR_EXPORT_PLUGIN(ZBuffer)
