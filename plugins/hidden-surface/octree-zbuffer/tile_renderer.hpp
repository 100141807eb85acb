// The front-to-back traversal of the octree-zbuffer plugin over one screen tile (see
// octree_zbuffer.cpp for the algorithm and its source): the placement hierarchy and the objects'
// octrees, each node's box tested against the tile's own z-pyramid, then the triangles of visible
// leaves rejected by the pyramid as wholes, by 32x32 blocks and by 8x8 tiles, and drawn with the
// plain z-buffer's pixel loop. A TileRenderer draws only the pixels of its tile and reads and
// writes no other, so the tiles of one frame can be drawn at once, each by its own renderer.
// This file is over 700 lines: the traversal and its three levels of rejection (node box,
// triangle, tile) are one pass over shared per-tile state, read best in one place, and so are its
// steps, which describe that pass as it goes.
#pragma once

#include "octree.hpp"

#include "hsr/bounds.hpp"
#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"
#include "hsr/zpyramid.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

namespace octree_zbuffer {

namespace raster = hsr::raster;

// ---------------------------------------------------------------------------------------------- //

constexpr int32_t kTile = 8;  // tile-level rejection works on 8x8 tiles aligned to the image ...
constexpr int32_t kBlock = 32;  // ... inside 32x32 blocks, each tested first ...
constexpr int64_t kLargeTriangle = 4 * kBlock * kBlock;  // ... when the triangle's bounds exceed 4 blocks
// A triangle whose pixel bounds hold at most this many pixels is tested once, as a whole.
constexpr int64_t kSmallTriangle = 4 * kTile * kTile;

enum class BoxVisibility { kOutside, kHidden, kVisible };

struct Rect {
    int32_t x0 = std::numeric_limits<int32_t>::max(), y0 = std::numeric_limits<int32_t>::max();
    int32_t x1 = std::numeric_limits<int32_t>::min(), y1 = std::numeric_limits<int32_t>::min();
    bool empty() const { return x0 > x1; }
    void add(int32_t ax0, int32_t ay0, int32_t ax1, int32_t ay1) {
        x0 = std::min(x0, ax0);
        y0 = std::min(y0, ay0);
        x1 = std::max(x1, ax1);
        y1 = std::max(y1, ay1);
    }
};

// Which node a box test is about, for its step: "octree node" or "instance node", its index, and
// its depth in the octree (HSR_NO_LEVEL for the instance hierarchy).
struct NodeName {
    const char* what;
    uint32_t index;
    uint32_t depth;
};

struct FrameStats {
    uint64_t nodes_visited = 0, nodes_culled = 0, nodes_outside = 0, leaves_drawn = 0;
    uint64_t instance_nodes_visited = 0, instance_nodes_culled = 0, instance_nodes_outside = 0;
    uint64_t placements_visited = 0, leaves_deferred = 0;
    uint64_t triangles_in_culled_nodes = 0, triangles_in_outside_nodes = 0;
    uint64_t triangles_culled_before_setup = 0, triangles_culled_after_setup = 0;
    uint64_t tiles_tested = 0, tiles_culled = 0;
    uint64_t pixels_tested = 0, pixels_written = 0;
    uint64_t vertices_transformed = 0, pyramid_updates = 0;

    void add(const FrameStats& o) {
        nodes_visited += o.nodes_visited;
        nodes_culled += o.nodes_culled;
        nodes_outside += o.nodes_outside;
        leaves_drawn += o.leaves_drawn;
        instance_nodes_visited += o.instance_nodes_visited;
        instance_nodes_culled += o.instance_nodes_culled;
        instance_nodes_outside += o.instance_nodes_outside;
        placements_visited += o.placements_visited;
        leaves_deferred += o.leaves_deferred;
        triangles_in_culled_nodes += o.triangles_in_culled_nodes;
        triangles_in_outside_nodes += o.triangles_in_outside_nodes;
        triangles_culled_before_setup += o.triangles_culled_before_setup;
        triangles_culled_after_setup += o.triangles_culled_after_setup;
        tiles_tested += o.tiles_tested;
        tiles_culled += o.tiles_culled;
        pixels_tested += o.pixels_tested;
        pixels_written += o.pixels_written;
        vertices_transformed += o.vertices_transformed;
        pyramid_updates += o.pyramid_updates;
    }
};

// What the plugin built for a scene, which every tile reads and none writes.
struct BuiltScene {
    OctreeForest forest;
    std::vector<uint32_t> placement_object;  // per placement: index into forest.objects
    std::vector<InstanceNode> bvh;
    hsr_scene leaf_scene{};  // forest.mesh seen as a scene, for the geometry stage
};

// Image pixels [x0, x1] x [y0, y1], inclusive.
struct PixelTile {
    int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};

class TileRenderer {
public:
    explicit TileRenderer(const BuiltScene& built)
        : forest_(built.forest), placement_object_(built.placement_object), bvh_(built.bvh),
          leaf_scene_(built.leaf_scene) {}

    // Draws the scene's pixels inside `tile` into `target`, which the other tiles share, with
    // `geometry`: a geometry stage no other tile uses meanwhile (one per thread: its vertex buffers
    // are as long as the leaf mesh, too large to keep one per tile).
    template <class Steps>
    void draw(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
              bool cull_backfaces, const PixelTile& tile, raster::GeometryStage& geometry, Steps& steps) {
        cull_backfaces_ = cull_backfaces;
        tile_ = tile;
        geometry_ = &geometry;
        begin_frame(scene, camera, target);
        stats_ = FrameStats{};
        rasterized_unclipped_ = 0;
        struct Done {  // also when a step limit ends the frame early
            TileRenderer& tile;
            ~Done() {
                tile.triangle_stats_ = tile.geometry_->stats();
                tile.triangle_stats_.in += tile.rasterized_unclipped_;
                tile.triangle_stats_.rasterized += tile.rasterized_unclipped_;
                tile.geometry_ = nullptr;
            }
        } done{*this};
        if (bvh_.empty()) return;
        if (buffers_.tests == nullptr)
            draw_instances<false>(0, steps);
        else
            draw_instances<true>(0, steps);
    }

    const FrameStats& stats() const { return stats_; }
    raster::TriangleStats triangle_stats() const { return triangle_stats_; }

private:
    // ------------------------------------------------------------------------------------------ //
    // Per frame

    void begin_frame(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target) {
        scene_ = &scene;
        geometry_->begin_frame(leaf_scene_, camera, cull_backfaces_);
        // Serials run on across frames, so that no vertex counts as placed in a geometry stage that
        // another tile may have used since.
        if (placed_by_.size() != leaf_scene_.vertex_count) placed_by_.assign(leaf_scene_.vertex_count, 0u);
        pyramid_.reset_window(tile_.x0, tile_.y0, uint32_t(tile_.x1 - tile_.x0 + 1), uint32_t(tile_.y1 - tile_.y0 + 1),
                              camera.width);
        view_projection_ = glm::dmat4(hsr::sdk::load_matrix(camera.view_projection));
        perspective_ = camera.projection_type == HSR_PROJECTION_PERSPECTIVE;
        // The eye and the direction toward the viewer, from the view matrix (world = inverse(view) * eye).
        const glm::dmat4 view(hsr::sdk::load_matrix(camera.view));
        const glm::dmat4 inverse_view = glm::inverse(view);
        eye_ = glm::dvec3(inverse_view[3]) / inverse_view[3][3];
        toward_viewer_ = glm::dvec3(view[0][2], view[1][2], view[2][2]);
        width_ = int32_t(camera.width);
        height_ = int32_t(camera.height);
        viewport_ = raster::Viewport(camera.width, camera.height);
        buffers_ = raster::PixelBuffers(target);
    }

    // The box's projection (hsr/bounds.hpp): outside the view volume (or between pixel centres),
    // hidden behind the pyramid, or possibly visible. A box reaching in front of the near plane (or
    // behind the eye) is always possibly visible.
    BoxVisibility test_box(const glm::dmat4& m, const float* lo, const float* hi) const {
        const raster::ProjectedBox box =
            raster::project_box(m, glm::dvec3(lo[0], lo[1], lo[2]), glm::dvec3(hi[0], hi[1], hi[2]), viewport_);
        if (box.outside != 0) return BoxVisibility::kOutside;
        if (!box.in_front) return BoxVisibility::kVisible;
        const raster::PixelRect r = box.pixel_centres(raster::kBoxPixelMargin, width_, height_);
        if (r.empty() || r.x1 < tile_.x0 || r.x0 > tile_.x1 || r.y1 < tile_.y0 || r.y0 > tile_.y1)
            return BoxVisibility::kOutside;
        const float nearest = float(box.nearest - raster::kBoxDepthMargin);
        return pyramid_.is_hidden(r.x0, r.y0, r.x1, r.y1, nearest) ? BoxVisibility::kHidden : BoxVisibility::kVisible;
    }

    // Where a box test is counted: the placement hierarchy's counters or the octrees'.
    struct BoxCounts {
        uint64_t &visited, &culled, &outside;
    };
    BoxCounts instance_node_counts() {
        return {stats_.instance_nodes_visited, stats_.instance_nodes_culled, stats_.instance_nodes_outside};
    }
    BoxCounts octree_node_counts() { return {stats_.nodes_visited, stats_.nodes_culled, stats_.nodes_outside}; }

    // test_box, counted: false (and the node's triangles counted as culled or outside) when nothing
    // in the box can show.
    // With steps, the test is one: `node` says which node it is.
    template <class Steps>
    bool box_may_show(const glm::dmat4& m, const float* lo, const float* hi, uint64_t triangles, BoxCounts counts,
                      Steps& steps, const NodeName& node) {
        ++counts.visited;
        const BoxVisibility visibility = test_box(m, lo, hi);
        if constexpr (Steps::enabled) node_step(steps, m, lo, hi, visibility, node, triangles);
        switch (visibility) {
            case BoxVisibility::kOutside:
                ++counts.outside;
                stats_.triangles_in_outside_nodes += triangles;
                return false;
            case BoxVisibility::kHidden:
                ++counts.culled;
                stats_.triangles_in_culled_nodes += triangles;
                return false;
            case BoxVisibility::kVisible: break;
        }
        return true;
    }

    // The top level: placements, nearest first.
    template <bool kCountTests, class Steps>
    void draw_instances(uint32_t index, Steps& steps) {
        const InstanceNode& node = bvh_[index];
        if (node.is_leaf()) {
            draw_placement<kCountTests>(node.first, steps);
            return;
        }
        if (!box_may_show(view_projection_, node.lo, node.hi, node.triangles, instance_node_counts(), steps,
                          NodeName{"instance node", index, HSR_NO_LEVEL}))
            return;
        const double toward = perspective_ ? double(node.split) - eye_[node.axis] : -toward_viewer_[node.axis];
        // toward >= 0: the eye is on the low side of the split (or looks from -axis): left first.
        const uint32_t first = toward >= 0.0 ? node.first : node.first + 1;
        draw_instances<kCountTests>(first, steps);
        draw_instances<kCountTests>(first == node.first ? node.first + 1 : node.first, steps);
    }

    struct PlacementFrame {
        hsr::sdk::Placement placement;
        glm::dmat4 clip_from_object;
        glm::dmat4 vertex_matrix;  // GeometryStage::clip_from_object, for its vertices
        glm::dvec3 eye;            // object space (perspective)
        glm::dvec3 toward_viewer;  // object space (orthographic)
        // (eye, 1) or (direction toward the viewer, 0) in object space, negated when the transform
        // mirrors: dot(LeafMesh::planes[t], viewer) > 0 for a triangle facing the camera.
        glm::vec4 viewer;
    };

    template <bool kCountTests, class Steps>
    void draw_placement(uint32_t k, Steps& steps) {
        ++stats_.placements_visited;
        const ObjectTree& object = forest_.objects[placement_object_[k]];
        if (!object.has_root) return;
        PlacementFrame frame;
        frame.placement = scene_->placement(k);
        double mirror = 1.0;
        glm::dvec3 viewer_direction = toward_viewer_;
        if (frame.placement.identity) {
            frame.clip_from_object = view_projection_;
            frame.eye = eye_;
            frame.toward_viewer = toward_viewer_;
        } else {
            const glm::dmat4 transform(frame.placement.transform);
            frame.clip_from_object = view_projection_ * transform;
            const glm::dmat4 inverse = glm::inverse(transform);
            const glm::dvec4 e = inverse * glm::dvec4(eye_, 1.0);
            frame.eye = glm::dvec3(e) / e.w;
            frame.toward_viewer = glm::transpose(glm::dmat3(transform)) * toward_viewer_;
            viewer_direction = glm::dmat3(inverse) * toward_viewer_;
            if (glm::determinant(glm::dmat3(transform)) < 0.0) mirror = -1.0;
        }
        frame.viewer = perspective_ ? glm::vec4(glm::dvec4(frame.eye, 1.0) * mirror)
                                    : glm::vec4(glm::dvec4(viewer_direction, 0.0) * mirror);
        frame.vertex_matrix = geometry_->clip_from_object(frame.placement);
        if (++placement_serial_ == 0) {  // wrapped: forget every stamp
            std::fill(placed_by_.begin(), placed_by_.end(), 0u);
            placement_serial_ = 1;
        }

        deferred_back_faces_.clear();
        deferred_leaves_.clear();
        draw_node<kCountTests>(frame, object.root, steps);
        draw_deferred<kCountTests>(frame, steps);
    }

    // What draw_leaf put off until the placement's front is in the pyramid: the back faces of the
    // leaves it drew (their vertices are still transformed: nothing else is placed over them before
    // the placement ends), then the leaves facing wholly away, box-tested again. On a closed
    // surface most of both are now hidden behind its front.
    template <bool kCountTests, class Steps>
    void draw_deferred(PlacementFrame& frame, Steps& steps) {
        const uint32_t instance_id = frame.placement.instance;
        const uint32_t* const faces = forest_.mesh.face.data();
        Rect written;
        for (const uint32_t t : deferred_back_faces_)
            draw_leaf_triangle<kCountTests>(t, faces[t], instance_id, written, steps);
        mark_written(written);
        for (const uint32_t index : deferred_leaves_) {
            const OctreeNode& node = forest_.nodes[index];
            if (!box_may_show(frame.clip_from_object, node.lo, node.hi, node.triangle_count, octree_node_counts(),
                              steps, NodeName{"octree node", index, node.depth}))
                continue;
            place_leaf(frame, node);
            Rect leaf_written;
            const uint32_t end = node.first_triangle + node.triangle_count;
            for (uint32_t t = node.first_triangle; t < end; ++t)
                draw_leaf_triangle<kCountTests>(t, faces[t], instance_id, leaf_written, steps);
            mark_written(leaf_written);
        }
    }

    // The vertices of a leaf that no leaf drawn before for this placement has placed.
    void place_leaf(const PlacementFrame& frame, const OctreeNode& node) {
        ++stats_.leaves_drawn;
        const uint32_t* const vertices = forest_.mesh.leaf_vertices.data() + node.first_vertex;
        uint32_t placed = 0;
        for (uint32_t k = 0; k < node.vertex_count; ++k) {
            const uint32_t v = vertices[k];
            if (placed_by_[v] == placement_serial_) continue;
            placed_by_[v] = placement_serial_;
            geometry_->place_vertex(frame.vertex_matrix, v);
            ++placed;
        }
        stats_.vertices_transformed += placed;
    }

    // Deferred pyramid update: the cells over the rectangle are recomputed at the next large query
    // (hsr/zpyramid.hpp); valid because depths here only ever decrease.
    void mark_written(const Rect& written) {
        if (written.empty()) return;
        pyramid_.mark_dirty(buffers_.depth, written.x0, written.y0, written.x1, written.y1);
        ++stats_.pyramid_updates;
    }

    template <bool kCountTests, class Steps>
    void draw_node(PlacementFrame& frame, uint32_t index, Steps& steps) {
        const OctreeNode& node = forest_.nodes[index];
        if (!box_may_show(frame.clip_from_object, node.lo, node.hi, node.triangle_count, octree_node_counts(), steps,
                          NodeName{"octree node", index, node.depth}))
            return;
        if (node.is_leaf()) {
            draw_leaf<kCountTests>(frame, node, index, steps);
            return;
        }
        // Greene's order: the child octant holding the eye first, then those across one splitting
        // plane from it, ...; octant (eye ^ k) for k = 0..7 never draws a cell before one that lies
        // between it and the eye.
        int eye_octant;
        if (perspective_)
            eye_octant = (frame.eye.x > node.split[0] ? 1 : 0) | (frame.eye.y > node.split[1] ? 2 : 0) |
                         (frame.eye.z > node.split[2] ? 4 : 0);
        else
            eye_octant = (frame.toward_viewer.x > 0.0 ? 1 : 0) | (frame.toward_viewer.y > 0.0 ? 2 : 0) |
                         (frame.toward_viewer.z > 0.0 ? 4 : 0);
        const uint32_t mask = node.child_mask, first_child = node.first_child;
        for (int k = 0; k < 8; ++k) {
            const int octant = eye_octant ^ k;
            if (!(mask & (1u << octant))) continue;
            draw_node<kCountTests>(frame, first_child + uint32_t(std::popcount(mask & ((1u << octant) - 1u))), steps);
        }
    }

    // A visible leaf: its front faces now; its back faces, which a closed surface hides behind its
    // front, once the whole placement's front is drawn (draw_deferred), when the pyramid rejects
    // most of them before setup instead of after rasterizing them; a leaf with no front face is put
    // off whole, before its vertices are transformed. Any order gives the same picture (see the tie
    // rule in fill); facing is judged in object space from the leaf mesh's planes.
    template <bool kCountTests, class Steps>
    void draw_leaf(PlacementFrame& frame, const OctreeNode& node, uint32_t index, Steps& steps) {
        const uint32_t end = node.first_triangle + node.triangle_count;
        const glm::vec4* const planes = forest_.mesh.planes.data();
        uint32_t front = 0;
        for (uint32_t t = node.first_triangle; t < end; ++t) front += glm::dot(planes[t], frame.viewer) > 0.0f;
        if (front == 0) {
            ++stats_.leaves_deferred;
            deferred_leaves_.push_back(index);
            return;
        }
        place_leaf(frame, node);
        Rect written;
        const uint32_t instance_id = frame.placement.instance;
        const uint32_t* const faces = forest_.mesh.face.data();
        for (uint32_t t = node.first_triangle; t < end; ++t) {
            if (glm::dot(planes[t], frame.viewer) > 0.0f)
                draw_leaf_triangle<kCountTests>(t, faces[t], instance_id, written, steps);
            else
                deferred_back_faces_.push_back(t);
        }
        mark_written(written);
    }

    template <bool kCountTests, class Steps>
    void draw_leaf_triangle(uint32_t t, uint32_t id, uint32_t instance_id, Rect& written, Steps& steps) {
        if constexpr (Steps::enabled) begin_triangle_step();
        raster::TriangleSetup setup;
        Rect mine;
        switch (test_triangle(forest_.mesh.indices.data() + 3 * size_t(t), setup, steps)) {
            case TriangleVisibility::kHidden:
                ++stats_.triangles_culled_before_setup;
                if constexpr (Steps::enabled) triangle_step(steps, t, id, instance_id);
                return;
            case TriangleVisibility::kOffTile: return;
            case TriangleVisibility::kSetUp:
                ++rasterized_unclipped_;
                if (!draw_triangle<kCountTests>(setup, id, instance_id, true, mine, steps))
                    ++stats_.triangles_culled_after_setup;
                if constexpr (Steps::enabled) triangle_step(steps, t, id, instance_id);
                mark_triangle_written(mine, written);
                return;
            case TriangleVisibility::kUntested: break;
        }
        uint32_t pieces = 0, culled = 0;
        geometry_->process(t, [&](const raster::TriangleSetup& s) {
            ++pieces;
            if (!draw_triangle<kCountTests>(s, id, instance_id, false, mine, steps)) ++culled;
        });
        if (pieces > 0 && culled == pieces) ++stats_.triangles_culled_after_setup;
        if constexpr (Steps::enabled) triangle_step(steps, t, id, instance_id);
        mark_triangle_written(mine, written);
    }

    void mark_triangle_written(const Rect& mine, Rect& written) {
        if (!mine.empty()) {
            // A large triangle's cells are marked at once: the leaf's next large triangles (a box's
            // back faces behind its front) are then rejected by the block test on fresh cells,
            // instead of tile by tile on the fine depths. Small ones wait for the end of the leaf.
            if (int64_t(mine.x1 - mine.x0 + 1) * (mine.y1 - mine.y0 + 1) > kBlock * kBlock) {
                pyramid_.mark_dirty(buffers_.depth, mine.x0, mine.y0, mine.x1, mine.y1);
                ++stats_.pyramid_updates;
            } else {
                written.add(mine.x0, mine.y0, mine.x1, mine.y1);
            }
        }
    }

    // Window depth held to [0, 1] over the pixel-centre rectangle [x0,x1]x[y0,y1] of a setup: its
    // smallest value over the rectangle is at a corner (depth_at is monotone in i and in j, rounding
    // included), so this is exactly the nearest depth any covered pixel there can get.
    static float nearest_depth(const raster::TriangleSetup& s, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
        const double i0 = x0 - s.min_x, i1 = x1 - s.min_x, j0 = y0 - s.min_y, j1 = y1 - s.min_y;
        return std::min(std::min(raster::depth_at(s, i0, j0), raster::depth_at(s, i1, j0)),
                        std::min(raster::depth_at(s, i0, j1), raster::depth_at(s, i1, j1)));
    }

    // Greene's triangle-level rejection before triangle setup, for a triangle that needs no
    // clipping and that GeometryStage::process would set up (finite, not trivially outside, not
    // culled as a back face, pixel centres inside the image): its pixel bounds are those of the
    // setup, and its nearest depth a bound no covered pixel goes below. The depth plane is set up
    // through the unsnapped corners, and covered pixel centres lie in the triangle of the snapped
    // ones (each corner moved by at most 1/512 pixel in x and y), so the depth there is at least
    // the smallest corner depth minus (|dz/dx| + |dz/dy|) / 512; rounded down to float, a covered
    // pixel's float depth cannot be smaller. A triangle the pyramid does not reject is set up here
    // (kSetUp: `setup` is what process() would emit), from the bounds found for the test.
    // kOffTile: none of its pixels is in this tile. kUntested: process() it.
    enum class TriangleVisibility { kUntested, kHidden, kSetUp, kOffTile };
    template <class Steps>
    TriangleVisibility test_triangle(const uint32_t* corner, raster::TriangleSetup& setup, Steps&) {
        const uint32_t i0 = corner[0], i1 = corner[1], i2 = corner[2];
        const uint32_t c0 = geometry_->vertex_outcode(i0), c1 = geometry_->vertex_outcode(i1),
                       c2 = geometry_->vertex_outcode(i2);
        if (((c0 | c1 | c2) & (raster::kNeedsClipping | raster::kNonFinite)) || (c0 & c1 & c2 & raster::kOutsideAnyPlane))
            return TriangleVisibility::kUntested;
        if (cull_backfaces_ && !raster::is_front_facing(geometry_->clip_vertex(i0), geometry_->clip_vertex(i1),
                                                        geometry_->clip_vertex(i2)))
            return TriangleVisibility::kUntested;
        const raster::WindowVertex& v0 = geometry_->window_vertex(i0);
        const raster::WindowVertex& v1 = geometry_->window_vertex(i1);
        const raster::WindowVertex& v2 = geometry_->window_vertex(i2);
        // raster::triangle_pixel_bounds, inlined: kOk, or process() counts the triangle.
        if (int64_t(v1.x - v0.x) * (v2.y - v0.y) - int64_t(v2.x - v0.x) * (v1.y - v0.y) == 0)
            return TriangleVisibility::kUntested;
        raster::PixelBounds b;
        b.min_x = std::max(raster::first_pixel_from(std::min(std::min(v0.x, v1.x), v2.x)), 0);
        b.max_x = std::min(raster::last_pixel_to(std::max(std::max(v0.x, v1.x), v2.x)), width_ - 1);
        b.min_y = std::max(raster::first_pixel_from(std::min(std::min(v0.y, v1.y), v2.y)), 0);
        b.max_y = std::min(raster::last_pixel_to(std::max(std::max(v0.y, v1.y), v2.y)), height_ - 1);
        if (b.min_x > b.max_x || b.min_y > b.max_y) return TriangleVisibility::kUntested;
        if (b.max_x < tile_.x0 || b.min_x > tile_.x1 || b.max_y < tile_.y0 || b.min_y > tile_.y1)
            return TriangleVisibility::kOffTile;
        // The depth gradient of the unsnapped triangle.
        const double ax = v1.exact_x - v0.exact_x, ay = v1.exact_y - v0.exact_y;
        const double bx = v2.exact_x - v0.exact_x, by = v2.exact_y - v0.exact_y;
        const double da = v1.depth - v0.depth, db = v2.depth - v0.depth;
        const double area = ax * by - bx * ay;
        const double slope = (std::abs(da * by - db * ay) + std::abs(db * ax - da * bx)) / std::abs(area);
        // (the last term covers rounding in the setup's plane equations, far below float precision)
        const double bound = std::min(std::min(v0.depth, v1.depth), v2.depth) - slope * (1.0 / 512.0) -
                             (1e-9 + 1e-12 * slope * double(raster::kMaxImageSize));
        if (bound > 0.0) {  // else (also NaN, a sliver) it cannot tell
            float nearest = float(std::min(bound, 1.0));
            if (double(nearest) > bound)  // rounded up: take the next float down (nearest > bound > 0)
                nearest = std::bit_cast<float>(std::bit_cast<uint32_t>(nearest) - 1u);
            if constexpr (Steps::enabled) step_.query = {b.min_x, b.min_y, b.max_x, b.max_y, nearest, true};
            if (pyramid_.is_hidden(b.min_x, b.min_y, b.max_x, b.max_y, nearest)) return TriangleVisibility::kHidden;
        }
        raster::setup_triangle_in_bounds(v0, v1, v2, raster::kWholeTriangleB1, raster::kWholeTriangleB2, b, setup);
        return TriangleVisibility::kSetUp;
    }

    // Greene's triangle-level (unless done before setup) and tile-level rejection, then the pixel
    // loop. False when the whole piece was rejected by the pyramid.
    template <bool kCountTests, class Steps>
    bool draw_triangle(const raster::TriangleSetup& s, uint32_t id, uint32_t instance_id, bool tested, Rect& written,
                       Steps& steps) {
        if constexpr (Steps::enabled) {
            step_.box.add(s.min_x, s.min_y, s.max_x, s.max_y);
            if (!tested)
                step_.query = {s.min_x, s.min_y, s.max_x, s.max_y, nearest_depth(s, s.min_x, s.min_y, s.max_x, s.max_y),
                               true};
        }
        // The setup's bounds within this tile.
        const int32_t min_x = std::max(s.min_x, tile_.x0), max_x = std::min(s.max_x, tile_.x1);
        const int32_t min_y = std::max(s.min_y, tile_.y0), max_y = std::min(s.max_y, tile_.y1);
        if (min_x > max_x || min_y > max_y) return true;
        if (!tested && pyramid_.is_hidden(min_x, min_y, max_x, max_y, nearest_depth(s, min_x, min_y, max_x, max_y)))
            return false;
        const int64_t area = int64_t(max_x - min_x + 1) * (max_y - min_y + 1);
        if (area <= kSmallTriangle) {
            if (fill<kCountTests>(s, min_x, min_y, max_x, max_y, id, instance_id) > 0)
                written.add(min_x, min_y, max_x, max_y);
            return true;
        }
        if (area <= kLargeTriangle) {
            draw_tiles<kCountTests>(s, min_x, min_y, max_x, max_y, id, instance_id, written, steps);
            return true;
        }
        // A large triangle goes in two levels: blocks of kBlock x kBlock pixels first, then the
        // tiles of a block that is not hidden as a whole.
        for (int32_t by = min_y & ~(kBlock - 1); by <= max_y; by += kBlock) {
            const int32_t y0 = std::max(by, min_y), y1 = std::min(by + kBlock - 1, max_y);
            for (int32_t bx = min_x & ~(kBlock - 1); bx <= max_x; bx += kBlock) {
                const int32_t x0 = std::max(bx, min_x), x1 = std::min(bx + kBlock - 1, max_x);
                if (raster::misses(s, x0, y0, x1, y1)) continue;
                ++stats_.tiles_tested;
                if (pyramid_.is_hidden(x0, y0, x1, y1, nearest_depth(s, x0, y0, x1, y1))) {
                    ++stats_.tiles_culled;
                    if constexpr (Steps::enabled)
                        steps.box(float(x0), float(y0), float(x1 + 1), float(y1 + 1), HSR_STEP_REJECTED);
                    continue;
                }
                draw_tiles<kCountTests>(s, x0, y0, x1, y1, id, instance_id, written, steps);
            }
        }
        return true;
    }

    // The kTile x kTile tiles of [x0,x1]x[y0,y1] (inside the setup's bounds), each tested against the
    // pyramid before its pixels are.
    template <bool kCountTests, class Steps>
    void draw_tiles(const raster::TriangleSetup& s, int32_t x0, int32_t y0, int32_t x1, int32_t y1, uint32_t id,
                    uint32_t instance_id, Rect& written, Steps& steps) {
        for (int32_t ty = y0 & ~(kTile - 1); ty <= y1; ty += kTile) {
            const int32_t tile_y0 = std::max(ty, y0), tile_y1 = std::min(ty + kTile - 1, y1);
            for (int32_t tx = x0 & ~(kTile - 1); tx <= x1; tx += kTile) {
                const int32_t tile_x0 = std::max(tx, x0), tile_x1 = std::min(tx + kTile - 1, x1);
                if (raster::misses(s, tile_x0, tile_y0, tile_x1, tile_y1)) continue;
                ++stats_.tiles_tested;
                if (pyramid_.is_hidden(tile_x0, tile_y0, tile_x1, tile_y1,
                                       nearest_depth(s, tile_x0, tile_y0, tile_x1, tile_y1))) {
                    ++stats_.tiles_culled;
                    if constexpr (Steps::enabled)
                        steps.box(float(tile_x0), float(tile_y0), float(tile_x1 + 1), float(tile_y1 + 1),
                                  HSR_STEP_REJECTED);
                    continue;
                }
                const uint64_t count =
                    raster::covers(s, tile_x0, tile_y0, tile_x1, tile_y1)
                        ? fill<kCountTests, true>(s, tile_x0, tile_y0, tile_x1, tile_y1, id, instance_id)
                        : fill<kCountTests>(s, tile_x0, tile_y0, tile_x1, tile_y1, id, instance_id);
                if (count > 0) written.add(tile_x0, tile_y0, tile_x1, tile_y1);
            }
        }
    }

    // The plain z-buffer's pixel loop (raster::DepthTest, as in zbuffer.cpp) over [x0,x1]x[y0,y1] of the
    // setup's bounds, with exact depth ties going to the surface the plain z-buffer draws first (lower
    // instance, then lower face), so the traversal order never shows. Returns the pixels written.
    // kAllCovered: every pixel of the rectangle is covered (the caller checked its corners).
    template <bool kCountTests, bool kAllCovered = false>
    uint64_t fill(const raster::TriangleSetup& s, int32_t x0, int32_t y0, int32_t x1, int32_t y1, uint32_t id,
                  uint32_t instance_id) {
        raster::DepthTest<raster::DepthRule::kNearerThenLowerId, kCountTests> test(buffers_, id, instance_id);
        raster::for_each_covered_pixel_in<kAllCovered>(
            s, x0, y0, x1, y1, [&](int32_t x, int32_t y, double i, double j) { test(s, x, y, i, j); });
        stats_.pixels_tested += test.tested;
        stats_.pixels_written += test.written;
        return test.written;
    }

    // ------------------------------------------------------------------------------------------ //
    // Steps (ABI 1.3)

    // A pyramid query, kept for the step that reports it.
    struct PyramidQuery {
        int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
        float nearest = 0.0f;
        bool made = false;
    };
    // What the step of the triangle being drawn shows, gathered while it is drawn.
    struct TriangleStep {
        FrameStats before;
        raster::TriangleStats geometry_before;
        PyramidQuery query;  // its test against the pyramid (of its last clipped piece, if clipped)
        Rect box;            // the pixel bounds of its setups
    };

    void begin_triangle_step() {
        step_.before = stats_;
        step_.geometry_before = geometry_->stats();
        step_.query = {};
        step_.box = Rect{};
    }

    // The outline of the pixels [x0, x1] x [y0, y1] clipped to the image.
    template <class Steps>
    void add_box(Steps& steps, int32_t x0, int32_t y0, int32_t x1, int32_t y1, hsr_step_role role) const {
        raster::pixel_box_lines(steps, x0, y0, x1, y1, width_, height_, role);
    }

    // A triangle's outline (corners of the leaf mesh), when it needs no clipping and lies within a
    // pixel of the image.
    template <class Steps>
    void add_outline(Steps& steps, const uint32_t* corner) const {
        geometry_->outline_lines(steps, corner);
    }

    // The step of a node's box test: visited (its screen box SUBJECT) or culled (REJECTED), and why.
    // The box is projected again as test_box projects it.
    template <class Steps>
    void node_step(Steps& steps, const glm::dmat4& m, const float* lo, const float* hi, BoxVisibility visibility,
                   const NodeName& node, uint64_t triangles) const {
        const raster::ProjectedBox box =
            raster::project_box(m, glm::dvec3(lo[0], lo[1], lo[2]), glm::dvec3(hi[0], hi[1], hi[2]), viewport_);
        const bool projected = box.outside == 0 && box.in_front;
        raster::PixelRect r;
        float nearest = 0.0f;
        if (projected) {
            r = box.pixel_centres(raster::kBoxPixelMargin, width_, height_);
            nearest = float(box.nearest - raster::kBoxDepthMargin);
        }
        const bool ru = steps.russian();
        const unsigned long long n = triangles;
        char name[128];
        if (ru) {
            const bool octree = std::strcmp(node.what, "octree node") == 0;
            const char* const triangle_word = hsr::sdk::russian_plural(n, "треугольник", "треугольника", "треугольников");
            if (node.depth == HSR_NO_LEVEL)
                std::snprintf(name, sizeof name, "%s %u (%llu %s)", octree ? "узел октодерева" : "узел иерархии экземпляров",
                              node.index, n, triangle_word);
            else
                std::snprintf(name, sizeof name, "%s %u (глубина %u, %llu %s)",
                              octree ? "узел октодерева" : "узел иерархии экземпляров", node.index, node.depth, n,
                              triangle_word);
        } else if (node.depth == HSR_NO_LEVEL) {
            std::snprintf(name, sizeof name, "%s %u (%llu triangles)", node.what, node.index, n);
        } else {
            std::snprintf(name, sizeof name, "%s %u (depth %u, %llu triangles)", node.what, node.index, node.depth, n);
        }
        pyramid_.add_step_buffers(steps);
        char where[64];
        switch (visibility) {
            case BoxVisibility::kOutside: {
                if (projected) add_box(steps, r.x0, r.y0, r.x1, r.y1, HSR_STEP_REJECTED);
                hsr::sdk::Steps::Event event{"node-culled"};
                event.phase = "node-outside";
                steps.step(event, ru ? "%s: вне области видимости, отсечён" : "%s: outside the view, culled", name);
                return;
            }
            case BoxVisibility::kHidden: {
                const int level = pyramid_.answering_level(r.x0, r.y0, r.x1, r.y1, nearest, true);
                pyramid_.describe_level(level, where, ru);
                add_box(steps, r.x0, r.y0, r.x1, r.y1, HSR_STEP_REJECTED);
                hsr::sdk::Steps::Event event{"node-culled", HSR_NO_FACE, 0, uint32_t(level)};
                event.phase = "node-hidden";
                steps.step(event, ru ? "%s: закрыт z-пирамидой на %s, отсечён"
                                     : "%s: hidden behind the z-pyramid at %s, culled", name, where);
                return;
            }
            case BoxVisibility::kVisible: break;
        }
        if (!projected) {
            hsr::sdk::Steps::Event event{"node-visited"};
            event.phase = "node-visit";
            steps.step(event, ru ? "%s: выходит за ближнюю плоскость отсечения, обходим"
                                 : "%s: reaches in front of the near plane, visited", name);
            return;
        }
        const int level = pyramid_.answering_level(r.x0, r.y0, r.x1, r.y1, nearest, false);
        pyramid_.describe_level(level, where, ru);
        add_box(steps, r.x0, r.y0, r.x1, r.y1, HSR_STEP_SUBJECT);
        hsr::sdk::Steps::Event event{"node-visited", HSR_NO_FACE, 0, uint32_t(level)};
        event.phase = "node-visit";
        steps.step(event, ru ? "%s: не закрыт z-пирамидой на %s, обходим" : "%s: not hidden at z-pyramid %s, visited",
                   name, where);
    }

    // The step of leaf-mesh triangle t (scene triangle `face`), from what drawing it counted
    // (stats_, the geometry stage's counts) and gathered (step_). Its phase is the last line of the
    // pseudocode it reached (docs/theory/en/octree-zbuffer.md).
    template <class Steps>
    void triangle_step(Steps& steps, uint32_t t, uint32_t face, uint32_t instance) {
        using hsr::sdk::russian_plural;
        const FrameStats& b = step_.before;
        const PyramidQuery& q = step_.query;
        const raster::TriangleStats after = geometry_->stats();
        const raster::TriangleStats& before = step_.geometry_before;
        const uint64_t tested = stats_.pixels_tested - b.pixels_tested;
        const uint64_t written = stats_.pixels_written - b.pixels_written;
        const unsigned f = face;
        const bool ru = steps.russian();
        const uint32_t* const corner = forest_.mesh.indices.data() + 3 * size_t(t);
        pyramid_.add_step_buffers(steps);
        char where[64];
        if (stats_.triangles_culled_before_setup != b.triangles_culled_before_setup ||
            stats_.triangles_culled_after_setup != b.triangles_culled_after_setup) {
            const int level = pyramid_.answering_level(q.x0, q.y0, q.x1, q.y1, q.nearest, true);
            pyramid_.describe_level(level, where, ru);
            add_outline(steps, corner);
            add_box(steps, q.x0, q.y0, q.x1, q.y1, HSR_STEP_REJECTED);
            hsr::sdk::Steps::Event event{"triangle", face, instance, uint32_t(level)};
            event.phase = "pyramid-test";
            steps.step(event, ru ? "треугольник %u: отброшен z-пирамидой на %s"
                                 : "triangle %u: rejected by the z-pyramid at %s", f, where);
            return;
        }
        if (raster::dropped_triangle_step(steps, before, after, face, instance)) return;
        add_outline(steps, corner);
        if (!step_.box.empty())
            add_box(steps, step_.box.x0, step_.box.y0, step_.box.x1, step_.box.y1, HSR_STEP_WRITTEN);
        char tiles[96] = "";
        const uint64_t tiles_culled = stats_.tiles_culled - b.tiles_culled;
        if (stats_.tiles_tested != b.tiles_tested) {
            const unsigned long long c = tiles_culled, n = stats_.tiles_tested - b.tiles_tested;
            if (ru)
                std::snprintf(tiles, sizeof tiles, "; z-пирамида отсекла %llu из %llu %s", c, n,
                              russian_plural(n, "плитки", "плиток", "плиток"));
            else
                std::snprintf(tiles, sizeof tiles, "; %u of %u tiles culled by the z-pyramid", unsigned(c), unsigned(n));
        }
        const uint32_t level =
            q.made ? uint32_t(pyramid_.answering_level(q.x0, q.y0, q.x1, q.y1, q.nearest, false)) : HSR_NO_LEVEL;
        hsr::sdk::Steps::Event event{"triangle", face, instance, level, written, tested - written};
        event.phase = written > 0        ? "write"
                      : tested > 0       ? "depth-test"
                      : tiles_culled > 0 ? "pyramid-test"
                                         : "rasterize";
        char drawn[256];
        const unsigned long long w = written, r = tested - written;
        if (tested == 0 && tiles[0] == '\0')
            std::snprintf(drawn, sizeof drawn, "%s",
                          ru ? "не покрывает ни одного центра пикселя" : "covers no pixel centre");
        else if (ru)
            std::snprintf(drawn, sizeof drawn, "нарисован: %s %llu %s, %s тестом глубины %llu%s",
                          russian_plural(w, "записан", "записано", "записано"), w,
                          russian_plural(w, "пиксель", "пикселя", "пикселей"),
                          russian_plural(r, "отброшен", "отброшено", "отброшено"), r, tiles);
        else
            std::snprintf(drawn, sizeof drawn, "drawn: %u pixel%s written, %u rejected by the depth test%s",
                          unsigned(written), written == 1 ? "" : "s", unsigned(tested - written), tiles);
        if (!q.made) {
            steps.step(event, ru ? "треугольник %u: %s" : "triangle %u: %s", f, drawn);
            return;
        }
        pyramid_.describe_level(int(level), where, ru);
        steps.step(event, ru ? "треугольник %u: не закрыт z-пирамидой на %s, %s"
                             : "triangle %u: not hidden at z-pyramid %s, %s", f, where, drawn);
    }

    TriangleStep step_;  // with steps only

    // Built once per scene
    const OctreeForest& forest_;
    const std::vector<uint32_t>& placement_object_;
    const std::vector<InstanceNode>& bvh_;
    const hsr_scene& leaf_scene_;

    // Per frame
    bool cull_backfaces_ = false;
    PixelTile tile_;
    raster::GeometryStage* geometry_ = nullptr;  // the drawing thread's, for the time of draw()
    raster::TriangleStats triangle_stats_;        // what geometry_ counted for this tile, and test_triangle
    uint64_t rasterized_unclipped_ = 0;           // triangles test_triangle set up, not geometry_
    raster::ZPyramid pyramid_;
    FrameStats stats_;
    const hsr::sdk::Scene* scene_ = nullptr;
    glm::dmat4 view_projection_{1.0};
    glm::dvec3 eye_{0.0}, toward_viewer_{0.0, 0.0, 1.0};
    bool perspective_ = true;
    int32_t width_ = 0, height_ = 0;
    raster::Viewport viewport_;
    raster::PixelBuffers buffers_;
    // Of the placement being drawn, for draw_deferred; kept to avoid allocating per placement.
    std::vector<uint32_t> deferred_back_faces_;  // triangles of LeafMesh
    std::vector<uint32_t> deferred_leaves_;      // node indices
    // Per LeafMesh vertex: the serial of the placement (counted across frames) that last placed it
    // in geometry_.
    std::vector<uint32_t> placed_by_;
    uint32_t placement_serial_ = 0;
};

}  // namespace octree_zbuffer
