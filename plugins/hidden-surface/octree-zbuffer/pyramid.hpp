// The z-pyramid of the octree-zbuffer plugin (Greene, Kass & Miller, "Hierarchical Z-Buffer
// Visibility", SIGGRAPH 1993, section 4), private to this plugin: a shared hsr/zpyramid.hpp with the
// same interface (reset, is_hidden, update) was planned but not there when this was written; this
// class can be swapped for it by changing one include and one alias in octree_zbuffer.cpp.
//
// Level 0 is the fine depth buffer itself (the array update() is given); level k > 0 holds, for each
// 2^k x 2^k block of pixels, the FARTHEST depth in it (+infinity while a pixel is empty). A pixel
// rectangle is hidden behind depth z when every pixel in it is strictly nearer than z. The query
// takes the coarsest level whose cells are as large as the rectangle (it meets at most 2x2 of
// them) and refines only the cells that are not nearer than z; rectangles of at most 64 pixels are
// checked on the fine depths directly, which measured faster than walking the levels.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

namespace octree_zbuffer {

class ZPyramid {
public:
    void reset(uint32_t width, uint32_t height) {
        fine_ = nullptr;
        if (int32_t(width) != width_ || int32_t(height) != height_) {
            width_ = int32_t(width);
            height_ = int32_t(height);
            top_ = 0;
            size_t total = 0;
            int32_t w = width_, h = height_;
            level_width_[0] = w;
            level_height_[0] = h;
            while (w > 1 || h > 1) {
                w = (w + 1) / 2;
                h = (h + 1) / 2;
                ++top_;
                level_width_[top_] = w;
                level_height_[top_] = h;
                offset_[top_] = total;
                total += size_t(w) * h;
            }
            storage_.resize(total);
        }
        std::fill(storage_.begin(), storage_.end(), std::numeric_limits<float>::infinity());
        for (int k = 1; k <= top_; ++k) level_[k] = storage_.data() + offset_[k];
    }

    // True when every pixel centre in [x0,x1]x[y0,y1] (clamped to the image) holds a depth strictly
    // nearer than nearest_depth.
    bool is_hidden(int32_t x0, int32_t y0, int32_t x1, int32_t y1, float nearest_depth) const {
        x0 = std::max(x0, 0);
        y0 = std::max(y0, 0);
        x1 = std::min(x1, width_ - 1);
        y1 = std::min(y1, height_ - 1);
        if (x0 > x1 || y0 > y1) return true;
        if (fine_ == nullptr) return false;  // nothing drawn yet
        if ((x1 - x0 + 1) * (y1 - y0 + 1) <= 64) {  // small: the fine depths themselves
            for (int32_t y = y0; y <= y1; ++y) {
                const float* row = fine_ + size_t(y) * width_;
                for (int32_t x = x0; x <= x1; ++x)
                    if (!(row[x] < nearest_depth)) return false;
            }
            return true;
        }
        // The level whose cells are at least as large as the rectangle: it meets at most 2x2 cells.
        int level = std::min(int(std::bit_width(uint32_t(std::max(x1 - x0, y1 - y0)))), top_);
        const int32_t cx0 = x0 >> level, cx1 = x1 >> level, cy0 = y0 >> level, cy1 = y1 >> level;
        for (int32_t cy = cy0; cy <= cy1; ++cy)
            for (int32_t cx = cx0; cx <= cx1; ++cx)
                if (!(value(level, cx, cy) < nearest_depth) && !refine(level, cx, cy, x0, y0, x1, y1, nearest_depth))
                    return false;
        return true;
    }

    // After depths of `depth` (row-major, the image's size) changed inside [x0,x1]x[y0,y1]: bring the
    // coarser levels up to date.
    void update(const float* depth, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
        fine_ = depth;
        level_[0] = depth;
        x0 = std::max(x0, 0);
        y0 = std::max(y0, 0);
        x1 = std::min(x1, width_ - 1);
        y1 = std::min(y1, height_ - 1);
        if (x0 > x1 || y0 > y1) return;
        for (int k = 1; k <= top_; ++k) {
            x0 >>= 1;
            y0 >>= 1;
            x1 >>= 1;
            y1 >>= 1;
            const float* below = level_[k - 1];
            const int32_t below_w = level_width_[k - 1], below_h = level_height_[k - 1];
            float* here = storage_.data() + offset_[k];
            const int32_t w = level_width_[k];
            bool changed = false;
            for (int32_t y = y0; y <= y1; ++y) {
                const float* row_a = below + size_t(2 * y) * below_w;
                const float* row_b = below + size_t(std::min(2 * y + 1, below_h - 1)) * below_w;
                for (int32_t x = x0; x <= x1; ++x) {
                    const int32_t a = 2 * x, b = std::min(2 * x + 1, below_w - 1);
                    const float m = std::max(std::max(row_a[a], row_a[b]), std::max(row_b[a], row_b[b]));
                    float& cell = here[size_t(y) * w + x];
                    changed |= cell != m;
                    cell = m;
                }
            }
            if (!changed) break;
        }
    }

private:
    float value(int level, int32_t cx, int32_t cy) const { return level_[level][size_t(cy) * level_width_[level] + cx]; }

    // Every pixel of cell (cx, cy) of `level` that lies in the rectangle is nearer than z.
    bool refine(int level, int32_t cx, int32_t cy, int32_t x0, int32_t y0, int32_t x1, int32_t y1, float z) const {
        if (level == 0) return false;
        const int below = level - 1;
        const int32_t lo_x = std::max(2 * cx, x0 >> below), hi_x = std::min(2 * cx + 1, x1 >> below);
        const int32_t lo_y = std::max(2 * cy, y0 >> below), hi_y = std::min(2 * cy + 1, y1 >> below);
        for (int32_t y = lo_y; y <= hi_y; ++y)
            for (int32_t x = lo_x; x <= hi_x; ++x)
                if (!(value(below, x, y) < z) && !refine(below, x, y, x0, y0, x1, y1, z)) return false;
        return true;
    }

    int32_t width_ = -1, height_ = -1;
    int top_ = 0;
    const float* fine_ = nullptr;
    int32_t level_width_[32] = {}, level_height_[32] = {};
    size_t offset_[32] = {};
    const float* level_[32] = {};
    std::vector<float> storage_;
};

}  // namespace octree_zbuffer
