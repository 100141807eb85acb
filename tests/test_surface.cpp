// Surfaces z = f(x, y) as grid meshes (hsr/surface.hpp): formula values at the grid points, the
// layout and adjacency, height maps from PNG files, the range syntax, and the errors.
#include "hsr/error.hpp"
#include "hsr/image.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/surface.hpp"

#include <catch2/catch.hpp>
#include <png.h>

#include <glm/glm.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>

namespace {

std::string error_of(auto&& f) {
    try {
        f();
    } catch (const hsr::Error& e) {
        return e.what();
    }
    return "(no error)";
}

glm::vec3 vertex(const hsr::SceneData& s, uint32_t v) {
    return {s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]};
}

std::filesystem::path temp_file(const std::string& name) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "hsr-test-surface";
    std::filesystem::create_directories(dir);
    return dir / name;
}

}  // namespace

TEST_CASE("surface: formula values at the grid points, world axes x, height, -y", "[surface]") {
    hsr::SurfaceRange range;
    range.x0 = -3;
    range.x1 = 3;
    range.y0 = -2;
    range.y1 = 2.5;
    range.columns = 13;
    range.rows = 7;
    const hsr::SceneData s = hsr::make_formula_surface("sin(x)*cos(y) + 0.1*x^2 - sqrt(y+3) + exp(-x*x)", range);
    REQUIRE(s.vertex_count() == 13 * 7);
    REQUIRE(s.triangle_count() == 2 * 12 * 6);
    REQUIRE(s.object_names.size() == 1);
    CHECK(s.object_names[0] == "z = sin(x)*cos(y) + 0.1*x^2 - sqrt(y+3) + exp(-x*x)");
    for (uint32_t r = 0; r < range.rows; ++r)
        for (uint32_t c = 0; c < range.columns; ++c) {
            const double x = -3 + 6.0 * c / 12.0, y = -2 + 4.5 * r / 6.0;
            const double z = std::sin(x) * std::cos(y) + 0.1 * x * x - std::sqrt(y + 3) + std::exp(-x * x);
            const glm::vec3 p = vertex(s, r * range.columns + c);
            CHECK(p.x == float(x));
            CHECK(p.z == float(-y));
            CHECK(p.y == Approx(z).margin(1e-6));
        }
    CHECK(s.bounds_min.x == -3.0f);
    CHECK(s.bounds_max.x == 3.0f);
    CHECK(s.bounds_min.z == -2.5f);
    CHECK(s.bounds_max.z == 2.0f);
    // pi and the conditional operator.
    const hsr::SceneData t = hsr::make_formula_surface("x > 0 ? pi : -1", {-1, 1, 0, 1, 3, 2});
    CHECK(vertex(t, 0).y == -1.0f);
    CHECK(vertex(t, 2).y == float(3.14159265358979));
}

TEST_CASE("surface: the layout find_surface_grid reads back, faces up, adjacency", "[surface]") {
    const hsr::SceneData s = hsr::make_formula_surface("0.3*sin(3*x)*y", {-1, 1, -1, 1, 9, 6});
    const hsr_scene view = s.view();
    std::string why;
    const std::optional<hsr::SurfaceGrid> grid = hsr::find_surface_grid(view, &why);
    INFO(why);
    REQUIRE(grid.has_value());
    CHECK(grid->columns == 9);
    CHECK(grid->rows == 6);
    // Every face is turned up (world +y), so from above the grid is its front.
    for (uint32_t t = 0; t < s.triangle_count(); ++t) CHECK(s.face_normals[3 * t + 1] > 0.0f);
    // Adjacency: symmetric, across the shared edge; interior edges (grid lines and diagonals) have two
    // faces, the outline 2 (C - 1) + 2 (R - 1) edges one.
    std::map<std::pair<uint32_t, uint32_t>, int> faces_of_edge;
    uint32_t boundary = 0;
    for (uint32_t t = 0; t < s.triangle_count(); ++t)
        for (int i = 0; i < 3; ++i) {
            const uint32_t a = s.indices[3 * t + i], b = s.indices[3 * t + (i + 1) % 3];
            ++faces_of_edge[{std::min(a, b), std::max(a, b)}];
            const int32_t n = s.edge_neighbors[3 * t + i];
            if (n == HSR_NO_NEIGHBOR) {
                ++boundary;
                continue;
            }
            bool back = false, shares = false;
            for (int j = 0; j < 3; ++j) {
                back = back || s.edge_neighbors[3 * n + j] == int32_t(t);
                shares = shares || (s.indices[3 * n + j] == b && s.indices[3 * n + (j + 1) % 3] == a);
            }
            CHECK(back);
            CHECK(shares);
        }
    CHECK(boundary == 2 * 8 + 2 * 5);
    uint32_t interior = 0, outline = 0;
    for (const auto& [edge, count] : faces_of_edge) {
        const uint32_t a = edge.first, b = edge.second;
        const uint32_t ca = a % 9, ra = a / 9, cb = b % 9, rb = b / 9;
        const bool on_outline = (ra == rb && (ra == 0 || ra == 5)) || (ca == cb && (ca == 0 || ca == 8));
        CHECK(count == (on_outline ? 1 : 2));
        (count == 2 ? interior : outline) += 1;
    }
    CHECK(outline == 26);
    // 8 x 6 row edges + 9 x 5 column edges + 8 x 5 diagonals, less the outline.
    CHECK(interior == 8 * 6 + 9 * 5 + 8 * 5 - 26);
    // Smooth corner normals, unit length.
    for (size_t k = 0; k < s.corner_normals.size(); k += 3)
        CHECK(glm::length(glm::vec3(s.corner_normals[k], s.corner_normals[k + 1], s.corner_normals[k + 2])) ==
              Approx(1.0f).margin(1e-5));
}

TEST_CASE("surface: find_surface_grid refuses other meshes and says why", "[surface]") {
    hsr::SceneBuilder builder;
    builder.add_model_file(std::string(HSR_MODELS_DIR) + "/cube.obj");
    const hsr::SceneData cube = builder.build();
    std::string why;
    CHECK_FALSE(hsr::find_surface_grid(cube.view(), &why).has_value());
    CHECK_FALSE(why.empty());

    // A grid whose triangles were rebuilt by SceneBuilder (vertices renumbered) is no longer one.
    const hsr::SceneData s = hsr::make_formula_surface("x*y", {-1, 1, -1, 1, 5, 4});
    std::vector<glm::vec3> positions;
    for (uint32_t v = 0; v < s.vertex_count(); ++v) positions.push_back(vertex(s, v));
    hsr::SceneBuilder rebuilt;
    rebuilt.add_triangles(positions, s.indices);
    CHECK_FALSE(hsr::find_surface_grid(rebuilt.build().view(), &why).has_value());
    INFO(why);

    // One vertex moved off the lattice, one triangle with another diagonal.
    hsr::SceneData moved = s;
    moved.positions[3 * 6] += 0.01f;
    CHECK_FALSE(hsr::find_surface_grid(moved.view(), &why).has_value());
    CHECK(why.find("off the lattice") != std::string::npos);
    hsr::SceneData flipped = s;
    flipped.indices[2] = 5;
    CHECK_FALSE(hsr::find_surface_grid(flipped.view(), &why).has_value());
    CHECK(why.find("triangle 0") != std::string::npos);
}

TEST_CASE("surface: the range syntax", "[surface]") {
    hsr::SurfaceRange r = hsr::parse_surface_range("-3:3,-3:3,80x80");
    CHECK(r.x0 == -3);
    CHECK(r.x1 == 3);
    CHECK(r.y0 == -3);
    CHECK(r.y1 == 3);
    CHECK(r.columns == 80);
    CHECK(r.rows == 80);
    r = hsr::parse_surface_range(" 0 : 6.5 , -1e1:+1E1 , 200X50 ");
    CHECK(r.x0 == 0);
    CHECK(r.x1 == 6.5);
    CHECK(r.y0 == -10);
    CHECK(r.y1 == 10);
    CHECK(r.columns == 200);
    CHECK(r.rows == 50);
    r = hsr::parse_surface_range("-1:1,2:3,17");
    CHECK(r.columns == 17);
    CHECK(r.rows == 17);
    r = hsr::parse_surface_range("-1:1,2:3");
    CHECK(r.columns == 64);
    CHECK(r.rows == 64);

    CHECK(error_of([] { hsr::parse_surface_range("-3:3"); }) ==
          "surface range \"-3:3\": expected X0:X1,Y0:Y1 or X0:X1,Y0:Y1,COLUMNSxROWS, e.g. -3:3,-3:3,80x80");
    CHECK(error_of([] { hsr::parse_surface_range("3:-3,-3:3"); }) ==
          "surface range \"3:-3,-3:3\": x runs from 3 to -3; the first must be smaller");
    CHECK(error_of([] { hsr::parse_surface_range("-3:3,1:1"); }) ==
          "surface range \"-3:3,1:1\": y runs from 1 to 1; the first must be smaller");
    CHECK(error_of([] { hsr::parse_surface_range("-3:a,1:2"); }) == "surface range \"-3:a,1:2\": \"a\" is not a number");
    CHECK(error_of([] { hsr::parse_surface_range("-3:3,1:2,80y80"); }) ==
          "surface range \"-3:3,1:2,80y80\": the count \"80y80\" is not N or COLUMNSxROWS (whole numbers)");
    CHECK(error_of([] { hsr::parse_surface_range("-3:3,1:2,1x80"); }) ==
          "surface range \"-3:3,1:2,1x80\": 1x80 samples; a surface needs at least 2 per side");
    CHECK(error_of([] { hsr::parse_surface_range("-3:3,1:2,5000x2"); }) ==
          "surface range \"-3:3,1:2,5000x2\": 5000x2 samples; at most 4096 per side");
    CHECK(error_of([] { hsr::parse_surface_range("-3:3,1:2,2000x2000"); }) ==
          "surface range \"-3:3,1:2,2000x2000\": 2000x2000: 4000000 grid samples, over the limit of 1048576 (raise it "
          "with --limit surface-samples=N)");
    CHECK(error_of([] { hsr::parse_surface_range("-3:3,1:inf"); }) ==
          "surface range \"-3:3,1:inf\": the bounds must be finite numbers");
}

TEST_CASE("surface: formula errors are one line with muparser's message and the position", "[surface]") {
    const hsr::SurfaceRange range{-1, 1, -1, 1, 4, 4};
    CHECK(error_of([&] { hsr::make_formula_surface("sin(x)*z", range); }) ==
          "formula \"sin(x)*z\": Unexpected token \"z\" found at position 7 (the variables are x and y; \"z\" is not a "
          "known name)");
    CHECK(error_of([&] { hsr::make_formula_surface("sin(x", range); }) ==
          "formula \"sin(x\": Missing parenthesis at position 6");
    CHECK(error_of([&] { hsr::make_formula_surface("x+*y", range); }) ==
          "formula \"x+*y\": Unexpected operator \"*\" found at position 2");
    CHECK(error_of([&] { hsr::make_formula_surface("  ", range); }) ==
          "formula \"  \": the formula is empty; write z as a function of x and y");
    // Not finite at a grid point: which one.
    CHECK(error_of([&] { hsr::make_formula_surface("sqrt(x)", range); }) ==
          "formula \"sqrt(x)\": the value at x = -1, y = -1 (grid column 0, row 0) is not a number (NaN)");
    CHECK(error_of([&] { hsr::make_formula_surface("1/(y-1)", range); }) ==
          "formula \"1/(y-1)\": the value at x = -1, y = 1 (grid column 0, row 3) is infinite");
    CHECK(error_of([&] { hsr::make_formula_surface("1e300*x", range); }) ==
          "formula \"1e300*x\": the value at x = -1, y = -1 (grid column 0, row 0) is -1e+300, too large for a "
          "float");
    CHECK(error_of([&] { hsr::make_formula_surface("x", {1, 1, -1, 1, 4, 4}); }) ==
          "surface range: x runs from 1 to 1; the first must be smaller");
    CHECK(error_of([&] { hsr::make_formula_surface("x", {-1, 1, -1, 1, 4, 5000}); }) ==
          "surface range: 4x5000 samples; at most 4096 per side");
}

TEST_CASE("surface: a height map from a PNG, grey and colour", "[surface]") {
    // 4 x 3 grey image: value = (10 * column + 50 * row) / 255; the top row is at the back.
    const uint32_t W = 4, H = 3;
    std::vector<uint8_t> grey(W * H);
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) grey[y * W + x] = uint8_t(10 * x + 50 * y);
    const std::filesystem::path grey_png = temp_file("grey.png");
    hsr::write_png(grey_png, W, H, 1, grey);
    hsr::HeightmapOptions options;
    options.spacing = 0.5;
    options.height = 2.0;
    const hsr::SceneData s = hsr::make_heightmap_surface(grey_png, options);
    REQUIRE(s.vertex_count() == W * H);
    REQUIRE(hsr::find_surface_grid(s.view()).has_value());
    CHECK(s.object_names[0] == "heightmap grey.png");
    for (uint32_t r = 0; r < H; ++r)
        for (uint32_t c = 0; c < W; ++c) {
            const glm::vec3 p = vertex(s, r * W + c);
            const uint32_t image_row = H - 1 - r;
            CHECK(p.x == Approx((c - 1.5) * 0.5));
            CHECK(p.z == Approx(-(r - 1.0) * 0.5));
            CHECK(p.y == Approx(2.0 * (10 * c + 50 * image_row) / 255.0).margin(1e-6));
        }

    // Colour: luminance of the stored values; default height a fifth of the larger side.
    std::vector<uint8_t> rgb(W * H * 3, 0);
    rgb[0] = 255;               // pixel (0, 0) pure red
    rgb[3 * 1 + 1] = 255;       // pixel (1, 0) pure green
    rgb[3 * 2 + 2] = 255;       // pixel (2, 0) pure blue
    for (int k = 0; k < 3; ++k) rgb[3 * 3 + k] = 255;  // pixel (3, 0) white
    const std::filesystem::path rgb_png = temp_file("rgb.png");
    hsr::write_png(rgb_png, W, H, 3, rgb);
    const hsr::SceneData t = hsr::make_heightmap_surface(rgb_png);
    const double full = 3.0 / 5.0;  // (max(4, 3) - 1) * 1 / 5
    const uint32_t back = (H - 1) * W;  // image row 0 is grid row H - 1
    CHECK(vertex(t, back + 0).y == Approx(full * 0.2126).margin(1e-6));
    CHECK(vertex(t, back + 1).y == Approx(full * 0.7152).margin(1e-6));
    CHECK(vertex(t, back + 2).y == Approx(full * 0.0722).margin(1e-6));
    CHECK(vertex(t, back + 3).y == Approx(full).margin(1e-6));
    CHECK(vertex(t, 0).y == 0.0f);

    // Every second pixel.
    options.step = 2;
    const hsr::SceneData u = hsr::make_heightmap_surface(grey_png, options);
    CHECK(u.vertex_count() == 2 * 2);
    CHECK(vertex(u, 1).y == Approx(2.0 * (20 + 100) / 255.0).margin(1e-6));  // column 2 of image row 2
}

TEST_CASE("surface: a 16-bit grey height map keeps its 16 bits", "[surface]") {
    // Written with libpng's simplified interface: linear 16-bit grey is stored as it is.
    const uint32_t W = 3, H = 2;
    const uint16_t values[W * H] = {0, 1, 256, 65535, 32768, 12345};  // top row first
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = W;
    image.height = H;
    image.format = PNG_FORMAT_LINEAR_Y;
    const std::filesystem::path file = temp_file("sixteen.png");
    REQUIRE(png_image_write_to_file(&image, file.c_str(), 0, values, 0, nullptr) != 0);
    hsr::HeightmapOptions options;
    options.height = 65535.0;  // heights equal to the stored values
    const hsr::SceneData s = hsr::make_heightmap_surface(file, options);
    REQUIRE(s.vertex_count() == W * H);
    for (uint32_t r = 0; r < H; ++r)
        for (uint32_t c = 0; c < W; ++c)
            CHECK(vertex(s, r * W + c).y == float(values[(H - 1 - r) * W + c]));
}

TEST_CASE("surface: height map errors", "[surface]") {
    CHECK(error_of([] { hsr::make_heightmap_surface(temp_file("missing.png")); }).ends_with("missing.png: no such file"));
    const std::filesystem::path text = temp_file("not-a-png.png");
    std::ofstream(text) << "hello, not a picture\n";
    CHECK(error_of([&] { hsr::make_heightmap_surface(text); }).ends_with("not-a-png.png: not a PNG file"));
    // A truncated PNG: libpng's message.
    const std::filesystem::path good = temp_file("good.png");
    std::vector<uint8_t> pixels(16 * 16, 128);
    hsr::write_png(good, 16, 16, 1, pixels);
    const auto size = std::filesystem::file_size(good);
    std::filesystem::copy_file(good, temp_file("short.png"), std::filesystem::copy_options::overwrite_existing);
    std::filesystem::resize_file(temp_file("short.png"), size / 2);
    CHECK(error_of([&] { hsr::make_heightmap_surface(temp_file("short.png")); }).find("cannot read it as PNG") !=
          std::string::npos);
    // One pixel wide.
    const std::filesystem::path line = temp_file("line.png");
    hsr::write_png(line, 1, 5, 1, std::vector<uint8_t>(5, 0));
    CHECK(error_of([&] { hsr::make_heightmap_surface(line); }).ends_with("1x5 samples; a surface needs at least 2 per side"));
    hsr::HeightmapOptions bad;
    bad.spacing = 0;
    CHECK(error_of([&] { hsr::make_heightmap_surface(good, bad); }).ends_with("the spacing 0 must be a number greater than 0"));
}
