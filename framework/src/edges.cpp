#include "hsr/edges.hpp"

#include "hsr/error.hpp"
#include "hsr/surface.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

namespace hsr {
namespace {

glm::dvec3 position(const hsr_scene& scene, uint32_t v) {
    return {scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]};
}

// Unnormalised normal of triangle t from its positions (front: counter-clockwise corners).
glm::dvec3 face_normal(const hsr_scene& scene, uint32_t t) {
    const glm::dvec3 a = position(scene, scene.indices[3 * t]);
    const glm::dvec3 b = position(scene, scene.indices[3 * t + 1]);
    const glm::dvec3 c = position(scene, scene.indices[3 * t + 2]);
    return glm::cross(b - a, c - a);
}

}  // namespace

hsr_line_request EdgeList::request(bool want_hidden) const {
    hsr_line_request r{};
    r.struct_size = sizeof r;
    r.edge_count = static_cast<uint32_t>(size());
    r.edge_vertices = vertices.data();
    r.edge_faces = faces.data();
    r.edge_flags = flags.data();
    r.want_hidden = want_hidden ? 1u : 0u;
    return r;
}

std::vector<uint8_t> front_facing_faces(const hsr_scene& scene, const hsr_camera& camera) {
    std::vector<uint8_t> front(scene.triangle_count);
    const glm::dvec3 eye(camera.eye[0], camera.eye[1], camera.eye[2]);
    const glm::dvec3 toward_viewer(-camera.view_direction[0], -camera.view_direction[1], -camera.view_direction[2]);
    const bool perspective = camera.projection_type == HSR_PROJECTION_PERSPECTIVE;
    for (uint32_t t = 0; t < scene.triangle_count; ++t) {
        const glm::dvec3 n = face_normal(scene, t);
        const glm::dvec3 to_eye = perspective ? eye - position(scene, scene.indices[3 * t]) : toward_viewer;
        front[t] = glm::dot(n, to_eye) > 0.0 ? 1 : 0;
    }
    return front;
}

EdgeList classify_edges(const hsr_scene& scene, const hsr_camera& camera, double crease_angle_degrees,
                        EdgeSelection selection) {
    if (scene.struct_size >= offsetof(hsr_scene, instances) + sizeof scene.instances && scene.instance_count > 0)
        throw Error("edges of an instanced scene: copy the instances out first");
    const std::vector<uint8_t> front = front_facing_faces(scene, camera);
    const double cos_crease = std::cos(crease_angle_degrees * 3.14159265358979323846 / 180.0);
    // Faces whose normals differ by less than this are one flat polygon (about 0.06 degrees).
    constexpr double cos_coplanar = 1.0 - 5e-7;
    // On a surface grid (hsr/surface.hpp) the grid lines are edges of the drawing even where the
    // surface is flat; only the cells' diagonals are triangulation.
    const std::optional<SurfaceGrid> grid =
        selection == EdgeSelection::kAll ? find_surface_grid(scene) : std::nullopt;
    const uint32_t grid_columns = grid ? grid->columns : 0;
    auto is_grid_line = [grid_columns](uint32_t a, uint32_t b) {
        const uint32_t lo = std::min(a, b), hi = std::max(a, b);
        return (hi - lo == 1 && hi % grid_columns != 0) || hi - lo == grid_columns;
    };
    EdgeList out;
    out.vertices.reserve(3 * size_t(scene.triangle_count));
    out.faces.reserve(3 * size_t(scene.triangle_count));
    out.flags.reserve(3 * size_t(scene.triangle_count) / 2 + 1);
    for (uint32_t t = 0; t < scene.triangle_count; ++t) {
        for (int i = 0; i < 3; ++i) {
            const int32_t other = scene.edge_neighbors[3 * t + i];
            if (other != HSR_NO_NEIGHBOR && uint32_t(other) < t) continue;  // listed from the other side
            uint32_t flags = 0;
            if (other == HSR_NO_NEIGHBOR) {
                flags |= HSR_EDGE_BOUNDARY;
                if (!front[t]) flags |= HSR_EDGE_BACK;
            } else {
                const uint32_t u = uint32_t(other);
                const glm::dvec3 a = face_normal(scene, t), b = face_normal(scene, u);
                const double lengths = glm::length(a) * glm::length(b);
                const double cosine = lengths > 0.0 ? glm::dot(a, b) / lengths : 1.0;
                if (cosine < cos_crease) flags |= HSR_EDGE_CREASE;
                if (front[t] != front[u]) flags |= HSR_EDGE_SILHOUETTE;
                if (!front[t] && !front[u]) flags |= HSR_EDGE_BACK;
                const bool coplanar = cosine > cos_coplanar &&
                                      !(grid && is_grid_line(scene.indices[3 * t + i], scene.indices[3 * t + (i + 1) % 3]));
                if (selection == EdgeSelection::kAll ? coplanar
                                                     : (flags & (HSR_EDGE_CREASE | HSR_EDGE_SILHOUETTE)) == 0)
                    continue;
            }
            out.vertices.push_back(scene.indices[3 * t + i]);
            out.vertices.push_back(scene.indices[3 * t + (i + 1) % 3]);
            out.faces.push_back(t);
            out.faces.push_back(other == HSR_NO_NEIGHBOR ? HSR_NO_FACE : uint32_t(other));
            out.flags.push_back(flags);
        }
    }
    return out;
}

}  // namespace hsr
