// SceneBuilder: models (OBJ, OFF, PLY, STL through OpenMesh), planar polygons and raw triangles
// gathered into one world-space triangle mesh (SceneData).
#pragma once

#include "hsr/camera.hpp"
#include "hsr/language.hpp"
#include "hsr/mesh_object.hpp"
#include "hsr/scene.hpp"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace hsr {

// Accumulates objects; build() transforms them to world space, drops zero-area triangles and
// computes normals, adjacency and bounds. Every add_* throws hsr::Error on bad input.
class SceneBuilder {
public:
    // `language`: of the messages about the polygons and options given here (a model file's own
    // parse errors stay English).
    explicit SceneBuilder(Language language = Language::english) : language_(language) {}
    // OBJ, OFF, PLY, STL (ASCII and binary where OpenMesh reads them); polygons are triangulated.
    void add_model_file(const std::filesystem::path& file, const MeshOptions& options = {});
    // One planar polygon (at least 3 vertices, no self-intersections, may be concave) in explicit
    // world coordinates; its front is the side from which the vertices run counter-clockwise.
    void add_polygon(std::span<const glm::vec3> vertices, glm::vec3 color, const std::string& name = {});
    void add_triangles(std::span<const glm::vec3> positions, std::span<const uint32_t> indices,
                       const MeshOptions& options = {});
    // An object already read (a glTF mesh), with its options set.
    void add_read_object(MeshObject object) { objects_.push_back(std::move(object)); }
    // Throws hsr::Error if the scene has no triangles.
    SceneData build() const;

    std::size_t object_count() const { return objects_.size(); }

    using Object = MeshObject;
    const std::vector<Object>& objects() const { return objects_; }  // as added, in order
    // Object `index` added once more with other options: what add_model_file adds for a file it read
    // before, without reading it again.
    void add_copy(std::size_t index, const MeshOptions& options) {
        Object copy = objects_.at(index);
        copy.options = options;
        objects_.push_back(std::move(copy));
    }

private:
    Language language_;
    std::vector<Object> objects_;
};

// Meshes placed by transforms (a glTF file's nodes, the Python module's meshes and instances) as
// one scene: a mesh placed once is transformed; a mesh placed several times is stored once and
// placed as instances when every placement is a similarity (ABI 1.1), else copied. `options`'
// transform goes before every placement's. The notes become the scene's first warnings.
SceneData placed_meshes_scene(PlacedMeshes model, const MeshOptions& options = {});

// One model file as a scene: one object, or a glTF file's meshes placed by its nodes (as instances
// when a mesh is placed several times), whose cameras go to `cameras` when given.
SceneData load_model(const std::filesystem::path& file, const MeshOptions& options = {},
                     std::vector<ModelCamera>* cameras = nullptr);

}  // namespace hsr
