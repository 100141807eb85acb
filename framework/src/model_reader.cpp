// Model files (OBJ, OFF, PLY, STL) and triangle lists read into SceneBuilder objects through
// OpenMesh. Adjacency comes from OpenMesh's half-edge structure (the triangle across edge i is the
// face of the opposite half-edge).
//
// Text files are checked before OpenMesh sees them (malformed_models.hpp), OpenMesh's own messages
// are captured instead of printed, and what it loaded is checked again. The checks of an OBJ file
// also parse it, and its mesh is built here as OpenMesh's OBJ reader builds it (as OpenMesh's
// importer), without that reader's two iostream passes; ASCII OFF goes to OpenMesh as the checks
// re-write it, PLY as the checks convert it.
#include "model_reader.hpp"

#include "hsr/abi.h"
#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "malformed_models.hpp"

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
    throw Error("{}: unsupported model format '{}' (use .obj, .off, .ply, .stl, .gltf or .glb)", display(file),
                extension.empty() ? "no extension" : printable(extension));
}

std::string read_whole_file(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) throw Error("{}: no such file", display(file));
    if (std::filesystem::is_directory(file, ec)) throw Error("{}: is a directory, not a model file", display(file));
    // A pipe would be read until its writer stops, a device such as /dev/zero until memory runs out.
    if (!std::filesystem::is_regular_file(file, ec))
        throw Error("{}: is not a regular file (a pipe, device or socket), not a model file", display(file));
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

// The mesh OpenMesh's OBJ reader makes of the text: every vertex first, then each face with its
// repeated corners left out (keeping the first), if 3 remain, added as OpenMesh's importer
// (ImporterT::add_face) adds it: TriMesh::add_face splits a polygon into a fan (done here with
// add_triangle), and when it fails (the last triangle would make the mesh non-manifold) the whole
// face is added again on vertices of its own, and that last triangle marked. The importer's checks
// for invalid and repeated vertices are left out: check_obj_text and the loop here have done them.
void build_obj_mesh(const ObjContents& contents, TriMesh& mesh) {
    const std::size_t corners = contents.corners.size();  // at least 3 a face
    mesh.reserve(static_cast<unsigned>(contents.positions.size()), static_cast<unsigned>(corners),
                 static_cast<unsigned>(corners - 2 * contents.face_ends.size()));
    for (const std::array<float, 3>& p : contents.positions) mesh.add_vertex(TriMesh::Point(p[0], p[1], p[2]));
    std::vector<TriMesh::VertexHandle> face;
    uint32_t begin = 0;
    for (uint32_t end : contents.face_ends) {
        face.clear();
        for (uint32_t c = begin; c < end; ++c) {
            const TriMesh::VertexHandle v(contents.corners[c]);
            if (std::find(face.begin(), face.end(), v) == face.end()) face.push_back(v);
        }
        begin = end;
        if (face.size() < 3) continue;
        // TriMesh::add_face: a fan from the first corner, each triangle added on its own; the face
        // is the last one's.
        TriMesh::FaceHandle added;
        for (std::size_t k = 1; k + 1 < face.size(); ++k) added = add_triangle(mesh, face[0], face[k], face[k + 1]);
        if (added.is_valid()) continue;
        for (TriMesh::VertexHandle& v : face) v = mesh.add_vertex(TriMesh::Point(mesh.point(v)));
        added = mesh.add_face(face);
        mesh.status(added).set_fixed_nonmanifold(true);
    }
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

Object read_model_object(const std::filesystem::path& file) {
    Format format = format_of(file);
    std::optional<std::string> cleaned;
    std::optional<ObjContents> obj;
    {
        std::string text = read_whole_file(file);
        switch (format) {
        case Format::obj: obj = check_obj_text(file, text); break;
        case Format::off: cleaned = check_off_text(file, text); break;
        case Format::ply: cleaned = check_ply_text(file, text); break;
        case Format::stl: check_stl_text(file, text); break;
        }
    }

    TriMesh mesh;
    mesh.request_face_status();
    std::string chatter;
    bool read = false;
    {
        OpenMeshCapture capture;
        try {
            if (obj) {
                build_obj_mesh(*obj, mesh);
                obj.reset();
                read = true;
            } else if (cleaned) {
                std::istringstream stream(std::move(*cleaned));
                cleaned.reset();
                OpenMesh::IO::Options options;
                const char* extension = format == Format::obj ? ".obj" : format == Format::off ? ".off" : ".ply";
                if (format == Format::ply) options += OpenMesh::IO::Options::Binary;
                read = OpenMesh::IO::read_mesh(mesh, stream, extension, options);
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

    uint32_t separated = 0;
    for (TriMesh::FaceHandle f : mesh.faces())
        if (mesh.status(f).fixed_nonmanifold()) ++separated;
    Object object = object_from_mesh(mesh);
    object.separated_faces = separated;
    object.source = display(file);
    for (std::size_t v = 0; v < object.positions.size(); ++v)
        if (!finite(object.positions[v]))
            throw Error("{}: vertex {} has a coordinate that is not a finite number", display(file), v);
    if (object.indices.empty()) throw Error("{}: the model has no faces", display(file));
    return object;
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
