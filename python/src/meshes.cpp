// Scenes from numpy arrays (hsr.Scene.from_arrays, hsr.Scene.from_meshes): each mesh's vertices and
// faces read where they lie when they are float32 and uint32 in C order, placed by its transforms
// (one instance each when a mesh is placed several times by rotations, uniform scales and shifts).
#include "meshes.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/scene_builder.hpp"

#include <fmt/format.h>

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace hsr::python {
namespace {

template <typename T>
using CArray = py::array_t<T, py::array::c_style | py::array::forcecast>;

// What one mesh dict of the Python side holds, its arrays checked and in C order.
struct MeshArrays {
    CArray<float> vertices;                 // (N, 3)
    std::optional<CArray<uint32_t>> triangles;  // (M, 3), or:
    std::optional<CArray<uint32_t>> corners, face_ends;
    std::optional<CArray<float>> face_colors;   // (faces, 3)
    std::optional<CArray<double>> transforms;   // (K, 4, 4), column vectors: world = T @ [x, y, z, 1]
    MeshOptions options;
    std::optional<float> opacity;
};

void check_shape(const py::array& array, std::initializer_list<py::ssize_t> trailing, const std::string& what) {
    const std::size_t dims = trailing.size() + 1;
    bool ok = std::size_t(array.ndim()) == dims;
    std::size_t k = 1;
    for (py::ssize_t n : trailing) ok = ok && array.shape(py::ssize_t(k++)) == n;
    if (!ok) {
        std::string expected = "(N";
        for (py::ssize_t n : trailing) expected += fmt::format(", {}", n);
        std::string got = "(";
        for (py::ssize_t i = 0; i < array.ndim(); ++i) got += fmt::format("{}{}", i ? ", " : "", array.shape(i));
        throw UsageError("{}: an array of shape {}) expected, not {})", what, expected, got);
    }
}

template <typename T>
std::optional<CArray<T>> optional_array(const py::dict& mesh, const char* key) {
    if (!mesh.contains(key) || mesh[key].is_none()) return std::nullopt;
    return CArray<T>::ensure(mesh[key]);
}

MeshArrays mesh_arrays(const py::dict& mesh, std::size_t index) {
    const std::string name = mesh.contains("name") && !mesh["name"].is_none() ? mesh["name"].cast<std::string>()
                                                                                : fmt::format("mesh {}", index);
    MeshArrays arrays{CArray<float>::ensure(mesh["vertices"]), optional_array<uint32_t>(mesh, "triangles"),
                      optional_array<uint32_t>(mesh, "corners"), optional_array<uint32_t>(mesh, "face_ends"),
                      optional_array<float>(mesh, "face_colors"), optional_array<double>(mesh, "transforms"),
                      MeshOptions{}, std::nullopt};
    if (!arrays.vertices) throw UsageError("{}: vertices must be numbers", name);
    check_shape(arrays.vertices, {3}, name + ": vertices");
    if (arrays.triangles) check_shape(*arrays.triangles, {3}, name + ": faces");
    if (arrays.face_colors) check_shape(*arrays.face_colors, {3}, name + ": colors");
    if (arrays.transforms) check_shape(*arrays.transforms, {4, 4}, name + ": transforms");
    arrays.options.name = name;
    if (mesh.contains("crease_angle") && !mesh["crease_angle"].is_none())
        arrays.options.crease_angle_degrees = mesh["crease_angle"].cast<float>();
    if (!(arrays.options.crease_angle_degrees >= 0 && arrays.options.crease_angle_degrees <= 180))
        throw UsageError("{}: crease_angle must be between 0 and 180 degrees", name);
    if (mesh.contains("color") && !mesh["color"].is_none()) {
        const auto c = mesh["color"].cast<std::vector<float>>();
        if (c.size() != 3 || !(c[0] >= 0 && c[0] <= 1 && c[1] >= 0 && c[1] <= 1 && c[2] >= 0 && c[2] <= 1))
            throw UsageError("{}: color must be three numbers between 0 and 1", name);
        arrays.options.color = glm::vec3(c[0], c[1], c[2]);
        arrays.options.color_given = true;
    }
    if (mesh.contains("opacity") && !mesh["opacity"].is_none()) {
        arrays.opacity = mesh["opacity"].cast<float>();
        if (!(*arrays.opacity >= 0 && *arrays.opacity <= 1)) throw UsageError("{}: opacity must be between 0 and 1", name);
    }
    return arrays;
}

// The mesh in its own coordinates, read from the arrays (which stay alive meanwhile).
MeshObject mesh_object(const MeshArrays& arrays) {
    const std::string& name = arrays.options.name;
    const std::span<const glm::vec3> positions(reinterpret_cast<const glm::vec3*>(arrays.vertices.data()),
                                               std::size_t(arrays.vertices.shape(0)));
    std::span<const glm::vec3> colors;
    if (arrays.face_colors)
        colors = {reinterpret_cast<const glm::vec3*>(arrays.face_colors->data()), std::size_t(arrays.face_colors->shape(0))};
    MeshObject object;
    if (arrays.triangles && colors.empty()) {
        object = object_from_triangles(positions, {arrays.triangles->data(), std::size_t(arrays.triangles->size())}, name);
        if (object.indices.empty()) throw Error("{}: the mesh has no faces with an area", name);
    } else if (arrays.triangles) {
        const std::size_t faces = std::size_t(arrays.triangles->shape(0));
        std::vector<uint32_t> ends(faces);
        for (std::size_t f = 0; f < faces; ++f) ends[f] = uint32_t(3 * (f + 1));
        object = object_from_polygons(positions, {arrays.triangles->data(), std::size_t(arrays.triangles->size())}, ends,
                                      colors, name);
    } else {
        object = object_from_polygons(positions, {arrays.corners->data(), std::size_t(arrays.corners->size())},
                                      {arrays.face_ends->data(), std::size_t(arrays.face_ends->size())}, colors, name);
    }
    object.options = arrays.options;
    if (object.options.color_given) object.face_colors.clear();
    return object;
}

glm::dmat4 transform_at(const CArray<double>& transforms, py::ssize_t k) {
    glm::dmat4 m;
    for (int row = 0; row < 4; ++row)
        for (int column = 0; column < 4; ++column) m[column][row] = transforms.at(k, row, column);
    return m;
}

}  // namespace

std::shared_ptr<Scene> scene_from_meshes(const py::list& meshes) {
    if (meshes.empty()) throw UsageError("a scene needs at least one mesh");
    std::vector<MeshArrays> arrays;
    for (std::size_t i = 0; i < meshes.size(); ++i) arrays.push_back(mesh_arrays(meshes[i].cast<py::dict>(), i));
    uint64_t placements = 0;
    for (const MeshArrays& a : arrays) placements += a.transforms ? uint64_t(a.transforms->shape(0)) : 1;
    check_limit(&Limits::instances, placements, "the meshes' transforms");

    PlacedMeshes model;
    std::vector<std::optional<float>> opacity;
    {
        py::gil_scoped_release unlocked;
        for (std::size_t i = 0; i < arrays.size(); ++i) {
            const MeshArrays& a = arrays[i];
            model.meshes.push_back(mesh_object(a));
            opacity.push_back(a.opacity);
            if (!a.transforms) {
                model.placements.push_back({i, glm::dmat4(1.0)});
                continue;
            }
            for (py::ssize_t k = 0; k < a.transforms->shape(0); ++k) {
                const glm::dmat4 m = transform_at(*a.transforms, k);
                for (int c = 0; c < 4; ++c)
                    for (int r = 0; r < 4; ++r)
                        if (!std::isfinite(m[c][r]))
                            throw UsageError("{}: transform {} has a value that is not a finite number", a.options.name, k);
                if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1)
                    throw UsageError("{}: transform {} is not affine (its last row must be 0, 0, 0, 1)", a.options.name, k);
                if (glm::determinant(glm::dmat3(m)) == 0)
                    throw UsageError("{}: transform {} flattens the mesh (its determinant is 0)", a.options.name, k);
                model.placements.push_back({i, m});
            }
        }
        if (model.placements.empty()) throw UsageError("no mesh is placed (every transforms array is empty)");
    }
    SceneData scene;
    {
        py::gil_scoped_release unlocked;
        const std::size_t placement_count = model.placements.size();
        std::vector<std::size_t> mesh_of_placement;
        for (const PlacedMeshes::Placement& p : model.placements) mesh_of_placement.push_back(p.mesh);
        scene = placed_meshes_scene(std::move(model));
        // One object per mesh when its placements are instances, else one per placement.
        const bool per_placement = scene.instances.empty() && scene.object_names.size() == placement_count;
        bool any_opacity = false;
        for (const std::optional<float>& o : opacity) any_opacity = any_opacity || o.has_value();
        if (any_opacity) {
            scene.object_opacity.assign(scene.object_names.size(), 1.0f);
            for (std::size_t object = 0; object < scene.object_opacity.size(); ++object) {
                const std::size_t mesh = per_placement ? mesh_of_placement[object] : object;
                if (mesh < opacity.size() && opacity[mesh]) scene.object_opacity[object] = *opacity[mesh];
            }
        }
    }
    auto result = std::make_shared<Scene>();
    result->renderer = std::make_shared<Renderer>(LoadedScene::of(std::move(scene), "arrays"));
    return result;
}

}  // namespace hsr::python
