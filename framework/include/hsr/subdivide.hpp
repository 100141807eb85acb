// Subdivision surfaces for larger test meshes: a model made finer by Loop subdivision (Loop,
// "Smooth Subdivision Surfaces Based on Triangles", MSc thesis, University of Utah, 1987), done by
// OpenMesh's uniform Loop subdivider. Each level splits every triangle into four and smooths the
// vertices, so the shape stays the same while the face count grows 4x per level: `hsr bench` uses
// it for the "bunny-loop" model (the 69,666-face Stanford bunny made into 278,664 faces).
#pragma once

#include "hsr/scene_builder.hpp"

#include <filesystem>

namespace hsr {

// Largest number of Loop levels accepted (each multiplies the face count by 4).
constexpr int max_loop_levels = 6;

// Reads `file` as load_model() does (same formats, same checks), applies `loop_levels` levels of
// Loop subdivision to each object, then builds the scene with `options` (transform, colour, crease
// angle, name) exactly as load_model() would. Level 0 gives load_model(file, options). Throws
// hsr::Error for a bad file or a level outside [0, max_loop_levels].
SceneData load_model_subdivided(const std::filesystem::path& file, int loop_levels, const MeshOptions& options = {});

// The same for a scene already built (without instances): every object subdivided, in the same
// order, each with its own colour and name; `crease_angle_degrees` for the new corner normals.
SceneData loop_subdivide(const SceneData& scene, int loop_levels, float crease_angle_degrees = 40.0f);

}  // namespace hsr
