// painter: the painter's algorithm, polygons painted back to front over one another with no depth
// test. mode=newell is the depth sort of M. E. Newell, R. G. Newell and T. L. Sancha, "A solution to
// the hidden surface problem", Proc. ACM Annual Conference 1972, pp. 443-450: polygons sorted by
// their farthest depth; before the farthest is painted, it is tested against every polygon whose
// depth extent overlaps its own (depth, x and y extents, P behind Q's plane, Q in front of P's
// plane, projections disjoint, and P behind Q wherever the projections overlap); a polygon it may
// hide is moved ahead of it, two that pierce one another are split at once, and when a moved
// polygon would have to move again (a cycle) a polygon of the cycle is split by another's plane,
// or along another's outline. mode=naive paints in the order of a single
// depth key and shows why the tests are needed.
//
// Each triangle's polygon is the part left after near/far and the camera's clip planes
// (GeometryStage::clipped_polygon). A piece of a split is painted as its triangle's polygon
// (GeometryStage::rasterize_polygon) at the pixel centres its cut planes keep, so coverage, depth
// and barycentrics are the zbuffer's. Candidates for the tests come from screen-space bins.
// docs/algorithms/painter.md describes the steps and counters.
// The file is over 700 lines: the sort, its seven tests, the splits and the steps that narrate them
// share one frame's polygon store and bins, and its Russian texts sit beside the English ones.
#include "polygons.hpp"

#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

using hsr::sdk::russian_plural;

namespace {

namespace raster = hsr::raster;
using hsr::sdk::ParamSpec;
using painter::ClipVertex;
using painter::Polygon;

constexpr uint32_t kNone = ~0u;

// Pieces with more corners than this skip the separating-axis shortcut of test 6.
constexpr uint32_t kMaxCorners = 32;

// What the sort did, reported as counters.
struct SortStats {
    uint64_t triangles_in = 0;
    uint64_t triangles_skipped = 0;  // culled, outside, cut away, seen edge-on
    uint64_t polygons_sorted = 0;    // polygons from triangles, before any split
    uint64_t polygons_painted = 0;
    uint64_t pixels_painted = 0;
    uint64_t reorderings = 0;
    uint64_t splits = 0;
    uint64_t unresolved = 0;        // cycles no cut could break: the head painted as it was
    uint64_t polygons_dropped = 0;  // polygons and pieces that cover no pixel centre
    uint64_t run[7] = {};           // the seven tests, in order
    uint64_t passed[7] = {};
};

class Painter final : public hsr::sdk::StepwiseRemover<Painter> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "painter", "1.0.0", "depth sort (Newell, Newell & Sancha 1972): painted back to front, cycles split"};
    static inline const ParamSpec params[] = {
        ParamSpec::choice("mode", "newell", "newell|naive",
                          "newell: the tests, reordering and splitting; naive: paint in sort order only"),
        ParamSpec::choice("naive-key", "farthest", "farthest|mid",
                          "the depth a polygon is sorted by in naive mode: its farthest point or mid-depth"),
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::integer("max-polygons", "1000000", 1, 100000000,
                           "refuse a frame that needs more polygons than this, counting split pieces"),
        ParamSpec::integer("max-reorderings", "5000000", 1, 2000000000,
                           "refuse a frame whose depth sort moves polygons ahead more often than this"),
    };

    // The steps of the depth sort, as a textbook gives them: the list sorted once, then for its
    // head P either Q moved ahead (tests 1-7 failed), a cycle split, or P painted. The seven tests
    // have no step of their own: their outcome is what the next step does.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"sort", "sort the polygons by farthest depth"},
        {"reorder", "P may hide Q: move Q ahead of P"},
        {"split", "a cycle: split a polygon of it"},
        {"paint", "P hides none of the others: paint it"},
    };

    static inline const hsr::sdk::TranslationSpec translations[] = {
        {"ru", "description",
         "алгоритм художника с сортировкой по глубине (Ньюэл, Ньюэл и Санча, 1972): многоугольники выводятся "
         "от дальних к ближним, циклическое перекрытие устраняется разрезанием"},
        {"ru", "param:mode", "вариант алгоритма"},
        {"ru", "help:mode",
         "«по Ньюэлу» — проверки, перестановки и разрезание циклов; «без проверок» — вывод строго в порядке "
         "сортировки"},
        {"ru", "choice:mode:newell", "по Ньюэлу"},
        {"ru", "choice:mode:naive", "без проверок"},
        {"ru", "param:naive-key", "ключ сортировки"},
        {"ru", "help:naive-key",
         "по какой глубине упорядочивать многоугольники в варианте «без проверок»: по самой дальней точке или по "
         "средней глубине"},
        {"ru", "choice:naive-key:farthest", "по дальней точке"},
        {"ru", "choice:naive-key:mid", "по средней глубине"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не выводить треугольники, обращённые к камере обратной стороной"},
        {"ru", "param:max-polygons", "предельное число многоугольников"},
        {"ru", "help:max-polygons",
         "отказаться от кадра, которому нужно больше многоугольников, считая и части после разрезаний"},
        {"ru", "param:max-reorderings", "предельное число перестановок"},
        {"ru", "help:max-reorderings",
         "отказаться от кадра, в котором сортировка по глубине переставляет многоугольники вперёд чаще, чем "
         "столько раз"},
        {"ru", "phase:sort", "упорядочить многоугольники по наибольшей глубине"},
        {"ru", "phase:reorder", "P может заслонять Q: переставить Q в списке перед P"},
        {"ru", "phase:split", "цикл: разрезать один из его многоугольников"},
        {"ru", "phase:paint", "P не заслоняет ни одного из остальных: нарисовать P"},
        {"ru", "counter:triangles-in", "треугольников на входе"},
        {"ru", "counter:triangles-skipped", "треугольников отброшено"},
        {"ru", "counter:polygons-sorted", "многоугольников упорядочено"},
        {"ru", "counter:polygons-without-pixels", "многоугольников без единого пикселя"},
        {"ru", "counter:polygons-made", "многоугольников всего, с частями"},
        {"ru", "counter:polygons-painted", "многоугольников нарисовано"},
        {"ru", "counter:pixels-painted", "пикселей закрашено"},
        {"ru", "counter:reorderings", "перестановок"},
        {"ru", "counter:splits", "разрезаний многоугольников"},
        {"ru", "counter:cycles-unresolved", "неустранённых циклов"},
        {"ru", "counter:test-1-depth-run", "проверка 1 (по глубине): выполнений"},
        {"ru", "counter:test-1-depth-passed", "проверка 1 (по глубине): успешных"},
        {"ru", "counter:test-2-x-run", "проверка 2 (оболочки по x): выполнений"},
        {"ru", "counter:test-2-x-passed", "проверка 2 (оболочки по x): успешных"},
        {"ru", "counter:test-3-y-run", "проверка 3 (оболочки по y): выполнений"},
        {"ru", "counter:test-3-y-passed", "проверка 3 (оболочки по y): успешных"},
        {"ru", "counter:test-4-p-behind-q-plane-run", "проверка 4 (P за плоскостью Q): выполнений"},
        {"ru", "counter:test-4-p-behind-q-plane-passed", "проверка 4 (P за плоскостью Q): успешных"},
        {"ru", "counter:test-5-q-before-p-plane-run", "проверка 5 (Q перед плоскостью P): выполнений"},
        {"ru", "counter:test-5-q-before-p-plane-passed", "проверка 5 (Q перед плоскостью P): успешных"},
        {"ru", "counter:test-6-projections-run", "проверка 6 (проекции не пересекаются): выполнений"},
        {"ru", "counter:test-6-projections-passed", "проверка 6 (проекции не пересекаются): успешных"},
        {"ru", "counter:test-7-p-behind-q-where-overlapping-run", "проверка 7 (P за Q там, где проекции перекрываются): выполнений"},
        {"ru", "counter:test-7-p-behind-q-where-overlapping-passed", "проверка 7 (P за Q там, где проекции перекрываются): успешных"},
        {"ru", "step:sort", "сортировка по глубине"},
        {"ru", "step:split", "рассечение треугольника"},
        {"ru", "step:reorder", "перестановка в списке"},
        {"ru", "step:polygon", "многоугольник"},
    };

    explicit Painter(const hsr::sdk::Params& p)
        : newell_(p.choice("mode") == 0), key_mid_(p.choice("naive-key") == 1),
          cull_backfaces_(p.boolean("cull-backfaces")), max_polygons_(uint64_t(p.integer("max-polygons"))),
          max_reorderings_(uint64_t(p.integer("max-reorderings"))) {}

    // render_steps (from StepwiseRemover) takes one step for the sort, then one per polygon painted,
    // per reordering and per split, in the order they happen.

private:
    // Sort order: farther key first, then lower polygon index (scene order).
    struct Key {
        double depth;
        uint32_t id;
    };
    struct FartherFirst {
        bool operator()(const Key& a, const Key& b) const {
            return a.depth > b.depth || (a.depth == b.depth && a.id < b.id);
        }
    };

    friend class hsr::sdk::StepwiseRemover<Painter>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        geometry_.begin_frame(scene.raw(), camera, cull_backfaces_);
        width_ = camera.width;
        height_ = camera.height;
        stats_ = SortStats{};
        auto finish = [&] { report(counters); };
        try {
            collect(scene);
            if (target.depth_tests() == nullptr)
                paint_all<false>(target, steps);
            else
                paint_all<true>(target, steps);
        } catch (const hsr::sdk::StepLimitReached&) {
            finish();
            throw;
        }
        finish();
    }

    void report(hsr::sdk::Counters& counters) const {
        const SortStats& s = stats_;
        counters.set("triangles-in", s.triangles_in);
        counters.set("triangles-skipped", s.triangles_skipped);
        counters.set("polygons-sorted", s.polygons_sorted);
        counters.set("polygons-without-pixels", s.polygons_dropped);
        counters.set("polygons-made", store_.polygons.size());
        counters.set("polygons-painted", s.polygons_painted);
        counters.set("pixels-painted", s.pixels_painted);
        if (!newell_) return;
        counters.set("reorderings", s.reorderings);
        counters.set("splits", s.splits);
        counters.set("cycles-unresolved", s.unresolved);
        static constexpr const char* kRun[7] = {
            "test-1-depth-run",
            "test-2-x-run",
            "test-3-y-run",
            "test-4-p-behind-q-plane-run",
            "test-5-q-before-p-plane-run",
            "test-6-projections-run",
            "test-7-p-behind-q-where-overlapping-run",
        };
        static constexpr const char* kPassed[7] = {
            "test-1-depth-passed",
            "test-2-x-passed",
            "test-3-y-passed",
            "test-4-p-behind-q-plane-passed",
            "test-5-q-before-p-plane-passed",
            "test-6-projections-passed",
            "test-7-p-behind-q-where-overlapping-passed",
        };
        for (int k = 0; k < 7; ++k) {
            counters.set(kRun[k], s.run[k]);
            counters.set(kPassed[k], s.passed[k]);
        }
    }

    // The refusal when the polygons would pass max-polygons.
    void reserve(uint64_t more) const {
        if (store_.polygons.size() + more > max_polygons_)
            throw hsr::sdk::Unsupported("painter: the frame needs more than max-polygons=" +
                                        std::to_string(max_polygons_) + " polygons (counting split pieces)");
    }

    // Every triangle of every placement as its clipped polygon, with its plane and extents.
    void collect(const hsr::sdk::Scene& scene) {
        store_.clear();
        const uint32_t* indices = scene.raw().indices;
        ClipVertex polygon[raster::kMaxClipVertices];
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            geometry_.place(placement);
            const uint32_t end = placement.first_triangle + placement.triangle_count;
            for (uint32_t t = placement.first_triangle; t < end; ++t) {
                ++stats_.triangles_in;
                const int count = geometry_.clipped_polygon(t, polygon);
                Polygon like;
                like.face = t;
                like.instance = placement.instance;
                if (count >= 3)
                    like.plane = painter::oriented_plane(geometry_.clip_vertex(indices[3 * size_t(t)]),
                                                         geometry_.clip_vertex(indices[3 * size_t(t) + 1]),
                                                         geometry_.clip_vertex(indices[3 * size_t(t) + 2]));
                if (count < 3 || like.plane == glm::dvec4(0.0)) {
                    ++stats_.triangles_skipped;
                    continue;
                }
                reserve(1);
                if (!add_polygon(polygon, count, like)) ++stats_.triangles_skipped;
            }
        }
        stats_.polygons_sorted = store_.polygons.size() - stats_.polygons_dropped;
    }

    // Stores a polygon (or a piece) and marks it done at once when it covers no pixel centre of the
    // image, which saves sorting the many triangles of a fine mesh that fall between pixel centres.
    // False when it could not be stored (a corner that does not project).
    bool add_polygon(const ClipVertex* corners, int count, const Polygon& like, const painter::Cut* cut = nullptr) {
        if (!store_.add(geometry_.viewport(), corners, count, like, cut)) return false;
        Polygon& p = store_.polygons.back();
        if (cut != nullptr) narrow_pixels(p);
        if (!covers_pixels(p)) {
            store_.done.back() = 1;
            ++stats_.polygons_dropped;
        }
        return true;
    }

    bool covers_pixels(const Polygon& p) const {
        const painter::Extent& e = p.extent;
        if (e.x1 < -1.0 || e.y1 < -1.0 || e.x0 > width_ + 1.0 || e.y0 > height_ + 1.0) return false;
        if (e.x1 - e.x0 > 4.0 || e.y1 - e.y0 > 4.0) return true;  // small ones are rasterized to see
        bool covered = false;
        for_each_pixel(p, whole_image(), [&](const raster::TriangleSetup&, int32_t, int32_t, double, double) {
            covered = true;
        });
        return covered;
    }

    // A rectangle of pixels, inclusive.
    struct PixelRect {
        int32_t x0, y0, x1, y1;
    };
    PixelRect whole_image() const { return {0, 0, int32_t(width_) - 1, int32_t(height_) - 1}; }

    // Calls visit(setup, x, y, i, j) for every pixel centre of polygon p inside `rect`: the pixels
    // its root polygon covers (GeometryStage::rasterize_polygon) that its cuts keep.
    template <class Visit>
    void for_each_pixel(const Polygon& p, const PixelRect& rect, Visit&& visit) const {
        const Polygon& root = store_.polygons[p.root];
        const painter::Cut* cuts = store_.cuts_of(p);
        const uint32_t cut_count = p.cut_count;
        const double to_ndc_x = 2.0 / width_, to_ndc_y = 2.0 / height_;
        const int32_t px0 = std::max(rect.x0, p.pixels_x0), py0 = std::max(rect.y0, p.pixels_y0);
        const int32_t px1 = std::min(rect.x1, p.pixels_x1), py1 = std::min(rect.y1, p.pixels_y1);
        if (px0 > px1 || py0 > py1) return;
        geometry_.rasterize_polygon(store_.corners_of(root), int(root.count), [&](const raster::TriangleSetup& s) {
            const int32_t x0 = std::max(px0, s.min_x), y0 = std::max(py0, s.min_y);
            const int32_t x1 = std::min(px1, s.max_x), y1 = std::min(py1, s.max_y);
            if (x0 > x1 || y0 > y1) return;
            raster::for_each_covered_pixel_in(s, x0, y0, x1, y1, [&](int32_t x, int32_t y, double i, double j) {
                if (cut_count != 0) {
                    // The triangle's point at this pixel centre, in NDC.
                    const glm::dvec4 point((x + 0.5) * to_ndc_x - 1.0, 1.0 - (y + 0.5) * to_ndc_y,
                                           2.0 * s.depth.at(i, j) - 1.0, 1.0);
                    for (uint32_t k = 0; k < cut_count; ++k) {
                        const double side = glm::dot(cuts[k].plane, point);
                        if (cuts[k].strict ? !(side > 0.0) : !(side >= 0.0)) return;
                    }
                }
                visit(s, x, y, i, j);
            });
        });
    }

    // Sets a piece's pixel box (Polygon::pixels_*): the union, over the triangles its root is
    // rasterized as, of what narrow_to_cuts leaves of the box it had from the polygon it was cut from.
    void narrow_pixels(Polygon& p) const {
        const Polygon& root = store_.polygons[p.root];
        const PixelRect image = whole_image();
        const PixelRect from{std::max(image.x0, p.pixels_x0), std::max(image.y0, p.pixels_y0),
                             std::min(image.x1, p.pixels_x1), std::min(image.y1, p.pixels_y1)};
        PixelRect box{INT32_MAX, INT32_MAX, INT32_MIN, INT32_MIN};
        geometry_.rasterize_polygon(store_.corners_of(root), int(root.count), [&](const raster::TriangleSetup& s) {
            PixelRect r{std::max(from.x0, s.min_x), std::max(from.y0, s.min_y), std::min(from.x1, s.max_x),
                        std::min(from.y1, s.max_y)};
            if (r.x0 > r.x1 || r.y0 > r.y1 || !narrow_to_cuts(s, store_.cuts_of(p), p.cut_count, r)) return;
            box = {std::min(box.x0, r.x0), std::min(box.y0, r.y0), std::max(box.x1, r.x1), std::max(box.y1, r.y1)};
        });
        p.pixels_x0 = box.x0;
        p.pixels_y0 = box.y0;
        p.pixels_x1 = box.x1;
        p.pixels_y1 = box.y1;
    }

    // The bounding box of n points in window coordinates.
    struct WindowBox {
        double x0, x1, y0, y1;
    };
    static WindowBox window_box_of(const glm::dvec2* points, int n) {
        WindowBox b{INFINITY, -INFINITY, INFINITY, -INFINITY};
        for (int i = 0; i < n; ++i) {
            b.x0 = std::min(b.x0, points[i].x);
            b.x1 = std::max(b.x1, points[i].x);
            b.y0 = std::min(b.y0, points[i].y);
            b.y1 = std::max(b.y1, points[i].y);
        }
        return b;
    }

    // Narrows rectangle r to the pixels whose centres the cuts may keep on triangle s, so that a
    // small piece of a large triangle is not rasterized over the whole triangle. A cut's test at
    // pixel (x, y) (for_each_pixel) is a linear function A x + B y + C of the pixel, up to rounding:
    // r is clipped by A x + B y + C >= -tolerance for each cut, the tolerance far above the
    // rounding error of either form, and r becomes the bounding box of what is left. A cut plane
    // nearly the triangle's own has A and B near zero and keeps r nearly whole: no error bound on
    // the piece's corners is needed. False when nothing is left.
    bool narrow_to_cuts(const raster::TriangleSetup& s, const painter::Cut* cuts, uint32_t cut_count,
                        PixelRect& r) const {
        const double sx = 2.0 / width_, sy = 2.0 / height_;
        // NDC depth at pixel (x, y): 2 * depth.at(x - min_x, y - min_y) - 1 = zx x + zy y + z0.
        const double zx = 2.0 * s.depth.dx, zy = 2.0 * s.depth.dy;
        const double z0 = 2.0 * (s.depth.origin - s.depth.dx * s.min_x - s.depth.dy * s.min_y) - 1.0;
        const double depth_size =
            1.0 + 2.0 * (std::abs(s.depth.origin) + std::abs(s.depth.dx) * (std::abs(double(s.min_x)) + width_) +
                         std::abs(s.depth.dy) * (std::abs(double(s.min_y)) + height_));
        constexpr uint32_t kMostCuts = 64;  // more (not seen) keep r as it is
        constexpr int kMax = 4 + kMostCuts;
        if (cut_count > kMostCuts) return true;
        glm::dvec2 first[kMax], second[kMax];
        glm::dvec2 *a = first, *b = second;
        int n = 4;
        a[0] = {r.x0, r.y0};
        a[1] = {r.x1, r.y0};
        a[2] = {r.x1, r.y1};
        a[3] = {r.x0, r.y1};
        for (uint32_t k = 0; k < cut_count && n >= 1; ++k) {
            const glm::dvec4& c = cuts[k].plane;
            // c . (X, Y, Z, 1) with X = (x + 0.5) sx - 1, Y = 1 - (y + 0.5) sy, Z = zx x + zy y + z0.
            const double A = c.x * sx + c.z * zx, B = -c.y * sy + c.z * zy;
            const double C = c.x * (0.5 * sx - 1.0) + c.y * (1.0 - 0.5 * sy) + c.z * z0 + c.w;
            const double size = std::abs(c.x) * (1.0 + 2.0 * std::abs(double(r.x1)) * sx) +
                                std::abs(c.y) * (1.0 + 2.0 * std::abs(double(r.y1)) * sy) +
                                std::abs(c.z) * depth_size + std::abs(c.w);
            const double tolerance = 1e-9 * size;
            int m = 0;
            for (int i = 0; i < n; ++i) {
                const glm::dvec2 &p = a[i], &q = a[i + 1 == n ? 0 : i + 1];
                const double fp = A * p.x + B * p.y + C + tolerance, fq = A * q.x + B * q.y + C + tolerance;
                if (fp >= 0.0) b[m++] = p;
                if ((fp >= 0.0) != (fq >= 0.0)) b[m++] = p + (q - p) * (fp / (fp - fq));
            }
            n = m;
            std::swap(a, b);
        }
        if (n == 0) return false;
        const WindowBox box = window_box_of(a, n);
        constexpr double kSlack = 1e-6;  // the clipped corners' own rounding
        r = {std::max(r.x0, int32_t(std::floor(box.x0 - kSlack))),
             std::max(r.y0, int32_t(std::floor(box.y0 - kSlack))),
             std::min(r.x1, int32_t(std::ceil(box.x1 + kSlack))),
             std::min(r.y1, int32_t(std::ceil(box.y1 + kSlack)))};
        return r.x0 <= r.x1 && r.y0 <= r.y1;
    }

    // Test 6 made exact: no pixel centre of the image belongs to both polygons. Separated
    // projections (the separating-axis test over their corners) answer first, then a pixel centre
    // deep inside the overlap of the projections; otherwise both are rasterized over the overlap.
    bool pixels_disjoint(const Polygon& p, const Polygon& q) {
        if (painter::projections_disjoint(store_.window_of(p), p.count, store_.window_of(q), q.count)) return true;
        const painter::Extent &a = p.extent, &b = q.extent;
        const PixelRect image = whole_image();
        PixelRect rect{std::max(image.x0, int32_t(std::floor(std::max(a.x0, b.x0))) - 1),
                       std::max(image.y0, int32_t(std::floor(std::max(a.y0, b.y0))) - 1),
                       std::min(image.x1, int32_t(std::ceil(std::min(a.x1, b.x1))) + 1),
                       std::min(image.y1, int32_t(std::ceil(std::min(a.y1, b.y1))) + 1)};
        if (p.count <= kMaxCorners && q.count <= kMaxCorners) {
            glm::dvec2 overlap[2 * kMaxCorners], scratch[2 * kMaxCorners];
            const int n = painter::convex_intersection(store_.window_of(p), p.count, store_.window_of(q), q.count,
                                                       overlap, scratch);
            if (n >= 3) {
                if (shares_a_pixel_centre(overlap, n)) return false;
                // Pixel centres of both lie in the overlap, give or take the snapping of corners.
                const WindowBox box = window_box_of(overlap, n);
                rect = {std::max(rect.x0, int32_t(std::floor(box.x0)) - 1),
                        std::max(rect.y0, int32_t(std::floor(box.y0)) - 1),
                        std::min(rect.x1, int32_t(std::ceil(box.x1)) + 1),
                        std::min(rect.y1, int32_t(std::ceil(box.y1)) + 1)};
            }
        }
        if (rect.x0 > rect.x1 || rect.y0 > rect.y1) return true;
        const size_t columns = size_t(rect.x1 - rect.x0 + 1);
        mask_.assign(columns * size_t(rect.y1 - rect.y0 + 1), 0);
        for_each_pixel(p, rect, [&](const raster::TriangleSetup&, int32_t x, int32_t y, double, double) {
            mask_[size_t(y - rect.y0) * columns + size_t(x - rect.x0)] = 1;
        });
        bool shared = false;
        for_each_pixel(q, rect, [&](const raster::TriangleSetup&, int32_t x, int32_t y, double, double) {
            shared = shared || mask_[size_t(y - rect.y0) * columns + size_t(x - rect.x0)] != 0;
        });
        return !shared;
    }

    // True when a pixel centre of the image next to the overlap's centre lies well inside it (by
    // more than snapping and rounding move an edge), so that both polygons cover it.
    bool shares_a_pixel_centre(const glm::dvec2* overlap, int n) const {
        constexpr double kInside = 1.0 / 16.0;
        glm::dvec2 centre(0.0);
        for (int k = 0; k < n; ++k) centre += overlap[k];
        centre /= double(n);
        const double x = std::floor(centre.x - 0.5), y = std::floor(centre.y - 0.5);
        for (const glm::dvec2 pixel : {glm::dvec2(x, y), glm::dvec2(x + 1, y), glm::dvec2(x, y + 1), glm::dvec2(x + 1, y + 1)}) {
            if (pixel.x < 0.0 || pixel.y < 0.0 || pixel.x >= width_ || pixel.y >= height_) continue;
            if (painter::deep_inside(pixel + 0.5, overlap, n, kInside)) return true;
        }
        return false;
    }

    glm::dvec2 window_xy(const ClipVertex& c) const { return glm::dvec2(geometry_.viewport().project(c.position)); }

    template <bool kCountPaints, class Steps>
    void paint_all(hsr::sdk::VisibilityBuffer& target, Steps& steps) {
        const raster::PixelBuffers buffers(target);
        if constexpr (Steps::enabled) sort_step(steps);
        if (!newell_) {
            std::vector<Key> order;
            for (uint32_t k = 0; k < store_.polygons.size(); ++k) {
                const painter::Extent& e = store_.polygons[k].extent;
                if (store_.done[k] == 0) order.push_back({key_mid_ ? 0.5 * (e.z0 + e.z1) : e.z1, k});
            }
            std::sort(order.begin(), order.end(), FartherFirst{});
            for (const Key& key : order) paint<kCountPaints>(key.id, buffers, steps);
            return;
        }
        depth_sort<kCountPaints>(buffers, steps);
    }

    // Newell, Newell & Sancha: `waiting` holds the polygons not yet painted nor moved, farthest
    // first; `moved` the chain of polygons moved ahead of the one below them, the last one first in
    // line. The head (the last moved one, else the farthest waiting one) is painted once it can hide
    // none of the others.
    template <bool kCountPaints, class Steps>
    void depth_sort(const raster::PixelBuffers& buffers, Steps& steps) {
        waiting_.clear();
        moved_.clear();
        disjoint_pairs_.clear();
        bins_.reset(width_, height_);
        for (uint32_t k = 0; k < store_.polygons.size(); ++k) enter(k);
        while (true) {
            uint32_t head;
            if (!moved_.empty())
                head = moved_.back();
            else if (!waiting_.empty())
                head = waiting_.begin()->id;
            else
                break;
            const uint32_t blocker = find_blocker(head);
            if (blocker == kNone) {
                remove(head);
                paint<kCountPaints>(head, buffers, steps);
            } else if (pierce(head, blocker)) {
                // Each may hide the other, and no order of the two can be right: a cut is needed
                // whatever else the chain would find, so it is made at once.
                cut(plane_cut(head, blocker), steps);
            } else if (!store_.polygons[blocker].marked) {
                if (stats_.reorderings == max_reorderings_)
                    throw hsr::sdk::Unsupported("painter: the depth sort needs more than max-reorderings=" +
                                                std::to_string(max_reorderings_) +
                                                " moves of a polygon ahead (too many overlapping cycles)");
                waiting_.erase({store_.polygons[blocker].extent.z1, blocker});
                store_.polygons[blocker].marked = true;
                moved_.push_back(blocker);
                ++stats_.reorderings;
                if constexpr (Steps::enabled) reorder_step(head, blocker, steps);
            } else {
                split<kCountPaints>(head, blocker, buffers, steps);
            }
        }
    }

    // Puts polygon `id` in line (unless it is done): in the waiting order and in the bins.
    void enter(uint32_t id) {
        if (store_.done[id] != 0) return;
        const Polygon& p = store_.polygons[id];
        waiting_.insert({p.extent.z1, id});
        bins_.add(id, p.extent);
    }

    // The first polygon the head may hide (all seven tests failed), or kNone. The candidates come
    // from the bins the head's extent touches (the others pass tests 2 or 3 without being looked
    // at), each once, and only those reaching behind the head's nearest depth (the others pass
    // test 1 without being looked at).
    uint32_t find_blocker(uint32_t head) {
        if (seen_.size() < store_.polygons.size()) seen_.resize(store_.polygons.size(), 0);
        if (++query_ == 0) {  // the stamps wrapped around
            std::fill(seen_.begin(), seen_.end(), 0);
            query_ = 1;
        }
        seen_[head] = query_;
        const Polygon& p = store_.polygons[head];
        uint32_t blocker = kNone;
        bins_.for_each_near(p.extent, p.extent.z0, store_.done, [&](uint32_t id) {
            if (seen_[id] == query_) return false;
            seen_[id] = query_;
            const Polygon& q = store_.polygons[id];
            ++stats_.run[0];
            if (q.extent.z1 <= p.extent.z0) {  // Q is nearer than all of P
                ++stats_.passed[0];
                return false;
            }
            if (may_paint_before(p, q)) return false;
            blocker = id;
            return true;
        }, [&](uint32_t id) {  // test 1 passes for it, and for the rest of its bin unseen
            if (seen_[id] == query_) return;
            seen_[id] = query_;
            ++stats_.run[0];
            ++stats_.passed[0];
        });
        return blocker;
    }

    // Tests 2 to 7 for P and Q, whose depth extents overlap: true when P cannot hide Q.
    bool may_paint_before(const Polygon& p, const Polygon& q) {
        constexpr double m = painter::kOverlapMargin;
        const painter::Extent &a = p.extent, &b = q.extent;
        auto passes = [&](int test, bool result) {
            ++stats_.run[test];
            if (result) ++stats_.passed[test];
            return result;
        };
        if (passes(1, a.x1 + m < b.x0 || b.x1 + m < a.x0)) return true;
        if (passes(2, a.y1 + m < b.y0 || b.y1 + m < a.y0)) return true;
        if (passes(3, painter::sides_of(q.plane, store_.corners_of(p), p.count).all_far)) return true;
        if (passes(4, painter::sides_of(p.plane, store_.corners_of(q), q.count).all_near)) return true;
        if (passes(5, pixels_disjoint_remembered(p, q))) return true;
        return passes(6, behind_where_overlapping(p, q));
    }

    // Test 7, exact for two convex polygons: P lies behind Q wherever their projections overlap.
    // Tests 4 and 5 fail whenever a polygon crosses the other's plane somewhere, even outside the
    // overlap; without this test such a pair would be taken for a cycle and cut.
    bool behind_where_overlapping(const Polygon& p, const Polygon& q) const {
        if (p.count > kMaxCorners || q.count > kMaxCorners) return false;
        glm::dvec2 overlap[2 * kMaxCorners], scratch[2 * kMaxCorners];
        const int n = painter::convex_intersection(store_.window_of(p), p.count, store_.window_of(q), q.count,
                                                   overlap, scratch);
        return painter::farther_over(p.plane, q.plane, overlap, n, double(width_), double(height_));
    }

    // Test 6: pixels_disjoint, remembered per pair: a head tested again after the polygon it moved
    // ahead was painted, or a chain found again after a split, meets the same pairs, and polygons
    // do not change once made.
    bool pixels_disjoint_remembered(const Polygon& p, const Polygon& q) {
        const uint32_t a = uint32_t(&p - store_.polygons.data()), b = uint32_t(&q - store_.polygons.data());
        if (const int known = disjoint_pairs_.find(a, b); known >= 0) return known != 0;
        const bool disjoint = pixels_disjoint(p, q);
        disjoint_pairs_.remember(a, b, disjoint);
        return disjoint;
    }

    // Takes a polygon out of the line (waiting or moved) for good.
    void remove(uint32_t id) {
        Polygon& p = store_.polygons[id];
        store_.done[id] = 1;
        if (p.marked) {
            moved_.erase(std::find(moved_.begin(), moved_.end(), id));
            p.marked = false;
        } else {
            waiting_.erase({p.extent.z1, id});
        }
    }

    // True when the plane (oriented or not) has corners of polygon `id` strictly on both sides.
    bool crosses(const glm::dvec4& plane, uint32_t id) const {
        const Polygon& p = store_.polygons[id];
        const painter::Sides s = painter::sides_of(plane, store_.corners_of(p), p.count);
        return !s.all_near && !s.all_far;
    }

    // A cut that makes progress on a cycle (see split()): polygon `cut` by `plane`, the plane of
    // polygon `by` or, when by == kNone, the plane through the eye and an edge of `by_edge_of`.
    struct CycleCut {
        uint32_t cut = kNone;
        glm::dvec4 plane{0.0};
        uint32_t by = kNone;
        uint32_t by_edge_of = kNone;
    };

    // Polygon x may hide polygon y: cut one by the other's plane where that plane crosses it. When
    // each plane crosses the other polygon (they pass through one another), a plane cuts a polygon
    // from edge to edge, while the two meet only along a segment of that chord: the rest of the
    // chord is a cut no pair needed, and it crosses other polygons' segments, which then need a
    // cut on each side. So the polygon whose chord reaches least beyond the other polygon is cut;
    // where the two are as good (within a pixel), the one smaller on screen.
    CycleCut plane_cut(uint32_t x, uint32_t y) const {
        const bool cut_x = crosses(store_.polygons[y].plane, x), cut_y = crosses(store_.polygons[x].plane, y);
        if (cut_x && cut_y) {
            const double waste_x = chord_beyond(x, y).beyond, waste_y = chord_beyond(y, x).beyond;
            const bool prefer_y = std::abs(waste_x - waste_y) > 1.0 ? waste_y < waste_x : screen_area(y) < screen_area(x);
            if (prefer_y) return {y, store_.polygons[x].plane, x};
        }
        if (cut_x) return {x, store_.polygons[y].plane, y};
        if (cut_y) return {y, store_.polygons[x].plane, x};
        return {};
    }

    // True when polygons x and y pass through one another: the chord y's plane cuts across x
    // reaches into y by more than a hundredth of a pixel.
    bool pierce(uint32_t x, uint32_t y) const {
        if (!crosses(store_.polygons[y].plane, x) || !crosses(store_.polygons[x].plane, y)) return false;
        const Chord c = chord_beyond(x, y);
        return c.length - c.beyond > 0.01;
    }

    // The chord that the plane of polygon `by` cuts across polygon `cut`: its length on screen
    // (pixels) and the length of it outside polygon `by`. The chord lies in `by`'s plane, so it is
    // inside `by` exactly where its projection is inside `by`'s projection.
    struct Chord {
        double length = 0.0;
        double beyond = 0.0;
    };
    Chord chord_beyond(uint32_t cut, uint32_t by) const {
        const Polygon &c = store_.polygons[cut], &b = store_.polygons[by];

        const ClipVertex* corners = store_.corners_of(c);
        glm::dvec2 ends[2];
        int found = 0;
        for (uint32_t k = 0; k < c.count && found < 2; ++k) {
            const glm::dvec4 &p = corners[k].position, &q = corners[k + 1 == c.count ? 0 : k + 1].position;
            const double dp = glm::dot(b.plane, p), dq = glm::dot(b.plane, q);
            if ((dp < 0.0) == (dq < 0.0)) continue;
            const glm::dvec4 crossing = p + (q - p) * (dp / (dp - dq));
            ends[found++] = glm::dvec2(geometry_.viewport().project(crossing));
        }
        if (found < 2) return {};
        return {glm::length(ends[1] - ends[0]),
                painter::length_outside(ends[0], ends[1], store_.window_of(b), int(b.count))};
    }

    double screen_area(uint32_t id) const {
        const Polygon& p = store_.polygons[id];
        const ClipVertex* c = store_.corners_of(p);
        double twice = 0.0;
        for (uint32_t k = 0; k < p.count; ++k) {
            const glm::dvec2 a = window_xy(c[k]), b = window_xy(c[k + 1 == p.count ? 0 : k + 1]);
            twice += a.x * b.y - a.y * b.x;
        }
        return 0.5 * std::abs(twice);
    }

    // The plane through the eye and an edge of polygon `outline` (in NDC, the line through two of
    // its corners) that crosses polygon `cut`: the piece beyond it no longer overlaps `outline`.
    CycleCut edge_cut(uint32_t cut, uint32_t outline) const {
        const Polygon& o = store_.polygons[outline];
        const ClipVertex* c = store_.corners_of(o);
        for (uint32_t k = 0; k < o.count; ++k) {
            const glm::dvec4 &a4 = c[k].position, &b4 = c[k + 1 == o.count ? 0 : k + 1].position;
            const glm::dvec2 a(a4.x / a4.w, a4.y / a4.w), b(b4.x / b4.w, b4.y / b4.w);
            const glm::dvec2 normal(a.y - b.y, b.x - a.x);
            const glm::dvec4 plane(normal.x, normal.y, 0.0, -glm::dot(normal, a));
            if (crosses(plane, cut)) return {cut, plane, kNone, outline};
        }
        return {};
    }

    // A cycle: the head may hide `blocker`, which is in the chain of moved polygons below it, so
    // each polygon of the chain from the blocker up may hide the next and the head may hide the
    // blocker. No two neighbours in it pierce one another (such a pair is cut when first met). Split the first pair of the cycle (the head and the blocker first) where one
    // polygon's plane crosses the other; in a cycle of polygons that do not cross one another's
    // planes, which is a true cyclic overlap, cut the head along the blocker's outline (or the
    // blocker along the head's). The pieces wait in line by their farthest depth, and the chain is
    // undone from the cut polygon up: what was moved there goes back in line, its order to be
    // found again.
    template <bool kCountPaints, class Steps>
    void split(uint32_t head, uint32_t blocker, const raster::PixelBuffers& buffers, Steps& steps) {
        const size_t first = size_t(std::find(moved_.begin(), moved_.end(), blocker) - moved_.begin());
        CycleCut c = plane_cut(head, blocker);
        for (size_t k = first; c.cut == kNone && k + 1 < moved_.size(); ++k) c = plane_cut(moved_[k], moved_[k + 1]);
        if (c.cut == kNone) c = edge_cut(head, blocker);
        if (c.cut == kNone) c = edge_cut(blocker, head);
        if (c.cut == kNone) {  // nothing left to cut (not seen): paint the head as it is
            ++stats_.unresolved;
            remove(head);
            paint<kCountPaints>(head, buffers, steps);
            return;
        }
        cut(c, steps);
    }

    // Splits polygon c.cut by c.plane: the pieces wait in line, and the chain is undone from the
    // cut polygon up.
    template <class Steps>
    void cut(const CycleCut& c, Steps& steps) {
        const Polygon original = store_.polygons[c.cut];  // add() may move the store
        const size_t n = original.count;
        split_corners_.assign(store_.corners_of(original), store_.corners_of(original) + n);
        split_front_.resize(n + 2);
        split_back_.resize(n + 2);
        int front_count = 0, back_count = 0;
        raster::split_by_plane(split_corners_.data(), int(n), c.plane, split_front_.data(), front_count,
                               split_back_.data(), back_count);
        reserve(2);
        // The chain below the cut polygon stays: each of those polygons may still hide the next,
        // and the farthest waiting one the first. From the cut polygon up it is undone.
        const size_t cut_at = size_t(std::find(moved_.begin(), moved_.end(), c.cut) - moved_.begin());
        for (size_t k = cut_at; k < moved_.size(); ++k) {
            Polygon& undone = store_.polygons[moved_[k]];
            undone.marked = false;
            if (moved_[k] != c.cut) waiting_.insert({undone.extent.z1, moved_[k]});
        }
        moved_.resize(std::min(cut_at, moved_.size()));
        remove(c.cut);
        const uint32_t first_piece = uint32_t(store_.polygons.size());
        const painter::Cut front_cut{c.plane, false}, back_cut{-c.plane, true};
        add_polygon(split_front_.data(), front_count, original, &front_cut);
        add_polygon(split_back_.data(), back_count, original, &back_cut);
        const uint32_t end = uint32_t(store_.polygons.size());
        for (uint32_t k = first_piece; k < end; ++k) enter(k);
        ++stats_.splits;
        if constexpr (Steps::enabled) {
            for (uint32_t k = first_piece; k < end; ++k) outline(k, HSR_STEP_SUBJECT, steps);
            hsr::sdk::Steps::Event event{"split", original.face, original.instance};
            event.phase = "split";
            const unsigned cut_face = original.face;
            if (c.by != kNone) {
                outline(c.by, HSR_STEP_CONTEXT, steps);
                const unsigned by_face = store_.polygons[c.by].face;
                if (steps.russian())
                    steps.step(event, "цикл: треугольник %u рассечён плоскостью треугольника %u", cut_face, by_face);
                else
                    steps.step(event, "cycle: triangle %u split by the plane of triangle %u", cut_face, by_face);
            } else {
                outline(c.by_edge_of, HSR_STEP_CONTEXT, steps);
                const unsigned by_face = store_.polygons[c.by_edge_of].face;
                if (steps.russian())
                    steps.step(event, "циклическое перекрытие: треугольник %u разрезан по контуру треугольника %u",
                               cut_face, by_face);
                else
                    steps.step(event, "cyclic overlap: triangle %u cut along the outline of triangle %u", cut_face,
                               by_face);
            }
        }
    }

    template <class Steps>
    void sort_step(Steps& steps) {
        const unsigned long long count = stats_.polygons_sorted;
        hsr::sdk::Steps::Event event{"sort"};
        event.phase = "sort";
        if (steps.russian())
            steps.step(event, "многоугольники упорядочены по %s глубине, дальние первыми: %llu %s",
                       newell_ || !key_mid_ ? "наибольшей" : "средней", count,
                       russian_plural(count, "многоугольник", "многоугольника", "многоугольников"));
        else
            steps.step(event, "%llu polygon%s sorted by %s depth, the farthest first", count, count == 1 ? "" : "s",
                       newell_ || !key_mid_ ? "farthest" : "mid");
    }

    template <class Steps>
    void reorder_step(uint32_t head, uint32_t blocker, Steps& steps) {
        const Polygon& q = store_.polygons[blocker];
        outline(head, HSR_STEP_CONTEXT, steps);
        outline(blocker, HSR_STEP_SUBJECT, steps);
        hsr::sdk::Steps::Event event{"reorder", q.face, q.instance};
        event.phase = "reorder";
        const unsigned p_face = store_.polygons[head].face, q_face = q.face;
        if (steps.russian())
            steps.step(event, "треугольник %u может заслонять треугольник %u (ни одна из семи проверок не прошла): "
                              "%u рисуется раньше",
                       p_face, q_face, q_face);
        else
            steps.step(event, "triangle %u may hide triangle %u (all seven tests failed): %u moves ahead", p_face,
                       q_face, q_face);
    }

    // Lines of a step: the outline of polygon `id` in window coordinates, unless it reaches far off
    // the image.
    template <class Steps>
    void outline(uint32_t id, hsr_step_role role, Steps& steps) const {
        const Polygon& p = store_.polygons[id];
        const ClipVertex* c = store_.corners_of(p);
        const double reach_x = 4.0 * width_, reach_y = 4.0 * height_;
        for (uint32_t k = 0; k < p.count; ++k) {
            const glm::dvec2 w = window_xy(c[k]);
            if (!(std::abs(w.x) <= reach_x && std::abs(w.y) <= reach_y)) return;
        }
        for (uint32_t k = 0; k < p.count; ++k) {
            const glm::dvec2 a = window_xy(c[k]), b = window_xy(c[k + 1 == p.count ? 0 : k + 1]);
            steps.line(float(a.x), float(a.y), float(b.x), float(b.y), role);
        }
    }

    // Paints polygon `id` over whatever is there: face, instance, depth and barycentrics at every
    // pixel centre it covers, but where it lies at exactly the depth already there and the surface
    // there comes first in the scene (the tie rule of hsr/visibility_rules.hpp).
    template <bool kCountPaints, class Steps>
    void paint(uint32_t id, const raster::PixelBuffers& b, Steps& steps) {
        const Polygon& p = store_.polygons[id];
        const uint32_t face = p.face, instance = p.instance;
        uint64_t written = 0;
        for_each_pixel(p, whole_image(), [&](const raster::TriangleSetup& s, int32_t x, int32_t y, double i, double j) {
            const size_t q = size_t(y) * b.stride + size_t(x);
            const float depth = raster::depth_at(s, i, j);
            if (depth == b.depth[q] && b.face[q] != HSR_NO_FACE &&
                !raster::drawn_before(instance, face, b.instance != nullptr ? b.instance[q] : 0, b.face[q])) {
                if constexpr (kCountPaints) ++b.tests[q];
                ++written;
                return;
            }
            b.depth[q] = depth;
            b.face[q] = face;
            if (b.instance != nullptr) b.instance[q] = instance;
            const glm::vec2 bary = raster::barycentrics_at(s, i, j);
            b.bary[2 * q] = bary.x;
            b.bary[2 * q + 1] = bary.y;
            if constexpr (kCountPaints) ++b.tests[q];
            ++written;
        });
        ++stats_.polygons_painted;
        stats_.pixels_painted += written;
        if constexpr (Steps::enabled) {
            outline(id, HSR_STEP_SUBJECT, steps);
            hsr::sdk::Steps::Event event{"polygon", face, instance, HSR_NO_LEVEL, written, 0};
            event.phase = "paint";
            const bool piece = p.cut_count != 0;
            if (steps.russian())
                steps.step(event, "%s %u нарисован%s: %llu %s", piece ? "часть треугольника" : "треугольник",
                           unsigned(face), piece ? "а" : "", (unsigned long long)written,
                           russian_plural(written, "пиксель", "пикселя", "пикселей"));
            else
                steps.step(event, "%s %u painted: %llu pixel%s", piece ? "piece of triangle" : "triangle",
                           unsigned(face), (unsigned long long)written, written == 1 ? "" : "s");
        }
    }

    bool newell_;
    bool key_mid_;
    bool cull_backfaces_;
    uint64_t max_polygons_;
    uint64_t max_reorderings_;
    uint32_t width_ = 0;
    uint32_t height_ = 0;
    SortStats stats_;
    raster::GeometryStage geometry_;  // these keep their buffers between frames
    painter::PolygonStore store_;
    std::set<Key, FartherFirst> waiting_;
    std::vector<uint32_t> moved_;
    painter::BinGrid bins_;
    std::vector<uint32_t> seen_;  // per polygon, the last find_blocker query that looked at it
    uint32_t query_ = 0;
    std::vector<uint8_t> mask_;  // pixels_disjoint's scratch
    static constexpr size_t kRememberedPairs = size_t(1) << 22;
    painter::PairAnswers disjoint_pairs_{kRememberedPairs};  // pixels_disjoint's answers this frame
    std::vector<ClipVertex> split_corners_, split_front_, split_back_;
};

}  // namespace

HSR_EXPORT_PLUGIN(Painter)
