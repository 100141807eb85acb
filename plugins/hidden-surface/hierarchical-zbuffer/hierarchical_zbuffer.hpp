// hierarchical-zbuffer: the z-pyramid half of Ned Greene, Michael Kass and Gavin Miller,
// "Hierarchical Z-Buffer Visibility", SIGGRAPH 1993 (section 4; the object-space octree half is the
// octree-zbuffer plugin). Triangles are drawn in scene order as by the plain z-buffer, but before a
// triangle is set up its screen bounding box and the nearest depth its samples can have are tested
// against a z-pyramid (hsr/zpyramid.hpp: the farthest depth of each 2^k x 2^k block, for k from 3
// up to one cell), and the triangle is rejected when everything under that box is already nearer.
// A triangle larger than a tile (32 x 32 by default) is rasterized tile by tile, each tile tested
// first, in O(1), against the pyramid cells that cover it. Written pixels mark the pyramid's cells
// for a deferred update. In a scene with instances (ABI 1.1) instances are drawn nearest first, and
// a whole instance whose projected world box is hidden is skipped before its vertices are
// transformed. While the test rarely culls (a front-faces-only mesh, the nearest objects of a
// scene) only every 8th triangle is tested, which keeps the cost of a useless test small.
//
// Coverage, depth and barycentrics are those of the zbuffer plugin bit for bit (hsr/raster.hpp's
// GeometryStage, integer edge functions with the top-left rule, raster::depth_at): the pyramid only
// removes work whose outcome would have been "not nearer". The image is cut into square screen
// tiles (parameter screen-tile-size), each drawn by its own TileDrawer, with its own z-pyramid over
// its pixels only, in parallel on oneTBB; every pixel still sees its candidate writes in the same
// order, less some that would not have been written, so tiles do not change the buffers.
// docs/algorithms/hierarchical-zbuffer.md describes the steps, the counters and measured times.
// This header holds the whole plugin, so that hierarchical_zbuffer_steps.cpp can compile its drawing
// with steps apart (hsr::sdk::StepsDrawing); hierarchical_zbuffer.cpp exports it. It is over 700
// lines: the per-tile drawing and its steps read best next to the plugin.
#pragma once

#include "hsr/bounds.hpp"
#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"
#include "hsr/zpyramid.hpp"

#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

namespace hierarchical_zbuffer {

namespace raster = hsr::raster;
using hsr::sdk::ParamSpec;

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// A float that is strictly below every float a sample of depth >= x (a double) can store: x held to
// [0, 1] as raster::depth_at holds it, rounded, then one float step down (so rounding differences in
// the double plane evaluation of nearby samples cannot make one of them nearer).
inline float depth_lower_bound(double x) {
    x -= 1e-9;  // room for rounding in the double plane evaluation where float steps are tiny (near 0)
    const float f = float(std::max(0.0, std::min(x, 1.0)));  // NaN becomes 0
    if (!(f > 0.0f)) return -1.0f;                              // nothing stored is below 0
    return std::bit_cast<float>(std::bit_cast<uint32_t>(f) - 1u);  // the next float down (f in (0, 1])
}

// The smallest value of an affine plane over the pixel centres of the rectangle [i0, i1] x [j0, j1]
// (relative to the setup's origin pixel): reached at a corner.
inline double plane_min(const raster::Plane& p, double i0, double j0, double i1, double j1) {
    const double a = p.at(i0, j0), b = p.at(i1, j0), c = p.at(i0, j1), d = p.at(i1, j1);
    return std::min(std::min(a, b), std::min(c, d));
}

struct Stats {
    uint64_t depth_tested = 0;
    uint64_t written = 0;
    uint64_t triangles_culled = 0;  // before setup: not in the geometry stage's counts
    uint64_t pieces_culled = 0;
    uint64_t triangles_untested = 0;  // drawn without a pyramid test (sampling, see draw())     // clipped pieces, after setup (their triangle counts as rasterized)
    uint64_t tiles_tested = 0;
    uint64_t tiles_culled = 0;
    uint64_t instances_culled = 0;
    uint64_t instances_outside = 0;
    uint64_t instance_triangles_skipped = 0;  // triangles of culled or outside instances

    void add(const Stats& o) {
        depth_tested += o.depth_tested;
        written += o.written;
        triangles_culled += o.triangles_culled;
        pieces_culled += o.pieces_culled;
        triangles_untested += o.triangles_untested;
        tiles_tested += o.tiles_tested;
        tiles_culled += o.tiles_culled;
        instances_culled += o.instances_culled;
        instances_outside += o.instances_outside;
        instance_triangles_skipped += o.instance_triangles_skipped;
    }
};

// A placement's world box seen by the camera (hsr/bounds.hpp): the pixels and nearest depth of
// its 8 corners, when they are all beyond the near plane.
struct PlacementBox {
    int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    float nearest = -kInfinity;
    bool projectable = false;  // every corner beyond the near plane: the rectangle and depth bound hold
    bool outside = false;      // out of view: beyond one frustum plane, or the rectangle misses the image
};

// Image pixels [x0, x1] x [y0, y1], inclusive.
struct PixelTile {
    int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};

// Draws the pixels of one screen tile, with its own geometry stage and its own z-pyramid over the
// tile's pixels only: tiles of one frame read and write disjoint pixels, and can be drawn at once.
class TileDrawer {
public:
    TileDrawer(const std::vector<uint32_t>& order, const std::vector<PlacementBox>& boxes, bool cull_backfaces,
               int32_t tile_size, bool cull_instances)
        : order_(order), boxes_(boxes), cull_backfaces_(cull_backfaces), tile_size_(tile_size),
          cull_instances_(cull_instances) {}

    // Draws the pixels inside `tile` with `geometry`, a geometry stage no other tile uses meanwhile
    // (one per thread: its vertex buffers are as long as the scene's, too large to keep one per tile).
    template <class Steps>
    void draw(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
              const PixelTile& tile, raster::GeometryStage& geometry, Steps& steps) {
        tile_ = tile;
        geometry_ = &geometry;
        geometry_->begin_frame(scene.raw(), camera, cull_backfaces_);
        width_ = int32_t(target.width());
        height_ = int32_t(target.height());
        pyramid_.reset_window(tile.x0, tile.y0, uint32_t(tile.x1 - tile.x0 + 1), uint32_t(tile.y1 - tile.y0 + 1),
                              target.width());
        pyramid_.reset_counters();
        stats_ = Stats{};
        struct Done {  // also when a step limit ends the frame early
            TileDrawer& tile;
            ~Done() {
                tile.triangle_stats_ = tile.geometry_->stats();
                tile.geometry_ = nullptr;
            }
        } done{*this};
        if (target.depth_tests() == nullptr)
            draw<false>(scene, target, stats_, steps);
        else
            draw<true>(scene, target, stats_, steps);
    }

    const Stats& stats() const { return stats_; }
    raster::TriangleStats triangle_stats() const { return triangle_stats_; }
    uint64_t pyramid_cells_visited() const { return pyramid_.cells_visited(); }
    uint64_t pyramid_cells_updated() const { return pyramid_.cells_updated(); }

private:
    bool misses_tile(int32_t x0, int32_t y0, int32_t x1, int32_t y1) const {
        return x1 < tile_.x0 || x0 > tile_.x1 || y1 < tile_.y0 || y0 > tile_.y1;
    }

    template <bool kCountTests, class Steps>
    void draw(const hsr::sdk::Scene& scene, hsr::sdk::VisibilityBuffer& target, Stats& stats, Steps& steps) {
        const raster::PixelBuffers buffers(target);
        for (const uint32_t k : order_) {
            const PlacementBox& box = boxes_[k];
            if (box.outside || (box.projectable && misses_tile(box.x0, box.y0, box.x1, box.y1))) {
                ++stats.instances_outside;
                stats.instance_triangles_skipped += scene.instance(k).triangle_count;
                if constexpr (Steps::enabled) instance_step(steps, k, scene.instance(k).triangle_count, false);
                continue;
            }
            if (box.projectable && cull_instances_ &&
                pyramid_.is_hidden(box.x0, box.y0, box.x1, box.y1, box.nearest)) {
                ++stats.instances_culled;
                stats.instance_triangles_skipped += scene.instance(k).triangle_count;
                if constexpr (Steps::enabled) instance_step(steps, k, scene.instance(k).triangle_count, true);
                continue;
            }
            const hsr::sdk::Placement placement = scene.placement(k);
            geometry_->place(placement);
            const uint32_t end = placement.first_triangle + placement.triangle_count;
            const uint32_t* const indices = scene.raw().indices;
            // Test feedback, per placement: while the pyramid rarely culls (the near parts of a scene,
            // a front-faces-only mesh) only every stride-th triangle is tested.
            constexpr uint32_t kWindow = 64, kStride = 8;
            uint32_t stride = 1, countdown = 1, window_tests = 0, window_culls = 0;
            // With steps, triangle t's is reported after its body, `continue` included.
            for (uint32_t t = placement.first_triangle; t < end;
                 triangle_step(steps, t, placement.instance, stats, indices), ++t) {
                if constexpr (Steps::enabled) begin_triangle_step(stats);
                const uint32_t i0 = indices[3 * t], i1 = indices[3 * t + 1], i2 = indices[3 * t + 2];
                const uint32_t c0 = geometry_->vertex_outcode(i0), c1 = geometry_->vertex_outcode(i1),
                               c2 = geometry_->vertex_outcode(i2);
                if (!((c0 | c1 | c2) & (raster::kNeedsClipping | raster::kNonFinite))) {
                    // Greene's triangle-level test, before triangle setup. Triangles the geometry
                    // stage rejects anyway (outside, back-facing, no pixel centre) go straight to it,
                    // to be counted; it decides, so they still get the drawing callback.
                    auto draw_whole = [&](const raster::TriangleSetup& s) {
                        draw_piece<kCountTests>(s, t, placement.instance, -std::numeric_limits<double>::infinity(),
                                                true, buffers, stats, steps);
                    };
                    if (c0 & c1 & c2 & raster::kOutsideAnyPlane) {
                        geometry_->process(t, draw_whole);
                        continue;
                    }
                    const raster::WindowVertex& a = geometry_->window_vertex(i0);
                    const raster::WindowVertex& b = geometry_->window_vertex(i1);
                    const raster::WindowVertex& c = geometry_->window_vertex(i2);
                    // Clockwise in window coordinates (y down) is front-facing; the geometry stage's
                    // clip-space test is the one that counts, this only saves work.
                    const double cross = (b.exact_x - a.exact_x) * (c.exact_y - a.exact_y) -
                                         (c.exact_x - a.exact_x) * (b.exact_y - a.exact_y);
                    if (cull_backfaces_ && !(cross < 0.0)) {
                        geometry_->process(t, draw_whole);
                        continue;
                    }
                    if (--countdown > 0) {  // sampling: this one is drawn untested
                        ++stats.triangles_untested;
                        geometry_->process(t, [&](const raster::TriangleSetup& s) {
                            draw_piece<kCountTests>(s, t, placement.instance,
                                                    -std::numeric_limits<double>::infinity(), false, buffers, stats,
                                                    steps);
                        });
                        continue;
                    }
                    countdown = stride;
                    // The pixel centres the snapped triangle can cover, exactly as setup_triangle
                    // bounds them, against the nearest depth its samples can have.
                    const int32_t x0 = std::max(raster::first_pixel_from(std::min({a.x, b.x, c.x})), 0);
                    const int32_t x1 = std::min(raster::last_pixel_to(std::max({a.x, b.x, c.x})), width_ - 1);
                    const int32_t y0 = std::max(raster::first_pixel_from(std::min({a.y, b.y, c.y})), 0);
                    const int32_t y1 = std::min(raster::last_pixel_to(std::max({a.y, b.y, c.y})), height_ - 1);
                    if (x0 > x1 || y0 > y1) {  // no pixel centre in the image: degenerate or outside
                        geometry_->process(t, draw_whole);
                        continue;
                    }
                    if (misses_tile(x0, y0, x1, y1)) continue;  // another tile's
                    const double lower = triangle_lower_depth(a, b, c, std::abs(cross));
                    const bool hidden = pyramid_.is_hidden(x0, y0, x1, y1, depth_lower_bound(lower));
                    if constexpr (Steps::enabled) step_.query = {x0, y0, x1, y1, depth_lower_bound(lower), true};
                    window_culls += hidden ? 1 : 0;
                    if (++window_tests == kWindow) {
                        // Fewer than 1 in 16 tests culled: test only every kStride-th triangle for a while.
                        stride = window_culls * 16 < window_tests ? kStride : 1;
                        window_tests = window_culls = 0;
                    }
                    if (hidden) {
                        ++stats.triangles_culled;
                        continue;
                    }
                    geometry_->process(t, [&](const raster::TriangleSetup& s) {
                        draw_piece<kCountTests>(s, t, placement.instance, lower, false, buffers, stats, steps);
                    });
                } else {
                    // Clipped (or non-finite): the geometry stage makes the pieces, each tested whole.
                    geometry_->process(t, [&](const raster::TriangleSetup& s) {
                        draw_piece<kCountTests>(s, t, placement.instance, -std::numeric_limits<double>::infinity(),
                                                true, buffers, stats, steps);
                    });
                }
            }
        }
    }

    // A lower bound of the window depth of every sample the triangle (not clipped) covers: its
    // smallest vertex depth, less how far the depth plane can fall over the 1/512 pixel by which a
    // covered sample may lie outside the unsnapped triangle. The plane's gradient is at most
    // (depth range) * (longest edge) / |twice the area| in each direction (the longest edge bounded
    // by its |dx| + |dy|); a sliver gets no useful bound.
    static double triangle_lower_depth(const raster::WindowVertex& a, const raster::WindowVertex& b,
                                       const raster::WindowVertex& c, double abs_cross) {
        const double d_min = std::min({a.depth, b.depth, c.depth});
        const double d_range = std::max({a.depth, b.depth, c.depth}) - d_min;
        const double lu = std::abs(b.exact_x - a.exact_x) + std::abs(b.exact_y - a.exact_y);
        const double lv = std::abs(c.exact_x - a.exact_x) + std::abs(c.exact_y - a.exact_y);
        const double lw = std::abs(c.exact_x - b.exact_x) + std::abs(c.exact_y - b.exact_y);
        if (!(abs_cross > 1e-6)) return -std::numeric_limits<double>::infinity();
        // Gradient bound times a distance of 1/128 pixel (more than twice the largest snapping offset).
        return d_min - 2.0 * d_range * std::max({lu, lv, lw}) / abs_cross * (1.0 / 128.0);
    }

    // One triangle (or clipped piece): reject it whole, draw it whole, or draw it tile by tile.
    template <bool kCountTests, class Steps>
    void draw_piece(const raster::TriangleSetup& setup, uint32_t id, uint32_t instance_id, double vertex_lower,
                    bool test_whole, const raster::PixelBuffers& buffers, Stats& stats, Steps& steps) {
        // A local copy: stores to face[] (uint32_t) may alias the caller's int32_t fields, which would
        // force the pixel loop to reload them after every write; a local whose address never escapes
        // cannot alias.
        const raster::TriangleSetup s = setup;
        const int32_t tile = tile_size_;
        const bool small = s.max_x - s.min_x < tile && s.max_y - s.min_y < tile;
        double lower = vertex_lower;
        if constexpr (Steps::enabled) step_.box.add(s.min_x, s.min_y, s.max_x, s.max_y);
        if (test_whole || !small) {
            lower = std::max(lower, plane_min(s.depth, 0.0, 0.0, double(s.max_x - s.min_x), double(s.max_y - s.min_y)));
            if constexpr (Steps::enabled)
                if (test_whole) step_.query = {s.min_x, s.min_y, s.max_x, s.max_y, depth_lower_bound(lower), true};
            if (test_whole && pyramid_.is_hidden(s.min_x, s.min_y, s.max_x, s.max_y, depth_lower_bound(lower))) {
                ++stats.pieces_culled;
                return;
            }
        }

        // The setup's bounds within this screen tile.
        const int32_t min_x = std::max(s.min_x, tile_.x0), max_x = std::min(s.max_x, tile_.x1);
        const int32_t min_y = std::max(s.min_y, tile_.y0), max_y = std::min(s.max_y, tile_.y1);
        if (min_x > max_x || min_y > max_y) return;
        raster::DepthTest<raster::DepthRule::kNearer, kCountTests> test(buffers, id, instance_id);
        auto visit = [&](int32_t x, int32_t y, double i, double j) { test(s, x, y, i, j); };
        if (small) {
            raster::for_each_covered_pixel_in(s, min_x, min_y, max_x, max_y, visit);
            stats.depth_tested += test.tested;
            stats.written += test.written;
            if (test.written > 0) note_written(buffers.depth, min_x, min_y, max_x, max_y);
            return;
        }

        // Tile by tile, on a grid aligned with the image.
        const int32_t first_tx = (min_x / tile) * tile, first_ty = (min_y / tile) * tile;
        for (int32_t ty = first_ty; ty <= max_y; ty += tile) {
            const int32_t y0 = std::max(ty, min_y), y1 = std::min(ty + tile - 1, max_y);
            for (int32_t tx = first_tx; tx <= max_x; tx += tile) {
                const int32_t x0 = std::max(tx, min_x), x1 = std::min(tx + tile - 1, max_x);
                if (raster::misses(s, x0, y0, x1, y1)) continue;
                ++stats.tiles_tested;
                const double i0 = x0 - s.min_x, j0 = y0 - s.min_y;
                const double tile_lower = std::max(lower, plane_min(s.depth, i0, j0, i0 + (x1 - x0), j0 + (y1 - y0)));
                // O(1): the pyramid cells covering the tile, not refined (refining a tile that turns
                // out visible measured slower than drawing it).
                if (pyramid_.farthest(x0, y0, x1, y1) < depth_lower_bound(tile_lower)) {
                    ++stats.tiles_culled;
                    if constexpr (Steps::enabled) steps.box(x0, y0, x1 + 1, y1 + 1, HSR_STEP_REJECTED);
                    continue;
                }
                const uint64_t written_before = test.written;
                raster::for_each_covered_pixel_in(s, x0, y0, x1, y1, visit);
                if (test.written != written_before) note_written(buffers.depth, x0, y0, x1, y1);
            }
        }
        stats.depth_tested += test.tested;
        stats.written += test.written;
    }

    // Deferred: the pyramid's cells over the rectangle are recomputed at the next large query
    // (hsr/zpyramid.hpp); valid because this plugin's depths only ever decrease.
    void note_written(const float* depth, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
        pyramid_.mark_dirty(depth, x0, y0, x1, y1);
    }
    // ---- Steps (ABI 1.3) ----

    // A pyramid query, kept for the step that reports it.
    struct PyramidQuery {
        int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
        float nearest = 0.0f;
        bool made = false;
    };
    struct PixelRect {
        int32_t x0 = std::numeric_limits<int32_t>::max(), y0 = std::numeric_limits<int32_t>::max();
        int32_t x1 = std::numeric_limits<int32_t>::min(), y1 = std::numeric_limits<int32_t>::min();
        void add(int32_t ax0, int32_t ay0, int32_t ax1, int32_t ay1) {
            x0 = std::min(x0, ax0);
            y0 = std::min(y0, ay0);
            x1 = std::max(x1, ax1);
            y1 = std::max(y1, ay1);
        }
    };
    // What the step of the triangle being drawn shows, gathered while it is drawn.
    struct TriangleStep {
        Stats before;
        raster::TriangleStats geometry_before;
        PyramidQuery query;  // its test against the pyramid (of its last clipped piece, if clipped)
        PixelRect box;       // the pixel bounds of its setups
    };

    void begin_triangle_step(const Stats& stats) {
        step_.before = stats;
        step_.geometry_before = geometry_->stats();
        step_.query = {};
        step_.box = {};
    }

    int answering_level(const PyramidQuery& q, bool hidden) const {
        return pyramid_.answering_level(q.x0, q.y0, q.x1, q.y1, q.nearest, hidden);
    }

    // The outline of the pixels [x0, x1] x [y0, y1] clipped to the image.
    template <class Steps>
    void add_box(Steps& steps, int32_t x0, int32_t y0, int32_t x1, int32_t y1, hsr_step_role role) const {
        raster::pixel_box_lines(steps, x0, y0, x1, y1, width_, height_, role);
    }
    // Triangle t's outline, when it needs no clipping and lies within a pixel of the image.
    template <class Steps>
    void add_outline(Steps& steps, const uint32_t* corner) const {
        geometry_->outline_lines(steps, corner);
    }

    template <class Steps>
    void instance_step(Steps& steps, uint32_t k, uint32_t triangles, bool hidden) const {
        const PlacementBox& box = boxes_[k];
        const unsigned long long n = triangles;
        const bool ru = steps.russian();
        const char* const triangle_word = hsr::sdk::russian_plural(n, "треугольник", "треугольника", "треугольников");
        if (box.projectable) add_box(steps, box.x0, box.y0, box.x1, box.y1, HSR_STEP_REJECTED);
        pyramid_.add_step_buffers(steps);
        if (!hidden) {
            hsr::sdk::Steps::Event event{"instance-outside", HSR_NO_FACE, k};
            event.phase = "instance-cull";
            if (ru)
                steps.step(event, "экземпляр %u: вне области видимости, пропущен целиком (%llu %s)", k, n,
                           triangle_word);
            else
                steps.step(event, "instance %u: outside the view, its %llu triangles skipped", k, n);
            return;
        }
        const int level = answering_level({box.x0, box.y0, box.x1, box.y1, box.nearest, true}, true);
        char where[64];
        pyramid_.describe_level(level, where, ru);
        hsr::sdk::Steps::Event event{"instance-culled", HSR_NO_FACE, k, uint32_t(level)};
        event.phase = "instance-cull";
        if (ru)
            steps.step(event, "экземпляр %u: закрыт z-пирамидой на %s, пропущен целиком (%llu %s)", k, where, n,
                       triangle_word);
        else
            steps.step(event, "instance %u: hidden behind the z-pyramid at %s, its %llu triangles skipped", k, where,
                       n);
    }

    // The step of triangle t, from what drawing it counted (Stats, the geometry stage's counts)
    // and gathered (step_). Its phase is the last line of the pseudocode it reached
    // (docs/theory/en/hierarchical-zbuffer.md).
    template <class Steps>
    void triangle_step(Steps& steps, uint32_t t, uint32_t instance, const Stats& stats, const uint32_t* indices) {
        if constexpr (Steps::enabled) {
            const Stats& b = step_.before;
            const PyramidQuery& q = step_.query;
            const raster::TriangleStats after = geometry_->stats();
            const raster::TriangleStats& before = step_.geometry_before;
            const uint64_t tested = stats.depth_tested - b.depth_tested, written = stats.written - b.written;
            const unsigned f = t;
            const bool ru = steps.russian();
            const uint32_t* const corner = indices + 3 * size_t(t);
            pyramid_.add_step_buffers(steps);
            if (stats.triangles_culled != b.triangles_culled ||
                (tested == 0 && stats.pieces_culled != b.pieces_culled)) {
                const int level = answering_level(q, true);
                char where[64];
                pyramid_.describe_level(level, where, ru);
                add_outline(steps, corner);
                add_box(steps, q.x0, q.y0, q.x1, q.y1, HSR_STEP_REJECTED);
                hsr::sdk::Steps::Event event{"triangle", t, instance, uint32_t(level), 0, 0};
                event.phase = "pyramid-test";
                steps.step(event, ru ? "треугольник %u: отброшен z-пирамидой на %s"
                                     : "triangle %u: rejected by the z-pyramid at %s", f, where);
                return;
            }
            if (raster::dropped_triangle_step(steps, before, after, t, instance)) return;
            add_outline(steps, corner);
            add_box(steps, step_.box.x0, step_.box.y0, step_.box.x1, step_.box.y1, HSR_STEP_WRITTEN);
            char tiles[96] = "";
            const uint64_t tiles_culled = stats.tiles_culled - b.tiles_culled;
            if (stats.tiles_tested != b.tiles_tested) {
                const unsigned long long c = tiles_culled, n = stats.tiles_tested - b.tiles_tested;
                if (ru)
                    std::snprintf(tiles, sizeof tiles, "; z-пирамида отсекла %llu из %llu %s", c, n,
                                  hsr::sdk::russian_plural(n, "плитки", "плиток", "плиток"));
                else
                    std::snprintf(tiles, sizeof tiles, "; %u of %u tiles culled by the z-pyramid", unsigned(c),
                                  unsigned(n));
            }
            hsr::sdk::Steps::Event event{"triangle", t, instance,
                                         q.made ? uint32_t(answering_level(q, false)) : HSR_NO_LEVEL, written,
                                         tested - written};
            event.phase = written > 0        ? "write"
                          : tested > 0       ? "depth-test"
                          : tiles_culled > 0 ? "pyramid-test"
                                             : "rasterize";
            char drawn[256];
            describe_drawn(tested, written, tiles, ru, drawn);
            if (!q.made) {
                const bool sampled = stats.triangles_untested != b.triangles_untested;
                if (ru)
                    steps.step(event, "треугольник %u: не проверялся по z-пирамиде (%s), %s", f,
                               sampled ? "пока отсечений мало, проверяется лишь каждый восьмой" : "проверка не нужна",
                               drawn);
                else
                    steps.step(event, "triangle %u: not tested against the z-pyramid (%s), %s", f,
                               sampled ? "only sampled while few are culled" : "none needed", drawn);
                return;
            }
            char where[64];
            pyramid_.describe_level(int(event.level), where, ru);
            steps.step(event, ru ? "треугольник %u: не закрыт z-пирамидой на %s, %s"
                                 : "triangle %u: not hidden at z-pyramid %s, %s", f, where, drawn);
        }
    }

    // "drawn: 37 pixels written, 12 rejected by the depth test", or that no pixel centre was covered.
    static void describe_drawn(uint64_t tested, uint64_t written, const char* tiles, bool ru, char (&out)[256]) {
        using hsr::sdk::russian_plural;
        const unsigned long long w = written, r = tested - written;
        if (tested == 0 && tiles[0] == '\0')
            std::snprintf(out, sizeof out, "%s", ru ? "не покрывает ни одного центра пикселя" : "covers no pixel centre");
        else if (ru)
            std::snprintf(out, sizeof out, "нарисован: %s %llu %s, %s тестом глубины %llu%s",
                          russian_plural(w, "записан", "записано", "записано"), w,
                          russian_plural(w, "пиксель", "пикселя", "пикселей"),
                          russian_plural(r, "отброшен", "отброшено", "отброшено"), r, tiles);
        else
            std::snprintf(out, sizeof out, "drawn: %u pixel%s written, %u rejected by the depth test%s",
                          unsigned(written), written == 1 ? "" : "s", unsigned(tested - written), tiles);
    }


    TriangleStep step_;  // with steps only

    const std::vector<uint32_t>& order_;      // placements in drawing order
    const std::vector<PlacementBox>& boxes_;  // their boxes
    bool cull_backfaces_;
    int32_t tile_size_;
    bool cull_instances_;
    PixelTile tile_;
    int32_t width_ = 0, height_ = 0;
    Stats stats_;
    raster::GeometryStage* geometry_ = nullptr;  // the drawing thread's, for the time of draw()
    raster::TriangleStats triangle_stats_;        // what geometry_ counted for this tile
    raster::ZPyramid pyramid_;                    // kept between frames
};

class HierarchicalZBuffer final : public hsr::sdk::StepwiseRemover<HierarchicalZBuffer> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "hierarchical-zbuffer", "1.0.0",
        "hierarchical z-buffer (Greene, Kass & Miller 1993): triangles, tiles and instances culled against a z-pyramid"};
    static inline const ParamSpec params[] = {
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::integer("tile-size", "32", 4, 64,
                           "side in pixels of the tiles a large triangle is rasterized in, each tested against the "
                           "pyramid first; triangles whose box fits in a tile are drawn whole"),
        ParamSpec::boolean("front-to-back", true,
                           "draw instances nearest first (by the nearest corner of their world box), so that "
                           "the pyramid hides the ones behind"),
        ParamSpec::boolean("cull-instances", true,
                           "skip a whole instance whose projected world box is hidden, before transforming it"),
        ParamSpec::integer("screen-tile-size", "512", 0, 65536,
                           "pixels per side of the screen tiles drawn in parallel, rounded up to a multiple of 8 "
                           "(0: the whole image as one tile)"),
    };

    explicit HierarchicalZBuffer(const hsr::sdk::Params& p)
        : cull_backfaces_(p.boolean("cull-backfaces")),
          tile_size_(int32_t(p.integer("tile-size"))),
          front_to_back_(p.boolean("front-to-back")),
          cull_instances_(p.boolean("cull-instances")),
          screen_tile_(int32_t((p.integer("screen-tile-size") + 7) / 8 * 8)) {}

    // render_steps (from StepwiseRemover) takes one step per input triangle in drawing order, and one
    // per instance skipped whole. Compiled in hierarchical_zbuffer_steps.cpp.
    // A step names the last line of the pseudocode (docs/theory/en/hierarchical-zbuffer.md) it reached.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"instance-cull", "skip an instance outside the view or hidden behind the z-pyramid"},
        {"cull", "cull a triangle that faces away or lies outside the view"},
        {"pyramid-test", "test the triangle's box against the z-pyramid"},
        {"rasterize", "find the pixel centres the triangle covers"},
        {"depth-test", "compare the triangle's depth with the depth buffer"},
        {"write", "write the nearer pixels and mark their pyramid cells"},
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description",
         "иерархический z-буфер (Грин, Касс и Миллер, 1993): треугольники, плитки и экземпляры отсекаются по "
         "z-пирамиде"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не рисовать треугольники, повёрнутые к камере нелицевой стороной"},
        {"ru", "param:tile-size", "размер плитки"},
        {"ru", "help:tile-size",
         "сторона в пикселях плиток, на которые делится при растеризации большой треугольник; каждая плитка "
         "сначала проверяется по z-пирамиде, а треугольник, оболочка которого умещается в плитку, рисуется целиком"},
        {"ru", "param:front-to-back", "рисовать от ближних к дальним"},
        {"ru", "help:front-to-back",
         "рисовать экземпляры начиная с ближних (по ближайшей вершине их оболочки в мировых координатах), чтобы "
         "z-пирамида закрывала те, что лежат позади"},
        {"ru", "param:cull-instances", "отсекать экземпляры целиком"},
        {"ru", "help:cull-instances",
         "пропускать весь экземпляр, если его спроецированная оболочка закрыта, ещё до преобразования вершин"},
        {"ru", "param:screen-tile-size", "размер экранного тайла"},
        {"ru", "help:screen-tile-size",
         "сторона в пикселях экранных тайлов, которые рисуются параллельно; округляется вверх до кратного 8 "
         "(0 — всё изображение одним тайлом)"},
        {"ru", "phase:instance-cull", "пропустить экземпляр вне области видимости или закрытый z-пирамидой"},
        {"ru", "phase:cull", "отбросить треугольник, если он нелицевой или лежит вне области видимости"},
        {"ru", "phase:pyramid-test", "проверить оболочку треугольника по z-пирамиде"},
        {"ru", "phase:rasterize", "найти центры пикселей, которые покрывает треугольник"},
        {"ru", "phase:depth-test", "сравнить глубину треугольника с буфером глубины"},
        {"ru", "phase:write", "записать более близкие пиксели и пометить их ячейки z-пирамиды"},
        {"ru", "counter:triangles-culled-by-pyramid", "треугольников отброшено z-пирамидой"},
        {"ru", "counter:clipped-pieces-culled-by-pyramid", "частей отсечённых треугольников отброшено z-пирамидой"},
        {"ru", "counter:triangles-untested", "треугольников нарисовано без проверки по z-пирамиде"},
        {"ru", "counter:tiles-tested", "плиток проверено по z-пирамиде"},
        {"ru", "counter:tiles-culled", "плиток отброшено z-пирамидой"},
        {"ru", "counter:instances-culled", "экземпляров закрыто целиком"},
        {"ru", "counter:instances-outside", "экземпляров вне области видимости"},
        {"ru", "counter:triangles-in-skipped-instances", "треугольников в пропущенных экземплярах"},
        {"ru", "counter:pyramid-cells-visited", "ячеек z-пирамиды прочитано"},
        {"ru", "counter:pyramid-cells-updated", "ячеек z-пирамиды пересчитано"},
        {"ru", "step:instance-outside", "экземпляр вне области видимости"},
        {"ru", "step:instance-culled", "экземпляр, закрытый z-пирамидой"},
    };
    static constexpr auto translations = hsr::sdk::join_translations(
        own_translations, raster::triangle_counter_translations, raster::depth_test_counter_translations,
        raster::zpyramid_buffer_translations, raster::triangle_step_translations);

private:
    friend class hsr::sdk::StepwiseRemover<HierarchicalZBuffer>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        width_ = int32_t(target.width());
        height_ = int32_t(target.height());
        prepare_placements(scene, camera);

        const int32_t size = Steps::enabled || screen_tile_ == 0 ? std::max(width_, height_) : screen_tile_;
        const int32_t across = (width_ + size - 1) / size, down = (height_ + size - 1) / size;
        const size_t count = size_t(across) * size_t(down);
        while (tiles_.size() < count)
            tiles_.push_back(
                std::make_unique<TileDrawer>(order_, boxes_, cull_backfaces_, tile_size_, cull_instances_));
        auto tile = [&](size_t k) {
            PixelTile t;
            t.x0 = int32_t(k % size_t(across)) * size;
            t.y0 = int32_t(k / size_t(across)) * size;
            t.x1 = std::min(t.x0 + size, width_) - 1;
            t.y1 = std::min(t.y0 + size, height_) - 1;
            return t;
        };
        if (count == 1) {
            try {
                tiles_[0]->draw(scene, camera, target, tile(0), geometry_.local(), steps);
            } catch (const hsr::sdk::StepLimitReached&) {
                report(counters, 1);
                throw;
            }
        } else {
            // Tiles own disjoint pixels and pyramids; the placements' order and boxes are only read.
            tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1), [&](const tbb::blocked_range<size_t>& range) {
                for (size_t k = range.begin(); k != range.end(); ++k) {
                    hsr::sdk::NoSteps no_steps;
                    tiles_[k]->draw(scene, camera, target, tile(k), geometry_.local(), no_steps);
                }
            });
        }
        report(counters, count);
    }

    // The counters of the first `count` tiles, summed: a triangle or instance that reaches several
    // tiles is counted in each.
    void report(hsr::sdk::Counters& counters, size_t count) const {
        Stats stats;
        raster::TriangleStats triangles;
        uint64_t cells_visited = 0, cells_updated = 0;
        for (size_t k = 0; k < count; ++k) {
            const TileDrawer& tile = *tiles_[k];
            stats.add(tile.stats());
            const raster::TriangleStats t = tile.triangle_stats();
            triangles.in += t.in;
            triangles.backface_culled += t.backface_culled;
            triangles.clipped += t.clipped;
            triangles.outside += t.outside;
            triangles.degenerate += t.degenerate;
            triangles.rasterized += t.rasterized;
            cells_visited += tile.pyramid_cells_visited();
            cells_updated += tile.pyramid_cells_updated();
        }
        // One tile: what the geometry stage saw, and what never reached it (culled whole, or in
        // skipped instances). Several: the scene's triangles (each tile sees only its own).
        triangles.in += stats.triangles_culled + stats.instance_triangles_skipped;
        if (count > 1) triangles.in = drawn_triangles_;
        triangles.report(counters);
        counters.set("pixels-depth-tested", stats.depth_tested);
        counters.set("pixels-written", stats.written);
        counters.set("triangles-culled-by-pyramid", stats.triangles_culled);
        counters.set("clipped-pieces-culled-by-pyramid", stats.pieces_culled);
        counters.set("triangles-untested", stats.triangles_untested);
        counters.set("tiles-tested", stats.tiles_tested);
        counters.set("tiles-culled", stats.tiles_culled);
        counters.set("instances-culled", stats.instances_culled);
        counters.set("instances-outside", stats.instances_outside);
        counters.set("triangles-in-skipped-instances", stats.instance_triangles_skipped);
        counters.set("pyramid-cells-visited", cells_visited);
        counters.set("pyramid-cells-updated", cells_updated);
    }

    void prepare_placements(const hsr::sdk::Scene& scene, const hsr_camera& camera) {
        const uint32_t n = scene.placement_count();
        drawn_triangles_ = 0;
        for (uint32_t k = 0; k < n; ++k) drawn_triangles_ += scene.placement(k).triangle_count;
        order_.resize(n);
        boxes_.resize(n);
        for (uint32_t k = 0; k < n; ++k) order_[k] = k;
        if (scene.instance_count() == 0) {
            boxes_[0] = PlacementBox{};  // one placement, drawn into an empty buffer: nothing to cull
            return;
        }
        const glm::dmat4 view_projection(hsr::sdk::load_matrix(camera.view_projection));
        const raster::Viewport viewport(camera.width, camera.height);
        for (uint32_t k = 0; k < n; ++k) {
            const hsr_instance& instance = scene.instance(k);
            glm::dvec3 lo(instance.bounds_min[0], instance.bounds_min[1], instance.bounds_min[2]);
            glm::dvec3 hi(instance.bounds_max[0], instance.bounds_max[1], instance.bounds_max[2]);
            // The bounds were computed in float; widen them a little so that every transformed vertex
            // (computed in double by the geometry stage) is surely inside.
            const glm::dvec3 extent = hi - lo;
            const double size = std::max({extent.x, extent.y, extent.z, std::abs(lo.x), std::abs(lo.y),
                                          std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
            lo -= glm::dvec3(1e-5 * size);
            hi += glm::dvec3(1e-5 * size);
            PlacementBox box;
            const raster::ProjectedBox projected = raster::project_box(view_projection, lo, hi, viewport);
            if (projected.in_front) {  // otherwise the projection does not bound the box
                // Pixel centres px + 0.5 within [min_x, max_x], with a pixel to spare for snapping.
                constexpr double limit = 1e9;
                box.x0 = int32_t(std::floor(std::clamp(projected.min_x - 1.5, -limit, limit)));
                box.x1 = int32_t(std::ceil(std::clamp(projected.max_x + 0.5, -limit, limit)));
                box.y0 = int32_t(std::floor(std::clamp(projected.min_y - 1.5, -limit, limit)));
                box.y1 = int32_t(std::ceil(std::clamp(projected.max_y + 0.5, -limit, limit)));
                box.nearest = depth_lower_bound(projected.nearest - raster::kBoxDepthMargin);
                box.projectable = true;
                box.outside = box.x1 < 0 || box.y1 < 0 || box.x0 >= width_ || box.y0 >= height_;
            }
            if (projected.outside != 0) box.outside = true;
            boxes_[k] = box;
        }
        if (front_to_back_) {
            // Nearest first; boxes reaching behind the eye (nearest -infinity) come first of all.
            std::stable_sort(order_.begin(), order_.end(),
                             [&](uint32_t a, uint32_t b) { return boxes_[a].nearest < boxes_[b].nearest; });
        }
    }

    int32_t width_ = 0, height_ = 0;
    bool cull_backfaces_;
    int32_t tile_size_;
    bool front_to_back_;
    bool cull_instances_;
    int32_t screen_tile_;
    uint64_t drawn_triangles_ = 0;
    std::vector<uint32_t> order_;     // placements in drawing order
    std::vector<PlacementBox> boxes_;
    std::vector<std::unique_ptr<TileDrawer>> tiles_;  // one per screen tile, kept between frames
    tbb::enumerable_thread_specific<raster::GeometryStage> geometry_;  // one per thread, likewise
};

}  // namespace hierarchical_zbuffer

extern template class hsr::sdk::StepsDrawing<hierarchical_zbuffer::HierarchicalZBuffer>;
