// facecolor: every visible pixel gets the colour of its face, unlit: the textbook way to look at the
// output of a hidden-surface algorithm, each polygon painted in its own flat colour so that which face
// won at each pixel is plain to see. No lights, no normals; no parameters.
#include "hsr/sdk.hpp"
#include "hsr/shading.hpp"

#include <array>
#include <optional>
#include <string>

namespace {

class FaceColor final : public hsr::sdk::LightingModel {
public:
    static constexpr hsr::sdk::PluginInfo info{"facecolor", "1.0.0", "Each face in its own scene colour, unlit"};
    static inline const std::array<hsr::sdk::ParamSpec, 0> params{};

    explicit FaceColor(const hsr::sdk::Params&) {}

    void prepare(const hsr::sdk::Scene& scene, const hsr_shading_context&) override {
        scene_.reset();
        const hsr_scene& raw = scene.raw();
        if (raw.struct_size < sizeof(hsr_scene))
            throw hsr::sdk::InvalidArgument("scene: struct_size " + std::to_string(raw.struct_size) +
                                            " is smaller than this plugin's " + std::to_string(sizeof(hsr_scene)));
        if (raw.triangle_count > 0 && raw.face_colors == nullptr)
            throw hsr::sdk::InvalidArgument("scene: face colours missing");
        scene_.emplace(scene);
    }

    void shade(hsr_fragment_batch& batch) const override {
        if (!scene_) throw hsr::sdk::InvalidArgument("shade() called before a successful prepare()");
        if (batch.struct_size < sizeof(hsr_fragment_batch))
            throw hsr::sdk::InvalidArgument("fragment batch: struct_size " + std::to_string(batch.struct_size) +
                                            " is smaller than this plugin's " + std::to_string(sizeof(hsr_fragment_batch)));
        if (batch.count == 0) return;
        if (batch.face == nullptr || batch.color == nullptr)
            throw hsr::sdk::InvalidArgument("fragment batch: face or color array is NULL");
        const uint32_t triangles = scene_->triangle_count();
        for (uint32_t i = 0; i < batch.count; ++i) {
            const uint32_t f = batch.face[i];
            if (f >= triangles)
                throw hsr::sdk::InvalidArgument("fragment batch: face index " + std::to_string(f) +
                                                " out of range (" + std::to_string(triangles) + " triangles)");
            const glm::vec3 c = hsr::shading::clamp01(scene_->face_color(f));
            batch.color[3 * size_t{i}] = c.x;
            batch.color[3 * size_t{i} + 1] = c.y;
            batch.color[3 * size_t{i} + 2] = c.z;
        }
    }

private:
    std::optional<hsr::sdk::Scene> scene_;
};

}  // namespace

HSR_EXPORT_PLUGIN(FaceColor)
