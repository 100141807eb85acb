// The colours the facecolor lighting model gives a scene's faces, read through the real ABI: one
// fragment of each face (of instance `instance` when the scene has instances), in face order. With
// by=given they are the scene's own face colours, as the readers set them.
#pragma once

#include "hsr/abi.h"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace test_colors {

inline const hsr::Plugin& facecolor() {
    static const hsr::PluginRegistry registry = [] {
        hsr::PluginRegistry r;
        r.scan_directory(HSR_PLUGIN_DIR);
        return r;
    }();
    return registry.find(HSR_KIND_LIGHTING_MODEL, "facecolor");
}

// by: facecolor's `by` setting, empty for its default.
inline std::vector<glm::vec3> face_colors(const hsr::SceneData& scene, const std::string& by = "given",
                                          uint32_t instance = 0) {
    hsr::LightingModel model(facecolor(), by.empty() ? std::vector<hsr::Setting>{} : std::vector<hsr::Setting>{{"by", by}});
    const hsr_scene view = scene.view();
    hsr_shading_context context{};
    context.struct_size = sizeof context;
    model.prepare(view, context);
    const uint32_t n = scene.triangle_count();
    std::vector<uint32_t> face(n), pixel(n), instances(n, instance);
    std::vector<float> bary(2 * n, 0.25f), position(3 * n, 0.0f), normal(3 * n, 0.0f), color(3 * n, -1.0f);
    for (uint32_t t = 0; t < n; ++t) face[t] = pixel[t] = t;
    hsr_fragment_batch batch{};
    batch.struct_size = sizeof batch;
    batch.count = n;
    batch.face = face.data();
    batch.bary = bary.data();
    batch.position = position.data();
    batch.normal = normal.data();
    batch.pixel = pixel.data();
    batch.color = color.data();
    batch.instance = scene.instances.empty() ? nullptr : instances.data();
    model.shade(batch);
    std::vector<glm::vec3> out;
    for (uint32_t t = 0; t < n; ++t) out.emplace_back(color[3 * t], color[3 * t + 1], color[3 * t + 2]);
    return out;
}

}  // namespace test_colors
