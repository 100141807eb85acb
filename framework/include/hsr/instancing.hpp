// Instanced scenes (ABI 1.1): one instance made from its placement, grids of one model for deep
// scenes, and instances copied out into plain triangles.
#pragma once

#include "hsr/abi.h"
#include "hsr/scene.hpp"

#include <glm/glm.hpp>

#include <cstdint>

namespace hsr {

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
// so the same grid every time). Throws hsr::Error, before allocating, when the copies or the
// triangles they draw are over the limits `instances` and `triangles` (limits.hpp).
struct InstanceGrid {
    uint32_t columns = 1, rows = 1, layers = 1;
    float gap = 0.25f;
    float yaw_jitter_degrees = 0.0f;
};
SceneData make_instance_grid(const SceneData& model, const InstanceGrid& grid);

// The same picture without instances: every instance's triangles copied out into world space (what
// a host hands a plugin built against ABI 1.0, and a hidden-line plugin). A scene without instances is
// returned as it is. Throws hsr::Error, before allocating, when the copy is over the limit
// `stored-triangles` (limits.hpp).
SceneData flatten_instances(const SceneData& scene);
// The same from a scene view (whose arrays must stay valid meanwhile).
SceneData flatten_instances(const hsr_scene& scene);

}  // namespace hsr
