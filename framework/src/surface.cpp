// Surfaces z = f(x, y) on a regular grid (see surface.hpp for the layout and the world axes).
#include "hsr/surface.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <fmt/format.h>
#include <muParser.h>
#include <png.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstddef>
#include <charconv>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

namespace hsr {
namespace {

std::string trim(std::string_view s) {
    size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
    return std::string(s.substr(a, b - a));
}

std::vector<std::string> split(std::string_view s, char separator) {
    std::vector<std::string> parts;
    size_t start = 0;
    for (;;) {
        const size_t at = s.find(separator, start);
        parts.push_back(trim(s.substr(start, at == std::string_view::npos ? std::string_view::npos : at - start)));
        if (at == std::string_view::npos) return parts;
        start = at + 1;
    }
}

// A whole decimal number, or nullopt.
std::optional<double> parse_number(const std::string& s) {
    if (s.empty()) return std::nullopt;
    double value = 0;
    const char* first = s.data();
    if (*first == '+') ++first;
    const auto [end, ec] = std::from_chars(first, s.data() + s.size(), value);
    if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return value;
}

std::optional<uint32_t> parse_count(const std::string& s) {
    if (s.empty()) return std::nullopt;
    uint64_t value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return uint32_t(std::min<uint64_t>(value, std::numeric_limits<uint32_t>::max()));
}

void check_samples(uint64_t columns, uint64_t rows, const std::string& what) {
    if (columns < 2 || rows < 2)
        throw Error("{}: {}x{} samples; a surface needs at least 2 per side", what, columns, rows);
    if (columns > kSurfaceMaxSide || rows > kSurfaceMaxSide)
        throw Error("{}: {}x{} samples; at most {} per side", what, columns, rows, kSurfaceMaxSide);
    check_limit(&Limits::surface_samples, columns * rows, fmt::format("{}: {}x{}", what, columns, rows));
}

// The mesh of the layout in surface.hpp from the lattice and the heights (row-major).
SceneData grid_scene(const std::vector<float>& xs, const std::vector<float>& zs, const std::vector<float>& heights,
                     glm::vec3 color, const std::string& name) {
    const uint32_t C = uint32_t(xs.size()), R = uint32_t(zs.size());
    SceneData scene;
    scene.positions.resize(3 * size_t(C) * R);
    for (uint32_t r = 0; r < R; ++r)
        for (uint32_t c = 0; c < C; ++c) {
            const size_t v = size_t(r) * C + c;
            scene.positions[3 * v] = xs[c];
            scene.positions[3 * v + 1] = heights[v];
            scene.positions[3 * v + 2] = zs[r];
        }
    const uint32_t cells = (C - 1) * (R - 1);
    const size_t triangles = 2 * size_t(cells);
    scene.indices.resize(3 * triangles);
    scene.edge_neighbors.resize(3 * triangles);
    auto A = [&](uint32_t c, uint32_t r) { return int32_t(2 * (r * (C - 1) + c)); };  // (v00, v10, v11)
    auto B = [&](uint32_t c, uint32_t r) { return int32_t(2 * (r * (C - 1) + c) + 1); };  // (v00, v11, v01)
    for (uint32_t r = 0; r + 1 < R; ++r)
        for (uint32_t c = 0; c + 1 < C; ++c) {
            const uint32_t v00 = r * C + c, v10 = v00 + 1, v01 = v00 + C, v11 = v01 + 1;
            const size_t a = size_t(A(c, r)), b = size_t(B(c, r));
            scene.indices[3 * a] = v00;
            scene.indices[3 * a + 1] = v10;
            scene.indices[3 * a + 2] = v11;
            scene.indices[3 * b] = v00;
            scene.indices[3 * b + 1] = v11;
            scene.indices[3 * b + 2] = v01;
            // A: v00->v10 (row r), v10->v11 (column c+1), v11->v00 (diagonal).
            scene.edge_neighbors[3 * a] = r > 0 ? B(c, r - 1) : HSR_NO_NEIGHBOR;
            scene.edge_neighbors[3 * a + 1] = c + 2 < C ? B(c + 1, r) : HSR_NO_NEIGHBOR;
            scene.edge_neighbors[3 * a + 2] = B(c, r);
            // B: v00->v11 (diagonal), v11->v01 (row r+1), v01->v00 (column c).
            scene.edge_neighbors[3 * b] = A(c, r);
            scene.edge_neighbors[3 * b + 1] = r + 2 < R ? A(c, r + 1) : HSR_NO_NEIGHBOR;
            scene.edge_neighbors[3 * b + 2] = c > 0 ? A(c - 1, r) : HSR_NO_NEIGHBOR;
        }

    auto position = [&](uint32_t v) {
        return glm::dvec3(scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]);
    };
    std::vector<glm::dvec3> normals(triangles);
    scene.face_normals.resize(3 * triangles);
    for (size_t t = 0; t < triangles; ++t) {
        const glm::dvec3 p0 = position(scene.indices[3 * t]), p1 = position(scene.indices[3 * t + 1]),
                         p2 = position(scene.indices[3 * t + 2]);
        const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
        const double length = glm::length(n);
        // Never degenerate: the corners' x and z differ (strictly monotonic lattice).
        normals[t] = length > 0 && std::isfinite(length) ? n / length : glm::dvec3(0, 1, 0);
        for (int k = 0; k < 3; ++k) scene.face_normals[3 * t + k] = float(normals[t][k]);
    }

    // Corner normals as SceneBuilder makes them: the angle-weighted mean of the normals of the
    // triangles around the vertex within 40 degrees of the corner's own triangle.
    const size_t vertices = size_t(C) * R;
    std::vector<uint32_t> start(vertices + 1, 0);
    for (uint32_t v : scene.indices) ++start[v + 1];
    for (size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
    std::vector<uint32_t> around(scene.indices.size());
    {
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (uint32_t corner = 0; corner < scene.indices.size(); ++corner) around[fill[scene.indices[corner]]++] = corner;
    }
    std::vector<double> angle(scene.indices.size());
    for (size_t t = 0; t < triangles; ++t)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 p = position(scene.indices[3 * t + k]);
            const glm::dvec3 u = position(scene.indices[3 * t + (k + 1) % 3]) - p;
            const glm::dvec3 w = position(scene.indices[3 * t + (k + 2) % 3]) - p;
            angle[3 * t + k] = std::atan2(glm::length(glm::cross(u, w)), glm::dot(u, w));
        }
    const double limit = std::cos(40.0 * std::numbers::pi / 180.0) - 1e-6;
    scene.corner_normals.resize(9 * triangles);
    for (size_t t = 0; t < triangles; ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = scene.indices[3 * t + k];
            glm::dvec3 sum(0.0);
            for (uint32_t i = start[v]; i < start[v + 1]; ++i) {
                const glm::dvec3& other = normals[around[i] / 3];
                if (glm::dot(normals[t], other) >= limit) sum += angle[around[i]] * other;
            }
            const double length = glm::length(sum);
            const glm::dvec3 n = length > 1e-12 ? sum / length : normals[t];
            for (int j = 0; j < 3; ++j) scene.corner_normals[9 * t + 3 * k + j] = float(n[j]);
        }

    scene.face_colors.resize(3 * triangles);
    for (size_t t = 0; t < triangles; ++t) {
        scene.face_colors[3 * t] = color.r;
        scene.face_colors[3 * t + 1] = color.g;
        scene.face_colors[3 * t + 2] = color.b;
    }
    scene.face_object.assign(triangles, 0);
    scene.object_names.push_back(name);
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (size_t v = 0; v < vertices; ++v) {
        const glm::vec3 p(scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    scene.bounds_min = lo;
    scene.bounds_max = hi;
    return scene;
}

void check_color(glm::vec3 color, const std::string& what) {
    for (int k = 0; k < 3; ++k)
        if (!(color[k] >= 0.0f && color[k] <= 1.0f))
            throw Error("{}: colour channel {} is outside [0, 1]", what, color[k]);
}

// Lattice coordinates as floats; throws if two neighbours round to the same float.
std::vector<float> lattice(double a, double b, uint32_t n, bool negate, const char* axis, const std::string& what) {
    std::vector<float> out(n);
    for (uint32_t i = 0; i < n; ++i) {
        const double t = a + (b - a) * double(i) / double(n - 1);
        out[i] = float(negate ? -t : t);
        if (i > 0 && !(negate ? out[i] < out[i - 1] : out[i] > out[i - 1]))
            throw Error("{}: {} samples along {} between {} and {} are too close together for float coordinates",
                        what, n, axis, a, b);
    }
    return out;
}

double grid_coordinate(double a, double b, uint32_t i, uint32_t n) { return a + (b - a) * double(i) / double(n - 1); }

// ---------------------------------------------------------------------------------------------
// PNG as grey values in [0, 1], through libpng's low-level interface (any bit depth, 16 bits kept).

struct PngContext {
    char message[256] = "";
};

void png_fail(png_structp png, png_const_charp message) {
    auto* context = static_cast<PngContext*>(png_get_error_ptr(png));
    std::snprintf(context->message, sizeof context->message, "%s", message != nullptr ? message : "libpng error");
    png_longjmp(png, 1);
}

void png_quiet(png_structp, png_const_charp) {}

struct GreyImage {
    uint32_t width = 0, height = 0;
    std::vector<float> value;  // row-major, top row first, in [0, 1]
};

struct PngRows {
    png_uint_32 width = 0, height = 0;
    int channels = 0, bit_depth = 0;
    std::vector<png_byte> data;
    std::vector<png_bytep> rows;
};

enum class PngPart { header, pixels };

// Reads out.width and out.height from the header, then for PngPart::pixels the rows (nothing is
// allocated for pixels otherwise). Returns false with context.message set on a libpng error. Only
// C calls and vector operations on objects that live in the caller happen between setjmp and a
// possible longjmp, which is also why the header and the pixels are two calls: the caller checks
// the size in between, and may throw.
bool read_png(std::FILE* file, PngContext& context, PngRows& out, PngPart part) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &context, png_fail, png_quiet);
    png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
    if (info == nullptr) {
        png_destroy_read_struct(&png, nullptr, nullptr);
        std::snprintf(context.message, sizeof context.message, "libpng could not start");
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_init_io(png, file);
    png_set_user_limits(png, 1u << 16, 1u << 16);
    png_read_info(png, info);
    if (part == PngPart::header) {
        out.width = png_get_image_width(png, info);
        out.height = png_get_image_height(png, info);
        png_destroy_read_struct(&png, &info, nullptr);
        return true;
    }
    png_set_expand(png);       // palette -> RGB, grey below 8 bits -> 8 bits, tRNS -> alpha
    png_set_strip_alpha(png);  // heights ignore transparency
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    out.width = png_get_image_width(png, info);
    out.height = png_get_image_height(png, info);
    out.channels = png_get_channels(png, info);
    out.bit_depth = png_get_bit_depth(png, info);
    const size_t row_bytes = png_get_rowbytes(png, info);
    out.data.resize(row_bytes * out.height);
    out.rows.resize(out.height);
    for (png_uint_32 y = 0; y < out.height; ++y) out.rows[y] = out.data.data() + row_bytes * y;
    png_read_image(png, out.rows.data());
    png_read_end(png, nullptr);
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

// check_size(width, height) sees the header's size before the pixels are allocated, and throws to
// refuse it.
template <class CheckSize>
GreyImage read_png_grey(const std::filesystem::path& path, const std::string& what, CheckSize check_size) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!file) throw Error("{}: cannot open it: {}", what, std::strerror(errno));
    png_byte signature[8] = {};
    if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
        throw Error("{}: not a PNG file", what);
    PngContext context;
    PngRows rows;
    // libpng reads the signature again from the start, each time.
    std::rewind(file.get());
    if (!read_png(file.get(), context, rows, PngPart::header))
        throw Error("{}: cannot read it as PNG: {}", what, context.message);
    check_size(rows.width, rows.height);
    std::rewind(file.get());
    if (!read_png(file.get(), context, rows, PngPart::pixels))
        throw Error("{}: cannot read it as PNG: {}", what, context.message);
    if (rows.channels != 1 && rows.channels != 3)
        throw Error("{}: unexpected PNG layout ({} channels after expansion)", what, rows.channels);
    GreyImage image;
    image.width = rows.width;
    image.height = rows.height;
    image.value.resize(size_t(rows.width) * rows.height);
    const bool wide = rows.bit_depth == 16;
    const double full = wide ? 65535.0 : 255.0;
    for (png_uint_32 y = 0; y < rows.height; ++y) {
        const png_byte* row = rows.rows[y];
        for (png_uint_32 x = 0; x < rows.width; ++x) {
            double channel[3] = {0, 0, 0};
            for (int k = 0; k < rows.channels; ++k) {
                const size_t i = size_t(x) * rows.channels + k;
                channel[k] = wide ? double((row[2 * i] << 8) | row[2 * i + 1]) : double(row[i]);
            }
            const double v = rows.channels == 1
                                 ? channel[0]
                                 : 0.2126 * channel[0] + 0.7152 * channel[1] + 0.0722 * channel[2];
            image.value[size_t(y) * rows.width + x] = float(std::clamp(v / full, 0.0, 1.0));
        }
    }
    return image;
}

}  // namespace

void check_surface_range(const SurfaceRange& r) {
    if (!(std::isfinite(r.x0) && std::isfinite(r.x1) && std::isfinite(r.y0) && std::isfinite(r.y1)))
        throw Error("surface range: the bounds must be finite numbers");
    if (!(r.x0 < r.x1)) throw Error("surface range: x runs from {} to {}; the first must be smaller", r.x0, r.x1);
    if (!(r.y0 < r.y1)) throw Error("surface range: y runs from {} to {}; the first must be smaller", r.y0, r.y1);
    check_samples(r.columns, r.rows, "surface range");
}

SurfaceRange parse_surface_range(std::string_view text) {
    const std::string quoted = fmt::format("surface range \"{}\"", printable(text));
    const std::string form = "expected X0:X1,Y0:Y1 or X0:X1,Y0:Y1,COLUMNSxROWS, e.g. -3:3,-3:3,80x80";
    const std::vector<std::string> parts = split(text, ',');
    if (parts.size() != 2 && parts.size() != 3) throw Error("{}: {}", quoted, form);
    SurfaceRange range;
    const char* axis_names[2] = {"x", "y"};
    for (int axis = 0; axis < 2; ++axis) {
        const std::vector<std::string> bounds = split(parts[axis], ':');
        if (bounds.size() != 2)
            throw Error("{}: the {} part \"{}\" is not FROM:TO; {}", quoted, axis_names[axis], printable(parts[axis]),
                        form);
        const std::optional<double> a = parse_number(bounds[0]), b = parse_number(bounds[1]);
        if (!a) throw Error("{}: \"{}\" is not a number", quoted, printable(bounds[0]));
        if (!b) throw Error("{}: \"{}\" is not a number", quoted, printable(bounds[1]));
        if (!std::isfinite(*a) || !std::isfinite(*b)) throw Error("{}: the bounds must be finite numbers", quoted);
        if (!(*a < *b))
            throw Error("{}: {} runs from {} to {}; the first must be smaller", quoted, axis_names[axis], *a, *b);
        (axis == 0 ? range.x0 : range.y0) = *a;
        (axis == 0 ? range.x1 : range.y1) = *b;
    }
    if (parts.size() == 3) {
        std::string counts = parts[2];
        std::replace(counts.begin(), counts.end(), 'X', 'x');
        const std::vector<std::string> sides = split(counts, 'x');
        if (sides.size() > 2)
            throw Error("{}: the count \"{}\" is not N or COLUMNSxROWS", quoted, printable(parts[2]));
        const std::optional<uint32_t> columns = parse_count(sides[0]);
        const std::optional<uint32_t> rows = sides.size() == 2 ? parse_count(sides[1]) : columns;
        if (!columns || !rows)
            throw Error("{}: the count \"{}\" is not N or COLUMNSxROWS (whole numbers)", quoted, printable(parts[2]));
        range.columns = *columns;
        range.rows = *rows;
    }
    check_samples(range.columns, range.rows, quoted);
    return range;
}

SceneData make_formula_surface(const std::string& formula, SurfaceRange range, glm::vec3 color) {
    check_surface_range(range);
    const std::string what = fmt::format("formula \"{}\"", printable(formula));
    check_color(color, what);
    if (trim(formula).empty()) throw Error("{}: the formula is empty; write z as a function of x and y", what);
    double x = 0.5 * (range.x0 + range.x1), y = 0.5 * (range.y0 + range.y1);
    mu::Parser parser;
    try {
        parser.DefineVar("x", &x);
        parser.DefineVar("y", &y);
        parser.DefineConst("pi", std::numbers::pi);
        parser.SetExpr(formula);
        parser.Eval();  // parses now, so that syntax errors are reported before any grid point
    } catch (const mu::Parser::exception_type& e) {
        std::string message = printable(e.GetMsg(), 2 * kMaxQuotedChars);
        while (!message.empty() && (message.back() == '.' || message.back() == ' ')) message.pop_back();
        if (message.find("position") == std::string::npos && e.GetPos() >= 0)
            message += fmt::format(" at position {}", e.GetPos());
        if (e.GetCode() == mu::ecUNASSIGNABLE_TOKEN)
            message += fmt::format(" (the variables are x and y; \"{}\" is not a known name)", printable(e.GetToken()));
        throw Error("{}: {}", what, message);
    }

    const std::vector<float> xs = lattice(range.x0, range.x1, range.columns, false, "x", what);
    const std::vector<float> zs = lattice(range.y0, range.y1, range.rows, true, "y", what);
    std::vector<float> heights(size_t(range.columns) * range.rows);
    for (uint32_t r = 0; r < range.rows; ++r)
        for (uint32_t c = 0; c < range.columns; ++c) {
            x = grid_coordinate(range.x0, range.x1, c, range.columns);
            y = grid_coordinate(range.y0, range.y1, r, range.rows);
            double z = 0;
            try {
                z = parser.Eval();
            } catch (const mu::Parser::exception_type& e) {
                throw Error("{}: {} at x = {}, y = {}", what, printable(e.GetMsg(), 2 * kMaxQuotedChars), x, y);
            }
            const float stored = float(z);
            if (!std::isfinite(stored))
                throw Error("{}: the value at x = {}, y = {} (grid column {}, row {}) is {}", what, x, y, c, r,
                            std::isnan(z)    ? std::string("not a number (NaN)")
                            : std::isinf(z) ? std::string("infinite")
                                            : fmt::format("{}, too large for a float", z));
            heights[size_t(r) * range.columns + c] = stored;
        }
    return grid_scene(xs, zs, heights, color, "z = " + formula);
}

SceneData make_heightmap_surface(const std::filesystem::path& png, const HeightmapOptions& options) {
    const std::string what = fmt::format("heightmap {}", printable(png.string(), kMaxQuotedPathChars));
    if (!(std::isfinite(options.spacing) && options.spacing > 0))
        throw Error("{}: the spacing {} must be a number greater than 0", what, options.spacing);
    if (!(std::isfinite(options.height) && options.height >= 0))
        throw Error("{}: the height {} must be a number, at least 0 (0 picks one)", what, options.height);
    if (options.step < 1) throw Error("{}: the step must be at least 1", what);
    check_color(options.color, what);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(png, ec))
        throw Error("{}: {}", what, std::filesystem::exists(png, ec) ? "is not a file" : "no such file");
    auto grid_side = [&](uint32_t pixels) { return (pixels - 1) / options.step + 1; };
    const GreyImage image = read_png_grey(png, what, [&](uint32_t width, uint32_t height) {
        const std::string size = fmt::format("{} ({}x{} pixels", what, width, height);
        check_limit(&Limits::heightmap_pixels, uint64_t(width) * height, size + ")");
        check_samples(grid_side(width), grid_side(height),
                      options.step > 1 ? fmt::format("{}, every {}th)", size, options.step)
                                       : size + "; a step above 1 uses fewer)");
    });
    const uint32_t C = grid_side(image.width), R = grid_side(image.height);
    const double spacing = options.spacing;
    const double height = options.height > 0 ? options.height : double(std::max(C, R) - 1) * spacing / 5.0;
    if (!std::isfinite(float(height))) throw Error("{}: the height {} does not fit a float", what, height);
    const double half_x = 0.5 * double(C - 1) * spacing, half_y = 0.5 * double(R - 1) * spacing;
    const std::vector<float> xs = lattice(-half_x, half_x, C, false, "x", what);
    const std::vector<float> zs = lattice(-half_y, half_y, R, true, "y", what);
    std::vector<float> heights(size_t(C) * R);
    for (uint32_t r = 0; r < R; ++r) {
        const uint32_t image_row = (R - 1 - r) * options.step;  // the bottom row of the picture at the front
        for (uint32_t c = 0; c < C; ++c) {
            const float v = image.value[size_t(image_row) * image.width + size_t(c) * options.step];
            heights[size_t(r) * C + c] = float(height * double(v));
        }
    }
    return grid_scene(xs, zs, heights, options.color, "heightmap " + png.filename().string());
}

std::optional<SurfaceGrid> find_surface_grid(const hsr_scene& s, std::string* why) {
    auto fail = [&](std::string reason) -> std::optional<SurfaceGrid> {
        if (why != nullptr) *why = std::move(reason);
        return std::nullopt;
    };
    if (s.struct_size >= offsetof(hsr_scene, instances) + sizeof s.instances && s.instance_count > 0)
        return fail("the scene has instances");
    const uint32_t V = s.vertex_count, T = s.triangle_count;
    if (V < 4 || s.positions == nullptr || s.indices == nullptr) return fail("fewer than 4 vertices");
    const float* p = s.positions;
    uint32_t C = 1;
    while (C < V && p[3 * C + 2] == p[2]) ++C;
    if (C < 2) return fail("the first row has fewer than 2 vertices");
    if (V % C != 0) return fail(fmt::format("{} vertices are not rows of {}", V, C));
    const uint32_t R = V / C;
    if (R < 2) return fail("fewer than 2 rows");
    if (uint64_t(T) != 2 * uint64_t(C - 1) * (R - 1))
        return fail(fmt::format("{} triangles, but a {}x{} grid has {}", T, C, R, 2 * uint64_t(C - 1) * (R - 1)));
    for (uint32_t r = 0; r < R; ++r)
        for (uint32_t c = 0; c < C; ++c) {
            const size_t v = size_t(r) * C + c;
            if (!std::isfinite(p[3 * v + 1])) return fail(fmt::format("vertex {} has a height that is not finite", v));
            if (p[3 * v] != p[3 * c] || !(c == 0 || p[3 * v] > p[3 * v - 3]))
                return fail(fmt::format("vertex {} (column {}, row {}) is off the lattice in x", v, c, r));
            if (p[3 * v + 2] != p[3 * size_t(r) * C + 2] || !(r == 0 || p[3 * v + 2] < p[3 * (v - C) + 2]))
                return fail(fmt::format("vertex {} (column {}, row {}) is off the lattice in z", v, c, r));
        }
    for (uint32_t r = 0; r + 1 < R; ++r)
        for (uint32_t c = 0; c + 1 < C; ++c) {
            const uint32_t v00 = r * C + c, v10 = v00 + 1, v01 = v00 + C, v11 = v01 + 1;
            const size_t t = 2 * (size_t(r) * (C - 1) + c);
            const uint32_t* i = s.indices + 3 * t;
            if (i[0] != v00 || i[1] != v10 || i[2] != v11)
                return fail(fmt::format("triangle {} is not the first triangle of cell ({}, {})", t, c, r));
            if (i[3] != v00 || i[4] != v11 || i[5] != v01)
                return fail(fmt::format("triangle {} is not the second triangle of cell ({}, {})", t + 1, c, r));
        }
    return SurfaceGrid{C, R};
}

}  // namespace hsr
