// The weiler-atherton plugin (polygon area sorting, Weiler & Atherton 1977) against the plain zbuffer
// plugin, both loaded through the real ABI: the same surface at every covered pixel of the cube,
// monkey, bunny, the interpenetrating boxes and the cyclically overlapping three polygons, from
// perspective and orthographic cameras, with and without clip planes; the visible fragments cover
// each pixel once (but for a widening band, measured); the counters of two hand-made cases counted by
// hand; steps run to the end equal render; a frame that needs too many fragments is refused.
#include "hsr/abi.h"
#include "hsr/image.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "surface_test_support.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

// The fragments are drawn with the z-buffer's own triangle setups, so depth and barycentrics are
// the z-buffer's, except where a setup comes from clipping (near plane, clip planes), which this
// plugin does again on the clipped polygon: allow a few float steps there.
const Agreement kWeilerAtherton{.plugin = "weiler-atherton", .label = "weiler-atherton", .bit_identical = false};
constexpr double kDepthUlps = 8.0;
constexpr double kBary = 1e-5;

// The distance in pixels from window point p to the nearest edge of triangle `face` as the camera
// projects it (infinite when a corner lies behind the eye).
double distance_to_edges(const hsr_scene& scene, const hsr_camera& camera, uint32_t face, glm::dvec2 p) {
    glm::dmat4 view_projection;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) view_projection[c][r] = camera.view_projection[4 * c + r];
    glm::dvec2 corner[3];
    for (int k = 0; k < 3; ++k) {
        const float* v = scene.positions + 3 * size_t(scene.indices[3 * size_t(face) + k]);
        const glm::dvec4 clip = view_projection * glm::dvec4(v[0], v[1], v[2], 1.0);
        if (!(clip.w > 0.0)) return std::numeric_limits<double>::infinity();
        corner[k] = {(clip.x / clip.w + 1.0) * 0.5 * camera.width, (1.0 - clip.y / clip.w) * 0.5 * camera.height};
    }
    double nearest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const glm::dvec2 a = corner[k], b = corner[(k + 1) % 3];
        const double t = std::clamp(glm::dot(p - a, b - a) / std::max(glm::dot(b - a, b - a), 1e-300), 0.0, 1.0);
        nearest = std::min(nearest, glm::length(a + t * (b - a) - p));
    }
    return nearest;
}

// Pixels where the two frames show different surfaces though the pixel centre lies within
// kEdgeBand pixels of an edge of one of the two triangles: there snapping the corners to the
// rasterizer's 1/256-pixel grid decides which triangle covers the centre, and the fragments'
// cuts, whose corners are snapped apart from the triangle's, may decide it otherwise.
constexpr double kEdgeBand = 1.0 / 128.0;

struct EdgeCases {
    uint64_t on_edges = 0;  // different surfaces with the centre within kEdgeBand of an edge
    uint64_t other = 0;     // different surfaces anywhere else (must not happen)
    std::string first_other;
};

EdgeCases classify_differences(const hsr_scene& scene, const hsr_camera& camera, const hsr::Frame& frame,
                               const hsr::Frame& reference) {
    EdgeCases e;
    for (size_t p = 0; p < reference.face.size(); ++p) {
        const uint32_t a = frame.face[p], b = reference.face[p];
        const bool same = a == b && (reference.instance.empty() || frame.instance[p] == reference.instance[p]);
        if (same || b == HSR_NO_FACE) continue;
        const float da = frame.depth[p], db = reference.depth[p];
        if (a != HSR_NO_FACE && std::abs(da - db) <= 2.0f * std::numeric_limits<float>::epsilon() * std::max(da, db))
            continue;  // a tie, as compare() counts it
        const glm::dvec2 centre(double(p % reference.width) + 0.5, double(p / reference.width) + 0.5);
        const double d = std::min(distance_to_edges(scene, camera, b, centre),
                                  a == HSR_NO_FACE ? std::numeric_limits<double>::infinity()
                                                   : distance_to_edges(scene, camera, a, centre));
        if (d <= kEdgeBand) {
            ++e.on_edges;
        } else if (++e.other == 1) {
            e.first_other = "pixel " + std::to_string(p % reference.width) + "," + std::to_string(p / reference.width) +
                            ": face " + std::to_string(a) + " depth " + std::to_string(da) + ", zbuffer face " +
                            std::to_string(b) + " depth " + std::to_string(db) + ", " + std::to_string(d) +
                            " px from an edge";
        }
    }
    return e;
}

// What the agreement tests found over all their frames (printed by the last test case).
struct Totals {
    uint64_t covered = 0, ties = 0, on_edges = 0, not_bit_identical = 0;
    double worst_depth_ulps = 0, worst_bary = 0;
};
Totals totals;

// The plugin's frame against zbuffer's: the same surface at every covered pixel but ties and
// centres on edges (both fewer than 0.1 % of the covered pixels), depth and barycentrics of the
// same surface within the bounds above. The scene must have no instances (edges are found from
// its positions).
Picture check_same_picture(const hsr_scene& scene, const hsr_camera& camera, const Settings& settings = {},
                           const Settings& zbuffer_settings = {}) {
    Picture p;
    p.reference = render("zbuffer", scene, camera, zbuffer_settings);
    p.frame = render("weiler-atherton", scene, camera, settings);
    const Comparison& c = p.comparison = compare(p.frame, p.reference, kWeilerAtherton);
    const EdgeCases e = classify_differences(scene, camera, p.frame, p.reference);
    INFO(camera.width << "x" << camera.height << ": " << e.first_other);
    CHECK(c.covered > 0);
    CHECK(e.other == 0);
    CHECK(c.different == e.on_edges);
    CHECK(double(c.ties) < 0.001 * double(c.covered));
    CHECK(double(e.on_edges) < 0.001 * double(c.covered));
    CHECK(c.worst_depth_ulps <= kDepthUlps);
    CHECK(c.worst_bary <= kBary);
    totals.covered += c.covered;
    totals.ties += c.ties;
    totals.on_edges += e.on_edges;
    totals.worst_depth_ulps = std::max(totals.worst_depth_ulps, c.worst_depth_ulps);
    totals.worst_bary = std::max(totals.worst_bary, c.worst_bary);
    for (size_t q = 0; q < p.frame.face.size(); ++q)
        if (p.frame.face[q] != HSR_NO_FACE && p.frame.face[q] == p.reference.face[q] &&
            (p.frame.depth[q] != p.reference.depth[q] || p.frame.bary[2 * q] != p.reference.bary[2 * q] ||
             p.frame.bary[2 * q + 1] != p.reference.bary[2 * q + 1]))
            ++totals.not_bit_identical;
    return p;
}

// An orthographic camera looking down -z from z = 5 at the square [-1, 1]^2: window x = (x + 1) / 2
// * size, window y = (1 - y) / 2 * size.
hsr_camera top_view(uint32_t size) {
    return make_camera(size, size, HSR_PROJECTION_ORTHOGRAPHIC, glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, 1.0f, 10.0f),
                       {0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0f, 10.0f);
}

hsr::SceneData triangles(const std::vector<glm::vec3>& corners) {
    hsr::SceneBuilder builder;
    std::vector<uint32_t> indices(corners.size());
    for (uint32_t k = 0; k < indices.size(); ++k) indices[k] = k;
    builder.add_triangles(corners, indices);
    return builder.build();
}

uint64_t covered(const hsr::Frame& frame) {
    return uint64_t(std::count_if(frame.face.begin(), frame.face.end(), [](uint32_t f) { return f != HSR_NO_FACE; }));
}

// The frames the agreement tests compare with zbuffer's.
void committed_views() {
    for (const char* file : {"cube.obj", "boxes.scene", "three-polygons.scene"}) {
        INFO(file);
        const hsr::SceneData& data = model(file);
        const hsr_scene scene = data.view();
        check_same_picture(scene, orbit(data, 35, 25, 1, false, 200));
        check_same_picture(scene, orbit(data, -120, -30, 1.2f, true, 160, 128));
        check_same_picture(scene, orbit(data, 200, 60, 2.5f, false, 128));  // zoomed in: much off screen
        check_same_picture(scene, orbit(data, 10, 5, 1, false, 160), {{"cull-backfaces", "true"}},
                           {{"cull-backfaces", "true"}});
    }
}

void monkey_views() {
    test_models::require_fetched();
    const hsr::SceneData& monkey = model("monkey.obj");
    const hsr_scene scene = monkey.view();
    check_same_picture(scene, orbit(monkey, 0, 0, 1, false, 256));
    check_same_picture(scene, orbit(monkey, 150, 30, 1.3f, false, 200));
    check_same_picture(scene, orbit(monkey, -70, -25, 1, true, 200));
}

void bunny_views() {
    test_models::require_fetched();
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr_scene scene = bunny.view();
    check_same_picture(scene, orbit(bunny, 0, 0, 1, false, 256));
    check_same_picture(scene, orbit(bunny, -60, -20, 1, true, 200));
    check_same_picture(scene, orbit(bunny, 200, 10, 4, false, 160));
}

}  // namespace

TEST_CASE("weiler-atherton: the cube, the boxes and the three polygons match zbuffer", "[weiler-atherton]") {
    committed_views();
}

TEST_CASE("weiler-atherton: the monkey matches zbuffer", "[weiler-atherton]") { monkey_views(); }

TEST_CASE("weiler-atherton: the bunny matches zbuffer", "[weiler-atherton][slow]") { bunny_views(); }

// The figures docs/algorithms/weiler-atherton.md quotes (a hidden case, not run by the suite):
//   build/tests/test_weiler_atherton "[figures]"
TEST_CASE("weiler-atherton: ties and edge pixels over all agreement views", "[weiler-atherton][.figures]") {
    committed_views();
    monkey_views();
    bunny_views();
    WARN("covered " << totals.covered << ", ties " << totals.ties << ", centres on edges " << totals.on_edges
                    << ", same surface not bit-identical " << totals.not_bit_identical << ", worst depth ulps "
                    << totals.worst_depth_ulps << ", worst bary " << totals.worst_bary);
}

TEST_CASE("weiler-atherton: visible fragments cover each pixel once, but for their widened edges", "[weiler-atherton]") {
    // Every covered pixel is tested by at least one visible fragment; more than one only where two
    // fragments' widened outlines overlap (kWidening = 1/64 pixel around each), which is a thin band
    // along the cuts: few pixels, and never more than a few fragments at one.
    test_models::require_fetched();
    for (const char* file : {"boxes.scene", "monkey.obj", "bunny.obj"}) {
        INFO(file);
        const hsr::SceneData& data = model(file);
        const hsr_camera camera = orbit(data, 25, 15, 1, false, 256);
        const hsr::Frame frame = render("weiler-atherton", data.view(), camera, {}, true);
        uint64_t covered_pixels = 0, tested_twice = 0, uncovered_tested = 0;
        uint32_t most = 0;
        for (size_t p = 0; p < frame.face.size(); ++p) {
            const uint32_t tests = frame.depth_tests[p];
            most = std::max(most, tests);
            if (frame.face[p] == HSR_NO_FACE) {
                uncovered_tested += tests > 0 ? 1 : 0;
                continue;
            }
            ++covered_pixels;
            CHECK(tests >= 1);
            tested_twice += tests >= 2 ? 1 : 0;
        }
        CHECK(uncovered_tested == 0);
        CHECK(covered_pixels == covered(render("zbuffer", data.view(), camera)));
        CHECK(double(tested_twice) < 0.005 * double(covered_pixels));
        CHECK(most <= 3);
        CHECK(counter(frame, "pixels-depth-tested") == std::accumulate(frame.depth_tests.begin(), frame.depth_tests.end(), uint64_t(0)));
        CHECK(counter(frame, "pixels-written") >= covered_pixels);
        CHECK(counter(frame, "pixels-written") - covered_pixels <= tested_twice);
    }
}

TEST_CASE("weiler-atherton: two overlapping triangles, counted by hand", "[weiler-atherton]") {
    // A (z = 0.5) in front of B (z = 0); B pokes out below A's bottom edge and lies inside A's other
    // two edges. A is the first clip polygon (nearest): B is clipped once (clips 1), by A's bottom
    // edge only, into a piece outside (a triangle below y = -0.8) and a piece inside, hidden behind
    // A (fragments 2, hidden 1). B's outside piece is the next clip polygon and overlaps nothing
    // left. Visible: A and B's outside piece.
    const hsr::SceneData data = triangles({{-0.8f, -0.8f, 0.5f}, {0.8f, -0.8f, 0.5f}, {0.0f, 0.8f, 0.5f},
                                           {-0.2f, -0.4f, 0.0f}, {0.0f, -0.95f, 0.0f}, {0.2f, -0.4f, 0.0f}});
    const hsr_camera camera = top_view(64);
    const Picture p = check_same_picture(data.view(), camera);
    CHECK(counter(p.frame, "polygons-in") == 2);
    CHECK(counter(p.frame, "clips") == 1);
    CHECK(counter(p.frame, "fragments") == 2);
    CHECK(counter(p.frame, "fragments-hidden") == 1);
    CHECK(counter(p.frame, "fragments-visible") == 2);
    CHECK(counter(p.frame, "recursive-subdivisions") == 0);
    // B shows only below y = -0.8, i.e. below window row (1 + 0.8) / 2 * 64 = 57.6.
    for (size_t q = 0; q < p.frame.face.size(); ++q)
        if (p.frame.face[q] == 1) CHECK(double(q / 64) + 0.5 > 57.6);
    CHECK(std::count(p.frame.face.begin(), p.frame.face.end(), 1u) > 0);
}

TEST_CASE("weiler-atherton: interpenetrating triangles start a recursive subdivision, counted by hand", "[weiler-atherton]") {
    // D lies in the plane z = x (x from -0.6 to 0.6), inside A (z = 0.5) on screen. D reaches
    // nearest (z = 0.6), so it is the first clip polygon. A is clipped by D's three edges (clips 1):
    // three pieces outside, and the piece inside, which D's plane splits at x = 0.5 into a part
    // behind D (hidden) and a part in front (fragments 5, hidden 1). That part in front starts a
    // recursive subdivision (1) as the next clip polygon, alone in it: visible. Then D is clipped by
    // it (clips 2): the part of D left of x = 0.5 is hidden, the part right of it is visible
    // (fragments 7, hidden 2). A's three outside pieces overlap nothing left: visible, 5 in all.
    const hsr::SceneData data = triangles({{-0.8f, -0.8f, 0.5f}, {0.8f, -0.8f, 0.5f}, {0.0f, 0.8f, 0.5f},
                                           {-0.6f, -0.6f, -0.6f}, {0.6f, -0.6f, 0.6f}, {0.0f, 0.6f, 0.0f}});
    const hsr_camera camera = top_view(64);
    const Picture p = check_same_picture(data.view(), camera);
    CHECK(counter(p.frame, "polygons-in") == 2);
    CHECK(counter(p.frame, "clips") == 2);
    CHECK(counter(p.frame, "fragments") == 7);
    CHECK(counter(p.frame, "fragments-hidden") == 2);
    CHECK(counter(p.frame, "fragments-visible") == 5);
    CHECK(counter(p.frame, "recursive-subdivisions") == 1);
    // D shows exactly right of x = 0.5 (window column 48) within its outline.
    for (size_t q = 0; q < p.frame.face.size(); ++q)
        if (p.frame.face[q] == 1) CHECK(double(q % 64) + 0.5 > 48.0);
    CHECK(std::count(p.frame.face.begin(), p.frame.face.end(), 1u) > 0);

    // Steps: the sort; the clip polygon D, the recursion into A's part in front of it, that part as
    // clip polygon, A's three outside pieces as clip polygons; then the five visible fragments.
    hsr::HiddenSurfaceRemover remover(plugin("weiler-atherton"), {});
    hsr::Frame all;
    hsr::resolve_visibility_steps(data.view(), camera, remover, all, 0, false);
    REQUIRE(all.steps.has_value());
    CHECK(all.steps->taken == 12);
    CHECK(counter(all, "steps") == 12);
}

namespace {

// One and then two clip planes through the model: the same picture as zbuffer's with the same planes.
void check_clip_planes(const char* file) {
    test_models::require_fetched();
    const hsr::SceneData& data = model(file);
    const glm::vec3 centre = 0.5f * (data.bounds_min + data.bounds_max);
    hsr_camera camera = orbit(data, 30, 20, 1, false, 192);
    // Keep x <= centre.x (a section through the middle), then also y >= centre.y - 0.1 * height.
    camera.clip_plane_count = 1;
    const float one[4] = {-1.0f, 0.0f, 0.0f, centre.x};
    std::copy(one, one + 4, camera.clip_planes[0]);
    const Picture cut_once = check_same_picture(data.view(), camera);
    camera.clip_plane_count = 2;
    const float two[4] = {0.0f, 1.0f, 0.0f, -(centre.y - 0.1f * (data.bounds_max.y - data.bounds_min.y))};
    std::copy(two, two + 4, camera.clip_planes[1]);
    const Picture cut_twice = check_same_picture(data.view(), camera);
    hsr_camera uncut = camera;
    uncut.clip_plane_count = 0;
    CHECK(covered(cut_twice.frame) < covered(render("weiler-atherton", data.view(), uncut)));
    CHECK(covered(cut_twice.frame) < covered(cut_once.frame));
}

}  // namespace

TEST_CASE("weiler-atherton: clip planes cut the monkey before it hides anything, as in zbuffer", "[weiler-atherton]") {
    check_clip_planes("monkey.obj");
}

TEST_CASE("weiler-atherton: clip planes cut the bunny before it hides anything, as in zbuffer", "[weiler-atherton][slow]") {
    check_clip_planes("bunny.obj");
}

namespace {

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

hsr::Frame run_steps(const hsr_scene& scene, const hsr_camera& camera, uint64_t stop_after) {
    hsr::HiddenSurfaceRemover remover(plugin("weiler-atherton"), {});
    hsr::Frame frame;
    hsr::resolve_visibility_steps(scene, camera, remover, frame, stop_after, true);
    REQUIRE(frame.steps.has_value());
    return frame;
}

}  // namespace

TEST_CASE("weiler-atherton: steps to the end equal render, fragments after clip polygons", "[weiler-atherton]") {
    test_models::require_fetched();
    for (const char* file : {"boxes.scene", "monkey.obj"}) {
        INFO(file);
        const hsr::SceneData& data = model(file);
        const hsr_camera camera = orbit(data, -40, 20, 1.1f, false, 96, 80);
        const hsr::Frame plain = render("weiler-atherton", data.view(), camera, {}, true);
        const hsr::Frame all = run_steps(data.view(), camera, 0);
        CHECK(same_bytes(all.depth, plain.depth));
        CHECK(same_bytes(all.face, plain.face));
        CHECK(same_bytes(all.bary, plain.bary));
        CHECK(same_bytes(all.instance, plain.instance));
        CHECK(same_bytes(all.depth_tests, plain.depth_tests));
        const uint64_t visible = counter(plain, "fragments-visible");
        const uint64_t taken = all.steps->taken;
        REQUIRE(taken > visible);
        CHECK(all.steps->last.type == "fragment");

        // After the last clip polygon nothing is drawn yet.
        const hsr::Frame clipped = run_steps(data.view(), camera, taken - visible);
        CHECK(clipped.steps->last.type == "clip-polygon");
        CHECK(covered(clipped) == 0);
        // One fragment later: exactly its pixels, all of its face.
        const hsr::Frame one = run_steps(data.view(), camera, taken - visible + 1);
        CHECK(one.steps->last.type == "fragment");
        CHECK(covered(one) == one.steps->last.pixels_written);
        for (uint32_t f : one.face)
            if (f != HSR_NO_FACE) CHECK(f == one.steps->last.face);
        // Half way: a subset of the final picture's pixels, each with the final surface or one
        // behind it that a later fragment covers along a widened edge.
        const hsr::Frame half = run_steps(data.view(), camera, taken - visible / 2);
        uint64_t half_covered = 0;
        for (size_t p = 0; p < half.face.size(); ++p) {
            if (half.face[p] == HSR_NO_FACE) continue;
            ++half_covered;
            CHECK(plain.face[p] != HSR_NO_FACE);
            CHECK(half.depth[p] >= plain.depth[p]);
        }
        CHECK(half_covered > covered(one));
        CHECK(half_covered < covered(plain));
    }
}

TEST_CASE("weiler-atherton: too many fragments are refused in one line", "[weiler-atherton]") {
    test_models::require_fetched();
    const std::string refusal = "weiler-atherton: the frame needs more than 5000 polygons and fragments (parameter max-fragments)";
    // The monkey's 3,936 triangles fit, but not with the 16,000-odd fragments clipping makes.
    const hsr::SceneData& monkey = model("monkey.obj");
    const hsr_camera camera = orbit(monkey, 0, 0, 1, false, 128);
    CHECK(counter(render("weiler-atherton", monkey.view(), camera), "fragments") > 5000);
    CHECK_THROWS_WITH(render("weiler-atherton", monkey.view(), camera, {{"max-fragments", "5000"}}), Catch::Contains(refusal));
    // The bunny's 69,666 triangles alone are too many: refused before any work.
    const hsr::SceneData& bunny = model("bunny.obj");
    CHECK_THROWS_WITH(render("weiler-atherton", bunny.view(), camera, {{"max-fragments", "5000"}}),
                      Catch::Contains(refusal));
}

// Writes docs/images/weiler-atherton-fragments.png (a hidden case, not run by the suite): the picture
// docs/images/weiler-atherton.png (boxes.scene at 400x400, --zoom 1.6, as `hsr render` draws it) with
// the outline of every visible fragment, taken from the steps, drawn over it. Both are in the
// docs/images/ of the working folder, so that docs/images/make.sh can run it in a folder of its own.
TEST_CASE("weiler-atherton: the picture of the visible fragments", "[weiler-atherton][.figures]") {
    const std::filesystem::path images = std::filesystem::path("docs") / "images";
    hsr::Image image = hsr::read_png_rgb(images / "weiler-atherton.png");
    const hsr::SceneData& data = model("boxes.scene");
    const hsr_camera camera = orbit(data, 35, 25, 1.6f, false, image.width, image.height);
    const hsr::Frame all = run_steps(data.view(), camera, 0);
    const uint64_t visible = counter(all, "fragments-visible");
    auto plot = [&](double x, double y) {
        const int32_t px = int32_t(std::floor(x)), py = int32_t(std::floor(y));
        if (px < 0 || py < 0 || px >= int32_t(image.width) || py >= int32_t(image.height)) return;
        uint8_t* rgb = &image.pixels[3 * (size_t(py) * image.width + px)];
        rgb[0] = 255;
        rgb[1] = 240;
        rgb[2] = 80;
    };
    for (uint64_t k = all.steps->taken - visible + 1; k <= all.steps->taken; ++k) {
        const hsr::Frame step = run_steps(data.view(), camera, k);
        const std::vector<float>& l = step.steps->last.lines;
        for (size_t i = 0; i + 3 < l.size(); i += 4) {
            const double length = std::hypot(l[i + 2] - l[i], l[i + 3] - l[i + 1]);
            const int n = int(std::ceil(2.0 * length)) + 1;
            for (int s = 0; s <= n; ++s)
                plot(l[i] + (l[i + 2] - l[i]) * s / n, l[i + 1] + (l[i + 3] - l[i + 1]) * s / n);
        }
    }
    hsr::write_png(images / "weiler-atherton-fragments.png", image.width, image.height, 3, image.pixels);
}
