// SceneData: the world-space triangle mesh that an hsr_scene points into. SceneBuilder
// (scene_builder.hpp) makes one from models, polygons and triangles; instancing.hpp places one many
// times; scene_file.hpp reads a `.scene` file into one.
#pragma once

#include "hsr/abi.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace hsr {

// Owns every array an hsr_scene points into (abi.h documents each one). Vertices are shared between
// the triangles of one object, so edge_neighbors describe real adjacency.
struct SceneData {
    std::vector<float> positions;        // 3 per vertex
    std::vector<uint32_t> indices;       // 3 per triangle, counter-clockwise seen from the front
    std::vector<float> face_normals;     // 3 per triangle
    std::vector<float> corner_normals;   // 9 per triangle
    std::vector<float> face_colors;      // 3 per triangle
    std::vector<int32_t> edge_neighbors; // 3 per triangle, HSR_NO_NEIGHBOR on a boundary
    std::vector<uint32_t> face_object;   // 1 per triangle
    std::vector<std::string> object_names;
    std::vector<float> object_opacity;   // 1 per object in [0, 1], or empty: everything opaque
    // ABI 1.1 instances; when non-empty, positions and normals are in object space (abi.h).
    std::vector<hsr_instance> instances;
    glm::vec3 bounds_min{0}, bounds_max{0};
    // Things the user may want to know that are not errors ("x.obj: 2 degenerate triangles
    // dropped"), one line each.
    std::vector<std::string> warnings;

    uint32_t vertex_count() const { return static_cast<uint32_t>(positions.size() / 3); }
    uint32_t triangle_count() const { return static_cast<uint32_t>(indices.size() / 3); }
    hsr_scene view() const;  // points into this object: keep it alive and unchanged meanwhile
};

}  // namespace hsr
