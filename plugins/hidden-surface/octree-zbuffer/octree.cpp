// Building the octrees and the placement hierarchy of the octree-zbuffer plugin (see octree.hpp).
#include "octree.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>

namespace octree_zbuffer {
namespace {

struct TriangleInfo {
    glm::vec3 lo, hi;     // bounds of the three corners
    glm::vec3 centroid;
    uint32_t id;          // the scene's triangle index
};

int octant_of(const glm::vec3& p, const glm::vec3& centre) {
    return (p.x > centre.x ? 1 : 0) | (p.y > centre.y ? 2 : 0) | (p.z > centre.z ? 4 : 0);
}

glm::vec3 child_centre(const glm::vec3& centre, float half, int octant) {
    const float q = 0.5f * half;
    return {centre.x + ((octant & 1) ? q : -q), centre.y + ((octant & 2) ? q : -q),
            centre.z + ((octant & 4) ? q : -q)};
}

class OctreeBuilder {
public:
    OctreeBuilder(const hsr_scene& scene, OctreeForest& forest, ObjectTree& object, const BuildParams& params)
        : scene_(scene), forest_(forest), object_(object), params_(params) {}

    void run() {
        tris_.reserve(object_.triangle_count);
        glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
        const uint32_t end = object_.first_triangle + object_.triangle_count;
        for (uint32_t t = object_.first_triangle; t < end; ++t) {
            glm::vec3 p[3];
            bool finite = true;
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = scene_.indices[3 * size_t(t) + k];
                p[k] = {scene_.positions[3 * size_t(v)], scene_.positions[3 * size_t(v) + 1],
                        scene_.positions[3 * size_t(v) + 2]};
                finite = finite && std::isfinite(p[k].x) && std::isfinite(p[k].y) && std::isfinite(p[k].z);
            }
            if (!finite) {
                ++object_.non_finite;  // GeometryStage would call it degenerate: it never draws it
                continue;
            }
            TriangleInfo info;
            info.lo = glm::min(p[0], glm::min(p[1], p[2]));
            info.hi = glm::max(p[0], glm::max(p[1], p[2]));
            info.centroid = (p[0] + p[1] + p[2]) / 3.0f;
            info.id = t;
            lo = glm::min(lo, info.lo);
            hi = glm::max(hi, info.hi);
            tris_.push_back(info);
        }
        if (tris_.empty()) return;
        scratch_.resize(tris_.size());
        remap_.assign(object_.vertex_count, kNoCopy);
        stamp_.assign(object_.vertex_count, 0);

        // The root cell is the cube around the object's bounds.
        const glm::vec3 centre = 0.5f * (lo + hi);
        const glm::vec3 extent = hi - lo;
        float half = 0.5f * std::max({extent.x, extent.y, extent.z});
        if (!(half > 0.0f) || !std::isfinite(half)) half = 1.0f;
        object_.root = uint32_t(forest_.nodes.size());
        object_.has_root = true;
        forest_.nodes.emplace_back();
        build(object_.root, centre, half, 0, 0, tris_.size());
        object_.node_count = uint32_t(forest_.nodes.size()) - object_.root;
    }

private:
    void build(uint32_t node, glm::vec3 centre, float half, uint32_t depth, size_t begin, size_t end) {
        glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
        for (size_t k = begin; k < end; ++k) {
            lo = glm::min(lo, tris_[k].lo);
            hi = glm::max(hi, tris_[k].hi);
        }
        {
            OctreeNode& n = forest_.nodes[node];
            n = OctreeNode{};
            for (int a = 0; a < 3; ++a) {
                n.lo[a] = lo[a];
                n.hi[a] = hi[a];
            }
        }

        size_t counts[8];
        for (;;) {
            if (end - begin <= params_.leaf_triangles || depth >= params_.max_depth) {
                make_leaf(node, depth, begin, end);
                return;
            }
            std::fill(std::begin(counts), std::end(counts), size_t(0));
            for (size_t k = begin; k < end; ++k) ++counts[octant_of(tris_[k].centroid, centre)];
            const int occupied = int(std::count_if(std::begin(counts), std::end(counts), [](size_t c) { return c > 0; }));
            if (occupied > 1) break;
            // Every centroid lies in one octant: descend into it without making a node.
            const int only = int(std::find_if(std::begin(counts), std::end(counts), [](size_t c) { return c > 0; }) -
                                 std::begin(counts));
            centre = child_centre(centre, half, only);
            half *= 0.5f;
            ++depth;
        }

        // Counting sort of [begin, end) by octant, stable (keeps scene order within an octant).
        size_t start[8];
        size_t running = begin;
        uint32_t mask = 0;
        for (int o = 0; o < 8; ++o) {
            start[o] = running;
            running += counts[o];
            if (counts[o] > 0) mask |= 1u << o;
        }
        size_t fill[8];
        std::copy(std::begin(start), std::end(start), std::begin(fill));
        for (size_t k = begin; k < end; ++k) scratch_[fill[octant_of(tris_[k].centroid, centre)]++] = tris_[k];
        std::copy(scratch_.begin() + std::ptrdiff_t(begin), scratch_.begin() + std::ptrdiff_t(end),
                  tris_.begin() + std::ptrdiff_t(begin));

        const uint32_t first_child = uint32_t(forest_.nodes.size());
        forest_.nodes.resize(forest_.nodes.size() + size_t(std::popcount(mask)));
        const uint32_t first_triangle = uint32_t(forest_.mesh.face.size());
        uint32_t child = first_child;
        for (int o = 0; o < 8; ++o) {
            if (counts[o] == 0) continue;
            build(child++, child_centre(centre, half, o), 0.5f * half, depth + 1, start[o], start[o] + counts[o]);
        }
        OctreeNode& n = forest_.nodes[node];  // the array may have grown meanwhile
        for (int a = 0; a < 3; ++a) n.split[a] = centre[a];
        n.first_child = first_child;
        n.child_mask = mask;
        n.first_triangle = first_triangle;
        n.triangle_count = uint32_t(forest_.mesh.face.size()) - first_triangle;
        n.depth = depth;
    }

    void make_leaf(uint32_t node, uint32_t depth, size_t begin, size_t end) {
        // Scene order within a leaf: ties between its triangles resolve as in the plain z-buffer.
        std::sort(tris_.begin() + std::ptrdiff_t(begin), tris_.begin() + std::ptrdiff_t(end),
                  [](const TriangleInfo& a, const TriangleInfo& b) { return a.id < b.id; });
        LeafMesh& mesh = forest_.mesh;
        OctreeNode& n = forest_.nodes[node];
        n.first_child = 0;
        n.child_mask = 0;
        n.depth = depth;
        n.first_triangle = uint32_t(mesh.face.size());
        n.triangle_count = uint32_t(end - begin);
        n.first_vertex = uint32_t(mesh.leaf_vertices.size());
        ++leaf_stamp_;
        for (size_t k = begin; k < end; ++k) {
            const uint32_t t = tris_[k].id;
            for (int c = 0; c < 3; ++c) {
                const uint32_t v = scene_.indices[3 * size_t(t) + c];
                const uint32_t local = v - object_.first_vertex;
                if (remap_[local] == kNoCopy) {  // the object's first use of v
                    remap_[local] = uint32_t(mesh.positions.size() / 3);
                    mesh.positions.insert(mesh.positions.end(), scene_.positions + 3 * size_t(v),
                                          scene_.positions + 3 * size_t(v) + 3);
                }
                if (stamp_[local] != leaf_stamp_) {  // the leaf's first use of v
                    stamp_[local] = leaf_stamp_;
                    mesh.leaf_vertices.push_back(remap_[local]);
                }
                mesh.indices.push_back(remap_[local]);
            }
            mesh.face.push_back(t);
            mesh.planes.push_back(plane_of(t));
        }
        n.vertex_count = uint32_t(mesh.leaf_vertices.size()) - n.first_vertex;
        ++object_.leaf_count;
        object_.depth = std::max(object_.depth, depth);
    }

    glm::vec4 plane_of(uint32_t t) const {
        glm::dvec3 p[3];
        for (int c = 0; c < 3; ++c) {
            const float* v = scene_.positions + 3 * size_t(scene_.indices[3 * size_t(t) + c]);
            p[c] = glm::dvec3(v[0], v[1], v[2]);
        }
        const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
        return glm::vec4(glm::vec3(n), float(-glm::dot(n, p[0])));
    }

    const hsr_scene& scene_;
    OctreeForest& forest_;
    ObjectTree& object_;
    BuildParams params_;
    std::vector<TriangleInfo> tris_, scratch_;
    static constexpr uint32_t kNoCopy = ~0u;
    std::vector<uint32_t> remap_;  // per object vertex: its copy in LeafMesh::positions
    std::vector<uint32_t> stamp_;  // per object vertex: the last leaf that used it
    uint32_t leaf_stamp_ = 0;
};

}  // namespace

uint32_t OctreeForest::add_object(const hsr_scene& scene, uint32_t first_triangle, uint32_t triangle_count,
                                  uint32_t first_vertex, uint32_t vertex_count, const BuildParams& params) {
    ObjectTree object;
    object.first_triangle = first_triangle;
    object.triangle_count = triangle_count;
    object.first_vertex = first_vertex;
    object.vertex_count = vertex_count;
    OctreeBuilder(scene, *this, object, params).run();
    objects.push_back(object);
    return uint32_t(objects.size() - 1);
}

void OctreeForest::clear() {
    nodes.clear();
    mesh.positions.clear();
    mesh.leaf_vertices.clear();
    mesh.indices.clear();
    mesh.face.clear();
    mesh.planes.clear();
    objects.clear();
}

namespace {

void build_instances(std::vector<InstanceItem>& items, std::vector<InstanceNode>& nodes, uint32_t node, size_t begin,
                     size_t end) {
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    glm::vec3 centre_lo = lo, centre_hi = hi;
    uint64_t triangles = 0;
    for (size_t k = begin; k < end; ++k) {
        lo = glm::min(lo, items[k].lo);
        hi = glm::max(hi, items[k].hi);
        const glm::vec3 c = 0.5f * (items[k].lo + items[k].hi);
        centre_lo = glm::min(centre_lo, c);
        centre_hi = glm::max(centre_hi, c);
        triangles += items[k].triangles;
    }
    {
        InstanceNode& n = nodes[node];
        for (int a = 0; a < 3; ++a) {
            n.lo[a] = lo[a];
            n.hi[a] = hi[a];
        }
        n.triangles = triangles;
    }
    if (end - begin == 1) {
        nodes[node].first = items[begin].placement;
        nodes[node].axis = 3;
        nodes[node].split = 0.0f;
        return;
    }
    // Median split along the axis where the centres spread most.
    const glm::vec3 spread = centre_hi - centre_lo;
    const uint32_t axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
    const size_t middle = begin + (end - begin) / 2;
    auto centre = [axis](const InstanceItem& item) { return item.lo[axis] + item.hi[axis]; };
    std::nth_element(items.begin() + std::ptrdiff_t(begin), items.begin() + std::ptrdiff_t(middle),
                     items.begin() + std::ptrdiff_t(end),
                     [&](const InstanceItem& a, const InstanceItem& b) { return centre(a) < centre(b); });
    float left_max = -std::numeric_limits<float>::infinity();
    for (size_t k = begin; k < middle; ++k) left_max = std::max(left_max, centre(items[k]));
    const uint32_t left = uint32_t(nodes.size());
    nodes.resize(nodes.size() + 2);
    nodes[node].first = left;
    nodes[node].axis = axis;
    nodes[node].split = 0.25f * (left_max + centre(items[middle]));  // centre() is twice the centre
    build_instances(items, nodes, left, begin, middle);
    build_instances(items, nodes, left + 1, middle, end);
}

}  // namespace

void build_instance_bvh(std::vector<InstanceItem>& items, std::vector<InstanceNode>& nodes) {
    nodes.clear();
    if (items.empty()) return;
    nodes.reserve(2 * items.size());
    nodes.emplace_back();
    build_instances(items, nodes, 0, 0, items.size());
}

}  // namespace octree_zbuffer
