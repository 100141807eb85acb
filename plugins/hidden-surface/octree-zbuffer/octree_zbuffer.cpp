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
// again: hsr/scene_key.hpp. What it costs and when it pays: docs/algorithms/octree-zbuffer.md.
#include "octree.hpp"
#include "tile_renderer.hpp"

#include "hsr/scene_key.hpp"
#include "hsr/sdk.hpp"

#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <vector>

namespace octree_zbuffer {

using hsr::sdk::ParamSpec;

class OctreeZBuffer final : public hsr::sdk::HiddenSurfaceRemover {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "octree-zbuffer", "1.0.0",
        "octree z-buffer (Greene, Kass & Miller 1993): object-space octrees, front to back, culled against a z-pyramid"};
    static inline const ParamSpec params[] = {
        ParamSpec::integer("max-depth", "8", 0, 20, "deepest octree level (the root is level 0)"),
        ParamSpec::integer("leaf-triangles", "64", 1, 65536,
                           "an octree cell with at most this many triangles is not split further"),
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
        ParamSpec::integer("tile-size", "512", 0, 65536,
                           "pixels per side of the screen tiles drawn in parallel, rounded up to a multiple of "
                           "8 (0: the whole image as one tile)"),
    };

    explicit OctreeZBuffer(const hsr::sdk::Params& p) : cull_backfaces_(p.boolean("cull-backfaces")) {
        build_params_.max_depth = uint32_t(p.integer("max-depth"));
        build_params_.leaf_triangles = uint32_t(p.integer("leaf-triangles"));
        tile_size_ = int32_t((p.integer("tile-size") + 7) / 8 * 8);
    }

    void render(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                hsr::sdk::Counters& counters) override {
        hsr::sdk::NoSteps no_steps;
        render_with(scene, camera, target, counters, no_steps);
    }

    // Steps in traversal order: each box test of a node (of the instance hierarchy or of an octree),
    // visited or culled, and each triangle of a visible leaf; the whole image as one tile.
    // Defined at the end of the file, in a translation unit of its own.
    void render_steps(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                      hsr::sdk::Counters& counters, hsr::sdk::Steps& steps);

private:
    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());

        hsr::sdk::timed_build(counters, [&] { return prepare(scene); });

        const int32_t width = int32_t(camera.width), height = int32_t(camera.height);
        const int32_t size = Steps::enabled || tile_size_ == 0 ? std::max(width, height) : tile_size_;
        const int32_t across = (width + size - 1) / size, down = (height + size - 1) / size;
        const size_t count = size_t(across) * size_t(down);
        while (tiles_.size() < count) tiles_.push_back(std::make_unique<TileRenderer>(built_));
        auto tile = [&](size_t k) {
            PixelTile t;
            t.x0 = int32_t(k % size_t(across)) * size;
            t.y0 = int32_t(k / size_t(across)) * size;
            t.x1 = std::min(t.x0 + size, width) - 1;
            t.y1 = std::min(t.y0 + size, height) - 1;
            return t;
        };
        if (count == 1) {
            try {
                tiles_[0]->draw(scene, camera, target, cull_backfaces_, tile(0), geometry_.local(), steps);
            } catch (const hsr::sdk::StepLimitReached&) {
                report(counters, 1);
                throw;
            }
        } else {
            // Tiles own disjoint pixels and pyramids: nothing is shared but what was built.
            tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1), [&](const tbb::blocked_range<size_t>& range) {
                for (size_t k = range.begin(); k != range.end(); ++k) {
                    hsr::sdk::NoSteps no_steps;
                    tiles_[k]->draw(scene, camera, target, cull_backfaces_, tile(k), geometry_.local(), no_steps);
                }
            });
        }
        report(counters, count);
    }

    // The counters of the first `count` tiles, summed: a node or triangle that reaches several tiles
    // is counted in each.
    void report(hsr::sdk::Counters& counters, size_t count) const {
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

    // ------------------------------------------------------------------------------------------ //
    // Build (once per scene)

    // Builds what is missing for this scene; true when anything was built.
    bool prepare(const hsr::sdk::Scene& scene) {
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

    // Parameters
    bool cull_backfaces_;
    BuildParams build_params_;
    int32_t tile_size_;

    // Built once per scene
    bool has_built_ = false;
    hsr::sdk::SceneKey scene_key_;
    hsr::sdk::InstanceKey instance_key_;
    BuiltScene built_;
    std::map<std::array<uint32_t, 4>, uint32_t> object_of_range_;
    uint64_t drawn_triangles_ = 0;
    uint64_t non_finite_triangles_ = 0;

    // Per frame: one renderer per tile, one geometry stage per thread (both kept between frames).
    std::vector<std::unique_ptr<TileRenderer>> tiles_;
    tbb::enumerable_thread_specific<raster::GeometryStage> geometry_;
};

}  // namespace octree_zbuffer

// render_steps() is compiled apart: this file again with HSR_STEPS_UNIT defined (CMakeLists.txt),
// so that the drawing code it instantiates with hsr::sdk::Steps cannot change how the compiler
// inlines render()'s.
#ifdef HSR_STEPS_UNIT
void octree_zbuffer::OctreeZBuffer::render_steps(const hsr::sdk::Scene& scene, const hsr_camera& camera,
                                                 hsr::sdk::VisibilityBuffer& target, hsr::sdk::Counters& counters,
                                                 hsr::sdk::Steps& steps) {
    render_with(scene, camera, target, counters, steps);
}
#else
HSR_EXPORT_PLUGIN(octree_zbuffer::OctreeZBuffer)
#endif
