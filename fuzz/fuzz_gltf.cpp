// Fuzz target: the input as a glTF model through hsr::load_model, as `hsr render` reads one: a GLB
// when it starts with the GLB magic "glTF" (input.glb), else a .gltf (input.gltf, whose buffers
// may only name files of the fuzzer's scratch folder); then tinygltf, the checks of the accessors,
// buffer views and nodes, the placements and the scene build.
#include "fuzz_support.hpp"

#include "hsr/scene_builder.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view bytes = hsr::fuzz::as_text(data, size);
    const char* name = bytes.substr(0, 4) == "glTF" ? "input.glb" : "input.gltf";
    return hsr::fuzz::run_one([&] { hsr::load_model(hsr::fuzz::write_scratch_file(name, bytes)); });
}
