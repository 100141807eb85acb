// Building Roberts' bodies (see bodies.hpp): grouping, checks, coplanar faces, plane matrices.
#include "bodies.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <string>

namespace roberts {
namespace {

// Above this many (plane, vertex) pairs a body's global convexity check is skipped: the local check
// at every edge, closedness and connectedness then stand for it (they imply convexity unless the
// surface overlaps itself; docs/algorithms/roberts.md).
constexpr double kGlobalCheckBudget = 5e7;
// Two neighbouring triangles belong to one face when their normals differ by less than this (in
// 1 - cos, about 0.06 degrees, as the host's coplanar test) and their corners lie within the
// body's tolerance of the face's first triangle's plane.
constexpr double kCoplanarCosine = 1.0 - 5e-7;

glm::dvec3 position(const hsr_scene& s, uint32_t v) {
    return {s.positions[3 * size_t(v)], s.positions[3 * size_t(v) + 1], s.positions[3 * size_t(v) + 2]};
}

glm::dvec3 corner(const hsr_scene& s, uint32_t t, int c) { return position(s, s.indices[3 * size_t(t) + c]); }

// Twice the area times the unit normal of the counter-clockwise side.
glm::dvec3 area_normal(const hsr_scene& s, uint32_t t) {
    const glm::dvec3 a = corner(s, t, 0);
    return glm::cross(corner(s, t, 1) - a, corner(s, t, 2) - a);
}

}  // namespace

void refuse(const char* format, ...) {
    char buffer[HSR_ERROR_MESSAGE_SIZE];
    std::va_list args;
    va_start(args, format);
    std::vsnprintf(buffer, sizeof buffer, format, args);
    va_end(args);
    throw hsr::sdk::InvalidArgument(std::string("roberts: ") + buffer);
}

void BodyBuilder::build(const hsr::sdk::Scene& scene, BodySet& out) {
    const hsr_scene& s = scene.raw();
    const uint32_t triangle_count = s.triangle_count;
    const uint32_t object_count = s.object_count;

    // Triangles grouped by object (a counting sort keeps scene order within an object).
    object_offsets_.assign(size_t(object_count) + 1, 0);
    for (uint32_t t = 0; t < triangle_count; ++t) ++object_offsets_[s.face_object[t] + 1];
    for (uint32_t o = 0; o < object_count; ++o) object_offsets_[o + 1] += object_offsets_[o];
    object_triangles_.resize(triangle_count);
    stack_.assign(object_offsets_.begin(), object_offsets_.end() - 1);  // write cursors
    for (uint32_t t = 0; t < triangle_count; ++t) object_triangles_[stack_[s.face_object[t]]++] = t;

    out.bodies.clear();
    out.planes.clear();
    out.plane_face.clear();
    out.vertices.clear();
    out.body_of_object.assign(object_count, kNoBody);
    out.plane_of_triangle.assign(triangle_count, kNoPlane);
    vertex_stamp_.assign(s.vertex_count, kNoBody);
    triangle_stamp_.assign(triangle_count, kNoBody);
    unit_normals_.resize(triangle_count);

    for (uint32_t o = 0; o < object_count; ++o)
        if (object_offsets_[o + 1] > object_offsets_[o]) build_body(scene, o, out);
}

void BodyBuilder::build_body(const hsr::sdk::Scene& scene, uint32_t object, BodySet& out) {
    const hsr_scene& s = scene.raw();
    const std::span<const uint32_t> triangles(object_triangles_.data() + object_offsets_[object],
                                              object_offsets_[object + 1] - object_offsets_[object]);

    Body body;
    body.object = object;
    gather_vertices(s, triangles, body, out);
    const double outward = orient(s, triangles, body);
    check_convex_edges(s, triangles, body);
    check_closed(s, object, triangles);
    check_connected(s, object, triangles);
    grow_faces(s, triangles, outward, body, out);
    if (body.plane_count == 0) refuse("object %u has no volume: all its triangles have zero area", object);
    place_thin_triangles(s, triangles, body, out);
    check_inside(body, out);
    check_convex_globally(s, body, out);

    out.body_of_object[object] = uint32_t(out.bodies.size());
    out.bodies.push_back(body);
}

// Distinct vertices, bounds, mean (the interior point of a convex body).
void BodyBuilder::gather_vertices(const hsr_scene& s, std::span<const uint32_t> triangles, Body& body, BodySet& out) {
    const uint32_t object = body.object;
    body.first_vertex = uint32_t(out.vertices.size());
    glm::dvec3 sum(0.0);
    double largest_coordinate = 0;
    body.box_min = glm::dvec3(std::numeric_limits<double>::infinity());
    body.box_max = -body.box_min;
    for (const uint32_t t : triangles)
        for (int c = 0; c < 3; ++c) {
            const uint32_t v = s.indices[3 * size_t(t) + c];
            if (vertex_stamp_[v] == object) continue;
            vertex_stamp_[v] = object;
            out.vertices.push_back(v);
            const glm::dvec3 p = position(s, v);
            sum += p;
            body.box_min = glm::min(body.box_min, p);
            body.box_max = glm::max(body.box_max, p);
            largest_coordinate = std::max({largest_coordinate, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
        }
    body.vertex_count = uint32_t(out.vertices.size()) - body.first_vertex;
    body.interior_point = sum / double(body.vertex_count);
    const double size = glm::length(body.box_max - body.box_min);
    // Float positions carry a rounding error of about 6e-8 of their magnitude; the tolerances are
    // well above that and well below anything a user would model on purpose.
    body.tolerance = 1e-5 * size + 1e-6 * largest_coordinate;
    body.shrink = 1e-6 * size + 1e-6 * largest_coordinate;
}

// Orientation: the scene's front side is counter-clockwise; a body given inside out has a
// negative signed volume and its triangle normals point inward. Returns the sign that turns the
// counter-clockwise normals outward, having stored the outward unit normals.
double BodyBuilder::orient(const hsr_scene& s, std::span<const uint32_t> triangles, const Body& body) {
    double six_volume = 0;
    for (const uint32_t t : triangles)
        six_volume += glm::dot(corner(s, t, 0) - body.interior_point,
                               glm::cross(corner(s, t, 1) - body.interior_point, corner(s, t, 2) - body.interior_point));
    const double outward = six_volume < 0 ? -1.0 : 1.0;
    const double size = glm::length(body.box_max - body.box_min);
    const double degenerate_area = 1e-24 * size * size + 1e-300;
    for (const uint32_t t : triangles) {
        const glm::dvec3 n = area_normal(s, t);
        const double length = glm::length(n);
        unit_normals_[t] = length > degenerate_area ? outward * n / length : glm::dvec3(0.0);
    }
    return outward;
}

// Convex at every edge: across each edge, the neighbour's far corner lies on or inside the
// triangle's plane. The worst fold is the one reported.
void BodyBuilder::check_convex_edges(const hsr_scene& s, std::span<const uint32_t> triangles, const Body& body) const {
    double worst_outside = body.tolerance;
    uint32_t worst_vertex = 0, worst_triangle = 0;
    for (const uint32_t t : triangles) {
        if (unit_normals_[t] == glm::dvec3(0.0)) continue;
        for (int i = 0; i < 3; ++i) {
            const uint32_t a = s.indices[3 * size_t(t) + i], b = s.indices[3 * size_t(t) + (i + 1) % 3];
            const int32_t neighbor = s.edge_neighbors[3 * size_t(t) + i];
            if (neighbor == HSR_NO_NEIGHBOR) continue;
            for (int c = 0; c < 3; ++c) {
                const uint32_t far = s.indices[3 * size_t(neighbor) + c];
                if (far == a || far == b) continue;
                const double outside = glm::dot(unit_normals_[t], position(s, far) - position(s, a));
                if (outside > worst_outside) {
                    worst_outside = outside;
                    worst_vertex = far;
                    worst_triangle = t;
                }
            }
        }
    }
    if (worst_outside > body.tolerance) {
        const glm::dvec3 p = position(s, worst_vertex);
        refuse("object %u is not convex: vertex %u at (%g, %g, %g) lies %g outside the plane of the face containing "
               "triangle %u (tolerance %g); Roberts' algorithm takes convex bodies only: give each convex part as an "
               "object of its own",
               body.object, worst_vertex, p.x, p.y, p.z, worst_outside, worst_triangle, body.tolerance);
    }
}

// Closed: every edge has a face of the same object on either side.
void BodyBuilder::check_closed(const hsr_scene& s, uint32_t object, std::span<const uint32_t> triangles) {
    for (const uint32_t t : triangles) {
        for (int i = 0; i < 3; ++i) {
            const int32_t neighbor = s.edge_neighbors[3 * size_t(t) + i];
            if (neighbor == HSR_NO_NEIGHBOR)
                refuse("object %u is not a closed surface: the edge from vertex %u to vertex %u (triangle %u) has a face "
                       "on one side only; Roberts' algorithm takes closed convex bodies",
                       object, s.indices[3 * size_t(t) + i], s.indices[3 * size_t(t) + (i + 1) % 3], t);
            if (s.face_object[uint32_t(neighbor)] != object)
                refuse("object %u is not a closed surface of its own: its triangle %u shares an edge with triangle %d of "
                       "object %u",
                       object, t, neighbor, s.face_object[uint32_t(neighbor)]);
        }
    }
}

// One connected surface (two boxes given as one object are two bodies).
void BodyBuilder::check_connected(const hsr_scene& s, uint32_t object, std::span<const uint32_t> triangles) {
    uint32_t components = 0;
    for (const uint32_t first : triangles) {
        if (triangle_stamp_[first] == object) continue;
        ++components;
        stack_.clear();
        stack_.push_back(first);
        triangle_stamp_[first] = object;
        while (!stack_.empty()) {
            const uint32_t t = stack_.back();
            stack_.pop_back();
            for (int i = 0; i < 3; ++i) {
                const uint32_t u = uint32_t(s.edge_neighbors[3 * size_t(t) + i]);
                if (triangle_stamp_[u] == object) continue;
                triangle_stamp_[u] = object;
                stack_.push_back(u);
            }
        }
    }
    if (components > 1)
        refuse("object %u is not one convex body: it is made of %u separate closed surfaces; give each as an object of "
               "its own",
               object, components);
}

// Faces: grow each from a first triangle over neighbours lying in its plane. A convex face is
// connected, so this finds it whole; the seed's plane is the reference, so no drift builds up.
void BodyBuilder::grow_faces(const hsr_scene& s, std::span<const uint32_t> triangles, double outward, Body& body,
                             BodySet& out) {
    body.first_plane = uint32_t(out.planes.size());
    for (const uint32_t seed : triangles) {
        if (out.plane_of_triangle[seed] != kNoPlane || unit_normals_[seed] == glm::dvec3(0.0)) continue;
        const uint32_t plane = uint32_t(out.planes.size());
        const glm::dvec3 seed_normal = unit_normals_[seed];
        const glm::dvec3 seed_point = corner(s, seed, 0);
        glm::dvec3 normal_sum(0.0), corner_sum(0.0);
        uint32_t corner_count = 0;
        stack_.clear();
        stack_.push_back(seed);
        out.plane_of_triangle[seed] = plane;
        while (!stack_.empty()) {
            const uint32_t t = stack_.back();
            stack_.pop_back();
            normal_sum += outward * area_normal(s, t);
            for (int c = 0; c < 3; ++c) corner_sum += corner(s, t, c);
            corner_count += 3;
            for (int i = 0; i < 3; ++i) {
                const uint32_t u = uint32_t(s.edge_neighbors[3 * size_t(t) + i]);
                if (out.plane_of_triangle[u] != kNoPlane || unit_normals_[u] == glm::dvec3(0.0)) continue;
                if (glm::dot(unit_normals_[u], seed_normal) <= kCoplanarCosine) continue;
                bool in_plane = true;
                for (int c = 0; c < 3; ++c)
                    in_plane = in_plane && std::abs(glm::dot(seed_normal, corner(s, u, c) - seed_point)) <= body.tolerance;
                if (!in_plane) continue;
                out.plane_of_triangle[u] = plane;
                stack_.push_back(u);
            }
        }
        const glm::dvec3 normal = glm::normalize(normal_sum);
        glm::dvec4 column(normal, -glm::dot(normal, corner_sum / double(corner_count)));
        // Roberts' sign rule: the interior point must give a positive value.
        if (glm::dot(column, glm::dvec4(body.interior_point, 1.0)) < 0) column = -column;
        out.planes.push_back(column);
        out.plane_face.push_back(seed);
    }
    body.plane_count = uint32_t(out.planes.size()) - body.first_plane;
}

// Triangles too thin to have a normal go with a neighbour's face.
void BodyBuilder::place_thin_triangles(const hsr_scene& s, std::span<const uint32_t> triangles, const Body& body,
                                       BodySet& out) {
    for (const uint32_t t : triangles) {
        if (out.plane_of_triangle[t] != kNoPlane) continue;
        uint32_t plane = body.first_plane;
        for (int i = 0; i < 3; ++i) {
            const uint32_t u = uint32_t(s.edge_neighbors[3 * size_t(t) + i]);
            if (out.plane_of_triangle[u] != kNoPlane) plane = out.plane_of_triangle[u];
        }
        out.plane_of_triangle[t] = plane;
    }
}

// The interior point must lie inside every plane by more than the tolerance (else the body is
// flat or too thin to tell its sides apart).
void BodyBuilder::check_inside(const Body& body, const BodySet& out) {
    for (uint32_t j = body.first_plane; j < body.first_plane + body.plane_count; ++j) {
        const double depth = glm::dot(out.planes[j], glm::dvec4(body.interior_point, 1.0));
        if (depth <= body.tolerance)
            refuse("object %u has no volume: its vertices lie within %g of the plane of the face containing triangle %u "
                   "(tolerance %g); Roberts' algorithm takes solid convex bodies",
                   body.object, depth, out.plane_face[j], body.tolerance);
    }
}

// Convex as a whole: every vertex on the inner side of every plane (skipped above a budget).
void BodyBuilder::check_convex_globally(const hsr_scene& s, const Body& body, const BodySet& out) {
    if (double(body.plane_count) * double(body.vertex_count) > kGlobalCheckBudget) return;
    for (uint32_t j = body.first_plane; j < body.first_plane + body.plane_count; ++j) {
        const glm::dvec4 column = out.planes[j];
        for (uint32_t k = body.first_vertex; k < body.first_vertex + body.vertex_count; ++k) {
            const glm::dvec3 p = position(s, out.vertices[k]);
            const double value = glm::dot(column, glm::dvec4(p, 1.0));
            if (value < -body.tolerance)
                refuse("object %u is not convex: vertex %u at (%g, %g, %g) lies %g outside the plane of the face "
                       "containing triangle %u (tolerance %g); Roberts' algorithm takes convex bodies only: give each "
                       "convex part as an object of its own",
                       body.object, out.vertices[k], p.x, p.y, p.z, -value, out.plane_face[j], body.tolerance);
        }
    }
}

}  // namespace roberts
