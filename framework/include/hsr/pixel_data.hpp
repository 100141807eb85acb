// What a frame's visibility buffer says about each pixel, in units a program outside hsr can use:
// the distance along the view axis, which face of which object and instance, and the face's normal
// in camera space. Rows top to bottom, as in the frame (frame.hpp); the writers are data_files.hpp.
#pragma once

#include "hsr/abi.h"
#include "hsr/frame.hpp"

#include <cstdint>
#include <vector>

namespace hsr {

// Per pixel: the camera-space distance from the eye to the visible surface along the view axis
// (view-space -z), in the scene's units; +infinity where no face covers the pixel centre. Recovered
// from the window depth the plugin wrote (abi.h) through the inverse of the camera's projection.
std::vector<float> camera_depth(const Frame& frame, const hsr_camera& camera);

// Per pixel, 3 values: the object (hsr_scene.face_object), the triangle's index among that
// object's triangles, and the instance (0 when the scene has none); -1, -1, -1 where no face covers
// the pixel. Throws hsr::Error when the frame's faces are not those of the scene (a plugin older
// than instances given a copy of them).
std::vector<int32_t> pixel_ids(const Frame& frame, const hsr_scene& scene);

// Per pixel, 3 values: the unit normal of the visible face (its front side, as the scene stores it,
// turned by its instance) in camera space: x right, y up, z toward the eye. 0, 0, 0 where no face
// covers the pixel. Throws as pixel_ids does.
std::vector<float> camera_normals(const Frame& frame, const hsr_scene& scene, const hsr_camera& camera);

}  // namespace hsr
