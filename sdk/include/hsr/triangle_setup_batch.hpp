// hsr triangle setup in batches: setup_whole_triangle (hsr/triangle_setup.hpp) for up to
// kSetupBatch triangles at once, in SIMD, each lane giving the scalar setup bit for bit (the
// argument is at the top of hsr/triangle_setup_batch-inl.h). The kernel is compiled for every
// instruction set Highway targets and the best one the CPU has is chosen at run time.
//
// Header-only, part of hsr::sdk; a plugin that includes it links hsr::sdk_simd (Highway), and since
// this header defines HWY_TARGET_INCLUDE it is the only Highway header of that source file.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hsr/triangle_setup.hpp"

namespace hsr::raster {

// At most this many triangles go into one batch: one AVX-512 vector of doubles, two of AVX2.
inline constexpr size_t kSetupBatch = 8;

}  // namespace hsr::raster

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "hsr/triangle_setup_batch-inl.h"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "hsr/triangle_setup_batch-inl.h"

namespace hsr::raster {
HWY_EXPORT(SetupWholeTriangles);

// setup_whole_triangle for the triangles whose corners are corners[n][0..2], n < count <=
// kSetupBatch, into out[n]: each a triangle that triangle_pixel_bounds accepts (SetupResult::kOk),
// as a sort-middle rasterizer's bins hold them.
inline void setup_whole_triangles(const WindowVertex* const (*corners)[3], size_t count, uint32_t width,
                                  uint32_t height, TriangleSetup* out) {
    if (count == 0) return;
    HWY_DYNAMIC_DISPATCH(SetupWholeTriangles)(corners, count, width, height, out);
}

}  // namespace hsr::raster
