// Model files checked before OpenMesh reads them (see malformed_models.hpp): the text is split into
// lines of tokens, or walked value by value for binary PLY and STL, with line numbers for messages.
// One file, over 700 lines, because one class (TextChecker) checks all four formats: they share its
// tokenizer, number parsing, messages and the stored-triangles count, and the OBJ checks in pieces
// run that class's line checks on each piece.
#include "malformed_models.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cctype>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace hsr {
namespace {

struct Line {
    std::size_t number;  // 1-based
    std::string_view text;  // the whole line, without its '\n'
    std::vector<std::string_view> tokens;
};

// std::isspace in the "C" locale (hsr never changes the locale), inline: the checks call it for
// every byte of a model.
constexpr bool is_space(char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }

// The line of text that starts at pos, without its '\n'; moves pos past it. pos < text.size().
std::string_view take_line(std::string_view text, std::size_t& pos) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    return line;
}

// The lines of a text one at a time, as whitespace-separated tokens: text from `comment` to the end
// of a line is dropped ('\0' for none) and lines without tokens are skipped. Only the current line
// is held, so checking a file takes memory for its longest line, not for the whole file in tokens.
class LineReader {
public:
    LineReader(std::string_view text, char comment, std::size_t lines_before = 0)
        : text_(text), comment_(comment), line_{lines_before, {}, {}} {}

    // The next line with tokens, or nullptr at the end of the text; valid until the next call.
    const Line* next() {
        while (pos_ < text_.size()) {
            std::string_view line = take_line(text_, pos_);
            ++line_.number;
            line_.text = line;
            if (comment_ != '\0') line = line.substr(0, line.find(comment_));
            line_.tokens.clear();
            const char* c = line.data();
            const char* const line_end = c + line.size();
            while (c < line_end) {
                while (c < line_end && is_space(*c)) ++c;
                const char* start = c;
                while (c < line_end && !is_space(*c)) ++c;
                if (c > start) line_.tokens.emplace_back(start, static_cast<std::size_t>(c - start));
            }
            if (!line_.tokens.empty()) return &line_;
        }
        return nullptr;
    }

private:
    std::string_view text_;
    char comment_;
    std::size_t pos_ = 0;
    Line line_;
};

std::optional<double> parse_number(std::string_view token) {
    if (token.starts_with("+-")) return std::nullopt;  // the readers take no second sign
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    double value = 0;
    auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (end != token.data() + token.size() || token.empty()) return std::nullopt;
    if (ec == std::errc::result_out_of_range) return HUGE_VAL;  // beyond double: certainly not finite as float
    if (ec != std::errc()) return std::nullopt;
    return value;
}

std::optional<long long> parse_integer(std::string_view token) {
    if (token.starts_with("+-")) return std::nullopt;
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    long long value = 0;
    auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size() || token.empty()) return std::nullopt;
    return value;
}

// The float that OpenMesh's reader (operator>>, which calls strtof) makes of a token that
// parse_number accepts; from_chars rounds as strtof does, and leaves underflow to it.
float openmesh_float(std::string_view token) {
    if (token.starts_with('+')) token.remove_prefix(1);
    float value = 0;
    if (std::from_chars(token.data(), token.data() + token.size(), value).ec == std::errc()) return value;
    return std::strtof(std::string(token).c_str(), nullptr);
}

// OpenMesh splits a polygon into a fan in time quadratic in its corners (each new triangle
// searches the first corner's growing fan), so a face takes at most this many.
constexpr long long max_face_corners = 1000;
// Real PLY files have a few elements of a few properties; these bound what a header can make the
// checks store.
constexpr std::size_t max_ply_elements = 1000;
constexpr std::size_t max_ply_properties = 1000;
const std::string too_many_corners = fmt::format("a face with more than {} vertices", max_face_corners);

// Text from the file in single quotes, as printable() makes it.
std::string in_quotes(std::string_view text) { return fmt::format("'{}'", printable(text)); }

// The PLY scalar types: each name, its size in bytes and what a value of it is in memory.
enum class PlyScalar { int8, uint8, int16, uint16, int32, uint32, float32, float64 };
struct PlyType {
    std::string_view name;
    int size;
    PlyScalar scalar;
};
constexpr std::array<PlyType, 16> ply_types = {{
    {"char", 1, PlyScalar::int8}, {"uchar", 1, PlyScalar::uint8}, {"short", 2, PlyScalar::int16},
    {"ushort", 2, PlyScalar::uint16}, {"int", 4, PlyScalar::int32}, {"uint", 4, PlyScalar::uint32},
    {"float", 4, PlyScalar::float32}, {"double", 8, PlyScalar::float64}, {"int8", 1, PlyScalar::int8},
    {"uint8", 1, PlyScalar::uint8}, {"int16", 2, PlyScalar::int16}, {"uint16", 2, PlyScalar::uint16},
    {"int32", 4, PlyScalar::int32}, {"uint32", 4, PlyScalar::uint32}, {"float32", 4, PlyScalar::float32},
    {"float64", 8, PlyScalar::float64}}};

// The type a word of a PLY header names, nullptr for a word that is none.
const PlyType* ply_type(std::string_view name) {
    for (const PlyType& type : ply_types)
        if (type.name == name) return &type;
    return nullptr;
}

// What a PLY header declares. The types are looked up once, there, rather than for every value.
struct PlyProperty {
    std::string name;
    const PlyType* type;                  // scalar type, or the item type of a list
    const PlyType* count_type = nullptr;  // lists only
};
struct PlyElement {
    std::string name;
    long long count = 0;
    std::vector<PlyProperty> properties;
};
struct PlyHeader {
    std::vector<PlyElement> elements;
    std::string format;
};

// The byte offset of a PLY file's body: just after the header's end_header line (npos without one).
std::size_t ply_header_end(std::string_view text) {
    for (std::size_t pos = 0; pos < text.size();) {
        std::size_t eol = text.find('\n', pos);
        std::string_view line = text.substr(pos, eol == std::string_view::npos ? std::string_view::npos : eol - pos);
        while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.remove_suffix(1);
        if (line == "end_header") return eol == std::string_view::npos ? text.size() : eol + 1;
        if (eol == std::string_view::npos) break;
        pos = eol + 1;
    }
    return std::string_view::npos;
}

class TextChecker {
public:
    explicit TextChecker(const std::filesystem::path& file) : file_(file) {}

    [[noreturn]] void fail(std::size_t line, const std::string& message) const {
        throw Error("{}:{}: {}", printable(file_.string(), kMaxQuotedPathChars), line, message);
    }
    [[noreturn]] void fail(const std::string& message) const {
        throw Error("{}: {}", printable(file_.string(), kMaxQuotedPathChars), message);
    }

    // Length of a UTF-8 byte-order mark at the start of text (some editors write one), which the
    // readers would take for part of the first word; UTF-16 text is refused, as a reader of ASCII
    // finds a NUL between each two characters.
    std::size_t byte_order_mark(std::string_view text) const {
        if (text.starts_with("\xEF\xBB\xBF")) return 3;
        if (text.starts_with("\xFE\xFF") || text.starts_with("\xFF\xFE"))
            fail("is UTF-16 text (it starts with a UTF-16 byte-order mark); save it as ASCII or UTF-8");
        return 0;
    }

    // The first three tokens from `first` must be finite numbers representable as float.
    void coordinates(const Line& line, std::size_t first) const {
        if (line.tokens.size() < first + 3) fail(line.number, "a vertex needs 3 coordinates");
        for (std::size_t i = first; i < first + 3; ++i) {
            std::optional<double> v = parse_number(line.tokens[i]);
            if (!v) fail(line.number, fmt::format("vertex coordinate {} is not a number", in_quotes(line.tokens[i])));
            if (!std::isfinite(*v) || std::fabs(*v) > FLT_MAX)
                fail(line.number, fmt::format("vertex coordinate {} is not a finite number", in_quotes(line.tokens[i])));
        }
    }

    // Checks the text and returns what OpenMesh's OBJ reader reads from it once rewritten as
    // rewrite_obj does. That reader skips a line that starts with a vertical tab or form feed (it
    // trims only " \t\r\n"), which the checks read as any other line, so the vertices it counts
    // can fall behind theirs: its own count resolves relative references.
    ModelContents check_obj(std::string_view text) {
        text.remove_prefix(byte_order_mark(text));
        std::vector<ObjPiece> pieces(1);
        check_obj_lines(text, ObjCounts{}, pieces[0]);
        return finish_obj(pieces);
    }

    // check_obj on pieces of about piece_bytes, cut after a line end, on the threads oneTBB allows.
    // A first pass counts each piece's lines, vertices and stored triangles (a scan for the first
    // word of each line); with those sums, each piece is checked as if every line before it had been
    // (the line numbers, the vertex counts relative references resolve against, the triangles the
    // limit counts). The first piece that fails fails the whole: every line before its first bad line
    // is good, so its counts, and so its message, are those of a check line by line.
    ModelContents check_obj_in_pieces(std::string_view text, std::size_t piece_bytes) {
        text.remove_prefix(byte_order_mark(text));
        std::vector<std::string_view> parts;
        while (!text.empty()) {
            std::size_t end = text.size();
            if (text.size() > piece_bytes) {
                const std::size_t line_end = text.find('\n', piece_bytes - 1);
                if (line_end != std::string_view::npos) end = line_end + 1;
            }
            parts.push_back(text.substr(0, end));
            text.remove_prefix(end);
        }
        if (parts.empty()) parts.emplace_back();
        std::vector<ObjCounts> counts(parts.size() + 1);  // counts[k + 1]: of part k alone, then before part k + 1
        tbb::parallel_for(std::size_t(0), parts.size(), [&](std::size_t k) { counts[k + 1] = count_obj_lines(parts[k]); });
        for (std::size_t k = 1; k < counts.size(); ++k) counts[k] += counts[k - 1];
        std::vector<ObjPiece> pieces(parts.size());
        std::atomic<std::size_t> first_failed{parts.size()};  // pieces after it need not be checked
        tbb::parallel_for(std::size_t(0), parts.size(), [&](std::size_t k) {
            if (k > first_failed.load()) return;
            try {
                TextChecker(file_).check_obj_lines(parts[k], counts[k], pieces[k]);
            } catch (...) {
                pieces[k].error = std::current_exception();
                std::size_t failed = first_failed.load();
                while (k < failed && !first_failed.compare_exchange_weak(failed, k)) {
                }
            }
        });
        for (const ObjPiece& piece : pieces)
            if (piece.error) std::rethrow_exception(piece.error);
        return finish_obj(pieces);
    }

private:
    // What checking an OBJ text carries from line to line.
    struct ObjCounts {
        std::size_t lines = 0;
        long long vertices = 0;
        long long openmesh_vertices = 0;  // the vertices as OpenMesh's reader counts them
        uint64_t triangles = 0;           // the faces' stored triangles, which the limit counts

        ObjCounts& operator+=(const ObjCounts& other) {
            lines += other.lines;
            vertices += other.vertices;
            openmesh_vertices += other.openmesh_vertices;
            triangles += other.triangles;
            return *this;
        }
    };
    // What the lines of a piece of an OBJ text hold.
    struct ObjPiece {
        ModelContents contents;
        long long vertices_after = 0;  // the file's vertices up to the piece's end, and OpenMesh's count
        long long openmesh_vertices_after = 0;
        long long largest = 0;  // the largest vertex reference, and the line of its first use
        std::size_t largest_line = 0;
        bool missing_vertex = false;  // a face refers to one OpenMesh's reader does not have
        std::exception_ptr error;
    };

    // Whether OpenMesh's OBJ reader skips the line (it trims only " \t\r\n", then sees no keyword).
    static bool openmesh_skips(std::string_view line) {
        const std::size_t first = line.find_first_not_of(" \t\r\n");
        return first != std::string_view::npos && is_space(line[first]);
    }

    // The counts of check_obj_lines for text whose lines are all good, from each line's first word
    // and, for a face, its number of words.
    static ObjCounts count_obj_lines(std::string_view text) {
        ObjCounts counts;
        std::size_t pos = 0;
        while (pos < text.size()) {
            const std::string_view line = take_line(text, pos);
            ++counts.lines;
            const std::string_view data = line.substr(0, line.find('#'));
            std::size_t c = 0;
            while (c < data.size() && is_space(data[c])) ++c;
            if (c + 1 > data.size() || (c + 1 < data.size() && !is_space(data[c + 1]))) continue;  // not one letter
            if (data[c] == 'v') {
                ++counts.vertices;
                if (!openmesh_skips(line)) ++counts.openmesh_vertices;
            } else if (data[c] == 'f') {
                uint64_t words = 0;
                for (std::size_t k = c; k < data.size(); ++k)
                    if (!is_space(data[k]) && (k == 0 || is_space(data[k - 1]))) ++words;
                if (words >= 4) counts.triangles += words - 3;
            }
        }
        return counts;
    }

    // Checks the lines of text, `before` being what the lines before it held, into piece.
    void check_obj_lines(std::string_view text, const ObjCounts& before, ObjPiece& piece) {
        LineReader lines(text, '#', before.lines);
        ModelContents& contents = piece.contents;
        long long vertices = before.vertices;
        long long openmesh_vertices = before.openmesh_vertices;
        triangles_ = before.triangles;
        while (const Line* next_line = lines.next()) {
            const Line& line = *next_line;
            std::string_view kind = line.tokens[0];
            const bool skipped = openmesh_skips(line.text);
            if (kind == "v") {
                std::array<float, 3> position;
                if (!obj_coordinates(line, position)) {
                    coordinates(line, 1);  // the message, or the value parsed the slow way
                    for (int k = 0; k < 3; ++k) position[k] = openmesh_float(line.tokens[1 + k]);
                }
                ++vertices;
                if (!skipped) {
                    contents.positions.push_back(position);
                    ++openmesh_vertices;
                }
            } else if (kind == "f") {
                if (line.tokens.size() < 4) fail(line.number, "a face needs at least 3 vertices");
                if (line.tokens.size() - 1 > max_face_corners) fail(line.number, too_many_corners);
                count_face(line.tokens.size() - 1);
                for (std::size_t i = 1; i < line.tokens.size(); ++i) {
                    std::string_view ref = line.tokens[i];
                    // vertex, vertex/texture, vertex//normal or vertex/texture/normal: OpenMesh's
                    // reader takes time quadratic in the number of slashes.
                    if (std::count(ref.begin(), ref.end(), '/') > 2)
                        fail(line.number, fmt::format("{} is not a vertex reference (more than two '/')", in_quotes(ref)));
                    std::optional<long long> index = parse_integer(ref.substr(0, ref.find('/')));
                    if (!index || *index == 0)
                        fail(line.number, fmt::format("{} is not a vertex reference", in_quotes(ref)));
                    if (*index < -vertices)
                        fail(line.number, fmt::format("vertex reference {} goes before the first vertex", *index));
                    if (*index > piece.largest) {
                        piece.largest = *index;
                        piece.largest_line = line.number;
                    }
                    if (skipped) continue;
                    const long long corner = (*index < 0 ? openmesh_vertices + *index + 1 : *index) - 1;
                    piece.missing_vertex = piece.missing_vertex || corner < 0;
                    contents.corners.push_back(static_cast<int32_t>(std::max(corner, -1LL)));
                }
                if (!skipped) contents.face_ends.push_back(static_cast<uint32_t>(contents.corners.size()));
            } else if (kind == "mtllib") {
                for (std::size_t i = 1; i < line.tokens.size(); ++i)
                    contents.material_libraries.emplace_back(line.tokens[i]);
            } else if (kind == "usemtl") {
                contents.material_uses.push_back({static_cast<uint32_t>(contents.face_ends.size()),
                                                  line.tokens.size() > 1 ? std::string(line.tokens[1]) : std::string()});
            } else if (kind == "o" || kind == "g") {
                std::string name;
                for (std::size_t i = 1; i < line.tokens.size(); ++i) name += (i > 1 ? " " : "") + std::string(line.tokens[i]);
                contents.groups.push_back({static_cast<uint32_t>(contents.face_ends.size()), std::move(name), kind == "o"});
            }
        }
        piece.vertices_after = vertices;
        piece.openmesh_vertices_after = openmesh_vertices;
    }

    // The checks of the whole file once its lines are checked, and the pieces' contents as one.
    ModelContents finish_obj(std::vector<ObjPiece>& pieces) const {
        long long largest = 0;
        std::size_t largest_line = 0;
        bool missing_vertex = false;
        std::size_t positions = 0, corners = 0, faces = 0;
        for (const ObjPiece& piece : pieces) {
            if (piece.largest > largest) {
                largest = piece.largest;
                largest_line = piece.largest_line;
            }
            missing_vertex = missing_vertex || piece.missing_vertex;
            positions += piece.contents.positions.size();
            corners += piece.contents.corners.size();
            faces += piece.contents.face_ends.size();
        }
        const long long vertices = pieces.back().vertices_after;
        const long long openmesh_vertices = pieces.back().openmesh_vertices_after;
        if (largest > vertices)
            fail(largest_line, fmt::format("vertex index {} is out of range (the file has {} vertices)",
                                           largest, vertices));
        if (pieces.size() == 1) {
            for (int32_t corner : pieces[0].contents.corners)
                missing_vertex = missing_vertex || corner >= openmesh_vertices;
            if (missing_vertex) fail("some faces refer to vertices that do not exist");
            return std::move(pieces[0].contents);
        }
        ModelContents contents;
        contents.positions.reserve(positions);
        contents.corners.reserve(corners);
        contents.face_ends.reserve(faces);
        for (const ObjPiece& piece : pieces) {
            const auto faces_before = static_cast<uint32_t>(contents.face_ends.size());
            for (const std::string& library : piece.contents.material_libraries)
                contents.material_libraries.push_back(library);
            for (const ModelContents::MaterialUse& use : piece.contents.material_uses)
                contents.material_uses.push_back({faces_before + use.first_face, use.name});
            for (const ModelContents::Group& group : piece.contents.groups)
                contents.groups.push_back({faces_before + group.first_face, group.name, group.is_object});
            const auto offset = static_cast<uint32_t>(contents.corners.size());
            contents.positions.insert(contents.positions.end(), piece.contents.positions.begin(),
                                      piece.contents.positions.end());
            contents.corners.insert(contents.corners.end(), piece.contents.corners.begin(), piece.contents.corners.end());
            for (uint32_t face_end : piece.contents.face_ends) contents.face_ends.push_back(offset + face_end);
        }
        for (int32_t corner : contents.corners) missing_vertex = missing_vertex || corner >= openmesh_vertices;
        if (missing_vertex) fail("some faces refer to vertices that do not exist");
        return contents;
    }

public:
    // The three coordinates of a v line parsed straight to float, when that settles the checks of
    // coordinates(): a finite float below FLT_MAX in size comes from a decimal whose double value is
    // finite and at most FLT_MAX. False when coordinates() must decide.
    static bool obj_coordinates(const Line& line, std::array<float, 3>& position) {
        if (line.tokens.size() < 4) return false;
        for (int k = 0; k < 3; ++k) {
            std::string_view token = line.tokens[1 + k];
            if (token.starts_with("+-")) return false;
            if (token.starts_with('+')) token.remove_prefix(1);
            const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), position[k]);
            if (ec != std::errc() || end != token.data() + token.size() || token.empty() ||
                !(std::fabs(position[k]) < FLT_MAX))
                return false;
        }
        return true;
    }

    // Returns the text for OpenMesh's reader: material-library lines become comments, as OpenMesh
    // would open any path named there (a device or a pipe reads forever) and hsr uses no materials;
    // so do texture coordinates, which hsr does not use and OpenMesh refuses with one value (`vt u`,
    // which the format allows); comments after data on a line become spaces, as OpenMesh would read
    // them as data.
    std::string rewrite_obj(std::string text) {
        const std::size_t mark = byte_order_mark(text);
        text.replace(0, mark, mark, ' ');
        {
            LineReader lines(text, '#');
            while (const Line* line = lines.next())
                if (line->tokens[0] == "mtllib" || line->tokens[0] == "vt")
                    text[static_cast<std::size_t>(line->tokens[0].data() - text.data())] = '#';
        }
        LineReader again(text, '#');
        while (const Line* next_line = again.next()) {
            const Line& line = *next_line;
            const std::string_view last = line.tokens.back();
            const auto data_end = static_cast<std::size_t>(last.data() + last.size() - text.data());
            const std::size_t line_end = std::min(text.find('\n', data_end), text.size());
            const std::size_t comment = std::string_view(text).substr(data_end, line_end - data_end).find('#');
            if (comment != std::string_view::npos)
                std::fill(text.begin() + static_cast<std::ptrdiff_t>(data_end + comment),
                          text.begin() + static_cast<std::ptrdiff_t>(line_end), ' ');
        }
        return text;
    }

    static constexpr std::array<float, 3> no_color = {NAN, NAN, NAN};

    // The colour r g b [a] of an OFF vertex or face (the rest of its line): whole numbers with one
    // above 1 are 0-255, anything else 0-1, each channel clamped to [0, 1]; no_color for fewer than
    // three numbers.
    static std::array<float, 3> off_color(std::span<const std::string_view> words) {
        if (words.size() < 3) return no_color;
        std::array<double, 3> values;
        bool whole = true;
        for (int k = 0; k < 3; ++k) {
            const std::optional<double> v = parse_number(words[k]);
            if (!v || !std::isfinite(*v)) return no_color;
            values[k] = *v;
            whole = whole && words[k].find_first_of(".eE") == std::string_view::npos;
        }
        const double scale = whole && std::max({values[0], values[1], values[2]}) > 1.0 ? 255.0 : 1.0;
        std::array<float, 3> color;
        for (int k = 0; k < 3; ++k) color[k] = static_cast<float>(std::clamp(values[k] / scale, 0.0, 1.0));
        return color;
    }

    // Checks an ASCII OFF file and returns its positions, faces and colours.
    ModelContents check_off(std::string_view text) {
        text.remove_prefix(byte_order_mark(text));
        LineReader lines(text, '#');
        const Line* first = lines.next();
        if (!first) fail("is empty");
        const Line header = *first;
        std::string keyword = std::string(header.tokens[0]);
        if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0 ||
            keyword.find_first_not_of("STCN4nOF") != std::string::npos)
            fail(header.number, "not an OFF file (it must start with OFF)");
        std::vector<std::string_view> counts(header.tokens.begin() + 1, header.tokens.end());
        if (!counts.empty() && counts[0] == "BINARY")
            fail(header.number, "binary OFF is not supported (OpenMesh reads it unreliably); use ASCII OFF or PLY");
        if (keyword.find_first_of("4n") != std::string::npos)
            fail(header.number, fmt::format("{} (homogeneous or n-dimensional) files are not supported", keyword));
        std::size_t counts_line = header.number;
        if (counts.empty()) {
            const Line* second = lines.next();
            if (!second) fail(header.number, "the vertex and face counts are missing");
            counts = second->tokens;
            counts_line = second->number;
        }
        if (counts.size() < 2) fail(counts_line, "expected the vertex and face counts");
        std::optional<long long> vertex_count = parse_integer(counts[0]);
        std::optional<long long> face_count = parse_integer(counts[1]);
        if (!vertex_count || !face_count || *vertex_count < 0 || *face_count < 0)
            fail(counts_line, "the vertex and face counts must be non-negative integers");
        auto next_line = [&]() -> const Line& {  // one line per vertex and face
            const Line* line = lines.next();
            if (!line)
                fail(fmt::format("ends early: the header promises {} vertices and {} faces", *vertex_count,
                                 *face_count));
            return *line;
        };
        ModelContents contents;
        // [ST][C][N]OFF: a vertex is x y z, then nx ny nz with N, then its colour with C.
        const bool vertex_colors = keyword.find('C') != std::string::npos;
        const std::size_t color_start = keyword.find('N') != std::string::npos ? 6 : 3;
        for (long long v = 0; v < *vertex_count; ++v) {
            const Line& line = next_line();
            coordinates(line, 0);  // x y z come first
            std::array<float, 3> position;
            for (int k = 0; k < 3; ++k) position[k] = static_cast<float>(*parse_number(line.tokens[k]));
            contents.positions.push_back(position);
            if (vertex_colors)
                contents.vertex_colors.push_back(
                    off_color(std::span(line.tokens).subspan(std::min(color_start, line.tokens.size()))));
        }
        for (long long f = 0; f < *face_count; ++f) {
            const Line& line = next_line();
            std::optional<long long> corners = parse_integer(line.tokens[0]);
            if (!corners) fail(line.number, fmt::format("{} is not a corner count", in_quotes(line.tokens[0])));
            if (*corners < 3) fail(line.number, "a face needs at least 3 vertices");
            if (*corners > max_face_corners) fail(line.number, too_many_corners);
            if (*corners > static_cast<long long>(line.tokens.size()) - 1)
                fail(line.number, fmt::format("the face lists fewer than its {} vertices", *corners));
            count_face(static_cast<uint64_t>(*corners));
            for (long long i = 1; i <= *corners; ++i) {
                std::optional<long long> index = parse_integer(line.tokens[i]);
                if (!index) fail(line.number, fmt::format("{} is not a vertex index", in_quotes(line.tokens[i])));
                if (*index < 0 || *index >= *vertex_count)
                    fail(line.number, fmt::format("vertex index {} is out of range (the file has {} vertices)",
                                                  *index, *vertex_count));
                contents.corners.push_back(static_cast<int32_t>(*index));
            }
            contents.face_ends.push_back(static_cast<uint32_t>(contents.corners.size()));
            // A colour after the indices: r g b [a]; one number (a colour-map index) is not read.
            contents.face_colors.push_back(off_color(std::span(line.tokens).subspan(1 + *corners)));
        }
        if (std::all_of(contents.face_colors.begin(), contents.face_colors.end(),
                        [](const std::array<float, 3>& c) { return std::isnan(c[0]); }))
            contents.face_colors.clear();
        if (!vertex_colors) return contents;
        // A file whose vertices carry no colour at all keeps the object's colour.
        if (std::all_of(contents.vertex_colors.begin(), contents.vertex_colors.end(),
                        [](const std::array<float, 3>& c) { return std::isnan(c[0]); }))
            contents.vertex_colors.clear();
        return contents;
    }

    // Walks the whole file the way a PLY reader would, ASCII or binary, and returns the vertex
    // positions and faces.
    ModelContents check_ply(std::string_view text) {
        const std::size_t header_end = ply_header_end(text);
        const PlyHeader header = read_ply_header(text, header_end);
        PlyValues values(*this, text, header_end, header.format);
        const PlyElement* vertex_element = nullptr;
        const PlyElement* face_element = nullptr;
        find_vertices_and_faces(header.elements, vertex_element, face_element);
        const long long vertex_count = vertex_element ? vertex_element->count : 0;
        return read_ply_body(header.elements, vertex_element, face_element, vertex_count, values);
    }

    void check_stl(std::string_view text) {
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
            if (text.size() > 84 + 50ull * triangles) {  // OpenMesh would read it as ASCII, finding nothing
                const auto extra = text.size() - 84 - 50ull * triangles;
                fail(fmt::format("binary STL has {} byte{} after its {} triangles", extra, extra == 1 ? "" : "s",
                                 triangles));
            }
            count_face(3, triangles);
            for (uint32_t t = 0; t < triangles; ++t) {  // normal, 3 corners, attribute bytes
                float corners[9];
                std::memcpy(corners, text.data() + 84 + 50ull * t + 12, sizeof corners);
                for (float c : corners)
                    if (!std::isfinite(c)) fail(fmt::format("triangle {} has a vertex coordinate that is not a finite number", t + 1));
            }
            return;
        }
        LineReader lines(text, '\0');
        while (const Line* line = lines.next()) {
            if (line->tokens[0] == "vertex") coordinates(*line, 1);
            if (line->tokens[0] == "facet") count_face(3);
        }
    }

private:
    // The header: its lines up to end_header (which ends at header_end, npos when it has none).
    PlyHeader read_ply_header(std::string_view text, std::size_t header_end) const {
        LineReader lines(text.substr(0, header_end == std::string_view::npos ? text.size() : header_end), '\0');
        const Line* first = lines.next();
        if (!first || first->number != 1 || first->tokens.size() != 1 || first->tokens[0] != "ply")
            fail(1, "not a PLY file (its first line must be ply)");
        if (header_end == std::string_view::npos) fail("the PLY header has no end_header line");

        PlyHeader header;
        std::vector<PlyElement>& elements = header.elements;
        std::string& format = header.format;
        while (const Line* next_line = lines.next()) {
            const Line& line = *next_line;
            std::string_view key = line.tokens[0];
            if (key == "end_header") break;
            if (key == "format") {
                if (line.tokens.size() != 3 || line.tokens[2] != "1.0")
                    fail(line.number, "expected: format ascii|binary_little_endian|binary_big_endian 1.0");
                format = std::string(line.tokens[1]);
                if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
                    fail(line.number, fmt::format("unknown PLY format {}", in_quotes(format)));
            } else if (key == "element") {
                std::optional<long long> count =
                    line.tokens.size() == 3 ? parse_integer(line.tokens[2]) : std::nullopt;
                if (!count || *count < 0) fail(line.number, "expected: element <name> <count>");
                if (elements.size() == max_ply_elements)
                    fail(line.number, fmt::format("more than {} elements", max_ply_elements));
                elements.push_back({std::string(line.tokens[1]), *count, {}});
            } else if (key == "property") {
                if (elements.empty()) fail(line.number, "property before any element");
                if (elements.back().properties.size() == max_ply_properties)
                    fail(line.number, fmt::format("more than {} properties in one element", max_ply_properties));
                bool list = line.tokens.size() >= 2 && line.tokens[1] == "list";
                if (list ? (line.tokens.size() != 5 || !ply_type(line.tokens[2]) || !ply_type(line.tokens[3]))
                         : (line.tokens.size() != 3 || !ply_type(line.tokens[1])))
                    fail(line.number, "expected: property <type> <name> or property list <type> <type> <name>");
                if (list)
                    elements.back().properties.push_back(
                        {std::string(line.tokens[4]), ply_type(line.tokens[3]), ply_type(line.tokens[2])});
                else
                    elements.back().properties.push_back({std::string(line.tokens[2]), ply_type(line.tokens[1])});
            } else if (key != "comment" && key != "obj_info") {
                fail(line.number, fmt::format("unknown PLY header line {}", in_quotes(key)));
            }
        }
        if (format.empty()) fail("the PLY header has no format line");
        for (const PlyElement& element : elements)
            if (element.properties.empty() && element.count > 0)  // nothing bounds a reader's loop over it
                fail(fmt::format("element {} has {} entries but no properties", in_quotes(element.name), element.count));
        return header;
    }

    // The body, as a stream of numbers: tokens for ASCII, fixed-size values for binary.
    class PlyValues {
    public:
        PlyValues(const TextChecker& checker, std::string_view text, std::size_t header_end, const std::string& format)
            : checker_(checker),
              ascii_(format == "ascii"),
              swap_((format == "binary_big_endian") == (std::endian::native == std::endian::little)),
              body_(text.substr(header_end)),
              lines_(ascii_ ? body_ : std::string_view(), '\0',
                     static_cast<std::size_t>(
                         std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(header_end), '\n'))) {}

        // Fails with the line of the last number read for ASCII (binary messages name no line).
        [[noreturn]] void fail_at(const std::string& message) const {
            if (ascii_) checker_.fail(where_, message);
            checker_.fail(message);
        }

        // The next number, of the given type when binary, in an entry of the element.
        double next(const PlyElement& element, const PlyType& type) {
            if (ascii_) {
                while (line_ == nullptr || token_index_ >= line_->tokens.size()) {
                    line_ = lines_.next();
                    token_index_ = 0;
                    if (line_ == nullptr)
                        checker_.fail(fmt::format("ends early while reading the {} elements", in_quotes(element.name)));
                }
                where_ = line_->number;
                std::string_view token = line_->tokens[token_index_++];
                std::optional<double> v = parse_number(token);
                if (!v) checker_.fail(where_, fmt::format("{} is not a number", in_quotes(token)));
                return *v;
            }
            const std::size_t size = static_cast<std::size_t>(type.size);
            if (body_.size() - byte_ < size)
                checker_.fail(fmt::format("ends early while reading the {} elements", in_quotes(element.name)));
            unsigned char raw[8];
            std::memcpy(raw, body_.data() + byte_, size);
            byte_ += size;
            if (swap_) std::reverse(raw, raw + size);
            auto as = [&raw](auto value) {
                std::memcpy(&value, raw, sizeof value);
                return static_cast<double>(value);
            };
            switch (type.scalar) {
                case PlyScalar::int8: return as(int8_t{});
                case PlyScalar::uint8: return as(uint8_t{});
                case PlyScalar::int16: return as(int16_t{});
                case PlyScalar::uint16: return as(uint16_t{});
                case PlyScalar::int32: return as(int32_t{});
                case PlyScalar::uint32: return as(uint32_t{});
                case PlyScalar::float32: return as(float{});
                case PlyScalar::float64: break;
            }
            return as(double{});
        }

    private:
        const TextChecker& checker_;
        const bool ascii_;
        const bool swap_;
        const std::string_view body_;
        LineReader lines_;
        const Line* line_ = nullptr;
        std::size_t token_index_ = 0, byte_ = 0;
        std::size_t where_ = 0;  // the line of the last number read (ASCII)
    };

    // The vertex and the face element (nullptr for none); the vertices must have x, y and z.
    void find_vertices_and_faces(const std::vector<PlyElement>& elements, const PlyElement*& vertex_element,
                                 const PlyElement*& face_element) const {
        for (const PlyElement& element : elements) {
            const PlyElement** known = element.name == "vertex" ? &vertex_element
                                       : element.name == "face" ? &face_element : nullptr;
            if (!known) continue;
            if (*known) fail(fmt::format("the PLY header declares two {} elements", in_quotes(element.name)));
            *known = &element;
        }
        if (vertex_element)
            for (std::string_view axis : {"x", "y", "z"})
                if (std::none_of(vertex_element->properties.begin(), vertex_element->properties.end(),
                                 [&](const PlyProperty& p) { return p.name == axis && !p.count_type; }))
                    fail(fmt::format("the vertex element has no {} property", axis));
    }

    // Reads every element's entries from values, checking the vertices and faces.
    ModelContents read_ply_body(const std::vector<PlyElement>& elements, const PlyElement* vertex_element,
                                const PlyElement* face_element, long long vertex_count, PlyValues& values) {
        ModelContents mesh;
        for (const PlyElement& element : elements) {
            const bool is_vertex = &element == vertex_element;
            const bool is_face = &element == face_element;
            const bool colored = (is_vertex || is_face) && has_rgb(element);
            for (long long e = 0; e < element.count; ++e) {
                float position[3] = {0, 0, 0};
                std::array<float, 3> color = {0, 0, 0};
                bool face_listed = false;
                for (const PlyProperty& property : element.properties) {
                    if (!property.count_type) {
                        double v = values.next(element, *property.type);
                        if (const int channel = rgb_channel(property); colored && channel >= 0) {
                            const bool whole = property.type->scalar != PlyScalar::float32 &&
                                               property.type->scalar != PlyScalar::float64;
                            const double value = whole ? v / 255.0 : v;
                            color[channel] = std::isfinite(value) ? static_cast<float>(std::clamp(value, 0.0, 1.0)) : 0.0f;
                        }
                        if (!is_vertex || property.name.size() != 1 || property.name[0] < 'x' || property.name[0] > 'z')
                            continue;
                        if (!std::isfinite(v) || std::fabs(v) > FLT_MAX)
                            values.fail_at(fmt::format("vertex {} has a coordinate that is not a finite number", e));
                        position[property.name[0] - 'x'] = static_cast<float>(v);
                        continue;
                    }
                    double count = values.next(element, *property.count_type);
                    if (!(count >= 0) || count != std::floor(count))
                        values.fail_at(fmt::format("{} is not a list length", count));
                    const bool indices = is_face && !face_listed &&
                                         (property.name == "vertex_indices" || property.name == "vertex_index");
                    if (indices && count < 3) values.fail_at(fmt::format("face {} has fewer than 3 vertices", e));
                    if (indices && count > max_face_corners) values.fail_at(too_many_corners);
                    if (indices) {
                        count_face(static_cast<uint64_t>(count));
                        face_listed = true;
                    }
                    for (double i = 0; i < count; ++i) {
                        double index = values.next(element, *property.type);
                        if (!indices) continue;
                        if (index != std::floor(index) || index < 0 || index >= static_cast<double>(vertex_count))
                            values.fail_at(fmt::format("vertex index {} is out of range (the file has {} vertices)",
                                                       index, vertex_count));
                        mesh.corners.push_back(static_cast<int32_t>(index));
                    }
                    if (indices) mesh.face_ends.push_back(static_cast<uint32_t>(mesh.corners.size()));
                }
                if (is_vertex) mesh.positions.push_back({position[0], position[1], position[2]});
                if (colored && is_vertex) mesh.vertex_colors.push_back(color);
                if (colored && face_listed) mesh.face_colors.push_back(color);
            }
        }
        return mesh;
    }

    // Which colour channel a property is (red, green, blue: 0, 1, 2), -1 for none.
    static int rgb_channel(const PlyProperty& property) {
        if (property.count_type) return -1;
        return property.name == "red" ? 0 : property.name == "green" ? 1 : property.name == "blue" ? 2 : -1;
    }
    static bool has_rgb(const PlyElement& element) {
        bool channels[3] = {false, false, false};
        for (const PlyProperty& property : element.properties)
            if (const int channel = rgb_channel(property); channel >= 0) channels[channel] = true;
        return channels[0] && channels[1] && channels[2];
    }

    // A face of `corners` vertices is stored as corners - 2 triangles; the stored-triangles limit is
    // checked as faces are counted, before OpenMesh allocates anything.
    void count_face(uint64_t corners, uint64_t faces = 1) {
        triangles_ += faces * (corners - 2);
        if (triangles_ > limits().stored_triangles)
            check_limit(&Limits::stored_triangles, triangles_, printable(file_.string(), kMaxQuotedPathChars));
    }

    std::filesystem::path file_;
    uint64_t triangles_ = 0;
};

}  // namespace

ModelContents check_obj_text(const std::filesystem::path& file, std::string_view text, std::size_t piece_bytes) {
    return TextChecker(file).check_obj_in_pieces(text, piece_bytes);
}

std::string obj_text_for_openmesh(const std::filesystem::path& file, std::string text) {
    TextChecker checker(file);
    checker.check_obj(text);
    return checker.rewrite_obj(std::move(text));
}

ModelContents check_off_text(const std::filesystem::path& file, std::string_view text) {
    return TextChecker(file).check_off(text);
}

ModelContents check_ply_text(const std::filesystem::path& file, std::string_view text) {
    return TextChecker(file).check_ply(text);
}

void check_stl_text(const std::filesystem::path& file, std::string_view text) { TextChecker(file).check_stl(text); }

}  // namespace hsr
