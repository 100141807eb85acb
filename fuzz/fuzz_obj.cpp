// Fuzz target: the input as a model file input.obj through hsr::load_model, as `hsr render` reads a
// model: OBJ: the checks of check_obj_text, which parse it, the mesh built with its polygons
// cut into triangles, then the scene build (normals, adjacency, bounds).
#include "fuzz_support.hpp"

#include "hsr/scene_builder.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return hsr::fuzz::run_one(
        [&] { hsr::load_model(hsr::fuzz::write_scratch_file("input.obj", hsr::fuzz::as_text(data, size))); });
}
