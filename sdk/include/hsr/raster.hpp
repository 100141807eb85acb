// hsr raster helpers: a frame of triangles through the shared rasterizer (hsr/triangle_setup.hpp)
// for every rasterizing hidden-surface remover (plain, scanline, hierarchical and octree
// z-buffers): the input checks (validate_frame), the per-vertex transform and the per-triangle
// cull, clip and setup (GeometryStage), and the depth test at covered pixels (DepthTest).
// Header-only, part of hsr::sdk. docs/algorithms/zbuffer.md walks through the steps.
#pragma once

#include "hsr/abi.h"
#include "hsr/sdk.hpp"
#include "hsr/triangle_setup.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace hsr::raster {

static_assert(kMaxClipPlanes == HSR_MAX_CLIP_PLANES);

// ---------------------------------------------------------------------------------------------- //
// The depth test every z-buffer variant shares

// Which surface a depth test keeps.
enum class DepthRule {
    kNearer,   // strictly nearer wins: of equal depths, the one drawn first stays
    kFarther,  // strictly farther wins (zbuffer's depth-test=greater)
    // Nearer wins, and of equal depths the lower instance, then the lower face: the surface the
    // plain z-buffer draws first, whatever order the triangles come in (octree-zbuffer)
    kNearerThenLowerId,
};

// The visibility buffer's arrays as plain pointers, read once per frame.
struct PixelBuffers {
    float* depth = nullptr;
    uint32_t* face = nullptr;
    float* bary = nullptr;
    uint32_t* instance = nullptr;  // nullptr: the scene has no instances
    uint32_t* tests = nullptr;     // per-pixel depth-test counts, or nullptr
    size_t stride = 0;

    PixelBuffers() = default;
    explicit PixelBuffers(hsr::sdk::VisibilityBuffer& target)
        : depth(target.depth()), face(target.face()), bary(target.bary()), instance(target.instance()),
          tests(target.depth_tests()), stride(target.width()) {}
};

// The depth test and the writes at covered pixel centres of one triangle: depth, face, instance and
// perspective-correct barycentrics where the triangle wins, and the test and write counts. Make one
// per triangle (or per piece of one) as a local: its fields then live in registers in the pixel
// loop, which stores to face[] (uint32_t) could otherwise force it to reload.
template <DepthRule kRule, bool kCountTests>
struct DepthTest {
    float* depth;
    uint32_t* face;
    float* bary;
    uint32_t* instance;
    uint32_t* tests;
    size_t stride;
    uint32_t face_id;
    uint32_t instance_id;
    uint64_t tested = 0;
    uint64_t written = 0;

    DepthTest(const PixelBuffers& b, uint32_t face_id, uint32_t instance_id)
        : depth(b.depth), face(b.face), bary(b.bary), instance(b.instance), tests(b.tests), stride(b.stride),
          face_id(face_id), instance_id(instance_id) {}

    // Pixel (x, y) = (min_x + i, min_y + j) of the setup, covered by it.
    void operator()(const TriangleSetup& s, int32_t x, int32_t y, double i, double j) {
        ++tested;
        const size_t p = size_t(y) * stride + size_t(x);
        if constexpr (kCountTests) ++tests[p];
        const float z = depth_at(s, i, j);
        const float stored = depth[p];
        if constexpr (kRule == DepthRule::kNearer) {
            if (!(z < stored)) return;
        } else if constexpr (kRule == DepthRule::kFarther) {
            if (!(z > stored)) return;
        } else {
            if (!(z < stored || (z == stored && (instance != nullptr && instance[p] != instance_id
                                                     ? instance_id < instance[p]
                                                     : face_id < face[p]))))
                return;
        }
        ++written;
        depth[p] = z;
        face[p] = face_id;
        if (instance != nullptr) instance[p] = instance_id;
        const glm::vec2 b = barycentrics_at(s, i, j);
        bary[2 * p] = b.x;
        bary[2 * p + 1] = b.y;
    }
};

// The names a z-buffer reports DepthTest's counts under ("pixels-depth-tested": `tested`,
// "pixels-written": `written`), in Russian, for the plugin's `translations`.
inline constexpr std::array<hsr::sdk::TranslationSpec, 2> depth_test_counter_translations{{
    {"ru", "counter:pixels-depth-tested", "тестов глубины выполнено"},
    {"ru", "counter:pixels-written", "пикселей прошло тест глубины"},
}};

// ---------------------------------------------------------------------------------------------- //
// Whole-frame geometry: input checks, per-vertex transform, per-triangle cull/clip/setup

// What happened to the triangles of a frame. Every input triangle lands in exactly one of
// backface_culled, outside, degenerate, rasterized; clipped counts those that touched the near plane
// (and were not rejected before clipping).
struct TriangleStats {
    uint64_t in = 0;
    uint64_t backface_culled = 0;
    uint64_t clipped = 0;
    uint64_t outside = 0;     // trivially rejected, nothing left after clipping, or off the image
    uint64_t degenerate = 0;  // zero area, too thin to hold a pixel centre, or non-finite
    uint64_t rasterized = 0;  // at least one (sub-)triangle reached the pixel loop

    TriangleStats& operator+=(const TriangleStats& o) {
        in += o.in;
        backface_culled += o.backface_culled;
        clipped += o.clipped;
        outside += o.outside;
        degenerate += o.degenerate;
        rasterized += o.rasterized;
        return *this;
    }

    void report(hsr::sdk::Counters& counters) const {
        counters.set("triangles-in", in);
        counters.set("triangles-backface-culled", backface_culled);
        counters.set("triangles-clipped", clipped);
        counters.set("triangles-outside", outside);
        counters.set("triangles-degenerate", degenerate);
        counters.set("triangles-rasterized", rasterized);
    }
};

// The counters TriangleStats::report sets, in Russian, for the plugin's `translations`.
inline constexpr std::array<hsr::sdk::TranslationSpec, 6> triangle_counter_translations{{
    {"ru", "counter:triangles-in", "треугольников на входе"},
    {"ru", "counter:triangles-backface-culled", "треугольников отброшено как нелицевые"},
    {"ru", "counter:triangles-clipped", "треугольников пересекло ближнюю плоскость"},
    {"ru", "counter:triangles-outside", "треугольников вне области видимости"},
    {"ru", "counter:triangles-degenerate", "вырожденных треугольников"},
    {"ru", "counter:triangles-rasterized", "треугольников растеризовано"},
}};

// Reports the step of a triangle the geometry stage dropped between the stats `before` and `after`
// (back-facing or outside the view: phase "cull"; too thin to hold a pixel centre, or
// `covers_nothing`: phase "rasterize"), in the language the host asked for, and returns true; returns
// false, reporting nothing, for a triangle that reached the pixel loop and covered something.
template <class StepsT>
bool dropped_triangle_step(StepsT& steps, const TriangleStats& before, const TriangleStats& after, uint32_t face,
                           uint32_t instance, bool covers_nothing = false) {
    hsr::sdk::Steps::Event event{"triangle", face, instance, HSR_NO_LEVEL, 0, 0};
    const bool ru = steps.russian();
    if (after.backface_culled != before.backface_culled) {
        event.phase = "cull";
        steps.step(event, ru ? "треугольник %u: нелицевая грань (обращена от камеры), отброшен"
                             : "triangle %u: culled, it faces away from the camera", face);
    } else if (after.outside != before.outside) {
        event.phase = "cull";
        steps.step(event, ru ? "треугольник %u: вне области видимости, не рисуется"
                             : "triangle %u: outside the view, not drawn", face);
    } else if (after.degenerate != before.degenerate || covers_nothing) {
        event.phase = "rasterize";
        steps.step(event, ru ? "треугольник %u: не покрывает ни одного центра пикселя"
                             : "triangle %u: covers no pixel centre", face);
    } else {
        return false;
    }
    return true;
}

// Reports the step of one input triangle of a z-buffer (ABI 1.3) from what the geometry stage
// counted for it (stats before and after processing it) and what its depth tests did: a dropped
// triangle as dropped_triangle_step does, else phase "write" when it wrote a pixel, "depth-test"
// when the test rejected all it covered.
template <class StepsT>
void triangle_step(StepsT& steps, const TriangleStats& before, const TriangleStats& after, uint32_t face,
                   uint32_t instance, uint64_t tested, uint64_t written) {
    if constexpr (StepsT::enabled) {
        if (dropped_triangle_step(steps, before, after, face, instance, tested == 0)) return;
        hsr::sdk::Steps::Event event{"triangle", face, instance, HSR_NO_LEVEL, written, tested - written};
        event.phase = written > 0 ? "write" : "depth-test";
        const unsigned long long w = written, r = tested - written;
        if (steps.russian())
            steps.step(event, "треугольник %u: %s %llu %s, %s тестом глубины %llu", face,
                       hsr::sdk::russian_plural(w, "записан", "записано", "записано"), w,
                       hsr::sdk::russian_plural(w, "пиксель", "пикселя", "пикселей"),
                       hsr::sdk::russian_plural(r, "отброшен", "отброшено", "отброшено"), r);
        else
            steps.step(event, "triangle %u: %llu pixel%s written, %llu rejected by the depth test", face, w,
                       w == 1 ? "" : "s", r);
    }
}

// The step type of dropped_triangle_step and triangle_step ("triangle") in Russian, for the plugin's
// `translations`.
inline constexpr std::array<hsr::sdk::TranslationSpec, 1> triangle_step_translations{{
    {"ru", "step:triangle", "треугольник"},
}};

// Lines of a step (ABI 1.3): the outline of the pixels [x0, x1] x [y0, y1], clipped to a width x
// height image (nothing when the box misses it).
template <class StepsT>
void pixel_box_lines(StepsT& steps, int32_t x0, int32_t y0, int32_t x1, int32_t y1, int32_t width, int32_t height,
                     hsr_step_role role) {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, width - 1);
    y1 = std::min(y1, height - 1);
    if (x0 <= x1 && y0 <= y1) steps.box(float(x0), float(y0), float(x1 + 1), float(y1 + 1), role);
}

// Checks what a rasterizing plugin relies on and throws hsr::sdk::InvalidArgument with a one-line
// message starting with the plugin's name. Scans the index array once (cheap next to rendering).
inline void validate_frame(const char* plugin, const hsr_scene& scene, const hsr_camera& camera,
                           const hsr_visibility_buffer& target) {
    const std::string who = std::string(plugin) + ": ";
    auto fail = [&](const std::string& message) { throw hsr::sdk::InvalidArgument(who + message); };
    if (scene.struct_size < sizeof(hsr_scene)) fail("scene struct is smaller than the ABI this plugin was built with");
    if (camera.struct_size < sizeof(hsr_camera)) fail("camera struct is smaller than the ABI this plugin was built with");
    if (target.struct_size < sizeof(hsr_visibility_buffer))
        fail("visibility buffer struct is smaller than the ABI this plugin was built with");
    if (target.width != camera.width || target.height != camera.height)
        fail("visibility buffer is " + std::to_string(target.width) + "x" + std::to_string(target.height) +
             " but the camera is " + std::to_string(camera.width) + "x" + std::to_string(camera.height));
    if (camera.width == 0 || camera.height == 0) fail("image has zero size");
    if (camera.width > kMaxImageSize || camera.height > kMaxImageSize)
        fail("image " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
             " is larger than the supported " + std::to_string(kMaxImageSize) + " pixels per side");
    if (target.depth == nullptr || target.face == nullptr || target.bary == nullptr)
        fail("visibility buffer has a NULL array");
    for (float m : camera.view_projection)
        if (!std::isfinite(m)) fail("camera view_projection matrix is not finite");
    if (camera.struct_size >= offsetof(hsr_camera, clip_planes) + sizeof camera.clip_planes) {
        if (camera.clip_plane_count > HSR_MAX_CLIP_PLANES)
            fail("camera has " + std::to_string(camera.clip_plane_count) + " clip planes, more than " +
                 std::to_string(HSR_MAX_CLIP_PLANES));
        for (uint32_t k = 0; k < camera.clip_plane_count; ++k)
            for (float c : camera.clip_planes[k])
                if (!std::isfinite(c)) fail("camera clip plane " + std::to_string(k) + " is not finite");
    }
    if (scene.vertex_count > 0 && scene.positions == nullptr) fail("scene has NULL positions");
    if (scene.triangle_count == 0) return;
    if (scene.indices == nullptr) fail("scene has NULL indices");
    const uint64_t index_count = uint64_t(scene.triangle_count) * 3;
    uint32_t largest = 0;
    for (uint64_t k = 0; k < index_count; ++k) largest = std::max(largest, scene.indices[k]);
    if (largest >= scene.vertex_count)
        fail("a triangle refers to vertex " + std::to_string(largest) + " but the scene has " +
             std::to_string(scene.vertex_count) + " vertices");

    const hsr::sdk::Scene view(scene);
    const hsr_instance* last_checked = nullptr;  // instances of one object usually come together
    for (uint32_t k = 0; k < view.instance_count(); ++k) {
        const hsr_instance& i = view.instance(k);
        const std::string which = "instance " + std::to_string(k) + " ";
        if (i.struct_size < sizeof(hsr_instance)) fail(which + "is smaller than ABI 1.1's");
        if (uint64_t(i.first_triangle) + i.triangle_count > scene.triangle_count ||
            uint64_t(i.first_vertex) + i.vertex_count > scene.vertex_count)
            fail(which + "names triangles or vertices the scene does not have");
        for (float m : i.transform)
            if (!std::isfinite(m)) fail(which + "has a transform that is not finite");
        if (!(i.scale > 0.0f)) fail(which + "has a scale that is not positive");
        if (last_checked && last_checked->first_triangle == i.first_triangle &&
            last_checked->triangle_count == i.triangle_count && last_checked->first_vertex == i.first_vertex &&
            last_checked->vertex_count == i.vertex_count)
            continue;
        for (uint64_t c = 3 * uint64_t(i.first_triangle); c < 3 * (uint64_t(i.first_triangle) + i.triangle_count); ++c)
            if (scene.indices[c] < i.first_vertex || scene.indices[c] - i.first_vertex >= i.vertex_count)
                fail(which + "has a triangle whose vertex lies outside its vertex range");
        last_checked = &i;
    }
}

// Transforms every vertex once per frame, then turns triangles into TriangleSetups. Buffers are
// kept between frames, so a long-lived instance allocates nothing in steady state.
class GeometryStage {
public:
    // scene, camera and target sizes must have passed validate_frame. Then place() each placement
    // of the scene (hsr::sdk::Scene::placement) before processing its triangles.
    void begin_frame(const hsr_scene& scene, const hsr_camera& camera, bool cull_backfaces) {
        width_ = camera.width;
        height_ = camera.height;
        indices_ = scene.indices;
        positions_ = scene.positions;
        cull_backfaces_ = cull_backfaces;
        guard_ = GuardBand(width_, height_);
        viewport_ = Viewport(width_, height_);
        stats_ = TriangleStats{};
        view_projection_ = glm::dmat4(hsr::sdk::load_matrix(camera.view_projection));
        const hsr::sdk::ClipPlanes world_planes(camera);
        const glm::dmat4 plane_to_clip = glm::transpose(glm::inverse(view_projection_));
        clip_planes_.count = int(world_planes.count);
        for (uint32_t k = 0; k < world_planes.count; ++k) {
            const glm::dvec4 p = plane_to_clip * world_planes.plane[k];
            const double length = glm::length(p);
            clip_planes_.plane[k] = length > 0.0 ? p / length : p;
        }
        clip_.resize(scene.vertex_count);
        outcode_.resize(scene.vertex_count);
        window_.resize(scene.vertex_count);
    }

    // Transforms the vertices of one placement to clip and window space; process() then works on
    // its triangles. Placing another placement over the same vertices overwrites them.
    void place(const hsr::sdk::Placement& placement) {
        place_vertices(clip_from_object(placement), placement.first_vertex,
                       placement.first_vertex + placement.vertex_count);
    }

    // place() for the vertices [first, end) of a placement whose matrix clip_from_object gave; calls
    // on disjoint ranges may run at the same time (a parallel place()).
    void place_vertices(const glm::dmat4& m, uint32_t first, uint32_t end) {
        for (uint32_t k = first; k < end; ++k) place_vertex(m, k);
    }

    // place() for vertex k alone, for a renderer that places only the vertices it is about to use
    // (each once per placement).
    void place_vertex(const glm::dmat4& m, uint32_t k) {
        const glm::vec3 p(positions_[3 * k], positions_[3 * k + 1], positions_[3 * k + 2]);
        clip_[k] = to_clip(m, p);
        uint32_t code = outcode(clip_[k], guard_) | clip_planes_.outcode(clip_[k]);
        if (!(code & (kNeedsClipping | kNonFinite)) && !viewport_.to_window(clip_[k], 0.0, 0.0, window_[k]))
            code |= kNonFinite;
        outcode_[k] = code;
    }

    // place() in chunks of kPlaceChunkVertices vertices for a parallel loop: run_chunks(count, work)
    // must call work(k) once for every chunk k < count, in any order and at the same time if it
    // likes (hsr::sdk::parallel_for_each of hsr/parallel.hpp).
    static constexpr uint32_t kPlaceChunkVertices = 8192;
    template <class RunChunks>
    void place_in_chunks(const hsr::sdk::Placement& placement, RunChunks&& run_chunks) {
        const glm::dmat4 m = clip_from_object(placement);
        const uint32_t count = (placement.vertex_count + kPlaceChunkVertices - 1) / kPlaceChunkVertices;
        const uint32_t end = placement.first_vertex + placement.vertex_count;
        run_chunks(count, [&, end](uint32_t k) {
            const uint32_t first = placement.first_vertex + k * kPlaceChunkVertices;
            place_vertices(m, first, std::min(first + kPlaceChunkVertices, end));
        });
    }

    // The matrix place() transforms a placement's vertices with.
    glm::dmat4 clip_from_object(const hsr::sdk::Placement& placement) const {
        return placement.identity ? view_projection_ : view_projection_ * glm::dmat4(placement.transform);
    }

    // The setup of triangle t that process() made without clipping, made again bit for bit from
    // the vertices (with the matrix clip_from_object gave for its placement), for a rasterizer that
    // keeps only part of a setup until it needs the rest, when other placements may have been
    // placed over the vertices since. Counts nothing.
    void setup_again(const glm::dmat4& clip_from_object, uint32_t t, TriangleSetup& s) const {
        WindowVertex v[3];
        for (int c = 0; c < 3; ++c) {
            const size_t k = indices_[3 * size_t(t) + c];
            const glm::vec3 p(positions_[3 * k], positions_[3 * k + 1], positions_[3 * k + 2]);
            viewport_.to_window(to_clip(clip_from_object, p), 0.0, 0.0, v[c]);  // succeeded in place()
        }
        setup_whole_triangle(v[0], v[1], v[2], width_, height_, s);  // kOk, as in process()
    }

    // Window-space vertex k of the current placement, when its outcode is clean (no clipping needed,
    // finite); for bounding tests by hierarchical algorithms.
    uint32_t vertex_outcode(uint32_t k) const { return outcode_[k]; }
    const WindowVertex& window_vertex(uint32_t k) const { return window_[k]; }
    const glm::dvec4& clip_vertex(uint32_t k) const { return clip_[k]; }

    // Culls, clips and sets up triangle t, calling emit(const TriangleSetup&) for every piece that
    // holds pixel centres inside the image (one piece unless clipping made a polygon).
    template <class Emit>
    void process(uint32_t t, Emit&& emit) {
        process(t, stats_, emit);
    }

    // process() counting into `stats` instead of stats(): calls for different triangles may run at
    // the same time, each thread with its own stats, which add up to what process() counts.
    template <class Emit>
    void process(uint32_t t, TriangleStats& stats, Emit&& emit) const {
        if (!process_unclipped(t, stats, emit)) process_to_clip(t, stats, emit);
    }

    // process() for a triangle whose corners are finite and need no clipping (most of them), then
    // true; false, having done and counted nothing, for any other. A rasterizer that handles the
    // others apart (out of line) calls this, then process() for those.
    template <class Emit>
    bool process_unclipped(uint32_t t, Emit&& emit) {
        return process_unclipped(t, stats_, emit);
    }
    template <class Emit>
    bool process_unclipped(uint32_t t, TriangleStats& stats, Emit&& emit) const {
        const uint32_t i0 = indices_[3 * t], i1 = indices_[3 * t + 1], i2 = indices_[3 * t + 2];
        const uint32_t c0 = outcode_[i0], c1 = outcode_[i1], c2 = outcode_[i2];
        if ((c0 | c1 | c2) & (kNeedsClipping | kNonFinite)) return false;
        ++stats.in;
        if (culled(i0, i1, i2, c0 & c1 & c2, stats)) return true;
        TriangleSetup setup;
        switch (setup_whole_triangle(window_[i0], window_[i1], window_[i2], width_, height_, setup)) {
            case SetupResult::kOk:
                ++stats.rasterized;
                emit(setup);
                break;
            case SetupResult::kDegenerate: ++stats.degenerate; break;
            case SetupResult::kOffscreen: ++stats.outside; break;
        }
        return true;
    }

    // For a rasterizer that sorts triangles to screen tiles before setting them up (sort-middle):
    // process_unclipped() without the setup. For a triangle that needs no clipping, counts it as
    // process() does and returns true, `bounds` holding the pixels of its setup when it is to be
    // drawn and nothing (min_x > max_x) when not; setup_unclipped() then makes the setup process()
    // emits, bit for bit, as long as the placement stays placed. False, counting nothing, for a
    // triangle that needs clipping (process() it).
    // (Always inlined, as triangle_pixel_bounds.)
    [[gnu::always_inline]] bool bound_unclipped(uint32_t t, TriangleStats& stats, PixelBounds& bounds) const {
        const uint32_t i0 = indices_[3 * t], i1 = indices_[3 * t + 1], i2 = indices_[3 * t + 2];
        const uint32_t c0 = outcode_[i0], c1 = outcode_[i1], c2 = outcode_[i2];
        if ((c0 | c1 | c2) & (kNeedsClipping | kNonFinite)) return false;
        ++stats.in;
        bounds = {0, 0, -1, -1};
        if (culled(i0, i1, i2, c0 & c1 & c2, stats)) return true;
        switch (triangle_pixel_bounds(window_[i0], window_[i1], window_[i2], width_, height_, bounds)) {
            case SetupResult::kOk: ++stats.rasterized; return true;
            case SetupResult::kDegenerate: ++stats.degenerate; break;
            case SetupResult::kOffscreen: ++stats.outside; break;
        }
        bounds = {0, 0, -1, -1};
        return true;
    }
    void setup_unclipped(uint32_t t, TriangleSetup& setup) const {
        setup_unclipped_corners(indices_[3 * t], indices_[3 * t + 1], indices_[3 * t + 2], setup);
    }
    // setup_unclipped for the triangle with these vertex indices (its corners, in order).
    void setup_unclipped_corners(uint32_t i0, uint32_t i1, uint32_t i2, TriangleSetup& setup) const {
        setup_whole_triangle(window_[i0], window_[i1], window_[i2], width_, height_, setup);
    }

    const TriangleStats& stats() const { return stats_; }

    // Lines of a step (ABI 1.3): the outline of the triangle with vertices corner[0..2] of the
    // current placement, when it needs no clipping and lies within a pixel of the image.
    template <class StepsT>
    void outline_lines(StepsT& steps, const uint32_t* corner) const {
        if ((outcode_[corner[0]] | outcode_[corner[1]] | outcode_[corner[2]]) & (kNeedsClipping | kNonFinite)) return;
        float x[3], y[3];
        for (int k = 0; k < 3; ++k) {
            const WindowVertex& v = window_[corner[k]];
            x[k] = float(v.exact_x);
            y[k] = float(v.exact_y);
            if (!(x[k] >= -1.0f && x[k] <= float(width_ + 1) && y[k] >= -1.0f && y[k] <= float(height_ + 1))) return;
        }
        for (int k = 0; k < 3; ++k) steps.line(x[k], y[k], x[(k + 1) % 3], y[(k + 1) % 3], HSR_STEP_SUBJECT);
    }

    // For algorithms that work on polygons (painters, BSP, area subdivision): triangle t of the
    // current placement as the convex polygon left after clipping it to the near and far planes
    // and the camera's clip planes (not the guard band), in clip space, its corners carrying the
    // triangle's barycentrics (corner 0 (0, 0), corner 1 (1, 0), corner 2 (0, 1)). 0 when nothing
    // is left, a corner is not finite, or the triangle is a back face and culling is on. Counts
    // nothing.
    int clipped_polygon(uint32_t t, ClipVertex (&out)[kMaxClipVertices]) const {
        const uint32_t i0 = indices_[3 * t], i1 = indices_[3 * t + 1], i2 = indices_[3 * t + 2];
        const uint32_t c0 = outcode_[i0], c1 = outcode_[i1], c2 = outcode_[i2];
        if (((c0 | c1 | c2) & kNonFinite) || (c0 & c1 & c2 & kOutsideAnyPlane)) return 0;
        if (cull_backfaces_ && !is_front_facing(clip_[i0], clip_[i1], clip_[i2])) return 0;
        const ClipVertex corners[3] = {{clip_[i0], {0.0, 0.0}}, {clip_[i1], {1.0, 0.0}}, {clip_[i2], {0.0, 1.0}}};
        return clip_polygon(corners, 3, (c0 | c1 | c2) & ~kOutsideGuardBand, guard_, clip_planes_, out);
    }

    // Rasterizes a convex piece of a triangle given in clip space (3 to kMaxPieceVertices corners,
    // carrying the triangle's barycentrics, as from clipped_polygon and split_by_plane): clips it to
    // the near and far planes, the camera's clip planes and the guard band, and calls
    // emit(const TriangleSetup&) for each of its fan triangles that holds pixel centres in the image.
    // Pieces of one triangle that share an edge bit for bit cover each pixel centre on it once.
    // Counts nothing; true when something was emitted.
    template <class Emit>
    bool rasterize_polygon(const ClipVertex* polygon, int count, Emit&& emit) const {
        if (count < 3 || count > kMaxPieceVertices) return false;
        uint32_t any = 0, all = ~0u;
        for (int k = 0; k < count; ++k) {
            const uint32_t code = outcode(polygon[k].position, guard_) | clip_planes_.outcode(polygon[k].position);
            any |= code;
            all &= code;
        }
        if ((any & kNonFinite) || (all & kOutsideAnyPlane)) return false;
        ClipVertex clipped[kMaxClipVertices];
        const int clipped_count = clip_polygon(polygon, count, any, guard_, clip_planes_, clipped);
        return rasterize_clipped(clipped, clipped_count, emit) == SetupResult::kOk;
    }

    // The camera's clip planes in clip space, as this frame uses them.
    const ClipSpacePlanes& clip_planes() const { return clip_planes_; }
    const Viewport& viewport() const { return viewport_; }

private:
    // Outside the view volume (all corners beyond one plane) or a culled back face: counted, true.
    bool culled(uint32_t i0, uint32_t i1, uint32_t i2, uint32_t all_corners, TriangleStats& stats) const {
        if (all_corners & kOutsideAnyPlane) {
            ++stats.outside;
            return true;
        }
        if (cull_backfaces_ && !is_front_facing(clip_[i0], clip_[i1], clip_[i2])) {
            ++stats.backface_culled;
            return true;
        }
        return false;
    }

    // process() for a triangle with a non-finite corner or one that needs clipping.
    template <class Emit>
    void process_to_clip(uint32_t t, TriangleStats& stats, Emit&& emit) const {
        ++stats.in;
        const uint32_t i0 = indices_[3 * t], i1 = indices_[3 * t + 1], i2 = indices_[3 * t + 2];
        const uint32_t c0 = outcode_[i0], c1 = outcode_[i1], c2 = outcode_[i2];
        const uint32_t any = c0 | c1 | c2;
        if (any & kNonFinite) {
            ++stats.degenerate;
            return;
        }
        if (culled(i0, i1, i2, c0 & c1 & c2, stats)) return;
        if (any & kOutsideNear) ++stats.clipped;
        const ClipVertex corners[3] = {{clip_[i0], {0.0, 0.0}}, {clip_[i1], {1.0, 0.0}}, {clip_[i2], {0.0, 1.0}}};
        ClipVertex polygon[kMaxClipVertices];
        const int count = clip_polygon(corners, 3, any, guard_, clip_planes_, polygon);
        switch (rasterize_clipped(polygon, count, emit)) {
            case SetupResult::kOk: ++stats.rasterized; break;
            case SetupResult::kDegenerate: ++stats.degenerate; break;
            case SetupResult::kOffscreen: ++stats.outside; break;
        }
    }

    // Sets up the fan triangles of a clipped convex polygon and emits those holding pixel centres
    // in the image: kOk when one did, else why none did (nothing left counts as offscreen).
    template <class Emit>
    SetupResult rasterize_clipped(const ClipVertex* polygon, int count, Emit&& emit) const {
        if (count == 0) return SetupResult::kOffscreen;
        WindowVertex window[kMaxClipVertices];
        for (int k = 0; k < count; ++k)
            if (!viewport_.to_window(polygon[k].position, polygon[k].bary.x, polygon[k].bary.y, window[k]))
                return SetupResult::kDegenerate;  // only with a projection whose w is not positive in front
        bool drawn = false, degenerate_only = true;
        TriangleSetup setup;
        for (int k = 1; k + 1 < count; ++k) {
            switch (setup_triangle(window[0], window[k], window[k + 1], width_, height_, setup)) {
                case SetupResult::kOk:
                    drawn = true;
                    degenerate_only = false;
                    emit(setup);
                    break;
                case SetupResult::kDegenerate: break;
                case SetupResult::kOffscreen: degenerate_only = false; break;
            }
        }
        return drawn ? SetupResult::kOk : degenerate_only ? SetupResult::kDegenerate : SetupResult::kOffscreen;
    }

    ClipSpacePlanes clip_planes_;
    std::vector<glm::dvec4> clip_;
    std::vector<uint32_t> outcode_;
    std::vector<WindowVertex> window_;  // valid where the outcode needs neither clipping nor skipping
    const uint32_t* indices_ = nullptr;
    const float* positions_ = nullptr;
    glm::dmat4 view_projection_{1.0};
    uint32_t width_ = 0;
    uint32_t height_ = 0;
    bool cull_backfaces_ = false;
    GuardBand guard_;
    Viewport viewport_;
    TriangleStats stats_;
};

}  // namespace hsr::raster
