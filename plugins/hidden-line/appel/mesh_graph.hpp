// The edge graph Appel's walk runs on, built from hsr_scene: every edge of the mesh once (from the
// half-edge adjacency, edge_neighbors), with its two faces (one on a boundary), and per vertex the
// edges and faces around it. A scene whose adjacency is not that of a manifold half-edge mesh is
// refused with a message that names the triangle.
#pragma once

#include "grids.hpp"

#include "hsr/abi.h"
#include "hsr/sdk.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace appel {

class MeshGraph {
public:
    void build(const hsr_scene& scene) {
        auto fail = [](const std::string& message) { throw hsr::sdk::InvalidArgument("appel: " + message); };
        vertex_count_ = scene.vertex_count;
        face_count_ = scene.triangle_count;
        indices_ = scene.indices;
        if (face_count_ > 0 && (scene.indices == nullptr || scene.positions == nullptr))
            fail("the scene has NULL positions or indices");
        if (face_count_ > 0 && scene.edge_neighbors == nullptr) fail("the scene has no edge_neighbors (adjacency)");
        if (uint64_t(face_count_) * 3 >= uint64_t(0xFFFFFFFFu)) fail("the scene has too many triangles");
        for (uint32_t f = 0; f < face_count_; ++f) {
            for (int i = 0; i < 3; ++i) {
                const uint32_t v = corner(f, i);
                if (v >= vertex_count_)
                    fail("triangle " + std::to_string(f) + " uses vertex " + std::to_string(v) + " but the scene has " +
                         std::to_string(vertex_count_) + " vertices");
                if (v == corner(f, (i + 1) % 3))
                    fail("triangle " + std::to_string(f) + " uses vertex " + std::to_string(v) + " twice");
            }
        }

        edge_vertices_.clear();
        edge_faces_.clear();
        halfedge_edge_.assign(size_t(face_count_) * 3, kNone);
        for (uint32_t f = 0; f < face_count_; ++f) {
            for (int i = 0; i < 3; ++i) {
                const int32_t neighbour = scene.edge_neighbors[3 * f + i];
                const uint32_t a = corner(f, i), b = corner(f, (i + 1) % 3);
                auto where = [&] {
                    return "triangle " + std::to_string(f) + ", side " + std::to_string(i) + " (vertices " +
                           std::to_string(a) + "-" + std::to_string(b) + ")";
                };
                if (neighbour == HSR_NO_NEIGHBOR) {
                    halfedge_edge_[3 * f + i] = add_edge(a, b, f, HSR_NO_FACE);
                    continue;
                }
                if (neighbour < 0 || uint32_t(neighbour) >= face_count_ || uint32_t(neighbour) == f)
                    fail(where() + " names triangle " + std::to_string(neighbour) + " as its neighbour");
                const uint32_t g = uint32_t(neighbour);
                // The side of g between the same two vertices (either direction: the faces need not
                // agree on their orientation, only on the vertices), naming f back.
                int side = -1;
                for (int j = 0; j < 3; ++j) {
                    const uint32_t c = corner(g, j), d = corner(g, (j + 1) % 3);
                    if (((c == b && d == a) || (c == a && d == b)) && scene.edge_neighbors[3 * g + j] == int32_t(f)) side = j;
                }
                if (side < 0)
                    fail(where() + " names triangle " + std::to_string(g) +
                         " as its neighbour, but that triangle has no side between the same vertices naming it back: "
                         "the adjacency is not that of a manifold mesh (an edge shared by more than two triangles?)");
                if (g < f) continue;  // added from g's side
                const uint32_t e = add_edge(a, b, f, g);
                halfedge_edge_[3 * f + i] = e;
                halfedge_edge_[3 * g + side] = e;
            }
        }

        vertex_edges_.build(vertex_count_, [&](auto&& add) {
            for (uint32_t e = 0; e < edge_count(); ++e) {
                add(edge_vertex(e, 0), e);
                add(edge_vertex(e, 1), e);
            }
        });
        vertex_faces_.build(vertex_count_, [&](auto&& add) {
            for (uint32_t f = 0; f < face_count_; ++f)
                for (int i = 0; i < 3; ++i) add(corner(f, i), f);
        });
    }

    static constexpr uint32_t kNone = 0xFFFFFFFFu;

    uint32_t vertex_count() const { return vertex_count_; }
    uint32_t face_count() const { return face_count_; }
    uint32_t edge_count() const { return uint32_t(edge_faces_.size() / 2); }
    uint32_t corner(uint32_t face, int i) const { return indices_[3 * size_t(face) + i]; }
    uint32_t edge_vertex(uint32_t edge, int end) const { return edge_vertices_[2 * size_t(edge) + end]; }
    uint32_t edge_face(uint32_t edge, int side) const { return edge_faces_[2 * size_t(edge) + side]; }  // HSR_NO_FACE
    uint32_t other_end(uint32_t edge, uint32_t vertex) const {
        return edge_vertex(edge, 0) == vertex ? edge_vertex(edge, 1) : edge_vertex(edge, 0);
    }
    // The edge along side i (corner i to corner i+1) of a face.
    uint32_t side_edge(uint32_t face, int i) const { return halfedge_edge_[3 * size_t(face) + i]; }
    bool face_has(uint32_t face, uint32_t vertex) const {
        return corner(face, 0) == vertex || corner(face, 1) == vertex || corner(face, 2) == vertex;
    }
    // The corner of a face that is neither a nor b.
    uint32_t third_corner(uint32_t face, uint32_t a, uint32_t b) const {
        for (int i = 0; i < 3; ++i)
            if (corner(face, i) != a && corner(face, i) != b) return corner(face, i);
        return kNone;
    }
    std::span<const uint32_t> edges_at(uint32_t vertex) const { return vertex_edges_[vertex]; }
    std::span<const uint32_t> faces_at(uint32_t vertex) const { return vertex_faces_[vertex]; }

private:
    uint32_t add_edge(uint32_t a, uint32_t b, uint32_t f, uint32_t g) {
        edge_vertices_.push_back(a);
        edge_vertices_.push_back(b);
        edge_faces_.push_back(f);
        edge_faces_.push_back(g);
        return edge_count() - 1;
    }

    uint32_t vertex_count_ = 0, face_count_ = 0;
    const uint32_t* indices_ = nullptr;
    std::vector<uint32_t> edge_vertices_, edge_faces_, halfedge_edge_;
    Bins vertex_edges_, vertex_faces_;
};

}  // namespace appel
