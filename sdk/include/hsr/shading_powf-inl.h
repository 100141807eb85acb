// powf(x, y) on SIMD lanes, bit-identical to glibc's powf on x86-64 where glibc runs its FMA
// variant (every CPU with AVX2 and FMA, i.e. every CPU that runs Highway's AVX2 or AVX-512 targets):
// the same double-precision operations, fused multiply-adds and tables. The algorithm is Szabolcs
// Nagy's from Arm's optimized-routines (glibc >= 2.28, sysdeps/ieee754/flt-32/e_powf.c):
//   log2(x) = k + log2(c) + log1p(z/c - 1)/ln2  (16-entry table of 1/c, log2 c; degree-5 polynomial)
//   2^(y log2 x) = 2^(j/32) * 2^r                (32-entry table of 2^(j/32); degree-3 polynomial)
// rounded once to float at the end. Lighting plugins use it for the specular exponent, so that SIMD
// shading gives the colours the scalar code (std::pow) gives. Only for x a positive normal float
// and y finite with y*log2(x) in range of the fast path or beyond it (overflow, underflow); callers
// send subnormal, infinite and NaN lanes to std::pow. Highway per-target header (re-included once
// per target by hwy/foreach_target.h).
#if defined(HSR_SHADING_POWF_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef HSR_SHADING_POWF_INL_H_
#undef HSR_SHADING_POWF_INL_H_
#else
#define HSR_SHADING_POWF_INL_H_
#endif

#include <hwy/highway.h>

#include <bit>
#include <cmath>
#include <cstdint>

// Defined where this target's vector pow equals the C library's powf bit for bit.
#undef HSR_EXACT_SIMD_POWF
#if HWY_NATIVE_FMA && HWY_ARCH_X86_64 && defined(__GLIBC__) && HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128
#if __GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 28)
#define HSR_EXACT_SIMD_POWF 1
#endif
#endif

HWY_BEFORE_NAMESPACE();
namespace hsr::shading::HWY_NAMESPACE {
#ifdef HSR_EXACT_SIMD_POWF
namespace hn = hwy::HWY_NAMESPACE;

namespace powf_data {
// glibc's __powf_log2_data (1/c, log2 c per table entry; polynomial) and __exp2f_data (2^(j/32)
// with j's bits taken out of the exponent; the shift that rounds to a multiple of 1/32; polynomial),
// as bit patterns.
alignas(64) inline constexpr uint64_t inverse_c[16] = {
    0x3ff661ec79f8f3beull, 0x3ff571ed4aaf883dull, 0x3ff49539f0f010b0ull, 0x3ff3c995b0b80385ull,
    0x3ff30d190c8864a5ull, 0x3ff25e227b0b8ea0ull, 0x3ff1bb4a4a1a343full, 0x3ff12358f08ae5baull,
    0x3ff0953f419900a7ull, 0x3ff0000000000000ull, 0x3fee608cfd9a47acull, 0x3feca4b31f026aa0ull,
    0x3feb2036576afce6ull, 0x3fe9c2d163a1aa2dull, 0x3fe886e6037841edull, 0x3fe767dcf5534862ull,
};
alignas(64) inline constexpr uint64_t log2_c[16] = {
    0xbfdefec65b963019ull, 0xbfdb0b6832d4fca4ull, 0xbfd7418b0a1fb77bull, 0xbfd39de91a6dcf7bull,
    0xbfd01d9bf3f2b631ull, 0xbfc97c1d1b3b7af0ull, 0xbfc2f9e393af3c9full, 0xbfb960cbbf788d5cull,
    0xbfaa6f9db6475fceull, 0x0000000000000000ull, 0x3fb338ca9f24f53dull, 0x3fc476a9543891baull,
    0x3fce840b4ac4e4d2ull, 0x3fd40645f0c6651cull, 0x3fd88e9c2c1b9ff8ull, 0x3fdce0a44eb17bccull,
};
alignas(64) inline constexpr uint64_t exp2_table[32] = {
    0x3ff0000000000000ull, 0x3fefd9b0d3158574ull, 0x3fefb5586cf9890full, 0x3fef9301d0125b51ull,
    0x3fef72b83c7d517bull, 0x3fef54873168b9aaull, 0x3fef387a6e756238ull, 0x3fef1e9df51fdee1ull,
    0x3fef06fe0a31b715ull, 0x3feef1a7373aa9cbull, 0x3feedea64c123422ull, 0x3feece086061892dull,
    0x3feebfdad5362a27ull, 0x3feeb42b569d4f82ull, 0x3feeab07dd485429ull, 0x3feea47eb03a5585ull,
    0x3feea09e667f3bcdull, 0x3fee9f75e8ec5f74ull, 0x3feea11473eb0187ull, 0x3feea589994cce13ull,
    0x3feeace5422aa0dbull, 0x3feeb737b0cdc5e5ull, 0x3feec49182a3f090ull, 0x3feed503b23e255dull,
    0x3feee89f995ad3adull, 0x3feeff76f2fb5e47ull, 0x3fef199bdd85529cull, 0x3fef3720dcef9069ull,
    0x3fef5818dcfba487ull, 0x3fef7c97337b9b5full, 0x3fefa4afa2a490daull, 0x3fefd0765b6e4540ull,
};
inline constexpr uint64_t log2_poly[5] = {0x3fd27616c9496e0bull, 0xbfd71969a075c67aull, 0x3fdec70a6ca7baddull,
                                          0xbfe7154748bef6c8ull, 0x3ff71547652ab82bull};
inline constexpr uint64_t exp2_shift = 0x42e8000000000000ull;  // 0x1.8p52 / 32
inline constexpr uint64_t exp2_poly[3] = {0x3fac6af84b912394ull, 0x3fcebfce50fac4f3ull, 0x3fe62e42ff0c52d6ull};
inline constexpr uint64_t overflow_bound = 0x405fffffffd1d571ull;  // 0x1.fffffffd1d571p+6
}  // namespace powf_data

// table[index[j]] in each lane j, loaded lane by lane (gather instructions are slow on some CPUs).
template <class D, class VI>
HWY_INLINE hn::Vec<D> LoadLanes(D d, const hn::TFromD<D>* table, VI index) {
    using T = hn::TFromD<D>;
    using I = hn::TFromV<VI>;
    HWY_ALIGN I lane_index[HWY_MAX_BYTES / sizeof(I)];
    HWY_ALIGN T lane_value[HWY_MAX_BYTES / sizeof(T)];
    hn::Store(index, hn::Rebind<I, D>(), lane_index);
    for (size_t j = 0; j < hn::Lanes(d); ++j) lane_value[j] = table[lane_index[j]];
    return hn::Load(d, lane_value);
}

// x^y for one half of a float vector, in doubles (DD: doubles as many as the half's floats).
template <class DD, class VI32Half, class VF32Half>
HWY_INLINE hn::Vec<DD> ExactPowfHalf(DD dd, VF32Half z_float, VI32Half k, VI32Half table_index, double y) {
    using namespace hn;
    const RebindToSigned<DD> di64;
    const RebindToUnsigned<DD> du64;
    auto constant = [&](uint64_t bits) { return Set(dd, std::bit_cast<double>(bits)); };
    const auto index = PromoteTo(di64, table_index);
    const auto inverse_c = LoadLanes(dd, reinterpret_cast<const double*>(powf_data::inverse_c), index);
    const auto log2_c = LoadLanes(dd, reinterpret_cast<const double*>(powf_data::log2_c), index);
    const auto z = PromoteTo(dd, z_float);
    // log2(x), the order and fusing of glibc's log2_inline.
    const auto r = MulAdd(z, inverse_c, Set(dd, -1.0));
    const auto y0 = Add(PromoteTo(dd, k), log2_c);
    const auto r2 = Mul(r, r);
    auto p_high = MulAdd(constant(powf_data::log2_poly[0]), r, constant(powf_data::log2_poly[1]));
    const auto p_mid = MulAdd(constant(powf_data::log2_poly[2]), r, constant(powf_data::log2_poly[3]));
    const auto r4 = Mul(r2, r2);
    auto q = MulAdd(constant(powf_data::log2_poly[4]), r, y0);
    q = MulAdd(p_mid, r2, q);
    const auto log2_x = MulAdd(p_high, r4, q);
    const auto y_log2_x = Mul(log2_x, Set(dd, y));
    // 2^(y log2 x), glibc's exp2_inline.
    const auto shift = constant(powf_data::exp2_shift);
    const auto shifted = Add(y_log2_x, shift);
    const auto ki = BitCast(du64, shifted);
    const auto s_index = BitCast(di64, And(ki, Set(du64, 31)));
    const auto t = Add(LoadLanes(du64, powf_data::exp2_table, s_index), ShiftLeft<47>(ki));
    const auto s = BitCast(dd, t);
    const auto rr = Sub(y_log2_x, Sub(shifted, shift));
    const auto zz = MulAdd(constant(powf_data::exp2_poly[0]), rr, constant(powf_data::exp2_poly[1]));
    const auto rr2 = Mul(rr, rr);
    auto result = MulAdd(constant(powf_data::exp2_poly[2]), rr, Set(dd, 1.0));
    result = Mul(MulAdd(zz, rr2, result), s);
    // |y log2 x| >= 126: glibc's overflow and underflow answers (the fast path holds in between).
    result = IfThenElse(Gt(y_log2_x, constant(powf_data::overflow_bound)), Set(dd, HUGE_VAL), result);
    // __math_may_uflowf: 0x1.4p-75f squared, rounded to float: the least subnormal 2^-149.
    result = IfThenElse(Lt(y_log2_x, Set(dd, -149.0)), Set(dd, 0x1p-149), result);
    result = IfThenElse(Le(y_log2_x, Set(dd, -150.0)), Zero(dd), result);
    return result;
}

// x^y in every lane; each x a positive normal float (see the file comment).
template <class DF>
HWY_INLINE hn::Vec<DF> ExactPowf(DF df, hn::Vec<DF> x, double y) {
    using namespace hn;
    const RebindToSigned<DF> di;
    const auto ix = BitCast(di, x);
    const auto tmp = Sub(ix, Set(di, 0x3f330000));
    const auto table_index = And(ShiftRight<19>(tmp), Set(di, 15));
    const auto top = And(tmp, Set(di, int32_t(0xff800000u)));
    const auto z = BitCast(df, Sub(ix, top));
    const auto k = ShiftRight<23>(top);
    const Half<DF> dh;
    const Rebind<double, decltype(dh)> dd;
    const auto low = ExactPowfHalf(dd, LowerHalf(dh, z), LowerHalf(k), LowerHalf(table_index), y);
    const auto high = ExactPowfHalf(dd, UpperHalf(dh, z), UpperHalf(Half<decltype(di)>(), k),
                                    UpperHalf(Half<decltype(di)>(), table_index), y);
    return Combine(df, DemoteTo(dh, high), DemoteTo(dh, low));
}
#endif  // HSR_EXACT_SIMD_POWF
}  // namespace hsr::shading::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard toggled per target
