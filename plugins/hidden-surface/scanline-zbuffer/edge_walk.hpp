// scanline-zbuffer's edges: the edge pair of a polygon on the active list, each edge an exact
// integer DDA over the polygon's edge function, so that every scanline covers exactly the pixel
// centres raster::setup_triangle's edge functions cover (top-left fill rule, 1/256-pixel corners).
// The active edge pairs of Watkins, "A Real Time Visible Surface Algorithm" (Utah 1970); the
// incremental error term of Bresenham (1965). Included by scanline_zbuffer.cpp only.
#pragma once

#include "hsr/raster.hpp"

#include <algorithm>
#include <cstdint>

namespace scanline_zbuffer {

namespace raster = hsr::raster;

inline constexpr int32_t kScale = raster::kSubpixelScale;
inline constexpr int kBits = raster::kSubpixelBits;

// floor(a / b) and a - b * floor(a / b) for b > 0 and |a| < 2^50, given inverse = 1.0 / b: the
// product is within 1/64 of a / b, so its truncation is at most one away from the floor, and the
// remainder tells which way, exactly. (One division per edge instead of two integer divisions.)
struct DivMod {
    int64_t q, r;
};
inline DivMod floor_divmod(int64_t a, int64_t b, double inverse) {
    int64_t q = static_cast<int64_t>(double(a) * inverse);
    int64_t r = a - q * b;
    const int64_t under = -int64_t(r < 0);  // masks, not branches: either way is as likely
    q += under;
    r += b & under;
    const int64_t over = -int64_t(r >= b);
    q -= over;
    r -= b & over;
    return {q, r};
}

// One edge of an active edge pair: an integer DDA (Bresenham style) over the edge function. `x` is
// the boundary pixel on the current scanline, the first covered pixel of a left edge or the last of
// a right edge; `error` is the edge function there (in units of 1/256 pixel, floored), kept in
// [0, den). One scanline down adds dx to it: `step` whole pixels plus a carry from `rem / den`.
struct EdgeWalk {
    int32_t x;
    int32_t error;
    int32_t den;   // |dy| of the edge on the subpixel grid: edge-function change per pixel in x
    int32_t rem;   // dx mod den
    int32_t step;  // floor(dx / den), negated for a left edge
};

// An entry of the active polygon list: the edge pair on the current scanline, and the depth.
struct ActivePolygon {
    EdgeWalk left, right;
    EdgeWalk lower;         // the lower short edge, started on switch_row
    int16_t last_row;       // its last scanline
    int16_t switch_row;     // where the lower short edge takes over (-1: it does not)
    uint32_t slot;          // its attributes, which stay put while the list is reordered
    int32_t lower_left;     // 1: the lower edge replaces the left edge, 0: the right one
    int32_t min_x, min_y;   // the origin pixel of its depth plane (its setup's)
    double z_origin;        // depth at the centre of pixel (min_x, min_y), on the polygon's plane
    double dzdx, dzdy;      // -A/C and -B/C of the plane Ax + By + Cz + D = 0
};

// Orders the corners (on the subpixel grid, in the setup's corner order) by y, takes the long
// edge (top to bottom corner) for one side and the upper short edge for the other, and starts
// each as an integer DDA on scanline `first`; the lower short edge is started on the scanline
// where it takes over. Sets the pair's edges and `last_row`, its last scanline (inside an image of `height`
// rows), unless no scanline is left (the only one lay on a horizontal bottom edge): then false.
inline bool start_edge_pair(const int32_t (&vx)[3], const int32_t (&vy)[3], int32_t first, int32_t height,
                            ActivePolygon& pair, int32_t& last_row) {
    // Edge k runs from corner k+1 to corner k+2, the interior on its positive side.
    int64_t dx[3], dy[3];
    for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        dx[k] = int64_t(vx[b]) - vx[a];
        dy[k] = int64_t(vy[b]) - vy[a];
    }
    int top = 0, bottom = 0;
    for (int k = 1; k < 3; ++k) {
        top = vy[k] < vy[top] ? k : top;
        bottom = vy[k] >= vy[bottom] ? k : bottom;
    }
    const int mid = 3 - top - bottom;

    // Last scanline: the last pixel centre at or above the bottom corner, except on a horizontal
    // bottom edge (not top-left: a centre exactly on it is not covered). The first is min_y (a
    // centre exactly on a horizontal top edge is covered).
    int64_t last = raster::last_pixel_to(vy[bottom]);
    if (vy[mid] == vy[bottom] && ((vy[bottom] - raster::kHalfPixel) & (kScale - 1)) == 0) --last;
    last = std::min<int64_t>(last, height - 1);
    if (first > last) return false;

    // Edge k's DDA on scanline `row`. The edge function E_k (fill-rule biased, as setup_triangle
    // makes it) steps by multiples of 256 between pixel centres, so E_k >= 0 exactly when
    // floor(E_k / 256) >= 0, which steps by -dy per pixel and by dx per scanline: one division
    // finds the boundary pixel and the step.
    auto start = [&](int k, int64_t row) {
        const int a = (k + 1) % 3;
        const int64_t edge =
            raster::biased_edge_function(dx[k], dy[k], vx[a], vy[a], raster::kHalfPixel, row * kScale + raster::kHalfPixel);
        const int64_t den = std::max<int64_t>(dy[k] < 0 ? -dy[k] : dy[k], 1);  // never horizontal
        const double inverse = 1.0 / double(den);
        const DivMod boundary = floor_divmod(edge >> kBits, den, inverse);
        const DivMod step = floor_divmod(dx[k], den, inverse);
        const bool left = dy[k] < 0;  // a left edge (E grows with x): its first pixel with E >= 0
        EdgeWalk w;
        w.x = int32_t(left ? -boundary.q : boundary.q);
        w.error = int32_t(boundary.r);
        w.den = int32_t(den);
        w.rem = int32_t(step.r);
        w.step = int32_t(left ? -step.q : step.q);
        return w;
    };

    // Edge k is opposite corner k: the long edge is opposite the middle corner, the upper short
    // edge (top to middle) opposite the bottom corner, the lower one opposite the top corner.
    // The lower one takes over on the first scanline whose centres are at or below the middle
    // corner (on the middle corner's own scanline both give the same boundary, and a horizontal
    // upper edge is never used).
    const int long_edge = mid, upper = bottom, lower = top;
    const int64_t switch_row = raster::first_pixel_from(vy[mid]);
    const bool long_is_left = dy[long_edge] < 0;
    const EdgeWalk long_walk = start(long_edge, first);
    const EdgeWalk short_walk = start(switch_row <= first ? lower : upper, first);
    const bool switches = switch_row > first && switch_row <= last;

    pair.lower = switches ? start(lower, switch_row) : EdgeWalk{};
    pair.lower_left = long_is_left ? 0 : 1;
    pair.left = long_is_left ? long_walk : short_walk;
    pair.right = long_is_left ? short_walk : long_walk;
    pair.switch_row = switches ? int16_t(switch_row) : int16_t(-1);
    last_row = int32_t(last);
    return true;
}

// Which pixel centres a setup covers when its bounds hold at most 2 x 2 of them (most polygons of a
// deep scene are that small): bit i + 2 j for pixel (min_x + i, min_y + j), found with its exact
// integer edge functions, the fill rule included, as zbuffer tests them. kLarger for larger bounds.
constexpr uint32_t kLarger = 16;
inline uint32_t small_coverage(const raster::TriangleSetup& s) {
    const int32_t w = s.max_x - s.min_x, h = s.max_y - s.min_y;
    if ((w | h) > 1) return kLarger;
    // A centre is covered when its three edge functions are >= 0, i.e. their OR is; centres outside
    // the bounds start negative. No branch per centre: which are covered is not predictable.
    int64_t c00 = 0, c10 = -int64_t(w == 0), c01 = -int64_t(h == 0), c11 = -int64_t((w & h) == 0);
    for (int e = 0; e < 3; ++e) {
        c00 |= s.edge_origin[e];
        c10 |= s.edge_origin[e] + s.edge_dx[e];
        c01 |= s.edge_origin[e] + s.edge_dy[e];
        c11 |= s.edge_origin[e] + s.edge_dx[e] + s.edge_dy[e];
    }
    return uint32_t(c00 >= 0) | uint32_t(c10 >= 0) << 1 | uint32_t(c01 >= 0) << 2 | uint32_t(c11 >= 0) << 3;
}

}  // namespace scanline_zbuffer
