// scanline-zbuffer: the scanline z-buffer (Wylie, Romney, Evans & Erdahl, "Half-tone Perspective
// Drawings by Computer", FJCC 1967; Watkins, "A Real Time Visible Surface Algorithm", Utah 1970; as
// taught in Foley, van Dam, Feiner & Hughes, "Computer Graphics" 2nd ed. §15.4, and Rogers,
// "Procedural Elements for Computer Graphics" §4). The image is built one scanline at a time:
// polygons are bucketed by their top scanline (the y-sorted polygon table); an active list holds
// the polygons crossing the current scanline with their left/right edge pair (boundary x, x step
// per scanline, the scanline where the edge ends); depth follows the plane along each span
// (dz/dx = -A/C) and from one scanline to the next (dz/dy = -B/C), evaluated at each pixel from the
// plane's origin as zbuffer evaluates it, so that both store the same depth and break a tie the
// same way (hsr/visibility_rules.hpp). The depth buffer is ONE row long, reused for every
// scanline; the winners of a row are copied into the visibility buffer when the row is done.
//
// An instanced scene is not set up whole before the first scanline: its placements (instances)
// are bucketed by the top scanline of their projected bounds, and a placement is transformed and
// its triangles set up only when the sweep reaches that scanline. Each becomes a record in the
// bucket of its own first scanline, in blocks recycled once that scanline is activated, so memory
// follows what is pending near the sweep, not the triangles drawn. Polygons covering at most 2 x 2
// pixel centres are given by their spans (no edge DDA), and those covering none are left out.
//
// The image is swept in bands of scanlines on every core (scan_bands, scan_instanced_bands): a band
// takes over the polygons that started above it, started directly on its first row, in the order
// the one sweep has them there, so every buffer and counter is the one sweep's. With instances a
// band first sets up again the placements that reach into it from above.
//
// Transform, clipping, culling and triangle setup are raster::GeometryStage's, as in zbuffer; the
// edges step with exact integer DDAs derived from the snapped corners, so every scanline covers
// exactly the pixel centres zbuffer covers (top-left fill rule, 1/256-pixel vertices).
// docs/algorithms/scanline-zbuffer.md describes the steps, the data structures and the counters.
//
// Where to read: scan() below is the sweep (the active-edge-list loop, draw_spans for one row),
// scan_bands() and scan_instanced_bands() the same over bands in parallel; edge_walk.hpp starts
// and steps an edge pair; record_pool.hpp is the memory polygons wait in for their first scanline
// (blocks, streaming stores, huge pages). The rest of this file fills the y-sorted polygon table
// and moves its buckets onto the active list. It is over 1,200 lines because those two share one
// class's state (the active list and its slots, the table, the geometry stage) with the sweep and
// its bands, in one translation unit so that activation inlines into it; the sweep's steps
// (render_steps, the scanlines as a viewer sees them) read that state too.
#include "edge_walk.hpp"
#include "record_pool.hpp"

#include "hsr/bounds.hpp"
#include "hsr/parallel.hpp"
#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

using namespace scanline_zbuffer;
using hsr::sdk::ParamSpec;

constexpr uint64_t kEmpty = ~uint64_t(0);   // an empty row-buffer entry: above every key
constexpr uint32_t kNone = ~uint32_t(0);    // no slot / planes already made

// What an active polygon needs besides its edge pair, by slot: written when it becomes active.
struct ActiveInfo {
    uint32_t id;            // drawing order, for depth ties
    uint32_t face;
    uint32_t instance;
    uint32_t placement;     // whose vertices its planes are made from when it first wins a pixel;
                            // kNone once they are made
};

// The planes of the barycentrics, by slot: needed only for the pixels a polygon wins.
struct ActivePlanes {
    int32_t min_x, min_y;   // the planes are relative to pixel (min_x, min_y), as in the setup
    raster::Plane inv_w, b1_over_w, b2_over_w;
};

// With one placement, the table keeps only the triangle (culled, clipped and set up when it becomes
// active: the geometry stage keeps the window vertices for the whole frame), or a record.
struct TableEntry {
    uint32_t index;         // triangle, or record
    uint32_t is_record;
};

// A polygon of an instanced scene that started above a band of rows and is set up again for it:
// its record, its first scanline, and where it joined the active list of a sweep from the top
// (`join`: first scanline, then 0 when it joined as its placement was set up or 1 when it waited
// in the pool, then the order it was made in).
struct CarriedPolygon {
    PolygonRecord record;
    int32_t first;
    uint64_t join;
};

// What a sweep of an instanced scene sets its placements up with: the geometry stage holding the
// placement being set up, the records waiting for their first scanline, and the setups of clipped
// pieces. The one sweep has one; the bands of rows one per thread.
struct PlacementWork {
    raster::GeometryStage geometry;
    RecordPool pending;
    std::vector<raster::TriangleSetup> pieces;
    std::vector<uint32_t> free_pieces;             // of pieces, once their polygon is active
    std::vector<CarriedPolygon> carried;           // a band's polygons from above it
};

inline void set_planes(ActivePlanes& p, const raster::TriangleSetup& s) {
    p.min_x = s.min_x;
    p.min_y = s.min_y;
    p.inv_w = s.inv_w;
    p.b1_over_w = s.b1_over_w;
    p.b2_over_w = s.b2_over_w;
}

// Perspective-correct (b1, b2) at pixel (min_x + i, min_y + j), on the planes of the active polygon.
inline void barycentrics(const ActivePlanes& a, double i, double j, float* out) {
    const glm::vec2 b = raster::perspective_barycentrics(a.inv_w, a.b1_over_w, a.b2_over_w, i, j);
    out[0] = b.x;
    out[1] = b.y;
}

// The polygon's depth is its setup's depth plane, evaluated at each pixel centre exactly as the
// z-buffer evaluates it (raster::Plane::at, from the setup's origin pixel (min_x, min_y)), so that
// both store the same float and a tie between two surfaces is a tie for both (the tie rule of
// hsr/visibility_rules.hpp). The origin pixel of a setup, from its snapped corners:
inline void depth_origin_pixel(const int32_t (&x)[3], const int32_t (&y)[3], int32_t& min_x, int32_t& min_y) {
    min_x = std::max(raster::first_pixel_from(std::min({x[0], x[1], x[2]})), 0);
    min_y = std::max(raster::first_pixel_from(std::min({y[0], y[1], y[2]})), 0);
}

class ScanlineZBuffer final : public hsr::sdk::StepwiseRemover<ScanlineZBuffer> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "scanline-zbuffer", "1.0.0",
        "scanline z-buffer (Wylie et al. 1967, Watkins 1970): y-sorted polygon table, active edge pairs, "
        "one-row depth buffer"};
    static inline const ParamSpec params[] = {
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::integer("band-rows", "0", 0, 16384,
                           "scanlines per band swept in parallel (0: the image's height over twice the threads, at "
                           "least 64; the image's height or more: one sweep)"),
    };

    explicit ScanlineZBuffer(const hsr::sdk::Params& p)
        : cull_backfaces_(p.boolean("cull-backfaces")), band_rows_(int32_t(p.integer("band-rows"))) {}

    // render_steps (from StepwiseRemover) takes one step per scanline, top to bottom, empty ones included:
    // step k leaves rows 0 .. k-1 drawn.
    // A scanline's phase is the last line of the pseudocode (docs/theory/en/scanline-zbuffer.md) it
    // needed: only the active list's update (no polygon on the row), spans that no other polygon
    // covered, or spans whose depth tests settled an overlap.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"active-edges", "update the active list: polygons that start on the scanline join, finished ones leave"},
        {"spans", "fill each active polygon's span between its edge pair"},
        {"depth-test", "depth-test overlapping spans in the one-row depth buffer"},
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description",
         "построчный z-буфер (Уайли и др., 1967; Уоткинс, 1970): таблица многоугольников по y, пары активных "
         "рёбер, буфер глубины длиной в одну строку"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не рисовать треугольники, повёрнутые к камере нелицевой стороной"},
        {"ru", "param:band-rows", "строк в полосе"},
        {"ru", "help:band-rows",
         "сколько строк развёртки в полосе, полосы обрабатываются параллельно (0 — высота изображения, делённая "
         "на удвоенное число потоков, но не меньше 64; высота изображения или больше — один проход)"},
        {"ru", "phase:active-edges",
         "обновить список активных: многоугольники, начинающиеся на этой строке, входят в него, закончившиеся — выходят"},
        {"ru", "phase:spans", "заполнить интервал каждого активного многоугольника между его парой рёбер"},
        {"ru", "phase:depth-test", "сравнить по глубине перекрывающиеся интервалы в буфере глубины строки"},
        {"ru", "counter:polygons-in-table", "многоугольников в таблице"},
        {"ru", "counter:polygons-empty", "пустых многоугольников отброшено"},
        {"ru", "counter:scanlines", "строк развёртки с многоугольниками"},
        {"ru", "counter:edge-pairs-processed", "пар рёбер обработано"},
        {"ru", "counter:active-polygons-max", "наибольшее число активных многоугольников"},
        {"ru", "counter:active-edges-max", "наибольшее число активных рёбер"},
        {"ru", "counter:polygon-records-max", "наибольшее число записей о многоугольниках"},
        {"ru", "step:scanline", "строка развёртки"},
    };
    static constexpr auto translations =
        hsr::sdk::join_translations(own_translations, raster::triangle_counter_translations,
                                    raster::depth_test_counter_translations);

private:
    struct Stats {
        uint64_t depth_tested = 0;
        uint64_t written = 0;
        uint64_t scanlines = 0;   // scanlines with at least one active polygon
        uint64_t edge_pairs = 0;  // (polygon, scanline) pairs: spans computed
        uint64_t active_max = 0;
        Stats& operator+=(const Stats& o) {
            depth_tested += o.depth_tested;
            written += o.written;
            scanlines += o.scanlines;
            edge_pairs += o.edge_pairs;
            active_max = std::max(active_max, o.active_max);
            return *this;
        }
    };

    // What one sweep works on, over the whole image or over a band of its rows: the active polygon
    // list with its slots, and the one-row depth buffer.
    struct Sweep {
        std::vector<TableEntry> staged;              // one bucket's entries, fetched together
        std::vector<ActivePolygon> active;           // the active polygon list (edge pairs)
        std::vector<ActiveInfo> infos;               // of the active polygons, by slot
        std::vector<ActivePlanes> planes;            // of the active polygons, by slot
        std::vector<uint32_t> free_slots, released;  // released: free once the row is resolved
        std::vector<uint64_t> row;                   // the one-row depth buffer
        raster::TriangleStats triangles;             // what activating triangles counted
        uint64_t polygons = 0, polygons_empty = 0;   // instanced: emitted setups, and those dropped
        uint64_t records_max = 0;                    // instanced: the most records its pool held
        PlacementWork* work = nullptr;               // instanced: what it sets its placements up with

        void start(int32_t width, uint32_t largest_bucket) {
            row.assign(size_t(width), kEmpty);
            if (staged.size() < largest_bucket) staged.resize(largest_bucket);
            active.clear();
            infos.clear();
            planes.clear();
            free_slots.clear();
            released.clear();
            triangles = {};
            polygons = polygons_empty = records_max = 0;
            work = nullptr;
        }
    };

    friend class hsr::sdk::StepwiseRemover<ScanlineZBuffer>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        geometry_.begin_frame(scene.raw(), camera, cull_backfaces_);
        width_ = camera.width;
        height_ = camera.height;
        scene_ = &scene.raw();
        camera_ = &camera;
        indices_ = scene.raw().indices;
        positions_ = scene.raw().positions;
        viewport_ = raster::Viewport(width_, height_);

        const uint32_t placements = scene.placement_count();
        placement_instance_.resize(placements);
        placement_matrix_.resize(placements);
        pieces_.clear();
        polygons_ = 0;
        polygons_empty_ = 0;
        records_max_ = 0;
        records_only_ = placements > 1;
        if (!records_only_) {
            // 1. One placement: its window vertices stay in the geometry stage for the whole frame,
            //    so a triangle is culled, clipped and set up only when its first scanline comes.
            //    Here it is only bucketed, by the first scanline its snapped corners reach.
            const hsr::sdk::Placement placement = scene.placement(0);
            table_.clear();
            records_.clear();
            first_row_.clear();
            last_row_bound_.clear();
            tallest_polygon_rows_ = 0;
            table_.reserve(placement.triangle_count);
            first_row_.reserve(placement.triangle_count);
            last_row_bound_.reserve(placement.triangle_count);
            bucket_start_.assign(size_t(height_) + 1, 0);
            geometry_.place_in_chunks(placement,
                                      [](uint32_t count, auto&& work) { hsr::sdk::parallel_for_each(count, work); });
            placement_instance_[0] = placement.instance;
            bucket_triangles(placement);

            // 2. The y-sorted polygon table: a counting sort of the ids by first scanline, stable,
            //    so each bucket keeps the drawing order.
            uint32_t largest_bucket = 0;
            for (int32_t y = 0; y < height_; ++y) {
                largest_bucket = std::max(largest_bucket, bucket_start_[y + 1]);
                bucket_start_[y + 1] += bucket_start_[y];
            }
            order_.resize(first_row_.size());
            for (uint32_t id = 0; id < uint32_t(first_row_.size()); ++id) order_[bucket_start_[first_row_[id]]++] = id;
            for (int32_t y = height_ - 1; y > 0; --y) bucket_start_[y] = bucket_start_[y - 1];  // back to starts
            bucket_start_[0] = 0;
            largest_bucket_ = largest_bucket;
            order_last_row_bound_.resize(order_.size());
            for (size_t k = 0; k < order_.size(); ++k) order_last_row_bound_[k] = last_row_bound_[order_[k]];
            polygons_ = first_row_.size();
            records_max_ = records_.size();
        } else {
            // 1-2. Several placements: each is bucketed by the top scanline of its projected bounds,
            //      and transformed and set up only when the sweep gets there (activate_placement).
            bucket_placements(scene);
            largest_bucket_ = 0;
        }

        // 3. The scanlines, top to bottom.
        Stats stats;
        auto report = [&] {
            raster::TriangleStats triangles = geometry_.stats();
            triangles += sweep_.triangles;
            triangles += activated_;
            triangles.report(counters);
            counters.set("pixels-depth-tested", stats.depth_tested);
            counters.set("pixels-written", stats.written);
            counters.set("polygons-in-table", polygons_);
            counters.set("polygons-empty", polygons_empty_);
            counters.set("scanlines", stats.scanlines);
            counters.set("edge-pairs-processed", stats.edge_pairs);
            counters.set("active-polygons-max", stats.active_max);
            counters.set("active-edges-max", 2 * stats.active_max);
            counters.set("polygon-records-max", records_max_);
        };
        activated_ = {};
        sweep_.triangles = {};
        try {
            const size_t threads = hsr::sdk::allowed_threads();
            const bool bands = !Steps::enabled && threads > 1 && height_ > band_height(threads);
            if (bands && records_only_ && target.depth_tests() == nullptr)
                scan_instanced_bands<false>(target, stats);
            else if (bands && records_only_)
                scan_instanced_bands<true>(target, stats);
            else if (bands && target.depth_tests() == nullptr)
                scan_bands<false>(target, stats);
            else if (bands)
                scan_bands<true>(target, stats);
            else if (target.depth_tests() == nullptr)
                scan<false>(target, stats, steps);
            else
                scan<true>(target, stats, steps);
        } catch (const hsr::sdk::StepLimitReached&) {
            report();
            throw;
        }
        report();
    }

    // The one placement's triangles into the polygon table, bucketed by first scanline, in drawing
    // order. A triangle that needs clipping is processed now (its pieces are kept as records), as is
    // one that the geometry stage will reject at once (outside one frustum plane, facing away with
    // cull-backfaces, non-finite) or that cannot reach the image: it draws nothing, but is counted.
    [[gnu::flatten]] void bucket_triangles(const hsr::sdk::Placement& placement) {
        const uint32_t end = placement.first_triangle + placement.triangle_count;
        for (uint32_t t = placement.first_triangle; t < end; ++t) {
            const uint32_t i0 = indices_[3 * t], i1 = indices_[3 * t + 1], i2 = indices_[3 * t + 2];
            const uint32_t c0 = geometry_.vertex_outcode(i0), c1 = geometry_.vertex_outcode(i1),
                           c2 = geometry_.vertex_outcode(i2);
            const uint32_t codes = c0 | c1 | c2;
            const bool rejected = (c0 & c1 & c2 & raster::kOutsideAnyPlane) ||
                                  (cull_backfaces_ && !raster::is_front_facing(geometry_.clip_vertex(i0),
                                                                               geometry_.clip_vertex(i1),
                                                                               geometry_.clip_vertex(i2)));
            if (!rejected && !(codes & (raster::kNeedsClipping | raster::kNonFinite))) {
                // The first pixel-centre row at or below the top corner, as setup_triangle finds it.
                const int32_t y0 = geometry_.window_vertex(i0).y, y1 = geometry_.window_vertex(i1).y,
                              y2 = geometry_.window_vertex(i2).y;
                const int32_t first = std::max(raster::first_pixel_from(std::min({y0, y1, y2})), 0);
                if (first < height_) {
                    add_to_table({t, 0}, first, raster::last_pixel_to(std::max({y0, y1, y2})));
                    continue;
                }
            }
            geometry_.process(t, [&](const raster::TriangleSetup& s) {
                add_to_table({uint32_t(records_.size()), 1}, s.min_y, s.max_y);
                fill_record(records_.emplace_back(), s, t, 0);
            });
        }
    }

    // A polygon of the table: its first scanline, and one it cannot reach below (for a sweep over
    // a band of rows, which takes over the polygons that started above it).
    void add_to_table(TableEntry e, int32_t first_row, int32_t last_row_bound) {
        if (first_row_.size() >= std::numeric_limits<uint32_t>::max())
            throw hsr::sdk::Unsupported("scanline-zbuffer: more than 2^32 - 1 polygons in one frame");
        table_.push_back(e);
        first_row_.push_back(uint16_t(first_row));
        last_row_bound_.push_back(uint16_t(std::clamp(last_row_bound, first_row, height_ - 1)));
        tallest_polygon_rows_ = std::max(tallest_polygon_rows_, int32_t(last_row_bound_.back()) - first_row);
        ++bucket_start_[size_t(first_row) + 1];
    }

    // One emitted setup of triangle t of placement k as a record. The corners come from the
    // geometry stage's window vertices, or, for a piece of a clipped triangle, from the setup.
    void fill_record(PolygonRecord& r, const raster::TriangleSetup& s, uint32_t t, uint32_t k) {
        const uint32_t i0 = indices_[3 * t], i1 = indices_[3 * t + 1], i2 = indices_[3 * t + 2];
        const uint32_t codes = geometry_.vertex_outcode(i0) | geometry_.vertex_outcode(i1) | geometry_.vertex_outcode(i2);
        if (codes & raster::kNeedsClipping) {
            raster::setup_corners(s, r.x, r.y);
            if (pieces_.size() >= kSmall) throw hsr::sdk::Unsupported("scanline-zbuffer: too many clipped pieces");
            r.piece = uint32_t(pieces_.size());
            pieces_.push_back(s);
        } else {
            corners_of(geometry_, s, i0, i1, i2, r.x, r.y);
            r.piece = kNoPiece;
        }
        r.z_origin = s.depth.origin;
        r.dzdx = s.depth.dx;
        r.dzdy = s.depth.dy;
        r.face = t;
        r.placement = k;
    }

    static uint32_t keep_piece(PlacementWork& work, const raster::TriangleSetup& s) {
        if (!work.free_pieces.empty()) {
            const uint32_t piece = work.free_pieces.back();
            work.free_pieces.pop_back();
            work.pieces[piece] = s;
            return piece;
        }
        if (work.pieces.size() >= kSmall) throw hsr::sdk::Unsupported("scanline-zbuffer: too many clipped pieces");
        work.pieces.push_back(s);
        return uint32_t(work.pieces.size() - 1);
    }

    // ---- Instances: placements activated lazily, in y order ----

    // Buckets the placements by the top scanline of their projected bounds and counts the drawing
    // order of their first triangles (for depth ties).
    void bucket_placements(const hsr::sdk::Scene& scene) {
        const uint32_t placements = scene.placement_count();
        placement_first_id_.resize(placements);
        placement_row_.resize(placements);
        placement_bottom_.resize(placements);
        placement_start_.assign(size_t(height_) + 2, 0);
        uint64_t id = 0;
        uint32_t box_first = 0, box_count = 0;
        glm::vec3 lo(0.0f), hi(0.0f);
        bool box_known = false;
        for (uint32_t k = 0; k < placements; ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            placement_instance_[k] = placement.instance;
            // To find the bounds, and to set a winner up again.
            placement_matrix_[k] = geometry_.clip_from_object(placement);
            placement_first_id_[k] = uint32_t(id);
            id += placement.triangle_count;
            if (!box_known || box_first != placement.first_vertex || box_count != placement.vertex_count) {
                object_bounds(placement.first_vertex, placement.vertex_count, lo, hi);
                box_first = placement.first_vertex;
                box_count = placement.vertex_count;
                box_known = true;
            }
            const int32_t row = top_row(placement_matrix_[k], lo, hi);
            placement_row_[k] = row;
            placement_bottom_[k] = bottom_row(placement_matrix_[k], lo, hi);
            ++placement_start_[size_t(row) + 1];
        }
        if (id > uint64_t(std::numeric_limits<uint32_t>::max()))
            throw hsr::sdk::Unsupported("scanline-zbuffer: more than 2^32 - 1 triangles drawn in one frame");
        for (int32_t y = 0; y <= height_; ++y) placement_start_[y + 1] += placement_start_[y];
        placement_order_.resize(placements);
        for (uint32_t k = 0; k < placements; ++k) placement_order_[placement_start_[placement_row_[k]]++] = k;
        for (int32_t y = height_; y > 0; --y) placement_start_[y] = placement_start_[y - 1];  // back to starts
        placement_start_[0] = 0;
    }

    // The object-space bounding box of a placement's vertex range (a NaN coordinate is left out:
    // its triangles are skipped as non-finite).
    void object_bounds(uint32_t first, uint32_t count, glm::vec3& lo, glm::vec3& hi) const {
        lo = glm::vec3(std::numeric_limits<float>::infinity());
        hi = -lo;
        for (size_t k = first; k < size_t(first) + count; ++k)
            for (int c = 0; c < 3; ++c) {
                const float v = positions_[3 * k + c];
                lo[c] = v < lo[c] ? v : lo[c];
                hi[c] = v > hi[c] ? v : hi[c];
            }
    }

    // A scanline at or above the first scanline of every polygon of a placement, from the projection
    // of its object-space box (hsr/bounds.hpp), with one scanline of margin for rounding and the
    // snapping of vertices. A box reaching the eye's side of the near plane starts at the top; one
    // below the image at `height_` (processed after the sweep, for the counters only).
    int32_t top_row(const glm::dmat4& m, const glm::vec3& lo, const glm::vec3& hi) const {
        const raster::ProjectedBox box = raster::project_box(m, glm::dvec3(lo), glm::dvec3(hi), viewport_);
        if (!box.in_front) return 0;
        const double top = box.min_y;
        if (!(top >= 2.0)) return 0;
        if (top >= double(height_) + 2.0) return height_;
        return int32_t(top) - 1;  // top >= 2: truncation is the floor
    }

    // A scanline at or below the last scanline of every polygon of a placement, as top_row finds
    // the first (-1: none reaches the image).
    int32_t bottom_row(const glm::dmat4& m, const glm::vec3& lo, const glm::vec3& hi) const {
        const raster::ProjectedBox box = raster::project_box(m, glm::dvec3(lo), glm::dvec3(hi), viewport_);
        if (!box.in_front) return height_ - 1;
        const double bottom = box.max_y;
        if (!(bottom < double(height_) - 2.0)) return height_ - 1;
        if (bottom < -1.0) return -1;
        return int32_t(bottom + 1.0) + 1;  // bottom + 1 >= 0: truncation is the floor
    }

    // The record of setup s of triangle t of placement k (drawing order id), and its first
    // scanline; -1 when it covers no pixel centre.
    int32_t make_record(const raster::GeometryStage& geometry, const raster::TriangleSetup& s, uint32_t t, uint32_t k,
                        uint32_t id, PolygonRecord& r) const {
        const uint32_t covered = small_coverage(s);
        if (covered == 0) return -1;
        r.z_origin = s.depth.origin;
        r.dzdx = s.depth.dx;
        r.dzdy = s.depth.dy;
        r.face = t;
        r.placement = k;
        r.id = id;
        if (covered != kLarger) {
            r.piece = kSmall;
            return small_spans(covered, s.min_x, s.min_y, r);
        }
        r.piece = kNoPiece;
        corners_of(geometry, s, indices_[3 * t], indices_[3 * t + 1], indices_[3 * t + 2], r.x, r.y);
        return s.min_y;
    }

    // Transforms placement k and sets up its triangles on scanline y, at or above the first scanline
    // of each, for a sweep that ends before scanline end_row (a band's end, or the image's). A
    // polygon that starts on y joins the active list at once, the others become records in the
    // bucket of their first scanline. Those that cover no pixel centre are left out. Every triangle
    // is counted here; those starting at end_row or below only that way (the band they start in
    // sets them up and counts their polygons). Flattened, so that setup_triangle is inlined and the
    // compiler leaves out the planes the records do not keep; a triangle to clip goes through
    // process, out of line.
    [[gnu::flatten]] void activate_placement(Sweep& sweep, const hsr::sdk::Scene& scene, uint32_t k, int32_t y,
                                             int32_t end_row) {
        PlacementWork& work = *sweep.work;
        const hsr::sdk::Placement placement = scene.placement(k);
        work.geometry.place(placement);
        const uint32_t end = placement.first_triangle + placement.triangle_count;
        const uint32_t id_base = placement_first_id_[k] - placement.first_triangle;
        const bool band = end_row < height_;
        for (uint32_t t = placement.first_triangle; t < end; ++t) {
            int32_t first_row, last_row;
            if (band && rows_of(work.geometry, t, first_row, last_row) && first_row >= end_row) {
                raster::PixelBounds bounds;
                work.geometry.bound_unclipped(t, sweep.triangles, bounds);
                continue;
            }
            const bool unclipped =
                work.geometry.process_unclipped(t, sweep.triangles, [&](const raster::TriangleSetup& s) {
                    PolygonRecord r;
                    const int32_t first = make_record(work.geometry, s, t, k, id_base + t, r);
                    if (first < 0) {
                        ++sweep.polygons_empty;
                        return;
                    }
                    ++sweep.polygons;
                    assert(s.min_y >= y && "top_row is conservative");
                    if (first >= end_row) return;
                    if (first > y)
                        store_streaming(work.pending.new_record(first), r);
                    else
                        activate_record(sweep, r, r.id, y);
                });
            if (!unclipped) [[unlikely]]
                process_clipped(sweep, t, k, id_base + t, y, end_row);
        }
        end_streaming();
    }

    // The scanlines [first, last] that triangle t of the placement in `geometry` can cover, from its
    // snapped corners as setup_triangle finds them (not clamped to the image); false, leaving them
    // unset, when its corners need clipping or are not finite.
    bool rows_of(const raster::GeometryStage& geometry, uint32_t t, int32_t& first, int32_t& last) const {
        const uint32_t i0 = indices_[3 * t], i1 = indices_[3 * t + 1], i2 = indices_[3 * t + 2];
        if ((geometry.vertex_outcode(i0) | geometry.vertex_outcode(i1) | geometry.vertex_outcode(i2)) &
            (raster::kNeedsClipping | raster::kNonFinite))
            return false;
        const int32_t y0 = geometry.window_vertex(i0).y, y1 = geometry.window_vertex(i1).y,
                      y2 = geometry.window_vertex(i2).y;
        first = raster::first_pixel_from(std::min({y0, y1, y2}));
        last = raster::last_pixel_to(std::max({y0, y1, y2}));
        return true;
    }

    // A triangle to clip (or to skip as non-finite): GeometryStage::process, kept out of line, or
    // the compiler merges its setup with activate_placement's and makes the planes there too.
    [[gnu::noinline, gnu::flatten]] void process_clipped(Sweep& sweep, uint32_t t, uint32_t k, uint32_t id, int32_t y,
                                                         int32_t end_row) {
        sweep.work->geometry.process(t, sweep.triangles, [&](const raster::TriangleSetup& s) {
            if (s.min_y >= end_row) return;
            if (small_coverage(s) == 0)
                ++sweep.polygons_empty;
            else
                add_piece(sweep, s, t, k, id, y);
        });
    }

    // The record of a piece of clipped triangle t of placement k, with its setup kept (clipping is
    // not repeated).
    static void piece_record(PlacementWork& work, const raster::TriangleSetup& s, uint32_t t, uint32_t k, uint32_t id,
                             PolygonRecord& r) {
        raster::setup_corners(s, r.x, r.y);
        r.z_origin = s.depth.origin;
        r.dzdx = s.depth.dx;
        r.dzdy = s.depth.dy;
        r.face = t;
        r.placement = k;
        r.piece = keep_piece(work, s);
        r.id = id;
    }

    // A piece of clipped triangle t of placement k, on scanline y: as activate_placement does with
    // a triangle.
    void add_piece(Sweep& sweep, const raster::TriangleSetup& s, uint32_t t, uint32_t k, uint32_t id, int32_t y) {
        ++sweep.polygons;
        assert(s.min_y >= y && "top_row is conservative");
        if (s.min_y > y) {
            piece_record(*sweep.work, s, t, k, id, sweep.work->pending.new_record(s.min_y));
            return;
        }
        int32_t x[3], corner_y[3];
        raster::setup_corners(s, x, corner_y);
        const uint32_t slot = start_polygon(sweep, x, corner_y, s.depth.origin, s.depth.dx, s.depth.dy, y);
        if (slot == kNone) return;
        set_info(sweep, slot, id, t, placement_instance_[k], kNone);
        set_planes(sweep.planes[slot], s);
    }

    // Placements whose bounds start on scanline y are set up; then the records of y join the active
    // list. Out of line, so that it does not change how scan's span loop is compiled.
    [[gnu::noinline]] void activate_instanced(Sweep& sweep, const hsr::sdk::Scene& scene, int32_t y, int32_t end_row) {
        for (uint32_t i = placement_start_[y]; i < placement_start_[y + 1]; ++i)
            activate_placement(sweep, scene, placement_order_[i], y, end_row);
        sweep.work->pending.drain(y, [&](const PolygonRecord& r) { activate_record(sweep, r, r.id, y); });
    }

    // For the band of rows [row, end_row) of an instanced scene: placement k, which a sweep from the
    // top sets up on a scanline above the band, set up again for the band. Its polygons that start
    // in the band wait there as records, in the order that sweep made them, and are counted here;
    // those that started above go to work.carried, to join the band's active list on its first row.
    // Its triangles are counted by the band that sets the placement up first.
    [[gnu::flatten]] void carry_placement(Sweep& sweep, const hsr::sdk::Scene& scene, uint32_t k, int32_t row,
                                          int32_t end_row) {
        PlacementWork& work = *sweep.work;
        raster::TriangleStats uncounted;
        const hsr::sdk::Placement placement = scene.placement(k);
        work.geometry.place(placement);
        const uint32_t end = placement.first_triangle + placement.triangle_count;
        const uint32_t id_base = placement_first_id_[k] - placement.first_triangle;
        const int32_t activated_on = placement_row_[k];
        auto keep = [&](const PolygonRecord& r, int32_t first) {
            if (first >= row) {
                store_streaming(work.pending.new_record(first), r);
                return;
            }
            const uint64_t waited = first > activated_on ? 1 : 0;
            work.carried.push_back({r, first, (uint64_t(first) << 33) | (waited << 32) | uint64_t(work.carried.size())});
        };
        for (uint32_t t = placement.first_triangle; t < end; ++t) {
            int32_t first_row, last_row;  // none in the band: nothing to set up
            if (rows_of(work.geometry, t, first_row, last_row) && (last_row < row || first_row >= end_row)) continue;
            const bool unclipped = work.geometry.process_unclipped(t, uncounted, [&](const raster::TriangleSetup& s) {
                PolygonRecord r;
                const int32_t first = make_record(work.geometry, s, t, k, id_base + t, r);
                if (s.min_y >= row && s.min_y < end_row) ++(first < 0 ? sweep.polygons_empty : sweep.polygons);
                if (first >= 0 && first < end_row) keep(r, first);
            });
            if (!unclipped) [[unlikely]]
                work.geometry.process(t, uncounted, [&](const raster::TriangleSetup& s) {
                    if (s.min_y >= end_row || s.max_y < row) return;
                    const bool empty = small_coverage(s) == 0;
                    if (s.min_y >= row) ++(empty ? sweep.polygons_empty : sweep.polygons);
                    if (empty) return;
                    PolygonRecord r;
                    piece_record(work, s, t, k, id_base + t, r);
                    keep(r, s.min_y);
                });
        }
        end_streaming();
    }

    // The snapped corners of an unclipped triangle in the setup's order, from the window vertices of
    // the geometry stage that set it up.
    static void corners_of(const raster::GeometryStage& geometry, const raster::TriangleSetup& s, uint32_t i0,
                           uint32_t i1, uint32_t i2, int32_t (&x)[3], int32_t (&y)[3]) {
        raster::setup_corners(s, geometry.window_vertex(i0), geometry.window_vertex(i1), geometry.window_vertex(i2),
                              x, y);
    }

    // Makes triangle t active (one placement): culled, clipped (never: see bucket_triangles) and set
    // up now, with its planes, counted into `stats`. It joins on row `row`: its first scanline, or,
    // when a band takes it over from above, the band's first row, as it stands there in a sweep
    // from the top.
    [[gnu::flatten]] void activate_triangle(Sweep& sweep, raster::TriangleStats& stats, uint32_t t, uint32_t id,
                                            int32_t row) {
        geometry_.process(t, stats, [&](const raster::TriangleSetup& s) {
            int32_t x[3], y[3];
            corners_of(geometry_, s, indices_[3 * t], indices_[3 * t + 1], indices_[3 * t + 2], x, y);
            const uint32_t slot = start_polygon(sweep, x, y, s.depth.origin, s.depth.dx, s.depth.dy, row);
            if (slot == kNone) return;
            set_info(sweep, slot, id, t, placement_instance_[0], kNone);
            set_planes(sweep.planes[slot], s);
        });
    }

    // Makes a record active on its first scanline, or on a band's first row (`row`) when it started
    // above. A piece's planes come from its setup; those of a triangle are made when it first wins
    // a pixel (make_planes). Pieces are recycled only with instances (records made as the sweep
    // goes).
    void activate_record(Sweep& sweep, const PolygonRecord& r, uint32_t id, int32_t first, int32_t row) {
        if (r.piece == kSmall) {
            // At most two scanlines: on the second, the spans moved by their steps and the depth
            // stepped once, as the sweep steps them.
            uint32_t slot;
            const int32_t min_x = r.y[2] >> 1, min_y = first - (r.y[2] & 1);
            if (row == first)
                slot = start_small(sweep, r.x[0], r.x[1], r.x[2], r.y[0], r.y[1], r.z_origin, r.dzdx, r.dzdy, min_x,
                                   min_y);
            else if (row == first + 1 && r.y[1] == row)
                slot = start_small(sweep, r.x[0] + r.x[2], r.x[1] + r.y[0], 0, 0, row, r.z_origin, r.dzdx, r.dzdy,
                                   min_x, min_y);
            else
                return;
            set_info(sweep, slot, id, r.face, placement_instance_[r.placement], r.placement);
            return;
        }
        const uint32_t slot =
            start_polygon(sweep, r.x, r.y, r.z_origin, r.dzdx, r.dzdy, row);
        if (r.piece != kNoPiece) [[unlikely]] {
            const std::vector<raster::TriangleSetup>& pieces = sweep.work != nullptr ? sweep.work->pieces : pieces_;
            if (slot != kNone) {
                set_info(sweep, slot, id, r.face, placement_instance_[r.placement], kNone);
                set_planes(sweep.planes[slot], pieces[r.piece]);
            }
            if (sweep.work != nullptr) sweep.work->free_pieces.push_back(r.piece);
        } else if (slot != kNone) {
            set_info(sweep, slot, id, r.face, placement_instance_[r.placement], r.placement);
        }
    }
    void activate_record(Sweep& sweep, const PolygonRecord& r, uint32_t id, int32_t first) {
        activate_record(sweep, r, id, first, first);
    }

    static void set_info(Sweep& sweep, uint32_t slot, uint32_t id, uint32_t face, uint32_t instance,
                         uint32_t placement) {
        ActiveInfo& info = sweep.infos[slot];
        info.id = id;
        info.face = face;
        info.instance = instance;
        info.placement = placement;
    }

    // The planes of an active triangle of an instanced scene, from its setup made again.
    [[gnu::noinline, gnu::flatten]] void make_planes(Sweep& sweep, uint32_t slot) {
        ActiveInfo& info = sweep.infos[slot];
        raster::TriangleSetup s{};
        geometry_.setup_again(placement_matrix_[info.placement], info.face, s);
        set_planes(sweep.planes[slot], s);
        info.placement = kNone;
    }

    static uint32_t take_slot(Sweep& sweep) {
        if (sweep.free_slots.empty()) {
            sweep.infos.emplace_back();
            sweep.planes.emplace_back();
            return uint32_t(sweep.infos.size() - 1);
        }
        const uint32_t slot = sweep.free_slots.back();
        sweep.free_slots.pop_back();
        return slot;
    }

    // Adds a small polygon, whose covered pixel centres small_coverage() found, to the active list: on
    // its first scanline the span [left, right], on the next (if `last` is that one) the span moved
    // by (left_step, right_step). Its edges are DDAs without error terms. Returns its slot.
    uint32_t start_small(Sweep& sweep, int32_t left, int32_t right, int32_t left_step, int32_t right_step, int32_t last,
                         double z_origin, double dzdx, double dzdy, int32_t min_x, int32_t min_y) {
        ActivePolygon a;
        a.left = EdgeWalk{left, 0, 1, 0, left_step};
        a.right = EdgeWalk{right, 0, 1, 0, right_step};
        a.lower = EdgeWalk{};
        a.lower_left = 0;
        a.switch_row = -1;
        a.min_x = min_x;
        a.min_y = min_y;
        return push_active(sweep, a, last, z_origin, dzdx, dzdy);
    }

    // Adds a polygon with the corners (vx, vy) (on the subpixel grid, in the setup's corner order)
    // to the active list on scanline `first` and returns its slot, unless no scanline is left:
    // then kNone.
    uint32_t start_polygon(Sweep& sweep, const int32_t (&vx)[3], const int32_t (&vy)[3], double z_origin, double dzdx,
                           double dzdy, int32_t first) {
        ActivePolygon a;  // built whole, then copied: emplace_back() would clear it first
        int32_t last;
        if (!start_edge_pair(vx, vy, first, height_, a, last)) return kNone;
        depth_origin_pixel(vx, vy, a.min_x, a.min_y);
        return push_active(sweep, a, last, z_origin, dzdx, dzdy);
    }

    // Adds a polygon whose edges and depth origin pixel are set to the active list, in a free slot,
    // with its last scanline and depth plane; returns the slot.
    static uint32_t push_active(Sweep& sweep, ActivePolygon& a, int32_t last, double z_origin, double dzdx,
                                double dzdy) {
        const uint32_t slot = take_slot(sweep);
        a.last_row = int16_t(last);
        a.slot = slot;
        a.dzdx = dzdx;
        a.dzdy = dzdy;
        a.z_origin = z_origin;
        sweep.active.push_back(a);
        return slot;
    }

    // Polygons whose first scanline is y join the active list. Their table entries lie scattered in
    // memory: they are prefetched a few polygons ahead, and with one placement the entries are
    // fetched first, in a tight loop whose loads overlap, then the corner indices and window vertices
    // are prefetched.
    void activate_bucket(Sweep& sweep, int32_t y) {
        const uint32_t begin = bucket_start_[y], count = bucket_start_[y + 1] - begin;
        if (count == 0) return;
        const uint32_t* const ids = order_.data() + begin;
        TableEntry* const staged = sweep.staged.data();
        for (uint32_t k = 0; k < count; ++k) staged[k] = table_[ids[k]];
        constexpr uint32_t kAhead = 4;
        for (uint32_t k = 0; k < count; ++k) {
            if (k + 2 * kAhead < count && !staged[k + 2 * kAhead].is_record)
                __builtin_prefetch(indices_ + 3 * size_t(staged[k + 2 * kAhead].index));
            if (k + kAhead < count && !staged[k + kAhead].is_record) {
                const uint32_t* const corner = indices_ + 3 * size_t(staged[k + kAhead].index);
                __builtin_prefetch(&geometry_.window_vertex(corner[0]));
                __builtin_prefetch(&geometry_.window_vertex(corner[1]));
                __builtin_prefetch(&geometry_.window_vertex(corner[2]));
            }
            if (staged[k].is_record)
                activate_record(sweep, records_[staged[k].index], ids[k], y);
            else
                activate_triangle(sweep, sweep.triangles, staged[k].index, ids[k], y);
        }
    }

    // 3. The sweep: scanline after scanline, top to bottom, the polygons of the y-sorted table that
    //    start there join the active list; each active polygon's span, between its edge pair, is
    //    depth-tested into the one-row buffer; a polygon on its last scanline leaves the list, the
    //    others step their edges and depth to the next one; the row's winners go out. With steps,
    //    each scanline is one; the counts reach `stats` before each, as a step may end the sweep.
    //    Out of line: inlined into render_with it runs 0.2 % more instructions.
    template <bool kCountTests, class Steps>
    [[gnu::noinline]] void scan(hsr::sdk::VisibilityBuffer& target, Stats& stats, Steps& steps) {
        Sweep& sweep = sweep_;
        sweep.start(int32_t(width_), largest_bucket_);
        if (records_only_) {
            begin_work(work_);
            sweep.work = &work_;
        }
        stats = {};
        const hsr::sdk::Scene scene(*scene_);
        for (int32_t y = 0; y < height_; ++y) {
            if (records_only_)
                activate_instanced(sweep, scene, y, height_);
            else
                activate_bucket(sweep, y);
            if (sweep.active.empty()) {
                if constexpr (Steps::enabled) scanline_step(steps, y, 0, {});
                continue;
            }
            [[maybe_unused]] const size_t polygons_on_row = sweep.active.size();
            [[maybe_unused]] const Stats before = stats;
            if constexpr (Steps::enabled) draw_active_edges(sweep, steps, y);
            const PixelRange touched = draw_spans<kCountTests>(sweep, target, y, stats);
            [[maybe_unused]] RowSpans spans;
            if constexpr (Steps::enabled) spans = draw_row_spans(sweep, steps, y, touched);
            finish_row(sweep, target, y, touched);
            if constexpr (Steps::enabled) {
                spans.tested = stats.depth_tested - before.depth_tested;
                spans.written = stats.written - before.written;
                scanline_step(steps, y, polygons_on_row, spans);
            }
        }
        if (records_only_) {  // below the image: nothing to draw, but counted as zbuffer counts them
            for (uint32_t i = placement_start_[height_]; i < placement_start_[height_ + 1]; ++i)
                activate_placement(sweep, scene, placement_order_[i], height_, height_);
            polygons_ += sweep.polygons;
            polygons_empty_ += sweep.polygons_empty;
            records_max_ = work_.pending.records_max();
        }
    }

    // band_starts_ for an instanced scene: `count` bands (fewer on a short image) of about the same
    // work, a scanline's work taken as the triangles of the placements over it, each placement's
    // spread evenly over the scanlines between its top_row and bottom_row. (The placements of a
    // deep scene crowd the middle of the picture: bands of equal height would leave one thread
    // with most of the work.)
    void balance_bands(size_t count) {
        row_work_.assign(size_t(height_) + 1, 0.0);
        const hsr::sdk::Scene scene(*scene_);
        double total = 0.0;
        for (uint32_t k = 0; k < uint32_t(placement_row_.size()); ++k) {
            const int32_t top = std::min(placement_row_[k], height_ - 1);
            const int32_t bottom = std::min(placement_bottom_[k], height_ - 1);
            if (bottom < top) continue;
            const double triangles = double(scene.placement(k).triangle_count);
            row_work_[size_t(top)] += triangles / double(bottom - top + 1);
            row_work_[size_t(bottom) + 1] -= triangles / double(bottom - top + 1);
            total += triangles;
        }
        count = std::min(count, size_t(height_));
        band_starts_.push_back(0);
        double per_row = 0.0, done = 0.0;
        for (int32_t y = 0; y < height_ && band_starts_.size() < count; ++y) {
            per_row += row_work_[size_t(y)];
            done += per_row;
            // Cut below y once its band has its share (every band keeps at least one scanline).
            if (done >= total * double(band_starts_.size()) / double(count) && y + 1 < height_)
                band_starts_.push_back(y + 1);
        }
        band_starts_.push_back(height_);
    }

    // A PlacementWork made ready for a sweep of this frame.
    void begin_work(PlacementWork& work) const {
        work.geometry.begin_frame(*scene_, *camera_, cull_backfaces_);
        work.pending.reset(height_);
        work.pieces.clear();
        work.free_pieces.clear();
        work.carried.clear();
    }

    // scan_bands() for an instanced scene. A band sets up again the placements that a sweep from
    // the top sets up above it and that reach into it (counting nothing for them: the band they
    // start in counts them), takes over their polygons that started above it, in the order that
    // sweep has them on its first row (first scanline, then those that joined as their placement
    // was set up before those that waited in the pool, then the order they were made in), and
    // keeps the records of the others that start in it; from there on it is that sweep, setting up
    // the placements that start in it as it reaches them. Every buffer and counter is the one
    // sweep's, except polygon-records-max, which is the most one band's pool held.
    template <bool kCountTests>
    void scan_instanced_bands(hsr::sdk::VisibilityBuffer& target, Stats& stats) {
        const size_t threads = hsr::sdk::allowed_threads();
        band_starts_.clear();
        if (band_rows_ == 0) {
            balance_bands(2 * std::min<size_t>(threads, kMaxBands / 2));
        } else {
            const int32_t rows = band_height(threads);
            for (int32_t y = 0; y < height_; y += rows) band_starts_.push_back(y);
            band_starts_.push_back(height_);
        }
        const uint32_t count = uint32_t(band_starts_.size() - 1);
        if (bands_.size() < count) bands_.resize(count);
        const hsr::sdk::Scene scene(*scene_);
        hsr::sdk::parallel_for_each(count, band_stats_, [&](uint32_t k, Stats& band_stats) {
            Sweep& sweep = bands_[k];
            sweep.start(int32_t(width_), 0);
            PlacementWork& work = band_work_.local();
            begin_work(work);
            sweep.work = &work;
            const int32_t first = band_starts_[k], end = band_starts_[k + 1];
            for (uint32_t i = 0; i < placement_start_[first]; ++i)
                if (placement_bottom_[placement_order_[i]] >= first)
                    carry_placement(sweep, scene, placement_order_[i], first, end);
            std::sort(work.carried.begin(), work.carried.end(),
                      [](const CarriedPolygon& a, const CarriedPolygon& b) { return a.join < b.join; });
            for (const CarriedPolygon& c : work.carried) activate_record(sweep, c.record, c.record.id, c.first, first);
            for (int32_t y = first; y < end; ++y) {
                activate_instanced(sweep, scene, y, end);
                if (sweep.active.empty()) continue;
                finish_row(sweep, target, y, draw_spans<kCountTests>(sweep, target, y, band_stats));
            }
            if (end == height_)  // below the image, as scan() counts them
                for (uint32_t i = placement_start_[height_]; i < placement_start_[height_ + 1]; ++i)
                    activate_placement(sweep, scene, placement_order_[i], height_, height_);
            sweep.records_max = work.pending.records_max();
            sweep.work = nullptr;
        });
        stats = {};
        for (uint32_t k = 0; k < count; ++k) {
            stats += band_stats_[k];
            activated_ += bands_[k].triangles;
            polygons_ += bands_[k].polygons;
            polygons_empty_ += bands_[k].polygons_empty;
            records_max_ = std::max(records_max_, bands_[k].records_max);
        }
    }

    // Scanlines per band: band-rows, or by default the image's height over twice the threads (a band
    // a thread can take while another finishes a slower one), at least kAutoBandRows. Each band
    // looks through the buckets above it that a polygon could reach down from, so the bands are at
    // most kMaxBands, which bounds that work by kMaxBands passes over the table.
    int32_t band_height(size_t threads) const {
        int32_t rows = band_rows_;
        if (rows == 0) {
            const int64_t bands = 2 * int64_t(std::min<size_t>(threads, kMaxBands));
            rows = std::max(kAutoBandRows, int32_t((height_ + bands - 1) / bands));
        }
        return std::max(rows, (height_ + kMaxBands - 1) / kMaxBands);
    }

    // The sweep of scan() over bands of band_height() scanlines, in parallel (one placement, no steps).
    // A band starts with the polygons that started above it and reach into it, in the order a sweep
    // from the top has them on the band's first row (the active list keeps the order polygons joined
    // it in, and they join by first scanline, then drawing order); from there on it is that sweep.
    // Every buffer and counter is the one sweep's.
    template <bool kCountTests>
    void scan_bands(hsr::sdk::VisibilityBuffer& target, Stats& stats) {
        const int32_t rows = band_height(hsr::sdk::allowed_threads());
        const uint32_t count = uint32_t((height_ + rows - 1) / rows);
        if (bands_.size() < count) bands_.resize(count);
        hsr::sdk::parallel_for_each(count, band_stats_, [&](uint32_t k, Stats& band_stats) {
            Sweep& sweep = bands_[k];
            sweep.start(int32_t(width_), largest_bucket_);
            const int32_t first = int32_t(k) * rows, end = std::min(first + rows, height_);
            raster::TriangleStats counted_above;  // counted by the band they start in
            for (uint32_t i = bucket_start_[std::max(first - tallest_polygon_rows_, 0)]; i < bucket_start_[first]; ++i) {
                if (order_last_row_bound_[i] < first) continue;
                const uint32_t id = order_[i];
                const TableEntry entry = table_[id];
                if (entry.is_record)
                    activate_record(sweep, records_[entry.index], id, first_row_[id], first);
                else
                    activate_triangle(sweep, counted_above, entry.index, id, first);
            }
            for (int32_t y = first; y < end; ++y) {
                activate_bucket(sweep, y);
                if (sweep.active.empty()) continue;
                finish_row(sweep, target, y, draw_spans<kCountTests>(sweep, target, y, band_stats));
            }
        });
        stats = {};
        for (uint32_t k = 0; k < count; ++k) {
            stats += band_stats_[k];
            activated_ += bands_[k].triangles;
        }
    }

    // The pixels [lo, hi] of the row buffer that a scanline's spans touched.
    struct PixelRange {
        int32_t lo, hi;
    };

    // Scanline y of a sweep: the spans of its active polygons depth-tested into the row buffer;
    // polygons on their last scanline leave the list (which keeps its order), the others step to
    // the next.
    template <bool kCountTests>
    PixelRange draw_spans(Sweep& sweep, hsr::sdk::VisibilityBuffer& target, int32_t y, Stats& stats) const {
        const int32_t width = int32_t(width_);
        uint64_t* const row = sweep.row.data();
        const ActiveInfo* const infos = sweep.infos.data();
        ++stats.scanlines;
        stats.edge_pairs += sweep.active.size();
        stats.active_max = std::max<uint64_t>(stats.active_max, sweep.active.size());
        uint32_t* const tests_row = kCountTests ? target.depth_tests() + size_t(y) * size_t(width) : nullptr;
        uint64_t tested = 0, written = 0;
        int32_t lo = width, hi = -1;
        ActivePolygon* const list = sweep.active.data();
        const size_t n = sweep.active.size();
        size_t kept = 0;
        for (size_t i = 0; i < n; ++i) {
            ActivePolygon& p = list[i];
            const int32_t x0 = std::max(p.left.x, 0);
            const int32_t x1 = std::min(p.right.x, width - 1);
            if (x0 <= x1) {
                lo = std::min(lo, x0);
                hi = std::max(hi, x1);
                tested += uint64_t(x1 - x0 + 1);
                written += depth_test_span<kCountTests>(p, infos, y, x0, x1, row, tests_row);
            }
            if (p.last_row == y) {  // done (its slot stays taken for this row)
                sweep.released.push_back(p.slot);
                continue;
            }
            step_to_next_scanline(p, y);
            if (kept != i) list[kept] = p;
            ++kept;
        }
        sweep.active.resize(kept);
        stats.depth_tested += tested;
        stats.written += written;
        return {lo, hi};
    }

    // Scanline y is done: its winners go out, and the slots of the polygons that ended are free.
    void finish_row(Sweep& sweep, hsr::sdk::VisibilityBuffer& target, int32_t y, PixelRange touched) {
        resolve_row(sweep, target, y, touched.lo, touched.hi);
        sweep.free_slots.insert(sweep.free_slots.end(), sweep.released.begin(), sweep.released.end());
        sweep.released.clear();
    }

    // ---- Steps (ABI 1.3): what a scanline shows ----

    // The row's spans: runs of pixels one polygon won, and what its depth tests did.
    struct RowSpans {
        uint64_t spans = 0, pixels = 0, tested = 0, written = 0;
    };

    // Each active polygon's edge pair where it crosses scanline y (before the edges step on): a
    // segment through the boundary, one scanline high, along the edge's slope, when inside the image.
    template <class Steps>
    void draw_active_edges(const Sweep& sweep, Steps& steps, int32_t y) const {
        const float width = float(width_), top = float(y), bottom = float(y + 1);
        auto edge = [&](float x, float slope) {
            if (!(x >= 0.0f && x <= width)) return;
            slope = std::clamp(slope, -2.0f * width, 2.0f * width);
            steps.line(std::clamp(x - 0.5f * slope, 0.0f, width), top, std::clamp(x + 0.5f * slope, 0.0f, width),
                       bottom, HSR_STEP_CONTEXT);
        };
        steps.line(0.0f, top + 0.5f, width, top + 0.5f, HSR_STEP_CONTEXT);
        for (const ActivePolygon& p : sweep.active) {
            // A left edge's x moves by step - rem/den a scanline on average, a right edge's by
            // step + rem/den (see step_to_next_scanline).
            edge(float(p.left.x), float(p.left.step) - float(p.left.rem) / float(p.left.den));
            edge(float(p.right.x + 1), float(p.right.step) + float(p.right.rem) / float(p.right.den));
        }
    }

    // The runs of pixels [lo, hi] of the row buffer that one polygon won, before they go out.
    template <class Steps>
    RowSpans draw_row_spans(const Sweep& sweep, Steps& steps, int32_t y, PixelRange touched) const {
        const int32_t lo = touched.lo, hi = touched.hi;
        RowSpans spans;
        const float centre = float(y) + 0.5f;
        int32_t x = lo;
        while (x <= hi) {
            const uint64_t key = sweep.row[x];
            if (key == kEmpty) {
                ++x;
                continue;
            }
            int32_t end = x + 1;
            while (end <= hi && sweep.row[end] != kEmpty && uint32_t(sweep.row[end]) == uint32_t(key)) ++end;
            steps.line(float(x), centre, float(end), centre, HSR_STEP_WRITTEN);
            ++spans.spans;
            spans.pixels += uint64_t(end - x);
            x = end;
        }
        return spans;
    }

    template <class Steps>
    void scanline_step(Steps& steps, int32_t y, size_t polygons, const RowSpans& spans) const {
        using hsr::sdk::russian_plural;
        hsr::sdk::Steps::Event event{"scanline", HSR_NO_FACE, 0, HSR_NO_LEVEL, spans.written,
                                     spans.tested - spans.written};
        const bool ru = steps.russian();
        if (polygons == 0) {
            event.phase = "active-edges";
            steps.line(0.0f, float(y) + 0.5f, float(width_), float(y) + 0.5f, HSR_STEP_CONTEXT);
            steps.step(event, ru ? "строка %d: активных многоугольников нет" : "scanline %d: no active polygons", int(y));
            return;
        }
        event.phase = spans.tested > spans.written ? "depth-test" : "spans";
        const unsigned long long n = polygons, edges = 2 * n, count = spans.spans, pixels = spans.pixels,
                                 passed = spans.written, failed = spans.tested - spans.written;
        if (ru) {
            steps.step(event,
                       "строка %d: в списке активных %llu %s (%llu %s), %llu %s; %s %llu %s; тест глубины пройден "
                       "%llu %s, не пройден %llu %s",
                       int(y), n, russian_plural(n, "многоугольник", "многоугольника", "многоугольников"), edges,
                       russian_plural(edges, "ребро", "ребра", "рёбер"), count,
                       russian_plural(count, "интервал", "интервала", "интервалов"),
                       russian_plural(pixels, "записан", "записано", "записано"), pixels,
                       russian_plural(pixels, "пиксель", "пикселя", "пикселей"), passed,
                       russian_plural(passed, "раз", "раза", "раз"), failed, russian_plural(failed, "раз", "раза", "раз"));
            return;
        }
        steps.step(event, "scanline %d: %llu active edges, %llu active polygons, %llu spans, %llu pixels written "
                          "(%llu depth tests passed, %llu failed)",
                   int(y), edges, n, count, pixels, passed, failed);
    }

    // The depth test along a span [x0, x1] of scanline y in the row buffer; returns the pixels won.
    // A row-buffer entry is (depth bits << 32 | slot). Depth is never negative, so its float bits
    // order like its value, and one integer comparison is the depth test; equal depths keep the
    // polygon drawn first (the lower id), as in zbuffer. Depth is zbuffer's, bit for bit: the plane
    // at (i, j) from the origin pixel, (origin + dz/dy j) + dz/dx i.
    template <bool kCountTests>
    [[gnu::always_inline]] static uint64_t depth_test_span(const ActivePolygon& p, const ActiveInfo* infos, int32_t y,
                                                           int32_t x0, int32_t x1, uint64_t* row, uint32_t* tests_row) {
        const uint64_t slot = p.slot;
        const double dzdx = p.dzdx;
        const double z_row = p.z_origin + p.dzdy * double(y - p.min_y);
        double i = double(x0 - p.min_x);
        uint64_t span_written = 0;
        for (int32_t x = x0; x <= x1; ++x, i += 1.0) {
            const double z = z_row + dzdx * i;
            // zbuffer's depth_at holds depth to [0, 1]: on the float's bits (which order like its
            // value when positive, and are negative as an int when it is) that is two integer
            // clamps, without the branches double min and max compile to.
            const uint32_t bits =
                uint32_t(std::clamp(std::bit_cast<int32_t>(float(z)), 0, std::bit_cast<int32_t>(1.0f)));
            const uint64_t key = (uint64_t(bits) << 32) | slot;
            const uint64_t old = row[x];
            uint64_t nearer = key < old ? 1 : 0;
            if (uint32_t(old >> 32) == bits) [[unlikely]]
                nearer = infos[slot].id < infos[uint32_t(old)].id ? 1 : 0;
            // Selected with a mask: as a branch, the depth test's outcome would be mispredicted
            // about as often as not.
            row[x] = old ^ ((old ^ key) & (0 - nearer));
            span_written += nearer;
            if constexpr (kCountTests) ++tests_row[x];
        }
        return span_written;
    }

    // Both edges of an active polygon step to scanline y + 1, and its depth by dz/dy. The carries
    // come as masks (0 or -1): a branch on them would be mispredicted about as often as taken.
    [[gnu::always_inline]] static void step_to_next_scanline(ActivePolygon& p, int32_t y) {
        EdgeWalk& l = p.left;
        l.error += l.rem;
        const int32_t left_carry = -int32_t(l.error >= l.den);
        l.error -= l.den & left_carry;
        l.x += l.step + left_carry;
        EdgeWalk& r = p.right;
        r.error += r.rem;
        const int32_t right_carry = -int32_t(r.error >= r.den);
        r.error -= r.den & right_carry;
        r.x += r.step - right_carry;
        if (p.switch_row == y + 1) (p.lower_left ? p.left : p.right) = p.lower;
    }

    // Scanline y is done: its winners in the row buffer, over the pixels [lo, hi] touched, go into
    // the visibility buffer (a winner's barycentric planes are made now if they were left out), and
    // the row buffer is cleared.
    void resolve_row(Sweep& sweep, hsr::sdk::VisibilityBuffer& target, int32_t y, int32_t lo, int32_t hi) {
        uint64_t* const row = sweep.row.data();
        float* const depth_out = target.depth();
        uint32_t* const face_out = target.face();
        float* const bary_out = target.bary();
        uint32_t* const instance_out = target.instance();
        const size_t row_start = size_t(y) * size_t(width_);
        const double j_base = double(y);
        for (int32_t x = lo; x <= hi; ++x) {
            const uint64_t key = row[x];
            if (key == kEmpty) continue;
            row[x] = kEmpty;
            const size_t pixel = row_start + size_t(x);
            const uint32_t slot = uint32_t(key);
            if (sweep.infos[slot].placement != kNone) [[unlikely]]
                make_planes(sweep, slot);
            const ActiveInfo& info = sweep.infos[slot];
            const ActivePlanes& w = sweep.planes[slot];
            depth_out[pixel] = std::bit_cast<float>(uint32_t(key >> 32));
            face_out[pixel] = info.face;
            if (instance_out != nullptr) instance_out[pixel] = info.instance;
            barycentrics(w, double(x - w.min_x), j_base - double(w.min_y), bary_out + 2 * pixel);
        }
    }

    bool cull_backfaces_;
    int32_t band_rows_;                              // 0: chosen by band_height()
    uint32_t width_ = 0;
    int32_t height_ = 0;
    raster::GeometryStage geometry_;                 // keeps its vertex buffers between frames
    raster::Viewport viewport_;
    const hsr_scene* scene_ = nullptr;
    const hsr_camera* camera_ = nullptr;
    const uint32_t* indices_ = nullptr;
    const float* positions_ = nullptr;
    std::vector<uint32_t> placement_instance_;
    std::vector<glm::dmat4> placement_matrix_;       // object to clip space, per placement
    bool records_only_ = false;                      // several placements: activated lazily, in y order
    raster::TriangleStats activated_;                // what the bands' activations counted
    uint32_t largest_bucket_ = 0;                    // polygons of the fullest bucket
    uint64_t polygons_ = 0;                          // emitted setups (polygons-in-table)
    uint64_t polygons_empty_ = 0;                    // small setups covering no pixel centre, dropped
    uint64_t records_max_ = 0;                       // polygon-records-max
    // One placement:
    std::vector<TableEntry> table_;                  // the polygon table, in drawing order
    std::vector<PolygonRecord> records_;             // pieces of clipped triangles, and what is offscreen
    // Several placements:
    std::vector<uint32_t> placement_first_id_;       // drawing order of its first triangle
    std::vector<int32_t> placement_row_;             // the scanline it is activated on (height_: after)
    std::vector<uint32_t> placement_start_;          // bucket y is placement_order_[start[y], start[y + 1])
    std::vector<uint32_t> placement_order_;          // placements sorted by that scanline
    std::vector<int32_t> placement_bottom_;          // a scanline below all of its polygons
    PlacementWork work_;                             // of the one sweep
    hsr::sdk::PerThread<PlacementWork> band_work_;   // of the bands, one per thread
    // Both:
    std::vector<raster::TriangleSetup> pieces_;      // setups of the pieces of clipped triangles
    std::vector<uint16_t> first_row_;                // per polygon: its bucket
    std::vector<uint32_t> bucket_start_;             // bucket y is order_[start[y], start[y + 1])
    std::vector<uint32_t> order_;                    // polygon ids sorted by first scanline
    std::vector<uint16_t> last_row_bound_;           // per polygon: no scanline of it lies below
    std::vector<uint16_t> order_last_row_bound_;     // the same in the order of order_
    int32_t tallest_polygon_rows_ = 0;               // the most any polygon's bound lies below its first
    static constexpr int32_t kMaxBands = 1024;
    static constexpr int32_t kAutoBandRows = 64;
    Sweep sweep_;                                    // of the whole image
    std::vector<Sweep> bands_;                       // of each band of rows
    std::vector<int32_t> band_starts_;               // instanced: band k is rows [start k, start k + 1)
    std::vector<double> row_work_;                   // instanced: the work of each scanline, as differences
    std::vector<Stats> band_stats_;
};

}  // namespace

HSR_EXPORT_PLUGIN(ScanlineZBuffer)
