// What the frame pipeline and the fragment-list compositor share (framework-internal): the arrays
// of one shading batch, the instances' transforms, and the assembly of one fragment (world position
// and interpolated shading normal from a face and barycentrics) for a lighting plugin.
#pragma once

#include "hsr/abi.h"

#include <glm/glm.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hsr {

// Fragment arrays for one batch (a band of rows), reused across the band's rows.
struct FragmentArrays {
    std::vector<uint32_t> face, pixel, instance;
    std::vector<float> bary, position, normal, color;

    void reserve(size_t n) {
        face.resize(n);
        pixel.resize(n);
        instance.resize(n);
        bary.resize(2 * n);
        position.resize(3 * n);
        normal.resize(3 * n);
        color.resize(3 * n);
    }
};

// Where each instance puts its triangles: world = transform * p, normals turn by rotation.
struct Placements {
    std::vector<glm::mat4> transform;
    std::vector<glm::mat3> rotation;

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

// Fragment n of `out`: triangle t (of `instance`, or kNotInstanced) at barycentrics (b1, b2), for
// `pixel`.
inline void assemble_fragment(const hsr_scene& scene, const Placements& placements, uint32_t t, uint32_t instance,
                              float b1, float b2, uint32_t pixel, FragmentArrays& out, uint32_t n) {
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
    glm::vec3 position(b0 * p0[0] + b1 * p1[0] + b2 * p2[0], b0 * p0[1] + b1 * p1[1] + b2 * p2[1],
                       b0 * p0[2] + b1 * p1[2] + b2 * p2[2]);
    glm::vec3 normal(nx, ny, nz);
    if (instance != kNotInstanced) {
        position = glm::vec3(placements.transform[instance] * glm::vec4(position, 1.0f));
        normal = placements.rotation[instance] * normal;
        out.instance[n] = instance;
    }
    out.face[n] = t;
    out.pixel[n] = pixel;
    out.bary[2 * n] = b1;
    out.bary[2 * n + 1] = b2;
    for (int k = 0; k < 3; ++k) {
        out.position[3 * n + k] = position[k];
        out.normal[3 * n + k] = normal[k];
    }
}

}  // namespace hsr
