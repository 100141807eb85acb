// normals: a lighting model that paints each pixel with its shading normal, mapped from [-1, 1] to
// [0, 1] per axis (x red, y green, z blue): the classic debugging view of a mesh's normals.
// The lighting example of docs/writing-a-plugin.md.
#include <hsr/sdk.hpp>

#include <algorithm>
#include <cmath>

class NormalsLighting final : public hsr::sdk::LightingModel {
public:
    static constexpr hsr::sdk::PluginInfo info{"normals", "1.0.0", "colour = shading normal (debug view)"};
    static inline const hsr::sdk::ParamSpec params[] = {
        hsr::sdk::ParamSpec::boolean("view-space", false, "normals relative to the camera instead of the world"),
    };

    explicit NormalsLighting(const hsr::sdk::Params& p) : view_space_(p.boolean("view-space")) {}

    void prepare(const hsr::sdk::Scene&, const hsr_shading_context& context) override {
        // An orthonormal camera basis, from the viewing direction and the world's up axis.
        forward_ = glm::normalize(glm::vec3(context.view_direction[0], context.view_direction[1],
                                            context.view_direction[2]));
        glm::vec3 up = std::abs(forward_.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
        right_ = glm::normalize(glm::cross(forward_, up));
        up_ = glm::cross(right_, forward_);
    }

    void shade(hsr_fragment_batch& batch) const override {
        for (uint32_t i = 0; i < batch.count; ++i) {
            glm::vec3 n(batch.normal[3 * i], batch.normal[3 * i + 1], batch.normal[3 * i + 2]);
            if (view_space_) n = {glm::dot(n, right_), glm::dot(n, up_), -glm::dot(n, forward_)};
            for (int k = 0; k < 3; ++k) batch.color[3 * i + k] = std::clamp(0.5f * n[k] + 0.5f, 0.0f, 1.0f);
        }
    }

private:
    bool view_space_;
    glm::vec3 forward_{0, 0, -1}, right_{1, 0, 0}, up_{0, 1, 0};
};

HSR_EXPORT_PLUGIN(NormalsLighting)
