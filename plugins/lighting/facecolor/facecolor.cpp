// facecolor: every visible pixel gets a flat colour of its face, unlit: the textbook way to look at
// the output of a hidden-surface algorithm, each polygon painted flat so that which face won at
// each pixel is plain to see. No lights, no normals. The colour is the scene's own (by=given), or
// one of a fixed palette per face (by=face: faces that share an edge always differ) or per object
// (by=object: each object, and each placed copy of one, in its own).
//
// The palette is Kenneth L. Kelly's sequence of colours of maximum contrast ("Twenty-two colors of
// maximum contrast", Color Engineering 3(6), 1965) without its white and black: 20 colours, each
// chosen to differ as much as possible from all before it, so that the first few are the most
// distinct. The sRGB values are the commonly used conversions of Kelly's ISCC-NBS centroid colours.
#include "hsr/sdk.hpp"
#include "hsr/shading.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace {

constexpr std::array<uint32_t, 20> kelly_palette = {
    0xFFB300, 0x803E75, 0xFF6800, 0xA6BDD7, 0xC10020, 0xCEA262, 0x817066, 0x007D34, 0xF6768E, 0x00538A,
    0xFF7A5C, 0x53377A, 0xFF8E00, 0xB32851, 0xF4C800, 0x7F180D, 0x93AA00, 0x593315, 0xF13A13, 0x232C16,
};

glm::vec3 palette_color(uint32_t k) {
    const uint32_t rgb = kelly_palette[k % kelly_palette.size()];
    return glm::vec3(float((rgb >> 16) & 0xFF), float((rgb >> 8) & 0xFF), float(rgb & 0xFF)) / 255.0f;
}

enum class ColorBy { kGiven = 0, kFace = 1, kObject = 2 };

class FaceColor final : public hsr::sdk::LightingModel {
public:
    static constexpr hsr::sdk::PluginInfo info{"facecolor", "1.1.0", "Each face in a flat colour, unlit"};
    static inline const std::array<hsr::sdk::ParamSpec, 1> params{
        hsr::sdk::ParamSpec::choice("by", "given", "given|face|object",
                                    "given: the scene's face colours; face: a palette colour per face, faces "
                                    "sharing an edge differ; object: a palette colour per object (and per placed "
                                    "copy)"),
    };

    static inline const hsr::sdk::TranslationSpec translations[] = {
        {"ru", "description", "каждая грань залита своим цветом, без освещения"},
        {"ru", "param:by", "цвет граней"},
        {"ru", "help:by",
         "из сцены — цвета граней, заданные в сцене; по граням — свой цвет палитры у каждой грани, грани с общим "
         "ребром всегда разного цвета; по объектам — свой цвет палитры у каждого объекта (и у каждой его "
         "размещённой копии)"},
        {"ru", "choice:by:given", "из сцены"},
        {"ru", "choice:by:face", "по граням"},
        {"ru", "choice:by:object", "по объектам"},
    };

    explicit FaceColor(const hsr::sdk::Params& p) : by_(ColorBy(p.choice("by"))) {}

    void prepare(const hsr::sdk::Scene& scene, const hsr_shading_context&) override {
        scene_.reset();
        const hsr_scene& raw = scene.raw();
        if (raw.struct_size < sizeof(hsr_scene))
            throw hsr::sdk::InvalidArgument("scene: struct_size " + std::to_string(raw.struct_size) +
                                            " is smaller than this plugin's " + std::to_string(sizeof(hsr_scene)));
        if (raw.triangle_count > 0 && raw.face_colors == nullptr)
            throw hsr::sdk::InvalidArgument("scene: face colours missing");
        if (by_ == ColorBy::kFace && raw.triangle_count > 0 && raw.edge_neighbors == nullptr)
            throw hsr::sdk::InvalidArgument("scene: edge neighbours missing (facecolor:by=face needs them)");
        if (by_ == ColorBy::kObject && raw.triangle_count > 0 && raw.face_object == nullptr)
            throw hsr::sdk::InvalidArgument("scene: face objects missing (facecolor:by=object needs them)");
        if (by_ == ColorBy::kFace) color_faces(scene);
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
        // One loop per mode, so that the mode is not decided per fragment.
        switch (by_) {
        case ColorBy::kGiven:
            fill(batch, [&](uint32_t f, uint32_t) { return hsr::shading::clamp01(scene_->face_color(f)); });
            break;
        case ColorBy::kFace:
            fill(batch, [&](uint32_t f, uint32_t) { return palette_color(face_palette_[f]); });
            break;
        case ColorBy::kObject: {
            const uint64_t objects = std::max(1u, scene_->object_count());
            const bool instanced = batch.instance != nullptr && scene_->instance_count() > 0;
            fill(batch, [&](uint32_t f, uint32_t i) {
                const uint64_t copy = instanced ? batch.instance[i] : 0;
                return palette_color(uint32_t((copy * objects + scene_->face_object(f)) % kelly_palette.size()));
            });
            break;
        }
        }
    }

private:
    // Writes color_of(face, fragment index) for every fragment of the batch.
    template <class ColorOf>
    void fill(hsr_fragment_batch& batch, ColorOf color_of) const {
        const uint32_t triangles = scene_->triangle_count();
        for (uint32_t i = 0; i < batch.count; ++i) {
            const uint32_t f = batch.face[i];
            if (f >= triangles)
                throw hsr::sdk::InvalidArgument("fragment batch: face index " + std::to_string(f) +
                                                " out of range (" + std::to_string(triangles) + " triangles)");
            const glm::vec3 c = color_of(f, i);
            batch.color[3 * size_t{i}] = c.x;
            batch.color[3 * size_t{i} + 1] = c.y;
            batch.color[3 * size_t{i} + 2] = c.z;
        }
    }

    // Greedy colouring in face order: each face takes the first palette entry, counting on from its
    // own index, that no already coloured edge neighbour has. A triangle has at most three
    // neighbours, so one of the 20 is always free.
    void color_faces(const hsr::sdk::Scene& scene) {
        const uint32_t n = scene.triangle_count();
        face_palette_.assign(n, 0);
        for (uint32_t t = 0; t < n; ++t) {
            uint32_t taken = 0;  // bit k: palette entry k is a neighbour's
            for (int e = 0; e < 3; ++e) {
                const int32_t other = scene.edge_neighbor(t, e);
                if (other >= 0 && uint32_t(other) < t) taken |= 1u << face_palette_[uint32_t(other)];
            }
            uint32_t k = t % kelly_palette.size();
            while (taken & (1u << k)) k = (k + 1) % kelly_palette.size();
            face_palette_[t] = uint8_t(k);
        }
    }

    ColorBy by_;
    std::vector<uint8_t> face_palette_;  // by=face: each face's palette entry
    std::optional<hsr::sdk::Scene> scene_;
};

}  // namespace

HSR_EXPORT_PLUGIN(FaceColor)
