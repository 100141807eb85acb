// One object of a scene as it is read, before SceneBuilder places it in the world: its triangles in
// its own coordinates, and the options it is placed with; objects made from arrays of triangles and
// polygons (model_reader.cpp).
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace hsr {

struct MeshOptions {
    glm::mat4 transform{1.0f};  // object to world; a mirroring transform keeps the front outside
    glm::vec3 color{0.8f, 0.8f, 0.8f};
    // Set when the colour was asked for (a .scene file's color line, --color): it then wins over
    // the colours the file gives its faces. Otherwise a face the file colours keeps that colour.
    bool color_given = false;
    // Corner normals average only the faces around a vertex whose normal is within this angle of
    // the corner's own face normal: 0 gives flat facets, 180 smooths everything.
    float crease_angle_degrees = 40.0f;
    std::string name;  // defaults to the file's stem, "polygon N" or "object N"
};

struct MeshObject {  // one object in its own coordinates, adjacency already known
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    std::vector<int32_t> neighbors;
    // One colour per triangle of `indices`, as the file gives them (materials, face or vertex
    // colours), each channel in [0, 1]; empty, or options.color_given: every triangle has
    // options.color.
    std::vector<glm::vec3> face_colors;
    MeshOptions options;
    std::string source;             // for messages: the file, or the object's name
    uint32_t separated_faces = 0;   // non-manifold faces given their own vertices
    std::vector<std::string> warnings;  // what the reader noticed, one line each, the file named
};

// An indexed triangle list as an object; `what` names it in messages. Triangles with a repeated
// corner are dropped; one that would make the mesh non-manifold gets vertices of its own.
MeshObject object_from_triangles(std::span<const glm::vec3> positions, std::span<const uint32_t> indices,
                                 const std::string& what);

// A polygon mesh given as arrays as an object, its faces cut into triangles as a model file's are:
// `corners` lists each face's vertices, face after face, and `face_ends` where each face's corners
// end; `face_colors` is empty or one colour (each channel in [0, 1]) per face. Throws hsr::Error,
// starting with `what`, for a face of fewer than 3 corners, an index out of range, a coordinate that
// is not finite or a mesh without a face left.
MeshObject object_from_polygons(std::span<const glm::vec3> positions, std::span<const uint32_t> corners,
                                std::span<const uint32_t> face_ends, std::span<const glm::vec3> face_colors,
                                const std::string& what);

// Meshes in their own coordinates and where each is placed, before they become one scene
// (placed_meshes_scene, scene_builder.hpp).
struct PlacedMeshes {
    std::vector<MeshObject> meshes;
    struct Placement {
        std::size_t mesh;            // into meshes
        glm::dmat4 transform;        // mesh to world
    };
    std::vector<Placement> placements;
    std::vector<std::string> notes;  // what was skipped, one line each
};

}  // namespace hsr
