// What the frame pipeline and the fragment-list compositor share (framework-internal): the arrays
// of one shading batch, the instances' transforms, the assembly of one fragment (world position
// and interpolated shading normal from a face and barycentrics) for a lighting plugin, and the
// bands of rows that shading threads take in turn.
#pragma once

#include "hsr/abi.h"

#include <glm/glm.hpp>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hsr {

// Fragment arrays for one band of rows, reused across bands. face, pixel and instance hold the
// band's covered pixels; the others hold one chunk of them at a time (a chunk's fragments are
// assembled, shaded and turned into bytes while those arrays are still in the L1 cache).
struct FragmentArrays {
    std::vector<uint32_t> face, pixel, instance;
    std::vector<float> bary, position, normal, color;

    // Room for `pixels` covered pixels and a chunk of `chunk` fragments, and a vector's worth more
    // of each (SIMD code stores whole vectors).
    void reserve(size_t pixels, size_t chunk) {
        pixels += kSimdSlack;
        chunk += kSimdSlack;
        face.resize(pixels);
        pixel.resize(pixels);
        instance.resize(pixels);
        bary.resize(2 * chunk);
        position.resize(3 * chunk);
        normal.resize(3 * chunk);
        color.resize(3 * chunk);
    }
    void reserve(size_t n) { reserve(n, n); }
    static constexpr size_t kSimdSlack = 64;
};

// Where each instance puts its triangles: world = transform * p, normals turn by rotation.
struct Placements {
    std::vector<glm::mat4> transform;
    std::vector<glm::mat3> rotation;

    Placements() = default;  // none: a scene without instances

    explicit Placements(const hsr_scene& scene) {
        for (uint32_t k = 0; k < scene.instance_count; ++k) {
            const hsr_instance& i = *HSR_ELEMENT(hsr_instance, scene.instances, k);
            glm::mat4 m;
            glm::mat3 r;
            for (int c = 0; c < 4; ++c)
                for (int row = 0; row < 4; ++row) m[c][row] = i.transform[4 * c + row];
            for (int c = 0; c < 3; ++c)
                for (int row = 0; row < 3; ++row) r[c][row] = i.rotation[3 * c + row];
            transform.push_back(m);
            rotation.push_back(r);
        }
    }
};

inline constexpr uint32_t kNotInstanced = 0xFFFFFFFFu;

// The world position and interpolated shading normal of triangle t (of `instance`, or
// kNotInstanced) at barycentrics (b1, b2).
inline void fragment_geometry(const hsr_scene& scene, const Placements& placements, uint32_t t, uint32_t instance,
                              float b1, float b2, glm::vec3& position, glm::vec3& normal) {
    const float b0 = 1.0f - b1 - b2;
    const uint32_t* tri = scene.indices + 3 * t;
    const float* p0 = scene.positions + 3 * tri[0];
    const float* p1 = scene.positions + 3 * tri[1];
    const float* p2 = scene.positions + 3 * tri[2];
    const float* n0 = scene.corner_normals + 9 * t;
    float nx = b0 * n0[0] + b1 * n0[3] + b2 * n0[6];
    float ny = b0 * n0[1] + b1 * n0[4] + b2 * n0[7];
    float nz = b0 * n0[2] + b1 * n0[5] + b2 * n0[8];
    const float len = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (len > 0.0f) {
        nx /= len, ny /= len, nz /= len;
    } else {
        const float* fn = scene.face_normals + 3 * t;
        nx = fn[0], ny = fn[1], nz = fn[2];
    }
    position = glm::vec3(b0 * p0[0] + b1 * p1[0] + b2 * p2[0], b0 * p0[1] + b1 * p1[1] + b2 * p2[1],
                         b0 * p0[2] + b1 * p1[2] + b2 * p2[2]);
    normal = glm::vec3(nx, ny, nz);
    if (instance != kNotInstanced) {
        position = glm::vec3(placements.transform[instance] * glm::vec4(position, 1.0f));
        normal = placements.rotation[instance] * normal;
    }
}

// Fragment n of `out`: triangle t (of `instance`, or kNotInstanced) at barycentrics (b1, b2), for
// `pixel`.
inline void assemble_fragment(const hsr_scene& scene, const Placements& placements, uint32_t t, uint32_t instance,
                              float b1, float b2, uint32_t pixel, FragmentArrays& out, uint32_t n) {
    glm::vec3 position, normal;
    fragment_geometry(scene, placements, t, instance, b1, b2, position, normal);
    if (instance != kNotInstanced) out.instance[n] = instance;
    out.face[n] = t;
    out.pixel[n] = pixel;
    out.bary[2 * n] = b1;
    out.bary[2 * n + 1] = b2;
    for (int k = 0; k < 3; ++k) {
        out.position[3 * n + k] = position[k];
        out.normal[3 * n + k] = normal[k];
    }
}

// A colour channel as a byte: [0, 1] to 0..255 rounded, below 0 and NaN to 0, from 1 up to 255.
inline uint8_t color_to_byte(float v) {
    if (!(v > 0.0f)) return 0;
    if (v >= 1.0f) return 255;
    return static_cast<uint8_t>(v * 255.0f + 0.5f);
}

// SIMD (fragment_assembly_simd.cpp), the same results as the scalar code:
// Whether assemble_covered_pixels takes the scene (its indices fit the SIMD code's 32-bit lanes).
inline bool fits_simd_assembly(const hsr_scene& scene) {
    return scene.triangle_count < (1u << 31) / 9 && scene.vertex_count < (1u << 31) / 3;
}
// The covered pixels [pixel_begin, pixel_end) of a frame, in pixel order: their face ids, pixel
// indices and (when `instance`, the frame's instance ids, is not null) instances into out.face,
// out.pixel and out.instance from 0 on; returns their count. `out` holds
// FragmentArrays::reserve(pixel_end - pixel_begin, ...).
uint32_t find_covered_pixels(const uint32_t* face, const uint32_t* instance, uint32_t pixel_begin, uint32_t pixel_end,
                             FragmentArrays& out);
// The fragments of covered pixels [first, first + count) of `out` (found by find_covered_pixels,
// `total` of them), assembled as assemble_fragment does into out.bary, out.position and
// out.normal from 0 on. `instanced`: out.instance holds the pixels' instances (then `placements`
// is not empty). `out` holds FragmentArrays::reserve(..., count).
void assemble_covered_fragments(const hsr_scene& scene, const Placements& placements, bool instanced, const float* bary,
                                uint32_t first, uint32_t count, uint32_t total, FragmentArrays& out);
// Both: the covered pixels [pixel_begin, pixel_end) assembled into fragments 0, 1, ... of `out`;
// returns their count. `out` holds FragmentArrays::reserve(pixel_end - pixel_begin).
inline uint32_t assemble_covered_pixels(const hsr_scene& scene, const Placements& placements, const uint32_t* face,
                                        const uint32_t* instance, const float* bary, uint32_t pixel_begin,
                                        uint32_t pixel_end, FragmentArrays& out) {
    const uint32_t n = find_covered_pixels(face, instance, pixel_begin, pixel_end, out);
    assemble_covered_fragments(scene, placements, instance != nullptr, bary, 0, n, n, out);
    return n;
}
// bytes[i] = color_to_byte(color[i]) for i < count.
void colors_to_bytes(const float* color, size_t count, uint8_t* bytes);
// rgb[3 pixel[i] + k] = color_to_byte(color[3 i + k]) for i < count, k < 3; pixel[] rises.
void colors_to_pixels(const float* color, const uint32_t* pixel, uint32_t count, uint8_t* rgb);

// The lighting plugin's batch over the first n fragments of `arrays`.
inline hsr_fragment_batch fragment_batch(FragmentArrays& arrays, uint32_t n, bool instanced) {
    hsr_fragment_batch batch{};
    batch.struct_size = sizeof batch;
    batch.count = n;
    batch.face = arrays.face.data();
    batch.bary = arrays.bary.data();
    batch.position = arrays.position.data();
    batch.normal = arrays.normal.data();
    batch.pixel = arrays.pixel.data();
    batch.color = arrays.color.data();
    batch.instance = instanced ? arrays.instance.data() : nullptr;
    return batch;
}

// The batch of a chunk: covered pixels [first, first + n) of the band, their fragments from 0 on.
inline hsr_fragment_batch chunk_batch(FragmentArrays& arrays, uint32_t first, uint32_t n, bool instanced) {
    hsr_fragment_batch batch = fragment_batch(arrays, n, instanced);
    batch.face += first;
    batch.pixel += first;
    if (instanced) batch.instance += first;
    return batch;
}

inline constexpr uint32_t kRowsPerBand = 8;
// Fragments shaded per call of the lighting plugin: their arrays (about 44 bytes a fragment) stay
// in the L1 cache from assembly to bytes. A multiple of every vector's lane count, so that only a
// band's last chunk leaves fragments to the scalar code.
inline constexpr uint32_t kFragmentsPerChunk = 256;

// The calling thread's FragmentArrays, kept for the thread's life so that no frame allocates them
// again (each oneTBB worker has its own).
inline FragmentArrays& thread_fragment_arrays() {
    static thread_local FragmentArrays arrays;
    return arrays;
}

// Calls band(row_begin, row_end, arrays) for every band of kRowsPerBand rows of an image `height`
// rows high, on oneTBB's workers, with the calling thread's FragmentArrays. `threads`: 1 runs every
// band on the caller; 0 takes as many threads as the process allows (the host bounds that with
// tbb::global_control from --threads); more makes an arena of that many if the process allows more. A band's result does not
// depend on the thread that runs it. The first exception a band throws cancels the rest and is
// thrown again here (oneTBB's exception propagation).
template <class Band>
void for_each_band(uint32_t height, unsigned threads, Band&& band) {
    const uint32_t bands = (height + kRowsPerBand - 1) / kRowsPerBand;
    auto run = [&](uint32_t first, uint32_t last) {
        FragmentArrays& arrays = thread_fragment_arrays();
        for (uint32_t b = first; b < last; ++b)
            band(b * kRowsPerBand, std::min(height, (b + 1) * kRowsPerBand), arrays);
    };
    if (threads == 1 || bands <= 1) {
        run(0, bands);
        return;
    }
    auto parallel = [&] {
        tbb::parallel_for(tbb::blocked_range<uint32_t>(0, bands, 1),
                          [&](const tbb::blocked_range<uint32_t>& r) { run(r.begin(), r.end()); });
    };
    if (threads == 0 || threads >= tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)) {
        parallel();
    } else {
        tbb::task_arena arena(int(std::min<unsigned>(threads, bands)));
        arena.execute(parallel);
    }
}

}  // namespace hsr
