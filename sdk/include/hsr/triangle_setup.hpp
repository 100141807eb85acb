// hsr triangle setup: one triangle from clip space to the pixel centres it covers, the part every
// rasterizing hidden-surface remover shares (plain, scanline, hierarchical and octree z-buffers).
// Header-only, part of hsr::sdk; hsr/raster.hpp runs a whole frame's triangles through it.
//
//   clip space --(outcodes, trivial reject, back-face test, Sutherland-Hodgman clipping against
//   near/far and a guard band)--> window coordinates snapped to a 1/256-pixel grid --(triangle
//   setup: integer edge functions, top-left fill rule, attribute planes)--> covered pixel centres
//   with window depth and perspective-correct barycentrics.
//
// Sources: edge functions after Pineda, "A Parallel Algorithm for Polygon Rasterization" (SIGGRAPH
// 1988); clipping in homogeneous coordinates after Sutherland & Hodgman (1974) and Blinn & Newell,
// "Clipping Using Homogeneous Coordinates" (1978); the top-left fill rule of Direct3D (OpenGL asks
// for the same outcome: a sample on an edge shared by two polygons is produced by exactly one);
// perspective-correct interpolation of a/w and 1/w after Heckbert & Moreton, "Interpolation for
// Polygon Texture Mapping and Shading" (1991). docs/algorithms/zbuffer.md walks through the steps.
//
// Conventions are those of hsr/abi.h: window y points down (row 0 at the top), pixel centres at
// +0.5, depth = (z_ndc + 1) / 2. A triangle that is counter-clockwise seen by the camera is
// counter-clockwise in NDC (y up) and therefore clockwise in window coordinates.
#pragma once

#include "hsr/visibility_rules.hpp"  // the top-left fill rule: is_top_left_edge

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>

namespace hsr::raster {

// ---------------------------------------------------------------------------------------------- //
// Fixed-point window coordinates

inline constexpr int kSubpixelBits = 8;
inline constexpr int32_t kSubpixelScale = 1 << kSubpixelBits;  // grid steps per pixel
inline constexpr int32_t kHalfPixel = kSubpixelScale / 2;
// Rasterized vertices stay within +-kGuardBand pixels of the origin (triangles reaching further are
// clipped in clip space first), so snapped coordinates fit in 25 bits and every edge-function value
// (a product of two coordinate differences) fits comfortably in an int64_t.
inline constexpr double kGuardBand = 32768.0;
inline constexpr uint32_t kMaxImageSize = 16384;  // must stay well inside the guard band

// ---------------------------------------------------------------------------------------------- //
// Clip space

// Outcode bits of a clip-space vertex. The six frustum bits allow trivial rejection (all three
// vertices outside the same plane); the others say which clipping a triangle needs.
enum : uint32_t {
    kOutsideLeft = 1u << 0,    // x < -w
    kOutsideRight = 1u << 1,   // x > w
    kOutsideBottom = 1u << 2,  // y < -w
    kOutsideTop = 1u << 3,     // y > w
    kOutsideNear = 1u << 4,    // z < -w
    kOutsideFar = 1u << 5,     // z > w
    kOutsideFrustum = 0x3Fu,
    kOutsideGuardBand = 1u << 6,  // |x| or |y| beyond the guard band: clip in x/y before snapping
    kNonFinite = 1u << 7,         // NaN or infinity: the triangle is skipped
    kOutsideClipPlanes = 0xFFu << 8,  // bit 8 + k: on the cut-away side of the camera's clip plane k
    kOutsideAnyPlane = kOutsideFrustum | kOutsideClipPlanes,  // shared by all corners: reject
    kNeedsClipping = kOutsideNear | kOutsideFar | kOutsideGuardBand | kOutsideClipPlanes,
};

inline constexpr int kMaxClipPlanes = 8;  // HSR_MAX_CLIP_PLANES of hsr/abi.h

// The camera's clip planes (sections) in clip space: a clip-space point c is kept where
// dot(plane, c) >= 0. A world-space plane P becomes inverse(view_projection)^T P, the same for
// every placement, since clip = view_projection * world.
struct ClipSpacePlanes {
    int count = 0;
    glm::dvec4 plane[kMaxClipPlanes];

    // The kOutsideClipPlanes bits of a clip-space point.
    uint32_t outcode(const glm::dvec4& c) const {
        uint32_t code = 0;
        for (int k = 0; k < count; ++k)
            if (glm::dot(plane[k], c) < 0.0) code |= 1u << (8 + k);
        return code;
    }
};

// The guard band in NDC units: |x_ndc| <= x and |y_ndc| <= y keep window coordinates within
// +-kGuardBand pixels.
struct GuardBand {
    double x = 1.0;
    double y = 1.0;
    GuardBand() = default;
    GuardBand(uint32_t width, uint32_t height)
        : x(2.0 * kGuardBand / width - 1.0), y(2.0 * kGuardBand / height - 1.0) {}
};

// Clip space is kept in double: near the near plane window depth changes steeply, and clipping
// there should not add more error than the float input already has.
inline glm::dvec4 to_clip(const glm::dmat4& view_projection, const glm::vec3& world) {
    return view_projection * glm::dvec4(world, 1.0);
}

// The six frustum bits of a clip-space point (none for NaN coordinates).
inline uint32_t frustum_outcode(const glm::dvec4& c) {
    uint32_t code = 0;
    if (c.x < -c.w) code |= kOutsideLeft;
    if (c.x > c.w) code |= kOutsideRight;
    if (c.y < -c.w) code |= kOutsideBottom;
    if (c.y > c.w) code |= kOutsideTop;
    if (c.z < -c.w) code |= kOutsideNear;
    if (c.z > c.w) code |= kOutsideFar;
    return code;
}

inline uint32_t outcode(const glm::dvec4& c, const GuardBand& guard) {
    if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && std::isfinite(c.w)))
        return kNonFinite;
    uint32_t code = frustum_outcode(c);
    if (std::abs(c.x) > guard.x * c.w || std::abs(c.y) > guard.y * c.w) code |= kOutsideGuardBand;
    return code;
}

// True when the triangle is counter-clockwise seen from the camera (its front, by the scene's
// convention). det[x y w] of the clip-space corners equals w0*w1*w2 times twice the signed NDC area,
// so for visible triangles it has the sign of the NDC (y-up) area; for triangles that cross w = 0 it
// is still the geometric side of the triangle's plane the eye is on, so no clipping is needed first.
// Edge-on triangles (det = 0) count as not front-facing.
inline bool is_front_facing(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c) {
    const double det = a.x * (b.y * c.w - c.y * b.w) - a.y * (b.x * c.w - c.x * b.w) + a.w * (b.x * c.y - c.x * b.y);
    return det > 0.0;
}

// A polygon vertex during clipping; bary carries (b1, b2) of the ORIGINAL triangle, which is affine
// over the triangle and therefore interpolates linearly in clip space.
struct ClipVertex {
    glm::dvec4 position;
    glm::dvec2 bary;
};

// A convex piece of a triangle handed to the rasterizer has at most kMaxPieceVertices corners;
// every clipping plane (near, far, four of the guard band, the clip planes) adds at most one.
inline constexpr int kMaxPieceVertices = 16;
inline constexpr int kMaxClipVertices = kMaxPieceVertices + 6 + kMaxClipPlanes;

// Sutherland-Hodgman against one plane; the inside is dot(plane, position) >= 0. The new vertex on
// a crossing edge is always interpolated from the inside end toward the outside end, so two
// triangles sharing that edge produce bit-identical vertices (no cracks along the clip line).
inline int clip_against_plane(const ClipVertex* in, int count, const glm::dvec4& plane, ClipVertex* out) {
    int written = 0;
    for (int i = 0; i < count; ++i) {
        const ClipVertex& a = in[i];
        const ClipVertex& b = in[i + 1 == count ? 0 : i + 1];
        const double da = glm::dot(plane, a.position);
        const double db = glm::dot(plane, b.position);
        if (da >= 0.0) out[written++] = a;
        if ((da >= 0.0) != (db >= 0.0)) {
            const bool a_inside = da >= 0.0;
            const ClipVertex& inside = a_inside ? a : b;
            const ClipVertex& outside = a_inside ? b : a;
            const double d_in = a_inside ? da : db;
            const double d_out = a_inside ? db : da;
            const double t = d_in / (d_in - d_out);  // d_in >= 0 > d_out: no division by zero
            out[written++] = {inside.position + t * (outside.position - inside.position),
                              inside.bary + t * (outside.bary - inside.bary)};
        }
    }
    return written;
}

// Splits a convex polygon by a plane into the part where dot(plane, position) >= 0 (front) and
// the part where it is <= 0 (back); corners on the plane go to both. A crossing corner is computed
// once, from the front end toward the back end, and given to both parts, so their shared edge is
// bit-identical and the rasterizer's fill rule draws each pixel centre on it exactly once. Either
// count may come back below 3 (nothing on that side). `front` and `back` hold count + 2 corners.
inline void split_by_plane(const ClipVertex* in, int count, const glm::dvec4& plane, ClipVertex* front,
                           int& front_count, ClipVertex* back, int& back_count) {
    front_count = back_count = 0;
    for (int i = 0; i < count; ++i) {
        const ClipVertex& a = in[i];
        const ClipVertex& b = in[i + 1 == count ? 0 : i + 1];
        const double da = glm::dot(plane, a.position);
        const double db = glm::dot(plane, b.position);
        if (da >= 0.0) front[front_count++] = a;
        if (da <= 0.0) back[back_count++] = a;
        if ((da > 0.0 && db < 0.0) || (da < 0.0 && db > 0.0)) {
            const bool a_front = da > 0.0;
            const ClipVertex& f = a_front ? a : b;
            const ClipVertex& k = a_front ? b : a;
            const double d_front = a_front ? da : db;
            const double d_back = a_front ? db : da;
            const double t = d_front / (d_front - d_back);
            const ClipVertex crossing{f.position + t * (k.position - f.position), f.bary + t * (k.bary - f.bary)};
            front[front_count++] = crossing;
            back[back_count++] = crossing;
        }
    }
}

// The clip-space plane through three clip-space points (the 4-vector orthogonal to all three, a
// generalized cross product): a plane of world space stays a plane of clip space, so a polygon can
// be split by another's plane in clip space exactly as in world space. Its sign is arbitrary: test
// a known point to orient it. Zero when the points are collinear.
inline glm::dvec4 plane_through(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c) {
    auto minor = [&](int i, int j, int k) {
        return a[i] * (b[j] * c[k] - b[k] * c[j]) - a[j] * (b[i] * c[k] - b[k] * c[i]) +
               a[k] * (b[i] * c[j] - b[j] * c[i]);
    };
    return {minor(1, 2, 3), -minor(0, 2, 3), minor(0, 1, 3), -minor(0, 1, 2)};
}

// Clips a convex polygon (count <= kMaxPieceVertices corners) against the planes its combined
// outcode asks for (near, far, guard band, clip planes). Returns the corner count of the convex
// polygon left in `out` (0 or 3..kMaxClipVertices).
inline int clip_polygon(const ClipVertex* polygon, int count, uint32_t combined_outcode, const GuardBand& guard,
                        const ClipSpacePlanes& clip_planes, ClipVertex (&out)[kMaxClipVertices]) {
    ClipVertex scratch[kMaxClipVertices];
    std::copy(polygon, polygon + count, out);
    auto apply = [&](const glm::dvec4& plane) {
        if (count < 3) return;
        count = clip_against_plane(out, count, plane, scratch);
        std::copy(scratch, scratch + count, out);
    };
    if (combined_outcode & kOutsideNear) apply({0.0, 0.0, 1.0, 1.0});
    if (combined_outcode & kOutsideFar) apply({0.0, 0.0, -1.0, 1.0});
    for (int k = 0; k < clip_planes.count; ++k)
        if (combined_outcode & (1u << (8 + k))) apply(clip_planes.plane[k]);
    if (combined_outcode & kOutsideGuardBand) {
        apply({1.0, 0.0, 0.0, guard.x});
        apply({-1.0, 0.0, 0.0, guard.x});
        apply({0.0, 1.0, 0.0, guard.y});
        apply({0.0, -1.0, 0.0, guard.y});
    }
    return count < 3 ? 0 : count;
}

// ---------------------------------------------------------------------------------------------- //
// Window coordinates

// A vertex ready for triangle setup: its position snapped to the subpixel grid (which decides
// coverage) and unsnapped (from which depth and barycentrics are interpolated), window depth, 1/w,
// and the barycentrics (b1, b2) of the original triangle at this vertex.
struct WindowVertex {
    int32_t x;  // window x * kSubpixelScale, rounded
    int32_t y;  // window y * kSubpixelScale, rounded (y down)
    double exact_x;
    double exact_y;
    double depth;
    double inv_w;
    double b1;
    double b2;
};

class Viewport {
public:
    Viewport() = default;
    Viewport(uint32_t width, uint32_t height) : half_width_(0.5 * width), half_height_(0.5 * height) {}

    // Window x, y and depth of a clip-space point, unsnapped and unchecked (w > 0 is the caller's).
    glm::dvec3 project(const glm::dvec4& clip) const {
        const double inv_w = 1.0 / clip.w;
        return {(clip.x * inv_w + 1.0) * half_width_, (1.0 - clip.y * inv_w) * half_height_,
                (clip.z * inv_w + 1.0) * 0.5};
    }

    // False when the vertex cannot be projected (w <= 0 or non-finite); never produces NaN.
    bool to_window(const glm::dvec4& clip, double b1, double b2, WindowVertex& out) const {
        if (!(clip.w > 0.0)) return false;
        const double inv_w = 1.0 / clip.w;
        const glm::dvec3 window = project(clip);
        const double x = window.x, y = window.y, depth = window.z;
        if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(depth) && std::isfinite(inv_w)))
            return false;
        constexpr double limit = 2.0 * kGuardBand;  // only reached through rounding at the guard band
        out.exact_x = std::clamp(x, -limit, limit);
        out.exact_y = std::clamp(y, -limit, limit);
        out.x = static_cast<int32_t>(std::nearbyint(out.exact_x * kSubpixelScale));
        out.y = static_cast<int32_t>(std::nearbyint(out.exact_y * kSubpixelScale));
        out.depth = depth;
        out.inv_w = inv_w;
        out.b1 = b1;
        out.b2 = b2;
        return true;
    }

private:
    double half_width_ = 0.0;
    double half_height_ = 0.0;
};

// The corners of a whole triangle (clip space) in window coordinates, snapped as the rasterizer
// snaps them, when the rasterizer draws it without clipping first: false when a corner needs
// clipping (near, far, guard band) or cannot be projected. For a renderer that does not rasterize
// and applies the fill rule to the rasterizer's corners (hsr/visibility_rules.hpp, covers_sample).
inline bool unclipped_window_corners(const glm::dvec4 (&clip)[3], const Viewport& viewport, const GuardBand& guard,
                                     WindowVertex (&out)[3]) {
    for (int c = 0; c < 3; ++c)
        if ((outcode(clip[c], guard) & (kNeedsClipping | kNonFinite)) || !viewport.to_window(clip[c], 0.0, 0.0, out[c]))
            return false;
    return true;
}

// The snapped corners of the few triangles that neighbouring samples meet, for a ray caster that
// applies the fill rule to each hit (one cache per casting thread): a small direct-mapped cache
// keyed by a placement and a triangle number.
struct SnappedCornerCache {
    struct Entry {
        uint32_t placement = ~0u, triangle = ~0u;
        bool known = false;  // what snap answered: the corners are the rasterizer's
        int64_t x[3], y[3];
    };
    static constexpr size_t kSize = 8;  // a power of 2
    Entry entry[kSize];

    // The entry of (placement, triangle); when it is not there, snap(x, y) fills its corners and
    // says whether they apply.
    template <class Snap>
    const Entry& find(uint32_t placement, uint32_t triangle, Snap&& snap) {
        Entry& e = entry[triangle & (kSize - 1)];
        if (e.placement != placement || e.triangle != triangle) {
            e.placement = placement;
            e.triangle = triangle;
            e.known = snap(e.x, e.y);
        }
        return e;
    }
};

// ---------------------------------------------------------------------------------------------- //
// Triangle setup

// A quantity that is affine in window space, evaluated at pixel centres relative to the setup's
// origin pixel (min_x, min_y): f = origin + dx * i + dy * j with i = x - min_x, j = y - min_y.
// Written so that (origin + dy * j) is loop-invariant along a row.
struct Plane {
    double origin;
    double dx;
    double dy;
    double at(double i, double j) const { return (origin + dy * j) + dx * i; }
};

// The edge function of the edge from (ax, ay) along (dx, dy) at grid point (px, py), positive on
// the interior side (right of the edge seen with y down), less 1 unless the edge is top-left: a
// sample is covered exactly when this is >= 0 for all three edges.
inline int64_t biased_edge_function(int64_t dx, int64_t dy, int32_t ax, int32_t ay, int64_t px, int64_t py) {
    return dx * (py - ay) - dy * (px - ax) - (is_top_left_edge(dx, dy) ? 0 : 1);
}

// The first pixel (column or row) whose centre lies at or after a coordinate on the subpixel grid,
// and the last whose centre lies at or before one: the pixel bounds of a triangle's snapped
// corners, before they are held to the image. (>> floors.)
inline int32_t first_pixel_from(int32_t grid) { return (grid - kHalfPixel + kSubpixelScale - 1) >> kSubpixelBits; }
inline int32_t last_pixel_to(int32_t grid) { return (grid - kHalfPixel) >> kSubpixelBits; }

// Pixels [min_x, max_x] x [min_y, max_y] (inclusive).
struct PixelBounds {
    int32_t min_x, min_y, max_x, max_y;
};

struct TriangleSetup {
    int32_t min_x, min_y, max_x, max_y;  // pixel bounds, inclusive, inside the image, non-empty
    // Edge function k (opposite corner k, positive inside) at the centre of pixel (min_x, min_y),
    // minus 1 unless the edge is top-left: a pixel is covered exactly when all three are >= 0.
    int64_t edge_origin[3];
    int64_t edge_dx[3];  // change per pixel step in +x
    int64_t edge_dy[3];  // change per pixel step in +y (down)
    Plane depth;      // window depth
    Plane inv_w;      // 1/w
    Plane b1_over_w;  // b1/w, b2/w: divided by 1/w they give perspective-correct barycentrics
    Plane b2_over_w;
    bool front_facing;  // clockwise in window coordinates = counter-clockwise seen by the camera
};

enum class SetupResult {
    kOk,
    kDegenerate,  // zero area on the subpixel grid, or the bounding box holds no pixel centre
    kOffscreen    // the bounding box holds pixel centres, but none inside the image
};

// The first part of setup_triangle, for a rasterizer that sorts triangles to screen tiles before
// setting them up: what setup_triangle answers for these corners and, when kOk, the pixel bounds
// of the setup it makes.
// (Always inlined: binning runs it for every triangle, and GCC would call it out of line once a
// plugin has several callers.)
[[gnu::always_inline]] inline SetupResult triangle_pixel_bounds(const WindowVertex& v0, const WindowVertex& v1,
                                                                const WindowVertex& v2, uint32_t width,
                                                                uint32_t height, PixelBounds& b) {
    const int64_t area = int64_t(v1.x - v0.x) * (v2.y - v0.y) - int64_t(v2.x - v0.x) * (v1.y - v0.y);
    if (area == 0) return SetupResult::kDegenerate;
    // Pixel (px, py) has its centre at grid coordinates (px * S + S/2, py * S + S/2).
    const int32_t first_x = first_pixel_from(std::min({v0.x, v1.x, v2.x}));
    const int32_t last_x = last_pixel_to(std::max({v0.x, v1.x, v2.x}));
    const int32_t first_y = first_pixel_from(std::min({v0.y, v1.y, v2.y}));
    const int32_t last_y = last_pixel_to(std::max({v0.y, v1.y, v2.y}));
    if (first_x > last_x || first_y > last_y) return SetupResult::kDegenerate;
    b.min_x = std::max(first_x, 0);
    b.max_x = std::min(last_x, int32_t(width) - 1);
    b.min_y = std::max(first_y, 0);
    b.max_y = std::min(last_y, int32_t(height) - 1);
    if (b.min_x > b.max_x || b.min_y > b.max_y) return SetupResult::kOffscreen;
    return SetupResult::kOk;
}

// The rest of setup_triangle for corners that triangle_pixel_bounds accepted (kOk) with `bounds`,
// for a rasterizer that tests the bounds first and keeps them: the same setup, bit for bit.
inline void setup_triangle_in_bounds(const WindowVertex& v0, const WindowVertex& v1, const WindowVertex& v2,
                                     const double (&b1)[3], const double (&b2)[3], const PixelBounds& bounds,
                                     TriangleSetup& s) {
    s.min_x = bounds.min_x;
    s.max_x = bounds.max_x;
    s.min_y = bounds.min_y;
    s.max_y = bounds.max_y;
    int64_t area = int64_t(v1.x - v0.x) * (v2.y - v0.y) - int64_t(v2.x - v0.x) * (v1.y - v0.y);
    s.front_facing = area < 0;
    // Corner order with the interior on the positive side of every edge function: corners 1 and 2
    // swap places when the triangle is clockwise.
    const int c1 = area < 0 ? 2 : 1, c2 = area < 0 ? 1 : 2;
    if (area < 0) area = -area;
    const WindowVertex* v[3] = {&v0, c1 == 1 ? &v1 : &v2, c2 == 2 ? &v2 : &v1};
    const int corner[3] = {0, c1, c2};

    const int64_t origin_x = int64_t(s.min_x) * kSubpixelScale + kHalfPixel;
    const int64_t origin_y = int64_t(s.min_y) * kSubpixelScale + kHalfPixel;
    for (int k = 0; k < 3; ++k) {
        const WindowVertex& a = *v[(k + 1) % 3];
        const WindowVertex& b = *v[(k + 2) % 3];
        const int64_t dx = int64_t(b.x) - a.x;
        const int64_t dy = int64_t(b.y) - a.y;
        s.edge_origin[k] = biased_edge_function(dx, dy, a.x, a.y, origin_x, origin_y);
        s.edge_dx[k] = -dy * kSubpixelScale;
        s.edge_dy[k] = dx * kSubpixelScale;
    }

    // Depth and barycentrics are interpolated over the unsnapped triangle, so snapping (by up to
    // 1/512 pixel) changes which samples are covered but not the values found at them; that matters
    // where depth changes steeply, near the near plane. A sliver that snapping reshaped (area off by
    // more than a factor of 2) uses the snapped corners instead, whose values stay bounded.
    const WindowVertex &w0 = *v[0], &w1 = *v[1], &w2 = *v[2];
    const double grid_area = double(area) / (double(kSubpixelScale) * kSubpixelScale);
    const double exact_area = (w1.exact_x - w0.exact_x) * (w2.exact_y - w0.exact_y) -
                              (w2.exact_x - w0.exact_x) * (w1.exact_y - w0.exact_y);
    const bool use_exact = exact_area > 0.5 * grid_area && exact_area < 2.0 * grid_area;
    const double inv_area = 1.0 / (use_exact ? exact_area : grid_area);
    double cx[3], cy[3];
    for (int k = 0; k < 3; ++k) {
        cx[k] = use_exact ? v[k]->exact_x : double(v[k]->x) / kSubpixelScale;
        cy[k] = use_exact ? v[k]->exact_y : double(v[k]->y) / kSubpixelScale;
    }
    const double centre_x = s.min_x + 0.5, centre_y = s.min_y + 0.5;
    double lambda_origin[3], lambda_dx[3], lambda_dy[3];  // barycentric weight of corner k in window space
    for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        const double dx = cx[b] - cx[a];
        const double dy = cy[b] - cy[a];
        lambda_origin[k] = (dx * (centre_y - cy[a]) - dy * (centre_x - cx[a])) * inv_area;
        lambda_dx[k] = -dy * inv_area;
        lambda_dy[k] = dx * inv_area;
    }
    auto plane = [&](double f0, double f1, double f2) {
        return Plane{f0 * lambda_origin[0] + f1 * lambda_origin[1] + f2 * lambda_origin[2],
                     f0 * lambda_dx[0] + f1 * lambda_dx[1] + f2 * lambda_dx[2],
                     f0 * lambda_dy[0] + f1 * lambda_dy[1] + f2 * lambda_dy[2]};
    };
    s.depth = plane(w0.depth, w1.depth, w2.depth);
    s.inv_w = plane(w0.inv_w, w1.inv_w, w2.inv_w);
    s.b1_over_w = plane(b1[0] * w0.inv_w, b1[corner[1]] * w1.inv_w, b1[corner[2]] * w2.inv_w);
    s.b2_over_w = plane(b2[0] * w0.inv_w, b2[corner[1]] * w1.inv_w, b2[corner[2]] * w2.inv_w);
}

// setup_triangle with the barycentrics (b1[k], b2[k]) of the original triangle at corner k given
// apart from the corners (whose own b1, b2 are not read).
inline SetupResult setup_triangle(const WindowVertex& v0, const WindowVertex& v1, const WindowVertex& v2,
                                  const double (&b1)[3], const double (&b2)[3], uint32_t width, uint32_t height,
                                  TriangleSetup& s) {
    PixelBounds bounds;
    const SetupResult result = triangle_pixel_bounds(v0, v1, v2, width, height, bounds);
    if (result != SetupResult::kOk) return result;
    setup_triangle_in_bounds(v0, v1, v2, b1, b2, bounds, s);
    return SetupResult::kOk;
}

// Sets up the triangle v0 v1 v2 for rasterization, each corner carrying its own barycentrics.
inline SetupResult setup_triangle(const WindowVertex& v0, const WindowVertex& v1, const WindowVertex& v2,
                                  uint32_t width, uint32_t height, TriangleSetup& s) {
    const double b1[3] = {v0.b1, v1.b1, v2.b1}, b2[3] = {v0.b2, v1.b2, v2.b2};
    return setup_triangle(v0, v1, v2, b1, b2, width, height, s);
}

// The barycentrics of a whole triangle's corners: (0, 0), (1, 0), (0, 1).
inline constexpr double kWholeTriangleB1[3] = {0.0, 1.0, 0.0};
inline constexpr double kWholeTriangleB2[3] = {0.0, 0.0, 1.0};

// Sets up a whole (unclipped) triangle, whatever b1, b2 its corners hold.
inline SetupResult setup_whole_triangle(const WindowVertex& v0, const WindowVertex& v1, const WindowVertex& v2,
                                        uint32_t width, uint32_t height, TriangleSetup& s) {
    return setup_triangle(v0, v1, v2, kWholeTriangleB1, kWholeTriangleB2, width, height, s);
}

// The snapped corners of a setup in its own corner order (edge k runs from corner k+1 to corner
// k+2, the interior on its positive side), given the vertices setup_triangle was called with: it
// swaps corners 1 and 2 of a front-facing (clockwise) triangle.
inline void setup_corners(const TriangleSetup& s, const WindowVertex& v0, const WindowVertex& v1,
                          const WindowVertex& v2, int32_t (&x)[3], int32_t (&y)[3]) {
    const WindowVertex& c1 = s.front_facing ? v2 : v1;
    const WindowVertex& c2 = s.front_facing ? v1 : v2;
    x[0] = v0.x, x[1] = c1.x, x[2] = c2.x;
    y[0] = v0.y, y[1] = c1.y, y[2] = c2.y;
}

// The same corners from the setup alone (for a piece of a clipped triangle, whose vertices are
// gone). Edge k has vector d_k; the unbiased edge functions E_k at the origin O (the centre of pixel
// (min_x, min_y)) are the barycentric weights of O times the doubled area 2A = E_0 + E_1 + E_2, so
// 2A (O - v0) = E_1 d_2 - E_2 d_1 (an exact division), v1 = v0 + d_2 and v2 = v0 - d_1.
inline void setup_corners(const TriangleSetup& s, int32_t (&x)[3], int32_t (&y)[3]) {
    __extension__ using int128 = __int128;
    int64_t dx[3], dy[3], e[3];
    for (int k = 0; k < 3; ++k) {
        dx[k] = s.edge_dy[k] / kSubpixelScale;
        dy[k] = -s.edge_dx[k] / kSubpixelScale;
        e[k] = s.edge_origin[k] + (is_top_left_edge(dx[k], dy[k]) ? 0 : 1);
    }
    const int128 area2 = int128(e[0]) + e[1] + e[2];
    const int64_t ox = int64_t(s.min_x) * kSubpixelScale + kHalfPixel;
    const int64_t oy = int64_t(s.min_y) * kSubpixelScale + kHalfPixel;
    const int64_t x0 = ox - int64_t((int128(e[1]) * dx[2] - int128(e[2]) * dx[1]) / area2);
    const int64_t y0 = oy - int64_t((int128(e[1]) * dy[2] - int128(e[2]) * dy[1]) / area2);
    x[0] = int32_t(x0);
    x[1] = int32_t(x0 + dx[2]);
    x[2] = int32_t(x0 - dx[1]);
    y[0] = int32_t(y0);
    y[1] = int32_t(y0 + dy[2]);
    y[2] = int32_t(y0 - dy[1]);
}

// Window depth at pixel (min_x + i, min_y + j), held to the depth range [0, 1] (a covered sample
// may lie a fraction of a subpixel outside the unsnapped triangle).
inline float depth_at(const TriangleSetup& s, double i, double j) {
    return float(std::max(0.0, std::min(s.depth.at(i, j), 1.0)));  // branch-free min/max
}

// Perspective-correct (b1, b2) from the planes of 1/w, b1/w and b2/w at (i, j), held inside the
// triangle (b1, b2 >= 0, b1 + b2 <= 1) for the same reason. Shared by every rasterizer that keeps
// these planes, so that all give the same barycentrics bit for bit.
inline glm::vec2 perspective_barycentrics(const Plane& inv_w_plane, const Plane& b1_over_w, const Plane& b2_over_w,
                                          double i, double j) {
    const double inv_w = inv_w_plane.at(i, j);
    if (!(inv_w > 0.0)) return {0.0f, 0.0f};  // not reached: 1/w > 0 on and near the triangle
    const double w = 1.0 / inv_w;
    double b1 = std::max(b1_over_w.at(i, j) * w, 0.0);
    double b2 = std::max(b2_over_w.at(i, j) * w, 0.0);
    const double sum = b1 + b2;
    if (sum > 1.0) {
        b1 /= sum;
        b2 /= sum;
    }
    return {float(b1), float(b2)};
}

// Perspective-correct (b1, b2) of the original triangle at pixel (min_x + i, min_y + j) of a setup.
inline glm::vec2 barycentrics_at(const TriangleSetup& s, double i, double j) {
    return perspective_barycentrics(s.inv_w, s.b1_over_w, s.b2_over_w, i, j);
}

// Calls visit(x, y, i, j) for every covered pixel centre inside the rectangle [x0,x1] x [y0,y1]
// (which lies inside the setup's bounds), row by row from the top and left to right in a row;
// (i, j) = (x - min_x, y - min_y) as doubles, ready for Plane::at. The edge functions step exactly in
// integers, so the fill rule holds bit for bit. The covered samples of a row are contiguous, so a row
// ends once its run has been left. (Finding each row's run directly, with one division per edge and
// row, measured slower on small triangles, which dominate real meshes.)
// kAllCovered: the caller knows every pixel of the rectangle is covered (covers() below), so the
// edge functions are not stepped.
template <bool kAllCovered = false, class Visit>
inline void for_each_covered_pixel_in(const TriangleSetup& s, int32_t x0, int32_t y0, int32_t x1, int32_t y1,
                                      Visit&& visit) {
    const int64_t di = x0 - s.min_x, dj = y0 - s.min_y;
    int64_t row0 = s.edge_origin[0] + s.edge_dx[0] * di + s.edge_dy[0] * dj;
    int64_t row1 = s.edge_origin[1] + s.edge_dx[1] * di + s.edge_dy[1] * dj;
    int64_t row2 = s.edge_origin[2] + s.edge_dx[2] * di + s.edge_dy[2] * dj;
    const int64_t dx0 = s.edge_dx[0], dx1 = s.edge_dx[1], dx2 = s.edge_dx[2];
    double j = double(dj);
    for (int32_t y = y0; y <= y1; ++y, j += 1.0) {
        int64_t e0 = row0, e1 = row1, e2 = row2;
        bool entered = false;
        double i = double(di);
        for (int32_t x = x0; x <= x1; ++x, i += 1.0) {
            if (kAllCovered || (e0 | e1 | e2) >= 0) {
                entered = true;
                visit(x, y, i, j);
            } else if (entered) {
                break;
            }
            e0 += dx0;
            e1 += dx1;
            e2 += dx2;
        }
        row0 += s.edge_dy[0];
        row1 += s.edge_dy[1];
        row2 += s.edge_dy[2];
    }
}

// Every covered pixel centre of the triangle.
template <class Visit>
inline void for_each_covered_pixel(const TriangleSetup& s, Visit&& visit) {
    for_each_covered_pixel_in(s, s.min_x, s.min_y, s.max_x, s.max_y, visit);
}

// The lowest and highest value of edge function k over the corners of the rectangle
// [x0,x1] x [y0,y1] (inside the setup's bounds): being linear, its extremes over the rectangle.
struct EdgeExtremes {
    int64_t lowest, highest;
};
inline EdgeExtremes edge_extremes(const TriangleSetup& s, int k, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
    const int64_t e00 = s.edge_origin[k] + s.edge_dx[k] * (x0 - s.min_x) + s.edge_dy[k] * (y0 - s.min_y);
    const int64_t step_x = s.edge_dx[k] * (x1 - x0), step_y = s.edge_dy[k] * (y1 - y0);
    return {e00 + std::min<int64_t>(step_x, 0) + std::min<int64_t>(step_y, 0),
            e00 + std::max<int64_t>(step_x, 0) + std::max<int64_t>(step_y, 0)};
}

// The rectangle holds no covered pixel centre: one edge function is negative at all four corners.
inline bool misses(const TriangleSetup& s, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
    for (int k = 0; k < 3; ++k)
        if (edge_extremes(s, k, x0, y0, x1, y1).highest < 0) return true;
    return false;
}

// Every pixel centre of the rectangle is covered: each edge function is >= 0 at all four corners.
inline bool covers(const TriangleSetup& s, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
    for (int k = 0; k < 3; ++k)
        if (edge_extremes(s, k, x0, y0, x1, y1).lowest < 0) return false;
    return true;
}

}  // namespace hsr::raster
