// Scenes made from numpy arrays (meshes.cpp).
#pragma once

#include "results.hpp"

#include <pybind11/pybind11.h>

#include <memory>

namespace hsr::python {

// A scene of the meshes the Python side describes, one dict each: "vertices" (N, 3); "triangles"
// (M, 3) or "corners" and "face_ends" (polygons, as hsr.Scene.from_arrays flattens them);
// optionally "face_colors" (one per face), "color", "transforms" (K, 4, 4), "name",
// "crease_angle" and "opacity". Mistakes are UsageErrors, a mesh hsr cannot use an hsr::Error.
std::shared_ptr<Scene> scene_from_meshes(const pybind11::list& meshes);

}  // namespace hsr::python
