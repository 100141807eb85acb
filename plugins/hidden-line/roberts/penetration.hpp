// Penetration (junction) lines: where two of Roberts' convex bodies intersect, the curve in which
// their surfaces meet. For convex bodies A and B it is made of straight pieces, each lying on one
// face of A and one face of B: the line where the two face planes meet, cut down to the part inside
// both faces (inside every other plane of A and every other plane of B). These lines are not edges
// of the scene; they are drawn like edges and tested for visibility against every body.
#pragma once

#include "bodies.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace roberts {

struct PenetrationLine {
    glm::dvec3 start, end;      // world space
    uint32_t body_a, body_b;    // indices into BodySet::bodies, body_a < body_b
    uint32_t plane_a, plane_b;  // the face of each that the line lies on (indices into BodySet::planes)
};

struct PenetrationStats {
    uint64_t body_pairs_overlapping = 0;  // pairs whose bounding boxes overlap (the others cannot meet)
    uint64_t plane_pairs_tested = 0;
};

// Every penetration line of every pair of bodies, appended to `lines` (cleared first). A line
// where two surfaces only touch (one lies in a face of the other) is not a penetration line.
void find_penetration_lines(const BodySet& bodies, std::vector<PenetrationLine>& lines, PenetrationStats& stats);

}  // namespace roberts
