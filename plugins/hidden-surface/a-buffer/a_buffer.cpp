// a-buffer: Carpenter's anti-aliased, area-averaged accumulation buffer (Loren Carpenter, "The
// A-buffer, an Antialiased Hidden Surface Method", SIGGRAPH 1984, Computer Graphics 18(3),
// pp. 103-108). Every pixel keeps a list of fragments: the part of one triangle inside the pixel,
// with a 4 x 8 bit mask of the pixel's subsamples it covers and its depth. At the end each list is
// sorted front to back, and fragments that nearer opaque ones hide on every sample they cover are
// dropped; the host shades the rest with any lighting model and composites them sample by sample,
// with the objects' opacities (ABI 1.4 fragment lists), so edges are anti-aliased and transparent
// objects show what lies behind them whatever order they come in.
//
// Coverage masks use the z-buffer's rasterizer (hsr/triangle_setup.hpp): the same integer edge
// functions, stepped exactly to the 32 subsample positions, so the fill rule holds at every sample
// and a sample on an edge shared by two triangles belongs to exactly one. A fragment's depth and
// barycentrics are taken at the centroid of its covered samples. The visibility buffer (one surface
// per pixel centre) is filled as zbuffer fills it, in the same pass. docs/algorithms/a-buffer.md
// describes the steps and the counters.
#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using hsr::sdk::russian_plural;

namespace {

namespace raster = hsr::raster;
using hsr::sdk::ParamSpec;

constexpr int kColumns = 8, kRows = 4;  // the subsample grid: bit 8 * row + column
static_assert(kColumns * kRows == HSR_COVERAGE_SAMPLES);
constexpr uint32_t kFullCoverage = 0xFFFFFFFFu;
constexpr uint32_t kEndOfList = 0xFFFFFFFFu;

// Subsample offsets from the pixel centre, in pixels: columns at (2c - 7) / 16, rows at (2r - 3) / 8.
constexpr double column_offset(int c) { return (2 * c - 7) / 16.0; }
constexpr double row_offset(int r) { return (2 * r - 3) / 8.0; }

// One fragment in a pixel's list (a singly linked list through a shared pool, as in the paper).
struct Fragment {
    uint32_t next;
    uint32_t face;
    uint32_t instance;
    uint32_t coverage;
    float depth;
    float b1, b2;
};

class ABuffer final : public hsr::sdk::StepwiseRemover<ABuffer> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "a-buffer", "1.0.0", "A-buffer (Carpenter 1984): per-pixel fragment lists with 4x8 coverage masks"};
    static inline const ParamSpec params[] = {
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::integer("max-fragments", "8388608", 1024, 268435456,
                           "fragments a frame may keep before the plugin refuses it (memory: 28 bytes each)"),
    };
    // ABI 1.5: the phases of Carpenter's A-buffer.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"rasterize", "rasterize a triangle into fragments with coverage masks, added to the pixels' lists"},
        {"resolve", "sort each pixel's fragments front to back and merge their coverage"},
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description", "A-буфер (Карпентер, 1984): списки фрагментов в каждом пикселе с масками покрытия 4×8"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не рисовать треугольники, повёрнутые к камере нелицевой стороной"},
        {"ru", "param:max-fragments", "предел числа фрагментов"},
        {"ru", "help:max-fragments",
         "сколько фрагментов может хранить кадр; кадр, которому нужно больше, не рисуется (28 байт памяти на фрагмент)"},
        {"ru", "phase:rasterize",
         "растеризовать треугольник во фрагменты с масками покрытия и добавить их в списки пикселей"},
        {"ru", "phase:resolve", "отсортировать фрагменты каждого пикселя от ближних к дальним и объединить их покрытие"},
        {"ru", "counter:fragments-made", "фрагментов создано"},
        {"ru", "counter:fragments-hidden", "фрагментов закрыто более близкими"},
        {"ru", "counter:fragments-kept", "фрагментов оставлено"},
        {"ru", "counter:pixels-partly-covered", "частично покрытых пикселей"},
        {"ru", "counter:fragments-per-pixel-max", "наибольшее число фрагментов в пикселе"},
        {"ru", "buffer:coverage", "покрытие пикселей"},
        {"ru", "step:triangle", "треугольник"},
        {"ru", "step:row", "строка изображения"},
    };
    static constexpr auto translations =
        hsr::sdk::join_translations(own_translations, raster::triangle_counter_translations,
                                    raster::depth_test_counter_translations);

    explicit ABuffer(const hsr::sdk::Params& p)
        : cull_backfaces_(p.boolean("cull-backfaces")), max_fragments_(uint64_t(p.integer("max-fragments"))) {}

    // render_steps (from StepwiseRemover) takes one step per input triangle (phase "rasterize"): its
    // fragments go to the pixels' lists, and the visibility buffer at pixel centres is filled as
    // zbuffer fills it; then one step per row of pixels (phase "resolve"), whose lists are sorted and
    // merged as render_fragments merges them, with the coverage so far as a step buffer.

    void render_fragments(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                          hsr::sdk::Counters& counters, hsr::sdk::FragmentWriter& fragments) {
        hsr::sdk::NoSteps no_steps;
        draw<true>(scene, camera, target, counters, no_steps);
        resolve(scene, target.width(), target.height(), counters, fragments);
    }

private:
    struct PixelStats {
        uint64_t depth_tested = 0;
        uint64_t written = 0;
    };

    friend class hsr::sdk::StepwiseRemover<ABuffer>;

    // render(): the visibility buffer alone, no fragments. render_steps(): the same buffer, and the
    // fragment lists made and resolved for the steps to show.
    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        if constexpr (Steps::enabled) {
            draw<true>(scene, camera, target, counters, steps);
            resolve_steps(scene, steps);
        } else {
            draw<false>(scene, camera, target, counters, steps);
        }
    }

    template <bool kFragments, class Steps>
    void draw(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
              hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        geometry_.begin_frame(scene.raw(), camera, cull_backfaces_);
        width_ = target.width();
        height_ = target.height();
        if constexpr (kFragments) {
            head_.assign(size_t(width_) * height_, kEndOfList);
            pool_.clear();
        }
        PixelStats pixels;
        try {
            if (target.depth_tests() == nullptr)
                draw_triangles<kFragments, false>(scene, target, pixels, steps);
            else
                draw_triangles<kFragments, true>(scene, target, pixels, steps);
        } catch (const hsr::sdk::StepLimitReached&) {
            report(counters, pixels);
            throw;
        }
        report(counters, pixels);
    }

    void report(hsr::sdk::Counters& counters, const PixelStats& pixels) const {
        geometry_.stats().report(counters);
        counters.set("pixels-depth-tested", pixels.depth_tested);
        counters.set("pixels-written", pixels.written);
    }

    template <bool kFragments, bool kCountTests, class Steps>
    void draw_triangles(const hsr::sdk::Scene& scene, hsr::sdk::VisibilityBuffer& target, PixelStats& pixels,
                        Steps& steps) {
        const raster::PixelBuffers buffers(target);
        const uint32_t* indices = scene.raw().indices;
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement placement = scene.placement(k);
            geometry_.place(placement);
            const uint32_t end = placement.first_triangle + placement.triangle_count;
            for (uint32_t t = placement.first_triangle; t < end; ++t) {
                const raster::TriangleStats before = geometry_.stats();
                const PixelStats pixels_before = pixels;
                const size_t fragments_before = pool_.size();
                geometry_.process(t, [&](const raster::TriangleSetup& s) {
                    raster::DepthTest<raster::DepthRule::kNearer, kCountTests> test(buffers, t, placement.instance);
                    raster::for_each_covered_pixel(s, [&](int32_t x, int32_t y, double i, double j) { test(s, x, y, i, j); });
                    pixels.depth_tested += test.tested;
                    pixels.written += test.written;
                    if constexpr (kFragments) add_fragments(s, t, placement.instance);
                });
                if constexpr (Steps::enabled) geometry_.outline_lines(steps, indices + 3 * size_t(t));
                triangle_step(steps, before, geometry_.stats(), t, placement.instance,
                              pixels.depth_tested - pixels_before.depth_tested, pixels.written - pixels_before.written,
                              pool_.size() - fragments_before);
            }
        }
    }

    // The step of one triangle: what became of it, its fragments, and the pixel centres it won.
    template <class Steps>
    static void triangle_step(Steps& steps, const raster::TriangleStats& before, const raster::TriangleStats& after,
                              uint32_t face, uint32_t instance, uint64_t tested, uint64_t written, uint64_t made) {
        if constexpr (Steps::enabled) {
            const hsr::sdk::Steps::Event event{"triangle", face, instance, HSR_NO_LEVEL, written, tested - written,
                                               "rasterize"};
            const unsigned long long f = face, n = made, w = written, r = tested - written;
            const bool ru = steps.russian();
            if (after.backface_culled != before.backface_culled)
                steps.step(event, ru ? "треугольник %llu: отброшен, он повёрнут к камере нелицевой стороной"
                                     : "triangle %llu: culled, it faces away from the camera", f);
            else if (after.outside != before.outside)
                steps.step(event, ru ? "треугольник %llu: вне поля зрения, не растеризуется"
                                     : "triangle %llu: outside the view, not drawn", f);
            else if (ru)
                steps.step(event, "треугольник %llu: %llu %s в списки пикселей; тест глубины в центрах пикселей: "
                           "записано %llu, отброшено %llu", f, n, russian_plural(n, "фрагмент", "фрагмента", "фрагментов"),
                           w, r);
            else
                steps.step(event, "triangle %llu: %llu fragment%s into the pixels' lists; at pixel centres %llu written, "
                           "%llu rejected by the depth test", f, n, n == 1 ? "" : "s", w, r);
        }
    }

    // One step per row of pixels: each list sorted front to back and its fragments merged as
    // resolve() merges them (nothing is written: the steps have no fragment writer), with the
    // fraction of every resolved pixel's samples covered as the "coverage" buffer.
    template <class Steps>
    void resolve_steps(const hsr::sdk::Scene& scene, Steps& steps) {
        std::vector<float> coverage(size_t(width_) * height_, 0.0f);
        std::vector<uint32_t> list;
        for (uint32_t y = 0; y < height_; ++y) {
            uint64_t lists = 0, kept = 0, hidden = 0, partial = 0, longest = 0;
            for (uint32_t x = 0; x < width_; ++x) {
                const size_t p = size_t(y) * width_ + x;
                list.clear();
                for (uint32_t f = head_[p]; f != kEndOfList; f = pool_[f].next) list.push_back(f);
                if (list.empty()) continue;
                ++lists;
                longest = std::max<uint64_t>(longest, list.size());
                std::stable_sort(list.begin(), list.end(), [&](uint32_t a, uint32_t b) {
                    return pool_[a].depth < pool_[b].depth || (pool_[a].depth == pool_[b].depth && a < b);
                });
                uint32_t closed = 0, covered = 0;
                for (uint32_t f : list) {
                    const Fragment& g = pool_[f];
                    if ((g.coverage & ~closed) == 0) {
                        ++hidden;
                        continue;
                    }
                    ++kept;
                    covered |= g.coverage;
                    if (scene.object_opacity(scene.face_object(g.face)) >= 1.0f) closed |= g.coverage;
                }
                partial += covered != kFullCoverage ? 1 : 0;
                coverage[p] = float(std::popcount(covered)) / float(HSR_COVERAGE_SAMPLES);
            }
            steps.box(0.0f, float(y), float(width_), float(y + 1), HSR_STEP_SUBJECT);
            steps.buffer("coverage", width_, height_, coverage.data());
            const hsr::sdk::Steps::Event event{"row", HSR_NO_FACE, 0, HSR_NO_LEVEL, kept, hidden, "resolve"};
            const unsigned long long row = y, n = lists, k = kept, h = hidden, e = partial, m = longest;
            const bool ru = steps.russian();
            if (lists == 0)
                steps.step(event, ru ? "строка %llu: фрагментов нет" : "row %llu: no fragments", row);
            else if (ru)
                steps.step(event, "строка %llu: списков — %llu (до %llu %s); видимых фрагментов — %llu, закрытых — "
                           "%llu; частично покрытых пикселей — %llu", row, n, m,
                           russian_plural(m, "фрагмента", "фрагментов", "фрагментов"), k, h, e);
            else
                steps.step(event, "row %llu: %llu list%s sorted by depth (the longest: %llu); %llu fragment%s "
                           "visible, %llu hidden by nearer ones; %llu pixel%s partly covered", row, n, n == 1 ? "" : "s",
                           m, k, k == 1 ? "" : "s", h, e, e == 1 ? "" : "s");
        }
    }

    // The fragments of one triangle setup: every pixel whose area it touches (its pixel-centre
    // bounds grown by one pixel), with the samples it covers.
    void add_fragments(const raster::TriangleSetup& s, uint32_t face, uint32_t instance) {
        // Edge function k at a subsample, relative to its value at the pixel centre: exact integers,
        // since a pixel step is kSubpixelScale grid units and the offsets are multiples of 1/16.
        int64_t at_column[3][kColumns], at_row[3][kRows];
        int64_t lowest[3], highest[3];  // the extremes over the 32 samples: corner samples
        for (int k = 0; k < 3; ++k) {
            for (int c = 0; c < kColumns; ++c) at_column[k][c] = s.edge_dx[k] / 16 * (2 * c - 7);
            for (int r = 0; r < kRows; ++r) at_row[k][r] = s.edge_dy[k] / 8 * (2 * r - 3);
            lowest[k] = std::min(at_column[k][0], at_column[k][kColumns - 1]) + std::min(at_row[k][0], at_row[k][kRows - 1]);
            highest[k] = std::max(at_column[k][0], at_column[k][kColumns - 1]) + std::max(at_row[k][0], at_row[k][kRows - 1]);
        }
        const int32_t x0 = std::max(s.min_x - 1, 0), x1 = std::min(s.max_x + 1, int32_t(width_) - 1);
        const int32_t y0 = std::max(s.min_y - 1, 0), y1 = std::min(s.max_y + 1, int32_t(height_) - 1);
        for (int32_t y = y0; y <= y1; ++y) {
            for (int32_t x = x0; x <= x1; ++x) {
                int64_t centre[3];
                for (int k = 0; k < 3; ++k)
                    centre[k] = s.edge_origin[k] + s.edge_dx[k] * (x - s.min_x) + s.edge_dy[k] * (y - s.min_y);
                if (centre[0] + highest[0] < 0 || centre[1] + highest[1] < 0 || centre[2] + highest[2] < 0) continue;
                uint32_t coverage = 0;
                double sum_x = 0.0, sum_y = 0.0;
                if (centre[0] + lowest[0] >= 0 && centre[1] + lowest[1] >= 0 && centre[2] + lowest[2] >= 0) {
                    coverage = kFullCoverage;  // every sample inside: the centroid is the centre
                } else {
                    for (int r = 0; r < kRows; ++r) {
                        for (int c = 0; c < kColumns; ++c) {
                            bool inside = true;
                            for (int k = 0; k < 3 && inside; ++k) inside = centre[k] + at_column[k][c] + at_row[k][r] >= 0;
                            if (!inside) continue;
                            coverage |= 1u << (kColumns * r + c);
                            sum_x += column_offset(c);
                            sum_y += row_offset(r);
                        }
                    }
                }
                if (coverage == 0) continue;
                if (pool_.size() >= max_fragments_)
                    throw hsr::sdk::Unsupported("a-buffer: the frame needs more than max-fragments=" +
                                                std::to_string(max_fragments_) + " fragments");
                const int samples = std::popcount(coverage);
                const double i = double(x - s.min_x) + sum_x / samples, j = double(y - s.min_y) + sum_y / samples;
                const glm::vec2 b = raster::barycentrics_at(s, i, j);
                const size_t p = size_t(y) * width_ + size_t(x);
                pool_.push_back({head_[p], face, instance, coverage, raster::depth_at(s, i, j), b.x, b.y});
                head_[p] = uint32_t(pool_.size() - 1);
            }
        }
    }

    // Each pixel's list sorted front to back; a fragment whose samples nearer opaque fragments
    // all cover is dropped; the rest go to the host.
    void resolve(const hsr::sdk::Scene& scene, uint32_t width, uint32_t height, hsr::sdk::Counters& counters,
                 hsr::sdk::FragmentWriter& out) {
        uint64_t hidden = 0, partial_pixels = 0, longest = 0;
        std::vector<uint32_t> list;
        for (uint32_t p = 0; p < width * height; ++p) {
            list.clear();
            for (uint32_t f = head_[p]; f != kEndOfList; f = pool_[f].next) list.push_back(f);
            if (list.empty()) continue;
            // Stable on equal depths: the triangle drawn first stays in front, as in the z-buffer.
            std::stable_sort(list.begin(), list.end(), [&](uint32_t a, uint32_t b) {
                return pool_[a].depth < pool_[b].depth || (pool_[a].depth == pool_[b].depth && a < b);
            });
            uint32_t closed = 0, covered = 0;
            uint64_t kept = 0;
            for (uint32_t f : list) {
                const Fragment& g = pool_[f];
                if ((g.coverage & ~closed) == 0) {
                    ++hidden;
                    continue;
                }
                out.add(p, g.face, g.instance, g.depth, g.coverage, g.b1, g.b2);
                ++kept;
                covered |= g.coverage;
                if (scene.object_opacity(scene.face_object(g.face)) >= 1.0f) closed |= g.coverage;
            }
            longest = std::max(longest, kept);
            partial_pixels += covered != kFullCoverage ? 1 : 0;
        }
        counters.set("fragments-made", pool_.size());
        counters.set("fragments-hidden", hidden);
        counters.set("fragments-kept", pool_.size() - hidden);
        counters.set("pixels-partly-covered", partial_pixels);
        counters.set("fragments-per-pixel-max", longest);
    }

    bool cull_backfaces_;
    uint64_t max_fragments_;
    raster::GeometryStage geometry_;
    uint32_t width_ = 0, height_ = 0;
    std::vector<uint32_t> head_;  // per pixel: its first fragment in pool_, or kEndOfList
    std::vector<Fragment> pool_;
};

}  // namespace

HSR_EXPORT_PLUGIN(ABuffer)
