// Planar polygons cut into triangles by ear clipping (polygon_triangulation.cpp).
#pragma once

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
// intersecting itself, may be concave. Throws hsr::Error starting with `what` otherwise.
PolygonTriangles triangulate_polygon(std::span<const glm::vec3> vertices, const std::string& what);

}  // namespace hsr
