// QI counted at a vertex in Appel's algorithm (steps 5 and 6 of docs/algorithms/appel.md): directly,
// at the seed vertex of a component, by testing the faces whose image covers it; and Appel's vertex
// rule, the faces around a vertex that hide an edge just after it leaves the vertex.
#pragma once

#include "view_geometry.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

namespace appel {

// A seed vertex whose line of sight passes within this angle (radians, roughly) of a face's border
// or plane is avoided when another one is available.
constexpr double kSeedMargin = 1e-9;

// The QI of vertex s by counting: faces (not its own) whose image covers the vertex's image and
// whose plane it lies behind. `clean` is cleared when the line of sight passes close to a face's
// border or plane, where rounding could decide. Adds the faces tested to face_tests.
inline int32_t faces_hiding_vertex(const ViewGeometry& g, const Viewer& viewer, uint32_t s, bool& clean,
                                   uint64_t& face_tests) {
    const glm::dvec3& p = g.position[s];
    int32_t qi = 0;
    for (const uint32_t f : g.face_bins[g.face_grid.cell_of(g.window[s])]) {
        if (g.graph.face_has(f, s)) continue;
        const FacePlane& plane = g.face_plane[f];
        if (plane.eye_side == 0) continue;
        ++face_tests;
        bool inside = true, clearly_outside = false, clearly_inside = true;
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = g.graph.corner(f, k), b = g.graph.corner(f, (k + 1) % 3), c = g.graph.corner(f, (k + 2) % 3);
            const SightPlane side = sight_plane(viewer, a, g.position[a], b, g.position[b]);
            const double value = side.value(p);
            const bool near = std::abs(value) <= kSeedMargin * glm::length(side.normal) * glm::length(p - side.origin);
            if (side.side(p) != side.side(g.position[c])) {
                inside = false;
                if (!near) clearly_outside = true;
            } else if (near) {
                clearly_inside = false;
            }
        }
        if (!inside) {
            if (!clearly_outside) clean = false;
            continue;
        }
        const double depth = glm::dot(plane.normal, p - plane.corner);
        if (!clearly_inside || std::abs(depth) <= kSeedMargin * glm::length(plane.normal) * glm::length(p - plane.corner))
            clean = false;
        if (plane.hides(p)) ++qi;
    }
    return qi;
}

// Appel's vertex rule: how many faces around v (other than those of the edge v-w itself) hide the
// edge from v toward w just after it leaves v. Such a face covers the edge's image near v when
// the image of w lies inside the face's corner at v, and hides it when w is behind its plane.
inline int32_t faces_hiding_edge_start(const ViewGeometry& g, const Viewer& viewer, uint32_t v, uint32_t w) {
    int32_t count = 0;
    const glm::dvec3& pv = g.position[v];
    const glm::dvec3& pw = g.position[w];
    for (const uint32_t f : g.graph.faces_at(v)) {
        const FacePlane& plane = g.face_plane[f];
        if (plane.eye_side == 0 || g.graph.face_has(f, w)) continue;
        if (sign_of(glm::dot(plane.normal, pw - pv)) != -plane.eye_side) continue;
        int k = 0;
        while (g.graph.corner(f, k) != v) ++k;
        const uint32_t a = g.graph.corner(f, (k + 1) % 3), b = g.graph.corner(f, (k + 2) % 3);
        const SightPlane va = sight_plane(viewer, v, pv, a, g.position[a]);
        const int inner_a = va.side(g.position[b]);
        if (inner_a == 0 || va.side(pw) != inner_a) continue;
        const SightPlane vb = sight_plane(viewer, v, pv, b, g.position[b]);
        const int inner_b = vb.side(g.position[a]);
        if (inner_b == 0 || vb.side(pw) != inner_b) continue;
        ++count;
    }
    return count;
}

}  // namespace appel
