// The SIMD kernel of hsr/triangle_setup_batch.hpp: setup_whole_triangle (hsr/triangle_setup.hpp)
// for as many triangles at once as a vector has double lanes. Highway per-target header
// (re-included once per target by hwy/foreach_target.h from hsr/triangle_setup_batch.hpp).
//
// Why every lane gives the scalar setup bit for bit:
// - The integer part (pixel bounds, orientation, edge functions) is done in double. Snapped corners
//   lie within +-2^24 grid steps (kGuardBand pixels of 2^8 steps, held there by clipping), so a
//   coordinate difference has at most 25 bits, each product of two at most 50 and a difference of
//   products at most 51: every value is an integer below 2^53, which double holds exactly, so the
//   double arithmetic is the int64 arithmetic. Division by the grid's 2^8 (2^16 for areas) is
//   multiplication by its exact reciprocal, which rounds to the same double. Pixel bounds are (g + 127) / 256 and (g - 128) / 256
//   floored: a division by a power of two and a floor, both exact, where the scalar code shifts.
// - The floating-point part (areas, barycentric weights, planes) does the scalar code's double
//   operations in its order, one rounding each (no fused multiply-add: -ffp-contract=off), and the
//   choice between exact and snapped corners is a select on the same comparison.
#if defined(HSR_TRIANGLE_SETUP_BATCH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef HSR_TRIANGLE_SETUP_BATCH_INL_H_
#undef HSR_TRIANGLE_SETUP_BATCH_INL_H_
#else
#define HSR_TRIANGLE_SETUP_BATCH_INL_H_
#endif

#include "hsr/triangle_setup.hpp"

#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace hsr::raster::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Sets up triangles [0, count) of `corners` (count <= kSetupBatch) into out[0, count).
inline void SetupWholeTriangles(const WindowVertex* const (*corners)[3], size_t count, uint32_t width,
                                uint32_t height, TriangleSetup* out) {
    using namespace hn;
    const ScalableTag<double> d;
    const RebindToSigned<decltype(d)> di;
    using V = Vec<decltype(d)>;
    const size_t lanes = Lanes(d);

    // Corner values by corner and lane; lanes past `count` repeat the last triangle.
    HWY_ALIGN double grid_x[3][kSetupBatch], grid_y[3][kSetupBatch];
    HWY_ALIGN double exact_x[3][kSetupBatch], exact_y[3][kSetupBatch];
    HWY_ALIGN double depth[3][kSetupBatch], inv_w[3][kSetupBatch];
    const size_t padded = (count + lanes - 1) / lanes * lanes;
    for (size_t n = 0; n < padded; ++n) {
        const size_t t = n < count ? n : count - 1;
        for (int c = 0; c < 3; ++c) {
            const WindowVertex& v = *corners[t][c];
            grid_x[c][n] = double(v.x);
            grid_y[c][n] = double(v.y);
            exact_x[c][n] = v.exact_x;
            exact_y[c][n] = v.exact_y;
            depth[c][n] = v.depth;
            inv_w[c][n] = v.inv_w;
        }
    }

    // Results by field and lane.
    HWY_ALIGN double bounds[4][kSetupBatch];  // min_x, min_y, max_x, max_y
    HWY_ALIGN int64_t edge[9][kSetupBatch];   // origin, dx, dy of edges 0..2
    HWY_ALIGN double plane[12][kSetupBatch];  // origin, dx, dy of depth, 1/w, b1/w, b2/w
    HWY_ALIGN double swapped[kSetupBatch];

    const auto zero = Zero(d), one = Set(d, 1.0), half = Set(d, 0.5), two = Set(d, 2.0);
    const auto scale = Set(d, double(kSubpixelScale));
    const auto inv_scale = Set(d, 1.0 / double(kSubpixelScale));  // a power of two: exact
    // An integer-valued double v with |v| < 2^51 as an int64: v + 1.5 * 2^52 is exact and has the
    // integer in its low mantissa bits (cheaper than Highway's general conversion on AVX2).
    const auto magic = Set(d, 6755399441055744.0);
    const auto magic_bits = BitCast(di, magic);
    auto to_int64 = [&](auto v) { return Sub(BitCast(di, Add(v, magic)), magic_bits); };
    for (size_t n = 0; n < padded; n += lanes) {
        const auto x0 = Load(d, grid_x[0] + n), x1 = Load(d, grid_x[1] + n), x2 = Load(d, grid_x[2] + n);
        const auto y0 = Load(d, grid_y[0] + n), y1 = Load(d, grid_y[1] + n), y2 = Load(d, grid_y[2] + n);
        const auto signed_area = Sub(Mul(Sub(x1, x0), Sub(y2, y0)), Mul(Sub(x2, x0), Sub(y1, y0)));

        // triangle_pixel_bounds: first_pixel_from of the lowest corner, last_pixel_to of the highest.
        auto first_pixel = [&](auto g) { return Floor(Mul(Add(g, Set(d, double(kHalfPixel - 1))), inv_scale)); };
        auto last_pixel = [&](auto g) { return Floor(Mul(Sub(g, Set(d, double(kHalfPixel))), inv_scale)); };
        const auto min_x = Max(first_pixel(Min(Min(x0, x1), x2)), zero);
        const auto min_y = Max(first_pixel(Min(Min(y0, y1), y2)), zero);
        const auto max_x = Min(last_pixel(Max(Max(x0, x1), x2)), Set(d, double(width) - 1.0));
        const auto max_y = Min(last_pixel(Max(Max(y0, y1), y2)), Set(d, double(height) - 1.0));
        Store(min_x, d, bounds[0] + n);
        Store(min_y, d, bounds[1] + n);
        Store(max_x, d, bounds[2] + n);
        Store(max_y, d, bounds[3] + n);

        // Clockwise triangles swap corners 1 and 2, so the interior is on every edge's positive side.
        const auto clockwise = Lt(signed_area, zero);
        Store(IfThenElseZero(clockwise, one), d, swapped + n);
        const auto area = Abs(signed_area);
        auto pick = [&](const double (&values)[3][kSetupBatch], int c) {
            const auto a = Load(d, values[1] + n), b = Load(d, values[2] + n);
            return c == 0 ? Load(d, values[0] + n) : c == 1 ? IfThenElse(clockwise, b, a) : IfThenElse(clockwise, a, b);
        };
        const V gx[3] = {x0, pick(grid_x, 1), pick(grid_x, 2)};
        const V gy[3] = {y0, pick(grid_y, 1), pick(grid_y, 2)};

        const auto origin_x = Add(Mul(min_x, scale), Set(d, double(kHalfPixel)));
        const auto origin_y = Add(Mul(min_y, scale), Set(d, double(kHalfPixel)));
        for (int k = 0; k < 3; ++k) {
            const int a = (k + 1) % 3, b = (k + 2) % 3;
            const auto dx = Sub(gx[b], gx[a]);
            const auto dy = Sub(gy[b], gy[a]);
            const auto top_left = Or(Lt(dy, zero), And(Eq(dy, zero), Gt(dx, zero)));  // is_top_left_edge
            const auto value = Sub(Mul(dx, Sub(origin_y, gy[a])), Mul(dy, Sub(origin_x, gx[a])));
            Store(to_int64(Sub(value, IfThenZeroElse(top_left, one))), di, edge[3 * k] + n);
            Store(to_int64(Mul(Neg(dy), scale)), di, edge[3 * k + 1] + n);
            Store(to_int64(Mul(dx, scale)), di, edge[3 * k + 2] + n);
        }

        // The planes of setup_triangle, over the exact corners unless snapping reshaped the triangle.
        const V ex[3] = {Load(d, exact_x[0] + n), pick(exact_x, 1), pick(exact_x, 2)};
        const V ey[3] = {Load(d, exact_y[0] + n), pick(exact_y, 1), pick(exact_y, 2)};
        const auto grid_area = Mul(area, Mul(inv_scale, inv_scale));  // = area / 2^16, exactly
        const auto exact_area = Sub(Mul(Sub(ex[1], ex[0]), Sub(ey[2], ey[0])), Mul(Sub(ex[2], ex[0]), Sub(ey[1], ey[0])));
        const auto use_exact = And(Gt(exact_area, Mul(half, grid_area)), Lt(exact_area, Mul(two, grid_area)));
        const auto inv_area = Div(one, IfThenElse(use_exact, exact_area, grid_area));
        V cx[3], cy[3];
        for (int c = 0; c < 3; ++c) {
            cx[c] = IfThenElse(use_exact, ex[c], Mul(gx[c], inv_scale));
            cy[c] = IfThenElse(use_exact, ey[c], Mul(gy[c], inv_scale));
        }
        const auto centre_x = Add(min_x, half), centre_y = Add(min_y, half);
        V lambda_origin[3], lambda_dx[3], lambda_dy[3];
        for (int k = 0; k < 3; ++k) {
            const int a = (k + 1) % 3, b = (k + 2) % 3;
            const auto dx = Sub(cx[b], cx[a]);
            const auto dy = Sub(cy[b], cy[a]);
            lambda_origin[k] = Mul(Sub(Mul(dx, Sub(centre_y, cy[a])), Mul(dy, Sub(centre_x, cx[a]))), inv_area);
            lambda_dx[k] = Mul(Neg(dy), inv_area);
            lambda_dy[k] = Mul(dx, inv_area);
        }
        auto store_plane = [&](int field, auto f0, auto f1, auto f2) {
            Store(Add(Add(Mul(f0, lambda_origin[0]), Mul(f1, lambda_origin[1])), Mul(f2, lambda_origin[2])), d,
                  plane[3 * field] + n);
            Store(Add(Add(Mul(f0, lambda_dx[0]), Mul(f1, lambda_dx[1])), Mul(f2, lambda_dx[2])), d,
                  plane[3 * field + 1] + n);
            Store(Add(Add(Mul(f0, lambda_dy[0]), Mul(f1, lambda_dy[1])), Mul(f2, lambda_dy[2])), d,
                  plane[3 * field + 2] + n);
        };
        store_plane(0, Load(d, depth[0] + n), pick(depth, 1), pick(depth, 2));
        const auto w0 = Load(d, inv_w[0] + n), w1 = pick(inv_w, 1), w2 = pick(inv_w, 2);
        store_plane(1, w0, w1, w2);
        // The corners' barycentrics (0, 0), (1, 0), (0, 1), corners 1 and 2 swapped when clockwise.
        const auto b1_at_1 = IfThenZeroElse(clockwise, one), b1_at_2 = IfThenElseZero(clockwise, one);
        store_plane(2, Mul(zero, w0), Mul(b1_at_1, w1), Mul(b1_at_2, w2));
        store_plane(3, Mul(zero, w0), Mul(b1_at_2, w1), Mul(b1_at_1, w2));
    }

    for (size_t n = 0; n < count; ++n) {
        TriangleSetup& s = out[n];
        s.min_x = int32_t(bounds[0][n]);
        s.min_y = int32_t(bounds[1][n]);
        s.max_x = int32_t(bounds[2][n]);
        s.max_y = int32_t(bounds[3][n]);
        for (int k = 0; k < 3; ++k) {
            s.edge_origin[k] = edge[3 * k][n];
            s.edge_dx[k] = edge[3 * k + 1][n];
            s.edge_dy[k] = edge[3 * k + 2][n];
        }
        Plane* planes[4] = {&s.depth, &s.inv_w, &s.b1_over_w, &s.b2_over_w};
        for (int f = 0; f < 4; ++f) *planes[f] = {plane[3 * f][n], plane[3 * f + 1][n], plane[3 * f + 2][n]};
        s.front_facing = swapped[n] != 0.0;
    }
}

}  // namespace hsr::raster::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard toggled per target
