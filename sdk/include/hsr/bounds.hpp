// hsr bounds: an axis-aligned box seen by the camera, for culling a whole group of triangles before
// any of them is transformed (octree nodes, instances, the placements of a scanline sweep).
// Header-only, part of hsr::sdk.
//
// The box's 8 corners go to clip space; the frustum outcode bits they all share say the box is out
// of view (Cohen-Sutherland's trivial reject, in homogeneous coordinates after Blinn & Newell,
// "Clipping Using Homogeneous Coordinates", 1978). When every corner lies beyond the near plane
// (and so in front of the eye, w > 0), a projective map takes the box onto the convex hull of its
// projected corners, and window depth (z/w, linear-fractional) is smallest at a corner, so the
// corners' window rectangle and nearest depth bound everything inside the box (Greene, Kass &
// Miller, "Hierarchical Z-Buffer Visibility", SIGGRAPH 1993, test the octree's nodes this way).
#pragma once

#include "hsr/triangle_setup.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace hsr::raster {

// The margins a culling test adds to a projected box. Pixels: snapping moves a vertex by up to
// 1/512 pixel, and the corners are projected in another order of operations than the vertices.
// Depth: rounding of depths to float, and the covered pixel centres that lie (by at most 1/512
// pixel) outside a triangle's unsnapped corners, where its depth plane is extrapolated.
inline constexpr double kBoxPixelMargin = 1.0 / 64.0;
inline constexpr double kBoxDepthMargin = 1e-6;

// Pixels x0..x1 by y0..y1, inclusive; empty when x0 > x1 or y0 > y1.
struct PixelRect {
    int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    bool empty() const { return x0 > x1 || y0 > y1; }
};

struct ProjectedBox {
    // Frustum outcode bits (kOutsideLeft .. kOutsideFar) shared by all 8 corners: when non-zero,
    // nothing in the box is in view.
    uint32_t outside = 0;
    // Every corner beyond the near plane, and the projection finite: only then do the fields below
    // bound the box.
    bool in_front = false;
    double min_x = 0.0, min_y = 0.0, max_x = 0.0, max_y = 0.0;  // window coordinates of the corners
    double nearest = 0.0;  // smallest window depth of the corners, in [0, 1] inside the frustum

    // The pixels whose centres (px + 0.5) lie within [min - margin, max + margin], inside the image.
    PixelRect pixel_centres(double margin, int32_t width, int32_t height) const {
        // Clamped first, so that the conversion to int32_t cannot overflow.
        const double lo_x = std::clamp(min_x - margin, -2.0, double(width) + 2.0);
        const double hi_x = std::clamp(max_x + margin, -2.0, double(width) + 2.0);
        const double lo_y = std::clamp(min_y - margin, -2.0, double(height) + 2.0);
        const double hi_y = std::clamp(max_y + margin, -2.0, double(height) + 2.0);
        return {std::max(int32_t(std::ceil(lo_x - 0.5)), 0), std::max(int32_t(std::ceil(lo_y - 0.5)), 0),
                std::min(int32_t(std::floor(hi_x - 0.5)), width - 1),
                std::min(int32_t(std::floor(hi_y - 0.5)), height - 1)};
    }
};

// The box [lo, hi] of object space under clip_from_object (view_projection times the object's
// transform). The near-plane rule: a box with a corner on the eye's side of the near plane
// (z < -w, or w <= 0 behind the eye) is not in_front and has no rectangle: what it holds may cover
// any pixel at any depth (clipping decides, triangle by triangle). Beyond the near plane w is at
// least the near distance, so x / w, y / w and z / w are well conditioned. An empty box (lo > hi on
// an axis, or NaN) is not in_front either.
inline ProjectedBox project_box(const glm::dmat4& clip_from_object, const glm::dvec3& lo, const glm::dvec3& hi,
                                const Viewport& viewport) {
    ProjectedBox box;
    const glm::dvec4 base = clip_from_object * glm::dvec4(lo, 1.0);
    const glm::dvec4 ex = clip_from_object[0] * (hi.x - lo.x);
    const glm::dvec4 ey = clip_from_object[1] * (hi.y - lo.y);
    const glm::dvec4 ez = clip_from_object[2] * (hi.z - lo.z);
    uint32_t shared = kOutsideFrustum;
    bool in_front = lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z;
    double min_x = std::numeric_limits<double>::infinity(), max_x = -min_x;
    double min_y = min_x, max_y = -min_x, nearest = min_x;
    double finite = 0.0;
    for (int c = 0; c < 8; ++c) {
        glm::dvec4 p = base;
        if (c & 1) p += ex;
        if (c & 2) p += ey;
        if (c & 4) p += ez;
        const uint32_t code = frustum_outcode(p);
        shared &= code;
        if ((code & kOutsideNear) || !(p.w > 0.0)) {
            in_front = false;
            continue;
        }
        const glm::dvec3 window = viewport.project(p);
        finite += window.x + window.y + window.z;  // NaN or infinity stays in the sum
        min_x = std::min(min_x, window.x);
        max_x = std::max(max_x, window.x);
        min_y = std::min(min_y, window.y);
        max_y = std::max(max_y, window.y);
        nearest = std::min(nearest, window.z);
    }
    box.outside = shared;
    box.in_front = in_front && std::isfinite(finite);
    if (box.in_front) {
        box.min_x = min_x;
        box.max_x = max_x;
        box.min_y = min_y;
        box.max_y = max_y;
        box.nearest = nearest;
    }
    return box;
}

}  // namespace hsr::raster
