// Shared shading helpers for lighting plugins: the local reflection formulas (Lambert, Phong 1975,
// Blinn 1977) and ShadedLightingModel, which implements prepare() and the three interpolation modes
// (flat, Gouraud 1971, Phong 1975) once, so that a lighting plugin is a parameter list and one line
// naming its specular term:
//
//   class MyModel final : public hsr::shading::ShadedLightingModel<hsr::shading::BlinnPhongSpecular> {
//   public:
//       static constexpr hsr::sdk::PluginInfo info{"my-model", "1.0.0", "..."};
//       static inline const hsr::sdk::ParamSpec params[] = {
//           hsr::shading::param::interpolation("phong"), hsr::shading::param::ambient(), ...};
//       explicit MyModel(const hsr::sdk::Params& p)
//           : ShadedLightingModel(hsr::shading::read_material(p, true)) {}
//   };
//   HSR_EXPORT_PLUGIN(MyModel)
//
// Conventions (docs/lighting.md has the formulas):
//   colour = clamp(ka*C + sum over lights of E_l * (kd*C*max(0, N.L) + ks*S*spec(N, L, V)), 0, 1)
// with C the face colour, S the specular colour, E_l = light colour * intensity, spec = 0 unless
// N.L > 0. L is the unit vector from the surface point toward the light, V toward the viewer.
//
// Speed: per-fragment (Phong) interpolation, and every interpolation of an instanced scene, runs a
// SIMD kernel (hsr/shading_kernels-inl.h) compiled for every instruction set Google Highway targets
// and chosen at run time; its colours equal the scalar code's bit for bit (shade_phong_scalar,
// shade_instanced_scalar; tests/test_shading_simd.cpp checks every target). The host calls shade()
// on oneTBB's threads, up to 256 fragments of a band of rows per call, as many at once as --threads
// allows; prepare() computes flat and Gouraud colours in chunks on the same threads
// (hsr/parallel.hpp), bounded by the same --threads (docs/abi.md, section 7).
// One header of about 700 lines, because the formulas, the light environment and the model with its
// scalar references are what a plugin author reads together, and what the kernel must equal.
// Header-only and installed with the SDK; depends on abi.h, sdk.hpp, parallel.hpp, GLM, oneTBB and
// Highway (link hsr::sdk_simd; this header defines HWY_TARGET_INCLUDE, so a plugin that includes it
// uses foreach_target.h only in a file of its own).
#pragma once

#include "hsr/abi.h"
#include "hsr/parallel.hpp"
#include "hsr/sdk.hpp"
#include "hsr/specular_power.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hsr::shading {

// ------------------------------------------------------------------------------------------------
// Reflection formulas. All vectors unit length; l points toward the light, v toward the viewer.

// Lambert's cosine law: the diffuse factor max(0, N.L).
inline float lambert_term(glm::vec3 n, glm::vec3 l) { return std::max(0.0f, glm::dot(n, l)); }

// Mirror direction of l about n: R = 2 (N.L) N - L.
inline glm::vec3 mirror_direction(glm::vec3 n, glm::vec3 l) { return 2.0f * glm::dot(n, l) * n - l; }

// Phong (1975): (R.V)^shininess, zero when the light is behind the surface (N.L <= 0) or R.V <= 0.
inline float phong_specular(glm::vec3 n, glm::vec3 l, glm::vec3 v, float shininess) {
    if (glm::dot(n, l) <= 0.0f) return 0.0f;
    const float r_dot_v = glm::dot(mirror_direction(n, l), v);
    return r_dot_v > 0.0f ? specular_power(r_dot_v, shininess) : 0.0f;
}

// Blinn (1977): (N.H)^shininess with the half vector H = normalize(L + V); zero when N.L <= 0.
inline float blinn_phong_specular(glm::vec3 n, glm::vec3 l, glm::vec3 v, float shininess) {
    if (glm::dot(n, l) <= 0.0f) return 0.0f;
    const glm::vec3 sum = l + v;
    const float length_squared = glm::dot(sum, sum);
    if (length_squared <= 0.0f) return 0.0f;  // L = -V: no half vector
    const float n_dot_h = glm::dot(n, sum) / std::sqrt(length_squared);
    return n_dot_h > 0.0f ? specular_power(n_dot_h, shininess) : 0.0f;
}

// Specular terms as types, so ShadedLightingModel is compiled once per term and its per-fragment
// loops contain no indirect call.
enum class SpecularKind { none, phong, blinn };  // the SIMD kernel's names for the three below

struct NoSpecular {
    static constexpr bool has_specular = false;
    static constexpr SpecularKind kind = SpecularKind::none;
    float operator()(glm::vec3, glm::vec3, glm::vec3, float) const { return 0.0f; }
};
struct PhongSpecular {
    static constexpr bool has_specular = true;
    static constexpr SpecularKind kind = SpecularKind::phong;
    float operator()(glm::vec3 n, glm::vec3 l, glm::vec3 v, float shininess) const {
        return phong_specular(n, l, v, shininess);
    }
};
struct BlinnPhongSpecular {
    static constexpr bool has_specular = true;
    static constexpr SpecularKind kind = SpecularKind::blinn;
    float operator()(glm::vec3 n, glm::vec3 l, glm::vec3 v, float shininess) const {
        return blinn_phong_specular(n, l, v, shininess);
    }
};

inline glm::vec3 clamp01(glm::vec3 c) { return glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f)); }

// ------------------------------------------------------------------------------------------------
// Material and parameters

// Where the reflection model is evaluated. Values are the indices in "flat|gouraud|phong".
enum class Interpolation : int {
    flat = 0,     // once per face, at the centroid with the face normal
    gouraud = 1,  // once per corner (corner normal and position), colours interpolated
    phong = 2     // per fragment, with the interpolated normal
};

struct Material {
    float ambient = 0.1f;
    float diffuse = 0.8f;
    float specular = 0.0f;
    float shininess = 32.0f;
    glm::vec3 specular_color{1.0f};
    bool two_sided = true;
    Interpolation interpolation = Interpolation::phong;
};

// The parameter specs the lit models share; each plugin lists the ones it reads.
namespace param {
constexpr sdk::ParamSpec interpolation(const char* default_mode) {
    return sdk::ParamSpec::choice(
        "interpolation", default_mode, "flat|gouraud|phong",
        "flat: one colour per face; gouraud: colours at the corners interpolated; phong: normal "
        "interpolated, model evaluated per pixel");
}
constexpr sdk::ParamSpec ambient() {
    return sdk::ParamSpec::real("ambient", "0.1", 0.0, 1.0, "ambient coefficient ka (times the face colour)");
}
constexpr sdk::ParamSpec diffuse() {
    return sdk::ParamSpec::real("diffuse", "0.8", 0.0, 1.0, "diffuse coefficient kd (times the face colour)");
}
constexpr sdk::ParamSpec specular() {
    return sdk::ParamSpec::real("specular", "0.5", 0.0, 1.0, "specular coefficient ks");
}
constexpr sdk::ParamSpec shininess(const char* default_value) {
    return sdk::ParamSpec::real("shininess", default_value, 1.0, 1000.0,
                                "specular exponent n: larger is a smaller, sharper highlight");
}
constexpr sdk::ParamSpec specular_color() {
    return sdk::ParamSpec::color("specular-color", "1/1/1", "colour of the highlight");
}
constexpr sdk::ParamSpec two_sided() {
    return sdk::ParamSpec::boolean("two-sided", true,
                                   "light the back of a face as if it were the front (open meshes, inside views)");
}

// Their texts in Russian (ABI 1.6), to join with a plugin's own (sdk::join_translations): the
// diffuse set (interpolation, ambient, diffuse, two-sided) and the specular one (specular,
// shininess, specular-color).
inline constexpr std::array<sdk::TranslationSpec, 11> diffuse_translations{{
    {"ru", "param:interpolation", "затенение"},
    {"ru", "help:interpolation",
     "плоское — один цвет на грань; по Гуро — цвета, найденные в вершинах, интерполируются вдоль грани; по "
     "Фонгу — интерполируется нормаль, и модель вычисляется в каждом пикселе"},
    {"ru", "choice:interpolation:flat", "плоское"},
    {"ru", "choice:interpolation:gouraud", "по Гуро"},
    {"ru", "choice:interpolation:phong", "по Фонгу"},
    {"ru", "param:ambient", "коэффициент фонового освещения"},
    {"ru", "help:ambient", "коэффициент ka рассеянного фонового света (умножается на цвет грани)"},
    {"ru", "param:diffuse", "коэффициент диффузного отражения"},
    {"ru", "help:diffuse", "коэффициент kd диффузного отражения (умножается на цвет грани)"},
    {"ru", "param:two-sided", "двустороннее освещение"},
    {"ru", "help:two-sided",
     "освещать обратную сторону грани так же, как лицевую (для незамкнутых сеток и взгляда изнутри)"},
}};
inline constexpr std::array<sdk::TranslationSpec, 6> specular_translations{{
    {"ru", "param:specular", "коэффициент зеркального отражения"},
    {"ru", "help:specular", "коэффициент ks зеркального отражения"},
    {"ru", "param:shininess", "показатель блеска"},
    {"ru", "help:shininess", "показатель степени n зеркальной составляющей: чем он больше, тем блик меньше и резче"},
    {"ru", "param:specular-color", "цвет блика"},
    {"ru", "help:specular-color", "цвет зеркального блика"},
}};
}  // namespace param

// Reads the parameters above; with_specular = false for models without a specular term (they do
// not declare specular, shininess or specular-color).
inline Material read_material(const sdk::Params& p, bool with_specular) {
    Material m;
    m.ambient = static_cast<float>(p.real("ambient"));
    m.diffuse = static_cast<float>(p.real("diffuse"));
    if (with_specular) {
        m.specular = static_cast<float>(p.real("specular"));
        m.shininess = static_cast<float>(p.real("shininess"));
        m.specular_color = p.color("specular-color");
    }
    m.two_sided = p.boolean("two-sided");
    const int mode = p.choice("interpolation");
    if (mode < 0 || mode > 2) throw sdk::InvalidArgument("interpolation: unknown mode index " + std::to_string(mode));
    m.interpolation = static_cast<Interpolation>(mode);
    return m;
}

// ------------------------------------------------------------------------------------------------
// Lights and viewer, validated and pre-multiplied once per frame.

class LightEnvironment {
public:
    // Throws sdk::InvalidArgument for a malformed context.
    void set(const hsr_shading_context& context) {
        if (context.struct_size < sizeof(hsr_shading_context))
            throw sdk::InvalidArgument("shading context: struct_size " + std::to_string(context.struct_size) +
                                       " is smaller than this plugin's " + std::to_string(sizeof(hsr_shading_context)));
        if (context.light_count > 0 && context.lights == nullptr)
            throw sdk::InvalidArgument("shading context: light_count is " + std::to_string(context.light_count) +
                                       " but lights is NULL");
        directional_.clear();
        point_.clear();
        for (uint32_t i = 0; i < context.light_count; ++i) {
            const hsr_light& light = *HSR_ELEMENT(hsr_light, context.lights, i);
            const glm::vec3 vector{light.vector[0], light.vector[1], light.vector[2]};
            const glm::vec3 radiance =
                glm::vec3{light.color[0], light.color[1], light.color[2]} * light.intensity;
            if (!all_finite(vector) || !all_finite(radiance))
                throw sdk::InvalidArgument("light " + std::to_string(i) + ": non-finite vector, colour or intensity");
            if (light.type == HSR_LIGHT_DIRECTIONAL) {
                const float length = glm::length(vector);
                if (!(length > 0.0f))
                    throw sdk::InvalidArgument("light " + std::to_string(i) + ": directional light with a zero direction");
                directional_.push_back({vector / length, radiance});
            } else if (light.type == HSR_LIGHT_POINT) {
                point_.push_back({vector, radiance});
            } else {
                throw sdk::InvalidArgument("light " + std::to_string(i) + ": unknown light type " +
                                           std::to_string(static_cast<int>(light.type)));
            }
        }
        if (context.projection_type == HSR_PROJECTION_PERSPECTIVE) {
            perspective_ = true;
            eye_ = {context.eye[0], context.eye[1], context.eye[2]};
            if (!all_finite(eye_)) throw sdk::InvalidArgument("shading context: non-finite eye point");
        } else if (context.projection_type == HSR_PROJECTION_ORTHOGRAPHIC) {
            perspective_ = false;
            const glm::vec3 d{context.view_direction[0], context.view_direction[1], context.view_direction[2]};
            const float length = glm::length(d);
            if (!(length > 0.0f) || !all_finite(d))
                throw sdk::InvalidArgument("shading context: orthographic view_direction must be a non-zero vector");
            toward_viewer_ = -d / length;
        } else {
            throw sdk::InvalidArgument("shading context: unknown projection type " +
                                       std::to_string(static_cast<int>(context.projection_type)));
        }
    }

    // Unit vector from p toward the viewer (zero when p is the eye point itself).
    glm::vec3 view_vector(glm::vec3 p) const {
        if (!perspective_) return toward_viewer_;
        const glm::vec3 d = eye_ - p;
        const float length_squared = glm::dot(d, d);
        return length_squared > 0.0f ? d / std::sqrt(length_squared) : glm::vec3(0.0f);
    }

    // The reflected colour at point p with unit shading normal n and view vector v, clamped to [0, 1].
    template <class Specular>
    glm::vec3 reflect(const Material& m, Specular specular, glm::vec3 base, glm::vec3 p, glm::vec3 n,
                      glm::vec3 v) const {
        glm::vec3 diffuse_sum(0.0f);
        glm::vec3 specular_sum(0.0f);
        auto add = [&](glm::vec3 l, glm::vec3 radiance) {
            const float n_dot_l = glm::dot(n, l);
            if (n_dot_l <= 0.0f) return;
            diffuse_sum += radiance * n_dot_l;
            if constexpr (Specular::has_specular) specular_sum += radiance * specular(n, l, v, m.shininess);
        };
        for (const Directional& light : directional_) add(light.direction, light.radiance);
        for (const Point& light : point_) {
            const glm::vec3 to_light = light.position - p;
            const float length_squared = glm::dot(to_light, to_light);
            if (length_squared > 0.0f) add(to_light / std::sqrt(length_squared), light.radiance);
        }
        glm::vec3 color = base * (m.ambient + m.diffuse * diffuse_sum);
        if constexpr (Specular::has_specular) color += m.specular * m.specular_color * specular_sum;
        return clamp01(color);
    }

    // The lights as 6 floats each (direction or position, then radiance), for the SIMD kernel.
    const float* directional_data() const { return directional_.empty() ? nullptr : &directional_[0].direction.x; }
    uint32_t directional_count() const { return uint32_t(directional_.size()); }
    const float* point_data() const { return point_.empty() ? nullptr : &point_[0].position.x; }
    uint32_t point_count() const { return uint32_t(point_.size()); }
    bool perspective() const { return perspective_; }
    glm::vec3 eye() const { return eye_; }
    glm::vec3 toward_viewer() const { return toward_viewer_; }

private:
    struct Directional {
        glm::vec3 direction;  // unit, toward the light
        glm::vec3 radiance;   // colour * intensity
    };
    struct Point {
        glm::vec3 position;
        glm::vec3 radiance;
    };
    static_assert(sizeof(Directional) == 6 * sizeof(float) && sizeof(Point) == 6 * sizeof(float));
    static bool all_finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

    std::vector<Directional> directional_;
    std::vector<Point> point_;
    bool perspective_ = true;
    glm::vec3 eye_{0.0f};
    glm::vec3 toward_viewer_{0.0f, 0.0f, 1.0f};
};

// ------------------------------------------------------------------------------------------------
// SIMD: what the per-fragment kernel (hsr/shading_kernels-inl.h) needs of a model, one frame's worth.
// The kernel is compiled for every instruction set Highway targets and the best one the CPU has is
// chosen at run time (HWY_DYNAMIC_DISPATCH); all give the scalar code's colours bit for bit.

struct PhongKernelInput {
    const float* directional = nullptr;  // LightEnvironment::directional_data()
    uint32_t directional_count = 0;
    const float* point = nullptr;
    uint32_t point_count = 0;
    bool perspective = true;
    float eye[3] = {0, 0, 0};
    float toward_viewer[3] = {0, 0, 1};
    bool two_sided = true;
    SpecularKind specular = SpecularKind::none;
    float ambient = 0, diffuse = 0, shininess = 1;
    float specular_factor[3] = {0, 0, 0};  // ks * specular colour
    const float* face_normals = nullptr;   // the scene's
    const float* face_colors = nullptr;
    // Instanced scenes: each fragment's face normal as its instance turns it, 3 floats per fragment
    // of the batch, which then stand in for face_normals (the face colours stay per face).
    const float* fragment_face_normals = nullptr;
};

}  // namespace hsr::shading

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "hsr/shading_kernels-inl.h"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "hsr/shading_kernels-inl.h"

namespace hsr::shading {
HWY_EXPORT(ShadePhongFragments);

// Shades fragments [0, k) of the batch with the best SIMD kernel the CPU runs, k the largest
// multiple of its vector length <= count, and returns k (the caller shades the rest).
inline uint32_t shade_phong_simd(const PhongKernelInput& input, const hsr_fragment_batch& batch, uint32_t count) {
    return HWY_DYNAMIC_DISPATCH(ShadePhongFragments)(input, batch, count);
}

// ------------------------------------------------------------------------------------------------
// A complete lighting model: ambient + diffuse + Specular, with flat, Gouraud or Phong interpolation.
//
// Two-sided lighting: which side of a face the viewer sees is decided by the face normal (for a
// plane the sign of N_face.V is the same at every point of it); when the back is seen, the shading
// normal (face, corner or interpolated) is negated before the model is evaluated. Deciding by the
// face rather than by each interpolated normal keeps the three modes consistent and avoids flips
// inside a triangle near silhouettes.
template <class Specular>
class ShadedLightingModel : public sdk::LightingModel {
public:
    explicit ShadedLightingModel(const Material& material) : material_(material) {}

    void prepare(const sdk::Scene& scene, const hsr_shading_context& context) final {
        scene_.reset();
        const hsr_scene& raw = scene.raw();
        if (raw.struct_size < sizeof(hsr_scene))
            throw sdk::InvalidArgument("scene: struct_size " + std::to_string(raw.struct_size) +
                                       " is smaller than this plugin's " + std::to_string(sizeof(hsr_scene)));
        if (raw.triangle_count > 0 && (raw.positions == nullptr || raw.indices == nullptr ||
                                       raw.face_normals == nullptr || raw.corner_normals == nullptr ||
                                       raw.face_colors == nullptr))
            throw sdk::InvalidArgument("scene: positions, indices, normals or face colours missing");
        lights_.set(context);
        kernel_input_ = phong_kernel_input(raw);
        const uint32_t triangles = scene.triangle_count();
        uint32_t largest_index = 0;  // one pass the compiler vectorizes; the message only when needed
        for (size_t k = 0; k < 3 * size_t{triangles}; ++k) largest_index = std::max(largest_index, raw.indices[k]);
        for (uint32_t t = 0; largest_index >= scene.vertex_count() && t < triangles; ++t)
            for (int corner = 0; corner < 3; ++corner)
                if (scene.index(t, corner) >= scene.vertex_count())
                    throw sdk::InvalidArgument("scene: triangle " + std::to_string(t) + " refers to vertex " +
                                               std::to_string(scene.index(t, corner)) + " of " +
                                               std::to_string(scene.vertex_count()));

        face_color_.clear();
        corner_color_.clear();
        instance_transform_.clear();
        instance_rotation_.clear();
        if (scene.instance_count() > 0) {
            // Instanced (ABI 1.1): the same face lies in many places, lit differently in each, so
            // flat and Gouraud colours are worked out per fragment from its instance's placement
            // instead of per face here (storing them per face and instance could take gigabytes).
            for (uint32_t k = 0; k < scene.instance_count(); ++k) {
                const sdk::Placement placement = scene.placement(k);
                instance_transform_.push_back(placement.transform);
                instance_rotation_.push_back(placement.rotation);
            }
        } else if (material_.interpolation == Interpolation::flat) {
            // The model at each face's centroid with the face normal, shaded as fragments are.
            face_color_.resize(triangles);
            shade_points(scene, triangles, [&](uint32_t t, glm::vec3& position, glm::vec3& normal) {
                position = (scene.corner_position(t, 0) + scene.corner_position(t, 1) + scene.corner_position(t, 2)) / 3.0f;
                normal = scene.face_normal(t);
                return t;
            }, face_color_.data());
        } else if (material_.interpolation == Interpolation::gouraud) {
            // The model at each corner with the corner normal (the face normal decides the side).
            corner_color_.resize(3 * size_t{triangles});
            shade_points(scene, 3 * size_t{triangles}, [&](size_t k, glm::vec3& position, glm::vec3& normal) {
                const uint32_t t = uint32_t(k / 3);
                position = scene.corner_position(t, int(k % 3));
                normal = scene.corner_normal(t, int(k % 3));
                return t;
            }, corner_color_.data());
        }
        scene_.emplace(scene);
    }

    void shade(hsr_fragment_batch& batch) const final {
        if (!scene_) throw sdk::InvalidArgument("shade() called before a successful prepare()");
        if (batch.struct_size < sizeof(hsr_fragment_batch))
            throw sdk::InvalidArgument("fragment batch: struct_size " + std::to_string(batch.struct_size) +
                                       " is smaller than this plugin's " + std::to_string(sizeof(hsr_fragment_batch)));
        if (batch.count == 0) return;
        if (batch.face == nullptr || batch.color == nullptr || batch.bary == nullptr ||
            batch.position == nullptr || batch.normal == nullptr)
            throw sdk::InvalidArgument("fragment batch: face, bary, position, normal or color array is NULL");
        const bool instanced = batch.struct_size >= offsetof(hsr_fragment_batch, instance) + sizeof batch.instance &&
                               batch.instance != nullptr;
        if (instanced != !instance_transform_.empty())
            throw sdk::InvalidArgument(instanced ? "fragment batch has instance ids but the scene has no instances"
                                                 : "the scene has instances but the fragment batch has no instance ids");
        if (instanced) {
            shade_instanced(batch);
            return;
        }
        switch (material_.interpolation) {
        case Interpolation::flat: shade_flat(batch); break;
        case Interpolation::gouraud: shade_gouraud(batch); break;
        case Interpolation::phong: shade_phong(batch); break;
        }
    }

    const Material& material() const { return material_; }

private:
    // n, negated when two-sided lighting is on and the viewer sees the back of the face.
    glm::vec3 facing_normal(glm::vec3 n, glm::vec3 face_normal, glm::vec3 v) const {
        return material_.two_sided && glm::dot(face_normal, v) < 0.0f ? -n : n;
    }

    void check_face(uint32_t face) const {
        if (face >= scene_->triangle_count()) [[unlikely]]
            throw sdk::InvalidArgument("fragment batch: face index " + std::to_string(face) + " out of range (" +
                                       std::to_string(scene_->triangle_count()) + " triangles)");
    }

    static void store(float* out, glm::vec3 c) {
        out[0] = c.x;
        out[1] = c.y;
        out[2] = c.z;
    }

    void shade_flat(hsr_fragment_batch& batch) const {
        const glm::vec3* colors = face_color_.data();
        for (uint32_t i = 0; i < batch.count; ++i) {
            const uint32_t f = batch.face[i];
            check_face(f);
            store(batch.color + 3 * size_t{i}, colors[f]);
        }
    }

    void shade_gouraud(hsr_fragment_batch& batch) const {
        const glm::vec3* colors = corner_color_.data();
        for (uint32_t i = 0; i < batch.count; ++i) {
            const uint32_t f = batch.face[i];
            check_face(f);
            const float b1 = batch.bary[2 * size_t{i}];
            const float b2 = batch.bary[2 * size_t{i} + 1];
            const glm::vec3* c = colors + 3 * size_t{f};
            store(batch.color + 3 * size_t{i}, clamp01((1.0f - b1 - b2) * c[0] + b1 * c[1] + b2 * c[2]));
        }
    }

    // color[k] = the model at point k as shade_phong evaluates a fragment, for k < count;
    // point(k, position, normal) sets point k's position and shading normal and returns its face.
    // In chunks spread over the threads the host allows, each through the SIMD kernel and the scalar
    // loop as fragments go (a point's colour depends on that point alone).
    template <class Point>
    void shade_points(const sdk::Scene& scene, size_t count, Point point, glm::vec3* color) {
        constexpr size_t kChunk = 4096;
        const auto chunks = uint32_t((count + kChunk - 1) / kChunk);
        sdk::parallel_for_each(chunks, [&](uint32_t chunk) {
            PointArrays& arrays = point_arrays_.local();
            arrays.face.resize(kChunk);
            arrays.position.resize(3 * kChunk);
            arrays.normal.resize(3 * kChunk);
            const size_t first = chunk * kChunk;
            const uint32_t n = uint32_t(std::min(kChunk, count - first));
            for (uint32_t i = 0; i < n; ++i) {
                glm::vec3 position, normal;
                arrays.face[i] = point(first + i, position, normal);
                for (int k = 0; k < 3; ++k) {
                    arrays.position[3 * size_t{i} + k] = position[k];
                    arrays.normal[3 * size_t{i} + k] = normal[k];
                }
            }
            hsr_fragment_batch batch{};
            batch.struct_size = sizeof batch;
            batch.count = n;
            batch.face = arrays.face.data();
            batch.position = arrays.position.data();
            batch.normal = arrays.normal.data();
            batch.color = &color[first].x;
            const uint32_t done = shade_phong_simd(kernel_input_, batch, n);
            const Specular specular{};
            for (uint32_t i = done; i < n; ++i) {
                const float* pos = batch.position + 3 * size_t{i};
                const float* nrm = batch.normal + 3 * size_t{i};
                const glm::vec3 p{pos[0], pos[1], pos[2]};
                const glm::vec3 v = lights_.view_vector(p);
                const glm::vec3 nv = facing_normal({nrm[0], nrm[1], nrm[2]}, scene.face_normal(batch.face[i]), v);
                color[first + i] = lights_.reflect(material_, specular, scene.face_color(batch.face[i]), p, nv, v);
            }
        });
    }

    PhongKernelInput phong_kernel_input(const hsr_scene& raw) const {
        PhongKernelInput in;
        in.directional = lights_.directional_data();
        in.directional_count = lights_.directional_count();
        in.point = lights_.point_data();
        in.point_count = lights_.point_count();
        in.perspective = lights_.perspective();
        for (int k = 0; k < 3; ++k) {
            in.eye[k] = lights_.eye()[k];
            in.toward_viewer[k] = lights_.toward_viewer()[k];
            in.specular_factor[k] = (material_.specular * material_.specular_color)[k];
        }
        in.two_sided = material_.two_sided;
        in.specular = Specular::kind;
        in.ambient = material_.ambient;
        in.diffuse = material_.diffuse;
        in.shininess = material_.shininess;
        in.face_normals = raw.face_normals;
        in.face_colors = raw.face_colors;
        return in;
    }

    // The SIMD kernel takes whole vectors of fragments when every face index is valid; the scalar
    // loop takes the rest (and finds the bad index, if any).
    void shade_phong(hsr_fragment_batch& batch) const {
        uint32_t largest_face = 0;
        for (uint32_t i = 0; i < batch.count; ++i) largest_face = std::max(largest_face, batch.face[i]);
        const uint32_t done =
            largest_face < scene_->triangle_count() ? shade_phong_simd(kernel_input_, batch, batch.count) : 0;
        shade_phong_scalar(batch, done);
    }

public:
    // The scalar code the SIMD kernel equals bit for bit (tests compare them): fragments [first, count).
    void shade_phong_scalar(hsr_fragment_batch& batch, uint32_t first = 0) const {
        const sdk::Scene& scene = *scene_;
        const Specular specular{};
        for (uint32_t i = first; i < batch.count; ++i) {
            const uint32_t f = batch.face[i];
            check_face(f);
            const float* pos = batch.position + 3 * size_t{i};
            const float* nrm = batch.normal + 3 * size_t{i};
            const glm::vec3 p{pos[0], pos[1], pos[2]};
            const glm::vec3 v = lights_.view_vector(p);
            const glm::vec3 n = facing_normal({nrm[0], nrm[1], nrm[2]}, scene.face_normal(f), v);
            store(batch.color + 3 * size_t{i}, lights_.reflect(material_, specular, scene.face_color(f), p, n, v));
        }
    }

private:
    // Fragments of an instanced scene: positions and normals arrive in world space; face and corner
    // data are turned into world space with the fragment's instance. A block of fragments at a time:
    // their faces' normals (and, for flat and Gouraud, the points where the model is evaluated) are
    // carried into world space here, then the SIMD kernel shades whole vectors of them and the
    // scalar code the rest.
    void shade_instanced(hsr_fragment_batch& batch) const {
        constexpr uint32_t kBlock = 256;
        float face_normal[3 * kBlock], position[3 * kBlock], normal[3 * kBlock], color[3][3 * kBlock];
        PhongKernelInput in = kernel_input_;
        in.fragment_face_normals = face_normal;
        for (uint32_t first = 0; first < batch.count; first += kBlock) {
            const uint32_t n = std::min(kBlock, batch.count - first);
            for (uint32_t i = 0; i < n; ++i) {
                const uint32_t f = batch.face[first + i];
                check_face(f);
                const uint32_t k = batch.instance[first + i];
                if (k >= instance_transform_.size()) [[unlikely]]
                    throw sdk::InvalidArgument("fragment batch: instance " + std::to_string(k) + " out of range");
                store(face_normal + 3 * size_t{i}, instance_rotation_[k] * scene_->face_normal(f));
            }
            hsr_fragment_batch block{};
            block.struct_size = sizeof block;
            block.count = n;
            block.face = batch.face + first;
            block.position = batch.position + 3 * size_t{first};
            block.normal = batch.normal + 3 * size_t{first};
            float* out = batch.color + 3 * size_t{first};
            switch (material_.interpolation) {
            case Interpolation::flat: {  // the model at the centroid, with the face normal
                for (uint32_t i = 0; i < n; ++i) {
                    const uint32_t f = block.face[i];
                    store(position + 3 * size_t{i},
                          world(batch.instance[first + i], (scene_->corner_position(f, 0) + scene_->corner_position(f, 1) +
                                                            scene_->corner_position(f, 2)) / 3.0f));
                }
                block.position = position;
                block.normal = face_normal;
                block.color = out;
                shade_block(in, block);
                break;
            }
            case Interpolation::gouraud: {  // the model at each corner, weighted by the barycentrics
                for (int corner = 0; corner < 3; ++corner) {
                    for (uint32_t i = 0; i < n; ++i) {
                        const uint32_t f = block.face[i], k = batch.instance[first + i];
                        store(position + 3 * size_t{i}, world(k, scene_->corner_position(f, corner)));
                        store(normal + 3 * size_t{i}, instance_rotation_[k] * scene_->corner_normal(f, corner));
                    }
                    block.position = position;
                    block.normal = normal;
                    block.color = color[corner];
                    shade_block(in, block);
                }
                for (uint32_t i = 0; i < n; ++i) {
                    const float b1 = batch.bary[2 * size_t{first + i}], b2 = batch.bary[2 * size_t{first + i} + 1];
                    const float b[3] = {1.0f - b1 - b2, b1, b2};
                    glm::vec3 c(0.0f);
                    for (int corner = 0; corner < 3; ++corner) c += b[corner] * load(color[corner] + 3 * size_t{i});
                    store(out + 3 * size_t{i}, clamp01(c));
                }
                break;
            }
            case Interpolation::phong:
                block.color = out;
                shade_block(in, block);
                break;
            }
        }
    }

    // Point p of instance k in world space.
    glm::vec3 world(uint32_t k, glm::vec3 p) const { return glm::vec3(instance_transform_[k] * glm::vec4(p, 1.0f)); }

    static glm::vec3 load(const float* in) { return {in[0], in[1], in[2]}; }

    // The model at the points of `block` (world positions and shading normals, the face normals of
    // in.fragment_face_normals deciding the side): whole vectors by the kernel, the rest here.
    void shade_block(const PhongKernelInput& in, hsr_fragment_batch& block) const {
        const uint32_t done = shade_phong_simd(in, block, block.count);
        const Specular specular{};
        for (uint32_t i = done; i < block.count; ++i) {
            const glm::vec3 p = load(block.position + 3 * size_t{i});
            const glm::vec3 v = lights_.view_vector(p);
            const glm::vec3 n = facing_normal(load(block.normal + 3 * size_t{i}),
                                              load(in.fragment_face_normals + 3 * size_t{i}), v);
            store(block.color + 3 * size_t{i},
                  lights_.reflect(material_, specular, scene_->face_color(block.face[i]), p, n, v));
        }
    }

public:
    // The scalar code the instanced path equals bit for bit (tests compare them).
    void shade_instanced_scalar(hsr_fragment_batch& batch) const {
        const sdk::Scene& scene = *scene_;
        const Specular specular{};
        for (uint32_t i = 0; i < batch.count; ++i) {
            const uint32_t f = batch.face[i];
            check_face(f);
            const uint32_t k = batch.instance[i];
            if (k >= instance_transform_.size()) [[unlikely]]
                throw sdk::InvalidArgument("fragment batch: instance " + std::to_string(k) + " out of range");
            const glm::mat3& rotation = instance_rotation_[k];
            const glm::vec3 face_normal = rotation * scene.face_normal(f);
            const glm::vec3 base = scene.face_color(f);
            glm::vec3 color;
            switch (material_.interpolation) {
            case Interpolation::flat: {
                const glm::vec3 centroid =
                    world(k, (scene.corner_position(f, 0) + scene.corner_position(f, 1) + scene.corner_position(f, 2)) / 3.0f);
                const glm::vec3 v = lights_.view_vector(centroid);
                color = lights_.reflect(material_, specular, base, centroid, facing_normal(face_normal, face_normal, v), v);
                break;
            }
            case Interpolation::gouraud: {
                const float b[3] = {1.0f - batch.bary[2 * size_t{i}] - batch.bary[2 * size_t{i} + 1],
                                    batch.bary[2 * size_t{i}], batch.bary[2 * size_t{i} + 1]};
                color = glm::vec3(0.0f);
                for (int corner = 0; corner < 3; ++corner) {
                    const glm::vec3 p = world(k, scene.corner_position(f, corner));
                    const glm::vec3 v = lights_.view_vector(p);
                    const glm::vec3 n = facing_normal(rotation * scene.corner_normal(f, corner), face_normal, v);
                    color += b[corner] * lights_.reflect(material_, specular, base, p, n, v);
                }
                color = clamp01(color);
                break;
            }
            case Interpolation::phong: {
                const glm::vec3 p = load(batch.position + 3 * size_t{i});
                const glm::vec3 v = lights_.view_vector(p);
                const glm::vec3 n = facing_normal(load(batch.normal + 3 * size_t{i}), face_normal, v);
                color = lights_.reflect(material_, specular, base, p, n, v);
                break;
            }
            }
            store(batch.color + 3 * size_t{i}, color);
        }
    }

private:
    Material material_;
    LightEnvironment lights_;
    std::vector<glm::mat4> instance_transform_;  // instanced scenes: one per instance
    std::vector<glm::mat3> instance_rotation_;
    std::optional<sdk::Scene> scene_;     // set by a successful prepare()
    std::vector<glm::vec3> face_color_;   // flat: one per triangle
    std::vector<glm::vec3> corner_color_; // gouraud: three per triangle
    PhongKernelInput kernel_input_;
    struct PointArrays {  // prepare(): flat and Gouraud points, a chunk at a time on each thread
        std::vector<uint32_t> face;
        std::vector<float> position, normal;
    };
    sdk::PerThread<PointArrays> point_arrays_;
};

}  // namespace hsr::shading
