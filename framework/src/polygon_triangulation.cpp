// Polygons into triangles: the planar polygons of a .scene file and the faces of model files. A
// polygon is projected onto a plane and cut by ear clipping: by the two-ears theorem (Meisters,
// "Polygons have ears", American Mathematical Monthly 82, 1975) every simple polygon with more than
// three corners has an ear, a corner whose triangle with its two neighbours holds no other corner,
// so cutting off ears one at a time triangulates it. The plane is the one of the Newell normal
// (Newell's method: the normal as the sum of the edges' cross products, Sutherland, Sproull and
// Schumacker, "A characterization of ten hidden-surface algorithms", Computing Surveys 6, 1974),
// which is also the best-fitting plane's normal for a face that is not quite planar.
#include "polygon_triangulation.hpp"

#include "hsr/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <utility>

namespace hsr {
namespace {

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double cross2(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Whether closed segments ab and cd share a point.
bool segments_touch(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
    auto on_segment = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r) {  // r collinear with pq
        return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
               r.y <= std::max(p.y, q.y);
    };
    const double d1 = cross2(c, d, a), d2 = cross2(c, d, b), d3 = cross2(a, b, c), d4 = cross2(a, b, d);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
    return (d1 == 0 && on_segment(c, d, a)) || (d2 == 0 && on_segment(c, d, b)) ||
           (d3 == 0 && on_segment(a, b, c)) || (d4 == 0 && on_segment(a, b, d));
}

// Whether two edges meet only as a polygon with a hole does where a bridge joins the hole to the
// outline (a keyhole, as model files write such faces): the same segment gone over both ways, or
// a corner the outline passes through twice, the edges meeting at nothing else.
bool bridge_or_shared_corner(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
    if (a == d && b == c) return true;
    if ((a == c) + (a == d) + (b == c) + (b == d) != 1) return false;
    const glm::dvec2 corner = (a == c || a == d) ? a : b;
    const glm::dvec2 along_ab = (corner == a ? b : a) - corner, along_cd = (corner == c ? d : c) - corner;
    // Not in line, or in line but going off either way from the corner.
    return along_ab.x * along_cd.y - along_ab.y * along_cd.x != 0.0 || glm::dot(along_ab, along_cd) < 0.0;
}

// Two edges, not neighbours along the outline, that meet (numbered from 1), if there are any; a
// keyhole's bridges and doubly visited corners do not count.
std::optional<std::pair<std::size_t, std::size_t>> meeting_edges(const std::vector<glm::dvec2>& points) {
    const std::size_t n = points.size();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // neighbouring edges share a corner
            const glm::dvec2 a = points[i], b = points[(i + 1) % n], c = points[j], d = points[(j + 1) % n];
            if (segments_touch(a, b, c, d) && !bridge_or_shared_corner(a, b, c, d)) return std::pair(i + 1, j + 1);
        }
    return std::nullopt;
}

// Ear clipping of a counter-clockwise simple polygon into corner indices, 3 per triangle, appended
// to `triangles`; false (with `triangles` as it was) if no ear is left, which happens only when the
// polygon is not simple. Collinear corners are removed without a triangle (they add no area).
bool ear_clip(const std::vector<glm::dvec2>& points, std::vector<uint32_t>& triangles) {
    const std::size_t first_triangle = triangles.size();
    std::vector<uint32_t> remaining(points.size());
    for (uint32_t i = 0; i < remaining.size(); ++i) remaining[i] = i;
    std::size_t i = 0, misses = 0;
    while (remaining.size() > 3) {
        std::size_t n = remaining.size();
        uint32_t a = remaining[(i + n - 1) % n], b = remaining[i % n], c = remaining[(i + 1) % n];
        double turn = cross2(points[a], points[b], points[c]);
        bool clip = false;
        if (turn == 0.0) {
            clip = true;  // b lies on the line through its neighbours
        } else if (turn > 0.0) {
            clip = true;
            for (uint32_t p : remaining) {
                if (p == a || p == b || p == c) continue;
                glm::dvec2 q = points[p];
                if (q == points[a] || q == points[b] || q == points[c]) continue;
                if (cross2(points[a], points[b], q) >= 0 && cross2(points[b], points[c], q) >= 0 &&
                    cross2(points[c], points[a], q) >= 0) {
                    clip = false;
                    break;
                }
            }
        }
        if (clip) {
            if (turn != 0.0) triangles.insert(triangles.end(), {a, b, c});
            remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(i % n));
            misses = 0;
            if (i >= remaining.size()) i = 0;
        } else {
            if (++misses > n) {
                triangles.resize(first_triangle);
                return false;
            }
            i = (i + 1) % n;
        }
    }
    if (cross2(points[remaining[0]], points[remaining[1]], points[remaining[2]]) != 0.0)
        triangles.insert(triangles.end(), {remaining[0], remaining[1], remaining[2]});
    return true;
}

// Twice the vector area of a polygon about its centre (Newell's method), and the largest distance
// of a corner from that centre.
template <class Point>
std::pair<glm::dvec3, double> newell_normal(std::span<const Point> corners, glm::dvec3& centre) {
    centre = glm::dvec3(0.0);
    for (const Point& c : corners) centre += glm::dvec3(c);
    centre /= static_cast<double>(corners.size());
    glm::dvec3 normal(0.0);
    double extent = 0.0;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        glm::dvec3 a = glm::dvec3(corners[i]) - centre, b = glm::dvec3(corners[(i + 1) % corners.size()]) - centre;
        normal += glm::cross(a, b);
        extent = std::max(extent, glm::length(a));
    }
    return {normal, extent};
}

// Whether a counter-clockwise outline turns left (or goes straight) at every corner and winds once
// around: then it is convex and the fan from any corner covers it exactly.
bool is_convex(const std::vector<glm::dvec2>& points) {
    const std::size_t n = points.size();
    double turning = 0.0;
    glm::dvec2 previous_edge(0.0);
    bool have_previous = false;
    for (std::size_t k = 0; k <= n; ++k) {  // the first edge again at the end, to turn onto it
        const glm::dvec2 edge = points[(k + 1) % n] - points[k % n];
        if (edge == glm::dvec2(0.0)) continue;
        if (have_previous) {
            const double cross = previous_edge.x * edge.y - previous_edge.y * edge.x;
            if (cross < 0.0) return false;
            turning += std::atan2(cross, glm::dot(previous_edge, edge));
        }
        previous_edge = edge;
        have_previous = true;
    }
    constexpr double full_turn = 2.0 * 3.14159265358979323846;
    return std::fabs(turning - full_turn) < 1e-6;
}

}  // namespace

PolygonTriangles triangulate_polygon(std::span<const glm::vec3> vertices, const std::string& what, Language language) {
    std::vector<glm::dvec3> corners;
    for (glm::vec3 v : vertices) {
        if (!finite(v)) throw Error(say(language, "{}: a vertex has a coordinate that is not a finite number",
                                         "{}: у вершины есть координата, которая не является конечным числом", what));
        if (corners.empty() || glm::dvec3(v) != corners.back()) corners.emplace_back(v);
    }
    while (corners.size() > 1 && corners.front() == corners.back()) corners.pop_back();
    if (corners.size() < 3) throw Error(say(language, "{}: needs at least 3 distinct vertices",
                                            "{}: нужно не меньше трёх различных вершин", what));

    glm::dvec3 centre;
    auto [normal, extent] = newell_normal(std::span<const glm::dvec3>(corners), centre);
    double area2 = glm::length(normal);
    if (!(area2 > 1e-12 * extent * extent)) throw Error(say(language, "{}: has no area (its vertices are collinear)",
                                                                     "{}: площадь равна нулю (вершины лежат на одной прямой)", what));
    normal /= area2;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        double off = std::fabs(glm::dot(corners[i] - centre, normal));
        if (off > 1e-4 * extent)
            throw Error(say(language, "{}: is not planar (vertex {} lies {:.3g} off the polygon's plane)",
                            "{}: не плоский (вершина {} отстоит от плоскости многоугольника на {:.3g})", what, i + 1, off));
    }

    // Project onto the coordinate plane the polygon faces most, keeping counter-clockwise order.
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (std::fabs(normal[k]) > std::fabs(normal[axis])) axis = k;
    int u = (axis + 1) % 3, w = (axis + 2) % 3;
    if (normal[axis] < 0) std::swap(u, w);
    std::vector<glm::dvec2> flat;
    for (const glm::dvec3& c : corners) flat.emplace_back(c[u], c[w]);
    if (auto edges = meeting_edges(flat))
        throw Error(say(language, "{}: the polygon intersects itself (edges {} and {} meet)",
                        "{}: многоугольник самопересекающийся (рёбра {} и {} пересекаются)", what, edges->first,
                        edges->second));
    std::vector<uint32_t> triangles;
    if (!ear_clip(flat, triangles))
        throw Error(say(language, "{}: the polygon intersects itself", "{}: многоугольник самопересекающийся", what));
    return {std::vector<glm::vec3>(corners.begin(), corners.end()), std::move(triangles)};
}

FaceCut triangulate_face(std::span<const glm::vec3> corners, std::vector<uint32_t>& triangles) {
    const auto n = static_cast<uint32_t>(corners.size());
    auto fan = [&](FaceCut cut) {
        for (uint32_t k = 1; k + 1 < n; ++k) triangles.insert(triangles.end(), {0, k, k + 1});
        return cut;
    };
    glm::dvec3 centre;
    auto [normal, extent] = newell_normal(corners, centre);
    const double area2 = glm::length(normal);
    if (!(area2 > 1e-12 * extent * extent)) return fan(FaceCut::fan_no_area);
    normal /= area2;
    // Axes u, v of the plane with u x v = normal, so that the outline stays counter-clockwise.
    const glm::dvec3 helper = std::fabs(normal.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(helper, normal));
    const glm::dvec3 v = glm::cross(normal, u);
    std::vector<glm::dvec2> flat;
    flat.reserve(n);
    for (glm::vec3 c : corners) {
        const glm::dvec3 d = glm::dvec3(c) - centre;
        flat.emplace_back(glm::dot(d, u), glm::dot(d, v));
    }
    if (is_convex(flat)) return fan(FaceCut::polygon);
    if (meeting_edges(flat) || !ear_clip(flat, triangles)) return fan(FaceCut::fan_intersecting);
    return FaceCut::polygon;
}

}  // namespace hsr
