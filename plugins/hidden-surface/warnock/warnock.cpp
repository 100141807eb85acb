// warnock: area subdivision (J. E. Warnock, "A Hidden-Surface Algorithm for Computer Generated
// Half-Tone Pictures", University of Utah Computer Science Technical Report TR 4-15, 1969; in the
// form of Sutherland, Sproull & Schumacker, "A Characterization of Ten Hidden-Surface Algorithms",
// Computing Surveys 6(1), 1974). A window of pixels, the whole image first, is decided when it is
// simple: no polygon (background), one polygon (drawn), or a polygon that surrounds the window in
// front of every other one there (filled); else it is split into four and each quarter is decided
// with the polygons not disjoint from it. A window of one pixel takes the polygon nearest at its
// centre.
//
// The polygons are the triangle setups of the SDK's geometry stage (clipped to near/far, guard band
// and clip planes), so a window is classified against a polygon with the setup's exact integer edge
// functions at the window's pixel centres, and depth, barycentrics and fill rule are the z-buffer's.
// docs/algorithms/warnock.md describes the cases, the counters and the steps.
#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

using hsr::sdk::russian_plural;

namespace {

namespace raster = hsr::raster;
using hsr::sdk::ParamSpec;

struct Polygon {
    raster::TriangleSetup setup;
    uint32_t face;
    uint32_t instance;
    // Bounds the rounding of the depth plane evaluated anywhere in the image, so that depth ranges
    // from a window's corners hold every pixel centre's depth_at.
    double depth_slack;
};

// A polygon's pixel bounds (its setup's), kept apart: many classifications end with them, and
// 16-byte records in a row keep the caches warm where 208-byte polygons would not.
struct PixelBounds {
    int32_t min_x, min_y, max_x, max_y;
};

// Pixels [x0, x1] x [y0, y1], inclusive.
struct Window {
    int32_t x0, y0, x1, y1;
    bool one_pixel() const { return x0 == x1 && y0 == y1; }
    uint64_t pixels() const { return uint64_t(x1 - x0 + 1) * uint64_t(y1 - y0 + 1); }
};

struct DepthRange {
    float nearest, farthest;
};

struct WindowStats {
    uint64_t empty = 0;
    uint64_t one_polygon = 0;
    uint64_t surrounder_in_front = 0;
    uint64_t one_pixel = 0;
    uint64_t subdivided = 0;
    uint64_t classifications = 0;
    uint64_t depth_comparisons = 0;
    uint64_t pixels_written = 0;
    uint64_t pixel_work = 0;  // what the per-pixel depth-test counts add up to
    uint64_t deepest_level = 0;

    void report(hsr::sdk::Counters& counters) const {
        counters.set("windows-empty", empty);
        counters.set("windows-one-polygon", one_polygon);
        counters.set("windows-surrounder-in-front", surrounder_in_front);
        counters.set("windows-one-pixel", one_pixel);
        counters.set("windows-subdivided", subdivided);
        counters.set("polygon-window-classifications", classifications);
        counters.set("pixel-depth-comparisons", depth_comparisons);
        counters.set("pixels-written", pixels_written);
        counters.set("pixels-depth-tested", pixel_work);
        counters.set("quadtree-depth", deepest_level);
    }
};

constexpr uint32_t kNone = ~0u;

const char* russian_polygons(uint64_t n) { return russian_plural(n, "многоугольник", "многоугольника", "многоугольников"); }
const char* russian_pixels(uint64_t n) { return russian_plural(n, "пиксель", "пикселя", "пикселей"); }

class Warnock final : public hsr::sdk::StepwiseRemover<Warnock> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "warnock", "1.0.0", "area subdivision (Warnock 1969): windows split in four until each is simple"};
    static inline const ParamSpec params[] = {
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::integer("max-polygons", "4000000", 1, 100000000,
                           "refuse a scene drawing more triangles (each polygon keeps its setup and bounds, ~225 bytes)"),
    };

    // Each step is one window decided; its phase is the case that decided it.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"empty", "no polygon in the window: background"},
        {"one-polygon", "one polygon in the window: draw it"},
        {"surrounder", "a surrounding polygon in front of all: fill"},
        {"pixel", "one pixel: the nearest polygon"},
        {"subdivide", "not simple: split the window in four"},
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description",
         "алгоритм Варнока (1969), разбиение окна: окно делится на четыре части, пока изображение в каждой из "
         "них не станет простым"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не выводить треугольники, обращённые к камере обратной стороной"},
        {"ru", "param:max-polygons", "предельное число многоугольников"},
        {"ru", "help:max-polygons",
         "отказаться от сцены, в которой выводится больше треугольников (каждый многоугольник хранит свои данные "
         "для растеризации и границы, около 225 байт)"},
        {"ru", "phase:empty", "в окне нет многоугольников: цвет фона"},
        {"ru", "phase:one-polygon", "в окне один многоугольник: нарисовать его"},
        {"ru", "phase:surrounder", "охватывающий многоугольник ближе всех остальных: залить им окно"},
        {"ru", "phase:pixel", "окно в один пиксель: ближайший многоугольник"},
        {"ru", "phase:subdivide", "случай не простой: разбить окно на четыре"},
        {"ru", "counter:polygons", "многоугольников"},
        {"ru", "counter:windows-empty", "пустых окон"},
        {"ru", "counter:windows-one-polygon", "окон с одним многоугольником"},
        {"ru", "counter:windows-surrounder-in-front", "окон, залитых охватывающим многоугольником"},
        {"ru", "counter:windows-one-pixel", "окон в один пиксель"},
        {"ru", "counter:windows-subdivided", "окон разбито на четыре"},
        {"ru", "counter:polygon-window-classifications", "проверок положения многоугольника относительно окна"},
        {"ru", "counter:pixel-depth-comparisons", "сравнений глубины в окнах в один пиксель"},
        {"ru", "counter:pixels-written", "пикселей записано"},
        {"ru", "counter:pixels-depth-tested", "пиксельных операций всего"},
        {"ru", "counter:quadtree-depth", "глубина дерева квадрантов"},
        {"ru", "step:window", "окно"},
    };
    static constexpr auto translations = hsr::sdk::join_translations(own_translations, hsr::raster::triangle_counter_translations);

    explicit Warnock(const hsr::sdk::Params& p)
        : cull_backfaces_(p.boolean("cull-backfaces")), max_polygons_(uint64_t(p.integer("max-polygons"))) {}

    // render_steps (from StepwiseRemover) takes one step per window decided, parents before their quarters
    // (depth first).

private:
    friend class hsr::sdk::StepwiseRemover<Warnock>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        uint64_t drawn_triangles = 0;
        for (uint32_t k = 0; k < scene.placement_count(); ++k) drawn_triangles += scene.placement(k).triangle_count;
        if (drawn_triangles > max_polygons_)
            throw hsr::sdk::Unsupported("warnock: the scene draws " + std::to_string(drawn_triangles) +
                                        " triangles, more than max-polygons=" + std::to_string(max_polygons_));
        geometry_.begin_frame(scene.raw(), camera, cull_backfaces_);
        collect_polygons(scene, drawn_triangles, double(camera.width) + double(camera.height));

        width_ = int32_t(target.width());
        height_ = int32_t(target.height());
        buffers_ = raster::PixelBuffers(target);
        stats_ = WindowStats{};
        // Level L windows are at most ceil(size / 2^L) pixels wide: one pixel by level ceil(log2 size).
        uint32_t levels = 1;
        while ((1 << (levels - 1)) < std::max(width_, height_)) ++levels;
        if (lists_.size() < levels) lists_.resize(levels);

        auto finish = [&] {
            geometry_.stats().report(counters);
            counters.set("polygons", polygons_.size());
            stats_.report(counters);
        };
        try {
            all_.resize(polygons_.size());
            std::iota(all_.begin(), all_.end(), 0u);
            const Window image{0, 0, width_ - 1, height_ - 1};
            float surrounder_far = 0.0f;
            const uint32_t surrounder = classify(all_, image, lists_[0], surrounder_far);
            decide(image, 0, surrounder, surrounder_far, steps);
        } catch (const hsr::sdk::StepLimitReached&) {
            finish();
            throw;
        }
        finish();
    }

    // The setups of every placement's triangles, in scene order (the z-buffer's drawing order).
    void collect_polygons(const hsr::sdk::Scene& scene, uint64_t drawn_triangles, double image_extent) {
        polygons_.clear();
        bounds_.clear();
        polygons_.reserve(drawn_triangles);  // one setup per triangle but for clipped ones
        bounds_.reserve(drawn_triangles);
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            geometry_.place(placement);
            const uint32_t end = placement.first_triangle + placement.triangle_count;
            for (uint32_t t = placement.first_triangle; t < end; ++t) {
                geometry_.process(t, [&](const raster::TriangleSetup& s) {
                    if (polygons_.size() >= max_polygons_)
                        throw hsr::sdk::Unsupported("warnock: clipping leaves more than max-polygons=" +
                                                    std::to_string(max_polygons_) + " polygons");
                    const double magnitude =
                        std::abs(s.depth.origin) + (std::abs(s.depth.dx) + std::abs(s.depth.dy)) * (image_extent + 2.0);
                    polygons_.push_back({s, t, placement.instance, 16.0 * DBL_EPSILON * magnitude});
                    bounds_.push_back({s.min_x, s.min_y, s.max_x, s.max_y});
                });
            }
        }
    }

    // The window-depth range of a polygon over the pixel centres of a window, within its bounds
    // (the plane is affine, so its extremes are at the corners), widened by its rounding slack.
    static DepthRange depth_range(const Polygon& p, const Window& w) {
        const raster::TriangleSetup& s = p.setup;
        const double i0 = std::max(w.x0, s.min_x) - s.min_x, i1 = std::min(w.x1, s.max_x) - s.min_x;
        const double j0 = std::max(w.y0, s.min_y) - s.min_y, j1 = std::min(w.y1, s.max_y) - s.min_y;
        const double a = s.depth.at(i0, j0), b = s.depth.at(i1, j0), c = s.depth.at(i0, j1), d = s.depth.at(i1, j1);
        const double lowest = std::min({a, b, c, d}) - p.depth_slack;
        const double highest = std::max({a, b, c, d}) + p.depth_slack;
        // depth_at holds depth to [0, 1] and rounds to float; both keep order.
        return {float(std::clamp(lowest, 0.0, 1.0)), float(std::clamp(highest, 0.0, 1.0))};
    }

    // Fills `out` with the polygons of `parent` not disjoint from window w, in the same order, and
    // returns the one surrounding w whose farthest depth there is nearest (the first of equals),
    // with that depth; kNone when none surrounds w (not looked for in a one-pixel window).
    uint32_t classify(const std::vector<uint32_t>& parent, const Window& w, std::vector<uint32_t>& out,
                      float& surrounder_far) {
        out.clear();
        stats_.classifications += parent.size();
        if (w.one_pixel()) {
            stats_.pixel_work += parent.size();
            if (buffers_.tests != nullptr)
                buffers_.tests[size_t(w.y0) * buffers_.stride + size_t(w.x0)] += uint32_t(parent.size());
        }
        uint32_t surrounder = kNone;
        for (const uint32_t k : parent) {
            const PixelBounds& b = bounds_[k];
            if (b.max_x < w.x0 || b.min_x > w.x1 || b.max_y < w.y0 || b.min_y > w.y1) continue;
            const raster::TriangleSetup& s = polygons_[k].setup;
            if (raster::misses(s, w.x0, w.y0, w.x1, w.y1)) continue;
            out.push_back(k);
            if (w.one_pixel() || !raster::covers(s, w.x0, w.y0, w.x1, w.y1)) continue;
            const float farthest = depth_range(polygons_[k], w).farthest;
            if (surrounder == kNone || farthest < surrounder_far) {
                surrounder = k;
                surrounder_far = farthest;
            }
        }
        return surrounder;
    }

    // Whether surrounding polygon `front` (farthest depth `far` over w) is the z-buffer's answer at
    // every pixel of w: strictly nearer than every polygon drawn before it, not farther than every
    // one drawn after it (of equal depths the z-buffer keeps the first).
    bool in_front_of_all(const std::vector<uint32_t>& list, const Window& w, uint32_t front, float far) {
        for (const uint32_t k : list) {
            if (k == front) continue;
            const float nearest = depth_range(polygons_[k], w).nearest;
            if (k < front ? !(far < nearest) : !(far <= nearest)) return false;
        }
        return true;
    }

    void write(const Polygon& p, int32_t x, int32_t y, double i, double j) {
        const size_t q = size_t(y) * buffers_.stride + size_t(x);
        buffers_.depth[q] = raster::depth_at(p.setup, i, j);
        buffers_.face[q] = p.face;
        if (buffers_.instance != nullptr) buffers_.instance[q] = p.instance;
        const glm::vec2 b = raster::barycentrics_at(p.setup, i, j);
        buffers_.bary[2 * q] = b.x;
        buffers_.bary[2 * q + 1] = b.y;
        if (buffers_.tests != nullptr) ++buffers_.tests[q];
        ++stats_.pixels_written;
        ++stats_.pixel_work;
    }

    // Draws polygon p at its covered pixel centres in w (every one of them when kAllCovered).
    template <bool kAllCovered>
    uint64_t draw(const Polygon& p, const Window& w) {
        const raster::TriangleSetup& s = p.setup;
        const int32_t x0 = std::max(w.x0, s.min_x), x1 = std::min(w.x1, s.max_x);
        const int32_t y0 = std::max(w.y0, s.min_y), y1 = std::min(w.y1, s.max_y);
        if (x0 > x1 || y0 > y1) return 0;
        const uint64_t before = stats_.pixels_written;
        raster::for_each_covered_pixel_in<kAllCovered>(
            s, x0, y0, x1, y1, [&](int32_t x, int32_t y, double i, double j) { write(p, x, y, i, j); });
        return stats_.pixels_written - before;
    }

    // Decides window w of quadtree level `level`, whose polygons are in lists_[level]; `surrounder`
    // and `surrounder_far` as classify() returned them.
    template <class Steps>
    void decide(const Window& w, uint32_t level, uint32_t surrounder, float surrounder_far, Steps& steps) {
        stats_.deepest_level = std::max<uint64_t>(stats_.deepest_level, level);
        const std::vector<uint32_t>& list = lists_[level];
        const unsigned long long count = list.size();
        if (list.empty()) {
            ++stats_.empty;
            if (Steps::enabled && steps.russian())
                window_step(steps, "empty", w, level, HSR_STEP_CONTEXT, HSR_NO_FACE, 0, 0,
                            "ни одного многоугольника: фон");
            else
                window_step(steps, "empty", w, level, HSR_STEP_CONTEXT, HSR_NO_FACE, 0, 0, "empty: background");
            return;
        }
        if (list.size() == 1) {
            ++stats_.one_polygon;
            const Polygon& p = polygons_[list[0]];
            const uint64_t written = draw<false>(p, w);
            if (Steps::enabled && steps.russian())
                window_step(steps, "one-polygon", w, level, HSR_STEP_WRITTEN, p.face, p.instance, written,
                            "один многоугольник (грань %u): закрашено %llu %s", p.face, (unsigned long long)written,
                            russian_pixels(written));
            else
                window_step(steps, "one-polygon", w, level, HSR_STEP_WRITTEN, p.face, p.instance, written,
                            "one polygon (face %u): %llu pixel%s drawn", p.face, (unsigned long long)written,
                            written == 1 ? "" : "s");
            return;
        }
        if (w.one_pixel()) {
            ++stats_.one_pixel;
            const Polygon* nearest = nullptr;
            float nearest_depth = 0.0f;
            for (const uint32_t k : list) {
                const Polygon& p = polygons_[k];
                const float z = raster::depth_at(p.setup, w.x0 - p.setup.min_x, w.y0 - p.setup.min_y);
                if (nearest == nullptr || z < nearest_depth) {
                    nearest = &p;
                    nearest_depth = z;
                }
            }
            stats_.depth_comparisons += list.size();
            stats_.pixel_work += list.size() - 1;  // and 1 for the write
            if (buffers_.tests != nullptr)
                buffers_.tests[size_t(w.y0) * buffers_.stride + size_t(w.x0)] += uint32_t(list.size()) - 1;
            write(*nearest, w.x0, w.y0, w.x0 - nearest->setup.min_x, w.y0 - nearest->setup.min_y);
            if (Steps::enabled && steps.russian())
                window_step(steps, "pixel", w, level, HSR_STEP_WRITTEN, nearest->face, nearest->instance, 1,
                            "один пиксель, %llu %s: ближайшая — грань %u", count, russian_polygons(count),
                            nearest->face);
            else
                window_step(steps, "pixel", w, level, HSR_STEP_WRITTEN, nearest->face, nearest->instance, 1,
                            "one pixel, %llu polygons: face %u nearest", count, nearest->face);
            return;
        }
        if (surrounder != kNone && in_front_of_all(list, w, surrounder, surrounder_far)) {
            ++stats_.surrounder_in_front;
            const Polygon& p = polygons_[surrounder];
            const uint64_t written = draw<true>(p, w);
            if (Steps::enabled && steps.russian())
                window_step(steps, "surrounder", w, level, HSR_STEP_WRITTEN, p.face, p.instance, written,
                            "грань %u охватывает окно и ближе всех остальных (%llu): залито %llu %s", p.face,
                            count - 1, (unsigned long long)written, russian_pixels(written));
            else
                window_step(steps, "surrounder", w, level, HSR_STEP_WRITTEN, p.face, p.instance, written,
                            "face %u surrounds the window in front of %llu other%s: %llu pixels filled", p.face,
                            count - 1, count == 2 ? "" : "s", (unsigned long long)written);
            return;
        }
        ++stats_.subdivided;
        if (Steps::enabled && steps.russian())
            window_step(steps, "subdivide", w, level, HSR_STEP_SUBJECT, HSR_NO_FACE, 0, 0,
                        "%llu %s, простого случая нет: окно делится на четыре", count, russian_polygons(count));
        else
            window_step(steps, "subdivide", w, level, HSR_STEP_SUBJECT, HSR_NO_FACE, 0, 0,
                        "%llu polygons, none simple: subdivided", count);
        const int32_t mid_x = w.x0 + (w.x1 - w.x0) / 2, mid_y = w.y0 + (w.y1 - w.y0) / 2;
        const Window quarters[4] = {{w.x0, w.y0, mid_x, mid_y},
                                    {mid_x + 1, w.y0, w.x1, mid_y},
                                    {w.x0, mid_y + 1, mid_x, w.y1},
                                    {mid_x + 1, mid_y + 1, w.x1, w.y1}};
        for (const Window& q : quarters) {
            if (q.x0 > q.x1 || q.y0 > q.y1) continue;  // a window one pixel wide or high splits in two
            float far = 0.0f;
            const uint32_t front = classify(list, q, lists_[level + 1], far);
            decide(q, level + 1, front, far, steps);
        }
    }

    // The step of a decided window: its box (with `role`), the phase that decided it and what was
    // decided, as text.
    template <class Steps, class... Args>
    void window_step(Steps& steps, const char* phase, const Window& w, uint32_t level, hsr_step_role role,
                     uint32_t face, uint32_t instance, uint64_t written, const char* what, Args... args) {
        if constexpr (Steps::enabled) {
            raster::pixel_box_lines(steps, w.x0, w.y0, w.x1, w.y1, width_, height_, role);
            char text[200];
            if constexpr (sizeof...(Args) == 0)
                std::snprintf(text, sizeof text, "%s", what);
            else
                std::snprintf(text, sizeof text, what, args...);
            hsr::sdk::Steps::Event event{"window", face, instance, level, written, 0};
            event.phase = phase;
            if (steps.russian())
                steps.step(event, "уровень %u, окно x %d..%d, y %d..%d: %s", level, w.x0, w.x1, w.y0, w.y1, text);
            else
                steps.step(event, "level %u window x %d..%d, y %d..%d: %s", level, w.x0, w.x1, w.y0, w.y1, text);
        }
    }

    bool cull_backfaces_;
    uint64_t max_polygons_;
    raster::GeometryStage geometry_;  // keeps its vertex buffers between frames
    std::vector<Polygon> polygons_;
    std::vector<PixelBounds> bounds_;  // of polygons_[k]
    std::vector<uint32_t> all_;                  // 0 .. polygon count - 1: the whole image's candidates
    std::vector<std::vector<uint32_t>> lists_;   // per quadtree level: the polygons of the window decided there
    raster::PixelBuffers buffers_;
    WindowStats stats_;
    int32_t width_ = 0, height_ = 0;
};

}  // namespace

HSR_EXPORT_PLUGIN(Warnock)
