// Uniform grids for the appel plugin: one over the image (which contour edges may an edge pass
// behind; which faces may cover a seed vertex) and one over world space (which faces may an edge
// pass through). Each stores, per cell, a list of item indices in one flat array (compressed rows),
// built in two passes over the items, so a query allocates nothing.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace appel {

// Cell -> items, compressed.
class Bins {
public:
    // for_each_pair(add) must call add(cell, item) for every pair, the same way both times it is called.
    template <class ForEachPair>
    void build(uint32_t cell_count, ForEachPair&& for_each_pair) {
        start_.assign(size_t(cell_count) + 1, 0);
        for_each_pair([&](uint32_t cell, uint32_t) { ++start_[cell + 1]; });
        for (uint32_t c = 0; c < cell_count; ++c) start_[c + 1] += start_[c];
        items_.resize(start_.back());
        cursor_.assign(start_.begin(), start_.end() - 1);
        for_each_pair([&](uint32_t cell, uint32_t item) { items_[cursor_[cell]++] = item; });
    }
    uint32_t size(uint32_t cell) const { return start_[cell + 1] - start_[cell]; }
    std::span<const uint32_t> operator[](uint32_t cell) const {
        return {items_.data() + start_[cell], items_.data() + start_[cell + 1]};
    }

private:
    std::vector<uint32_t> start_, items_, cursor_;
};

// A cell index along one axis, for a coordinate in cell units; anything beyond the grid goes to the
// border cell (so the grid need not cover every query).
inline int clamp_cell(double v, int n) {
    if (!(v > 0.0)) return 0;
    if (v >= double(n - 1)) return n - 1;
    return int(v);
}

// A grid over a rectangle of window coordinates.
class ImageGrid {
public:
    // About target_cells square cells over [lo, hi]; pad_px widens every query and insertion.
    void frame(glm::dvec2 lo, glm::dvec2 hi, double target_cells, double pad_px) {
        lo_ = lo;
        const glm::dvec2 size = glm::max(hi - lo, glm::dvec2(0.0));
        target_cells = std::clamp(target_cells, 1.0, double(kMaxSide) * kMaxSide);
        const double area = size.x * size.y;
        const double cell = area > 0.0 ? std::sqrt(area / target_cells) : std::max(size.x, size.y) / target_cells;
        nx_ = cell > 0.0 ? std::clamp(int(std::ceil(size.x / cell)), 1, kMaxSide) : 1;
        ny_ = cell > 0.0 ? std::clamp(int(std::ceil(size.y / cell)), 1, kMaxSide) : 1;
        scale_ = {size.x > 0.0 ? nx_ / size.x : 0.0, size.y > 0.0 ? ny_ / size.y : 0.0};
        pad_ = pad_px * scale_;
    }
    uint32_t cell_count() const { return uint32_t(nx_) * uint32_t(ny_); }

    uint32_t cell_of(glm::dvec2 p) const {
        const glm::dvec2 c = (p - lo_) * scale_;
        return uint32_t(clamp_cell(c.y, ny_)) * nx_ + uint32_t(clamp_cell(c.x, nx_));
    }

    template <class F>
    void for_box(glm::dvec2 lo, glm::dvec2 hi, F&& f) const {
        const glm::dvec2 a = (lo - lo_) * scale_ - pad_, b = (hi - lo_) * scale_ + pad_;
        const int c0 = clamp_cell(a.x, nx_), c1 = clamp_cell(b.x, nx_);
        const int r0 = clamp_cell(a.y, ny_), r1 = clamp_cell(b.y, ny_);
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c) f(uint32_t(r) * nx_ + uint32_t(c));
    }
    // How many cells for_box visits.
    uint64_t box_cells(glm::dvec2 lo, glm::dvec2 hi) const {
        const glm::dvec2 a = (lo - lo_) * scale_ - pad_, b = (hi - lo_) * scale_ + pad_;
        return uint64_t(clamp_cell(b.x, nx_) - clamp_cell(a.x, nx_) + 1) * uint64_t(clamp_cell(b.y, ny_) - clamp_cell(a.y, ny_) + 1);
    }

    // Every cell the segment (widened by the pad) passes through, each once.
    template <class F>
    void for_segment(glm::dvec2 a, glm::dvec2 b, F&& f) const {
        for_segment_rows(a, b, [&](int r, int c0, int c1) {
            for (int c = c0; c <= c1; ++c) f(uint32_t(r) * nx_ + uint32_t(c));
        });
    }
    // How many cells for_segment visits.
    uint64_t segment_cells(glm::dvec2 a, glm::dvec2 b) const {
        uint64_t cells = 0;
        for_segment_rows(a, b, [&](int, int c0, int c1) { cells += uint64_t(c1 - c0 + 1); });
        return cells;
    }

private:
    // f(row, first column, last column) for each row of cells the segment passes through.
    template <class F>
    void for_segment_rows(glm::dvec2 a, glm::dvec2 b, F&& f) const {
        a = (a - lo_) * scale_;
        b = (b - lo_) * scale_;
        if (a.y > b.y) std::swap(a, b);
        const double dy = b.y - a.y;
        const int r0 = clamp_cell(a.y - pad_.y, ny_), r1 = clamp_cell(b.y + pad_.y, ny_);
        constexpr double kInf = std::numeric_limits<double>::infinity();
        for (int r = r0; r <= r1; ++r) {
            // The part of the segment within this row (the border rows reach to infinity), padded.
            const double slab_lo = r == 0 ? -kInf : r - pad_.y;
            const double slab_hi = r == ny_ - 1 ? kInf : r + 1 + pad_.y;
            const double y_lo = std::max(slab_lo, a.y), y_hi = std::min(slab_hi, b.y);
            double x_lo = std::min(a.x, b.x), x_hi = std::max(a.x, b.x);
            if (dy > 0.0 && y_lo <= y_hi) {
                const double xa = a.x + (y_lo - a.y) / dy * (b.x - a.x);
                const double xb = a.x + (y_hi - a.y) / dy * (b.x - a.x);
                x_lo = std::min(xa, xb);
                x_hi = std::max(xa, xb);
            }
            f(r, clamp_cell(x_lo - pad_.x, nx_), clamp_cell(x_hi + pad_.x, nx_));
        }
    }

    static constexpr int kMaxSide = 2048;
    glm::dvec2 lo_{0.0}, scale_{0.0}, pad_{0.0};
    int nx_ = 1, ny_ = 1;
};

// A grid over a box of world space.
class SpaceGrid {
public:
    // Cubic cells of about cell_size (at most kMaxSide per axis and max_cells in all) over [lo, hi].
    void frame(glm::dvec3 lo, glm::dvec3 hi, double cell_size, double pad, double max_cells) {
        max_cells = std::clamp(max_cells, 1.0, kMaxCells);
        lo_ = lo;
        const glm::dvec3 size = glm::max(hi - lo, glm::dvec3(0.0));
        const double largest = std::max({size.x, size.y, size.z});
        if (!(cell_size > 0.0)) cell_size = largest > 0.0 ? largest : 1.0;
        cell_size = std::max(cell_size, largest / kMaxSide);
        for (;;) {
            for (int k = 0; k < 3; ++k) n_[k] = std::clamp(int(std::ceil(size[k] / cell_size)), 1, kMaxSide);
            if (double(n_[0]) * n_[1] * n_[2] <= max_cells) break;
            cell_size *= 1.25;
        }
        for (int k = 0; k < 3; ++k) scale_[k] = size[k] > 0.0 ? n_[k] / size[k] : 0.0;
        pad_ = pad * scale_;
    }
    uint32_t cell_count() const { return uint32_t(n_[0]) * uint32_t(n_[1]) * uint32_t(n_[2]); }

    template <class F>
    void for_box(glm::dvec3 lo, glm::dvec3 hi, F&& f) const {
        const glm::dvec3 a = (lo - lo_) * scale_ - pad_, b = (hi - lo_) * scale_ + pad_;
        int c0[3], c1[3];
        for (int k = 0; k < 3; ++k) {
            c0[k] = clamp_cell(a[k], n_[k]);
            c1[k] = clamp_cell(b[k], n_[k]);
        }
        for (int z = c0[2]; z <= c1[2]; ++z)
            for (int y = c0[1]; y <= c1[1]; ++y)
                for (int x = c0[0]; x <= c1[0]; ++x) f(index(x, y, z));
    }
    // How many cells for_box visits.
    uint64_t box_cells(glm::dvec3 lo, glm::dvec3 hi) const {
        const glm::dvec3 a = (lo - lo_) * scale_ - pad_, b = (hi - lo_) * scale_ + pad_;
        uint64_t cells = 1;
        for (int k = 0; k < 3; ++k) cells *= uint64_t(clamp_cell(b[k], n_[k]) - clamp_cell(a[k], n_[k]) + 1);
        return cells;
    }

    // Every cell the segment (widened by the pad) passes through, each once: slabs across the axis
    // along which it is longest, so each slab adds only a few cells.
    template <class F>
    void for_segment(glm::dvec3 a, glm::dvec3 b, F&& f) const {
        // A short segment: its bounding box is hardly larger than the cells it passes through.
        {
            const glm::dvec3 lo = (glm::min(a, b) - lo_) * scale_ - pad_, hi = (glm::max(a, b) - lo_) * scale_ + pad_;
            int c0[3], c1[3];
            for (int k = 0; k < 3; ++k) {
                c0[k] = clamp_cell(lo[k], n_[k]);
                c1[k] = clamp_cell(hi[k], n_[k]);
            }
            if ((c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) * (c1[2] - c0[2] + 1) <= 8) {
                for (int z = c0[2]; z <= c1[2]; ++z)
                    for (int y = c0[1]; y <= c1[1]; ++y)
                        for (int x = c0[0]; x <= c1[0]; ++x) f(index(x, y, z));
                return;
            }
        }
        a = (a - lo_) * scale_;
        b = (b - lo_) * scale_;
        const glm::dvec3 d = glm::abs(b - a);
        const int major = d.x >= d.y ? (d.x >= d.z ? 0 : 2) : (d.y >= d.z ? 1 : 2);
        const int u = (major + 1) % 3, v = (major + 2) % 3;
        if (a[major] > b[major]) std::swap(a, b);
        const double length = b[major] - a[major];
        const int s0 = clamp_cell(a[major] - pad_[major], n_[major]);
        const int s1 = clamp_cell(b[major] + pad_[major], n_[major]);
        constexpr double kInf = std::numeric_limits<double>::infinity();
        for (int s = s0; s <= s1; ++s) {
            double t0 = 0.0, t1 = 1.0;
            if (length > 0.0) {
                const double slab_lo = s == 0 ? -kInf : s - pad_[major];
                const double slab_hi = s == n_[major] - 1 ? kInf : s + 1 + pad_[major];
                t0 = std::clamp((slab_lo - a[major]) / length, 0.0, 1.0);
                t1 = std::clamp((slab_hi - a[major]) / length, 0.0, 1.0);
            }
            const glm::dvec3 p = a + t0 * (b - a), q = a + t1 * (b - a);
            const int u0 = clamp_cell(std::min(p[u], q[u]) - pad_[u], n_[u]);
            const int u1 = clamp_cell(std::max(p[u], q[u]) + pad_[u], n_[u]);
            const int v0 = clamp_cell(std::min(p[v], q[v]) - pad_[v], n_[v]);
            const int v1 = clamp_cell(std::max(p[v], q[v]) + pad_[v], n_[v]);
            for (int j = v0; j <= v1; ++j)
                for (int i = u0; i <= u1; ++i) {
                    int c[3];
                    c[major] = s;
                    c[u] = i;
                    c[v] = j;
                    f(index(c[0], c[1], c[2]));
                }
        }
    }

private:
    static constexpr int kMaxSide = 256;
    static constexpr double kMaxCells = 4.0 * 1024 * 1024;
    uint32_t index(int x, int y, int z) const { return (uint32_t(z) * n_[1] + uint32_t(y)) * n_[0] + uint32_t(x); }
    glm::dvec3 lo_{0.0}, scale_{0.0}, pad_{0.0};
    int n_[3] = {1, 1, 1};
};

}  // namespace appel
