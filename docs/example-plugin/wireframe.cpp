// wireframe: a hidden-line remover that hides nothing. Every requested edge is returned whole and
// visible, cut off where it passes behind the near plane: the hidden-line example of
// docs/writing-a-plugin.md, and the "before" picture that every hidden-line algorithm improves on.
#include <hsr/sdk.hpp>

#include <array>
#include <cstdint>

namespace {

class Wireframe final : public hsr::sdk::HiddenLineRemover {
public:
    static constexpr hsr::sdk::PluginInfo info{"wireframe", "1.0.0", "every requested edge, none hidden"};
    static inline const std::array<hsr::sdk::ParamSpec, 0> params{};

    explicit Wireframe(const hsr::sdk::Params&) {}

    void render_lines(const hsr::sdk::Scene& scene, const hsr_camera& camera, const hsr::sdk::LineRequest& request,
                      hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace,
                      hsr::sdk::Counters& counters) override {
        const glm::mat4 to_clip = hsr::sdk::load_matrix(camera.view_projection);
        const glm::vec2 size(camera.width, camera.height);
        uint64_t behind = 0;
        for (uint32_t e = 0; e < request.edge_count(); ++e) {
            if (trace.enabled()) trace.emit({.type = "edge-begin", .edge = e});
            glm::vec4 a = to_clip * glm::vec4(scene.position(request.vertex(e, 0)), 1.0f);
            glm::vec4 b = to_clip * glm::vec4(scene.position(request.vertex(e, 1)), 1.0f);
            // In clip space the near plane is z = -w, and what lies in front of it has z + w >= 0.
            // Cut the edge there before dividing by w: behind the eye, w is negative and the
            // division would throw the point to the other side of the picture.
            const float in_front_a = a.z + a.w, in_front_b = b.z + b.w;
            if (in_front_a < 0 && in_front_b < 0) {
                ++behind;
                continue;
            }
            if (in_front_a < 0) a += in_front_a / (in_front_a - in_front_b) * (b - a);
            if (in_front_b < 0) b += in_front_b / (in_front_b - in_front_a) * (a - b);
            segments.add(to_window(a, size), to_window(b, size), e, request.flags(e), /*qi=*/0);
        }
        counters.set("edges-behind-near-plane", behind);
    }

private:
    // Window coordinates: x right, y down, in pixels (abi.md section 10).
    static glm::vec2 to_window(glm::vec4 clip, glm::vec2 size) {
        return {(clip.x / clip.w + 1.0f) * 0.5f * size.x, (1.0f - clip.y / clip.w) * 0.5f * size.y};
    }
};

}  // namespace

HSR_EXPORT_PLUGIN(Wireframe)
