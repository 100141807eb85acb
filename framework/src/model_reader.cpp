// Model files (OBJ, OFF, PLY, STL) and triangle lists read into SceneBuilder objects through
// OpenMesh. Adjacency comes from OpenMesh's half-edge structure (the triangle across edge i is the
// face of the opposite half-edge).
//
// Text files are checked before OpenMesh sees them (malformed_models.hpp), OpenMesh's own messages
// are captured instead of printed, and what it loaded is checked again. The checks of an OBJ, OFF or
// PLY file also parse it, and its mesh is built here as OpenMesh's importer builds an OBJ file's,
// except that a face of more than 3 corners is cut by polygon_triangulation.hpp rather than into a
// fan; only STL goes through OpenMesh's reader.
#include "model_reader.hpp"

#include "hsr/abi.h"
#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "malformed_models.hpp"
#include "material_library.hpp"
#include "polygon_triangulation.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iostream>
#include <iterator>
#include <mutex>
#include <optional>
#include <sstream>
#include <utility>

namespace hsr {
namespace {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;
using Object = MeshObject;

std::string display(const std::filesystem::path& file) { return printable(file.string(), kMaxQuotedPathChars); }

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

// ---------------------------------------------------------------------------------------------
// Keeping OpenMesh quiet: its streams omerr, omlog and omout write to std::cerr, std::clog and
// std::cout (as do the few places that write to std::cerr directly); while OpenMesh runs, those three
// write into a string instead, so that the host prints one line. Their buffers are swapped rather
// than OpenMesh's targets disconnected and connected again: its disconnect() forgets a target
// without freeing it (16 bytes a call, 96 a model).

class OpenMeshCapture {
public:
    OpenMeshCapture()
        : lock_(mutex()),
          saved_cerr_(std::cerr.rdbuf(captured_.rdbuf())),
          saved_clog_(std::clog.rdbuf(captured_.rdbuf())),
          saved_cout_(std::cout.rdbuf(captured_.rdbuf())) {}
    ~OpenMeshCapture() {
        flush_openmesh();
        std::cout.rdbuf(saved_cout_);
        std::clog.rdbuf(saved_clog_);
        std::cerr.rdbuf(saved_cerr_);
    }
    OpenMeshCapture(const OpenMeshCapture&) = delete;
    OpenMeshCapture& operator=(const OpenMeshCapture&) = delete;

    std::string text() {
        flush_openmesh();
        return captured_.str();
    }

private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    static void flush_openmesh() {
        omerr().flush();
        omlog().flush();
        omout().flush();
    }
    std::lock_guard<std::mutex> lock_;
    std::ostringstream captured_;
    std::streambuf* saved_cerr_;
    std::streambuf* saved_clog_;
    std::streambuf* saved_cout_;
};

// First non-empty line of OpenMesh's chatter, to explain a failure.
std::string first_line(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
        if (!line.empty()) return line;
    }
    return {};
}

enum class Format { obj, off, ply, stl };

Format format_of(const std::filesystem::path& file) {
    std::string extension = lower(file.extension().string());
    if (extension == ".obj") return Format::obj;
    if (extension == ".off") return Format::off;
    if (extension == ".ply") return Format::ply;
    if (extension == ".stl") return Format::stl;
    throw Error("{}: unsupported model format '{}' (hsr reads .obj, .off, .ply, .stl, .gltf and .glb; convert others "
                "to .glb with assimp: see docs/formats.md)",
                display(file),
                extension.empty() ? "no extension" : printable(extension));
}

// That the file is there and is a regular file, before its name's extension is asked for a format:
// a folder or a device has no extension to speak of.
void check_model_file(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) throw Error("{}: no such file", display(file));
    if (std::filesystem::is_directory(file, ec)) throw Error("{}: is a folder, not a model file", display(file));
    // A pipe would be read until its writer stops, a device such as /dev/zero until memory runs out.
    if (!std::filesystem::is_regular_file(file, ec))
        throw Error("{}: is not a regular file (a pipe, device or socket), not a model file", display(file));
}

// The file passed check_model_file.
std::string read_whole_file(const std::filesystem::path& file) {
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(file, ec);
    if (ec) throw Error("{}: cannot read the file size", display(file));
    check_limit(&Limits::model_bytes, size, display(file));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error("{}: cannot open the file for reading", display(file));
    std::string text;
    text.resize(size);
    in.read(text.data(), static_cast<std::streamsize>(size));
    text.resize(static_cast<std::size_t>(in.gcount()));  // the file may have shrunk meanwhile
    if (in.bad()) throw Error("{}: read error", display(file));
    return text;
}

// ---------------------------------------------------------------------------------------------
// OpenMesh meshes to objects.

// Adds a triangle; if it would make the mesh non-manifold, gives it vertices of its own (as
// OpenMesh's importer does) so that it stays in the scene without adjacency across the bad edges.
void add_face_or_separate(TriMesh& mesh, std::array<TriMesh::VertexHandle, 3> corners, uint32_t& separated) {
    if (mesh.add_face(corners[0], corners[1], corners[2]).is_valid()) return;
    for (auto& corner : corners) corner = mesh.add_vertex(TriMesh::Point(mesh.point(corner)));
    mesh.add_face(corners[0], corners[1], corners[2]);
    ++separated;
}

Object object_from_mesh(const TriMesh& mesh) {
    Object object;
    object.positions.reserve(mesh.n_vertices());
    for (TriMesh::VertexHandle v : mesh.vertices()) {
        const TriMesh::Point& p = mesh.point(v);
        object.positions.emplace_back(p[0], p[1], p[2]);
    }
    object.indices.reserve(3 * mesh.n_faces());
    object.neighbors.reserve(3 * mesh.n_faces());
    for (TriMesh::FaceHandle f : mesh.faces()) {
        TriMesh::HalfedgeHandle h = mesh.halfedge_handle(f);
        for (int edge = 0; edge < 3; ++edge) {  // half-edge `edge` runs from corner edge to edge+1
            object.indices.push_back(static_cast<uint32_t>(mesh.from_vertex_handle(h).idx()));
            TriMesh::HalfedgeHandle opposite = mesh.opposite_halfedge_handle(h);
            object.neighbors.push_back(mesh.is_boundary(opposite) ? HSR_NO_NEIGHBOR
                                                                   : mesh.face_handle(opposite).idx());
            h = mesh.next_halfedge_handle(h);
        }
    }
    return object;
}

// ---------------------------------------------------------------------------------------------
// Adding triangles as OpenMesh's PolyConnectivity::add_face adds them (OpenMesh 9.0,
// PolyConnectivity.cc), compiled here: the distributions build OpenMesh with its assertions, which
// turn every handle access in its add_face into a call (is_valid_handle), half the time of adding
// the bunny's faces. Only the common case is done here, a triangle that needs no patch of faces
// re-linked; every other goes to OpenMesh's own add_face, which then does the same tests (nothing
// is changed before them) and the rest.

TriMesh::HalfedgeHandle find_halfedge(const TriMesh& mesh, TriMesh::VertexHandle from, TriMesh::VertexHandle to) {
    for (auto h = mesh.cvoh_iter(from); h.is_valid(); ++h)
        if (mesh.to_vertex_handle(*h) == to) return *h;
    return TriMesh::HalfedgeHandle();
}

// PolyConnectivity::adjust_outgoing_halfedge, compiled here for the same reason: makes a boundary
// halfedge, if the vertex has one, its outgoing halfedge.
void adjust_outgoing_halfedge(TriMesh& mesh, TriMesh::VertexHandle v) {
    for (auto h = mesh.cvoh_iter(v); h.is_valid(); ++h)
        if (mesh.is_boundary(*h)) {
            mesh.set_halfedge_handle(v, *h);
            return;
        }
}

TriMesh::FaceHandle add_triangle(TriMesh& mesh, TriMesh::VertexHandle a, TriMesh::VertexHandle b,
                                 TriMesh::VertexHandle c) {
    using Halfedge = TriMesh::HalfedgeHandle;
    const TriMesh::VertexHandle v[3] = {a, b, c};
    Halfedge edge[3];
    bool is_new[3];
    for (int i = 0; i < 3; ++i) {
        if (!mesh.is_boundary(v[i])) return mesh.add_face(a, b, c);  // a complex vertex
        edge[i] = find_halfedge(mesh, v[i], v[(i + 1) % 3]);
        is_new[i] = !edge[i].is_valid();
        if (!is_new[i] && !mesh.is_boundary(edge[i])) return mesh.add_face(a, b, c);  // a complex edge
    }
    for (int i = 0; i < 3; ++i)
        if (!is_new[i] && !is_new[(i + 1) % 3] && mesh.next_halfedge_handle(edge[i]) != edge[(i + 1) % 3])
            return mesh.add_face(a, b, c);  // a patch to re-link
    for (int i = 0; i < 3; ++i)
        if (is_new[i]) edge[i] = mesh.new_edge(v[i], v[(i + 1) % 3]);
    const TriMesh::FaceHandle face = mesh.new_face();
    mesh.set_halfedge_handle(face, edge[2]);
    std::array<std::pair<Halfedge, Halfedge>, 18> next_links;  // set after the loop, as OpenMesh does
    std::size_t links = 0;
    bool needs_adjust[3] = {false, false, false};
    for (int i = 0; i < 3; ++i) {
        const int ii = (i + 1) % 3;
        const TriMesh::VertexHandle vh = v[ii];
        const Halfedge inner_prev = edge[i], inner_next = edge[ii];
        const int id = (is_new[i] ? 1 : 0) | (is_new[ii] ? 2 : 0);
        if (id != 0) {
            const Halfedge outer_prev = mesh.opposite_halfedge_handle(inner_next);
            const Halfedge outer_next = mesh.opposite_halfedge_handle(inner_prev);
            switch (id) {
            case 1:  // prev is new, next is old
                next_links[links++] = {mesh.prev_halfedge_handle(inner_next), outer_next};
                mesh.set_halfedge_handle(vh, outer_next);
                break;
            case 2:  // next is new, prev is old
                next_links[links++] = {outer_prev, mesh.next_halfedge_handle(inner_prev)};
                mesh.set_halfedge_handle(vh, mesh.next_halfedge_handle(inner_prev));
                break;
            default:  // both are new
                if (!mesh.halfedge_handle(vh).is_valid()) {
                    mesh.set_halfedge_handle(vh, outer_next);
                    next_links[links++] = {outer_prev, outer_next};
                } else {
                    const Halfedge boundary_next = mesh.halfedge_handle(vh);
                    next_links[links++] = {mesh.prev_halfedge_handle(boundary_next), outer_next};
                    next_links[links++] = {outer_prev, boundary_next};
                }
                break;
            }
            next_links[links++] = {inner_prev, inner_next};
        } else {
            needs_adjust[ii] = mesh.halfedge_handle(vh) == inner_next;
        }
        mesh.set_face_handle(edge[i], face);
    }
    for (std::size_t i = 0; i < links; ++i) mesh.set_next_halfedge_handle(next_links[i].first, next_links[i].second);
    for (int i = 0; i < 3; ++i)
        if (needs_adjust[i]) adjust_outgoing_halfedge(mesh, v[i]);
    return face;
}

using Color = std::array<float, 3>;
constexpr Color no_color = {NAN, NAN, NAN};

// What building a mesh noticed about its faces, and the colour of each triangle it added.
struct FaceCounts {
    uint32_t intersecting = 0;  // faces whose outline crosses itself, cut into a fan
    std::vector<Color> triangle_colors;  // by OpenMesh face index; empty when the faces have none
    std::vector<uint32_t> triangle_faces;  // by OpenMesh face index, the file's face; filled when asked
};

// The mesh of a model's contents, built as OpenMesh's importer (ImporterT::add_face) builds it:
// every vertex first, then each face with its repeated corners left out (keeping the first), if 3
// remain, cut into triangles (triangulate_face) and each added on its own (with add_triangle); when
// the last fails (it would make the mesh non-manifold) the whole face is added again on vertices of
// its own, and that last triangle marked. A convex face's triangles are the fan TriMesh::add_face
// makes, so such a face is added exactly as OpenMesh adds it. The importer's checks for invalid and
// repeated vertices are left out: the checks of the text and the loop here have done them.
// `face_colors` holds one colour per face (no_color for none) or is empty.
FaceCounts build_polygon_mesh(const ModelContents& contents, const std::vector<Color>& face_colors, TriMesh& mesh,
                              bool record_faces = false) {
    const std::size_t corners = contents.corners.size();  // at least 3 a face
    mesh.reserve(static_cast<unsigned>(contents.positions.size()), static_cast<unsigned>(corners),
                 static_cast<unsigned>(corners - 2 * contents.face_ends.size()));
    for (const std::array<float, 3>& p : contents.positions) mesh.add_vertex(TriMesh::Point(p[0], p[1], p[2]));
    FaceCounts counts;
    std::vector<TriMesh::VertexHandle> face;
    std::vector<glm::vec3> face_positions;
    std::vector<uint32_t> triangles;
    uint32_t begin = 0;
    auto set_color = [&](TriMesh::FaceHandle added, std::size_t face_number) {
        if (!added.is_valid()) return;
        const auto index = static_cast<std::size_t>(added.idx());
        if (record_faces) {
            if (counts.triangle_faces.size() <= index) counts.triangle_faces.resize(index + 1, 0);
            counts.triangle_faces[index] = static_cast<uint32_t>(face_number);
        }
        if (face_colors.empty()) return;
        if (counts.triangle_colors.size() <= index) counts.triangle_colors.resize(index + 1, no_color);
        counts.triangle_colors[index] = face_colors[face_number];
    };
    for (std::size_t face_number = 0; face_number < contents.face_ends.size(); ++face_number) {
        const uint32_t end = contents.face_ends[face_number];
        // A corner repeated right after itself adds nothing; one visited again later is kept, as
        // the two ends of a keyhole's bridge are (a ring written as one face).
        face.clear();
        for (uint32_t c = begin; c < end; ++c) {
            const TriMesh::VertexHandle v(contents.corners[c]);
            if (face.empty() || face.back() != v) face.push_back(v);
        }
        while (face.size() > 1 && face.front() == face.back()) face.pop_back();
        begin = end;
        if (face.size() < 3) continue;
        triangles.clear();
        if (face.size() == 3) {
            triangles = {0, 1, 2};
        } else {
            face_positions.clear();
            for (TriMesh::VertexHandle v : face) {
                const TriMesh::Point& p = mesh.point(v);
                face_positions.emplace_back(p[0], p[1], p[2]);
            }
            if (triangulate_face(face_positions, triangles) == FaceCut::fan_intersecting) ++counts.intersecting;
        }
        // Corners visited twice can put one vertex in a triangle twice: it has no area.
        for (std::size_t t = 0; t < triangles.size();) {
            const TriMesh::VertexHandle a = face[triangles[t]], b = face[triangles[t + 1]], c = face[triangles[t + 2]];
            if (a == b || b == c || c == a)
                triangles.erase(triangles.begin() + std::ptrdiff_t(t), triangles.begin() + std::ptrdiff_t(t + 3));
            else
                t += 3;
        }
        if (triangles.empty()) continue;
        TriMesh::FaceHandle added;
        for (std::size_t t = 0; t < triangles.size(); t += 3) {
            added = add_triangle(mesh, face[triangles[t]], face[triangles[t + 1]], face[triangles[t + 2]]);
            set_color(added, face_number);
        }
        if (added.is_valid()) continue;
        for (TriMesh::VertexHandle& v : face) v = mesh.add_vertex(TriMesh::Point(mesh.point(v)));
        for (std::size_t t = 0; t < triangles.size(); t += 3) {
            added = mesh.add_face(face[triangles[t]], face[triangles[t + 1]], face[triangles[t + 2]]);
            set_color(added, face_number);
        }
        mesh.status(added).set_fixed_nonmanifold(true);
    }
    if (!counts.triangle_colors.empty()) counts.triangle_colors.resize(mesh.n_faces(), no_color);
    return counts;
}

bool any_color(const std::vector<Color>& colors) {
    return std::any_of(colors.begin(), colors.end(), [](const Color& c) { return !std::isnan(c[0]); });
}

// Each face's colour from its OBJ material's Kd (no_color before any usemtl, or for a material
// not found); empty when no face has one. One warning line for each library not read, one for the
// materials not found when every library was read, and one for textures, which are not drawn.
std::vector<Color> material_colors(const std::filesystem::path& file, const ModelContents& contents,
                                   std::vector<std::string>& warnings) {
    if (contents.material_uses.empty()) return {};
    MaterialLibrary materials;
    bool all_read = true;
    for (const std::string& name : contents.material_libraries) {
        std::string text;
        if (!read_material_file(file, name, text, warnings)) {
            all_read = false;
            continue;
        }
        MaterialLibrary library = parse_material_library(text, display(file.parent_path() / name), warnings);
        materials.diffuse.merge(library.diffuse);  // the first library to define a name wins
        materials.has_textures = materials.has_textures || library.has_textures;
    }
    if (contents.material_libraries.empty())
        warnings.push_back(fmt::format("{}: usemtl without an mtllib line: the faces keep the object's colour",
                                       display(file)));
    if (materials.has_textures)
        warnings.push_back(fmt::format("{}: textures (map_Kd and other maps) are not drawn: faces take their "
                                       "material's Kd colour", display(file)));
    std::vector<Color> colors(contents.face_ends.size(), no_color);
    std::vector<std::string> missing;
    for (std::size_t u = 0; u < contents.material_uses.size(); ++u) {
        const ModelContents::MaterialUse& use = contents.material_uses[u];
        const std::size_t last = u + 1 < contents.material_uses.size() ? contents.material_uses[u + 1].first_face
                                                                         : colors.size();
        const auto found = materials.diffuse.find(use.name);
        if (found == materials.diffuse.end()) {
            // A library not read has had its warning, which explains its materials too.
            if (!contents.material_libraries.empty() && all_read && use.first_face < last &&
                std::find(missing.begin(), missing.end(), use.name) == missing.end())
                missing.push_back(use.name);
            continue;
        }
        for (std::size_t f = use.first_face; f < last; ++f) colors[f] = {found->second.r, found->second.g, found->second.b};
    }
    if (!missing.empty())
        warnings.push_back(fmt::format("{}: no Kd colour for material '{}'{} in the material libraries read: "
                                       "those faces keep the object's colour",
                                       display(file), printable(missing[0]),
                                       missing.size() == 1 ? std::string()
                                                           : fmt::format(" (and {} more)", missing.size() - 1)));
    return any_color(colors) ? colors : std::vector<Color>{};
}

// Each face's colour from an OFF or PLY file: its own colour, else the mean of its corners'
// colours; empty when no face has one.
std::vector<Color> file_colors(const ModelContents& contents) {
    if (contents.face_colors.empty() && contents.vertex_colors.empty()) return {};
    std::vector<Color> colors(contents.face_ends.size(), no_color);
    uint32_t begin = 0;
    for (std::size_t f = 0; f < contents.face_ends.size(); ++f) {
        const uint32_t end = contents.face_ends[f];
        if (!contents.face_colors.empty() && !std::isnan(contents.face_colors[f][0])) {
            colors[f] = contents.face_colors[f];
        } else if (!contents.vertex_colors.empty()) {
            glm::dvec3 sum(0.0);
            int counted = 0;
            for (uint32_t c = begin; c < end; ++c) {
                const Color& corner = contents.vertex_colors[static_cast<std::size_t>(contents.corners[c])];
                if (std::isnan(corner[0])) continue;
                sum += glm::dvec3(corner[0], corner[1], corner[2]);
                ++counted;
            }
            if (counted > 0) {
                const glm::dvec3 mean = sum / double(counted);
                colors[f] = {float(mean.x), float(mean.y), float(mean.z)};
            }
        }
        begin = end;
    }
    return any_color(colors) ? colors : std::vector<Color>{};
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The object of a mesh build_polygon_mesh made, with its faces' colours and what was noticed.
Object object_from_polygon_mesh(const TriMesh& mesh, const FaceCounts& face_counts, const std::string& what) {
    uint32_t separated = 0;
    for (TriMesh::FaceHandle f : mesh.faces())
        if (mesh.status(f).fixed_nonmanifold()) ++separated;
    Object object = object_from_mesh(mesh);
    object.separated_faces = separated;
    object.source = what;
    const glm::vec3 object_color = MeshOptions().color;
    for (const Color& c : face_counts.triangle_colors)
        object.face_colors.push_back(std::isnan(c[0]) ? object_color : glm::vec3(c[0], c[1], c[2]));
    if (face_counts.intersecting > 0)
        object.warnings.push_back(fmt::format("{}: {} face{} crossing {} outline cut into a fan from the first corner",
                                              object.source, face_counts.intersecting,
                                              face_counts.intersecting == 1 ? "" : "s",
                                              face_counts.intersecting == 1 ? "its" : "their"));
    for (std::size_t v = 0; v < object.positions.size(); ++v)
        if (!finite(object.positions[v]))
            throw Error("{}: vertex {} has a coordinate that is not a finite number", what, v);
    if (object.indices.empty()) throw Error("{}: the model has no faces", what);
    return object;
}

// The faces' groups of an OBJ file: its o lines if it has any, else its g lines; a group named
// again goes on. Each face's group number, and the groups' names; empty with one group or none.
std::vector<uint32_t> face_groups(const ModelContents& contents, std::vector<std::string>& names) {
    const bool by_object = std::any_of(contents.groups.begin(), contents.groups.end(),
                                       [](const ModelContents::Group& g) { return g.is_object; });
    std::vector<uint32_t> group_of_face(contents.face_ends.size(), 0);
    names.assign(1, std::string());
    std::size_t face = 0;
    uint32_t current = 0;
    for (const ModelContents::Group& group : contents.groups) {
        if (group.is_object != by_object) continue;
        for (; face < group.first_face && face < group_of_face.size(); ++face) group_of_face[face] = current;
        const auto found = std::find(names.begin(), names.end(), group.name);
        current = static_cast<uint32_t>(found - names.begin());
        if (found == names.end()) names.push_back(group.name);
    }
    for (; face < group_of_face.size(); ++face) group_of_face[face] = current;
    if (names.size() < 2) return {};
    return group_of_face;
}

// The object cut into one object a group, each named after its group; triangles across a cut
// are no longer neighbours. Groups without triangles are left out.
std::vector<Object> split_by_group(Object whole, const std::vector<uint32_t>& triangle_group,
                                   const std::vector<std::string>& names) {
    const std::size_t triangles = whole.indices.size() / 3;
    std::vector<std::size_t> count(names.size(), 0);
    for (uint32_t g : triangle_group) ++count[g];
    if (std::count_if(count.begin(), count.end(), [](std::size_t c) { return c > 0; }) < 2) {
        std::vector<Object> one;
        one.push_back(std::move(whole));
        return one;
    }
    std::vector<Object> parts;
    std::vector<int64_t> new_vertex(whole.positions.size(), -1);
    std::vector<int32_t> new_triangle(triangles, -1);
    for (uint32_t g = 0; g < names.size(); ++g) {
        if (count[g] == 0) continue;
        Object part;
        part.source = whole.source + " (" + (names[g].empty() ? std::string("faces before the first group") : "'" + names[g] + "'") + ")";
        part.options.name = names[g].empty() ? std::string("default") : names[g];
        std::fill(new_vertex.begin(), new_vertex.end(), -1);
        int32_t next = 0;
        for (std::size_t t = 0; t < triangles; ++t)
            if (triangle_group[t] == g) new_triangle[t] = next++;
        for (std::size_t t = 0; t < triangles; ++t) {
            if (triangle_group[t] != g) continue;
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = whole.indices[3 * t + k];
                if (new_vertex[v] < 0) {
                    new_vertex[v] = static_cast<int64_t>(part.positions.size());
                    part.positions.push_back(whole.positions[v]);
                }
                part.indices.push_back(static_cast<uint32_t>(new_vertex[v]));
                const int32_t n = whole.neighbors[3 * t + k];
                part.neighbors.push_back(n >= 0 && triangle_group[std::size_t(n)] == g ? new_triangle[std::size_t(n)]
                                                                                      : HSR_NO_NEIGHBOR);
            }
            if (!whole.face_colors.empty()) part.face_colors.push_back(whole.face_colors[t]);
        }
        parts.push_back(std::move(part));
    }
    parts.front().separated_faces = whole.separated_faces;
    parts.front().warnings = std::move(whole.warnings);
    return parts;
}

// One model file as an object; for an OBJ file with groups, also each triangle's group.
Object read_model(const std::filesystem::path& file, std::vector<uint32_t>* triangle_group,
                  std::vector<std::string>* group_names) {
    check_model_file(file);
    Format format = format_of(file);
    std::optional<ModelContents> contents;
    {
        std::string text = read_whole_file(file);
        switch (format) {
        case Format::obj: contents = check_obj_text(file, text); break;
        case Format::off: contents = check_off_text(file, text); break;
        case Format::ply: contents = check_ply_text(file, text); break;
        case Format::stl: check_stl_text(file, text); break;
        }
    }

    std::vector<uint32_t> group_of_face;
    if (contents && format == Format::obj && triangle_group != nullptr && group_names != nullptr)
        group_of_face = face_groups(*contents, *group_names);
    std::vector<std::string> warnings;
    const std::vector<Color> face_colors = !contents ? std::vector<Color>{}
                                           : format == Format::obj ? material_colors(file, *contents, warnings)
                                                                   : file_colors(*contents);

    TriMesh mesh;
    mesh.request_face_status();
    std::string chatter;
    bool read = false;
    FaceCounts face_counts;
    {
        OpenMeshCapture capture;
        try {
            if (contents) {
                face_counts = build_polygon_mesh(*contents, face_colors, mesh, !group_of_face.empty());
                contents.reset();
                read = true;
            } else {
                read = OpenMesh::IO::read_mesh(mesh, file.string());
            }
        } catch (const std::bad_alloc&) {
            throw Error("{}: not enough memory to read the model", display(file));
        } catch (const std::exception& e) {
            throw Error("{}: could not be parsed ({})", display(file), e.what());
        }
        chatter = capture.text();
    }
    if (!read) {
        std::string reason = first_line(chatter);
        throw Error("{}: could not be parsed as {}{}", display(file), lower(file.extension().string()).substr(1),
                    reason.empty() ? "" : " (" + printable(reason) + ")");
    }
    if (chatter.find("invalid vertex index") != std::string::npos ||
        chatter.find("invalid faces") != std::string::npos)
        throw Error("{}: some faces refer to vertices that do not exist", display(file));

    Object object = object_from_polygon_mesh(mesh, face_counts, display(file));
    object.warnings.insert(object.warnings.begin(), warnings.begin(), warnings.end());
    if (!group_of_face.empty()) {
        triangle_group->resize(face_counts.triangle_faces.size());
        for (std::size_t t = 0; t < triangle_group->size(); ++t)
            (*triangle_group)[t] = group_of_face[face_counts.triangle_faces[t]];
    }
    return object;
}

}  // namespace

Object read_model_object(const std::filesystem::path& file) { return read_model(file, nullptr, nullptr); }

std::vector<Object> read_model_objects(const std::filesystem::path& file) {
    std::vector<uint32_t> triangle_group;
    std::vector<std::string> names;
    Object whole = read_model(file, &triangle_group, &names);
    if (triangle_group.empty() || triangle_group.size() != whole.indices.size() / 3) {
        std::vector<Object> one;
        one.push_back(std::move(whole));
        return one;
    }
    return split_by_group(std::move(whole), triangle_group, names);
}

Object object_from_polygons(std::span<const glm::vec3> positions, std::span<const uint32_t> corners,
                            std::span<const uint32_t> face_ends, std::span<const glm::vec3> face_colors,
                            const std::string& what) {
    if (!face_colors.empty() && face_colors.size() != face_ends.size())
        throw Error("{}: {} colours for {} faces", what, face_colors.size(), face_ends.size());
    ModelContents contents;
    contents.positions.reserve(positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) {
        if (!finite(positions[v])) throw Error("{}: vertex {} has a coordinate that is not a finite number", what, v);
        contents.positions.push_back({positions[v].x, positions[v].y, positions[v].z});
    }
    uint32_t begin = 0;
    for (std::size_t f = 0; f < face_ends.size(); ++f) {
        if (face_ends[f] > corners.size())
            throw Error("{}: face {} ends at corner {}, past the {} corners given", what, f, face_ends[f], corners.size());
        if (face_ends[f] < begin + 3) throw Error("{}: face {} has fewer than 3 corners", what, f);
        begin = face_ends[f];
    }
    contents.corners.reserve(corners.size());
    for (uint32_t index : corners) {
        if (index >= positions.size())
            throw Error("{}: vertex index {} is out of range (there are {} vertices)", what, index, positions.size());
        contents.corners.push_back(int32_t(index));
    }
    contents.face_ends.assign(face_ends.begin(), face_ends.end());
    std::vector<Color> colors;
    for (const glm::vec3& c : face_colors) {
        if (!(c.r >= 0 && c.r <= 1 && c.g >= 0 && c.g <= 1 && c.b >= 0 && c.b <= 1))
            throw Error("{}: a face colour outside [0, 1] ({}, {}, {})", what, c.r, c.g, c.b);
        colors.push_back({c.r, c.g, c.b});
    }
    TriMesh mesh;
    mesh.request_face_status();
    FaceCounts face_counts;
    {
        OpenMeshCapture capture;
        face_counts = build_polygon_mesh(contents, colors, mesh);
    }
    return object_from_polygon_mesh(mesh, face_counts, what);
}

Object object_from_triangles(std::span<const glm::vec3> positions, std::span<const uint32_t> indices,
                             const std::string& what) {
    if (indices.size() % 3 != 0)
        throw Error("{}: {} indices is not a whole number of triangles", what, indices.size());
    for (std::size_t v = 0; v < positions.size(); ++v)
        if (!finite(positions[v]))
            throw Error("{}: vertex {} has a coordinate that is not a finite number", what, v);
    for (uint32_t index : indices)
        if (index >= positions.size())
            throw Error("{}: vertex index {} is out of range (there are {} vertices)", what, index, positions.size());

    TriMesh mesh;
    uint32_t separated = 0;
    {
        OpenMeshCapture capture;  // add_face reports non-manifold attempts on omerr
        for (glm::vec3 p : positions) mesh.add_vertex(TriMesh::Point(p.x, p.y, p.z));
        for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
            uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
            if (a == b || b == c || c == a) continue;  // no area: dropped like any degenerate triangle
            add_face_or_separate(mesh, {TriMesh::VertexHandle(static_cast<int>(a)), TriMesh::VertexHandle(static_cast<int>(b)),
                                        TriMesh::VertexHandle(static_cast<int>(c))},
                                 separated);
        }
    }
    Object object = object_from_mesh(mesh);
    object.separated_faces = separated;
    object.source = what;
    return object;
}

}  // namespace hsr
