// Polygons cut into triangles by ear clipping (polygon_triangulation.cpp): the planar polygons of a
// .scene file, and the faces of model files.
#pragma once

#include "hsr/language.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace hsr {

struct PolygonTriangles {
    std::vector<glm::vec3> positions;  // the polygon's distinct corners
    std::vector<uint32_t> indices;     // 3 per triangle, counter-clockwise like the polygon
};

// `vertices` as SceneBuilder::add_polygon takes them: at least 3 distinct, finite, planar, not
// intersecting itself, may be concave. Throws hsr::Error starting with `what` otherwise, in `language`.
PolygonTriangles triangulate_polygon(std::span<const glm::vec3> vertices, const std::string& what,
                                     Language language = Language::english);

// How a model file's face was cut into triangles.
enum class FaceCut {
    polygon,          // the face's own area: a fan if it is convex, ear clipping otherwise
    fan_no_area,      // its corners are collinear or coincide: a fan, whose triangles have no area
    fan_intersecting  // its outline crosses or touches itself: a fan from its first corner
};

// Cuts a face of 4 or more corners (positions in the file's order, not necessarily planar) into
// triangles of corner numbers (0 .. corners.size() - 1), 3 per triangle, appended to `triangles`
// in the face's orientation. A convex face becomes the fan from its first corner; any other is ear
// clipped in the plane of its Newell normal, the corners projected along that normal.
FaceCut triangulate_face(std::span<const glm::vec3> corners, std::vector<uint32_t>& triangles);

}  // namespace hsr
