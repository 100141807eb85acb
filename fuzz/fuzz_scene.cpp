// Fuzz target: the input as a `.scene` file through hsr::load_scene_file, as `hsr render` reads one:
// statements, lights, camera settings, polygons, `repeat` (instancing) and the limits. The file
// sits in the scratch folder next to two small meshes, cube.obj and tetrahedron.off, so that
// `mesh` lines naming them (as the seed corpus does) load a real model without depending on any
// file outside the target.
#include "fuzz_support.hpp"

#include "hsr/scene_file.hpp"

namespace {

constexpr const char* cube_obj =
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "f 5 6 7 8\nf 1 4 3 2\nf 2 3 7 6\nf 1 5 8 4\nf 4 8 7 3\nf 1 2 6 5\n";
constexpr const char* tetrahedron_off =
    "OFF\n4 4 0\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const bool meshes_written = [] {
        hsr::fuzz::write_scratch_file("cube.obj", cube_obj);
        hsr::fuzz::write_scratch_file("tetrahedron.off", tetrahedron_off);
        return true;
    }();
    (void)meshes_written;
    return hsr::fuzz::run_one(
        [&] { hsr::load_scene_file(hsr::fuzz::write_scratch_file("input.scene", hsr::fuzz::as_text(data, size))); });
}
