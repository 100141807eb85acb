// The two horizons of the floating-horizon method (Wright 1973; Rogers, "Procedural Elements for
// Computer Graphics", 2nd ed., section 4.2): the highest and the lowest height reached so far over a
// set of columns, the test of a segment against them and the update with it (steps 5 to 7 of
// docs/algorithms/floating-horizon.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace floating_horizon {
// Internal linkage: only floating_horizon.cpp includes this, and so the compiler inlines as it would
// in one file (the per-column test inside Horizon::classify above all).
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A point of a curve counts as on the horizon (and so visible) within this distance, in the
// horizons' units (a billionth of a pixel in the image's columns; in the vertical space, whose unit
// is the distance in depth, around a millionth of a pixel at usual sizes): an edge whose ends are shared with edges already
// drawn can lie exactly along the horizon they made (the outline of the grid drawn so far), and
// rounding must not hide it.
constexpr double kEpsilon = 1e-9;

// A vertex in the space of the horizons: column coordinate X, height H (larger is higher), and the
// projective weight W > 0 of the map that produced them (for parameters along an edge in 3D).
struct SpacePoint {
    double x;
    double h;
    double w;
};

struct Piece {
    double s0, s1;  // parameters along the segment in the horizons' space
    bool visible;
};

// The upper and lower horizon, sampled at a sorted set of positions x ("columns") and linear between
// neighbouring samples. The columns are evenly spaced ones (`spacing` apart, on multiples of it)
// covering the grid and, with vertex columns on, also the x of every grid vertex (to about 1e-9 of
// the spacing): every segment then starts and ends on a column, so a kink of the horizon at a vertex
// is never cut off by the interpolation, and a segment upright in this space still reaches the
// horizon. With vertex columns off, each vertex is moved to the nearest even column instead (at
// most half a column): fewer columns on a grid denser than the pixels, at some cost in accuracy.
//
// Each column keeps three values of each horizon: the limit from its left and the limit from its
// right (what the segments reaching into the intervals on either side give there), and the value at
// the column itself (everything that touches it, upright segments included). Where a segment ends,
// the horizon steps; with one value per column the step would be smeared over the neighbouring
// interval, and an edge running through that interval (typically one nearly upright, starting where
// the step is) would be judged against a slope that is not there.
class Horizon {
public:
    void build(const std::vector<SpacePoint>& points, double x_min, double x_max, double spacing,
               bool vertex_columns) {
        // Positions are the first even column plus whole multiples of a quantum: the spacing, or
        // about a billionth of it (kept relative to the first column, so the integers stay small).
        const int64_t per_spacing = vertex_columns ? int64_t(1) << 30 : 1;
        const double quantum = spacing / double(per_spacing);
        const int64_t first = int64_t(std::floor(x_min / spacing)), last = int64_t(std::ceil(x_max / spacing));
        const double origin = double(first) * spacing;
        auto key = [&](double x) { return std::llround((x - origin) / quantum); };
        std::vector<int64_t> keys;
        keys.reserve(size_t(last - first + 1) + points.size());
        for (int64_t k = 0; k <= last - first; ++k) keys.push_back(k * per_spacing);
        for (const SpacePoint& p : points) keys.push_back(key(p.x));
        std::sort(keys.begin(), keys.end());
        keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
        x_.resize(keys.size());
        for (size_t k = 0; k < keys.size(); ++k) x_[k] = origin + double(keys[k]) * quantum;
        column_of_.resize(points.size());
        for (size_t v = 0; v < points.size(); ++v)
            column_of_[v] = uint32_t(std::lower_bound(keys.begin(), keys.end(), key(points[v].x)) - keys.begin());
        for (Side side : {kLeft, kRight, kAt}) {
            upper_[side].assign(x_.size(), -kInf);
            lower_[side].assign(x_.size(), kInf);
        }
    }
    size_t size() const { return x_.size(); }
    // The column at vertex v's x; a segment's update visits the columns from one end's to the other's.
    uint32_t column(uint32_t v) const { return column_of_[v]; }
    // f(x, upper, lower) for each column, with the values at the column itself (-kInf and kInf where
    // nothing reached it yet).
    template <class F>
    void for_each_column(F&& f) const {
        for (size_t k = 0; k < x_.size(); ++k) f(x_[k], upper_[kAt][k], lower_[kAt][k]);
    }

    // The visible pieces of the segment from vertex a to vertex b against the horizons, merged, in
    // order of s. Returns the number of column intervals looked at.
    uint64_t classify(uint32_t a, uint32_t b, const SpacePoint& A, const SpacePoint& B,
                      std::vector<Piece>& pieces) const {
        pieces.clear();
        const int64_t ka = column_of_[a], kb = column_of_[b];
        const double ax = x_[size_t(ka)], dx = x_[size_t(kb)] - ax, dh = B.h - A.h;
        auto add = [&](double s0, double s1, bool visible) {
            if (!(s1 > s0)) return;
            if (!pieces.empty() && pieces.back().visible == visible)
                pieces.back().s1 = s1;
            else
                pieces.push_back({s0, s1, visible});
        };
        // Over [s0, s1] the segment runs from column k0 (value on side0) to column k1 (side1); the
        // same column for a segment upright here. The curve and both horizons are linear in s there.
        auto interval = [&](int64_t k0, Side side0, int64_t k1, Side side1, double s0, double s1) {
            const double u0 = upper_[side0][size_t(k0)], u1 = upper_[side1][size_t(k1)];
            if (!(u0 > -kInf && u1 > -kInf)) {  // nothing drawn here yet
                add(s0, s1, true);
                return;
            }
            const double h0 = A.h + dh * s0, h1 = A.h + dh * s1;
            // On or above the upper horizon (du >= 0), or on or below the lower one (dl >= 0).
            const double du0 = h0 - u0 + kEpsilon, du1 = h1 - u1 + kEpsilon;
            const double dl0 = lower_[side0][size_t(k0)] - h0 + kEpsilon, dl1 = lower_[side1][size_t(k1)] - h1 + kEpsilon;
            double cuts[4] = {s0, 0, 0, 0};
            int n = 1;
            for (const auto& [d0, d1] : {std::pair{du0, du1}, std::pair{dl0, dl1}})
                if ((d0 >= 0) != (d1 >= 0)) {
                    // Where the curve's segment crosses the horizon's segment.
                    const double s = s0 + (s1 - s0) * d0 / (d0 - d1);
                    if (s > s0 && s < s1) cuts[n++] = s;
                }
            if (n == 3 && cuts[2] < cuts[1]) std::swap(cuts[1], cuts[2]);
            cuts[n++] = s1;
            for (int i = 0; i + 1 < n; ++i) {
                const double f = (0.5 * (cuts[i] + cuts[i + 1]) - s0) / (s1 - s0);
                add(cuts[i], cuts[i + 1], du0 + (du1 - du0) * f >= 0 || dl0 + (dl1 - dl0) * f >= 0);
            }
        };
        if (ka == kb) {
            interval(ka, kAt, ka, kAt, 0.0, 1.0);
            return 1;
        }
        const int64_t step = kb > ka ? 1 : -1;
        // Leaving a column to the right, its right-hand values count; arriving, the left-hand ones.
        const Side leaving = step > 0 ? kRight : kLeft, arriving = step > 0 ? kLeft : kRight;
        double s = 0;
        for (int64_t k = ka; k != kb; k += step) {
            const double next = k + step == kb ? 1.0 : std::clamp((x_[size_t(k + step)] - ax) / dx, s, 1.0);
            interval(k, leaving, k + step, arriving, s, next);
            s = next;
        }
        return uint64_t(std::abs(kb - ka));
    }

    // Raises the upper and lowers the lower horizon with the segment from vertex a to vertex b at the
    // columns it spans. Returns the number of column values changed and, in s_lo .. s_hi, the
    // parameters where it changed any.
    uint64_t update(uint32_t a, uint32_t b, const SpacePoint& A, const SpacePoint& B, double& s_lo, double& s_hi) {
        const int64_t ka = column_of_[a], kb = column_of_[b], k0 = std::min(ka, kb), k1 = std::max(ka, kb);
        uint64_t changed = 0;
        s_lo = kInf;
        s_hi = -kInf;
        auto raise = [&](Side side, size_t k, double top, double bottom) {
            bool any = false;
            if (top > upper_[side][k]) {
                upper_[side][k] = top;
                any = true;
            }
            if (bottom < lower_[side][k]) {
                lower_[side][k] = bottom;
                any = true;
            }
            return any;
        };
        for (int64_t k = k0; k <= k1; ++k) {
            double top, bottom, s;
            if (ka == kb) {  // upright: only the column itself
                top = std::max(A.h, B.h);
                bottom = std::min(A.h, B.h);
                s = 0.5;
            } else {
                s = k == ka ? 0.0 : k == kb ? 1.0 : std::clamp((x_[size_t(k)] - x_[size_t(ka)]) / (x_[size_t(kb)] - x_[size_t(ka)]), 0.0, 1.0);
                top = bottom = A.h + (B.h - A.h) * s;
            }
            bool any = raise(kAt, size_t(k), top, bottom);
            if (k > k0) any = raise(kLeft, size_t(k), top, bottom) || any;
            if (k < k1) any = raise(kRight, size_t(k), top, bottom) || any;
            if (any) {
                ++changed;
                s_lo = std::min(s_lo, ka == kb ? 0.0 : s);
                s_hi = std::max(s_hi, ka == kb ? 1.0 : s);
            }
        }
        return changed;
    }

private:
    enum Side { kLeft = 0, kRight = 1, kAt = 2 };
    std::vector<double> x_;            // the columns, sorted
    std::vector<uint32_t> column_of_;  // per vertex, the column at its x
    std::vector<double> upper_[3], lower_[3];  // per side, per column
};

}  // namespace
}  // namespace floating_horizon
