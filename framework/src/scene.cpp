// SceneData's arrays seen through the ABI's hsr_scene.
#include "hsr/scene.hpp"

namespace hsr {

hsr_scene SceneData::view() const {
    hsr_scene s{};
    s.struct_size = sizeof(hsr_scene);
    s.vertex_count = vertex_count();
    s.triangle_count = triangle_count();
    s.object_count = static_cast<uint32_t>(object_names.size());
    s.positions = positions.data();
    s.indices = indices.data();
    s.face_normals = face_normals.data();
    s.corner_normals = corner_normals.data();
    s.face_colors = face_colors.data();
    s.edge_neighbors = edge_neighbors.data();
    s.face_object = face_object.data();
    for (int i = 0; i < 3; ++i) {
        s.bounds_min[i] = bounds_min[i];
        s.bounds_max[i] = bounds_max[i];
    }
    s.instance_count = static_cast<uint32_t>(instances.size());
    s.instances = instances.empty() ? nullptr : instances.data();
    s.object_opacity = object_opacity.size() == object_names.size() && !object_opacity.empty() ? object_opacity.data()
                                                                                               : nullptr;
    return s;
}

}  // namespace hsr
