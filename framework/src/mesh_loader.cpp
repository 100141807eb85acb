// Mesh input: model files read with OpenMesh, planar polygons triangulated by ear clipping, raw
// triangle lists; SceneBuilder merges them into the world-space hsr_scene arrays.
//
// Adjacency comes from OpenMesh's half-edge structure (the triangle across edge i is the face of
// the opposite half-edge). Corner normals are angle-weighted averages of the face normals around a
// vertex (Thürmer & Wüthrich, "Computing vertex normals from polygonal facets", JGT 1998), limited
// to faces within a crease angle of the corner's own face, so hard edges stay hard. Polygons are
// triangulated by ear clipping (Meisters, "Polygons have ears", 1975) in the plane of their Newell
// normal.
//
// OpenMesh's readers trust their input: a PLY header without end_header or an OFF face claiming a
// billion corners makes them spin, and an unparsable number silently shifts every later vertex. So
// text files are checked here first (structure, finite coordinates, index ranges, with line
// numbers), OpenMesh's own messages are captured instead of printed, and what it loaded is checked
// again. ASCII OFF goes to OpenMesh re-written without comment lines and with the counts on their
// own line, two things its OFF reader does not accept.
#include "hsr/error.hpp"
#include "hsr/scene.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <mutex>
#include <optional>
#include <sstream>

namespace hsr {
namespace {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;
using Object = SceneBuilder::Object;

std::string display(const std::filesystem::path& file) { return file.string(); }

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

// ---------------------------------------------------------------------------------------------
// Keeping OpenMesh quiet: its streams (omerr, omlog, omout) and the few places that write to
// std::cerr directly go into a string while OpenMesh runs, so that the host prints one line.

class OpenMeshCapture {
public:
    OpenMeshCapture() : lock_(mutex()) {
        cerr_was_connected_ = omerr().disconnect(std::cerr);
        clog_was_connected_ = omlog().disconnect(std::clog);
        cout_was_connected_ = omout().disconnect(std::cout);
        omerr().connect(captured_);
        omlog().connect(captured_);
        omout().connect(captured_);
        saved_cerr_ = std::cerr.rdbuf(captured_.rdbuf());
    }
    ~OpenMeshCapture() {
        omerr().flush();
        omlog().flush();
        omout().flush();
        std::cerr.rdbuf(saved_cerr_);
        omerr().disconnect(captured_);
        omlog().disconnect(captured_);
        omout().disconnect(captured_);
        if (cerr_was_connected_) omerr().connect(std::cerr);
        if (clog_was_connected_) omlog().connect(std::clog);
        if (cout_was_connected_) omout().connect(std::cout);
    }
    OpenMeshCapture(const OpenMeshCapture&) = delete;
    OpenMeshCapture& operator=(const OpenMeshCapture&) = delete;

    std::string text() {
        omerr().flush();
        omlog().flush();
        omout().flush();
        return captured_.str();
    }

private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    std::lock_guard<std::mutex> lock_;
    std::ostringstream captured_;
    std::streambuf* saved_cerr_ = nullptr;
    bool cerr_was_connected_ = false, clog_was_connected_ = false, cout_was_connected_ = false;
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

// ---------------------------------------------------------------------------------------------
// Text checks before OpenMesh sees a file.

struct Line {
    std::size_t number;  // 1-based
    std::vector<std::string_view> tokens;
};

// Splits text into lines of whitespace-separated tokens; text from `comment` to the end of a line
// is dropped (pass '\0' for none). Lines without tokens are skipped.
std::vector<Line> tokenize(std::string_view text, char comment) {
    std::vector<Line> lines;
    std::size_t number = 0, pos = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++number;
        if (comment != '\0') line = line.substr(0, line.find(comment));
        Line parsed{number, {}};
        std::size_t i = 0;
        while (i < line.size()) {
            while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
            std::size_t start = i;
            while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
            if (i > start) parsed.tokens.push_back(line.substr(start, i - start));
        }
        if (!parsed.tokens.empty()) lines.push_back(std::move(parsed));
    }
    return lines;
}

std::optional<double> parse_number(std::string_view token) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    double value = 0;
    auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (end != token.data() + token.size() || token.empty()) return std::nullopt;
    if (ec == std::errc::result_out_of_range) return HUGE_VAL;  // beyond double: certainly not finite as float
    if (ec != std::errc()) return std::nullopt;
    return value;
}

std::optional<long long> parse_integer(std::string_view token) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    long long value = 0;
    auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size() || token.empty()) return std::nullopt;
    return value;
}

class TextChecker {
public:
    explicit TextChecker(const std::filesystem::path& file) : file_(file) {}

    [[noreturn]] void fail(std::size_t line, const std::string& message) const {
        throw Error("{}:{}: {}", display(file_), line, message);
    }
    [[noreturn]] void fail(const std::string& message) const {
        throw Error("{}: {}", display(file_), message);
    }

    // The first three tokens from `first` must be finite numbers representable as float.
    void coordinates(const Line& line, std::size_t first) const {
        if (line.tokens.size() < first + 3) fail(line.number, "a vertex needs 3 coordinates");
        for (std::size_t i = first; i < first + 3; ++i) {
            std::optional<double> v = parse_number(line.tokens[i]);
            if (!v) fail(line.number, fmt::format("vertex coordinate '{}' is not a number", line.tokens[i]));
            if (!std::isfinite(*v) || std::fabs(*v) > FLT_MAX)
                fail(line.number, fmt::format("vertex coordinate '{}' is not a finite number", line.tokens[i]));
        }
    }

    void check_obj(std::string_view text) const {
        std::vector<Line> lines = tokenize(text, '#');
        long long vertices = 0;
        long long largest = 0;
        std::size_t largest_line = 0;
        for (const Line& line : lines) {
            std::string_view kind = line.tokens[0];
            if (kind == "v") {
                coordinates(line, 1);
                ++vertices;
            } else if (kind == "f") {
                if (line.tokens.size() < 4) fail(line.number, "a face needs at least 3 vertices");
                for (std::size_t i = 1; i < line.tokens.size(); ++i) {
                    std::string_view ref = line.tokens[i];
                    std::optional<long long> index = parse_integer(ref.substr(0, ref.find('/')));
                    if (!index || *index == 0)
                        fail(line.number, fmt::format("'{}' is not a vertex reference", ref));
                    if (*index < 0 && -*index > vertices)
                        fail(line.number, fmt::format("vertex reference {} goes before the first vertex", *index));
                    if (*index > largest) {
                        largest = *index;
                        largest_line = line.number;
                    }
                }
            }
        }
        if (largest > vertices)
            fail(largest_line, fmt::format("vertex index {} is out of range (the file has {} vertices)",
                                           largest, vertices));
    }

    // Returns the file re-written for OpenMesh's reader: no comments, counts on their own line.
    std::string check_off(std::string_view text) const {
        std::vector<Line> lines = tokenize(text, '#');
        if (lines.empty()) fail("is empty");
        const Line& header = lines[0];
        std::string keyword = std::string(header.tokens[0]);
        if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0 ||
            keyword.find_first_not_of("STCN4nOF") != std::string::npos)
            fail(header.number, "not an OFF file (it must start with OFF)");
        std::vector<std::string_view> counts(header.tokens.begin() + 1, header.tokens.end());
        if (!counts.empty() && counts[0] == "BINARY")
            fail(header.number, "binary OFF is not supported (OpenMesh reads it unreliably); use ASCII OFF or PLY");
        if (keyword.find_first_of("4n") != std::string::npos)
            fail(header.number, fmt::format("{} (homogeneous or n-dimensional) files are not supported", keyword));
        std::size_t next = 1;
        std::size_t counts_line = header.number;
        if (counts.empty()) {
            if (lines.size() < 2) fail(header.number, "the vertex and face counts are missing");
            counts = lines[1].tokens;
            counts_line = lines[1].number;
            next = 2;
        }
        if (counts.size() < 2) fail(counts_line, "expected the vertex and face counts");
        std::optional<long long> vertex_count = parse_integer(counts[0]);
        std::optional<long long> face_count = parse_integer(counts[1]);
        if (!vertex_count || !face_count || *vertex_count < 0 || *face_count < 0)
            fail(counts_line, "the vertex and face counts must be non-negative integers");
        if (static_cast<long long>(lines.size() - next) < *vertex_count + *face_count)
            fail(fmt::format("ends early: the header promises {} vertices and {} faces", *vertex_count,
                             *face_count));
        std::string cleaned = keyword + "\n" + std::string(counts[0]) + " " + std::string(counts[1]) + " 0\n";
        auto append = [&cleaned](const Line& line) {
            for (std::string_view token : line.tokens) (cleaned += token) += ' ';
            cleaned += '\n';
        };
        for (long long v = 0; v < *vertex_count; ++v) {
            coordinates(lines[next], 0);  // x y z come first
            append(lines[next++]);
        }
        for (long long f = 0; f < *face_count; ++f) {
            const Line& line = lines[next++];
            append(line);
            std::optional<long long> corners = parse_integer(line.tokens[0]);
            if (!corners) fail(line.number, fmt::format("'{}' is not a corner count", line.tokens[0]));
            if (*corners < 3) fail(line.number, "a face needs at least 3 vertices");
            if (static_cast<long long>(line.tokens.size()) < *corners + 1)
                fail(line.number, fmt::format("the face lists fewer than its {} vertices", *corners));
            for (long long i = 1; i <= *corners; ++i) {
                std::optional<long long> index = parse_integer(line.tokens[i]);
                if (!index) fail(line.number, fmt::format("'{}' is not a vertex index", line.tokens[i]));
                if (*index < 0 || *index >= *vertex_count)
                    fail(line.number, fmt::format("vertex index {} is out of range (the file has {} vertices)",
                                                  *index, *vertex_count));
            }
        }
        return cleaned;
    }

    // Walks the whole file the way a PLY reader would, ASCII or binary, so that OpenMesh only sees
    // files whose counts match their contents.
    void check_ply(std::string_view text) const {
        // The header: lines up to end_header.
        std::size_t header_end = std::string_view::npos;  // byte offset of the body
        for (std::size_t pos = 0; pos < text.size();) {
            std::size_t eol = text.find('\n', pos);
            std::string_view line = text.substr(pos, eol == std::string_view::npos ? std::string_view::npos : eol - pos);
            while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.remove_suffix(1);
            if (line == "end_header") {
                header_end = eol == std::string_view::npos ? text.size() : eol + 1;
                break;
            }
            if (eol == std::string_view::npos) break;
            pos = eol + 1;
        }
        std::vector<Line> lines = tokenize(text.substr(0, header_end == std::string_view::npos ? text.size() : header_end), '\0');
        if (lines.empty() || lines[0].number != 1 || lines[0].tokens.size() != 1 || lines[0].tokens[0] != "ply")
            fail(1, "not a PLY file (its first line must be ply)");
        if (header_end == std::string_view::npos) fail("the PLY header has no end_header line");

        struct Property {
            std::string name;
            std::string type;        // scalar type, or the item type of a list
            std::string count_type;  // lists only
        };
        struct Element {
            std::string name;
            long long count = 0;
            std::vector<Property> properties;
        };
        static const std::array<std::pair<std::string_view, int>, 16> types = {{
            {"char", 1}, {"uchar", 1}, {"short", 2}, {"ushort", 2}, {"int", 4}, {"uint", 4}, {"float", 4},
            {"double", 8}, {"int8", 1}, {"uint8", 1}, {"int16", 2}, {"uint16", 2}, {"int32", 4}, {"uint32", 4},
            {"float32", 4}, {"float64", 8}}};
        auto type_size = [&](std::string_view t) {
            for (auto [name, size] : types)
                if (name == t) return size;
            return 0;
        };

        std::vector<Element> elements;
        std::string format;
        for (std::size_t i = 1; i < lines.size(); ++i) {
            const Line& line = lines[i];
            std::string_view key = line.tokens[0];
            if (key == "end_header") break;
            if (key == "format") {
                if (line.tokens.size() != 3 || line.tokens[2] != "1.0")
                    fail(line.number, "expected: format ascii|binary_little_endian|binary_big_endian 1.0");
                format = std::string(line.tokens[1]);
                if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
                    fail(line.number, fmt::format("unknown PLY format '{}'", format));
            } else if (key == "element") {
                std::optional<long long> count =
                    line.tokens.size() == 3 ? parse_integer(line.tokens[2]) : std::nullopt;
                if (!count || *count < 0) fail(line.number, "expected: element <name> <count>");
                elements.push_back({std::string(line.tokens[1]), *count, {}});
            } else if (key == "property") {
                if (elements.empty()) fail(line.number, "property before any element");
                bool list = line.tokens.size() >= 2 && line.tokens[1] == "list";
                if (list ? (line.tokens.size() != 5 || !type_size(line.tokens[2]) || !type_size(line.tokens[3]))
                         : (line.tokens.size() != 3 || !type_size(line.tokens[1])))
                    fail(line.number, "expected: property <type> <name> or property list <type> <type> <name>");
                if (list)
                    elements.back().properties.push_back(
                        {std::string(line.tokens[4]), std::string(line.tokens[3]), std::string(line.tokens[2])});
                else
                    elements.back().properties.push_back({std::string(line.tokens[2]), std::string(line.tokens[1]), {}});
            } else if (key != "comment" && key != "obj_info") {
                fail(line.number, fmt::format("unknown PLY header line '{}'", key));
            }
        }
        if (format.empty()) fail("the PLY header has no format line");

        // The body, as a stream of numbers: tokens for ASCII, fixed-size values for binary.
        // `where` is a line number for ASCII (0 when binary, whose messages name no line).
        const bool ascii = format == "ascii";
        const bool swap = (format == "binary_big_endian") == (std::endian::native == std::endian::little);
        const std::string_view body = text.substr(header_end);
        std::vector<Line> body_lines;
        if (ascii) {
            body_lines = tokenize(body, '\0');
            const auto header_lines = static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(header_end), '\n'));
            for (Line& line : body_lines) line.number += header_lines;
        }
        std::size_t line_index = 0, token_index = 0, byte = 0;
        std::size_t where = 0;
        auto fail_at = [&](const std::string& message) {
            if (ascii) fail(where, message);
            fail(message);
        };
        auto next = [&](const Element& element, std::string_view type) -> double {
            if (ascii) {
                while (line_index < body_lines.size() && token_index >= body_lines[line_index].tokens.size()) {
                    ++line_index;
                    token_index = 0;
                }
                if (line_index >= body_lines.size())
                    fail(fmt::format("ends early while reading the '{}' elements", element.name));
                const Line& line = body_lines[line_index];
                where = line.number;
                std::string_view token = line.tokens[token_index++];
                std::optional<double> v = parse_number(token);
                if (!v) fail(where, fmt::format("'{}' is not a number", token));
                return *v;
            }
            const std::size_t size = static_cast<std::size_t>(type_size(type));
            if (body.size() - byte < size)
                fail(fmt::format("ends early while reading the '{}' elements", element.name));
            unsigned char raw[8];
            std::memcpy(raw, body.data() + byte, size);
            byte += size;
            if (swap) std::reverse(raw, raw + size);
            auto as = [&raw](auto value) {
                std::memcpy(&value, raw, sizeof value);
                return static_cast<double>(value);
            };
            if (type == "char" || type == "int8") return as(int8_t{});
            if (type == "uchar" || type == "uint8") return as(uint8_t{});
            if (type == "short" || type == "int16") return as(int16_t{});
            if (type == "ushort" || type == "uint16") return as(uint16_t{});
            if (type == "int" || type == "int32") return as(int32_t{});
            if (type == "uint" || type == "uint32") return as(uint32_t{});
            if (type == "float" || type == "float32") return as(float{});
            return as(double{});
        };

        long long vertex_count = -1;
        for (const Element& element : elements) {
            const bool is_vertex = element.name == "vertex";
            const bool is_face = element.name == "face";
            if (is_vertex) vertex_count = element.count;
            for (long long e = 0; e < element.count; ++e) {
                for (const Property& property : element.properties) {
                    if (property.count_type.empty()) {
                        double v = next(element, property.type);
                        bool coordinate = is_vertex && (property.name == "x" || property.name == "y" || property.name == "z");
                        if (coordinate && (!std::isfinite(v) || std::fabs(v) > FLT_MAX))
                            fail_at(fmt::format("vertex {} has a coordinate that is not a finite number", e));
                        continue;
                    }
                    double count = next(element, property.count_type);
                    if (!(count >= 0) || count != std::floor(count)) fail_at(fmt::format("{} is not a list length", count));
                    const bool indices = is_face && (property.name == "vertex_indices" || property.name == "vertex_index");
                    if (indices && count < 3) fail_at(fmt::format("face {} has fewer than 3 vertices", e));
                    for (double i = 0; i < count; ++i) {
                        double index = next(element, property.type);
                        if (!indices) continue;
                        if (index != std::floor(index) || index < 0 || (vertex_count >= 0 && index >= vertex_count))
                            fail_at(fmt::format("vertex index {} is out of range (the file has {} vertices)", index,
                                                std::max(vertex_count, 0LL)));
                    }
                }
            }
        }
    }

    void check_stl(std::string_view text) const {
        bool ascii = text.size() >= 5 && text.substr(0, 5) == "solid";
        if (text.size() >= 84) {
            uint32_t triangles = 0;
            std::memcpy(&triangles, text.data() + 80, 4);  // little-endian count after the 80-byte header
            if (text.size() == 84 + 50ull * triangles) ascii = false;  // binary files may start with "solid" too
        }
        if (!ascii) {
            if (text.size() < 84) fail("is neither an ASCII STL (starting with solid) nor a binary STL");
            uint32_t triangles = 0;
            std::memcpy(&triangles, text.data() + 80, 4);
            if (text.size() < 84 + 50ull * triangles)
                fail(fmt::format("binary STL is truncated: it declares {} triangles but holds {}", triangles,
                                 (text.size() - 84) / 50));
            for (uint32_t t = 0; t < triangles; ++t) {  // normal, 3 corners, attribute bytes
                float corners[9];
                std::memcpy(corners, text.data() + 84 + 50ull * t + 12, sizeof corners);
                for (float c : corners)
                    if (!std::isfinite(c)) fail(fmt::format("triangle {} has a vertex coordinate that is not a finite number", t + 1));
            }
            return;
        }
        for (const Line& line : tokenize(text, '\0'))
            if (line.tokens[0] == "vertex") coordinates(line, 1);
    }

private:
    std::filesystem::path file_;
};

enum class Format { obj, off, ply, stl };

Format format_of(const std::filesystem::path& file) {
    std::string extension = lower(file.extension().string());
    if (extension == ".obj") return Format::obj;
    if (extension == ".off") return Format::off;
    if (extension == ".ply") return Format::ply;
    if (extension == ".stl") return Format::stl;
    throw Error("{}: unsupported model format '{}' (use .obj, .off, .ply or .stl)", display(file),
                extension.empty() ? "no extension" : extension);
}

std::string read_whole_file(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) throw Error("{}: no such file", display(file));
    if (std::filesystem::is_directory(file, ec)) throw Error("{}: is a directory, not a model file", display(file));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error("{}: cannot open the file for reading", display(file));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
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

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Object load_object(const std::filesystem::path& file) {
    Format format = format_of(file);
    std::optional<std::string> cleaned;
    {
        std::string text = read_whole_file(file);
        TextChecker check(file);
        switch (format) {
        case Format::obj: check.check_obj(text); break;
        case Format::off: cleaned = check.check_off(text); break;
        case Format::ply: check.check_ply(text); break;
        case Format::stl: check.check_stl(text); break;
        }
    }

    TriMesh mesh;
    mesh.request_face_status();
    std::string chatter;
    bool read = false;
    {
        OpenMeshCapture capture;
        try {
            if (cleaned) {
                std::istringstream stream(*cleaned);
                OpenMesh::IO::Options options;
                read = OpenMesh::IO::read_mesh(mesh, stream, ".off", options);
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
                    reason.empty() ? "" : " (" + reason + ")");
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

// ---------------------------------------------------------------------------------------------
// Polygon triangulation.

double cross2(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Whether closed segments ab and cd share a point.
bool segments_touch(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
    auto on_segment = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r) {  // r collinear with pq
        return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
               r.y <= std::max(p.y, q.y);
    };
    const double d1 = cross2(c, d, a), d2 = cross2(c, d, b), d3 = cross2(a, b, c), d4 = cross2(a, b, d);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
    return (d1 == 0 && on_segment(c, d, a)) || (d2 == 0 && on_segment(c, d, b)) ||
           (d3 == 0 && on_segment(a, b, c)) || (d4 == 0 && on_segment(a, b, d));
}

// Throws if two edges that are not neighbours along the outline meet.
void check_simple(const std::vector<glm::dvec2>& points, const std::string& what) {
    const std::size_t n = points.size();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // neighbouring edges share a corner
            if (segments_touch(points[i], points[(i + 1) % n], points[j], points[(j + 1) % n]))
                throw Error("{}: the polygon intersects itself (edges {} and {} meet)", what, i + 1, j + 1);
        }
}

// Ear clipping of a counter-clockwise simple polygon; returns corner indices, 3 per triangle.
// Collinear corners are removed without a triangle (they add no area).
std::vector<uint32_t> ear_clip(const std::vector<glm::dvec2>& points, const std::string& what) {
    std::vector<uint32_t> remaining(points.size());
    for (uint32_t i = 0; i < remaining.size(); ++i) remaining[i] = i;
    std::vector<uint32_t> triangles;
    std::size_t i = 0, misses = 0;
    while (remaining.size() > 3) {
        std::size_t n = remaining.size();
        uint32_t a = remaining[(i + n - 1) % n], b = remaining[i % n], c = remaining[(i + 1) % n];
        double turn = cross2(points[a], points[b], points[c]);
        bool clip = false;
        if (turn == 0.0) {
            clip = true;  // b lies on the line through its neighbours
        } else if (turn > 0.0) {
            clip = true;
            for (uint32_t p : remaining) {
                if (p == a || p == b || p == c) continue;
                glm::dvec2 q = points[p];
                if (q == points[a] || q == points[b] || q == points[c]) continue;
                if (cross2(points[a], points[b], q) >= 0 && cross2(points[b], points[c], q) >= 0 &&
                    cross2(points[c], points[a], q) >= 0) {
                    clip = false;
                    break;
                }
            }
        }
        if (clip) {
            if (turn != 0.0) triangles.insert(triangles.end(), {a, b, c});
            remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(i % n));
            misses = 0;
            if (i >= remaining.size()) i = 0;
        } else {
            if (++misses > n) throw Error("{}: the polygon intersects itself", what);
            i = (i + 1) % n;
        }
    }
    if (cross2(points[remaining[0]], points[remaining[1]], points[remaining[2]]) != 0.0)
        triangles.insert(triangles.end(), {remaining[0], remaining[1], remaining[2]});
    return triangles;
}

// ---------------------------------------------------------------------------------------------
// Building the scene.

double corner_angle(const glm::dvec3& p, const glm::dvec3& next, const glm::dvec3& prev) {
    glm::dvec3 u = next - p, v = prev - p;
    return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

void push3(std::vector<float>& out, glm::dvec3 v) {
    out.push_back(static_cast<float>(v.x));
    out.push_back(static_cast<float>(v.y));
    out.push_back(static_cast<float>(v.z));
}

}  // namespace

hsr_scene SceneData::view() const {
    hsr_scene s{};
    s.struct_size = sizeof(hsr_scene);
    s.vertex_count = vertex_count();
    s.triangle_count = triangle_count();
    s.object_count = static_cast<uint32_t>(object_names.size());
    s.positions = positions.data();
    s.indices = indices.data();
    s.face_normals = face_normals.data();
    s.corner_normals = corner_normals.data();
    s.face_colors = face_colors.data();
    s.edge_neighbors = edge_neighbors.data();
    s.face_object = face_object.data();
    for (int i = 0; i < 3; ++i) {
        s.bounds_min[i] = bounds_min[i];
        s.bounds_max[i] = bounds_max[i];
    }
    s.instance_count = static_cast<uint32_t>(instances.size());
    s.instances = instances.empty() ? nullptr : instances.data();
    return s;
}

void SceneBuilder::add_model_file(const std::filesystem::path& file, const MeshOptions& options) {
    Object object = load_object(file);
    object.options = options;
    if (object.options.name.empty()) object.options.name = file.stem().string();
    objects_.push_back(std::move(object));
}

void SceneBuilder::add_triangles(std::span<const glm::vec3> positions, std::span<const uint32_t> indices,
                                 const MeshOptions& options) {
    std::string name = options.name.empty() ? fmt::format("object {}", objects_.size() + 1) : options.name;
    Object object = object_from_triangles(positions, indices, name);
    object.options = options;
    object.options.name = name;
    objects_.push_back(std::move(object));
}

void SceneBuilder::add_polygon(std::span<const glm::vec3> vertices, glm::vec3 color, const std::string& name) {
    std::string what = name.empty() ? fmt::format("polygon {}", objects_.size() + 1) : "polygon '" + name + "'";
    std::vector<glm::dvec3> corners;
    for (glm::vec3 v : vertices) {
        if (!finite(v)) throw Error("{}: a vertex has a coordinate that is not a finite number", what);
        if (corners.empty() || glm::dvec3(v) != corners.back()) corners.emplace_back(v);
    }
    while (corners.size() > 1 && corners.front() == corners.back()) corners.pop_back();
    if (corners.size() < 3) throw Error("{}: needs at least 3 distinct vertices", what);

    glm::dvec3 centre(0.0);
    for (const glm::dvec3& c : corners) centre += c;
    centre /= static_cast<double>(corners.size());
    glm::dvec3 normal(0.0);  // Newell's method: twice the vector area
    double extent = 0.0;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        glm::dvec3 a = corners[i] - centre, b = corners[(i + 1) % corners.size()] - centre;
        normal += glm::cross(a, b);
        extent = std::max(extent, glm::length(a));
    }
    double area2 = glm::length(normal);
    if (!(area2 > 1e-12 * extent * extent)) throw Error("{}: has no area (its vertices are collinear)", what);
    normal /= area2;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        double off = std::fabs(glm::dot(corners[i] - centre, normal));
        if (off > 1e-4 * extent)
            throw Error("{}: is not planar (vertex {} lies {:.3g} off the polygon's plane)", what, i + 1, off);
    }

    // Project onto the coordinate plane the polygon faces most, keeping counter-clockwise order.
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (std::fabs(normal[k]) > std::fabs(normal[axis])) axis = k;
    int u = (axis + 1) % 3, w = (axis + 2) % 3;
    if (normal[axis] < 0) std::swap(u, w);
    std::vector<glm::dvec2> flat;
    for (const glm::dvec3& c : corners) flat.emplace_back(c[u], c[w]);
    check_simple(flat, what);
    std::vector<uint32_t> triangles = ear_clip(flat, what);

    std::vector<glm::vec3> positions(corners.begin(), corners.end());
    MeshOptions options;
    options.color = color;
    options.name = name.empty() ? fmt::format("polygon {}", objects_.size() + 1) : name;
    Object object = object_from_triangles(positions, triangles, what);
    object.options = options;
    objects_.push_back(std::move(object));
}

SceneData SceneBuilder::build() const {
    SceneData scene;
    std::vector<float> crease_cosines;  // per object
    std::size_t total_triangles = 0;
    for (const Object& object : objects_) total_triangles += object.indices.size() / 3;
    scene.indices.reserve(3 * total_triangles);
    scene.edge_neighbors.reserve(3 * total_triangles);
    scene.face_normals.reserve(3 * total_triangles);
    scene.face_colors.reserve(3 * total_triangles);
    scene.face_object.reserve(total_triangles);
    std::vector<glm::dvec3> world;      // all kept vertices, double precision for normals
    std::vector<glm::dvec3> normals;    // per kept triangle

    for (std::size_t o = 0; o < objects_.size(); ++o) {
        const Object& object = objects_[o];
        const MeshOptions& options = object.options;
        const std::string& name = options.name;
        const glm::dmat4 transform(options.transform);
        for (int c = 0; c < 4; ++c)
            if (!finite(glm::vec3(options.transform[c])) || !std::isfinite(options.transform[c][3]))
                throw Error("{}: the transform has a value that is not a finite number", name);
        if (!(options.crease_angle_degrees >= 0.0f && options.crease_angle_degrees <= 180.0f))
            throw Error("{}: crease angle {} is outside [0, 180] degrees", name, options.crease_angle_degrees);
        for (int k = 0; k < 3; ++k)
            if (!(options.color[k] >= 0.0f && options.color[k] <= 1.0f))
                throw Error("{}: colour channel {} is outside [0, 1]", name, options.color[k]);
        const bool mirrored = glm::determinant(glm::dmat3(transform)) < 0.0;

        std::vector<glm::dvec3> local_world(object.positions.size());
        for (std::size_t v = 0; v < object.positions.size(); ++v) {
            glm::dvec4 p = transform * glm::dvec4(glm::dvec3(object.positions[v]), 1.0);
            local_world[v] = glm::dvec3(p) / p.w;
            if (!std::isfinite(local_world[v].x) || !std::isfinite(local_world[v].y) ||
                !std::isfinite(local_world[v].z) || std::fabs(local_world[v].x) > FLT_MAX ||
                std::fabs(local_world[v].y) > FLT_MAX || std::fabs(local_world[v].z) > FLT_MAX)
                throw Error("{}: the transform moves vertex {} to a non-finite position", name, v);
        }

        // Keep triangles with a well-defined normal; number them in the merged scene.
        const std::size_t triangle_count = object.indices.size() / 3;
        const uint32_t first_triangle = static_cast<uint32_t>(scene.indices.size() / 3);
        std::vector<int32_t> new_triangle(triangle_count, -1);
        std::vector<glm::dvec3> kept_normals;
        uint32_t kept = 0;
        for (std::size_t t = 0; t < triangle_count; ++t) {
            const glm::dvec3& a = local_world[object.indices[3 * t]];
            const glm::dvec3& b = local_world[object.indices[3 * t + 1]];
            const glm::dvec3& c = local_world[object.indices[3 * t + 2]];
            glm::dvec3 n = glm::cross(b - a, c - a);
            if (mirrored) n = -n;
            double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
            double length = glm::length(n);
            if (!(length > 1e-12 * longest * longest) || !std::isfinite(length)) continue;
            new_triangle[t] = static_cast<int32_t>(first_triangle + kept++);
            kept_normals.push_back(n / length);
        }
        if (kept < triangle_count)
            scene.warnings.push_back(fmt::format("{}: {} triangle{} without area dropped", object.source,
                                                 triangle_count - kept, triangle_count - kept == 1 ? "" : "s"));
        if (object.separated_faces > 0)
            scene.warnings.push_back(fmt::format("{}: {} non-manifold face{} given separate vertices",
                                                 object.source, object.separated_faces,
                                                 object.separated_faces == 1 ? "" : "s"));

        // Only vertices of kept triangles enter the scene.
        std::vector<int64_t> new_vertex(object.positions.size(), -1);
        for (std::size_t t = 0; t < triangle_count; ++t) {
            if (new_triangle[t] < 0) continue;
            std::array<uint32_t, 3> corner;
            std::array<int32_t, 3> across;
            for (int k = 0; k < 3; ++k) {
                uint32_t v = object.indices[3 * t + k];
                if (new_vertex[v] < 0) {
                    new_vertex[v] = static_cast<int64_t>(world.size());
                    world.push_back(local_world[v]);
                }
                corner[k] = static_cast<uint32_t>(new_vertex[v]);
                int32_t neighbor = object.neighbors[3 * t + k];
                across[k] = neighbor < 0 ? HSR_NO_NEIGHBOR : new_triangle[static_cast<std::size_t>(neighbor)];
            }
            if (mirrored) {  // (a, b, c) -> (a, c, b): edges a-c, c-b, b-a were edges 2, 1, 0
                std::swap(corner[1], corner[2]);
                std::swap(across[0], across[2]);
            }
            scene.indices.insert(scene.indices.end(), corner.begin(), corner.end());
            scene.edge_neighbors.insert(scene.edge_neighbors.end(), across.begin(), across.end());
            scene.face_object.push_back(static_cast<uint32_t>(o));
            scene.face_colors.insert(scene.face_colors.end(), {options.color.r, options.color.g, options.color.b});
        }
        for (const glm::dvec3& n : kept_normals) {
            normals.push_back(n);
            push3(scene.face_normals, n);
        }
        scene.object_names.push_back(name);
        crease_cosines.push_back(static_cast<float>(std::cos(glm::radians(double(options.crease_angle_degrees)))));
    }
    if (scene.indices.empty()) throw Error("the scene has no triangles");

    scene.positions.reserve(3 * world.size());
    for (const glm::dvec3& p : world) push3(scene.positions, p);
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const glm::dvec3& p : world) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    scene.bounds_min = glm::vec3(lo);
    scene.bounds_max = glm::vec3(hi);

    // Corner normals: for each vertex, the (triangle, corner) pairs around it.
    const std::size_t triangles = scene.triangle_count();
    std::vector<uint32_t> start(world.size() + 1, 0);
    for (uint32_t v : scene.indices) ++start[v + 1];
    for (std::size_t v = 0; v < world.size(); ++v) start[v + 1] += start[v];
    std::vector<uint32_t> around(scene.indices.size());  // corner ids 3t+k
    {
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (uint32_t corner = 0; corner < scene.indices.size(); ++corner) around[fill[scene.indices[corner]]++] = corner;
    }
    std::vector<double> angle(scene.indices.size());
    for (std::size_t t = 0; t < triangles; ++t)
        for (int k = 0; k < 3; ++k)
            angle[3 * t + k] = corner_angle(world[scene.indices[3 * t + k]], world[scene.indices[3 * t + (k + 1) % 3]],
                                            world[scene.indices[3 * t + (k + 2) % 3]]);
    scene.corner_normals.reserve(9 * triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        const glm::dvec3& own = normals[t];
        const double limit = static_cast<double>(crease_cosines[scene.face_object[t]]) - 1e-6;
        for (int k = 0; k < 3; ++k) {
            uint32_t v = scene.indices[3 * t + k];
            glm::dvec3 sum(0.0);
            for (uint32_t i = start[v]; i < start[v + 1]; ++i) {
                uint32_t corner = around[i];
                const glm::dvec3& other = normals[corner / 3];
                if (glm::dot(own, other) >= limit) sum += angle[corner] * other;
            }
            double length = glm::length(sum);
            push3(scene.corner_normals, length > 1e-12 ? sum / length : own);
        }
    }
    return scene;
}

SceneData load_model(const std::filesystem::path& file, const MeshOptions& options) {
    SceneBuilder builder;
    builder.add_model_file(file, options);
    return builder.build();
}

}  // namespace hsr
