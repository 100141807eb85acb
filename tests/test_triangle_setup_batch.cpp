// Triangle setup in SIMD batches (hsr/triangle_setup_batch.hpp) against the scalar setup it stands
// for (setup_whole_triangle of hsr/triangle_setup.hpp), field by field and bit for bit, on every
// Highway target this CPU runs (each forced in turn): random small, large and sliver triangles of
// both orientations, corners up to the guard band, batches of every length from 1 to kSetupBatch.
#include "hsr/triangle_setup_batch.hpp"
#include "highway_targets.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using highway_tests::for_each_target;

using namespace hsr::raster;

bool same_bits(double a, double b) { return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b); }
bool same_plane(const Plane& a, const Plane& b) {
    return same_bits(a.origin, b.origin) && same_bits(a.dx, b.dx) && same_bits(a.dy, b.dy);
}
bool same_setup(const TriangleSetup& a, const TriangleSetup& b) {
    bool same = a.min_x == b.min_x && a.min_y == b.min_y && a.max_x == b.max_x && a.max_y == b.max_y &&
                a.front_facing == b.front_facing && same_plane(a.depth, b.depth) && same_plane(a.inv_w, b.inv_w) &&
                same_plane(a.b1_over_w, b.b1_over_w) && same_plane(a.b2_over_w, b.b2_over_w);
    for (int k = 0; k < 3; ++k)
        same = same && a.edge_origin[k] == b.edge_origin[k] && a.edge_dx[k] == b.edge_dx[k] && a.edge_dy[k] == b.edge_dy[k];
    return same;
}

WindowVertex vertex_at(double x, double y, double depth, double inv_w) {
    WindowVertex v{};
    v.exact_x = x;
    v.exact_y = y;
    v.x = int32_t(std::nearbyint(x * kSubpixelScale));
    v.y = int32_t(std::nearbyint(y * kSubpixelScale));
    v.depth = depth;
    v.inv_w = inv_w;
    v.b1 = 0.25;  // not read: a whole triangle's corners are (0, 0), (1, 0), (0, 1)
    v.b2 = 0.5;
    return v;
}

// Random triangles that setup accepts, of the kinds a frame holds.
std::vector<std::array<WindowVertex, 3>> random_triangles(std::mt19937_64& random, uint32_t width, uint32_t height,
                                                          size_t count) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<std::array<WindowVertex, 3>> out;
    while (out.size() < count) {
        const int kind = int(out.size() % 4);
        const double cx = unit(random) * width, cy = unit(random) * height;
        const double reach = kind == 0 ? 4.0 : kind == 1 ? 200.0 : kind == 2 ? 2.0 * kGuardBand : 30.0;
        std::array<WindowVertex, 3> t;
        for (int c = 0; c < 3; ++c) {
            double x = cx + (unit(random) - 0.5) * 2.0 * reach, y = cy + (unit(random) - 0.5) * 2.0 * reach;
            if (kind == 3 && c == 2) {  // a sliver: the third corner a hair off the line of the first two
                x = 0.5 * (t[0].exact_x + t[1].exact_x) + (unit(random) - 0.5) * 0.01;
                y = 0.5 * (t[0].exact_y + t[1].exact_y) + (unit(random) - 0.5) * 0.01;
            }
            x = std::clamp(x, -2.0 * kGuardBand, 2.0 * kGuardBand);
            y = std::clamp(y, -2.0 * kGuardBand, 2.0 * kGuardBand);
            t[c] = vertex_at(x, y, unit(random), 0.01 + 10.0 * unit(random));
        }
        PixelBounds bounds;
        if (triangle_pixel_bounds(t[0], t[1], t[2], width, height, bounds) == SetupResult::kOk) out.push_back(t);
    }
    return out;
}

}  // namespace

TEST_CASE("triangle setup in SIMD batches equals the scalar setup bit for bit", "[zbuffer]") {
    std::mt19937_64 random(20261130);
    size_t slivers_on_snapped_corners = 0;
    for (const auto& size : {std::pair<uint32_t, uint32_t>{1024, 1024}, {37, 5}, {1, 1}, {16384, 300}}) {
        const uint32_t width = size.first, height = size.second;  // named: clang 14 lambdas cannot capture bindings
        const auto triangles = random_triangles(random, width, height, 4000);
        std::vector<TriangleSetup> expected(triangles.size());
        for (size_t t = 0; t < triangles.size(); ++t) {
            REQUIRE(setup_whole_triangle(triangles[t][0], triangles[t][1], triangles[t][2], width, height, expected[t]) ==
                    SetupResult::kOk);
            const auto& v = triangles[t];
            const double exact_area = (v[1].exact_x - v[0].exact_x) * (v[2].exact_y - v[0].exact_y) -
                                      (v[2].exact_x - v[0].exact_x) * (v[1].exact_y - v[0].exact_y);
            const double grid_area = (double(v[1].x - v[0].x) * (v[2].y - v[0].y) -
                                      double(v[2].x - v[0].x) * (v[1].y - v[0].y)) / 65536.0;
            const double ratio = exact_area / grid_area;
            if (!(ratio > 0.5 && ratio < 2.0)) ++slivers_on_snapped_corners;
        }
        for_each_target([&](int64_t) {
            for (size_t length = 1; length <= kSetupBatch; ++length) {
                for (size_t first = 0; first + length <= triangles.size(); first += length) {
                    const WindowVertex* corners[kSetupBatch][3];
                    for (size_t n = 0; n < length; ++n)
                        for (int c = 0; c < 3; ++c) corners[n][c] = &triangles[first + n][c];
                    TriangleSetup got[kSetupBatch];
                    setup_whole_triangles(corners, length, width, height, got);
                    for (size_t n = 0; n < length; ++n) {
                        INFO("image " << width << "x" << height << ", triangle " << first + n << ", batch of " << length);
                        REQUIRE(same_setup(got[n], expected[first + n]));
                    }
                }
            }
        });
    }
    CHECK(slivers_on_snapped_corners > 0);  // the branch that interpolates over snapped corners is tried
}
