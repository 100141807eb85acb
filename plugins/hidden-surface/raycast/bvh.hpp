// The bounding-volume hierarchies of the raycast plugin: one per object (a distinct triangle range
// of the scene) in object space, shared by every placement that draws it, and one over the placed
// objects in world space. Built once per scene, reused by every render() of it.
//
// Build: top down with the surface area heuristic (Goldsmith & Salmon, "Automatic Creation of Object
// Hierarchies for Ray Tracing", IEEE CG&A 1987; MacDonald & Booth, "Heuristics for Ray Tracing
// Using Space Subdivision", The Visual Computer 1990), its candidate planes binned after Wald, "On
// fast Construction of SAH-based Bounding Volume Hierarchies", IEEE Symposium on Interactive Ray
// Tracing 2007: the primitives' centroids fall into kBins bins per axis, and the plane between two
// bins with the least estimated cost splits the node. A node with at most `leaf_size` primitives is a
// leaf; deep in the tree (past kMedianDepth) nodes are halved instead, so the tree never gets deeper
// than the fixed traversal stack (kMaxDepth).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace raycast {

inline constexpr int kBins = 16;
inline constexpr uint32_t kMedianDepth = 64;
inline constexpr uint32_t kMaxDepth = kMedianDepth + 34;  // halving 2^32 primitives takes 32 more
inline constexpr int kStackSize = kMaxDepth + 2;

struct Box {
    float lo[3] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                   std::numeric_limits<float>::infinity()};
    float hi[3] = {-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                   -std::numeric_limits<float>::infinity()};
    void add(const Box& b) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], b.lo[a]);
            hi[a] = std::max(hi[a], b.hi[a]);
        }
    }
    void add(const float* p) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    }
    bool empty() const { return lo[0] > hi[0]; }
    double half_area() const {
        if (empty()) return 0.0;
        const double x = double(hi[0]) - lo[0], y = double(hi[1]) - lo[1], z = double(hi[2]) - lo[2];
        return x * y + y * z + z * x;
    }
};

// A node: an inner node's children are nodes `first` and `first + 1`; a leaf holds primitives
// [first, first + count) of its hierarchy's primitive order.
struct Node {
    Box box;
    uint32_t first = 0;
    uint32_t count = 0;  // 0 for an inner node
    bool is_leaf() const { return count != 0; }
};

// A primitive to build over: its box and the centroid of that box. `id` is the caller's.
struct PrimitiveRef {
    Box box;
    float centroid[3];
    uint32_t id;
};

inline PrimitiveRef make_ref(const Box& box, uint32_t id) {
    PrimitiveRef r{box, {}, id};
    for (int a = 0; a < 3; ++a) r.centroid[a] = 0.5f * box.lo[a] + 0.5f * box.hi[a];
    return r;
}

// Builds a hierarchy over refs (reordered into leaf order) and appends its nodes to `nodes`; the
// root is the first node appended. refs must not be empty.
inline void build_bvh(std::vector<PrimitiveRef>& refs, uint32_t leaf_size, std::vector<Node>& nodes) {
    struct Task {
        uint32_t node, begin, end, depth;
    };
    std::vector<Task> tasks;
    nodes.push_back(Node{});
    tasks.push_back({uint32_t(nodes.size() - 1), 0, uint32_t(refs.size()), 0});
    while (!tasks.empty()) {
        const Task task = tasks.back();
        tasks.pop_back();
        Box bounds, centroids;
        for (uint32_t k = task.begin; k < task.end; ++k) {
            bounds.add(refs[k].box);
            centroids.add(refs[k].centroid);
        }
        nodes[task.node].box = bounds;
        const uint32_t n = task.end - task.begin;
        if (n <= leaf_size) {
            nodes[task.node].first = task.begin;
            nodes[task.node].count = n;
            continue;
        }

        // The binned SAH plane (cost: traversal 1, each primitive 1), or the middle of the range.
        uint32_t middle = task.begin + n / 2;
        bool split_by_plane = false;
        if (task.depth < kMedianDepth) {
            double best_cost = std::numeric_limits<double>::infinity();
            int best_axis = -1, best_plane = 0;
            for (int a = 0; a < 3; ++a) {
                const double extent = double(centroids.hi[a]) - centroids.lo[a];
                if (!(extent > 0.0)) continue;
                const double scale = kBins * (1.0 - 1e-9) / extent;
                Box bin_box[kBins];
                uint32_t bin_count[kBins] = {};
                for (uint32_t k = task.begin; k < task.end; ++k) {
                    const int b = std::min(kBins - 1, int((refs[k].centroid[a] - double(centroids.lo[a])) * scale));
                    bin_box[b].add(refs[k].box);
                    ++bin_count[b];
                }
                double right_area[kBins];
                uint32_t right_count[kBins];
                Box right;
                uint32_t count = 0;
                for (int b = kBins - 1; b > 0; --b) {
                    right.add(bin_box[b]);
                    count += bin_count[b];
                    right_area[b] = right.half_area();
                    right_count[b] = count;
                }
                Box left;
                count = 0;
                for (int b = 0; b < kBins - 1; ++b) {
                    left.add(bin_box[b]);
                    count += bin_count[b];
                    if (count == 0 || right_count[b + 1] == 0) continue;
                    const double cost = left.half_area() * count + right_area[b + 1] * right_count[b + 1];
                    if (cost < best_cost) {
                        best_cost = cost;
                        best_axis = a;
                        best_plane = b;
                    }
                }
            }
            if (best_axis >= 0) {
                const int a = best_axis;
                const double scale = kBins * (1.0 - 1e-9) / (double(centroids.hi[a]) - centroids.lo[a]);
                const auto split = std::partition(refs.begin() + task.begin, refs.begin() + task.end,
                                                  [&](const PrimitiveRef& r) {
                                                      return std::min(kBins - 1, int((r.centroid[a] - double(centroids.lo[a])) *
                                                                                     scale)) <= best_plane;
                                                  });
                middle = uint32_t(split - refs.begin());
                split_by_plane = middle > task.begin && middle < task.end;
            }
        }
        if (!split_by_plane) {
            // Halve along the widest centroid axis.
            int a = 0;
            for (int k = 1; k < 3; ++k)
                if (double(centroids.hi[k]) - centroids.lo[k] > double(centroids.hi[a]) - centroids.lo[a]) a = k;
            middle = task.begin + n / 2;
            std::nth_element(refs.begin() + task.begin, refs.begin() + middle, refs.begin() + task.end,
                             [a](const PrimitiveRef& x, const PrimitiveRef& y) { return x.centroid[a] < y.centroid[a]; });
        }
        const uint32_t left = uint32_t(nodes.size());
        nodes.push_back(Node{});
        nodes.push_back(Node{});
        nodes[task.node].first = left;
        nodes[task.node].count = 0;
        tasks.push_back({left + 1, middle, task.end, task.depth + 1});
        tasks.push_back({left, task.begin, middle, task.depth + 1});
    }
}

}  // namespace raycast
