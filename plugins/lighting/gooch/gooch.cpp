// gooch: cool-to-warm tone shading for technical illustration, after A. Gooch, B. Gooch, P. Shirley
// and E. Cohen, "A Non-Photorealistic Lighting Model for Automatic Technical Illustration",
// SIGGRAPH 1998. Shape is shown by hue rather than by darkness: surfaces facing the light are warm
// (toward yellow), surfaces facing away are cool (toward blue), and no surface goes black, so black
// edge lines stay readable over every part of the model.
//
// With k_d the face colour, n the shading normal and l the unit vector toward the light:
//
//     k_cool = k_blue + alpha * k_d,   k_blue   = (0, 0, b)
//     k_warm = k_yellow + beta * k_d,  k_yellow = (y, y, 0)
//     t      = (1 + l.n) / 2
//     colour = t * k_warm + (1 - t) * k_cool
//
// The paper prints the blend with (1 + l.n)/2 weighting k_cool; its text and figures put the warm
// colour toward the light, which is what this model does, as do later accounts of it (Akenine-Moller
// et al., "Real-Time Rendering"). The paper's defaults are b = y = 0.4, alpha = 0.2, beta = 0.6.
// The paper lights with one light. With several, t is the mean of each light's t weighted by the
// light's brightness (intensity times the mean of its colour), so the colour stays a blend of k_cool
// and k_warm; with no light (or only dark ones), t = 1/2. Light colours tint only the optional
// highlight, the paper's white Phong highlight: colour += highlight * E * max(0, r.v)^shininess for
// each light with n.l > 0, E its colour times intensity, r = 2(n.l)n - l. The result is clamped to
// [0, 1].
#include <hsr/sdk.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace {

class Gooch final : public hsr::sdk::LightingModel {
public:
    static constexpr hsr::sdk::PluginInfo info{"gooch", "1.0.0",
                                               "Gooch cool-to-warm tone shading for technical illustration"};
    static inline const hsr::sdk::ParamSpec params[] = {
        hsr::sdk::ParamSpec::real("b", "0.4", 0, 1, "blue of the cool colour: k_blue = (0, 0, b)"),
        hsr::sdk::ParamSpec::real("y", "0.4", 0, 1, "yellow of the warm colour: k_yellow = (y, y, 0)"),
        hsr::sdk::ParamSpec::real("alpha", "0.2", 0, 1, "share of the face colour in the cool colour"),
        hsr::sdk::ParamSpec::real("beta", "0.6", 0, 1, "share of the face colour in the warm colour"),
        hsr::sdk::ParamSpec::real("highlight", "0", 0, 1, "strength of a Phong highlight (0: none)"),
        hsr::sdk::ParamSpec::real("shininess", "32", 1, 1000, "exponent of the highlight"),
        hsr::sdk::ParamSpec::boolean("two-sided", true, "light the back of a face seen from behind as its front"),
    };

    static inline const hsr::sdk::TranslationSpec translations[] = {
        {"ru", "description",
         "модель Гуча: тоновое затенение от холодного к тёплому для технических иллюстраций"},
        {"ru", "param:b", "синий в холодном цвете, b"},
        {"ru", "help:b", "синяя составляющая холодного цвета: k_blue = (0, 0, b)"},
        {"ru", "param:y", "жёлтый в тёплом цвете, y"},
        {"ru", "help:y", "жёлтая составляющая тёплого цвета: k_yellow = (y, y, 0)"},
        {"ru", "param:alpha", "доля цвета грани в холодном цвете, α"},
        {"ru", "help:alpha", "какая доля цвета грани входит в холодный цвет"},
        {"ru", "param:beta", "доля цвета грани в тёплом цвете, β"},
        {"ru", "help:beta", "какая доля цвета грани входит в тёплый цвет"},
        {"ru", "param:highlight", "яркость блика"},
        {"ru", "help:highlight", "яркость блика по Фонгу (0 — без блика)"},
        {"ru", "param:shininess", "показатель блеска"},
        {"ru", "help:shininess", "показатель степени блика"},
        {"ru", "param:two-sided", "двустороннее освещение"},
        {"ru", "help:two-sided", "освещать обратную сторону грани, видимую сзади, так же, как лицевую"},
    };

    explicit Gooch(const hsr::sdk::Params& p)
        : blue_(glm::vec3(0, 0, float(p.real("b")))),
          yellow_(glm::vec3(float(p.real("y")), float(p.real("y")), 0)),
          alpha_(float(p.real("alpha"))),
          beta_(float(p.real("beta"))),
          highlight_(float(p.real("highlight"))),
          shininess_(float(p.real("shininess"))),
          two_sided_(p.boolean("two-sided")) {}

    void prepare(const hsr::sdk::Scene& scene, const hsr_shading_context& context) override {
        prepared_ = false;
        if (context.struct_size < sizeof(hsr_shading_context))
            throw hsr::sdk::InvalidArgument("gooch: hsr_shading_context is smaller than this plugin's");
        scene_.emplace(scene);
        perspective_ = context.projection_type == HSR_PROJECTION_PERSPECTIVE;
        eye_ = glm::vec3(context.eye[0], context.eye[1], context.eye[2]);
        const glm::vec3 view_direction(context.view_direction[0], context.view_direction[1],
                                       context.view_direction[2]);
        if (!perspective_ && !(glm::length(view_direction) > 0))
            throw hsr::sdk::InvalidArgument("gooch: the orthographic view_direction has zero length");
        toward_viewer_ = perspective_ ? glm::vec3(0) : -glm::normalize(view_direction);

        read_lights(context);

        // k_cool and k_warm depend on the face colour only: once per face here, not per pixel.
        const uint32_t faces = scene.triangle_count();
        cool_.resize(faces);
        warm_minus_cool_.resize(faces);
        for (uint32_t t = 0; t < faces; ++t) {
            const glm::vec3 kd = scene.face_color(t);
            cool_[t] = blue_ + alpha_ * kd;
            warm_minus_cool_[t] = yellow_ + beta_ * kd - cool_[t];
        }
        rotations_.resize(scene.instance_count());
        for (uint32_t k = 0; k < scene.instance_count(); ++k) rotations_[k] = scene.placement(k).rotation;
        prepared_ = true;
    }

    void shade(hsr_fragment_batch& batch) const override {
        if (!prepared_) throw hsr::sdk::InvalidArgument("gooch: shade before a successful prepare");
        // A host never accepts a plugin newer than itself, so this only refuses a malformed call.
        if (batch.struct_size < sizeof(hsr_fragment_batch))
            throw hsr::sdk::InvalidArgument("gooch: hsr_fragment_batch is smaller than this plugin's");
        if (highlight_ > 0)
            shade_batch<true>(batch);
        else
            shade_batch<false>(batch);
    }

private:
    struct Light {
        glm::vec3 vector;    // directional: unit, toward the light; point: world position
        glm::vec3 radiance;  // colour * intensity, for the highlight
        float weight;        // share of the tone blend
        bool point;
    };

    void read_lights(const hsr_shading_context& context) {
        lights_.clear();
        point_lights_.clear();
        directional_sum_ = glm::vec3(0);
        float total = 0;
        for (uint32_t i = 0; i < context.light_count; ++i) {
            const hsr_light& light = *HSR_ELEMENT(hsr_light, context.lights, i);
            Light out;
            out.vector = glm::vec3(light.vector[0], light.vector[1], light.vector[2]);
            out.radiance = glm::vec3(light.color[0], light.color[1], light.color[2]) * light.intensity;
            out.weight = (out.radiance.r + out.radiance.g + out.radiance.b) / 3;
            out.point = light.type == HSR_LIGHT_POINT;
            if (!std::isfinite(out.weight) || out.weight < 0 || !std::isfinite(glm::dot(out.vector, out.vector)))
                throw hsr::sdk::InvalidArgument("gooch: light " + std::to_string(i) + " is not finite");
            if (!out.point) {
                if (!(glm::length(out.vector) > 0))
                    throw hsr::sdk::InvalidArgument("gooch: light " + std::to_string(i) + " has a zero direction");
                out.vector = glm::normalize(out.vector);
            }
            total += out.weight;
            lights_.push_back(out);
        }
        // The blend factor is linear in l.n, so the weighted directional lights add up to one vector.
        for (Light& light : lights_) {
            light.weight = total > 0 ? light.weight / total : 0;
            if (light.point)
                point_lights_.push_back(light);
            else
                directional_sum_ += light.weight * light.vector;
        }
    }

    template <bool kHighlight>
    void shade_batch(hsr_fragment_batch& batch) const {
        const uint32_t* instance = batch.instance;
        const auto faces = static_cast<uint32_t>(cool_.size());
        const auto instances = static_cast<uint32_t>(rotations_.size());
        for (uint32_t i = 0; i < batch.count; ++i) {
            const uint32_t face = batch.face[i];
            if (face >= faces)
                throw hsr::sdk::InvalidArgument("gooch: face index " + std::to_string(face) + " is out of range");
            const glm::vec3 p(batch.position[3 * i], batch.position[3 * i + 1], batch.position[3 * i + 2]);
            glm::vec3 n(batch.normal[3 * i], batch.normal[3 * i + 1], batch.normal[3 * i + 2]);
            const glm::vec3 toward_viewer = perspective_ ? eye_ - p : toward_viewer_;
            if (two_sided_) {
                // The face normal decides which side is seen, the same at every pixel of the face; the
                // interpolated normal near a silhouette may tilt away on its own and must not flip.
                glm::vec3 face_normal = scene_->face_normal(face);
                if (instance) {
                    if (instance[i] >= instances)
                        throw hsr::sdk::InvalidArgument("gooch: instance index " + std::to_string(instance[i]) +
                                                        " is out of range");
                    face_normal = rotations_[instance[i]] * face_normal;
                }
                if (glm::dot(face_normal, toward_viewer) < 0) n = -n;
            }
            float along = glm::dot(n, directional_sum_);
            for (const Light& light : point_lights_) {
                const glm::vec3 to_light = light.vector - p;
                const float distance = glm::length(to_light);
                if (distance > 0) along += light.weight * glm::dot(n, to_light) / distance;
            }
            const float t = 0.5f + 0.5f * along;
            glm::vec3 color = cool_[face] + t * warm_minus_cool_[face];
            if constexpr (kHighlight) {
                const float view_length = glm::length(toward_viewer);
                const glm::vec3 v = view_length > 0 ? toward_viewer / view_length : n;
                for (const Light& light : lights_) {
                    glm::vec3 l = light.vector;
                    if (light.point) {
                        const float distance = glm::length(l - p);
                        if (!(distance > 0)) continue;
                        l = (l - p) / distance;
                    }
                    const float n_dot_l = glm::dot(n, l);
                    if (n_dot_l <= 0) continue;
                    const float r_dot_v = glm::dot(2 * n_dot_l * n - l, v);
                    if (r_dot_v > 0) color += highlight_ * std::pow(r_dot_v, shininess_) * light.radiance;
                }
            }
            for (int k = 0; k < 3; ++k) batch.color[3 * i + k] = std::clamp(color[k], 0.0f, 1.0f);
        }
    }

    // Parameters.
    glm::vec3 blue_, yellow_;
    float alpha_, beta_, highlight_, shininess_;
    bool two_sided_;

    // What prepare builds for shade.
    bool prepared_ = false;
    std::optional<hsr::sdk::Scene> scene_;  // Scene has no empty state: absent before the first prepare
    bool perspective_ = true;
    glm::vec3 eye_{0}, toward_viewer_{0};
    std::vector<Light> lights_, point_lights_;
    glm::vec3 directional_sum_{0};
    std::vector<glm::vec3> cool_, warm_minus_cool_;
    std::vector<glm::mat3> rotations_;
};

}  // namespace

HSR_EXPORT_PLUGIN(Gooch)
