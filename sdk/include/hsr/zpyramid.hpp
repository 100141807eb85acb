// hsr z-pyramid: the depth pyramid of Greene, Kass & Miller, "Hierarchical Z-Buffer Visibility"
// (SIGGRAPH 1993, section 4), shared by the hierarchical rasterizing hidden-surface removers.
// Header-only, part of hsr::sdk.
//
// Levels. The finest level is the fine depth buffer itself: the visibility buffer's depth array,
// which update() is given and which the pyramid reads but never writes or copies. Above it, level k
// holds for each block of 2^k x 2^k pixels the FARTHEST (largest) depth in it, +infinity while any
// of its pixels is empty. Levels start at a base level B (set_base_level, default 3: 8 x 8 tiles)
// computed straight from the fine depths (a block of 2^B x 2^B floats, read row by row, is cheap and
// cache-friendly), up to a top level of one cell; the intermediate levels 1 .. B-1 are not stored.
// A size that is not a power of two is padded: a level has ceil(size / 2^k) cells per side, and a
// cell on the right or bottom edge takes the maximum of the pixels that exist (queries are clamped
// to the image, so pixels outside it are never asked about).
//
// Query (is_hidden): a screen rectangle whose nearest depth is z is hidden when every pixel in it
// already holds a depth strictly nearer than z. The query looks at the coarsest level whose cells
// are as large as the rectangle, where it meets at most 2 x 2 cells; a cell nearer than z settles
// its part at once. Small rectangles (at most set_direct_area pixels, default 256) that this does
// not settle are checked on the fine depths directly, four at a time, stopping at the first group
// holding a pixel that is not nearer. Larger ones refine each cell that is not nearer than z
// through its children inside the rectangle, down to the fine pixels; since a cell is the maximum
// of its children, some child of a failing cell fails too, so a visible rectangle is found in a few
// steps. Refining stops after a budget of cells and pixels (set_refine_budget, default 256) and
// then answers "not hidden": answers are conservative, never "hidden" for a rectangle that brute
// force finds visible.
//
// Update: after depths were written inside a rectangle of the fine buffer, update() recomputes the
// base cells over that rectangle, then the cells above level by level, and stops as soon as a level
// does not change (Greene's "propagate only while the maximum changes").
//
// Deferred update: mark_dirty() only flags the base cells under a written rectangle; flush(), or the
// next query of a large rectangle, recomputes each flagged cell once however many writes it received
// meanwhile, and the levels above it while they change. Queries of small rectangles do not flush:
// they read the cells as they are, then the fine depths, which are always current. A cell that lags
// behind is never nearer than the truth PROVIDED DEPTHS ONLY EVER DECREASE between reset() and the
// query (a nearer-wins depth test), so answers stay conservative; with update() alone (no
// mark_dirty) the stored levels are always exact and this proviso does not apply. A renderer whose
// triangles are mostly small (a dense mesh) thus rarely pays for bringing the pyramid up to date.
//
// Window: reset_window() makes a pyramid over one rectangle of the image only (a screen tile that
// one thread renders): it takes and answers image coordinates, clamps every query and update to its
// rectangle, and reads the fine depths only there, so pyramids over disjoint tiles of one depth
// buffer never touch each other's pixels.
//
// Depth convention: window depth, smaller is nearer, +infinity = nothing drawn yet.
#pragma once

#include "hsr/sdk.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hsr::raster {

class ZPyramid {
public:
    static constexpr int kMaxLevels = 32;
    static constexpr int kMaxBaseLevel = 5;  // 32 x 32 pixel base cells

    // The level the stored pyramid starts at (cells of 2^level pixels per side), 1..kMaxBaseLevel.
    // Takes effect at the next reset().
    void set_base_level(int level) { requested_base_ = std::clamp(level, 1, kMaxBaseLevel); }
    // Rectangles of at most this many pixels are checked on the fine depths directly.
    void set_direct_area(int pixels) { direct_area_ = std::max(pixels, 0); }
    // How many cells and pixels a query may look at below its starting level before it gives up and
    // answers "not hidden" (conservatively). 0 = never refine.
    void set_refine_budget(int cells) { refine_budget_ = std::max(cells, 0); }

    // Sizes the pyramid for a width x height depth buffer and sets every level to +infinity.
    // Allocates only when the total size grows. The fine level is unknown until the next update().
    void reset(uint32_t width, uint32_t height) { reset_window(0, 0, width, height, width); }

    // A pyramid over the width x height pixels from image pixel (x, y) on, of a fine depth buffer
    // whose rows are `stride` pixels apart (x + width <= stride). Queries and updates still name
    // image pixels; whatever lies outside the window is clamped off.
    void reset_window(int32_t x, int32_t y, uint32_t width, uint32_t height, uint32_t stride) {
        fine_ = nullptr;
        origin_x_ = x;
        origin_y_ = y;
        stride_ = stride;
        if (int32_t(width) != width_ || int32_t(height) != height_ || requested_base_ != base_) {
            width_ = int32_t(width);
            height_ = int32_t(height);
            base_ = requested_base_;
            const int32_t cell = int32_t(1) << base_;
            int32_t w = (width_ + cell - 1) >> base_, h = (height_ + cell - 1) >> base_;
            top_ = base_;
            size_t total = 0;
            for (;;) {
                level_width_[top_] = w;
                level_height_[top_] = h;
                offset_[top_] = total;
                total += size_t(w) * size_t(h);
                if ((w <= 1 && h <= 1) || top_ + 1 >= kMaxLevels) break;
                w = (w + 1) / 2;
                h = (h + 1) / 2;
                ++top_;
            }
            if (total > storage_.size()) storage_.resize(total);
            total_ = total;
            const size_t base_cells = size_t(level_width_[base_]) * size_t(level_height_[base_]);
            if (base_cells > dirty_flag_.size()) dirty_flag_.resize(base_cells);
            dirty_list_.reserve(base_cells);
            base_cells_ = base_cells;
        }
        std::fill_n(storage_.data(), total_, std::numeric_limits<float>::infinity());
        std::fill_n(dirty_flag_.data(), base_cells_, uint8_t(0));
        dirty_list_.clear();
    }

    // True when every pixel centre in the inclusive rectangle [x0,x1] x [y0,y1], clamped to the image,
    // already holds a depth strictly nearer than nearest_depth: anything whose depth over that
    // rectangle is >= nearest_depth is hidden. An empty rectangle (after clamping) is hidden.
    bool is_hidden(int32_t x0, int32_t y0, int32_t x1, int32_t y1, float nearest_depth) const {
        to_window(x0, y0, x1, y1);
        x0 = std::max(x0, 0);
        y0 = std::max(y0, 0);
        x1 = std::min(x1, width_ - 1);
        y1 = std::min(y1, height_ - 1);
        if (x0 > x1 || y0 > y1) return true;
        if (fine_ != nullptr && int64_t(x1 - x0 + 1) * (y1 - y0 + 1) <= direct_area_) {
            // The covering cells as they are, without flushing: cells never go below the truth when
            // depths only decrease, so "nearer" there is a safe answer; otherwise ask the fine depths.
            const int level = start_level(x0, y0, x1, y1);
            if (cells_nearer(level, x0 >> level, y0 >> level, x1 >> level, y1 >> level, nearest_depth)) return true;
            return fine_nearer(x0, y0, x1, y1, nearest_depth);
        }
        return refined_is_hidden(x0, y0, x1, y1, nearest_depth);
    }

    // An upper bound of the depths over the rectangle (clamped; -infinity when empty): the largest of
    // the at most 2 x 2 cells of the coarsest level that covers it (flushing deferred marks first).
    // O(1): "farthest(rectangle) < z" is a coarse, never refined is_hidden.
    float farthest(int32_t x0, int32_t y0, int32_t x1, int32_t y1) const {
        to_window(x0, y0, x1, y1);
        x0 = std::max(x0, 0);
        y0 = std::max(y0, 0);
        x1 = std::min(x1, width_ - 1);
        y1 = std::min(y1, height_ - 1);
        if (x0 > x1 || y0 > y1) return -std::numeric_limits<float>::infinity();
        flush();
        const int level = start_level(x0, y0, x1, y1);
        float m = -std::numeric_limits<float>::infinity();
        for (int32_t cy = y0 >> level; cy <= (y1 >> level); ++cy)
            for (int32_t cx = x0 >> level; cx <= (x1 >> level); ++cx) {
                ++cells_visited_;
                m = std::max(m, cell(level, cx, cy));
            }
        return m;
    }

    // Call after writing depths inside [x0,x1] x [y0,y1] of the fine depth buffer `depth` (row-major,
    // width * height; the same array every time until the next reset): recomputes the farthest depth
    // upward through the levels over that rectangle, stopping at the first level that did not change.
    void update(const float* depth, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
        fine_ = window_of(depth);
        to_window(x0, y0, x1, y1);
        x0 = std::max(x0, 0);
        y0 = std::max(y0, 0);
        x1 = std::min(x1, width_ - 1);
        y1 = std::min(y1, height_ - 1);
        if (x0 > x1 || y0 > y1) return;
        switch (base_) {
            case 1: update_base<1>(x0, y0, x1, y1); break;
            case 2: update_base<2>(x0, y0, x1, y1); break;
            case 3: update_base<3>(x0, y0, x1, y1); break;
            case 4: update_base<4>(x0, y0, x1, y1); break;
            default: update_base<5>(x0, y0, x1, y1); break;
        }
    }

    // Deferred update: note that depths of `depth` (as for update()) were written inside
    // [x0,x1] x [y0,y1]; the base cells over it are flagged, and brought up to date, with the levels
    // above them, by flush() or automatically by the next query of a large rectangle. Cheaper than
    // update() when many small writes land in the same cells between large queries. Only valid
    // while depths never increase (see the top of this file).
    void mark_dirty(const float* depth, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
        fine_ = window_of(depth);
        to_window(x0, y0, x1, y1);
        if (x1 < 0 || y1 < 0 || x0 >= width_ || y0 >= height_) return;
        x0 = std::max(x0, 0) >> base_;
        y0 = std::max(y0, 0) >> base_;
        x1 = std::min(x1, width_ - 1) >> base_;
        y1 = std::min(y1, height_ - 1) >> base_;
        const int32_t w = level_width_[base_];
        for (int32_t y = y0; y <= y1; ++y)
            for (int32_t x = x0; x <= x1; ++x) {
                const uint32_t index = uint32_t(y) * uint32_t(w) + uint32_t(x);
                if (dirty_flag_[index]) continue;
                dirty_flag_[index] = 1;
                dirty_list_.push_back(index);  // capacity reserved by reset(): never allocates
            }
    }
    bool has_dirty() const { return !dirty_list_.empty(); }
    void flush() const {
        if (dirty_list_.empty()) return;
        switch (base_) {
            case 1: flush_base<1>(); break;
            case 2: flush_base<2>(); break;
            case 3: flush_base<3>(); break;
            case 4: flush_base<4>(); break;
            default: flush_base<5>(); break;
        }
    }

    // Geometry: the stored levels are base_level() .. top_level(); level k has level_width(k) x
    // level_height(k) cells of 2^k x 2^k pixels.
    int32_t width() const { return width_; }
    int32_t height() const { return height_; }
    int base_level() const { return base_; }
    int top_level() const { return top_; }
    int32_t level_width(int k) const { return level_width_[k]; }
    int32_t level_height(int k) const { return level_height_[k]; }
    // The farthest depth in cell (cx, cy) of a stored level k.
    float cell(int k, int32_t cx, int32_t cy) const {
        return storage_[offset_[k] + size_t(cy) * level_width_[k] + size_t(cx)];
    }
    // The cells of stored level k, row by row, as they are (deferred marks not flushed).
    const float* level_cells(int k) const { return storage_.data() + offset_[k]; }
    // The level a query of the rectangle (clamped, non-empty) starts at: the coarsest whose cells
    // are as large as the rectangle, where it meets at most 2 x 2 of them.
    int query_level(int32_t x0, int32_t y0, int32_t x1, int32_t y1) const {
        to_window(x0, y0, x1, y1);
        return start_level(std::max(x0, 0), std::max(y0, 0), std::min(x1, width_ - 1), std::min(y1, height_ - 1));
    }

    // For the steps of a renderer (ABI 1.3; nothing here is used by render()):
    // The level that answered is_hidden() of the rectangle and depth, asked right after it with its
    // answer: for "hidden", query_level() when the cells there alone are nearer, else 0 (finer
    // levels or the fine depths were needed); for "visible", query_level(). Counts nothing.
    int answering_level(int32_t x0, int32_t y0, int32_t x1, int32_t y1, float nearest_depth, bool hidden) const {
        const int level = query_level(x0, y0, x1, y1);
        if (!hidden) return level;
        to_window(x0, y0, x1, y1);
        const int32_t cx0 = std::max(x0, 0) >> level, cy0 = std::max(y0, 0) >> level;
        const int32_t cx1 = std::min(x1, width_ - 1) >> level, cy1 = std::min(y1, height_ - 1) >> level;
        for (int32_t cy = cy0; cy <= cy1; ++cy)
            for (int32_t cx = cx0; cx <= cx1; ++cx)
                if (!(cell(level, cx, cy) < nearest_depth)) return 0;
        return level;
    }
    // "level 5 (32x32 cells)", or "level 0 (the depth buffer)", for a step's text; in Russian
    // "уровне 5 (сетка 32×32)", to follow "на".
    void describe_level(int level, char (&out)[64], bool russian = false) const {
        if (level <= 0)
            std::snprintf(out, sizeof out, "%s", russian ? "уровне 0 (сам буфер глубины)" : "level 0 (the depth buffer)");
        else
            std::snprintf(out, sizeof out, russian ? "уровне %d (сетка %d×%d)" : "level %d (%dx%d cells)", level,
                          int(level_width_[level]), int(level_height_[level]));
    }
    // Hands every stored level, as it is (deferred marks not flushed), to steps.buffer() (an
    // hsr::sdk::Steps) as "z-pyramid-<level>"; valid until the pyramid changes.
    template <class Steps>
    void add_step_buffers(Steps& steps) const {
        static constexpr const char* names[kMaxLevels] = {
            "z-pyramid-0",  "z-pyramid-1",  "z-pyramid-2",  "z-pyramid-3",  "z-pyramid-4",  "z-pyramid-5",
            "z-pyramid-6",  "z-pyramid-7",  "z-pyramid-8",  "z-pyramid-9",  "z-pyramid-10", "z-pyramid-11",
            "z-pyramid-12", "z-pyramid-13", "z-pyramid-14", "z-pyramid-15", "z-pyramid-16", "z-pyramid-17",
            "z-pyramid-18", "z-pyramid-19", "z-pyramid-20", "z-pyramid-21", "z-pyramid-22", "z-pyramid-23",
            "z-pyramid-24", "z-pyramid-25", "z-pyramid-26", "z-pyramid-27", "z-pyramid-28", "z-pyramid-29",
            "z-pyramid-30", "z-pyramid-31"};
        for (int k = base_; k <= top_; ++k)
            steps.buffer(names[k], uint32_t(level_width_[k]), uint32_t(level_height_[k]), level_cells(k));
    }

    // Work counters, cumulative until reset_counters() (reset() does not clear them).
    uint64_t cells_visited() const { return cells_visited_; }  // cells and fine pixels read by queries
    uint64_t cells_updated() const { return cells_updated_; }  // cells recomputed by updates
    void reset_counters() { cells_visited_ = cells_updated_ = 0; }

private:
    // Image coordinates to the window's.
    void to_window(int32_t& x0, int32_t& y0, int32_t& x1, int32_t& y1) const {
        x0 -= origin_x_;
        x1 -= origin_x_;
        y0 -= origin_y_;
        y1 -= origin_y_;
    }
    const float* window_of(const float* depth) const {
        return depth + size_t(origin_y_) * size_t(stride_) + size_t(origin_x_);
    }

    // is_hidden() of a large rectangle (clamped, non-empty): flush, then refine from the start level.
    // Out of line, so that the small-rectangle path inlines into its callers.
    [[gnu::noinline]] bool refined_is_hidden(int32_t x0, int32_t y0, int32_t x1, int32_t y1, float z) const {
        flush();
        const int level = start_level(x0, y0, x1, y1);
        int budget = refine_budget_;
        return all_nearer(level, x0 >> level, y0 >> level, x1 >> level, y1 >> level, x0, y0, x1, y1, z, budget);
    }

    int start_level(int32_t x0, int32_t y0, int32_t x1, int32_t y1) const {
        const int level = int(std::bit_width(uint32_t(std::max(x1 - x0, y1 - y0))));
        return std::clamp(level, base_, top_);
    }

    // Every cell of [cx0,cx1] x [cy0,cy1] of a stored level is strictly nearer than z.
    bool cells_nearer(int level, int32_t cx0, int32_t cy0, int32_t cx1, int32_t cy1, float z) const {
        const float* data = storage_.data() + offset_[level];
        const int32_t w = level_width_[level];
        for (int32_t cy = cy0; cy <= cy1; ++cy)
            for (int32_t cx = cx0; cx <= cx1; ++cx) {
                ++cells_visited_;
                if (!(data[size_t(cy) * w + cx] < z)) return false;
            }
        return true;
    }

    // Every fine pixel of the (clamped, non-empty) rectangle is strictly nearer than z. Rows of at
    // least 4 pixels are compared 4 at a time (SSE2, the x86-64 baseline), the last group of a row
    // overlapping the one before: one branch per group instead of one per pixel, which the
    // data-dependent exit otherwise mispredicts.
    bool fine_nearer(int32_t x0, int32_t y0, int32_t x1, int32_t y1, float z) const {
        const int32_t w = x1 - x0 + 1;
#if defined(__SSE2__)
        if (w >= 4) {
            const __m128 limit = _mm_set1_ps(z);
            for (int32_t y = y0; y <= y1; ++y) {
                const float* row = fine_ + size_t(y) * size_t(stride_) + size_t(x0);
                bool nearer = true;
                for (int32_t x = 0; x + 4 <= w && nearer; x += 4)
                    nearer = _mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(row + x), limit)) == 0xF;
                if (nearer && (w & 3) != 0)
                    nearer = _mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(row + w - 4), limit)) == 0xF;
                if (!nearer) {
                    cells_visited_ += uint64_t(y - y0 + 1) * uint64_t(w);
                    return false;
                }
            }
            cells_visited_ += uint64_t(y1 - y0 + 1) * uint64_t(w);
            return true;
        }
#endif
        for (int32_t y = y0; y <= y1; ++y) {
            const float* row = fine_ + size_t(y) * size_t(stride_);
            for (int32_t x = x0; x <= x1; ++x) {
                if (!(row[x] < z)) {
                    cells_visited_ += uint64_t(y - y0) * uint64_t(w) + uint64_t(x - x0 + 1);
                    return false;
                }
            }
        }
        cells_visited_ += uint64_t(y1 - y0 + 1) * uint64_t(w);
        return true;
    }

    // Every pixel of the rectangle (x0..y1, pixel units) inside cells [cx0,cx1] x [cy0,cy1] of
    // `level` is strictly nearer than z.
    bool all_nearer(int level, int32_t cx0, int32_t cy0, int32_t cx1, int32_t cy1, int32_t x0, int32_t y0, int32_t x1,
                    int32_t y1, float z, int& budget) const {
        const float* data = storage_.data() + offset_[level];
        const int32_t w = level_width_[level];
        for (int32_t cy = cy0; cy <= cy1; ++cy) {
            const float* row = data + size_t(cy) * w;
            for (int32_t cx = cx0; cx <= cx1; ++cx) {
                ++cells_visited_;
                if (row[cx] < z) continue;
                if (level == base_) {
                    // Refine into the fine pixels of this cell inside the rectangle.
                    if (fine_ == nullptr) return false;
                    const int32_t px0 = std::max(cx << level, x0), px1 = std::min(((cx + 1) << level) - 1, x1);
                    const int32_t py0 = std::max(cy << level, y0), py1 = std::min(((cy + 1) << level) - 1, y1);
                    budget -= (px1 - px0 + 1) * (py1 - py0 + 1);
                    if (budget < 0 || !fine_nearer(px0, py0, px1, py1, z)) return false;
                    continue;
                }
                // Refine: the children of (cx, cy) that meet the rectangle.
                const int below = level - 1;
                const int32_t lo_x = std::max(2 * cx, x0 >> below), hi_x = std::min(2 * cx + 1, x1 >> below);
                const int32_t lo_y = std::max(2 * cy, y0 >> below), hi_y = std::min(2 * cy + 1, y1 >> below);
                budget -= (hi_x - lo_x + 1) * (hi_y - lo_y + 1);
                if (budget < 0) return false;
                if (!all_nearer(below, lo_x, lo_y, hi_x, hi_y, x0, y0, x1, y1, z, budget)) return false;
            }
        }
        return true;
    }

    // The farthest fine depth of base cell (cx, cy) of 2^B x 2^B pixels.
    template <int B>
    float base_cell_max(int32_t cx, int32_t cy) const {
        constexpr int32_t n = int32_t(1) << B;
        const int32_t px = cx << B, py = cy << B;
        const float* p = fine_ + size_t(py) * size_t(stride_) + size_t(px);
        if (px + n <= width_ && py + n <= height_) {
            // A whole block: lane-wise maxima over the rows (vectorizes), then across the lanes.
            float lanes[n];
            for (int32_t i = 0; i < n; ++i) lanes[i] = p[i];
            for (int32_t r = 1; r < n; ++r) {
                const float* row = p + size_t(r) * size_t(stride_);
                for (int32_t i = 0; i < n; ++i) lanes[i] = lanes[i] < row[i] ? row[i] : lanes[i];
            }
            float m = lanes[0];
            for (int32_t i = 1; i < n; ++i) m = std::max(m, lanes[i]);
            return m;
        }
        const int32_t w = std::min(n, width_ - px), h = std::min(n, height_ - py);
        float m = -std::numeric_limits<float>::infinity();
        for (int32_t r = 0; r < h; ++r) {
            const float* row = p + size_t(r) * size_t(stride_);
            for (int32_t i = 0; i < w; ++i) m = std::max(m, row[i]);
        }
        return m;
    }

    template <int B>
    void flush_base() const {
        float* base = storage_.data() + offset_[B];
        const int32_t w = level_width_[B];
        for (const uint32_t index : dirty_list_) {
            dirty_flag_[index] = 0;
            int32_t cx = int32_t(index % uint32_t(w)), cy = int32_t(index / uint32_t(w));
            ++cells_updated_;
            const float m = base_cell_max<B>(cx, cy);
            if (m == base[index]) continue;
            base[index] = m;
            for (int k = B + 1; k <= top_; ++k) {  // up the levels while the maximum changes
                cx >>= 1;
                cy >>= 1;
                const float parent = parent_of(k, cx, cy);
                float& out = storage_[offset_[k] + size_t(cy) * level_width_[k] + size_t(cx)];
                ++cells_updated_;
                if (parent == out) break;
                out = parent;
            }
        }
        dirty_list_.clear();
    }

    // The bounding rectangle of the cells of one level whose value changed.
    struct ChangedCells {
        int32_t x0 = std::numeric_limits<int32_t>::max(), y0 = -1, x1 = -1, y1 = -1;
        bool empty() const { return y1 < 0; }
        void add(int32_t x, int32_t y) {  // rows come in increasing order
            x0 = std::min(x0, x);
            x1 = std::max(x1, x);
            if (y1 < 0) y0 = y;
            y1 = y;
        }
    };

    // Cells [x0,x1] x [y0,y1] of stored level k get value(x, y); returns those that changed.
    template <class Value>
    ChangedCells recompute_cells(int k, int32_t x0, int32_t y0, int32_t x1, int32_t y1, Value&& value) {
        ChangedCells changed;
        float* here = storage_.data() + offset_[k];
        const int32_t w = level_width_[k];
        for (int32_t y = y0; y <= y1; ++y) {
            float* out = here + size_t(y) * w;
            for (int32_t x = x0; x <= x1; ++x) {
                const float m = value(x, y);
                if (m != out[x]) {
                    out[x] = m;
                    changed.add(x, y);
                }
            }
        }
        cells_updated_ += uint64_t(x1 - x0 + 1) * uint64_t(y1 - y0 + 1);
        return changed;
    }

    // The farthest of the (up to) 2 x 2 cells of level k - 1 under cell (cx, cy) of level k.
    float parent_of(int k, int32_t cx, int32_t cy) const {
        const float* below = storage_.data() + offset_[k - 1];
        const int32_t below_w = level_width_[k - 1], below_h = level_height_[k - 1];
        const float* row_a = below + size_t(2 * cy) * below_w;
        const float* row_b = below + size_t(std::min(2 * cy + 1, below_h - 1)) * below_w;
        const int32_t a = 2 * cx, b = std::min(2 * cx + 1, below_w - 1);
        return std::max(std::max(row_a[a], row_a[b]), std::max(row_b[a], row_b[b]));
    }

    // update(): the base cells over the pixel rectangle from the fine depths, then each level above
    // over the cells that changed below, until none did.
    template <int B>
    void update_base(int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
        ChangedCells changed = recompute_cells(B, x0 >> B, y0 >> B, x1 >> B, y1 >> B,
                                               [&](int32_t x, int32_t y) { return base_cell_max<B>(x, y); });
        for (int k = B + 1; k <= top_ && !changed.empty(); ++k)
            changed = recompute_cells(k, changed.x0 >> 1, changed.y0 >> 1, changed.x1 >> 1, changed.y1 >> 1,
                                      [&](int32_t x, int32_t y) { return parent_of(k, x, y); });
    }

    int32_t width_ = -1, height_ = -1;  // of the window
    int32_t origin_x_ = 0, origin_y_ = 0;  // the window's first pixel in the image
    size_t stride_ = 0;                    // of the fine depth buffer's rows
    int base_ = 3, requested_base_ = 3;
    int top_ = 3;
    int32_t level_width_[kMaxLevels] = {};
    int32_t level_height_[kMaxLevels] = {};
    size_t offset_[kMaxLevels] = {};
    size_t total_ = 0;
    const float* fine_ = nullptr;
    mutable std::vector<float> storage_;  // mutable: queries flush deferred marks first
    mutable std::vector<uint8_t> dirty_flag_;     // per base cell: in dirty_list_
    mutable std::vector<uint32_t> dirty_list_;    // base cells marked since the last flush
    size_t base_cells_ = 0;
    int direct_area_ = 256;
    int refine_budget_ = 256;
    mutable uint64_t cells_visited_ = 0;
    mutable uint64_t cells_updated_ = 0;
};

// The step buffers of ZPyramid::add_step_buffers ("z-pyramid-<level>") in Russian, for the plugin's
// `translations`.
inline constexpr std::array<hsr::sdk::TranslationSpec, 1> zpyramid_buffer_translations{{
    {"ru", "buffer:z-pyramid", "z-пирамида"},
}};

}  // namespace hsr::raster
