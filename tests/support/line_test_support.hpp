// What the hidden-line tests share: models loaded once, orbit cameras, running a hidden-line plugin
// from the build's plugin folder, and its segments in the form line_reference.hpp compares.
#pragma once

#include "hsr/camera.hpp"
#include "hsr/lines.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "line_reference.hpp"

#include <string>
#include <utility>
#include <vector>

namespace line_tests {

inline const hsr::Plugin& plugin(const std::string& name, const char* dir = HSR_PLUGIN_DIR,
                                 const char* prefix = "hsr-") {
    static std::vector<std::vector<hsr::Plugin>> loaded;
    for (const auto& plugins : loaded)
        if (plugins.at(0).descriptor.name == name) return plugins.at(0);
    loaded.push_back(hsr::load_plugin_library(std::string(dir) + "/" + prefix + name + ".so"));
    return loaded.back().at(0);
}

// models/<file>: a mesh, or a .scene file (its instances copied out).
inline const hsr::SceneData& model(const std::string& file) {
    static std::vector<std::pair<std::string, hsr::SceneData>> cache;
    for (const auto& [name, data] : cache)
        if (name == file) return data;
    const std::string path = std::string(HSR_MODELS_DIR) + "/" + file;
    hsr::SceneData data = file.ends_with(".scene") ? hsr::load_scene_file(path).scene : hsr::load_model(path);
    if (!data.instances.empty()) data = hsr::flatten_instances(data);
    cache.emplace_back(file, std::move(data));
    return cache.back().second;
}

inline hsr_camera orbit(const hsr::SceneData& scene, float yaw, float pitch, float zoom, bool ortho,
                        uint32_t size) {
    hsr::CameraSettings s;
    s.yaw_degrees = yaw;
    s.pitch_degrees = pitch;
    s.zoom = zoom;
    s.orthographic = ortho;
    s.width = s.height = size;
    return hsr::make_orbit_camera(scene.bounds_min, scene.bounds_max, s);
}

inline hsr::LineDrawing draw(const std::string& plugin_name, const hsr_scene& scene, const hsr_camera& camera,
                             hsr::LineSettings settings = {}, const std::vector<hsr::Setting>& params = {}) {
    hsr::HiddenLineRemover remover(plugin(plugin_name), params);
    return hsr::render_lines(scene, camera, remover, settings);
}

inline std::vector<line_reference::Segment> reference_segments(const hsr::LineDrawing& d) {
    std::vector<line_reference::Segment> out;
    out.reserve(d.segments.size());
    for (const hsr::LineSegment& s : d.segments)
        out.push_back({glm::dvec2(s.a), glm::dvec2(s.b), s.edge, s.flags, s.qi});
    return out;
}

}  // namespace line_tests
