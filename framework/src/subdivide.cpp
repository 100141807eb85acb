// Loop subdivision of loaded models (see subdivide.hpp), through OpenMesh's uniform Loop
// subdivider. The model is read and checked by the ordinary loader first, so every format and
// every error message is the same as for load_model(); the subdivided triangles then go through
// SceneBuilder like any other triangles (normals, adjacency, bounds).
#include "hsr/subdivide.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <array>
#include <span>
#include <vector>

namespace hsr {
namespace {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

struct Triangles {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
};

void check_levels(int levels) {
    if (levels < 0 || levels > max_loop_levels)
        throw Error("Loop subdivision: {} levels is outside [0, {}]", levels, max_loop_levels);
}

// One object's triangles subdivided `levels` times. A triangle that would make the mesh
// non-manifold gets vertices of its own (as the loader does), so nothing is lost; Loop treats its
// edges as boundary edges.
Triangles subdivide(const Triangles& in, int levels) {
    if (levels == 0) return in;
    const uint64_t triangles = in.indices.size() / 3;  // each level makes four of each triangle
    check_limit(&Limits::stored_triangles, triangles << (2 * levels),
                fmt::format("Loop subdivision: {} levels of {} triangles", levels, triangles));
    TriMesh mesh;
    mesh.reserve(in.positions.size(), 3 * in.indices.size() / 2, in.indices.size() / 3);
    for (const glm::vec3& p : in.positions) mesh.add_vertex(TriMesh::Point(p.x, p.y, p.z));
    for (std::size_t t = 0; t + 2 < in.indices.size(); t += 3) {
        std::array<TriMesh::VertexHandle, 3> corner;
        for (int k = 0; k < 3; ++k) corner[k] = TriMesh::VertexHandle(static_cast<int>(in.indices[t + k]));
        if (corner[0] == corner[1] || corner[1] == corner[2] || corner[2] == corner[0]) continue;
        if (mesh.add_face(corner[0], corner[1], corner[2]).is_valid()) continue;
        for (auto& c : corner) c = mesh.add_vertex(TriMesh::Point(mesh.point(c)));
        mesh.add_face(corner[0], corner[1], corner[2]);
    }

    OpenMesh::Subdivider::Uniform::LoopT<TriMesh> loop;
    if (!loop.attach(mesh) || !loop(static_cast<size_t>(levels))) {
        loop.detach();
        throw Error("Loop subdivision failed");
    }
    loop.detach();

    Triangles out;
    out.positions.reserve(mesh.n_vertices());
    for (TriMesh::VertexHandle v : mesh.vertices()) {
        const TriMesh::Point& p = mesh.point(v);
        out.positions.emplace_back(p[0], p[1], p[2]);
    }
    out.indices.reserve(3 * mesh.n_faces());
    for (TriMesh::FaceHandle f : mesh.faces())
        for (TriMesh::VertexHandle v : mesh.fv_range(f)) out.indices.push_back(static_cast<uint32_t>(v.idx()));
    return out;
}

// The triangles of object `o` of a scene without instances, with only the vertices they use.
Triangles object_triangles(const SceneData& scene, uint32_t o) {
    Triangles out;
    std::vector<int64_t> local(scene.vertex_count(), -1);
    for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
        if (scene.face_object[t] != o) continue;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = scene.indices[3 * t + k];
            if (local[v] < 0) {
                local[v] = static_cast<int64_t>(out.positions.size());
                out.positions.emplace_back(scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]);
            }
            out.indices.push_back(static_cast<uint32_t>(local[v]));
        }
    }
    return out;
}

}  // namespace

SceneData loop_subdivide(const SceneData& scene, int loop_levels, float crease_angle_degrees) {
    check_levels(loop_levels);
    if (!scene.instances.empty())
        throw Error("Loop subdivision: the scene has instances; subdivide the model before placing it");
    SceneBuilder builder;
    for (uint32_t o = 0; o < scene.object_names.size(); ++o) {
        const Triangles triangles = object_triangles(scene, o);
        if (triangles.indices.empty()) continue;
        MeshOptions options;
        options.name = scene.object_names[o];
        options.crease_angle_degrees = crease_angle_degrees;
        for (uint32_t t = 0; t < scene.triangle_count(); ++t)
            if (scene.face_object[t] == o) {
                options.color = glm::vec3(scene.face_colors[3 * t], scene.face_colors[3 * t + 1], scene.face_colors[3 * t + 2]);
                break;
            }
        const Triangles fine = subdivide(triangles, loop_levels);
        builder.add_triangles(fine.positions, fine.indices, options);
    }
    SceneData out = builder.build();
    out.warnings.insert(out.warnings.begin(), scene.warnings.begin(), scene.warnings.end());
    return out;
}

SceneData load_model_subdivided(const std::filesystem::path& file, int loop_levels, const MeshOptions& options) {
    check_levels(loop_levels);
    if (loop_levels == 0) return load_model(file, options);
    MeshOptions plain;  // identity transform: subdivide in the model's own coordinates
    plain.name = options.name.empty() ? file.stem().string() : options.name;
    const SceneData model = load_model(file, plain);
    const Triangles fine = subdivide(object_triangles(model, 0), loop_levels);
    MeshOptions final_options = options;
    final_options.name = plain.name;
    SceneBuilder builder;
    builder.add_triangles(fine.positions, fine.indices, final_options);
    SceneData out = builder.build();
    out.warnings.insert(out.warnings.begin(), model.warnings.begin(), model.warnings.end());
    return out;
}

}  // namespace hsr
