// glTF 2.0 models (.gltf with its .bin files and data URIs, and .glb) read through tinygltf into
// mesh objects and placements (gltf_reader.cpp).
#pragma once

#include "hsr/camera.hpp"
#include "hsr/mesh_object.hpp"

#include <glm/glm.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hsr {

bool is_gltf_file(const std::filesystem::path& file);

// A camera of the file, placed by the first node that names it.
using GltfCamera = ModelCamera;

// One mesh per glTF mesh that has triangles, placed by the nodes' world transforms.
struct GltfModel : PlacedMeshes {
    std::vector<GltfCamera> cameras;  // every camera a node of the scene places
};

// The default scene of the file (or its first) with the limits (limits.hpp) checked before the work
// they bound. Throws hsr::Error naming the file on any problem with it.
GltfModel read_gltf(const std::filesystem::path& file, const MeshOptions& options = {});

// The same from bytes already in memory (a fuzzing harness's), with no other file readable.
GltfModel read_gltf_bytes(const std::string& bytes, bool binary, const std::string& what,
                          const MeshOptions& options = {});

// Every placement copied into one object in world space (what a .scene file's `mesh` line adds).
MeshObject read_gltf_object(const std::filesystem::path& file);

}  // namespace hsr
