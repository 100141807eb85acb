// Instanced scenes (ABI 1.1): grids of one model for deep-scene experiments, and the copy-out that
// turns instances back into plain triangles for plugins built against ABI 1.0.
#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
#include "hsr/limits.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace hsr {
namespace {

void store_matrix(const glm::mat4& m, float (&out)[16]) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) out[4 * c + r] = m[c][r];
}

glm::mat4 load_matrix(const float (&m)[16]) {
    glm::mat4 r;
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) r[c][row] = m[4 * c + row];
    return r;
}

glm::mat3 load_rotation(const float (&m)[9]) {
    glm::mat3 r;
    for (int c = 0; c < 3; ++c)
        for (int row = 0; row < 3; ++row) r[c][row] = m[3 * c + row];
    return r;
}

}  // namespace

hsr_instance make_instance(uint32_t first_triangle, uint32_t triangle_count, uint32_t first_vertex,
                           uint32_t vertex_count, const glm::mat3& rotation, float scale, glm::vec3 translation,
                           glm::vec3 object_bounds_min, glm::vec3 object_bounds_max) {
    if (!(scale > 0.0f) || !std::isfinite(scale)) throw Error("instance scale {} is not a positive number", scale);
    hsr_instance instance{};
    instance.struct_size = sizeof instance;
    instance.first_triangle = first_triangle;
    instance.triangle_count = triangle_count;
    instance.first_vertex = first_vertex;
    instance.vertex_count = vertex_count;
    glm::mat4 transform(rotation * scale);
    transform[3] = glm::vec4(translation, 1.0f);
    store_matrix(transform, instance.transform);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) instance.rotation[3 * c + r] = rotation[c][r];
    instance.scale = scale;
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p((corner & 1) ? object_bounds_max.x : object_bounds_min.x,
                          (corner & 2) ? object_bounds_max.y : object_bounds_min.y,
                          (corner & 4) ? object_bounds_max.z : object_bounds_min.z);
        const glm::vec3 w = glm::vec3(transform * glm::vec4(p, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
    for (int i = 0; i < 3; ++i) {
        instance.bounds_min[i] = lo[i];
        instance.bounds_max[i] = hi[i];
    }
    return instance;
}

SceneData make_instance_grid(const SceneData& model, const InstanceGrid& grid) {
    if (!model.instances.empty()) throw Error("instance grid: the model is already instanced");
    if (model.triangle_count() == 0) throw Error("instance grid: the model has no triangles");
    if (grid.columns == 0 || grid.rows == 0 || grid.layers == 0)
        throw Error("instance grid: columns, rows and layers must be at least 1");
    const uint64_t count = uint64_t(grid.columns) * grid.rows * grid.layers;
    const std::string copies = fmt::format("{}x{}x{} copies of {} triangles", grid.columns, grid.rows, grid.layers,
                                           model.triangle_count());
    check_limit(&Limits::instances, count, copies);
    if (count > std::numeric_limits<uint32_t>::max())
        throw Error("{}: {} instances, more than a scene can hold", copies, count);
    check_limit(&Limits::triangles, count * model.triangle_count(), copies);  // at most 2^32 * 2^32
    if (!(grid.gap >= 0.0f) || !std::isfinite(grid.gap)) throw Error("instance grid: gap must be 0 or more");

    SceneData scene = model;
    const glm::vec3 extent = model.bounds_max - model.bounds_min;
    const glm::vec3 centre = 0.5f * (model.bounds_max + model.bounds_min);
    const float size = std::max({extent.x, extent.y, extent.z});
    const glm::vec3 step = extent + glm::vec3(grid.gap * size);
    std::mt19937 random(12345);
    std::uniform_real_distribution<float> jitter(-grid.yaw_jitter_degrees, grid.yaw_jitter_degrees);

    scene.instances.clear();
    scene.instances.reserve(count);
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (uint32_t layer = 0; layer < grid.layers; ++layer) {
        for (uint32_t row = 0; row < grid.rows; ++row) {
            for (uint32_t column = 0; column < grid.columns; ++column) {
                const glm::vec3 place((column - 0.5f * (grid.columns - 1)) * step.x,
                                      (row - 0.5f * (grid.rows - 1)) * step.y, -float(layer) * step.z);
                const float yaw = grid.yaw_jitter_degrees > 0.0f ? glm::radians(jitter(random)) : 0.0f;
                const glm::mat3 rotation(glm::rotate(glm::mat4(1.0f), yaw, glm::vec3(0, 1, 0)));
                // Turn about the model's centre, then move that centre to its grid place.
                const glm::vec3 translation = place - rotation * centre;
                const hsr_instance instance =
                    make_instance(0, model.triangle_count(), 0, model.vertex_count(), rotation, 1.0f, translation,
                                  model.bounds_min, model.bounds_max);
                for (int i = 0; i < 3; ++i) {
                    lo[i] = std::min(lo[i], instance.bounds_min[i]);
                    hi[i] = std::max(hi[i], instance.bounds_max[i]);
                }
                scene.instances.push_back(instance);
            }
        }
    }
    scene.bounds_min = lo;
    scene.bounds_max = hi;
    return scene;
}

SceneData flatten_instances(const SceneData& scene) {
    if (scene.instances.empty()) return scene;
    SceneData flat = flatten_instances(scene.view());
    flat.object_names = scene.object_names;
    flat.warnings = scene.warnings;
    return flat;
}

SceneData flatten_instances(const hsr_scene& scene) {
    SceneData flat;
    flat.object_names.resize(scene.object_count);
    if (scene.struct_size >= offsetof(hsr_scene, object_opacity) + sizeof scene.object_opacity &&
        scene.object_opacity != nullptr)
        flat.object_opacity.assign(scene.object_opacity, scene.object_opacity + scene.object_count);
    for (int i = 0; i < 3; ++i) {
        flat.bounds_min[i] = scene.bounds_min[i];
        flat.bounds_max[i] = scene.bounds_max[i];
    }
    std::vector<hsr_instance> instances;
    for (uint32_t k = 0; k < scene.instance_count; ++k)
        instances.push_back(*HSR_ELEMENT(hsr_instance, scene.instances, k));
    if (instances.empty())
        instances.push_back(make_instance(0, scene.triangle_count, 0, scene.vertex_count, glm::mat3(1.0f), 1.0f,
                                          glm::vec3(0.0f), flat.bounds_min, flat.bounds_max));
    uint64_t triangles = 0, vertices = 0;
    for (const hsr_instance& i : instances) {
        triangles += i.triangle_count;
        vertices += i.vertex_count;
    }
    const std::string what = fmt::format("{} instances copied out into plain triangles", instances.size());
    check_limit(&Limits::stored_triangles, triangles, what);
    // Every vertex an instance uses belongs to one of its triangles: a scene that says otherwise is
    // bounded by the same limit.
    if (vertices > 3 * limits().stored_triangles)
        throw LimitError("{}: {} vertices, over 3 per triangle of the limit of {} stored triangles (raise it with --limit "
                    "stored-triangles=N)", what, vertices, limits().stored_triangles);
    if (triangles > std::numeric_limits<int32_t>::max() || vertices > std::numeric_limits<uint32_t>::max())
        throw Error("{}: {} triangles, too many for a plugin built against ABI 1.0", what, triangles);
    flat.positions.reserve(3 * vertices);
    flat.indices.reserve(3 * triangles);
    flat.face_normals.reserve(3 * triangles);
    flat.corner_normals.reserve(9 * triangles);
    flat.face_colors.reserve(3 * triangles);
    flat.edge_neighbors.reserve(3 * triangles);
    flat.face_object.reserve(triangles);

    for (const hsr_instance& instance : instances) {
        const glm::mat4 transform = load_matrix(instance.transform);
        const glm::mat3 rotation = load_rotation(instance.rotation);
        const uint32_t vertex_base = flat.vertex_count();
        const uint32_t triangle_base = flat.triangle_count();
        for (uint32_t v = instance.first_vertex; v < instance.first_vertex + instance.vertex_count; ++v) {
            const glm::vec3 p(scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]);
            const glm::vec3 w = glm::vec3(transform * glm::vec4(p, 1.0f));
            flat.positions.insert(flat.positions.end(), {w.x, w.y, w.z});
        }
        auto rotate = [&](const float* from, size_t at, std::vector<float>& to) {
            const glm::vec3 n = rotation * glm::vec3(from[at], from[at + 1], from[at + 2]);
            to.insert(to.end(), {n.x, n.y, n.z});
        };
        const uint32_t end = instance.first_triangle + instance.triangle_count;
        for (uint32_t t = instance.first_triangle; t < end; ++t) {
            for (int k = 0; k < 3; ++k) {
                flat.indices.push_back(scene.indices[3 * t + k] - instance.first_vertex + vertex_base);
                const int32_t n = scene.edge_neighbors[3 * t + k];
                const bool inside = n >= 0 && uint32_t(n) >= instance.first_triangle && uint32_t(n) < end;
                flat.edge_neighbors.push_back(inside ? int32_t(uint32_t(n) - instance.first_triangle + triangle_base)
                                                     : HSR_NO_NEIGHBOR);
                rotate(scene.corner_normals, 9 * size_t(t) + 3 * k, flat.corner_normals);
            }
            rotate(scene.face_normals, 3 * size_t(t), flat.face_normals);
            flat.face_colors.insert(flat.face_colors.end(), scene.face_colors + 3 * size_t(t),
                                    scene.face_colors + 3 * size_t(t) + 3);
            flat.face_object.push_back(scene.face_object[t]);
        }
    }
    return flat;
}

}  // namespace hsr
