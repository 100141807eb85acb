// zbuffer: the plain depth buffer (Catmull, "A Subdivision Algorithm for Computer Display of Curved
// Surfaces", PhD thesis, University of Utah, 1974). Triangles are drawn one after another in scene
// order; every covered pixel centre compares the triangle's depth with the depth stored for that
// pixel and keeps the nearer (or, with depth-test=greater, the farther) surface.
//
// Rasterization uses the shared helpers of hsr/raster.hpp: near/far and guard-band clipping in
// homogeneous clip space, integer edge functions (Pineda 1988) on a 1/256-pixel grid with the
// top-left fill rule, and perspective-correct barycentrics computed only for pixels that pass the
// depth test. docs/algorithms/zbuffer.md describes the steps and the counters.
//
// A frame runs on every thread allowed (sort-middle, after Molnar et al., "A Sorting Classification
// of Parallel Rendering", 1994): chunks of triangles are culled and binned to square screen tiles in
// parallel, in scene order, then the tiles are drawn in parallel, each setting up and rasterizing
// its triangles in scene order, so every buffer and counter is the serial one bit for bit. Render
// step by step (one step per triangle) and a frame allowed one thread draw in order, the latter
// setting its triangles up in batches as the tiles do.
// docs/speed/visibility.md has the design and the measurements.
#include "hsr/parallel.hpp"
#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"
#include "hsr/tiles.hpp"
#include "hsr/triangle_setup_batch.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

namespace raster = hsr::raster;
using hsr::sdk::ParamSpec;

class ZBuffer final : public hsr::sdk::StepwiseRemover<ZBuffer> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "zbuffer", "1.0.0", "plain z-buffer (Catmull 1974): per-triangle edge-function rasterization"};
    static inline const ParamSpec params[] = {
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::choice("depth-test", "less", "less|greater",
                          "keep the nearest surface (less) or the farthest one (greater)"),
    };

    explicit ZBuffer(const hsr::sdk::Params& p)
        : cull_backfaces_(p.boolean("cull-backfaces")), keep_farthest_(p.choice("depth-test") == 1) {}

    // render_steps (from StepwiseRemover) takes one step per input triangle, in drawing order. A
    // step names the last line of the pseudocode the triangle reached (docs/theory/en/zbuffer.md).
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"cull", "cull a triangle that faces away or lies outside the view"},
        {"rasterize", "find the pixel centres the triangle covers"},
        {"depth-test", "compare the triangle's depth with the depth buffer"},
        {"write", "write the nearer pixels to the depth and frame buffers"},
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description", "обычный z-буфер (Кэтмелл, 1974): треугольники растеризуются по одному с помощью рёберных функций"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не рисовать треугольники, повёрнутые к камере нелицевой стороной"},
        {"ru", "param:depth-test", "тест глубины"},
        {"ru", "help:depth-test", "оставлять ближайшую поверхность (less) или самую дальнюю (greater)"},
        {"ru", "choice:depth-test:less", "ближайшая (less)"},
        {"ru", "choice:depth-test:greater", "самая дальняя (greater)"},
        {"ru", "phase:cull", "отбросить треугольник, если он нелицевой или лежит вне области видимости"},
        {"ru", "phase:rasterize", "найти центры пикселей, которые покрывает треугольник"},
        {"ru", "phase:depth-test", "сравнить глубину треугольника с буфером глубины"},
        {"ru", "phase:write", "записать более близкие пиксели в буфер глубины и буфер кадра"},
    };
    static constexpr auto translations =
        hsr::sdk::join_translations(own_translations, raster::triangle_counter_translations,
                                    raster::depth_test_counter_translations, raster::triangle_step_translations);

private:
    struct PixelStats {
        uint64_t depth_tested = 0;
        uint64_t written = 0;
    };

    // A piece of a clipped triangle, set up while binning (the others are set up in their tiles).
    struct ClippedPiece {
        raster::TriangleSetup setup;
        uint32_t face;
    };
    // A triangle in a bin: its number and, unless it is a clipped piece, its vertices.
    struct BinEntry {
        uint32_t entry;
        uint32_t corner[3];
    };
    // Consecutive triangles of one placement, binned by one task.
    struct Chunk {
        uint32_t instance = 0;
        // Per tile, in scene order: a triangle that needs no clipping (its index), or, with
        // kPieceBit set, one of `pieces`.
        std::vector<std::vector<BinEntry>> bins;
        std::vector<ClippedPiece> pieces;
        raster::TriangleStats stats;
    };
    static constexpr uint32_t kPieceBit = 1u << 31;

    // Triangles drawn in the order they are added, within `area`: whole ones set up kSetupBatch at a
    // time in SIMD, clipped pieces from the setup they come with, which must live until the next
    // flush().
    template <bool kKeepNearest, bool kCountTests>
    class DrawQueue {
    public:
        DrawQueue(const raster::PixelBuffers& buffers, uint32_t width, uint32_t height, const raster::PixelBounds& area,
                  PixelStats& stats)
            : buffers_(buffers), width_(width), height_(height), area_(area), stats_(stats) {}
        ~DrawQueue() { flush(); }
        DrawQueue(const DrawQueue&) = delete;
        DrawQueue& operator=(const DrawQueue&) = delete;

        // A triangle that needs no clipping and holds pixel centres in the image (as bins hold them).
        void add_whole(const raster::WindowVertex* v0, const raster::WindowVertex* v1, const raster::WindowVertex* v2,
                       uint32_t face, uint32_t instance) {
            const raster::WindowVertex* corner[3] = {v0, v1, v2};
            for (int k = 0; k < 3; ++k) {
                // Read when the batch is full: fetched now, they arrive meanwhile.
                __builtin_prefetch(corner[k]);
                __builtin_prefetch(reinterpret_cast<const char*>(corner[k]) + sizeof *corner[k] - 1);
                corners_[batched_][k] = corner[k];
            }
            ++batched_;
            add(nullptr, face, instance);
        }
        void add_setup(const raster::TriangleSetup* setup, uint32_t face, uint32_t instance) {
            add(setup, face, instance);
        }

        void flush() {
            constexpr raster::DepthRule rule = kKeepNearest ? raster::DepthRule::kNearer : raster::DepthRule::kFarther;
            raster::setup_whole_triangles(corners_, batched_, width_, height_, batch_);
            const raster::TriangleSetup* next = batch_;
            for (size_t n = 0; n < queued_; ++n) {
                const raster::TriangleSetup& s = queue_[n].setup != nullptr ? *queue_[n].setup : *next++;
                raster::DepthTest<rule, kCountTests> test(buffers_, queue_[n].face, queue_[n].instance);
                raster::for_each_covered_pixel_in(
                    s, std::max(s.min_x, area_.min_x), std::max(s.min_y, area_.min_y), std::min(s.max_x, area_.max_x),
                    std::min(s.max_y, area_.max_y), [&](int32_t x, int32_t y, double i, double j) { test(s, x, y, i, j); });
                stats_.depth_tested += test.tested;
                stats_.written += test.written;
            }
            queued_ = batched_ = 0;
        }

    private:
        struct Queued {
            const raster::TriangleSetup* setup;  // a clipped piece's, or nullptr: the next of the batch
            uint32_t face, instance;
        };
        void add(const raster::TriangleSetup* setup, uint32_t face, uint32_t instance) {
            queue_[queued_++] = {setup, face, instance};
            if (queued_ == raster::kSetupBatch) flush();
        }

        const raster::PixelBuffers& buffers_;
        uint32_t width_, height_;
        raster::PixelBounds area_;
        PixelStats& stats_;
        Queued queue_[raster::kSetupBatch];
        const raster::WindowVertex* corners_[raster::kSetupBatch][3];
        raster::TriangleSetup batch_[raster::kSetupBatch];
        size_t queued_ = 0, batched_ = 0;
    };

    // Measured on the bunny at 1024x1024 (docs/speed/visibility.md).
    static constexpr uint32_t kTileSize = 64;          // pixels a side
    static constexpr uint32_t kChunkTriangles = 2048;  // input triangles binned by one task
    static constexpr uint32_t kMaxPendingChunks = 64;  // bounds the memory of the bins

    friend class hsr::sdk::StepwiseRemover<ZBuffer>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        geometry_.begin_frame(scene.raw(), camera, cull_backfaces_);

        const size_t pixel_count = size_t(target.width()) * target.height();
        PixelStats pixels;
        auto finish = [&] {
            if (keep_farthest_) {
                // Uncovered pixels go back to the buffer's "nothing here" depth.
                float* depth = target.depth();
                const uint32_t* face = target.face();
                for (size_t p = 0; p < pixel_count; ++p)
                    if (face[p] == HSR_NO_FACE) depth[p] = std::numeric_limits<float>::infinity();
            }
            (counted_apart_ ? triangle_stats_ : geometry_.stats()).report(counters);
            counters.set("pixels-depth-tested", pixels.depth_tested);
            counters.set("pixels-written", pixels.written);
        };
        try {
            if (keep_farthest_) {
                // The host clears depth to +infinity; keeping the farthest surface needs -infinity.
                std::fill_n(target.depth(), pixel_count, -std::numeric_limits<float>::infinity());
                draw<false>(scene, target, pixels, steps);
            } else {
                draw<true>(scene, target, pixels, steps);
            }
        } catch (const hsr::sdk::StepLimitReached&) {
            finish();
            throw;
        }
        finish();
    }

    template <bool kKeepNearest, class Steps>
    void draw(const hsr::sdk::Scene& scene, hsr::sdk::VisibilityBuffer& target, PixelStats& pixels, Steps& steps) {
        // Binning costs some work of its own, so one thread draws in order; so do scenes too large
        // for kPieceBit to tell triangles from clipped pieces.
        const bool tiles = !Steps::enabled && scene.raw().triangle_count < kPieceBit && hsr::sdk::allowed_threads() > 1;
        counted_apart_ = !Steps::enabled;
        if constexpr (!Steps::enabled) {
            if (!tiles) {
                if (target.depth_tests() == nullptr)
                    draw_in_batches<kKeepNearest, false>(scene, target, pixels);
                else
                    draw_in_batches<kKeepNearest, true>(scene, target, pixels);
                return;
            }
        }
        if (!tiles) {
            if (target.depth_tests() == nullptr)
                draw_in_order<kKeepNearest, false>(scene, target, pixels, steps);
            else
                draw_in_order<kKeepNearest, true>(scene, target, pixels, steps);
        } else {
            if (target.depth_tests() == nullptr)
                draw_tiled<kKeepNearest, false>(scene, target, pixels);
            else
                draw_tiled<kKeepNearest, true>(scene, target, pixels);
        }
    }

    // One triangle after another, each a step.
    template <bool kKeepNearest, bool kCountTests, class Steps>
    void draw_in_order(const hsr::sdk::Scene& scene, hsr::sdk::VisibilityBuffer& target, PixelStats& pixels, Steps& steps) {
        constexpr raster::DepthRule rule = kKeepNearest ? raster::DepthRule::kNearer : raster::DepthRule::kFarther;
        const raster::PixelBuffers buffers(target);
        const uint32_t* indices = scene.raw().indices;
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            geometry_.place(placement);
            const uint32_t end = placement.first_triangle + placement.triangle_count;
            for (uint32_t t = placement.first_triangle; t < end; ++t) {
                const raster::TriangleStats before = geometry_.stats();
                const PixelStats pixels_before = pixels;
                geometry_.process(t, [&](const raster::TriangleSetup& s) {
                    raster::DepthTest<rule, kCountTests> test(buffers, t, placement.instance);
                    raster::for_each_covered_pixel(s, [&](int32_t x, int32_t y, double i, double j) { test(s, x, y, i, j); });
                    pixels.depth_tested += test.tested;
                    pixels.written += test.written;
                });
                if constexpr (Steps::enabled) geometry_.outline_lines(steps, indices + 3 * size_t(t));
                if constexpr (Steps::enabled)
                    raster::triangle_step(steps, before, geometry_.stats(), t, placement.instance,
                                  pixels.depth_tested - pixels_before.depth_tested,
                                  pixels.written - pixels_before.written);
            }
        }
    }

    // One triangle after another on one thread, as draw_in_order without steps, the whole triangles
    // set up in batches.
    template <bool kKeepNearest, bool kCountTests>
    void draw_in_batches(const hsr::sdk::Scene& scene, hsr::sdk::VisibilityBuffer& target, PixelStats& pixels) {
        const raster::PixelBuffers buffers(target);
        const raster::PixelBounds image{0, 0, int32_t(target.width()) - 1, int32_t(target.height()) - 1};
        const uint32_t* indices = scene.raw().indices;
        raster::TriangleStats triangles;
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            geometry_.place(placement);
            // Emptied when it goes out of scope, before the next placement moves the vertices.
            DrawQueue<kKeepNearest, kCountTests> queue(buffers, target.width(), target.height(), image, pixels);
            const uint32_t end = placement.first_triangle + placement.triangle_count;
            for (uint32_t t = placement.first_triangle; t < end; ++t) {
                raster::PixelBounds bounds;
                if (geometry_.bound_unclipped(t, triangles, bounds)) {
                    if (bounds.min_x <= bounds.max_x)
                        queue.add_whole(&geometry_.window_vertex(indices[3 * size_t(t)]),
                                        &geometry_.window_vertex(indices[3 * size_t(t) + 1]),
                                        &geometry_.window_vertex(indices[3 * size_t(t) + 2]), t, placement.instance);
                    continue;
                }
                queue.flush();  // what came before is drawn before the pieces
                geometry_.process(t, triangles, [&](const raster::TriangleSetup& s) {
                    queue.add_setup(&s, t, placement.instance);
                    queue.flush();
                });
            }
        }
        triangle_stats_ = triangles;
    }

    // Binned in parallel chunks, drawn in parallel tiles, one placement after another (the tiles set
    // up the triangles from the placed vertices).
    template <bool kKeepNearest, bool kCountTests>
    void draw_tiled(const hsr::sdk::Scene& scene, hsr::sdk::VisibilityBuffer& target, PixelStats& pixels) {
        grid_ = hsr::sdk::TileGrid{target.width(), target.height(), kTileSize};
        indices_ = scene.raw().indices;
        const raster::PixelBuffers buffers(target);
        raster::TriangleStats triangles;
        uint32_t pending = 0;  // chunks binned, not drawn yet
        auto draw_pending = [&] {
            hsr::sdk::parallel_for_each(grid_.count(), tile_stats_, [&](uint32_t k, PixelStats& stats) {
                draw_tile<kKeepNearest, kCountTests>(k, pending, buffers, stats);
            });
            for (const PixelStats& stats : tile_stats_) {
                pixels.depth_tested += stats.depth_tested;
                pixels.written += stats.written;
            }
            pending = 0;
        };
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            place(placement);
            const uint32_t chunk_count = (placement.triangle_count + kChunkTriangles - 1) / kChunkTriangles;
            for (uint32_t done = 0; done < chunk_count;) {
                const uint32_t batch = std::min(chunk_count - done, kMaxPendingChunks - pending);
                if (chunks_.size() < pending + batch) chunks_.resize(pending + batch);
                hsr::sdk::parallel_for_each(batch, [&](uint32_t c) {
                    const uint32_t first = placement.first_triangle + (done + c) * kChunkTriangles;
                    const uint32_t end = std::min(first + kChunkTriangles,
                                                  placement.first_triangle + placement.triangle_count);
                    bin(chunks_[pending + c], placement.instance, first, end);
                });
                for (uint32_t c = 0; c < batch; ++c) triangles += chunks_[pending + c].stats;
                pending += batch;
                done += batch;
                if (pending == kMaxPendingChunks) draw_pending();
            }
            if (pending > 0) draw_pending();  // before the next placement overwrites the vertices
        }
        triangle_stats_ = triangles;
    }

    // GeometryStage::place, in parallel chunks of vertices.
    void place(const hsr::sdk::Placement& placement) {
        geometry_.place_in_chunks(placement, [](uint32_t count, auto&& work) { hsr::sdk::parallel_for_each(count, work); });
    }

    // Counts the triangles [first, end) of the placed placement into `chunk` and bins each to the
    // tiles whose pixels it may cover.
    void bin(Chunk& chunk, uint32_t instance, uint32_t first, uint32_t end) const {
        chunk.instance = instance;
        chunk.bins.resize(grid_.count());
        chunk.pieces.clear();
        chunk.stats = {};
        const uint32_t across = grid_.across();
        auto add = [&](const BinEntry& entry, const raster::PixelBounds& b, const auto& may_cover) {
            const uint32_t tx0 = uint32_t(b.min_x) / kTileSize, tx1 = uint32_t(b.max_x) / kTileSize;
            const uint32_t ty0 = uint32_t(b.min_y) / kTileSize, ty1 = uint32_t(b.max_y) / kTileSize;
            if (tx0 == tx1 && ty0 == ty1) {
                chunk.bins[ty0 * across + tx0].push_back(entry);
                return;
            }
            for (uint32_t ty = ty0; ty <= ty1; ++ty)
                for (uint32_t tx = tx0; tx <= tx1; ++tx) {
                    const raster::PixelBounds tile{
                        std::max(b.min_x, int32_t(tx * kTileSize)), std::max(b.min_y, int32_t(ty * kTileSize)),
                        std::min(b.max_x, int32_t((tx + 1) * kTileSize) - 1),
                        std::min(b.max_y, int32_t((ty + 1) * kTileSize) - 1)};
                    if (may_cover(tile)) chunk.bins[ty * across + tx].push_back(entry);
                }
        };
        raster::TriangleSetup setup;
        for (uint32_t t = first; t < end; ++t) {
            raster::PixelBounds bounds;
            if (geometry_.bound_unclipped(t, chunk.stats, bounds)) {
                if (bounds.min_x > bounds.max_x) continue;
                const bool large = bounds.max_x - bounds.min_x >= int32_t(kTileSize) ||
                                   bounds.max_y - bounds.min_y >= int32_t(kTileSize);
                if (large) geometry_.setup_unclipped(t, setup);  // to skip tiles of its box it misses
                add(BinEntry{t, {indices_[3 * size_t(t)], indices_[3 * size_t(t) + 1], indices_[3 * size_t(t) + 2]}},
                    bounds, [&](const raster::PixelBounds& r) {
                    return !large || !raster::misses(setup, r.min_x, r.min_y, r.max_x, r.max_y);
                });
                continue;
            }
            geometry_.process(t, chunk.stats, [&](const raster::TriangleSetup& s) {
                chunk.pieces.push_back({s, t});
                add(BinEntry{uint32_t(chunk.pieces.size() - 1) | kPieceBit, {}}, {s.min_x, s.min_y, s.max_x, s.max_y},
                    [&](const raster::PixelBounds& r) { return !raster::misses(s, r.min_x, r.min_y, r.max_x, r.max_y); });
            });
        }
    }

    // Draws what the first `pending` chunks binned to tile k, in scene order, and empties those bins.
    template <bool kKeepNearest, bool kCountTests>
    void draw_tile(uint32_t k, uint32_t pending, const raster::PixelBuffers& buffers, PixelStats& stats) {
        uint32_t tx0, ty0, tx1, ty1;
        grid_.rect(k, tx0, ty0, tx1, ty1);
        const raster::PixelBounds tile{int32_t(tx0), int32_t(ty0), int32_t(tx1) - 1, int32_t(ty1) - 1};
        {
            DrawQueue<kKeepNearest, kCountTests> queue(buffers, grid_.width, grid_.height, tile, stats);
            for (uint32_t c = 0; c < pending; ++c) {
                const Chunk& chunk = chunks_[c];
                for (const BinEntry& binned : chunk.bins[k]) {
                    if (binned.entry & kPieceBit) {
                        const ClippedPiece& piece = chunk.pieces[binned.entry & ~kPieceBit];
                        queue.add_setup(&piece.setup, piece.face, chunk.instance);
                    } else {
                        queue.add_whole(&geometry_.window_vertex(binned.corner[0]),
                                        &geometry_.window_vertex(binned.corner[1]),
                                        &geometry_.window_vertex(binned.corner[2]), binned.entry, chunk.instance);
                    }
                }
            }
        }
        for (uint32_t c = 0; c < pending; ++c) chunks_[c].bins[k].clear();
    }

    bool cull_backfaces_;
    bool keep_farthest_;
    raster::GeometryStage geometry_;  // keeps its vertex buffers between frames
    bool counted_apart_ = false;            // the last frame counted its triangles in triangle_stats_
    raster::TriangleStats triangle_stats_;
    hsr::sdk::TileGrid grid_;
    std::vector<Chunk> chunks_;  // kept between frames, with their capacity
    std::vector<PixelStats> tile_stats_;
    const uint32_t* indices_ = nullptr;  // the scene's, for the frame being drawn
};

}  // namespace

HSR_EXPORT_PLUGIN(ZBuffer)
