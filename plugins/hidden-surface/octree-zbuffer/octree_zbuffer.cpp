// octree-zbuffer: the hierarchical z-buffer with an object-space octree, after Ned Greene, Michael
// Kass and Gavin Miller, "Hierarchical Z-Buffer Visibility", SIGGRAPH 1993.
//
// The scene's triangles sit in octrees (one per object, in object space, built once and reused while
// the scene stays the same), under a bounding-volume hierarchy over the placed instances. Both are
// traversed front to back from the eye. A node whose box, projected to the screen, lies behind what
// is already drawn (a z-pyramid query: the bounding rectangle of its projected corners against the
// nearest corner depth) is culled with everything it holds, its vertices never transformed. The
// front faces of visible leaves (back faces, and leaves with no front face, wait until the rest of
// their placement is drawn) are tested against the pyramid (Greene's triangle-level rejection,
// before triangle setup), go through the plain z-buffer's geometry stage (hsr/raster.hpp: the same
// clipping, snapping, coverage and depth as the zbuffer plugin, bit for bit), larger ones are
// rejected by 32x32 blocks and 8x8 tiles, and the rest is the z-buffer's own per-pixel depth test.
// After each leaf (after each triangle larger than a block) the pyramid (hsr/zpyramid.hpp) is
// marked for a deferred update. Exact depth ties go to the surface the plain
// z-buffer draws first, so the picture is the zbuffer plugin's, pixel for pixel.
//
// The image is cut into square screen tiles (parameter tile-size), each drawn by its own traversal
// with its own z-pyramid over its pixels only (tile_renderer.hpp), the tiles in parallel on oneTBB.
// The tie rule makes the order of drawing invisible, so tiles give the same buffers as one pass.
//
// Where a triangle goes and how the octree is laid out: octree.hpp; how a built scene is recognised
// again: hsr/scene_key.hpp; the plugin's class and its drawing over the tiles: octree_zbuffer.hpp.
// This file builds the octrees and reports the counters. What it costs and when it pays:
// docs/algorithms/octree-zbuffer.md.
#include "octree_zbuffer.hpp"

#include "octree.hpp"
#include "tile_renderer.hpp"

#include "hsr/scene_key.hpp"
#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace octree_zbuffer {

// The counters of the first `count` tiles, summed: a node or triangle that reaches several tiles
// is counted in each.
void OctreeZBuffer::report(hsr::sdk::Counters& counters, size_t count) const {
    FrameStats stats;
    raster::TriangleStats triangles;
    for (size_t k = 0; k < count; ++k) {
        stats.add(tiles_[k]->stats());
        const raster::TriangleStats t = tiles_[k]->triangle_stats();
        triangles.backface_culled += t.backface_culled;
        triangles.clipped += t.clipped;
        triangles.outside += t.outside;
        triangles.degenerate += t.degenerate;
        triangles.rasterized += t.rasterized;
    }
    triangles.in = drawn_triangles_;
    triangles.outside += stats.triangles_in_outside_nodes;
    triangles.degenerate += non_finite_triangles_;
    triangles.rasterized -= stats.triangles_culled_after_setup;
    triangles.report(counters);
    counters.set("triangles-in-culled-nodes", stats.triangles_in_culled_nodes);
    counters.set("triangles-culled-by-pyramid",
                 stats.triangles_culled_before_setup + stats.triangles_culled_after_setup);
    counters.set("octree-nodes", built_.forest.nodes.size());
    counters.set("octree-nodes-visited", stats.nodes_visited);
    counters.set("octree-nodes-culled", stats.nodes_culled);
    counters.set("octree-nodes-outside", stats.nodes_outside);
    counters.set("octree-leaves-drawn", stats.leaves_drawn);
    counters.set("octree-leaves-deferred", stats.leaves_deferred);
    counters.set("instance-nodes", built_.bvh.size());
    counters.set("instance-nodes-visited", stats.instance_nodes_visited);
    counters.set("instance-nodes-culled", stats.instance_nodes_culled);
    counters.set("instance-nodes-outside", stats.instance_nodes_outside);
    counters.set("placements-visited", stats.placements_visited);
    counters.set("vertices-transformed", stats.vertices_transformed);
    counters.set("tiles-tested", stats.tiles_tested);
    counters.set("tiles-culled", stats.tiles_culled);
    counters.set("pyramid-updates", stats.pyramid_updates);
    counters.set("pixels-depth-tested", stats.pixels_tested);
    counters.set("pixels-written", stats.pixels_written);
}

// ---------------------------------------------------------------------------------------------- //
// Build (once per scene)

// Builds what is missing for this scene; true when anything was built.
bool OctreeZBuffer::prepare(const hsr::sdk::Scene& scene) {
    const hsr::sdk::SceneKey skey = hsr::sdk::scene_key(scene);
    const hsr::sdk::InstanceKey ikey = hsr::sdk::instance_key(scene);
    if (has_built_ && skey == scene_key_ && ikey == instance_key_) return false;
    const bool same_geometry = has_built_ && skey == scene_key_;
    has_built_ = false;  // until everything below is done (it may throw bad_alloc)
    if (!same_geometry) {  // otherwise only placements changed: keep the objects' octrees
        built_.forest.clear();
        object_of_range_.clear();
    }

    const uint32_t placements = scene.placement_count();
    built_.placement_object.assign(placements, 0);
    std::vector<InstanceItem> items;
    items.reserve(placements);
    drawn_triangles_ = 0;
    non_finite_triangles_ = 0;
    for (uint32_t k = 0; k < placements; ++k) {
        const hsr::sdk::Placement p = scene.placement(k);
        drawn_triangles_ += p.triangle_count;
        const std::array<uint32_t, 4> range{p.first_triangle, p.triangle_count, p.first_vertex, p.vertex_count};
        auto found = object_of_range_.find(range);
        if (found == object_of_range_.end())
            found = object_of_range_
                        .emplace(range, built_.forest.add_object(scene.raw(), p.first_triangle, p.triangle_count,
                                                           p.first_vertex, p.vertex_count, build_params_))
                        .first;
        built_.placement_object[k] = found->second;
        const ObjectTree& object = built_.forest.objects[found->second];
        non_finite_triangles_ += object.non_finite;
        if (!object.has_root) continue;
        // World box: the object's root box carried by the transform, rounded outward.
        const OctreeNode& root = built_.forest.nodes[object.root];
        const glm::dmat4 m = p.identity ? glm::dmat4(1.0) : glm::dmat4(p.transform);
        glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (int c = 0; c < 8; ++c) {
            const glm::dvec4 w = m * glm::dvec4((c & 1) ? root.hi[0] : root.lo[0], (c & 2) ? root.hi[1] : root.lo[1],
                                                (c & 4) ? root.hi[2] : root.lo[2], 1.0);
            lo = glm::min(lo, glm::dvec3(w));
            hi = glm::max(hi, glm::dvec3(w));
        }
        InstanceItem item;
        for (int a = 0; a < 3; ++a) {
            item.lo[a] = std::nextafter(float(lo[a]), -std::numeric_limits<float>::infinity());
            item.hi[a] = std::nextafter(float(hi[a]), std::numeric_limits<float>::infinity());
            if (!(std::isfinite(item.lo[a]) && std::isfinite(item.hi[a]))) {  // overflow: anywhere
                item.lo[a] = -std::numeric_limits<float>::max();
                item.hi[a] = std::numeric_limits<float>::max();
            }
        }
        item.placement = k;
        item.triangles = object.triangle_count - object.non_finite;
        items.push_back(item);
    }
    build_instance_bvh(items, built_.bvh);

    built_.leaf_scene = hsr_scene{};
    built_.leaf_scene.struct_size = sizeof(hsr_scene);
    built_.leaf_scene.vertex_count = uint32_t(built_.forest.mesh.positions.size() / 3);
    built_.leaf_scene.triangle_count = uint32_t(built_.forest.mesh.face.size());
    built_.leaf_scene.object_count = 1;
    built_.leaf_scene.positions = built_.forest.mesh.positions.data();
    built_.leaf_scene.indices = built_.forest.mesh.indices.data();
    scene_key_ = skey;
    instance_key_ = ikey;
    has_built_ = true;
    return true;
}

}  // namespace octree_zbuffer

HSR_EXPORT_PLUGIN(octree_zbuffer::OctreeZBuffer)
