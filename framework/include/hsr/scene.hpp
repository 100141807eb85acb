// Geometry input: models (OBJ, OFF, PLY, STL through OpenMesh), planar polygons and raw triangles
// gathered into one world-space triangle mesh (SceneData) that an hsr_scene points into; the
// `.scene` text format (docs/scene-format.md); light specifications shared by scene files and the
// command line.
#pragma once

#include "hsr/abi.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
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

struct MeshOptions {
    glm::mat4 transform{1.0f};  // object to world; a mirroring transform keeps the front outside
    glm::vec3 color{0.8f, 0.8f, 0.8f};
    // Corner normals average only the faces around a vertex whose normal is within this angle of
    // the corner's own face normal: 0 gives flat facets, 180 smooths everything.
    float crease_angle_degrees = 40.0f;
    std::string name;  // defaults to the file's stem, "polygon N" or "object N"
};

// Accumulates objects; build() transforms them to world space, drops zero-area triangles and
// computes normals, adjacency and bounds. Every add_* throws hsr::Error on bad input.
class SceneBuilder {
public:
    // OBJ, OFF, PLY, STL (ASCII and binary where OpenMesh reads them); polygons are triangulated.
    void add_model_file(const std::filesystem::path& file, const MeshOptions& options = {});
    // One planar polygon (at least 3 vertices, no self-intersections, may be concave) in explicit
    // world coordinates; its front is the side from which the vertices run counter-clockwise.
    void add_polygon(std::span<const glm::vec3> vertices, glm::vec3 color, const std::string& name = {});
    void add_triangles(std::span<const glm::vec3> positions, std::span<const uint32_t> indices,
                       const MeshOptions& options = {});
    // Throws hsr::Error if the scene has no triangles.
    SceneData build() const;

    std::size_t object_count() const { return objects_.size(); }

    struct Object {  // one object in its own coordinates, adjacency already known
        std::vector<glm::vec3> positions;
        std::vector<uint32_t> indices;
        std::vector<int32_t> neighbors;
        MeshOptions options;
        std::string source;             // for messages: the file, or the object's name
        uint32_t separated_faces = 0;   // non-manifold faces given their own vertices
    };

private:
    std::vector<Object> objects_;
};

// One instance (abi.h) of the triangles [first_triangle, +triangle_count) using the vertices
// [first_vertex, +vertex_count): world = translation + scale * rotation * object. The world bounds
// come from the object bounds given. Throws hsr::Error for a scale that is not positive.
hsr_instance make_instance(uint32_t first_triangle, uint32_t triangle_count, uint32_t first_vertex,
                           uint32_t vertex_count, const glm::mat3& rotation, float scale, glm::vec3 translation,
                           glm::vec3 object_bounds_min, glm::vec3 object_bounds_max);

// A deep scene for hierarchical algorithms: every object of `model` placed columns x rows x layers
// times on a grid (x across, y up, layers receding from the default camera along -z). The mesh is
// stored once; the result has one hsr_instance per placement. `gap` is the space between
// neighbours as a fraction of the model's largest extent; each placement is turned about the
// vertical axis by a pseudo-random angle in [-yaw_jitter_degrees, +yaw_jitter_degrees] (fixed seed,
// so the same grid every time).
struct InstanceGrid {
    uint32_t columns = 1, rows = 1, layers = 1;
    float gap = 0.25f;
    float yaw_jitter_degrees = 0.0f;
};
SceneData make_instance_grid(const SceneData& model, const InstanceGrid& grid);

// The same picture without instances: every instance's triangles copied out into world space (what
// a host hands a plugin built against ABI 1.0). A scene without instances is returned as it is.
SceneData flatten_instances(const SceneData& scene);
// The same from a scene view (whose arrays must stay valid meanwhile).
SceneData flatten_instances(const hsr_scene& scene);

// One model file as a scene of one object.
SceneData load_model(const std::filesystem::path& file, const MeshOptions& options = {});

// A light as the user writes it (docs/scene-format.md, "Lights"). Camera-space vectors use x right,
// y up, z toward the viewer, with the eye at the origin; resolve_light() in camera.hpp turns a spec
// into a world-space hsr_light.
struct LightSpec {
    hsr_light_type type = HSR_LIGHT_DIRECTIONAL;
    glm::vec3 vector{0.0f, 0.0f, 1.0f};  // POINT: position; DIRECTIONAL: unit direction toward the light
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    bool camera_space = true;
};

// "point:1,2,3" or "dir:0,0,1", then optionally ",intensity=0.8", ",color=1/0.9/0.8" (or #rrggbb),
// ",space=world" (default camera). Throws hsr::Error naming the text on any mistake.
LightSpec parse_light_spec(std::string_view text);

// A parsed `.scene` file. Optional fields are unset when the file does not mention them; the
// command line overrides what the file says.
struct SceneFile {
    SceneData scene;
    std::optional<glm::vec3> background;
    bool pixel_camera = false;             // `camera pixel`: see make_pixel_camera()
    std::optional<uint32_t> width, height; // `size W H`; with `camera pixel` always set (derived
                                           // from the scene's bounds when `size` is absent)
    std::optional<float> yaw_degrees, pitch_degrees, zoom;  // `camera orbit ...`
    std::optional<bool> orthographic;
    std::vector<LightSpec> lights;
};

// Throws hsr::Error "file:line: message" on any mistake, including problems with the meshes it
// names (relative paths resolve against the scene file's folder).
SceneFile load_scene_file(const std::filesystem::path& file);
bool is_scene_file(const std::filesystem::path& file);  // extension ".scene", any case

}  // namespace hsr
