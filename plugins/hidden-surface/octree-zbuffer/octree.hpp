// The object-space octrees of the octree-zbuffer plugin, and the bounding-volume hierarchy over the
// scene's placements (instances) above them. Built once per scene, reused by every render() of it.
//
// Octree (after Greene, Kass & Miller, "Hierarchical Z-Buffer Visibility", SIGGRAPH 1993, section 3):
// the cube around an object is split at its centre into eight octants, recursively, until a cell
// holds at most `leaf_triangles` triangles or `max_depth` levels have been made. A triangle belongs
// to exactly ONE cell: the octant holding its centroid. A node's box for visibility tests is not the
// cell itself but the tight bounds of the triangles below it (it may reach a little into the
// neighbouring cells, as in a "loose" octree), so no triangle is stored twice, no triangle is stuck
// at the root because it straddles a splitting plane, and no per-frame "already drawn" stamp is
// needed. Children still split space at the cell centre, which gives the front-to-back order.
//
// Each leaf's triangles are copied out into a mesh of their own (`LeafMesh`, one copy of each object
// vertex they use), with the list of the vertices each leaf uses: a visible leaf's vertices are
// transformed when it is drawn, those it shares with a leaf drawn before for the same placement
// only once, and a culled subtree costs no vertex work at all.
#pragma once

#include "hsr/abi.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace octree_zbuffer {

struct OctreeNode {
    float lo[3], hi[3];       // tight object-space bounds of every triangle below (finite)
    float split[3];           // centre of the octree cell: child octant o lies on side bit k of o
                              // (bit k set = above split[k]) for axis k
    uint32_t first_child;     // children are nodes [first_child, +popcount(child_mask)), octant order
    uint32_t child_mask;      // bit o set when octant o has a child; 0 for a leaf
    uint32_t first_triangle;  // triangles below this node in LeafMesh (contiguous: depth-first order)
    uint32_t triangle_count;
    uint32_t first_vertex;    // leaf only: the vertices its triangles use, LeafMesh::leaf_vertices[first_vertex,
    uint32_t vertex_count;    // +vertex_count)
    uint32_t depth;           // root = 0 (levels that split nothing are skipped but still counted)
    bool is_leaf() const { return child_mask == 0; }
};

// The triangles of every object's octree leaves, leaf after leaf, and the vertices they use.
struct LeafMesh {
    std::vector<float> positions;  // 3 per vertex, object space: bit-identical copies of the scene's
    std::vector<uint32_t> leaf_vertices;  // per leaf, the vertices its triangles use, each once
    std::vector<uint32_t> indices; // 3 per triangle, corners in the scene's order
    std::vector<uint32_t> face;    // per triangle: the scene's triangle id
    // Per triangle: its object-space plane (n, -n . p0) with n = (p1 - p0) x (p2 - p0), so that
    // dot(plane, (eye, 1)) > 0 when the eye sees the corners counter-clockwise (the front), and
    // dot(plane, (direction toward the viewer, 0)) likewise for an orthographic camera. Used only to
    // choose the drawing order, never to cull, so float precision is enough.
    std::vector<glm::vec4> planes;
};

// One distinct triangle range of the scene (an object that one or more placements draw).
struct ObjectTree {
    uint32_t first_triangle = 0, triangle_count = 0;  // the scene's range
    uint32_t first_vertex = 0, vertex_count = 0;
    uint32_t root = 0;           // node index; valid only when has_root
    bool has_root = false;       // false when no triangle of the range has finite corners
    uint32_t node_count = 0;
    uint32_t leaf_count = 0;
    uint32_t depth = 0;          // deepest leaf
    uint32_t non_finite = 0;     // triangles left out because a corner is not finite
};

struct BuildParams {
    uint32_t max_depth = 8;
    uint32_t leaf_triangles = 64;
};

// All octrees of a scene share one node array and one LeafMesh.
struct OctreeForest {
    std::vector<OctreeNode> nodes;
    LeafMesh mesh;
    std::vector<ObjectTree> objects;

    // Builds the octree of the scene's triangles [first_triangle, +count) whose vertices lie in
    // [first_vertex, +vertex_count) (validated by the caller) and returns its index in `objects`.
    uint32_t add_object(const hsr_scene& scene, uint32_t first_triangle, uint32_t triangle_count,
                        uint32_t first_vertex, uint32_t vertex_count, const BuildParams& params);
    void clear();
};

// A binary BVH over placements (world-space boxes), leaves hold one placement each.
struct InstanceNode {
    float lo[3], hi[3];   // world bounds of everything below
    uint32_t first;       // inner: left child (right child is first + 1); leaf: the placement
    uint32_t axis;        // inner: the axis the children were split on; 3 for a leaf
    float split;          // inner: where along axis the two children's centres part
    uint64_t triangles;   // triangles drawn below (for the culled-triangle counter)
    bool is_leaf() const { return axis == 3; }
};

struct InstanceItem {
    glm::vec3 lo, hi;     // world bounds
    uint32_t placement;
    uint64_t triangles;
};

// Builds the hierarchy over `items` (reordered); node 0 is the root. Empty input gives no nodes.
void build_instance_bvh(std::vector<InstanceItem>& items, std::vector<InstanceNode>& nodes);

}  // namespace octree_zbuffer
