// hsr scene keys: a plugin's memory of the scene it built an acceleration structure for (an octree,
// a BVH, a BSP tree). Cheap keys (addresses, sizes, sampled hashes of the geometry, a hash of every
// instance's ranges and transform) tell whether the structure can be reused for the next frame, or
// only the part over the placements must be rebuilt. Header-only, part of hsr::sdk.
#pragma once

#include "hsr/abi.h"
#include "hsr/sdk.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace hsr::sdk {

inline uint64_t mix(uint64_t h, uint64_t v) {
    h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    return h * 0xff51afd7ed558ccdull;
}

// Up to ~4096 evenly spaced 32-bit words of an array, plus its last word: cheap, and enough to notice
// that a different mesh now sits at the same address with the same size.
inline uint64_t sampled_hash(const void* data, size_t bytes) {
    uint64_t h = bytes;
    const size_t words = bytes / 4;
    if (data == nullptr || words == 0) return h;
    const auto* bytes_in = static_cast<const unsigned char*>(data);
    const size_t step = std::max<size_t>(1, words / 4096);
    uint32_t w;
    for (size_t k = 0; k < words; k += step) {
        std::memcpy(&w, bytes_in + 4 * k, 4);
        h = mix(h, w);
    }
    std::memcpy(&w, bytes_in + 4 * (words - 1), 4);
    return mix(h, w);
}

struct SceneKey {
    const float* positions = nullptr;
    const uint32_t* indices = nullptr;
    uint32_t vertex_count = 0, triangle_count = 0;
    uint64_t geometry_hash = 0;
    bool operator==(const SceneKey&) const = default;
};

struct InstanceKey {
    const hsr_instance* instances = nullptr;
    uint32_t instance_count = 0;
    uint64_t hash = 0;  // every instance's ranges and transform
    bool operator==(const InstanceKey&) const = default;
};

inline InstanceKey instance_key(const hsr::sdk::Scene& scene) {
    InstanceKey key;
    key.instance_count = scene.instance_count();
    if (key.instance_count == 0) return key;
    key.instances = scene.raw().instances;
    // Four independent lanes keep the multiplies from waiting on each other.
    uint64_t lane[4] = {1, 2, 3, 4};
    for (uint32_t k = 0; k < key.instance_count; ++k) {
        const hsr_instance& i = scene.instance(k);
        uint32_t words[20];
        words[0] = i.first_triangle;
        words[1] = i.triangle_count;
        words[2] = i.first_vertex;
        words[3] = i.vertex_count;
        std::memcpy(words + 4, i.transform, sizeof i.transform);
        for (int w = 0; w < 20; w += 4)
            for (int l = 0; l < 4; ++l) lane[l] = (lane[l] ^ words[w + l]) * 0x9e3779b97f4a7c15ull + uint64_t(l);
    }
    key.hash = mix(mix(mix(lane[0], lane[1]), lane[2]), lane[3]);
    return key;
}

inline SceneKey scene_key(const hsr::sdk::Scene& scene) {
    const hsr_scene& s = scene.raw();
    SceneKey key;
    key.positions = s.positions;
    key.indices = s.indices;
    key.vertex_count = s.vertex_count;
    key.triangle_count = s.triangle_count;
    key.geometry_hash = mix(sampled_hash(s.positions, size_t(s.vertex_count) * 12),
                            sampled_hash(s.indices, size_t(s.triangle_count) * 12));
    return key;
}

// Runs build(), which answers whether it built the structure (true) or reused the one it had
// (false), and reports its time as the counter build-time-us: at least 1 when it built, so that
// "built" never reads as "reused", and 0 when it reused.
template <class Build>
void timed_build(Counters& counters, Build&& build) {
    const auto start = std::chrono::steady_clock::now();
    const bool built = build();
    const auto us =
        std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - start).count();
    counters.set("build-time-us", built ? std::max<uint64_t>(1, uint64_t(us)) : 0);
}

// The counter timed_build sets, in Russian, for the plugin's `translations`.
inline constexpr std::array<TranslationSpec, 1> build_time_counter_translations{{
    {"ru", "counter:build-time-us", "время построения, мкс"},
}};

}  // namespace hsr::sdk
