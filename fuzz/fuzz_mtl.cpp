// Fuzz target: the input as a material library input.mtl, named by an OBJ file beside it whose
// faces use the materials a, b and red, through hsr::load_model as `hsr render` reads a model: the
// mtllib path checks, the MTL parse (newmtl, Kd, map_*), the faces' colours, the scene build.
#include "fuzz_support.hpp"

#include "hsr/scene_builder.hpp"

namespace {

constexpr const char* model_obj =
    "mtllib input.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
    "usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\nusemtl red\nf 2 5 3\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::filesystem::path model = hsr::fuzz::write_scratch_file("model.obj", model_obj);
    return hsr::fuzz::run_one([&] {
        hsr::fuzz::write_scratch_file("input.mtl", hsr::fuzz::as_text(data, size));
        for (const std::string& warning : hsr::load_model(model).warnings)
            if (warning.find('\n') != std::string::npos) {
                std::fprintf(stderr, "hsr fuzz: a warning of more than one line:\n%s\n", warning.c_str());
                std::abort();
            }
    });
}
