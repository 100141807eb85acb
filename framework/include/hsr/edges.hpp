// The edges a hidden-line drawing shows, found from the half-edge adjacency of a flat scene and
// classified for one camera (ABI 1.2, hsr_line_request): boundaries, creases, silhouettes and edges
// between two faces turned away from the eye.
#pragma once

#include "hsr/abi.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hsr {

enum class EdgeSelection {
    kAll,       // every edge of the mesh except those between coplanar faces (the diagonals a
                // triangulation added inside flat polygons): the classic wireframe. On a surface
                // grid (hsr/surface.hpp) every grid line, flat or not, and no cell diagonal
    kFeatures,  // silhouettes, creases and boundaries only: a clean drawing of a smooth mesh
};

// The edges of one request as arrays, in the layout hsr_line_request points into.
struct EdgeList {
    std::vector<uint32_t> vertices;  // 2 per edge
    std::vector<uint32_t> faces;     // 2 per edge, HSR_NO_FACE for the missing one of a boundary
    std::vector<uint32_t> flags;     // HSR_EDGE_* per edge

    std::size_t size() const { return flags.size(); }
    // Points into this list: keep it alive and unchanged while the request is used.
    hsr_line_request request(bool want_hidden) const;
};

// Every edge of the scene once (it must have no instances: copy them out first), classified for the
// camera. A face is turned toward the eye when the eye (perspective) or the direction toward the
// viewer (orthographic) lies strictly on its front side, computed in double precision from the
// positions. An edge is a crease when its faces' normals differ by more than crease_angle_degrees.
EdgeList classify_edges(const hsr_scene& scene, const hsr_camera& camera, double crease_angle_degrees,
                        EdgeSelection selection);

// Whether each triangle faces the camera (the rule above), for code that needs the same answer.
std::vector<uint8_t> front_facing_faces(const hsr_scene& scene, const hsr_camera& camera);

}  // namespace hsr
