// Model files and triangle lists as mesh objects for SceneBuilder, through OpenMesh (model_reader.cpp).
#pragma once

#include "hsr/mesh_object.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace hsr {

// One model file (OBJ, OFF, PLY, STL) as an object in its own coordinates, options not yet set.
// Throws hsr::Error naming the file on any problem with it.
MeshObject read_model_object(const std::filesystem::path& file);
// The same, except that an OBJ file's groups become objects of their own: its o groups, or its g
// groups when it has no o line (faces before the first group make one more). Each object is named
// after its group (options.name), so that algorithms that need convex bodies see one each.
std::vector<MeshObject> read_model_objects(const std::filesystem::path& file);

}  // namespace hsr
