// Fuzz target: the input as a PNG file through hsr::make_heightmap_surface with the default options,
// as `hsr render --heightmap FILE.png` reads it: the size check from the header, libpng's decoding
// (any colour type, bit depth, interlacing) and the grid build.
#include "fuzz_support.hpp"

#include "hsr/surface.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return hsr::fuzz::run_one([&] {
        hsr::make_heightmap_surface(hsr::fuzz::write_scratch_file("input.png", hsr::fuzz::as_text(data, size)));
    });
}
