// simple-zbuffer: the plain depth buffer (Catmull 1974) in its shortest form on the SDK, the
// hidden-surface example of docs/writing-a-plugin.md. It draws the same pictures as the bundled
// zbuffer. With depth-test=false every triangle overwrites what is under it, so the last one drawn
// wins: the "before" picture that every hidden-surface algorithm improves on.
#include <hsr/raster.hpp>
#include <hsr/sdk.hpp>

#include <cstddef>
#include <cstdint>

namespace {

namespace raster = hsr::raster;

class SimpleZBuffer final : public hsr::sdk::HiddenSurfaceRemover {
public:
    static constexpr hsr::sdk::PluginInfo info{"simple-zbuffer", "1.0.0", "the shortest z-buffer on the SDK"};
    static inline const hsr::sdk::ParamSpec params[] = {
        hsr::sdk::ParamSpec::boolean("depth-test", true, "keep the nearest surface; false: the last one drawn wins"),
    };

    explicit SimpleZBuffer(const hsr::sdk::Params& p) : depth_test_(p.boolean("depth-test")) {}

    void render(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                hsr::sdk::Counters& counters) override {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        geometry_.begin_frame(scene.raw(), camera, /*cull_backfaces=*/false);

        float* const depth = target.depth();
        uint32_t* const face = target.face();
        float* const bary = target.bary();
        uint32_t* const instance = target.instance();  // NULL unless the scene has instances
        uint32_t* const tests = target.depth_tests();  // NULL unless the host wants the work map
        const size_t width = target.width();
        const bool depth_test = depth_test_;
        uint64_t tested = 0, written = 0;  // hot counts in locals, reported once at the end

        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            geometry_.place(placement);  // projects the vertices of this placement
            const uint32_t end = placement.first_triangle + placement.triangle_count;
            for (uint32_t t = placement.first_triangle; t < end; ++t) {
                geometry_.process(t, [&](const raster::TriangleSetup& s) {
                    raster::for_each_covered_pixel(s, [&](int32_t x, int32_t y, double i, double j) {
                        const size_t p = size_t(y) * width + size_t(x);
                        const float z = raster::depth_at(s, i, j);
                        if (depth_test) {
                            ++tested;
                            if (tests) ++tests[p];
                            if (!(z < depth[p])) return;  // something nearer is already there
                        }
                        ++written;
                        depth[p] = z;
                        face[p] = t;
                        if (instance) instance[p] = placement.instance;
                        const glm::vec2 b = raster::barycentrics_at(s, i, j);
                        bary[2 * p] = b.x;
                        bary[2 * p + 1] = b.y;
                    });
                });
            }
        }
        geometry_.stats().report(counters);
        counters.set("pixels-depth-tested", tested);
        counters.set("pixels-written", written);
    }

private:
    bool depth_test_;
    raster::GeometryStage geometry_;  // keeps its vertex buffers between frames
};

}  // namespace

HSR_EXPORT_PLUGIN(SimpleZBuffer)
