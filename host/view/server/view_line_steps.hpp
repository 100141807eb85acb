// What hsr view draws for one step of a hidden-line plugin besides the plugin's own lines: the edge
// under test, the face the step names as the flat polygon a person sees (its coplanar triangles
// joined, never their diagonals), and the numbers of the drawing's edges and faces with the places
// to write them (view_frames.cpp puts them into the step as "figure").
#pragma once

#include "hsr/abi.h"
#include "hsr/lines.hpp"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace hsr::host {

// Per triangle: the lowest triangle of its flat face, the polygon of the triangles of one object
// joined across edges whose two triangles are coplanar (unit normals within kCoplanarCosine). The
// faces of a step's text and of the labels are numbered so.
inline constexpr double kCoplanarCosine = 0.999999;
std::vector<uint32_t> polygon_faces(const hsr_scene& scene);

// The closed outlines of the polygon `face` belongs to, in world space (a ring of corners each,
// counter-clockwise seen from its front; a polygon with holes has several).
std::vector<std::vector<glm::vec3>> polygon_loops(const hsr_scene& scene, const std::vector<uint32_t>& polygon_of,
                                                  uint32_t face);

// The step's figure:
//   {"edge": {"index", "lines": [[x0, y0, x1, y1]], "label": [x, y]} or null,
//    "face": {"index", "object", "loops": [[[x, y], ...], ...], "label": [x, y]} or null,
//    "labels": {"edges": [[index, x, y], ...], "faces": [[index, x, y], ...]} or null when too many,
//    "background": [r, g, b]}
// in window coordinates, cut at the near plane. background: the picture's, 0-255.
nlohmann::json line_step_figure(const hsr_scene& scene, const hsr_camera& camera, const hsr::LineDrawing& drawing,
                                const hsr::TraceEventRecord& event, glm::vec3 background);

}  // namespace hsr::host
