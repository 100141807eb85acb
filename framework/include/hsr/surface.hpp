// Surfaces z = f(x, y) as a triangle mesh on a regular grid: from a formula (parsed by muparser) or
// from a greyscale height-map image (PNG). The floating-horizon hidden-line plugin draws such grids;
// it recognises one from the hsr_scene alone by the layout fixed below (see "The grid layout").
//
// World axes. The surface's own coordinates (x, y, z = f(x, y)) map to world space as
//     world x = x,   world y = z (height, up),   world z = -y (depth)
// a rotation (no mirroring), so the default orbit camera (yaw 0, looking from +z toward -z, y up)
// sees x running to the right, y running away from the viewer and heights going up: the front edge
// of the plot is y = y0, and a positive pitch looks down on it from above that edge.
//
// The grid layout (what make_formula_surface and make_heightmap_surface build, and exactly what
// find_surface_grid accepts):
//   - C columns (samples along x) and R rows (samples along y), C, R >= 2;
//     vertex_count = C * R, triangle_count = 2 * (C - 1) * (R - 1), one object, no instances;
//   - vertex k = r * C + c (row-major, row r at y_r, column c at x_c) lies at world
//     (X[c], h, Z[r]): X strictly increasing with c and bit-for-bit the same in every row, Z strictly
//     decreasing with r (y increasing) and the same for every vertex of a row; the height h is any
//     finite number. The spacing need not be uniform (a rectilinear lattice);
//   - cell (c, r), c < C - 1, r < R - 1, with corners v00 = r * C + c, v10 = v00 + 1,
//     v01 = v00 + C, v11 = v01 + 1, is triangles 2 * (r * (C - 1) + c) and that + 1, with corners
//     exactly (v00, v10, v11) and (v00, v11, v01): counter-clockwise seen from above (world +y), the
//     diagonal from v00 to v11.
// Vertices are shared, so edge_neighbors give real adjacency: an interior grid edge or diagonal has
// a triangle on both sides.
#pragma once

#include "hsr/abi.h"
#include "hsr/scene.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace hsr {

// Samples per side are at least 2 and at most this; in all at most the limit `surface-samples`
// (limits.hpp).
inline constexpr uint32_t kSurfaceMaxSide = 4096;

struct SurfaceRange {
    double x0 = -1, x1 = 1;  // x0 < x1
    double y0 = -1, y1 = 1;  // y0 < y1
    uint32_t columns = 64;   // samples along x (vertices per row)
    uint32_t rows = 64;      // samples along y
};

// The command line's range text: "X0:X1,Y0:Y1" or "X0:X1,Y0:Y1,N" (N x N samples) or
// "X0:X1,Y0:Y1,CxR" (C samples along x, R along y; 'x' or 'X'). Numbers are decimal, may be
// negative and use an exponent ("-3:3,-3:3,80x80", "0:6.2832,-1e1:1e1,200x50"); spaces around the
// separators are allowed. Without a count the grid is 64 x 64. Throws hsr::Error naming the text and
// what is wrong: a missing or malformed part, X0 >= X1, a non-finite bound, fewer than 2 or more
// than kSurfaceMaxSide samples per side, more than the limit `surface-samples` in all.
SurfaceRange parse_surface_range(std::string_view text);
// Throws hsr::Error for the same mistakes in a range built in code.
void check_surface_range(const SurfaceRange& range);

// z = f(x, y) on the grid x_c = x0 + c (x1 - x0) / (C - 1), y_r = y0 + r (y1 - y0) / (R - 1).
// The formula uses the variables x and y, the constant pi (and muparser's _pi, _e), muparser's
// operators (+ - * / ^, comparisons, && ||, c ? a : b) and functions (sin cos tan asin acos atan
// sinh cosh tanh asinh acosh atanh exp ln log log2 log10 sqrt abs sign rint min max sum avg).
// Throws hsr::Error with one line for: an empty or malformed formula, an unknown name (muparser's
// message and the position, counted from 0), a value that is not a finite number at a grid point (with
// that point), a bad range (check_surface_range). The scene has one object named
// "z = <formula>" of colour `color`, smooth corner normals (creases above 40 degrees kept), and the
// layout above.
SceneData make_formula_surface(const std::string& formula, SurfaceRange range,
                               glm::vec3 color = {0.8f, 0.8f, 0.8f});

struct HeightmapOptions {
    double spacing = 1.0;  // world distance between neighbouring pixels, along x and along depth (> 0)
    // World height of a white pixel (black is 0). 0 picks a fifth of the grid's larger side:
    // (max(C, R) - 1) * spacing / 5.
    double height = 0.0;
    uint32_t step = 1;  // use every step-th pixel in both directions (>= 1), for large images
    glm::vec3 color{0.8f, 0.8f, 0.8f};
};

// Each used pixel of the PNG is one grid sample: image column -> x, image row -> y with the image's
// top row at the back (largest y) and its bottom row at the front, so the picture reads the right way
// round from the default camera looking down. The grid is centred on x = 0, y = 0. A pixel's value v
// in [0, 1] is its grey level (any bit depth; 16-bit kept exact) or, for a colour image, its
// luminance 0.2126 R + 0.7152 G + 0.0722 B of the stored values (no gamma decoding); alpha is ignored;
// height = options.height * v. Throws hsr::Error when the file is missing or not a readable PNG, when
// the image (after step) has fewer than 2 samples per side or too many (the limits above), when the
// image has more pixels than the limit `heightmap-pixels` (checked from its header, before its pixels
// are read), or for bad options.
SceneData make_heightmap_surface(const std::filesystem::path& png, const HeightmapOptions& options = {});

// The grid a scene is laid out as (the layout above), as find_surface_grid reads it back.
struct SurfaceGrid {
    uint32_t columns = 0, rows = 0;
};
// The grid if the scene follows the layout above exactly; otherwise nullopt, and `why` (when not
// NULL) says the first rule broken, e.g. "triangle 5 is not the expected corner of cell (2, 0)".
std::optional<SurfaceGrid> find_surface_grid(const hsr_scene& scene, std::string* why = nullptr);

}  // namespace hsr
