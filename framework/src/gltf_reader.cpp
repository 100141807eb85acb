// glTF 2.0 models read into mesh objects, following the glTF 2.0 specification (Khronos, 2021,
// https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html): tinygltf parses the JSON and the GLB
// container; every accessor, buffer view, node and primitive it hands back is checked here again
// before it is used, and the work they ask for is counted against the limits (limits.hpp) before
// anything is allocated for it.
//
// Read: triangle primitives (TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN; indexed or not, any index and
// component type, normalized integers, sparse accessors), the node hierarchy of the default scene,
// base colour factors and COLOR_0 as face colours, and cameras. Not read: textures (never decoded),
// skins, morph targets, animations; Draco and meshopt compression are refused.
//
// Files a .gltf names are read only from its own folder, as regular files, through the checked
// reader below (tinygltf's file-system callbacks); image files are never opened.
//
// tinygltf's implementation is compiled here and nowhere else, without stb_image; that is also why
// this one file holds the whole reader, over 700 lines: its checks all take tinygltf's types, which
// no header of hsr's should bring into other files. The system headers come first: tiny_gltf.h
// includes its JSON parser under hidden visibility, which would otherwise apply to their
// declarations too.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include "gltf_reader.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "model_reader.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>

namespace fs = std::filesystem;

namespace hsr {
namespace {

std::string display(const fs::path& file) { return printable(file.string(), kMaxQuotedPathChars); }

// ---------------------------------------------------------------------------------------------
// Reading files: the model itself, and the buffers a .gltf names, each a regular file whose size is
// checked before it is read. A FIFO is opened without blocking and refused by its type.

std::string read_regular_file(const fs::path& file, const std::string& what, bool follow_links) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | (follow_links ? 0 : O_NOFOLLOW));
    if (fd < 0) {
        const int error = errno;
        if (error == ENOENT) throw Error("{}: no such file", what);
        if (error == ELOOP) throw Error("{}: is a symbolic link", what);
        throw Error("{}: cannot open the file for reading ({})", what, std::strerror(error));
    }
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat info {};
    if (::fstat(fd, &info) != 0) throw Error("{}: cannot read the file size", what);
    if (S_ISDIR(info.st_mode)) throw Error("{}: is a folder, not a model file", what);
    if (!S_ISREG(info.st_mode)) throw Error("{}: is not a regular file (a pipe, device or socket)", what);
    const uint64_t size = static_cast<uint64_t>(info.st_size);
    check_limit(&Limits::model_bytes, size, what);
    std::string bytes(size, '\0');
    std::size_t done = 0;
    while (done < size) {
        const ssize_t got = ::read(fd, bytes.data() + done, size - done);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw Error("{}: read error", what);
        if (got == 0) break;  // the file shrank meanwhile
        done += static_cast<std::size_t>(got);
    }
    bytes.resize(done);
    return bytes;
}

// What the file-system callbacks need: the model's folder (none: no file may be read), the bytes
// read so far, and the first refusal, which becomes the error.
struct FileAccess {
    std::optional<fs::path> folder;
    std::string model;  // for messages
    uint64_t bytes_read = 0;
    std::string refusal;
};

// A buffer's file, named by `uri` relative to the model's folder: refused when absolute, with a
// scheme, with a `..`, or when it resolves (links followed) outside the folder. What was checked is
// what is opened: the resolved path, without following a link at its end.
std::string read_buffer_file(FileAccess& access, const std::string& uri) {
    const std::string what = fmt::format("{}: buffer '{}'", access.model, printable(uri, kMaxQuotedPathChars));
    if (!access.folder) throw Error("{}: no other file may be read here", what);
    const std::size_t colon = uri.find(':');
    if (colon != std::string::npos && uri.find('/') > colon)
        throw Error("{}: only files beside the model are read, not URIs such as '{}:'", what,
                    printable(uri.substr(0, std::min<std::size_t>(colon, 16)), 20));
    const fs::path relative(uri);
    if (uri.empty() || relative.is_absolute()) throw Error("{}: not a relative path", what);
    for (const fs::path& part : relative)
        if (part == "..") throw Error("{}: '..' leads out of the model's folder", what);
    std::error_code ec;
    const fs::path folder = fs::canonical(*access.folder, ec);
    if (ec) throw Error("{}: cannot resolve the model's folder", what);
    const fs::path resolved = fs::weakly_canonical(folder / relative, ec);
    if (ec) throw Error("{}: cannot resolve the path", what);
    const auto [folder_end, resolved_it] = std::mismatch(folder.begin(), folder.end(), resolved.begin(), resolved.end());
    if (folder_end != folder.end() || resolved_it == resolved.end())
        throw Error("{}: leads out of the model's folder", what);
    std::string bytes = read_regular_file(resolved, what, false);
    access.bytes_read += bytes.size();
    check_limit(&Limits::model_bytes, access.bytes_read, fmt::format("{}: the model and its buffers", access.model));
    return bytes;
}

bool file_exists_callback(const std::string&, void*) { return true; }  // read_buffer_file decides
std::string expand_path_callback(const std::string& path, void*) { return path; }
bool write_file_callback(std::string* error, const std::string&, const std::vector<unsigned char>&, void*) {
    if (error) *error = "writing is not supported";
    return false;
}
bool read_file_callback(std::vector<unsigned char>* out, std::string* error, const std::string& path, void* user) {
    FileAccess& access = *static_cast<FileAccess*>(user);
    try {
        const std::string bytes = read_buffer_file(access, path);
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const std::exception& e) {
        if (access.refusal.empty()) access.refusal = e.what();
        if (error) *error += e.what();
        return false;
    }
}
bool skip_image_callback(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                         void*) {
    return true;  // textures are not sampled, so never decoded
}

// tinygltf turns `extras` and `extensions` into values recursively: nesting deeper than any glTF
// needs is refused before it parses, so that a file of brackets cannot exhaust the stack.
void check_json_nesting(std::string_view json, const std::string& what) {
    constexpr int deepest = 64;
    int depth = 0;
    bool in_string = false, escaped = false;
    for (char c : json) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > deepest) throw Error("{}: the JSON nests deeper than {} levels", what, deepest);
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

uint32_t read_u32(const std::string& bytes, std::size_t at) {
    uint32_t value;
    std::memcpy(&value, bytes.data() + at, 4);
    return value;  // glTF is little-endian, as is every machine hsr is built for
}

// The GLB container's header and first chunk, before tinygltf reads them.
void check_glb(const std::string& bytes, const std::string& what) {
    if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0) throw Error("{}: not a GLB file (no glTF header)", what);
    if (read_u32(bytes, 4) != 2) throw Error("{}: GLB version {}, only version 2 is read", what, read_u32(bytes, 4));
    const uint64_t length = read_u32(bytes, 8);
    if (length > bytes.size()) throw Error("{}: the GLB header claims {} bytes, the file has {}", what, length, bytes.size());
    const uint64_t json_length = read_u32(bytes, 12);
    if (20 + json_length > length) throw Error("{}: the JSON chunk runs past the end of the file", what);
    if (read_u32(bytes, 16) != 0x4E4F534Au) throw Error("{}: the first GLB chunk is not JSON", what);
    check_json_nesting(std::string_view(bytes).substr(20, json_length), what);
}

std::string first_line(const std::string& text) {
    std::string line = text.substr(0, text.find('\n'));
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    return line;
}

// Compressed meshes, which hsr does not decode.
const char* const refused_extensions[] = {"KHR_draco_mesh_compression", "EXT_meshopt_compression",
                                          "KHR_meshopt_compression"};

tinygltf::Model parse(const std::string& bytes, bool binary, FileAccess& access) {
    const std::string& what = access.model;
    if (bytes.size() > std::numeric_limits<uint32_t>::max()) throw Error("{}: larger than 4 GiB", what);
    if (binary) check_glb(bytes, what);
    else check_json_nesting(bytes, what);
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(skip_image_callback, nullptr);
    loader.SetFsCallbacks(
        tinygltf::FsCallbacks{file_exists_callback, expand_path_callback, read_file_callback, write_file_callback, &access});
    tinygltf::Model model;
    std::string error, warning;
    bool loaded = false;
    try {
        loaded = binary ? loader.LoadBinaryFromMemory(&model, &error, &warning,
                                                      reinterpret_cast<const unsigned char*>(bytes.data()),
                                                      static_cast<unsigned>(bytes.size()), "")
                        : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(),
                                                     static_cast<unsigned>(bytes.size()), "");
    } catch (const std::bad_alloc&) {
        throw Error("{}: not enough memory to read the model", what);
    } catch (const std::exception& e) {
        throw Error("{}: could not be parsed as glTF ({})", what, printable(first_line(e.what()), 200));
    }
    if (!access.refusal.empty()) throw Error("{}", access.refusal);
    if (!loaded) {
        for (const char* name : refused_extensions)
            if (bytes.find(name) != std::string::npos)
                throw Error("{}: compressed with {}, which hsr does not read", what, name);
        const std::string reason = first_line(error.empty() ? warning : error);
        throw Error("{}: could not be parsed as glTF{}", what, reason.empty() ? "" : " (" + printable(reason, 200) + ")");
    }
    return model;
}

// ---------------------------------------------------------------------------------------------
// Accessors, checked: every byte they name lies inside its buffer view and buffer, and the values
// they make are counted against model-bytes before they are allocated.

int component_count(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    default: return 0;  // matrices: never a vertex attribute read here
    }
}

int component_size(int component_type) {
    switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
    }
}

double component_value(const unsigned char* p, int component_type, bool normalized) {
    switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const auto v = static_cast<int8_t>(*p);
        return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *p / 255.0 : *p;
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        std::memcpy(&v, p, 4);
        return normalized ? v / 4294967295.0 : v;
    }
    default: {
        float v;
        std::memcpy(&v, p, 4);
        return v;
    }
    }
}

class Reader {
public:
    Reader(const tinygltf::Model& model, std::string what) : model_(model), what_(std::move(what)) {}

    const std::string& what() const { return what_; }

    const tinygltf::Accessor& accessor(int index, const std::string& use) const {
        if (index < 0 || std::size_t(index) >= model_.accessors.size())
            throw Error("{}: {} names accessor {}, which does not exist", what_, use, index);
        return model_.accessors[std::size_t(index)];
    }

    // The bytes [offset, offset + (count - 1) * stride + element) of buffer view `view`, checked.
    const unsigned char* view_bytes(int view_index, uint64_t offset, uint64_t count, uint64_t stride, uint64_t element,
                                    const std::string& use, uint64_t* stride_out = nullptr) const {
        if (view_index < 0 || std::size_t(view_index) >= model_.bufferViews.size())
            throw Error("{}: {} names buffer view {}, which does not exist", what_, use, view_index);
        const tinygltf::BufferView& view = model_.bufferViews[std::size_t(view_index)];
        if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
            throw Error("{}: buffer view {} names buffer {}, which does not exist", what_, view_index, view.buffer);
        const std::vector<unsigned char>& buffer = model_.buffers[std::size_t(view.buffer)].data;
        if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
            throw Error("{}: buffer view {} ({} bytes at {}) runs past the end of buffer {} ({} bytes)", what_,
                        view_index, view.byteLength, view.byteOffset, view.buffer, buffer.size());
        if (stride == 0) stride = view.byteStride != 0 ? view.byteStride : element;
        if (stride < element)
            throw Error("{}: {}: byte stride {} is smaller than an element ({} bytes)", what_, use, stride, element);
        if (stride_out) *stride_out = stride;
        // offset + (count - 1) * stride + element <= byteLength, without overflowing (stride >= element >= 1)
        if (count > 0) {
            const uint64_t length = view.byteLength;
            if (offset > length || element > length - offset || count - 1 > (length - offset - element) / stride)
                throw Error("{}: {}: {} elements of {} bytes every {} from byte {} run past the end of buffer view {} "
                            "({} bytes)",
                            what_, use, count, element, stride, offset, view_index, view.byteLength);
        }
        return buffer.data() + view.byteOffset + offset;
    }

    // Accessor `index` as `components` doubles per element (fewer in the file is an error, more are
    // ignored), sparse substitutions applied.
    std::vector<double> values(int index, int components, const std::string& use) const {
        const tinygltf::Accessor& a = accessor(index, use);
        const std::string name = fmt::format("{} (accessor {})", use, index);
        const int have = component_count(a.type);
        const int size = component_size(a.componentType);
        if (have == 0 || size == 0) throw Error("{}: {}: unsupported accessor type", what_, name);
        if (have < components) throw Error("{}: {}: {} components, {} needed", what_, name, have, components);
        if (a.count > std::numeric_limits<uint32_t>::max())
            throw Error("{}: {}: {} elements, more than a mesh can hold", what_, name, a.count);
        const uint64_t element = uint64_t(size) * have;
        uint64_t stride = 0;
        const unsigned char* base =
            a.bufferView >= 0 ? view_bytes(a.bufferView, a.byteOffset, a.count, 0, element, name, &stride) : nullptr;
        check_limit(&Limits::model_bytes, a.count * 8 * components, name);  // what `out` takes
        std::vector<double> out(a.count * std::size_t(components), 0.0);
        if (base != nullptr) {
            for (std::size_t i = 0; i < a.count; ++i)
                for (int c = 0; c < components; ++c)
                    out[i * components + c] = component_value(base + i * stride + c * size, a.componentType, a.normalized);
        }
        if (a.sparse.isSparse) apply_sparse(a, name, components, element, size, out);
        return out;
    }

    // Index accessor `index`: unsigned integers, each below `vertex_count`.
    std::vector<uint32_t> indices(int index, std::size_t vertex_count, const std::string& use) const {
        const tinygltf::Accessor& a = accessor(index, use);
        if (a.type != TINYGLTF_TYPE_SCALAR || (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                               a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                               a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            throw Error("{}: {} (accessor {}): indices must be unsigned integer scalars", what_, use, index);
        const std::vector<double> raw = values(index, 1, use);
        std::vector<uint32_t> out(raw.size());
        for (std::size_t i = 0; i < raw.size(); ++i) {
            if (!(raw[i] >= 0 && raw[i] < double(vertex_count)))
                throw Error("{}: {} (accessor {}): index {} is out of range (there are {} vertices)", what_, use,
                            index, raw[i], vertex_count);
            out[i] = static_cast<uint32_t>(raw[i]);
        }
        return out;
    }

private:
    void apply_sparse(const tinygltf::Accessor& a, const std::string& name, int components, uint64_t element, int size,
                      std::vector<double>& out) const {
        const auto count = a.sparse.count;
        if (count < 0 || uint64_t(count) > a.count)
            throw Error("{}: {}: {} sparse values for {} elements", what_, name, count, a.count);
        if (count == 0) return;
        const int index_type = a.sparse.indices.componentType;
        const int index_size = component_size(index_type);
        if (index_size == 0 || index_type == TINYGLTF_COMPONENT_TYPE_BYTE || index_type == TINYGLTF_COMPONENT_TYPE_SHORT ||
            index_type == TINYGLTF_COMPONENT_TYPE_FLOAT)
            throw Error("{}: {}: sparse indices must be unsigned integers", what_, name);
        if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
            throw Error("{}: {}: a negative sparse byte offset", what_, name);
        const unsigned char* index_bytes = view_bytes(a.sparse.indices.bufferView, uint64_t(a.sparse.indices.byteOffset),
                                                      uint64_t(count), index_size, index_size, name + " sparse indices");
        const unsigned char* value_bytes = view_bytes(a.sparse.values.bufferView, uint64_t(a.sparse.values.byteOffset),
                                                      uint64_t(count), element, element, name + " sparse values");
        for (std::size_t i = 0; i < std::size_t(count); ++i) {
            const double target = component_value(index_bytes + i * index_size, index_type, false);
            if (!(target >= 0 && target < double(a.count)))
                throw Error("{}: {}: sparse index {} is out of range ({} elements)", what_, name, target, a.count);
            for (int c = 0; c < components; ++c)
                out[std::size_t(target) * components + c] =
                    component_value(value_bytes + i * element + c * size, a.componentType, a.normalized);
        }
    }

    const tinygltf::Model& model_;
    std::string what_;
};

// ---------------------------------------------------------------------------------------------
// Meshes.


void refuse_compression(const tinygltf::Model& model, const std::string& what) {
    for (const char* name : refused_extensions) {
        const auto required = std::find(model.extensionsRequired.begin(), model.extensionsRequired.end(), name);
        if (required != model.extensionsRequired.end())
            throw Error("{}: compressed with {}, which hsr does not read", what, name);
        for (const tinygltf::Mesh& mesh : model.meshes)
            for (const tinygltf::Primitive& primitive : mesh.primitives)
                if (primitive.extensions.count(name))
                    throw Error("{}: compressed with {}, which hsr does not read", what, name);
        for (const tinygltf::BufferView& view : model.bufferViews)
            if (view.extensions.count(name)) throw Error("{}: compressed with {}, which hsr does not read", what, name);
    }
}

int primitive_mode(const tinygltf::Primitive& primitive) {
    return primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
}

bool is_triangles(int mode) {
    return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

// Elements a primitive draws: its index count, or its vertex count when it has no indices.
uint64_t element_count(const tinygltf::Model& model, const tinygltf::Primitive& primitive) {
    int index = primitive.indices;
    if (index < 0) {
        const auto position = primitive.attributes.find("POSITION");
        if (position == primitive.attributes.end()) return 0;
        index = position->second;
    }
    if (index < 0 || std::size_t(index) >= model.accessors.size()) return 0;  // refused when read
    return model.accessors[std::size_t(index)].count;
}

uint64_t triangle_count(int mode, uint64_t elements) {
    if (mode == TINYGLTF_MODE_TRIANGLES) return elements / 3;
    return elements >= 3 ? elements - 2 : 0;
}

// Corner i of triangle t of a strip or fan, as the specification's section 3.7.2.1 numbers them.
std::array<uint64_t, 3> corners_of(int mode, uint64_t t) {
    if (mode == TINYGLTF_MODE_TRIANGLES) return {3 * t, 3 * t + 1, 3 * t + 2};
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) return {t, t + 1 + t % 2, t + 2 - t % 2};
    return {t + 1, t + 2, 0};
}

glm::vec3 clamped(glm::dvec3 c) {
    glm::vec3 out;
    for (int k = 0; k < 3; ++k) out[k] = std::isfinite(c[k]) ? float(std::clamp(c[k], 0.0, 1.0)) : 0.0f;
    return out;
}

struct Notes {
    bool lines_or_points = false, textures = false, skins = false, morph_targets = false, no_positions = false;
};

// All triangle primitives of mesh m as one object, each triangle coloured by its material's base
// colour times the mean of its corners' COLOR_0. Empty when the mesh has no triangles.
MeshObject read_mesh(const tinygltf::Model& model, const Reader& reader, std::size_t m, const MeshOptions& options,
                     Notes& notes) {
    const tinygltf::Mesh& mesh = model.meshes[m];
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    std::vector<glm::vec3> colors;
    bool coloured = false;
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
        const tinygltf::Primitive& primitive = mesh.primitives[p];
        const int mode = primitive_mode(primitive);
        if (!is_triangles(mode)) {
            notes.lines_or_points = true;
            continue;
        }
        if (!primitive.targets.empty()) notes.morph_targets = true;
        const auto position = primitive.attributes.find("POSITION");
        if (position == primitive.attributes.end()) {
            notes.no_positions = true;
            continue;
        }
        const std::string use = fmt::format("mesh {} primitive {}", m, p);
        const std::vector<double> xyz = reader.values(position->second, 3, use + " POSITION");
        const std::size_t vertex_count = xyz.size() / 3;
        const std::size_t first_vertex = positions.size();
        if (first_vertex + vertex_count > std::numeric_limits<uint32_t>::max())
            throw Error("{}: mesh {} has more vertices than a mesh can hold", reader.what(), m);
        for (std::size_t v = 0; v < vertex_count; ++v) {
            const glm::dvec3 point(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
            if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z) ||
                std::fabs(point.x) > FLT_MAX || std::fabs(point.y) > FLT_MAX || std::fabs(point.z) > FLT_MAX)
                throw Error("{}: {} vertex {} has a coordinate that is not a finite number", reader.what(), use, v);
            positions.emplace_back(point);
        }
        std::vector<uint32_t> elements;
        if (primitive.indices >= 0) {
            elements = reader.indices(primitive.indices, vertex_count, use + " indices");
        } else {
            elements.resize(vertex_count);
            for (std::size_t v = 0; v < vertex_count; ++v) elements[v] = uint32_t(v);
        }

        glm::dvec3 base(options.color);
        if (primitive.material >= 0) {
            if (std::size_t(primitive.material) >= model.materials.size())
                throw Error("{}: {} names material {}, which does not exist", reader.what(), use, primitive.material);
            const tinygltf::Material& material = model.materials[std::size_t(primitive.material)];
            const std::vector<double>& factor = material.pbrMetallicRoughness.baseColorFactor;
            if (factor.size() >= 3) base = glm::dvec3(factor[0], factor[1], factor[2]);
            if (material.pbrMetallicRoughness.baseColorTexture.index >= 0) notes.textures = true;
            coloured = true;
        }
        std::vector<double> corner_colors;
        const auto color = primitive.attributes.find("COLOR_0");
        if (color != primitive.attributes.end()) {
            corner_colors = reader.values(color->second, 3, use + " COLOR_0");
            if (corner_colors.size() / 3 != vertex_count)
                throw Error("{}: {} has {} colours for {} vertices", reader.what(), use, corner_colors.size() / 3,
                            vertex_count);
            if (primitive.material < 0) base = glm::dvec3(1.0);
            coloured = true;
        }

        const uint64_t triangles = triangle_count(mode, elements.size());
        for (uint64_t t = 0; t < triangles; ++t) {
            const std::array<uint64_t, 3> at = corners_of(mode, t);
            const uint32_t a = elements[at[0]], b = elements[at[1]], c = elements[at[2]];
            if (a == b || b == c || c == a) continue;  // no area
            indices.insert(indices.end(), {uint32_t(first_vertex + a), uint32_t(first_vertex + b), uint32_t(first_vertex + c)});
            glm::dvec3 face = base;
            if (!corner_colors.empty()) {
                glm::dvec3 mean(0.0);
                for (uint32_t v : {a, b, c}) mean += glm::dvec3(corner_colors[3 * v], corner_colors[3 * v + 1], corner_colors[3 * v + 2]);
                face *= mean / 3.0;
            }
            colors.push_back(clamped(face));
        }
    }
    if (indices.empty()) return {};
    MeshObject object = object_from_triangles(positions, indices, reader.what());
    if (coloured) object.face_colors = std::move(colors);
    object.options = options;
    object.options.name = mesh.name.empty() ? fmt::format("mesh {}", m) : mesh.name;
    object.source = reader.what();
    return object;
}

// ---------------------------------------------------------------------------------------------
// Nodes.

glm::dmat4 local_transform(const tinygltf::Node& node, std::size_t n, const std::string& what) {
    const auto finite = [&](const std::vector<double>& values) {
        for (double v : values)
            if (!std::isfinite(v)) throw Error("{}: node {} has a transform that is not finite", what, n);
    };
    finite(node.matrix);
    finite(node.translation);
    finite(node.rotation);
    finite(node.scale);
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) throw Error("{}: node {}: a matrix has 16 numbers", what, n);
        glm::dmat4 m;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[std::size_t(4 * c + r)];
        return m;
    }
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (!node.translation.empty()) {
        if (node.translation.size() != 3) throw Error("{}: node {}: a translation has 3 numbers", what, n);
        t[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
    }
    if (!node.rotation.empty()) {
        if (node.rotation.size() != 4) throw Error("{}: node {}: a rotation has 4 numbers", what, n);
        glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // w, x, y, z
        const double length = glm::length(q);
        if (!(length > 0)) throw Error("{}: node {}: the rotation is not a unit quaternion", what, n);
        r = glm::mat4_cast(q / length);
    }
    if (!node.scale.empty()) {
        if (node.scale.size() != 3) throw Error("{}: node {}: a scale has 3 numbers", what, n);
        s = glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    }
    return t * r * s;
}

GltfCamera camera_of(const tinygltf::Model& model, std::size_t c, const glm::dmat4& world) {
    const tinygltf::Camera& source = model.cameras[c];
    GltfCamera camera;
    camera.name = source.name.empty() ? fmt::format("camera {}", c) : source.name;
    if (source.type == "orthographic") {
        camera.orthographic = true;
        camera.xmag = float(std::fabs(source.orthographic.xmag));
        camera.ymag = float(std::fabs(source.orthographic.ymag));
        camera.znear = float(source.orthographic.znear);
    } else {
        camera.yfov_radians = float(source.perspective.yfov);
        camera.aspect_ratio = float(source.perspective.aspectRatio);
        camera.znear = float(source.perspective.znear);
    }
    camera.eye = glm::vec3(world[3]);
    camera.forward = glm::vec3(glm::normalize(glm::dvec3(world * glm::dvec4(0, 0, -1, 0))));
    camera.up = glm::vec3(glm::normalize(glm::dvec3(world * glm::dvec4(0, 1, 0, 0))));
    return camera;
}

// The scene's nodes depth first, without recursion: each node is visited at most once, so a node
// graph that is not a forest (a cycle, or a node with two parents) is refused instead of followed.
void place_nodes(const tinygltf::Model& model, const std::string& what, const std::vector<int>& mesh_object,
                 GltfModel& out) {
    std::vector<int> roots;
    if (!model.scenes.empty()) {
        const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
        if (std::size_t(scene) >= model.scenes.size()) throw Error("{}: the default scene {} does not exist", what, scene);
        roots = model.scenes[std::size_t(scene)].nodes;
    } else {
        std::vector<bool> is_child(model.nodes.size(), false);
        for (const tinygltf::Node& node : model.nodes)
            for (int child : node.children)
                if (child >= 0 && std::size_t(child) < model.nodes.size()) is_child[std::size_t(child)] = true;
        for (std::size_t n = 0; n < model.nodes.size(); ++n)
            if (!is_child[n]) roots.push_back(int(n));
    }
    std::vector<bool> visited(model.nodes.size(), false);
    std::vector<bool> camera_placed(model.cameras.size(), false);
    std::vector<std::pair<int, glm::dmat4>> stack;
    for (auto root = roots.rbegin(); root != roots.rend(); ++root) stack.emplace_back(*root, glm::dmat4(1.0));
    uint64_t placed_triangles = 0;
    while (!stack.empty()) {
        const auto [n, parent] = stack.back();
        stack.pop_back();
        if (n < 0 || std::size_t(n) >= model.nodes.size()) throw Error("{}: node {} does not exist", what, n);
        if (visited[std::size_t(n)])
            throw Error("{}: node {} is reached twice (its nodes must form trees, without cycles)", what, n);
        visited[std::size_t(n)] = true;
        const tinygltf::Node& node = model.nodes[std::size_t(n)];
        const glm::dmat4 world = parent * local_transform(node, std::size_t(n), what);
        if (node.mesh >= 0) {
            if (std::size_t(node.mesh) >= model.meshes.size())
                throw Error("{}: node {} names mesh {}, which does not exist", what, n, node.mesh);
            const int object = mesh_object[std::size_t(node.mesh)];
            if (object >= 0) {
                out.placements.push_back({std::size_t(object), world});
                check_limit(&Limits::instances, out.placements.size(), fmt::format("{}: mesh placements", what));
                placed_triangles += out.meshes[std::size_t(object)].indices.size() / 3;
                check_limit(&Limits::triangles, placed_triangles, what);
            }
        }
        if (node.camera >= 0) {
            if (std::size_t(node.camera) >= model.cameras.size())
                throw Error("{}: node {} names camera {}, which does not exist", what, n, node.camera);
            if (!camera_placed[std::size_t(node.camera)]) {
                camera_placed[std::size_t(node.camera)] = true;
                out.cameras.push_back(camera_of(model, std::size_t(node.camera), world));
            }
        }
        for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) stack.emplace_back(*child, world);
    }
}

GltfModel convert(const tinygltf::Model& model, const std::string& what, const MeshOptions& options) {
    const std::string& version = model.asset.version;
    if (!version.empty() && version[0] != '2')
        throw Error("{}: glTF version {}, only glTF 2.0 is read", what, printable(version, 20));
    refuse_compression(model, what);
    // The triangles the meshes store, counted before any is read.
    uint64_t stored = 0;
    for (const tinygltf::Mesh& mesh : model.meshes)
        for (const tinygltf::Primitive& primitive : mesh.primitives) {
            const int mode = primitive_mode(primitive);
            if (is_triangles(mode)) stored += triangle_count(mode, element_count(model, primitive));
        }
    check_limit(&Limits::stored_triangles, stored, what);

    const Reader reader(model, what);
    GltfModel out;
    Notes notes;
    std::vector<int> mesh_object(model.meshes.size(), -1);
    for (std::size_t m = 0; m < model.meshes.size(); ++m) {
        MeshObject object = read_mesh(model, reader, m, options, notes);
        if (object.indices.empty()) continue;
        mesh_object[m] = int(out.meshes.size());
        out.meshes.push_back(std::move(object));
    }
    place_nodes(model, what, mesh_object, out);
    if (out.placements.empty())
        throw Error("{}: the model has no triangles in its scene{}", what,
                    notes.lines_or_points ? " (only points and lines, which are not drawn)" : "");

    if (notes.lines_or_points) out.notes.push_back(fmt::format("{}: points and lines skipped (only triangles are drawn)", what));
    if (notes.no_positions) out.notes.push_back(fmt::format("{}: primitives without POSITION skipped", what));
    if (notes.textures || !model.textures.empty())
        out.notes.push_back(fmt::format("{}: textures are not sampled (base colour factors and COLOR_0 are used)", what));
    if (!model.skins.empty()) out.notes.push_back(fmt::format("{}: skins ignored (the mesh is drawn in its rest pose)", what));
    if (notes.morph_targets) out.notes.push_back(fmt::format("{}: morph targets ignored", what));
    if (!model.animations.empty()) out.notes.push_back(fmt::format("{}: animations ignored", what));
    return out;
}

}  // namespace

bool is_gltf_file(const fs::path& file) {
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return extension == ".gltf" || extension == ".glb";
}

GltfModel read_gltf(const fs::path& file, const MeshOptions& options) {
    FileAccess access;
    access.model = display(file);
    std::string bytes = read_regular_file(file, access.model, true);
    access.bytes_read = bytes.size();
    access.folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
    std::string extension = file.extension().string();
    const bool binary = extension.size() == 4 && std::tolower(static_cast<unsigned char>(extension[3])) == 'b';
    const tinygltf::Model model = parse(bytes, binary, access);
    std::string().swap(bytes);
    return convert(model, access.model, options);
}

GltfModel read_gltf_bytes(const std::string& bytes, bool binary, const std::string& what, const MeshOptions& options) {
    FileAccess access;
    access.model = what;
    check_limit(&Limits::model_bytes, bytes.size(), what);
    const tinygltf::Model model = parse(bytes, binary, access);
    return convert(model, what, options);
}

MeshObject read_gltf_object(const fs::path& file) {
    const GltfModel model = read_gltf(file);
    uint64_t stored = 0;
    for (const GltfModel::Placement& placement : model.placements) stored += model.meshes[placement.mesh].indices.size() / 3;
    check_limit(&Limits::stored_triangles, stored, display(file) + ": the placed meshes");
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    std::vector<glm::vec3> colors;
    bool coloured = false;
    for (const GltfModel::Placement& placement : model.placements) {
        const MeshObject& mesh = model.meshes[placement.mesh];
        coloured = coloured || !mesh.face_colors.empty();
        const uint32_t first = uint32_t(positions.size());
        for (const glm::vec3& p : mesh.positions) {
            const glm::dvec4 w = placement.transform * glm::dvec4(glm::dvec3(p), 1.0);
            positions.emplace_back(glm::dvec3(w));
        }
        const bool mirrored = glm::determinant(glm::dmat3(placement.transform)) < 0;
        for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
            const uint32_t a = first + mesh.indices[t], b = first + mesh.indices[t + 1], c = first + mesh.indices[t + 2];
            if (mirrored) indices.insert(indices.end(), {a, c, b});
            else indices.insert(indices.end(), {a, b, c});
            colors.push_back(mesh.face_colors.empty() ? mesh.options.color : mesh.face_colors[t / 3]);
        }
    }
    MeshObject object = object_from_triangles(positions, indices, display(file));
    if (coloured) object.face_colors = std::move(colors);
    return object;
}

}  // namespace hsr
