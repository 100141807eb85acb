// Random triangles, the textbook's exercise generator for hidden-surface algorithms: planar
// triangles of mixed sizes and orientations, each in its own colour, scattered through a cube so
// that they overlap and some interpenetrate. The same count and seed give the same scene on every
// platform: the numbers come from std::mt19937_64 (whose output the C++ standard fixes) mapped to
// floats here, not through the implementation-defined std::uniform_real_distribution.
#pragma once

#include "hsr/scene.hpp"

#include <cstdint>

namespace hsr {

// The cube the triangles lie in: every vertex within [-extent, extent] on each axis.
constexpr float random_triangles_extent = 1.0f;

// `count` triangles (at least 1, at most the stored-triangles limit: hsr::Error otherwise) as one
// object named "random triangles"; face i has its own colour in face_colors.
SceneData make_random_triangles(uint64_t count, uint64_t seed);

}  // namespace hsr
