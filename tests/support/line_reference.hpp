// An independent answer for hidden-line plugins: points sampled along each requested edge,
// classified visible or hidden by casting a ray from the point to the eye against every triangle of
// the scene (double precision, Moller-Trumbore; shares no code with the plugins), and a comparison
// of those samples with the segments a plugin returned, forgiving samples within a tolerance (in
// pixels) of a change of visibility on either side.
#pragma once

#include "hsr/abi.h"
#include "hsr/edges.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace line_reference {

struct Segment {
    glm::dvec2 a, b;  // window coordinates
    uint32_t edge;
    uint32_t flags;
    int32_t qi;
};

inline glm::dvec3 position(const hsr_scene& s, uint32_t v) {
    return {s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]};
}

inline glm::dmat4 view_projection(const hsr_camera& c) {
    glm::dmat4 m;
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) m[col][row] = c.view_projection[4 * col + row];
    return m;
}

inline glm::dvec2 to_window(const hsr_camera& c, const glm::dmat4& vp, glm::dvec3 p) {
    const glm::dvec4 clip = vp * glm::dvec4(p, 1.0);
    return {(clip.x / clip.w + 1.0) * 0.5 * c.width, (1.0 - clip.y / clip.w) * 0.5 * c.height};
}

// Does the open segment from `origin` along `dir` (parameter in (t_min, t_max)) cross triangle
// (a, b, c) strictly inside (barycentric margin `inside`)?
inline bool ray_hits(glm::dvec3 origin, glm::dvec3 dir, double t_min, double t_max, glm::dvec3 a, glm::dvec3 b,
                     glm::dvec3 c, double inside) {
    const glm::dvec3 e1 = b - a, e2 = c - a;
    const glm::dvec3 p = glm::cross(dir, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-300) return false;
    const double inv = 1.0 / det;
    const glm::dvec3 s = origin - a;
    const double u = glm::dot(s, p) * inv;
    if (u <= inside || u >= 1.0 - inside) return false;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(dir, q) * inv;
    if (v <= inside || u + v >= 1.0 - inside) return false;
    const double t = glm::dot(e2, q) * inv;
    return t > t_min && t < t_max;
}

// The number of triangles between world point p and the eye, the faces in `skip` (those p lies on)
// left out.
inline int occluders(const hsr_scene& s, const hsr_camera& c, glm::dvec3 p, uint32_t skip0, uint32_t skip1) {
    glm::dvec3 dir;
    if (c.projection_type == HSR_PROJECTION_PERSPECTIVE) {
        dir = glm::dvec3(c.eye[0], c.eye[1], c.eye[2]) - p;
    } else {
        const glm::dvec3 lo(s.bounds_min[0], s.bounds_min[1], s.bounds_min[2]);
        const glm::dvec3 hi(s.bounds_max[0], s.bounds_max[1], s.bounds_max[2]);
        const double reach = 4.0 * glm::length(hi - lo) + 1.0;
        dir = -glm::dvec3(c.view_direction[0], c.view_direction[1], c.view_direction[2]) * reach;
    }
    int count = 0;
    for (uint32_t t = 0; t < s.triangle_count; ++t) {
        if (t == skip0 || t == skip1) continue;
        if (ray_hits(p, dir, 1e-9, 1.0, position(s, s.indices[3 * t]), position(s, s.indices[3 * t + 1]),
                     position(s, s.indices[3 * t + 2]), 1e-9))
            ++count;
    }
    return count;
}

struct Comparison {
    uint64_t samples = 0, checked = 0, disagreements = 0;
    uint64_t reference_visible = 0, plugin_visible = 0;
    std::string first;  // the first disagreement, for the test's message
};

// Samples every requested edge (every `edge_stride`-th one, to bound the cost on large meshes: each
// sample casts a ray against every triangle) every `step_px` pixels (at least 8 samples) and compares: a sample is
// visible for the plugin when a QI-0 segment of its edge passes within 0.02 px of its window point.
// Samples within `tolerance_px` of a change of the reference's answer along the edge, or of an end
// of one of the plugin's visible segments of that edge, are not checked.
inline Comparison compare(const hsr_scene& s, const hsr_camera& c, const hsr::EdgeList& edges,
                          const std::vector<Segment>& segments, double step_px = 0.25, double tolerance_px = 0.5,
                          uint32_t edge_stride = 1) {
    const glm::dmat4 vp = view_projection(c);
    std::vector<std::vector<const Segment*>> visible_of(edges.size());
    for (const Segment& seg : segments)
        if (seg.qi == 0 && seg.edge < edges.size()) visible_of[seg.edge].push_back(&seg);
    Comparison out;
    for (uint32_t e = 0; e < edges.size(); e += std::max<uint32_t>(edge_stride, 1)) {
        const glm::dvec3 p0 = position(s, edges.vertices[2 * e]), p1 = position(s, edges.vertices[2 * e + 1]);
        const glm::dvec2 w0 = to_window(c, vp, p0), w1 = to_window(c, vp, p1);
        const int n = std::max(8, int(std::ceil(glm::length(w1 - w0) / step_px)));
        std::vector<glm::dvec2> window(n + 1);
        std::vector<int> reference(n + 1), plugin(n + 1);
        for (int k = 0; k <= n; ++k) {
            // Samples strictly inside the edge: its end points lie on other faces too.
            const double t = (k + 0.5) / (n + 1.0);
            const glm::dvec3 p = p0 + t * (p1 - p0);
            window[k] = to_window(c, vp, p);
            reference[k] = occluders(s, c, p, edges.faces[2 * e], edges.faces[2 * e + 1]) == 0 ? 1 : 0;
            int on = 0;
            for (const Segment* seg : visible_of[e]) {
                const glm::dvec2 d = seg->b - seg->a;
                const double len2 = glm::dot(d, d);
                const double u = len2 > 0 ? std::clamp(glm::dot(window[k] - seg->a, d) / len2, 0.0, 1.0) : 0.0;
                if (glm::length(seg->a + u * d - window[k]) < 0.02) {
                    on = 1;
                    break;
                }
            }
            plugin[k] = on;
        }
        std::vector<glm::dvec2> changes;
        for (int k = 0; k < n; ++k)
            if (reference[k] != reference[k + 1]) changes.push_back(0.5 * (window[k] + window[k + 1]));
        for (const Segment* seg : visible_of[e]) {
            changes.push_back(seg->a);
            changes.push_back(seg->b);
        }
        for (int k = 0; k <= n; ++k) {
            ++out.samples;
            out.reference_visible += reference[k];
            out.plugin_visible += plugin[k];
            bool near_change = false;
            for (const glm::dvec2& ch : changes)
                if (glm::length(ch - window[k]) <= tolerance_px) {
                    near_change = true;
                    break;
                }
            if (near_change) continue;
            ++out.checked;
            if (reference[k] != plugin[k]) {
                if (out.disagreements == 0)
                    out.first = "edge " + std::to_string(e) + " sample " + std::to_string(k) + "/" + std::to_string(n) +
                                " at window (" + std::to_string(window[k].x) + ", " + std::to_string(window[k].y) +
                                "): ray casting says " + (reference[k] ? "visible" : "hidden") + ", the plugin " +
                                (plugin[k] ? "visible" : "hidden");
                ++out.disagreements;
            }
        }
    }
    return out;
}

}  // namespace line_reference
