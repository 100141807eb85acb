// bsp: the binary space-partitioning tree of Fuchs, Kedem & Naylor, "On Visible Surface Generation
// by A Priori Tree Structures", SIGGRAPH 1980 (Computer Graphics 14(3), pp. 124-133), built in world
// space over every placement's triangles. Each node holds a splitting plane (the plane of one of its
// polygons), the polygons lying in that plane, and the subtrees of what lies in front of it and
// behind it; a polygon crossing the plane is cut in two. Node polygons are convex pieces of the
// scene's triangles, each knowing its triangle and the cuts that made it.
// Built by bsp_tree.cpp; drawn by bsp.cpp.
#pragma once

#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace bsp {

inline constexpr uint32_t kNoNode = 0xffffffffu;

// A placed triangle of the scene in world space, as the tree found it.
struct Triangle {
    glm::dvec3 corner[3];
    glm::dvec4 plane;  // (normal, offset), the normal by the winding (front side counter-clockwise)
    uint32_t face;
    uint32_t instance;
};

// A cut of a triangle by a splitting plane, as the affine function of the triangle's barycentrics
// (b1, b2) that the plane's equation becomes on it: f = value.x + value.y * b1 + value.z * b2. The
// piece on the plane's front keeps f >= 0, the piece behind keeps f < 0: evaluated alike at a pixel
// centre, the two tests are exact complements, so the pieces of a triangle share its pixel centres
// among them without a gap or an overlap.
struct Cut {
    glm::dvec3 value;
    bool front;
};

// A node polygon: a convex piece of a triangle, its corners (for the tree and the screen bounds)
// and the cuts that made it (for its pixels).
struct Polygon {
    uint32_t first_corner;  // into Tree::corners
    uint32_t corner_count;  // 3 .. kMaxPieceVertices
    uint32_t triangle;      // into Tree::triangles
    uint32_t first_cut;     // into Tree::cuts
    uint32_t cut_count;
};

struct Node {
    glm::dvec4 plane{0.0};  // (normal, offset): a point p is in front where dot(normal, p) + offset > 0
    uint32_t front = kNoNode;
    uint32_t back = kNoNode;
    uint32_t first_polygon = 0;  // its polygons (all in its plane): Tree::polygons[first, first + count)
    uint32_t polygon_count = 0;
};

enum class SplitChoice { kFirst, kFewestSplits };

struct BuildParams {
    SplitChoice choice = SplitChoice::kFewestSplits;
    uint32_t samples = 8;                // candidate planes tried per node (kFewestSplits)
    uint64_t max_polygons = 1'000'000;   // refuse the scene above this many polygons after splits
};

struct BuildStats {
    uint64_t polygons_in = 0;            // non-degenerate triangles of all placements
    uint64_t polygons_split = 0;         // polygons cut in two by a splitting plane
    uint64_t polygons_after_splits = 0;  // node polygons in the finished tree
    uint32_t depth = 0;                  // nodes on the longest root-to-leaf path
};

class Tree {
public:
    // Builds the tree over every placement of the scene. Throws hsr::sdk::Unsupported (naming the
    // parameter max-polygons) as soon as the polygons after splits would exceed the limit, so that
    // memory stays bounded; the tree is then empty.
    void build(const hsr::sdk::Scene& scene, const BuildParams& params);
    void clear();

    // The finished tree in pre-order (a node, its front subtree, its back subtree), its polygons
    // node by node with their corners and cuts, and the triangles in the order they are first used.
    std::vector<Node> nodes;  // nodes[0] is the root, when there is one
    std::vector<Triangle> triangles;
    std::vector<Polygon> polygons;
    std::vector<glm::dvec3> corners;
    std::vector<Cut> cuts;
    BuildStats stats;
    double epsilon = 0.0;  // distance within which a corner counts as on a plane

private:
    struct Split {  // what a candidate plane does to a list of polygons
        uint64_t front = 0, back = 0, spanning = 0;
    };
    enum class Side { kOn, kFront, kBack, kSpanning };

    Side classify(const Polygon& polygon, const glm::dvec4& plane) const;
    uint32_t choose_splitter(const std::vector<uint32_t>& list, const BuildParams& params) const;
    void split(uint32_t index, const glm::dvec4& plane, std::vector<uint32_t>& front, std::vector<uint32_t>& back,
               const BuildParams& params);
    Cut cut_of(uint32_t triangle, const glm::dvec4& plane, bool front) const;
    void add_piece(const glm::dvec3* piece, int count, const Polygon& from, const Cut* cut,
                   std::vector<uint32_t>& list, const BuildParams& params);
    void lay_out(const std::vector<uint32_t>& node_polygons);
};

}  // namespace bsp
