// The specular power x^y of the lighting models (x > 0 the cosine of Phong's R.V or Blinn's N.H,
// y the shininess, 1 to 1000), in single precision, cheaper than the C library's powf and close
// enough that no 8-bit colour channel moves by more than 1:
//   x^y = 2^(y log2 x), x = 2^e m with m in [sqrt(1/2), sqrt(2)), f = m - 1 (exact),
//   log2 m = (f - f^2/2 + f^3 P8(f)) log2(e)                  (Cephes' log2f: Moshier 1984-2000),
//   2^t = 2^n 2^g, n = t rounded to an integer, |g| <= 1/2, 2^g = 1 + g P5(g)  (Cephes' exp2f).
// Every step is a float addition, multiplication, comparison or bit operation, without fused
// multiply-adds (the build has -ffp-contract=off), so the Highway kernel's copy of it
// (shading_powf-inl.h) gives the same bits on every instruction set.
//
// The bound. Over every float x in (0, 1 + 2^-10] and the exponents 1, 7.3, 32, 64, 150, 500.5
// and 1000, against x^y in double precision:
//   |specular_power(x, y) - x^y| <= eps x^y + 2^-149,  eps = kSpecularPowerRelativeError = 2e-5;
// the largest relative error found is 1.36e-5 (y = 500.5; 1.2e-5 on every 61st float for nine other
// exponents from 1.5 to 999). tests/test_specular_power.cpp checks it on 18 million bases per
// exponent. The relative part is mostly the rounding of t = y log2 x to float (|t| up to 151 before
// the result rounds to 0: 151 * 2^-24 in the exponent, 6e-6 of the result) and the relative error of
// log2 x carried into t; the absolute part is the rounding of results below 2^-126 to subnormals.
//
// Why no channel moves by more than 1 against std::pow (glibc's powf, within 1 ulp, 6e-8, of x^y).
// A channel is clamp(a, 0, 1) with a = d + s, d >= 0 the ambient and diffuse part and
// s = ks * sum of E_l * x_l^y >= 0 the specular part (materials and lights are non-negative). With
// every power off by at most a relative e = eps + 6e-8 (and 2^-149 absolute), a moves to a' with
// |a' - a| <= e * s + ks * sum E_l * 2^-149, plus the float roundings of the few operations after
// the power (a relative 2^-24 each, under 1e-6 of a). If a <= 1 that is below e + 1e-6; if a > 1,
// a' >= a (1 - e - 1e-6), so clamp(a') is within e + 1e-6 of 1. Either way the clamped value moves
// by less than delta = 2.2e-5 (for light radiance below 1e30). A byte is floor(255 v + 1/2): values
// less than 1/255 apart give bytes at most 1 apart, and 255 delta = 0.006. So a channel changes by
// at most 1, and only where 255 v lies within 0.006 of a rounding boundary (none of the 220,000
// channels that highlights decide in the test's pictures moved).
// Header-only and installed with the SDK (used by hsr/shading.hpp).
#pragma once

#include <bit>
#include <cstdint>

namespace hsr::shading {

// The bound of the relative error (see above), with room: the largest measured is 1.36e-5.
inline constexpr double kSpecularPowerRelativeError = 2e-5;

namespace detail::specular_power_constants {
inline constexpr uint32_t sqrt_half_bits = 0x3f3504f3u;  // sqrt(1/2), the bottom of m's range
// Cephes log2f: log(1 + f) = f - f^2/2 + f^3 P8(f) for f in [sqrt(1/2) - 1, sqrt(2) - 1).
inline constexpr float log_poly[9] = {7.0376836292e-2f,  -1.1514610310e-1f, 1.1676998740e-1f,
                                      -1.2420140846e-1f, 1.4249322787e-1f,  -1.6668057665e-1f,
                                      2.0000714765e-1f,  -2.4999993993e-1f, 3.3333331174e-1f};
inline constexpr float log2e_minus_1 = 0.44269504088896340736f;
// Cephes exp2f: 2^g = 1 + g P5(g) for g in [-1/2, 1/2].
inline constexpr float exp2_poly[6] = {1.535336188319500e-4f, 1.339887440266574e-3f, 9.618437357674640e-3f,
                                       5.550332471162809e-2f, 2.402264791363012e-1f, 6.931472028550421e-1f};
inline constexpr float round_shift = 12582912.0f;  // 1.5 * 2^23: (t + it) - it rounds t to an integer
inline constexpr float smallest_normal = 0x1p-126f;
}  // namespace detail::specular_power_constants

// x^y for x > 0 finite and y in [0, 1000]; above the float range, +inf.
inline float specular_power(float x, float y) {
    namespace d = detail::specular_power_constants;
    // Subnormal x: scaled by 2^23 first.
    float exponent_bias = 0.0f;
    if (x < d::smallest_normal) {
        x = x * 0x1p23f;
        exponent_bias = -23.0f;
    }
    const int32_t ix = std::bit_cast<int32_t>(x);
    const int32_t e = (ix - int32_t(d::sqrt_half_bits)) >> 23;
    const float m = std::bit_cast<float>(ix - (e << 23));
    const float f = m - 1.0f;
    const float f2 = f * f;
    float p = d::log_poly[0];
    for (int k = 1; k < 9; ++k) p = p * f + d::log_poly[k];
    const float tail = p * f * f2 - 0.5f * f2;  // log(1 + f) - f
    float log2_x = tail * d::log2e_minus_1;
    log2_x = log2_x + f * d::log2e_minus_1;
    log2_x = log2_x + tail;
    log2_x = log2_x + f;
    log2_x = log2_x + (float(e) + exponent_bias);

    float t = y * log2_x;
    t = t < -151.0f ? -151.0f : t;  // below: 0 (2^-151 rounds to 0)
    t = t > 128.0f ? 128.0f : t;    // above: +inf (2^128 overflows)
    const float n = (t + d::round_shift) - d::round_shift;
    const float g = t - n;
    float q = d::exp2_poly[0];
    for (int k = 1; k < 6; ++k) q = q * g + d::exp2_poly[k];
    const float two_to_g = 1.0f + g * q;
    // 2^n as 2^h 2^(n - h), h = floor(n / 2): both factors normal floats for n in [-151, 128], and
    // the first product exact, so the result is rounded once (to a subnormal, if it is one).
    const int32_t n_int = int32_t(n);
    const int32_t h = n_int >> 1;
    const float scale_low = std::bit_cast<float>((h + 127) << 23);
    const float scale_high = std::bit_cast<float>((n_int - h + 127) << 23);
    const float power = two_to_g * scale_low * scale_high;
    return power;
}

}  // namespace hsr::shading
