// Model files and triangle lists as mesh objects for SceneBuilder, through OpenMesh (model_reader.cpp).
#pragma once

#include "hsr/mesh_object.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace hsr {

// One model file (OBJ, OFF, PLY, STL) as an object in its own coordinates, options not yet set.
// Throws hsr::Error naming the file on any problem with it.
MeshObject read_model_object(const std::filesystem::path& file);

}  // namespace hsr
