// The SIMD batch kernel of ShadedLightingModel (hsr/shading.hpp) for per-fragment (Phong)
// interpolation: the reflection model of LightEnvironment::reflect evaluated on as many fragments at
// once as a vector has float lanes. Every lane does the float operations of the scalar code in the
// same order (no fused multiply-adds; the build has -ffp-contract=off), comparisons and selects
// stand for its branches, and the specular power is specular_power's (shading_powf-inl.h), so the
// colours equal the scalar ones exactly. Highway per-target header
// (re-included once per target by hwy/foreach_target.h from hsr/shading.hpp).
#if defined(HSR_SHADING_KERNELS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef HSR_SHADING_KERNELS_INL_H_
#undef HSR_SHADING_KERNELS_INL_H_
#else
#define HSR_SHADING_KERNELS_INL_H_
#endif

#include "hsr/shading_powf-inl.h"

#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#ifndef HWY_INLINE_LAMBDA
#if defined(__GNUC__) || defined(__clang__)
#define HWY_INLINE_LAMBDA __attribute__((always_inline))
#else
#define HWY_INLINE_LAMBDA
#endif
#endif

HWY_BEFORE_NAMESPACE();
namespace hsr::shading::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// base^shininess in the lanes of `needed` (specular_power), zero in the others.
template <class DF>
HWY_INLINE hn::Vec<DF> SpecularPower(DF df, hn::Vec<DF> base, hn::Mask<DF> needed, float shininess) {
    using namespace hn;
    if (AllFalse(df, needed)) return Zero(df);
    // Lanes not needed compute 1^n.
    const auto x = IfThenElse(needed, base, Set(df, 1.0f));
    return IfThenElseZero(needed, SpecularPowerLanes(df, x, shininess));
}

// The colours of fragments [0, k) of `batch`, k the largest multiple of the vector's lane count
// <= count; returns k. Every face index is already checked. Directional and point lights are 6 floats each: the unit
// direction toward the light (directional) or the position (point), then the radiance.
HWY_NOINLINE uint32_t ShadePhongFragments(const PhongKernelInput& in, const hsr_fragment_batch& batch,
                                          uint32_t count) {
    using namespace hn;
    const ScalableTag<float> df;
    const size_t lanes = Lanes(df);
    const auto zero = Zero(df);
    const auto one = Set(df, 1.0f);
    const uint32_t vector_count = count - count % uint32_t(lanes);
    // Each fragment's face normal and colour, copied lane by lane into columns a block at a time
    // (gathers are slow on some CPUs; a vector load right after its lanes' stores would wait for them).
    constexpr uint32_t kBlock = HWY_MAX_BYTES / sizeof(float) > 64 ? uint32_t(HWY_MAX_BYTES / sizeof(float)) : 64;
    constexpr uint32_t kPrefetchDistance = 24;
    HWY_ALIGN float face_data[6][kBlock];
    for (uint32_t i = 0; i < vector_count; i += uint32_t(lanes)) {
        const uint32_t j = i % kBlock;
        if (j == 0) {
            const uint32_t block = std::min(kBlock, vector_count - i);
            const bool with_normals = in.fragment_face_normals == nullptr;
            for (uint32_t b = 0; b < block; ++b) {
                // Fragments come in screen order, not in the order of the face arrays: ask ahead.
                if (i + b + kPrefetchDistance < count) {
                    const size_t ahead = 3 * size_t{batch.face[i + b + kPrefetchDistance]};
                    if (with_normals) hwy::Prefetch(in.face_normals + ahead);
                    hwy::Prefetch(in.face_colors + ahead);
                }
                const size_t f3 = 3 * size_t{batch.face[i + b]};
                for (int k = 0; k < 3; ++k) {
                    if (with_normals) face_data[k][b] = in.face_normals[f3 + k];
                    face_data[3 + k][b] = in.face_colors[f3 + k];
                }
            }
        }
        Vec<decltype(df)> px, py, pz, nx, ny, nz;
        LoadInterleaved3(df, batch.position + 3 * size_t{i}, px, py, pz);
        LoadInterleaved3(df, batch.normal + 3 * size_t{i}, nx, ny, nz);
        Vec<decltype(df)> fx, fy, fz;
        if (in.fragment_face_normals == nullptr) {
            fx = Load(df, face_data[0] + j);
            fy = Load(df, face_data[1] + j);
            fz = Load(df, face_data[2] + j);
        } else {
            LoadInterleaved3(df, in.fragment_face_normals + 3 * size_t{i}, fx, fy, fz);
        }

        // View vector (LightEnvironment::view_vector).
        Vec<decltype(df)> vx, vy, vz;
        if (in.perspective) {
            const auto dx = Sub(Set(df, in.eye[0]), px);
            const auto dy = Sub(Set(df, in.eye[1]), py);
            const auto dz = Sub(Set(df, in.eye[2]), pz);
            const auto length_squared = Add(Add(Mul(dx, dx), Mul(dy, dy)), Mul(dz, dz));
            const auto has_length = Gt(length_squared, zero);
            const auto length = Sqrt(length_squared);
            vx = IfThenElseZero(has_length, Div(dx, length));
            vy = IfThenElseZero(has_length, Div(dy, length));
            vz = IfThenElseZero(has_length, Div(dz, length));
        } else {
            vx = Set(df, in.toward_viewer[0]);
            vy = Set(df, in.toward_viewer[1]);
            vz = Set(df, in.toward_viewer[2]);
        }

        // Two-sided: negate n where the viewer sees the back of the face.
        if (in.two_sided) {
            const auto back = Lt(Add(Add(Mul(fx, vx), Mul(fy, vy)), Mul(fz, vz)), zero);
            nx = IfThenElse(back, Neg(nx), nx);
            ny = IfThenElse(back, Neg(ny), ny);
            nz = IfThenElse(back, Neg(nz), nz);
        }

        auto diffuse_r = zero, diffuse_g = zero, diffuse_b = zero;
        auto specular_r = zero, specular_g = zero, specular_b = zero;
        // Inlined: called once per light, it updates six sums that would otherwise live in memory.
        auto add = [&](auto lit, auto lx, auto ly, auto lz, const float* radiance) HWY_INLINE_LAMBDA {
            const auto n_dot_l = Add(Add(Mul(nx, lx), Mul(ny, ly)), Mul(nz, lz));
            lit = And(lit, Not(Le(n_dot_l, zero)));
            if (AllFalse(df, lit)) return;
            const auto er = Set(df, radiance[0]), eg = Set(df, radiance[1]), eb = Set(df, radiance[2]);
            diffuse_r = IfThenElse(lit, Add(diffuse_r, Mul(er, n_dot_l)), diffuse_r);
            diffuse_g = IfThenElse(lit, Add(diffuse_g, Mul(eg, n_dot_l)), diffuse_g);
            diffuse_b = IfThenElse(lit, Add(diffuse_b, Mul(eb, n_dot_l)), diffuse_b);
            if (in.specular == SpecularKind::none) return;
            Vec<decltype(df)> base;
            Mask<decltype(df)> needed;
            if (in.specular == SpecularKind::blinn) {  // blinn_phong_specular
                const auto sx = Add(lx, vx), sy = Add(ly, vy), sz = Add(lz, vz);
                const auto sum_squared = Add(Add(Mul(sx, sx), Mul(sy, sy)), Mul(sz, sz));
                base = Div(Add(Add(Mul(nx, sx), Mul(ny, sy)), Mul(nz, sz)), Sqrt(sum_squared));
                needed = And(And(lit, Not(Le(sum_squared, zero))), Gt(base, zero));
            } else {  // phong_specular: R = 2 (N.L) N - L
                const auto twice = Mul(Set(df, 2.0f), n_dot_l);
                const auto rx = Sub(Mul(twice, nx), lx), ry = Sub(Mul(twice, ny), ly), rz = Sub(Mul(twice, nz), lz);
                base = Add(Add(Mul(rx, vx), Mul(ry, vy)), Mul(rz, vz));
                needed = And(lit, Gt(base, zero));
            }
            const auto power = SpecularPower(df, base, needed, in.shininess);
            specular_r = IfThenElse(lit, Add(specular_r, Mul(er, power)), specular_r);
            specular_g = IfThenElse(lit, Add(specular_g, Mul(eg, power)), specular_g);
            specular_b = IfThenElse(lit, Add(specular_b, Mul(eb, power)), specular_b);
        };
        const auto all = Eq(zero, zero);
        for (uint32_t k = 0; k < in.directional_count; ++k) {
            const float* light = in.directional + 6 * size_t{k};
            add(all, Set(df, light[0]), Set(df, light[1]), Set(df, light[2]), light + 3);
        }
        for (uint32_t k = 0; k < in.point_count; ++k) {
            const float* light = in.point + 6 * size_t{k};
            const auto tx = Sub(Set(df, light[0]), px);
            const auto ty = Sub(Set(df, light[1]), py);
            const auto tz = Sub(Set(df, light[2]), pz);
            const auto length_squared = Add(Add(Mul(tx, tx), Mul(ty, ty)), Mul(tz, tz));
            const auto length = Sqrt(length_squared);
            add(Gt(length_squared, zero), Div(tx, length), Div(ty, length), Div(tz, length), light + 3);
        }

        // colour = C (ka + kd D) + (ks S) P, clamped to [0, 1] as glm::clamp does (NaN stays NaN).
        const auto ambient = Set(df, in.ambient), diffuse = Set(df, in.diffuse);
        auto color = [&](const float* face_color, const auto& diffuse_sum, const auto& specular_sum,
                         float specular_factor) {
            const auto base = Load(df, face_color);
            auto c = Mul(base, Add(ambient, Mul(diffuse, diffuse_sum)));
            if (in.specular != SpecularKind::none) c = Add(c, Mul(Set(df, specular_factor), specular_sum));
            c = IfThenElse(Lt(c, zero), zero, c);
            return IfThenElse(Lt(one, c), one, c);
        };
        StoreInterleaved3(color(face_data[3] + j, diffuse_r, specular_r, in.specular_factor[0]),
                          color(face_data[4] + j, diffuse_g, specular_g, in.specular_factor[1]),
                          color(face_data[5] + j, diffuse_b, specular_b, in.specular_factor[2]), df,
                          batch.color + 3 * size_t{i});
    }
    return vector_count;
}

}  // namespace hsr::shading::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard toggled per target
