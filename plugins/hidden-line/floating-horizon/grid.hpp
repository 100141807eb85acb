// The grid the floating-horizon plugin draws: its layout, checked against the one hsr/surface.hpp
// fixes (grid_problem), and the order in which the method takes it (choose_order): which lines of
// the grid are the curves, nearest first, and within the strip between two curves the order of its
// cross edges and diagonals (steps 1 and 2 of docs/algorithms/floating-horizon.md).
#pragma once

#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace floating_horizon {
// Internal linkage: only floating_horizon.cpp includes this, and so the compiler inlines as it would
// in one file (the per-column test inside Horizon::classify above all).
namespace {

// The grid (the layout of hsr/surface.hpp, checked as hsr::find_surface_grid checks it; a plugin
// links only the SDK, so the rule is restated here).

struct GridShape {
    uint32_t columns = 0, rows = 0;
};

inline std::string grid_problem(const hsr::sdk::Scene& s, GridShape& out) {
    const uint32_t V = s.vertex_count(), T = s.triangle_count();
    if (V < 4) return "fewer than 4 vertices";
    const float* p = s.raw().positions;
    uint32_t C = 1;
    while (C < V && p[3 * C + 2] == p[2]) ++C;
    if (C < 2) return "its first row has fewer than 2 vertices";
    if (V % C != 0) return std::to_string(V) + " vertices are not rows of " + std::to_string(C);
    const uint32_t R = V / C;
    if (R < 2) return "fewer than 2 rows";
    if (uint64_t(T) != 2 * uint64_t(C - 1) * (R - 1))
        return std::to_string(T) + " triangles, but a " + std::to_string(C) + "x" + std::to_string(R) + " grid has " +
               std::to_string(2 * uint64_t(C - 1) * (R - 1));
    for (uint32_t r = 0; r < R; ++r)
        for (uint32_t c = 0; c < C; ++c) {
            const size_t v = size_t(r) * C + c;
            if (!std::isfinite(p[3 * v + 1])) return "vertex " + std::to_string(v) + " has a height that is not finite";
            if (p[3 * v] != p[3 * c] || !(c == 0 || p[3 * v] > p[3 * v - 3]))
                return "vertex " + std::to_string(v) + " is off the lattice in x";
            if (p[3 * v + 2] != p[3 * size_t(r) * C + 2] || !(r == 0 || p[3 * v + 2] < p[3 * (v - C) + 2]))
                return "vertex " + std::to_string(v) + " is off the lattice in z";
        }
    for (uint32_t r = 0; r + 1 < R; ++r)
        for (uint32_t c = 0; c + 1 < C; ++c) {
            const uint32_t v00 = r * C + c, v10 = v00 + 1, v01 = v00 + C, v11 = v01 + 1;
            const uint32_t t = 2 * (r * (C - 1) + c);
            if (s.index(t, 0) != v00 || s.index(t, 1) != v10 || s.index(t, 2) != v11 ||
                s.index(t + 1, 0) != v00 || s.index(t + 1, 1) != v11 || s.index(t + 1, 2) != v01)
                return "triangles " + std::to_string(t) + " and " + std::to_string(t + 1) + " are not cell (" +
                       std::to_string(c) + ", " + std::to_string(r) + ")";
        }
    out = {C, R};
    return {};
}

// The grid seen as curves (index j, processed nearest first) of points along them (index i).
struct Layout {
    bool curves_are_rows = true;     // rows of constant y; otherwise columns of constant x
    uint32_t columns = 0;            // of the grid
    uint32_t along = 0, curves = 0;  // points per curve (nI), curves (nJ)
    uint32_t vertex(uint32_t i, uint32_t j) const { return curves_are_rows ? j * columns + i : i * columns + j; }
};
// How the camera sees the grid, in grid coordinates: depth across the curves, lateral along them.
struct View {
    bool perspective = true;
    double eye_depth = 0, eye_lateral = 0, eye_height = 0;  // perspective
    double depth_sign = 1;  // +1 when depth grows away from the eye
    double ray_depth = 0, ray_lateral = 0, ray_height = 0;  // orthographic: the view direction
};
enum class Kind { curve, cross, diagonal };
struct Element {
    Kind kind;
    uint32_t i;  // position along the curves
};

struct CurveOrder {
    Layout layout;
    View view;
    std::vector<uint32_t> curves;  // curve indices j, nearest first
    std::vector<Element> strip;    // a strip's cross edges and diagonals, nearest first
};

// Which curves run across the view, and the nearest-first orders of the curves and, within a strip,
// of its cross edges and diagonals.
//
// In grid coordinates (u = world x, v = -world z, so v grows with the row), a point P can be hidden
// only by surface between P and the eye. Curves of constant v have a nearest-first order exactly
// when the eye's v lies outside the grid's v range (perspective), or the view direction has a v
// component (orthographic): then every ray from a point toward the eye runs to smaller (or larger)
// v, and only nearer curves and the strips between them can hide a curve. Within a strip, the ray
// also moves toward the eye's u, so cross edges and diagonals are taken in order of their distance
// in u from the eye (from the viewer's side for an orthographic view): a cell's diagonal after the
// nearer cross edge of its cell and before the farther one, and the diagonal of the cell under the
// eye first. The same holds with u and v exchanged (curves of constant u).
inline void choose_order(const hsr::sdk::Scene& scene, const hsr_camera& camera, const GridShape& grid,
                         CurveOrder& order) {
    const float* p = scene.raw().positions;
    const uint32_t C = grid.columns, R = grid.rows;
    const double u0 = p[0], u1 = p[3 * (C - 1)];
    const double v0 = -double(p[2]), v1 = -double(p[3 * size_t(C) * (R - 1) + 2]);
    const glm::dvec3 direction(camera.view_direction[0], camera.view_direction[1], camera.view_direction[2]);
    const bool perspective = camera.projection_type == HSR_PROJECTION_PERSPECTIVE;
    const double eye_u = camera.eye[0], eye_v = -double(camera.eye[2]), eye_y = camera.eye[1];
    // The view direction in (u, v); components this small count as none.
    const double ray_u = direction.x, ray_v = -direction.z;
    const double tiny = 1e-9;
    const bool rows_ok = perspective ? (eye_v < v0 || eye_v > v1) : std::abs(ray_v) > tiny;
    const bool columns_ok = perspective ? (eye_u < u0 || eye_u > u1) : std::abs(ray_u) > tiny;
    if (!rows_ok && !columns_ok) {
        if (perspective)
            throw hsr::sdk::InvalidArgument(
                "floating-horizon: the eye is above or below the grid's area (at x = " + std::to_string(eye_u) +
                ", y = " + std::to_string(eye_v) + "; the grid covers x " + std::to_string(u0) + " to " +
                std::to_string(u1) + ", y " + std::to_string(v0) + " to " + std::to_string(v1) +
                "), so no order of its curves runs from the nearest to the farthest; lower the pitch until the eye "
                "is outside the grid in x or y");
        throw hsr::sdk::InvalidArgument(
            "floating-horizon: the orthographic view looks straight down (or up) on the grid, so its curves have no "
            "order from the nearest to the farthest; tilt the view");
    }
    const bool rows = rows_ok && (!columns_ok || std::abs(ray_v) >= std::abs(ray_u));
    order.layout.curves_are_rows = rows;
    order.layout.columns = C;
    order.layout.along = rows ? C : R;
    order.layout.curves = rows ? R : C;

    order.view.perspective = perspective;
    order.view.eye_depth = rows ? eye_v : eye_u;
    order.view.eye_lateral = rows ? eye_u : eye_v;
    order.view.eye_height = eye_y;
    order.view.ray_depth = rows ? ray_v : ray_u;
    order.view.ray_lateral = rows ? ray_u : ray_v;
    order.view.ray_height = direction.y;
    const double depth_first = rows ? v0 : u0;
    const bool first_is_nearest = perspective ? order.view.eye_depth < depth_first : order.view.ray_depth > 0;
    order.view.depth_sign = first_is_nearest ? 1.0 : -1.0;
    order.curves.resize(order.layout.curves);
    for (uint32_t j = 0; j < order.layout.curves; ++j) order.curves[j] = first_is_nearest ? j : order.layout.curves - 1 - j;

    std::vector<double> lateral(order.layout.along);
    for (uint32_t i = 0; i < order.layout.along; ++i) lateral[i] = rows ? double(p[3 * i]) : -double(p[3 * size_t(i) * C + 2]);
    // Distance along the curves from the eye: |lateral - eye| for a perspective eye; from the end the
    // viewer is on for an orthographic view. An orthographic view along the curves' normal (no lateral
    // component) moves no ray along the curves: a strip's cross edges and diagonals cannot hide each
    // other, and all its cross edges go first (key 0, diagonals key 1), so that a cross edge, upright
    // in the horizons' space, is never compared with the end of the diagonal that meets it at its top.
    const bool along_normal = !perspective && std::abs(order.view.ray_lateral) <= tiny;
    auto key = [&](double l) {
        if (perspective) return std::abs(l - order.view.eye_lateral);
        if (along_normal) return 0.0;
        return order.view.ray_lateral < 0 ? lateral.back() - l : l - lateral.front();
    };
    struct Keyed {
        double key;
        Element element;
    };
    std::vector<Keyed> keyed;
    for (uint32_t i = 0; i < order.layout.along; ++i) keyed.push_back({key(lateral[i]), {Kind::cross, i}});
    for (uint32_t m = 0; m + 1 < order.layout.along; ++m) {
        const bool under_eye = perspective && lateral[m] <= order.view.eye_lateral && order.view.eye_lateral <= lateral[m + 1];
        const double k = along_normal ? 1.0 : under_eye ? 0.0 : std::min(key(lateral[m]), key(lateral[m + 1]));
        keyed.push_back({k, {Kind::diagonal, m}});
    }
    // Ties: a cross edge before the diagonal of the cell it bounds on the eye's side.
    std::stable_sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
        if (a.key != b.key) return a.key < b.key;
        return a.element.kind == Kind::cross && b.element.kind != Kind::cross;
    });
    order.strip.clear();
    for (const Keyed& k : keyed) order.strip.push_back(k.element);
}

}  // namespace
}  // namespace floating_horizon
