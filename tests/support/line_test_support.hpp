// What the hidden-line tests share (on top of surface_test_support.hpp's plugin loader, model cache
// and cameras): models with instances copied out, running a hidden-line plugin
// from the build's plugin folder, and its segments in the form line_reference.hpp compares.
#pragma once

#include "hsr/camera.hpp"
#include "hsr/lines.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "line_reference.hpp"
#include "surface_test_support.hpp"

#include <deque>
#include <string>
#include <utility>
#include <vector>

namespace line_tests {

using surface_tests::plugin;

// models/<file>: a mesh, or a .scene file with its instances copied out; loaded once.
inline const hsr::SceneData& model(const std::string& file) {
    static std::deque<std::pair<std::string, hsr::SceneData>> cache;  // references stay valid as it grows
    for (const auto& [name, data] : cache)
        if (name == file) return data;
    const hsr::SceneData& loaded = surface_tests::model(file);
    cache.emplace_back(file, loaded.instances.empty() ? loaded : hsr::flatten_instances(loaded));
    return cache.back().second;
}

using surface_tests::orbit;

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
