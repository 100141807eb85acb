// The scene as the appel plugin's walk looks it up, computed once per call from the scene and the
// camera: the edge graph, every vertex in world space (double precision) and in the window, each
// face's plane and box, the contour edges (steps 2-4 of docs/algorithms/appel.md), and the grids
// that find the contour edges and faces near an edge or a vertex.
#pragma once

#include "grids.hpp"
#include "mesh_graph.hpp"
#include "sight.hpp"

#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace appel {

struct ContourEdge {
    uint32_t v0, v1;
    int32_t weight;  // faces on the positive side of the sight plane minus faces on its negative side
    uint32_t face;   // a face of the edge, for the trace
    SightPlane plane;
};

struct FaceBox {
    glm::vec3 low, high;
};

class ViewGeometry {
public:
    // Throws hsr::sdk::InvalidArgument when the grids would hold more than max_grid_entries entries
    // together, before storing them.
    void build(const hsr_scene& scene, const hsr_camera& camera, const Viewer& viewer, uint64_t max_grid_entries) {
        camera_ = &camera;
        graph.build(scene);
        prepare_vertices(scene, camera);
        prepare_faces(viewer);
        find_contours(viewer);
        build_grids(max_grid_entries);
    }

    // The window position of the point at parameter t along the edge from `from` to `to`.
    glm::dvec2 window_at(uint32_t from, uint32_t to, double t) const {
        if (t <= 0.0) return window[from];
        if (t >= 1.0) return window[to];
        return window_of(position[from] + t * (position[to] - position[from]));
    }

    MeshGraph graph;
    std::vector<glm::dvec3> position;
    std::vector<glm::dvec2> window;
    std::vector<FacePlane> face_plane;
    std::vector<FaceBox> face_box;
    std::vector<ContourEdge> contours;
    ImageGrid contour_grid, face_grid;  // contour edges, faces on the screen
    SpaceGrid space_grid;               // faces in space
    Bins contour_bins, face_bins, space_bins;
    uint64_t grid_entries = 0;  // held by the three

private:
    // World positions in double precision and window positions; every vertex a face uses must be
    // finite and, for a perspective camera, in front of the eye.
    void prepare_vertices(const hsr_scene& scene, const hsr_camera& camera) {
        const uint32_t n = graph.vertex_count();
        position.resize(n);
        window.resize(n);
        view_projection_ = glm::dmat4(hsr::sdk::load_matrix(camera.view_projection));
        const bool perspective = camera.projection_type == HSR_PROJECTION_PERSPECTIVE;
        for (uint32_t v = 0; v < n; ++v) {
            position[v] = {scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]};
            if (graph.faces_at(v).empty()) {
                window[v] = glm::dvec2(0.0);
                continue;
            }
            if (!std::isfinite(position[v].x) || !std::isfinite(position[v].y) || !std::isfinite(position[v].z))
                throw hsr::sdk::InvalidArgument("appel: vertex " + std::to_string(v) + " has a position that is not finite");
            const glm::dvec4 clip = view_projection_ * glm::dvec4(position[v], 1.0);
            if (perspective && !(clip.w > 0.0))
                throw hsr::sdk::InvalidArgument("appel: vertex " + std::to_string(v) +
                                                " is not in front of the eye; with a perspective camera every vertex "
                                                "must be (move the camera out of the scene)");
            window[v] = to_window(clip);
        }
    }

    glm::dvec2 to_window(const glm::dvec4& clip) const {
        return {(clip.x / clip.w + 1.0) * 0.5 * camera_->width, (1.0 - clip.y / clip.w) * 0.5 * camera_->height};
    }
    glm::dvec2 window_of(const glm::dvec3& p) const { return to_window(view_projection_ * glm::dvec4(p, 1.0)); }

    void prepare_faces(const Viewer& viewer) {
        face_plane.resize(graph.face_count());
        face_box.resize(graph.face_count());
        constexpr float kWiden = 1.0f / (1 << 21), kTiny = 1e-30f;
        for (uint32_t f = 0; f < graph.face_count(); ++f) {
            const glm::dvec3 &a = position[graph.corner(f, 0)], &b = position[graph.corner(f, 1)],
                             &c = position[graph.corner(f, 2)];
            face_plane[f] = appel::face_plane(viewer, a, b, c);
            // Widened by more than a float's rounding, so that the float box holds the face.
            const glm::vec3 low(glm::min(a, glm::min(b, c))), high(glm::max(a, glm::max(b, c)));
            face_box[f].low = low - glm::abs(low) * kWiden - kTiny;
            face_box[f].high = high + glm::abs(high) * kWiden + kTiny;
        }
    }

    // Contour edges: those whose faces do not lie equally on both sides of the plane through the eye
    // and the edge. A silhouette edge has both faces on one side (weight +-2), a boundary edge its one
    // face (+-1); an ordinary edge one on each side (0, not a contour).
    void find_contours(const Viewer& viewer) {
        contours.clear();
        for (uint32_t e = 0; e < graph.edge_count(); ++e) {
            const uint32_t a = graph.edge_vertex(e, 0), b = graph.edge_vertex(e, 1);
            const SightPlane plane = sight_plane(viewer, a, position[a], b, position[b]);
            int32_t weight = 0;
            for (int side = 0; side < 2; ++side) {
                const uint32_t f = graph.edge_face(e, side);
                if (f == HSR_NO_FACE || face_plane[f].eye_side == 0) continue;
                weight += plane.side(position[graph.third_corner(f, a, b)]);
            }
            if (weight != 0) contours.push_back({a, b, weight, graph.edge_face(e, 0), plane});
        }
    }

    // The grids are framed and their entries counted (from each item's extent in cells) before any
    // is filled, so that too many are refused before they are stored.
    void build_grids(uint64_t max_entries) {
        // Contour edges on the screen, for the crossing tests.
        if (!contours.empty()) {
            glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
            for (const ContourEdge& c : contours) {
                lo = glm::min(lo, glm::min(window[c.v0], window[c.v1]));
                hi = glm::max(hi, glm::max(window[c.v0], window[c.v1]));
            }
            contour_grid.frame(lo, hi, 2.0 * double(contours.size()), kPadPixels);
        }
        // Faces on the screen, for counting what hides a seed vertex; faces in space, for the faces
        // an edge passes through (bodies that intersect).
        glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        glm::dvec3 world_lo(std::numeric_limits<double>::max()), world_hi(-std::numeric_limits<double>::max());
        double edge_length = 0.0;
        for (uint32_t v = 0; v < graph.vertex_count(); ++v) {
            if (graph.faces_at(v).empty()) continue;
            lo = glm::min(lo, window[v]);
            hi = glm::max(hi, window[v]);
            world_lo = glm::min(world_lo, position[v]);
            world_hi = glm::max(world_hi, position[v]);
        }
        for (uint32_t e = 0; e < graph.edge_count(); ++e)
            edge_length += glm::length(position[graph.edge_vertex(e, 1)] - position[graph.edge_vertex(e, 0)]);
        const bool faces = graph.face_count() > 0;
        if (faces) {
            face_grid.frame(lo, hi, std::max(1.0, graph.face_count() / 2.0), kPadPixels);
            const double mean_edge = graph.edge_count() > 0 ? edge_length / graph.edge_count() : 0.0;
            const double extent = glm::length(world_hi - world_lo);
            space_grid.frame(world_lo, world_hi, mean_edge, 1e-9 * extent, 4.0 * graph.face_count());
        }
        const auto screen_box = [&](uint32_t f, auto&& use) {
            const glm::dvec2 a = window[graph.corner(f, 0)], b = window[graph.corner(f, 1)], c = window[graph.corner(f, 2)];
            return use(glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c)));
        };
        const auto space_box = [&](uint32_t f, auto&& use) {
            const glm::dvec3 &a = position[graph.corner(f, 0)], &b = position[graph.corner(f, 1)], &c = position[graph.corner(f, 2)];
            return use(glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c)));
        };

        uint64_t largest = 0;  // entries of one grid, which indexes them with 32 bits
        grid_entries = 0;
        {
            uint64_t n = 0;
            for (const ContourEdge& c : contours) n += contour_grid.segment_cells(window[c.v0], window[c.v1]);
            largest = std::max(largest, n);
            grid_entries += n;
        }
        if (faces) {
            uint64_t on_screen = 0, in_space = 0;
            for (uint32_t f = 0; f < graph.face_count(); ++f) {
                on_screen += screen_box(f, [&](glm::dvec2 l, glm::dvec2 h) { return face_grid.box_cells(l, h); });
                in_space += space_box(f, [&](glm::dvec3 l, glm::dvec3 h) { return space_grid.box_cells(l, h); });
            }
            largest = std::max({largest, on_screen, in_space});
            grid_entries += on_screen + in_space;
        }
        if (grid_entries > max_entries || largest > std::numeric_limits<uint32_t>::max())
            throw hsr::sdk::InvalidArgument("appel: the grids of the edges and faces seen would hold " +
                                            std::to_string(grid_entries) + " entries, over the limit of " +
                                            std::to_string(std::min<uint64_t>(max_entries, std::numeric_limits<uint32_t>::max())) +
                                            " (raise it with max-candidates=N)");

        if (!contours.empty())
            contour_bins.build(contour_grid.cell_count(), [&](auto&& add) {
                for (uint32_t c = 0; c < contours.size(); ++c)
                    contour_grid.for_segment(window[contours[c].v0], window[contours[c].v1],
                                             [&](uint32_t cell) { add(cell, c); });
            });
        if (!faces) return;
        face_bins.build(face_grid.cell_count(), [&](auto&& add) {
            for (uint32_t f = 0; f < graph.face_count(); ++f)
                screen_box(f, [&](glm::dvec2 l, glm::dvec2 h) { face_grid.for_box(l, h, [&](uint32_t cell) { add(cell, f); }); });
        });
        space_bins.build(space_grid.cell_count(), [&](auto&& add) {
            for (uint32_t f = 0; f < graph.face_count(); ++f)
                space_box(f, [&](glm::dvec3 l, glm::dvec3 h) { space_grid.for_box(l, h, [&](uint32_t cell) { add(cell, f); }); });
        });
    }

    static constexpr double kPadPixels = 0.01;

    const hsr_camera* camera_ = nullptr;
    glm::dmat4 view_projection_{1.0};
};

}  // namespace appel
