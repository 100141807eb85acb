// specular_power (hsr/specular_power.hpp) on SIMD lanes: the same float operations in the same
// order, so every lane gives the scalar function's bits on every instruction set. Highway
// per-target header (re-included once per target by hwy/foreach_target.h).
#if defined(HSR_SHADING_POWF_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef HSR_SHADING_POWF_INL_H_
#undef HSR_SHADING_POWF_INL_H_
#else
#define HSR_SHADING_POWF_INL_H_
#endif

#include "hsr/specular_power.hpp"

#include <hwy/highway.h>

#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace hsr::shading::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// specular_power(x, y) in every lane; each x > 0 finite.
template <class DF>
HWY_INLINE hn::Vec<DF> SpecularPowerLanes(DF df, hn::Vec<DF> x, float y) {
    using namespace hn;
    namespace d = detail::specular_power_constants;
    const RebindToSigned<DF> di;
    const auto subnormal = Lt(x, Set(df, d::smallest_normal));
    x = IfThenElse(subnormal, Mul(x, Set(df, 0x1p23f)), x);
    const auto exponent_bias = IfThenElseZero(subnormal, Set(df, -23.0f));
    const auto ix = BitCast(di, x);
    const auto e = ShiftRight<23>(Sub(ix, Set(di, int32_t(d::sqrt_half_bits))));
    const auto m = BitCast(df, Sub(ix, ShiftLeft<23>(e)));
    const auto f = Sub(m, Set(df, 1.0f));
    const auto f2 = Mul(f, f);
    auto p = Set(df, d::log_poly[0]);
    for (int k = 1; k < 9; ++k) p = Add(Mul(p, f), Set(df, d::log_poly[k]));
    const auto tail = Sub(Mul(Mul(p, f), f2), Mul(Set(df, 0.5f), f2));
    const auto log2e_minus_1 = Set(df, d::log2e_minus_1);
    auto log2_x = Mul(tail, log2e_minus_1);
    log2_x = Add(log2_x, Mul(f, log2e_minus_1));
    log2_x = Add(log2_x, tail);
    log2_x = Add(log2_x, f);
    log2_x = Add(log2_x, Add(ConvertTo(df, e), exponent_bias));

    auto t = Mul(Set(df, y), log2_x);
    t = IfThenElse(Lt(t, Set(df, -151.0f)), Set(df, -151.0f), t);
    t = IfThenElse(Gt(t, Set(df, 128.0f)), Set(df, 128.0f), t);
    const auto shift = Set(df, d::round_shift);
    const auto n = Sub(Add(t, shift), shift);
    const auto g = Sub(t, n);
    auto q = Set(df, d::exp2_poly[0]);
    for (int k = 1; k < 6; ++k) q = Add(Mul(q, g), Set(df, d::exp2_poly[k]));
    const auto two_to_g = Add(Set(df, 1.0f), Mul(g, q));
    const auto n_int = ConvertTo(di, n);
    const auto h = ShiftRight<1>(n_int);
    const auto bias = Set(di, 127);
    const auto scale_low = BitCast(df, ShiftLeft<23>(Add(h, bias)));
    const auto scale_high = BitCast(df, ShiftLeft<23>(Add(Sub(n_int, h), bias)));
    return Mul(Mul(two_to_g, scale_low), scale_high);
}

}  // namespace hsr::shading::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard toggled per target
