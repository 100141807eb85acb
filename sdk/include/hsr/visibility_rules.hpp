// hsr visibility rules: the one tie rule and the one fill rule every hidden-surface plugin follows,
// so that a picture does not depend on the algorithm that made it. Header-only, part of hsr::sdk;
// docs/algorithms/ties-and-fill.md states both rules and how each plugin keeps them.
//
// Tie rule: of two surfaces at exactly the same window depth at a pixel (the same float, as the
// depth buffer stores it), the one earlier in the scene's drawing order is kept: the lower instance
// (placement), and within one instance the lower face. It is what the plain z-buffer does with its
// strict depth test, drawing placements in order and each placement's triangles in order.
//
// Fill rule: a pixel centre lying exactly on a triangle's edge, with the corners snapped to the
// 1/256-pixel grid of hsr/triangle_setup.hpp, belongs to the triangle only when that edge is a top
// or a left edge (the top-left rule of Direct3D; OpenGL asks for the same outcome: a sample on an
// edge shared by two triangles is drawn by exactly one of them, and one on an outline edge by the
// triangle only on its top and left sides).
#pragma once

#include <cstdint>

namespace hsr::raster {

// ---------------------------------------------------------------------------------------------- //
// The tie rule

// True when the surface (instance, face) comes before (other_instance, other_face) in the drawing
// order, and so is the one kept when both lie at the same depth.
inline bool drawn_before(uint32_t instance, uint32_t face, uint32_t other_instance, uint32_t other_face) {
    return instance != other_instance ? instance < other_instance : face < other_face;
}

// True when a surface at window depth `depth` replaces the one stored at a pixel (stored_depth,
// stored_instance, stored_face) under the nearer-wins depth test and the tie rule. A pixel nothing
// covers yet (stored_face is HSR_NO_FACE, 0xFFFFFFFF; the host clears depth to +infinity) is taken
// by any surface.
inline bool replaces(float depth, uint32_t instance, uint32_t face, float stored_depth, uint32_t stored_instance,
                     uint32_t stored_face) {
    if (stored_face == 0xFFFFFFFFu) return true;
    if (depth != stored_depth) return depth < stored_depth;
    return drawn_before(instance, face, stored_instance, stored_face);
}

// ---------------------------------------------------------------------------------------------- //
// The fill rule

// Top-left fill rule for an edge running from a to b of a triangle whose interior is on the side
// where the edge function is positive (window y down): a top edge is horizontal with the interior
// below it (it runs toward +x), a left edge runs upward (toward -y). Samples exactly on a top or
// left edge belong to the triangle, samples on any other edge do not, so a sample on an edge shared
// by two triangles is drawn exactly once.
inline bool is_top_left_edge(int64_t dx, int64_t dy) { return dy < 0 || (dy == 0 && dx > 0); }

// The fill rule at one sample for a triangle whose corners (x[k], y[k]) and the sample (sx, sy)
// are given on the snapped grid (window coordinates times 256, y down, either winding): true when
// the rasterizer covers the sample. A triangle of zero area on the grid covers nothing. For a
// renderer that does not rasterize (a ray caster) and must still draw a pixel centre on an edge
// exactly as the rasterizers do.
inline bool covers_sample(const int64_t (&x)[3], const int64_t (&y)[3], int64_t sx, int64_t sy) {
    const int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (area == 0) return false;
    // Walked so that the interior is on the positive side of every edge function, as
    // hsr/triangle_setup.hpp walks it: as given when area > 0, else backwards.
    const int order[3] = {0, area > 0 ? 1 : 2, area > 0 ? 2 : 1};
    for (int k = 0; k < 3; ++k) {
        const int a = order[k], b = order[(k + 1) % 3];
        const int64_t dx = x[b] - x[a], dy = y[b] - y[a];
        const int64_t edge = dx * (sy - y[a]) - dy * (sx - x[a]);
        if (edge < 0 || (edge == 0 && !is_top_left_edge(dx, dy))) return false;
    }
    return true;
}

}  // namespace hsr::raster
