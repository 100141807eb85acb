// Roberts' bodies: each object of the scene as a convex polyhedron given by its plane equations.
//
// The scene's triangles are grouped by object (hsr_scene.face_object). Coplanar triangles of one
// object (the pieces a triangulation cut a flat face into) are merged into one face, and each face
// gives one plane (a, b, c, d), one column of the body's matrix in Roberts' notation, with its sign
// fixed so that an interior point S = (x, y, z, 1) gives S · (a, b, c, d) > 0. A point lies inside
// the body exactly when it is on the positive side of every plane. Objects that are not closed,
// not convex, flat, or made of several pieces are refused with a message naming the object.
#pragma once

#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace roberts {

inline constexpr uint32_t kNoBody = 0xFFFFFFFFu;
inline constexpr uint32_t kNoPlane = 0xFFFFFFFFu;

struct Body {
    uint32_t object = 0;                      // index in hsr_scene's objects
    uint32_t first_plane = 0, plane_count = 0;  // rows of BodySet::planes
    uint32_t first_vertex = 0, vertex_count = 0;  // entries of BodySet::vertices
    glm::dvec3 box_min{0.0}, box_max{0.0};    // world-space bounds of its vertices
    glm::dvec3 interior_point{0.0};           // the mean of its vertices
    double tolerance = 0;  // world units: how far a vertex may lie outside a face plane (rounding)
    double shrink = 0;     // world units: a line of sight must pass more than this deep inside the
                           // body for it to hide anything, so that a body does not hide what lies on
                           // (or touches) its surface; the hidden interval's end points come from the
                           // true planes all the same
};

// Every body of a scene, with their planes (the columns of all body matrices, body after body).
struct BodySet {
    std::vector<Body> bodies;
    std::vector<uint32_t> body_of_object;     // kNoBody for an object with no triangles
    std::vector<glm::dvec4> planes;           // (a, b, c, d), |(a, b, c)| = 1, positive inside
    std::vector<uint32_t> plane_face;         // a triangle of each plane's face (for messages, trace)
    std::vector<uint32_t> plane_of_triangle;  // the plane each triangle lies in
    std::vector<uint32_t> vertices;           // each body's distinct vertex indices
};

// Throws hsr::sdk::InvalidArgument with "roberts: " and the printf-formatted message.
[[noreturn]] void refuse(const char* format, ...) __attribute__((format(printf, 1, 2)));

// Builds the bodies of a scene whose arrays have been checked (indices in range, finite positions,
// face_object < object_count, edge_neighbors in range). Throws hsr::sdk::InvalidArgument naming
// the object when one cannot be a Roberts body. Keeps its scratch space between calls.
class BodyBuilder {
public:
    void build(const hsr::sdk::Scene& scene, BodySet& out);

private:
    void build_body(const hsr::sdk::Scene& scene, uint32_t object, BodySet& out);
    // Its phases, in order, on the object's triangles; each check refuse()s what fails it.
    void gather_vertices(const hsr_scene& s, std::span<const uint32_t> triangles, Body& body, BodySet& out);
    double orient(const hsr_scene& s, std::span<const uint32_t> triangles, const Body& body);
    void check_convex_edges(const hsr_scene& s, std::span<const uint32_t> triangles, const Body& body) const;
    static void check_closed(const hsr_scene& s, uint32_t object, std::span<const uint32_t> triangles);
    void check_connected(const hsr_scene& s, uint32_t object, std::span<const uint32_t> triangles);
    void grow_faces(const hsr_scene& s, std::span<const uint32_t> triangles, double outward, Body& body, BodySet& out);
    static void place_thin_triangles(const hsr_scene& s, std::span<const uint32_t> triangles, const Body& body,
                                     BodySet& out);
    static void check_inside(const Body& body, const BodySet& out);
    static void check_convex_globally(const hsr_scene& s, const Body& body, const BodySet& out);

    std::vector<uint32_t> object_offsets_;    // triangles of object o: object_triangles_[offsets[o] .. offsets[o+1])
    std::vector<uint32_t> object_triangles_;
    std::vector<uint32_t> vertex_stamp_;      // last object whose vertex list took the vertex
    std::vector<uint32_t> triangle_stamp_;    // flood-fill marks
    std::vector<uint32_t> stack_;
    std::vector<glm::dvec3> unit_normals_;    // per triangle of the current object (0 when degenerate)
};

}  // namespace roberts
