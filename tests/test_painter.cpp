// The painter plugin (depth sort, Newell, Newell & Sancha 1972) through the real ABI: mode=newell
// against the plain zbuffer plugin on real models and the intersecting boxes from several cameras,
// with clip planes, and on the cyclic three-polygon exercise, where mode=naive must come out wrong;
// hand-made pairs of triangles where each of the seven tests decides (the counters say which ran);
// steps run to the end against a plain render; and the refusal above max-polygons.
#include "hsr/abi.h"
#include "hsr/camera.hpp"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/random_triangles.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"
#include "surface_test_support.hpp"

#include "../plugins/hidden-surface/painter/polygons.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

// compare() checks the same surface only; check_newell asks for bit-identical depth and
// barycentrics where the surface is the same, and sorts the other pixels.
const Agreement kPainter{.plugin = "painter", .label = "painter", .bit_identical = false};

// What the painter's frame shows where it is not the zbuffer's surface.
struct Exceptions {
    uint64_t coplanar_ties = 0;  // a tie between two triangles in one plane (z-fighting in the zbuffer)
    uint64_t other_ties = 0;     // a tie elsewhere (where two surfaces meet)
    uint64_t shared_edge = 0;    // a pixel centre on the edge two triangles share
    uint64_t wrong = 0;          // anything else
};

// The plane of triangle t in world space (a scene without instances): unit normal and offset.
glm::dvec4 world_plane(const hsr::SceneData& s, uint32_t t) {
    glm::dvec3 v[3];
    for (int k = 0; k < 3; ++k) {
        const uint32_t i = s.indices[3 * size_t(t) + k];
        v[k] = glm::dvec3(s.positions[3 * i], s.positions[3 * i + 1], s.positions[3 * i + 2]);
    }
    const glm::dvec3 n = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
    return glm::dvec4(n, -glm::dot(n, v[0]));
}

bool coplanar(const hsr::SceneData& s, uint32_t a, uint32_t b) {
    const glm::dvec4 pa = world_plane(s, a), pb = world_plane(s, b);
    const double same = glm::dot(glm::dvec3(pa), glm::dvec3(pb));
    const double size = glm::length(glm::dvec3(s.bounds_max - s.bounds_min));
    return std::abs(same) > 1.0 - 1e-6 && std::abs(pa.w - (same > 0 ? pb.w : -pb.w)) <= 1e-5 * size;
}

bool share_edge(const hsr::SceneData& s, uint32_t a, uint32_t b) {
    int common = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) common += s.indices[3 * size_t(a) + i] == s.indices[3 * size_t(b) + j];
    return common >= 2;
}

// Sorts the pixels where painter and zbuffer show different surfaces (coplanar ties only in a
// scene without instances).
Exceptions classify(const hsr::SceneData& s, const hsr::Frame& frame, const hsr::Frame& reference) {
    Exceptions e;
    for (size_t p = 0; p < reference.face.size(); ++p) {
        const uint32_t a = frame.face[p], b = reference.face[p];
        const bool same_instance = reference.instance.empty() || frame.instance[p] == reference.instance[p];
        if (a == b && same_instance) continue;
        if (a == HSR_NO_FACE || b == HSR_NO_FACE) {
            ++e.wrong;
            continue;
        }
        const float da = frame.depth[p], db = reference.depth[p];
        const bool tie = std::abs(da - db) <= 2.0f * std::numeric_limits<float>::epsilon() * std::max(da, db);
        if (tie)
            ++(s.instances.empty() && coplanar(s, a, b) ? e.coplanar_ties : e.other_ties);
        else if (same_instance && share_edge(s, a, b))
            ++e.shared_edge;
        else
            ++e.wrong;
    }
    return e;
}

// Newell's frame against zbuffer's: the same surface at every covered pixel but ties and pixel
// centres on the edge two triangles share. Where two triangles sharing an edge fold over one
// another (at a silhouette) the rasterizer snaps the shared corners to its 1/256-pixel grid, and a
// pixel centre within that distance of the edge can be covered by both though it lies outside
// both exact triangles: their depth planes, continued past the edge, then rank them the other way
// round, and which one wins depends on the order of drawing. Coplanar triangles overlapping (the
// boxes' faces) z-fight in the zbuffer; the painter shows the one painted last. Unsplit triangles
// have the zbuffer's depth and barycentrics bit for bit; split pieces are the same triangle's
// pixels, kept or not by the cut, so they do too.
Picture check_newell(const hsr::SceneData& scene, const hsr_camera& camera, const Settings& settings = {},
                     const Settings& zbuffer_settings = {}) {
    Picture p;
    p.reference = render("zbuffer", scene.view(), camera, zbuffer_settings);
    p.frame = render("painter", scene.view(), camera, settings);
    const Comparison& c = p.comparison = compare(p.frame, p.reference, kPainter);
    const Exceptions e = classify(scene, p.frame, p.reference);
    INFO(camera.width << "x" << camera.height << ": " << c.covered << " covered, " << e.coplanar_ties
                      << " coplanar ties, " << e.other_ties << " other ties, " << e.shared_edge
                      << " on shared edges, " << e.wrong << " wrong; " << c.first_difference);
    CHECK(c.covered > 0);
    CHECK(e.wrong == 0);
    CHECK(double(e.other_ties + e.shared_edge) <= 0.001 * double(c.covered));
    CHECK(c.worst_depth_ulps == 0.0);
    CHECK(c.worst_bary == 0.0);
    CHECK(counter(p.frame, "cycles-unresolved") == 0);
    return p;
}

// An orthographic camera at the origin looking down -z over [-4, 4] x [-4, 4]: world x, y are
// window (x + 4) * size / 8, (4 - y) * size / 8; depth grows with -z.
hsr_camera flat_camera(uint32_t size = 64) {
    return make_camera(size, size, HSR_PROJECTION_ORTHOGRAPHIC, glm::ortho(-4.0f, 4.0f, -4.0f, 4.0f, 1.0f, 20.0f),
                       {0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1.0f, 20.0f);
}

// Two triangles, P (face 0) and Q (face 1).
hsr::SceneData two_triangles(std::initializer_list<glm::vec3> p, std::initializer_list<glm::vec3> q) {
    hsr::SceneBuilder builder;
    const std::vector<glm::vec3> a(p), b(q);
    builder.add_polygon(a, {1, 0, 0}, "P");
    builder.add_polygon(b, {0, 1, 0}, "Q");
    return builder.build();
}

const char* const kRun[7] = {
    "test-1-depth-run",
    "test-2-x-run",
    "test-3-y-run",
    "test-4-p-behind-q-plane-run",
    "test-5-q-before-p-plane-run",
    "test-6-projections-run",
    "test-7-p-behind-q-where-overlapping-run",
};
const char* const kPassed[7] = {
    "test-1-depth-passed",
    "test-2-x-passed",
    "test-3-y-passed",
    "test-4-p-behind-q-plane-passed",
    "test-5-q-before-p-plane-passed",
    "test-6-projections-passed",
    "test-7-p-behind-q-where-overlapping-passed",
};

}  // namespace

TEST_CASE("painter: newell matches zbuffer on the cube, the monkey and the bunny", "[painter]") {
    const hsr::SceneData& cube = model("cube.obj");
    check_newell(cube, orbit(cube, 35, 25, 1, false, 128));
    check_newell(cube, orbit(cube, -20, 60, 1, true, 128));

    test_models::require_fetched();
    const hsr::SceneData& monkey = model("monkey.obj");
    check_newell(monkey, orbit(monkey, 0, 0, 1, false, 256));
    check_newell(monkey, orbit(monkey, 145, -30, 1.5f, true, 200));
    check_newell(monkey, orbit(monkey, 30, 20, 1, false, 200), {{"cull-backfaces", "true"}},
                 {{"cull-backfaces", "true"}});

    const hsr::SceneData& bunny = model("bunny.obj");
    check_newell(bunny, orbit(bunny, 0, 0, 1, false, 256));
    check_newell(bunny, orbit(bunny, 120, 35, 1.3f, true, 200));
}

TEST_CASE("painter: the intersecting boxes need splits and match zbuffer", "[painter]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    for (const bool ortho : {false, true}) {
        INFO((ortho ? "orthographic" : "perspective"));
        const Picture p = check_newell(boxes, orbit(boxes, 35, 25, 1, ortho, 256));
        CHECK(counter(p.frame, "splits") > 0);  // every pair of boxes interpenetrates
    }
    check_newell(boxes, orbit(boxes, -80, 60, 2.5f, false, 200));
    const glm::vec3 centre = 0.5f * (boxes.bounds_min + boxes.bounds_max);
    check_newell(boxes, look(centre + glm::vec3(0.1f, 0.05f, 3.0f), centre, 1e-2f, 20.0f, 200, 160));
}

TEST_CASE("painter: three cyclically overlapping polygons: naive is wrong, newell is right", "[painter]") {
    const hsr::SceneFile file = hsr::load_scene_file(test_models::path("three-polygons.scene"));
    const hsr::SceneData& s = file.scene;
    const hsr_camera camera = hsr::make_pixel_camera(256, 256, s.bounds_min.z, s.bounds_max.z);

    const Picture newell = check_newell(s, camera);
    CHECK(counter(newell.frame, "splits") > 0);  // red and green pierce one another

    // Sorted by farthest depth, naive paints red (from z = -20), then blue (z = 0), then green
    // (from z = 8), so green covers red everywhere they overlap. But red is nearer there on its
    // right: red's z = -20 + 40 (x - 20) / 216 is above 13.33 for x >= 200, while green's plane
    // reaches only z = 13.0 at (200, 80) in red's rows 40 <= y <= 80 (its z grows toward smaller x
    // and larger y). Green covers x in [200, 204] on all of those rows (its right edge, from
    // (228.3, 27.6) to (128.3, 243.6), is at x = 204 at y = 80). So at least the 4 x 40 = 160 pixel
    // centres of [200, 204] x [40, 80] show green where red is in front. The mid-depth key (red 0,
    // blue 0, green 18) paints in the same order.
    for (const char* key : {"farthest", "mid"}) {
        INFO("naive-key=" << key);
        const hsr::Frame naive = render("painter", s.view(), camera, {{"mode", "naive"}, {"naive-key", key}});
        const Comparison c = compare(naive, newell.reference, kPainter);
        CHECK(c.different >= 160);
        CHECK(c.covered == newell.comparison.covered);
        uint64_t green_over_red = 0;
        for (size_t p = 0; p < naive.face.size(); ++p)
            if (newell.reference.face[p] != HSR_NO_FACE && s.face_object[newell.reference.face[p]] == 0 &&
                naive.face[p] != HSR_NO_FACE && s.face_object[naive.face[p]] == 1)
                ++green_over_red;
        CHECK(green_over_red >= 160);
        CHECK(green_over_red == c.different);  // the only mistake is green over red
    }
}

TEST_CASE("painter: each of the seven tests decides a hand-made pair", "[painter]") {
    // P is face 0 and the farther (its farthest point is farther), so it is the head first; Q is
    // face 1. Each pair overlaps in depth (but the first) and in x and y extents up to the test
    // meant to decide. World units are 8 pixels; bins are 8 pixels, so both share a bin.
    struct Pair {
        const char* what;
        hsr::SceneData scene;
        int deciding;  // 0-based
    };
    std::vector<Pair> pairs;
    pairs.push_back({"depth extents disjoint",
                     two_triangles({{-2, -2, -10}, {2, -2, -10}, {0, 2, -10}}, {{-2, -2, -5}, {2, -2, -5}, {0, 2, -5}}),
                     0});
    pairs.push_back({"x extents disjoint",
                     two_triangles({{-3, -1, -10}, {0.1f, -1, -6}, {-2, 1, -8}}, {{0.6f, -1, -9}, {3, -1, -7}, {2, 1, -8}}),
                     1});
    pairs.push_back({"y extents disjoint",
                     two_triangles({{-1, -3, -10}, {-1, 0.1f, -6}, {1, -2, -8}}, {{-1, 0.6f, -9}, {-1, 3, -7}, {1, 2, -8}}),
                     2});
    // Q's plane is z = -7 + y / 2; every corner of P is below it.
    pairs.push_back({"P behind Q's plane",
                     two_triangles({{-1, -1, -9}, {1, -1, -9}, {0, 1, -7}}, {{-2, -2, -8}, {2, -2, -8}, {0, 2, -6}}),
                     3});
    // P's plane is z = -7 + y, Q above it; P's top corner (0, 3, -4) is above Q's plane.
    pairs.push_back({"Q in front of P's plane",
                     two_triangles({{-3, -3, -10}, {3, -3, -10}, {0, 3, -4}},
                                   {{-1, -1, -7.5f}, {1, -1, -7.5f}, {0, 0.5f, -6.2f}}),
                     4});
    // Planes z = -8 + x and z = -8 - x cross one another's triangles; the hypotenuses x + y = -0.2
    // and x + y = 0.2 keep the projections apart though their extents overlap.
    pairs.push_back({"projections disjoint",
                     two_triangles({{-2, -2, -10}, {1.8f, -2, -6.2f}, {-2, 1.8f, -10}},
                                   {{2, 2, -10}, {-1.8f, 2, -6.2f}, {2, -1.8f, -10}}),
                     5});
    // P (plane z = -8 + x, below x + y = 0) and Q (plane z = -6 - x) cross one another's planes,
    // which meet at x = 1, and their projections overlap in the triangle (-2, 0.5), (-2, 2),
    // (-0.96, 0.96). There x <= -0.5, so P's z <= -8.5 and Q's z >= -5.5: P is behind Q wherever
    // they overlap. Where the planes meet, P has y <= -1 and Q y >= 1.8: they do not touch.
    pairs.push_back({"P behind Q where the projections overlap",
                     two_triangles({{-3, -3, -11}, {3, -3, -5}, {-3, 3, -11}},
                                   {{-2, 0.5f, -4}, {2.5f, 2.5f, -8.5f}, {-2, 2.5f, -4}}),
                     6});
    for (const Pair& pair : pairs) {
        INFO(pair.what);
        const Picture p = check_newell(pair.scene, flat_camera());
        // P against Q once; then Q alone.
        for (int k = 0; k < 7; ++k) {
            INFO("test " << k + 1);
            CHECK(counter(p.frame, kRun[k]) == (k <= pair.deciding ? 1u : 0u));
            CHECK(counter(p.frame, kPassed[k]) == (k == pair.deciding ? 1u : 0u));
        }
        CHECK(counter(p.frame, "reorderings") == 0);
        CHECK(counter(p.frame, "splits") == 0);
        CHECK(counter(p.frame, "polygons-painted") == 2);
    }
}

TEST_CASE("painter: a polygon behind the farther one's near part is moved ahead of it", "[painter]") {
    // P (plane z = -7 + y) reaches farthest, but small Q lies behind P's upper part: all seven tests
    // fail for P against Q, Q moves ahead, and Q against P passes test 4 (Q behind P's plane).
    const hsr::SceneData scene =
        two_triangles({{-3, -3, -10}, {3, -3, -10}, {0, 3, -4}}, {{-0.5f, 1, -7.5f}, {0.5f, 1, -7.5f}, {0, 2, -7}});
    const Picture p = check_newell(scene, flat_camera());
    CHECK(counter(p.frame, "reorderings") == 1);
    CHECK(counter(p.frame, "splits") == 0);
    CHECK(counter(p.frame, "test-6-projections-run") == 1);
    CHECK(counter(p.frame, "test-6-projections-passed") == 0);
    CHECK(counter(p.frame, "test-7-p-behind-q-where-overlapping-run") == 1);
    CHECK(counter(p.frame, "test-7-p-behind-q-where-overlapping-passed") == 0);
    CHECK(counter(p.frame, "test-4-p-behind-q-plane-passed") == 1);

    // Two triangles piercing one another along y = 0 (planes z = -7 + y and z = -7 - y): a cycle,
    // broken by one split, made as soon as the pair is met.
    const hsr::SceneData pierced =
        two_triangles({{-2, -2, -9}, {2, -2, -9}, {0, 2, -5}}, {{-2, 2, -9}, {2, 2, -9}, {0, -2, -5}});
    const Picture q = check_newell(pierced, flat_camera(128));
    CHECK(counter(q.frame, "splits") == 1);
    CHECK(counter(q.frame, "polygons-painted") == 2 + counter(q.frame, "splits"));

    // A long thin triangle whose two long edges pass through a wide one: the thin one's chord in
    // the wide one's plane (z = -7) lies inside the wide one, while the wide one's chord in the
    // thin one's plane runs across all of it. Either cut is right; the picture must be.
    const hsr::SceneData skewer = two_triangles({{-3, -2, -7}, {3, -2, -7}, {0, 3, -7}},
                                                {{-0.3f, -3.5f, -10}, {0.3f, -3.5f, -10}, {0, 3.8f, -4}});
    const Picture r = check_newell(skewer, flat_camera(128));
    CHECK(counter(r.frame, "splits") >= 1);
}

TEST_CASE("painter: a chord's length outside a polygon and planes apart over an overlap", "[painter]") {
    using painter::farther_over;
    using painter::length_outside;
    // The segment from (0, 0) to (10, 0) against the square [2, 5] x [-1, 1], either orientation.
    const glm::dvec2 square[] = {{2, -1}, {5, -1}, {5, 1}, {2, 1}};
    const glm::dvec2 square_clockwise[] = {{2, -1}, {2, 1}, {5, 1}, {5, -1}};
    CHECK(length_outside({0, 0}, {10, 0}, square, 4) == Approx(7.0));
    CHECK(length_outside({0, 0}, {10, 0}, square_clockwise, 4) == Approx(7.0));
    CHECK(length_outside({10, 0}, {3, 0}, square, 4) == Approx(5.0));
    CHECK(length_outside({3, 0.5}, {4, -0.5}, square, 4) == Approx(0.0).margin(1e-12));
    CHECK(length_outside({0, 2}, {10, 2}, square, 4) == Approx(10.0));
    // NDC planes (oriented as Polygon::plane): z = 0.5, and z = 0.2 + 0.1 X or z = 0.45 + 0.1 X,
    // in a 100 x 100 image (X = x / 50 - 1).
    const glm::dvec4 flat(0, 0, -1, 0.5), low(0.1, 0, -1, 0.2), high(0.1, 0, -1, 0.45);
    const glm::dvec2 image[] = {{0, 0}, {100, 0}, {100, 100}, {0, 100}};
    const glm::dvec2 left_half[] = {{0, 0}, {50, 0}, {50, 100}, {0, 100}};
    CHECK(farther_over(flat, low, image, 4, 100, 100));        // 0.5 > 0.2 + 0.1 X for X <= 1
    CHECK_FALSE(farther_over(low, flat, image, 4, 100, 100));  // the other way round
    CHECK_FALSE(farther_over(flat, high, image, 4, 100, 100)); // at X = 1, 0.55 > 0.5
    CHECK(farther_over(flat, high, left_half, 4, 100, 100));   // X <= 0: 0.45 < 0.5
    // Where the gap closes to nothing at a corner, there is no room to spare: not decided.
    const glm::dvec4 touching(0.1, 0, -1, 0.5);  // z = 0.5 + 0.1 X, equal to `flat` at X = 0
    const glm::dvec2 left_of_middle[] = {{0, 0}, {50, 0}, {0, 100}};
    CHECK_FALSE(farther_over(flat, touching, left_of_middle, 3, 100, 100));
    CHECK_FALSE(farther_over(flat, low, image, 2, 100, 100));  // fewer than 3 corners: no overlap
}

TEST_CASE("painter: clip planes cut the polygons before they are sorted", "[painter]") {
    test_models::require_fetched();
    for (const char* file : {"monkey.obj", "boxes.scene"}) {
        INFO(file);
        const hsr::SceneData& data = model(file);
        const glm::vec3 centre = 0.5f * (data.bounds_min + data.bounds_max);
        hsr_camera camera = orbit(data, 30, 20, 1.2f, false, 200);
        // Keep x >= centre.x - 0.1, then also z <= centre.z + 0.2 (a corner cut away).
        camera.clip_plane_count = 1;
        const float planes[2][4] = {{1, 0, 0, -(centre.x - 0.1f)}, {0.3f, 0, -1, centre.z + 0.2f}};
        std::copy_n(planes[0], 4, camera.clip_planes[0]);
        check_newell(data, camera);
        camera.clip_plane_count = 2;
        std::copy_n(planes[1], 4, camera.clip_planes[1]);
        check_newell(data, camera);
        hsr_camera ortho = orbit(data, 30, 20, 1.2f, true, 200);
        ortho.clip_plane_count = 2;
        std::copy_n(&planes[0][0], 8, &ortho.clip_planes[0][0]);
        check_newell(data, ortho);
    }
}

TEST_CASE("painter: steps run to the end give the render, each step the sort, a paint, move or split", "[painter]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr::SceneFile three = hsr::load_scene_file(test_models::path("three-polygons.scene"));
    const hsr_camera three_camera =
        hsr::make_pixel_camera(256, 256, three.scene.bounds_min.z, three.scene.bounds_max.z);
    struct Case {
        const hsr_scene scene;
        hsr_camera camera;
        Settings settings;
    };
    const Case cases[] = {{boxes.view(), orbit(boxes, 35, 25, 1, false, 160), {}},
                          {three.scene.view(), three_camera, {}},
                          {three.scene.view(), three_camera, {{"mode", "naive"}}}};
    for (const Case& c : cases) {
        hsr::HiddenSurfaceRemover remover(plugin("painter"), c.settings);
        const hsr::Frame plain = render(remover, c.scene, c.camera, true);
        hsr::Frame stepped;
        hsr::resolve_visibility_steps(c.scene, c.camera, remover, stepped, 0, true);
        REQUIRE(stepped.steps.has_value());
        CHECK(stepped.depth == plain.depth);
        CHECK(stepped.face == plain.face);
        CHECK(stepped.bary == plain.bary);
        CHECK(stepped.instance == plain.instance);
        CHECK(stepped.depth_tests == plain.depth_tests);
        // One step for the sort, then one per paint, move and split.
        CHECK(stepped.steps->taken ==
              1 + counter(plain, "polygons-painted") + plain.counter("reorderings") + plain.counter("splits"));
        // depth_tests counts paints: the per-pixel counts add up to the pixels painted.
        CHECK(std::accumulate(plain.depth_tests.begin(), plain.depth_tests.end(), uint64_t(0)) ==
              counter(plain, "pixels-painted"));

        // Stopped after step k, the buffer holds the paints of the first k steps: as many painted
        // pixels as the per-pixel counts say, never fewer than after an earlier stop.
        uint64_t previous = 0;
        for (const uint64_t k : {uint64_t(1), stepped.steps->taken / 3, stepped.steps->taken / 2}) {
            hsr::Frame partial;
            hsr::resolve_visibility_steps(c.scene, c.camera, remover, partial, std::max<uint64_t>(k, 1), true);
            const uint64_t painted = std::accumulate(partial.depth_tests.begin(), partial.depth_tests.end(), uint64_t(0));
            CHECK(painted >= previous);
            CHECK(painted <= counter(plain, "pixels-painted"));
            previous = painted;
        }
    }
}

TEST_CASE("painter: more polygons than max-polygons is refused with one line", "[painter]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_camera camera = orbit(boxes, 35, 25, 1, false, 128);
    // 36 triangles fit; the splits the boxes need do not fit in 36 polygons.
    CHECK_NOTHROW(render("painter", boxes.view(), camera, {{"max-polygons", "36"}, {"mode", "naive"}}));
    for (const char* limit : {"10", "36"}) {
        INFO("max-polygons=" << limit);
        try {
            render("painter", boxes.view(), camera, {{"max-polygons", limit}});
            FAIL("no refusal");
        } catch (const std::exception& e) {
            const std::string message = e.what();
            CHECK_THAT(message, Catch::Contains(std::string("painter: the frame needs more than max-polygons=") +
                                                limit + " polygons (counting split pieces)"));
            CHECK(message.find('\n') == std::string::npos);
        }
    }
}

TEST_CASE("painter: random triangles passing through one another match zbuffer", "[painter]") {
    // Many pairs pierce one another: cycles everywhere, each broken by a cut.
    const hsr::SceneData scene = hsr::make_random_triangles(300, 3);
    for (const bool ortho : {false, true}) {
        INFO((ortho ? "orthographic" : "perspective"));
        const Picture p = check_newell(scene, orbit(scene, 20, 10, 1, ortho, 160));
        CHECK(counter(p.frame, "splits") > 100);
    }
}

TEST_CASE("painter: more moves than max-reorderings is refused with one line", "[painter]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_camera camera = orbit(boxes, 35, 25, 1, false, 128);
    const hsr::Frame free = render("painter", boxes.view(), camera);
    const uint64_t moves = counter(free, "reorderings");
    REQUIRE(moves > 1);
    CHECK_NOTHROW(render("painter", boxes.view(), camera, {{"max-reorderings", std::to_string(moves)}}));
    const std::string limit = std::to_string(moves - 1);
    try {
        render("painter", boxes.view(), camera, {{"max-reorderings", limit}});
        FAIL("no refusal");
    } catch (const std::exception& e) {
        const std::string message = e.what();
        CHECK_THAT(message, Catch::Contains("painter: the depth sort needs more than max-reorderings=" + limit +
                                            " moves of a polygon ahead"));
        CHECK(message.find('\n') == std::string::npos);
    }
}

TEST_CASE("painter: projections that touch overlap, planes through shared corners", "[painter]") {
    using painter::projections_disjoint;
    const glm::dvec2 a[] = {{0, 0}, {4, 0}, {0, 4}};
    const glm::dvec2 touching[] = {{4, 0}, {4, 4}, {0, 4}};  // shares the hypotenuse
    const glm::dvec2 apart[] = {{4.1, 0.1}, {4.1, 4.1}, {0.1, 4.1}};
    const glm::dvec2 crossing[] = {{1, 1}, {5, 1}, {5, 5}};
    CHECK_FALSE(projections_disjoint(a, 3, touching, 3));
    CHECK(projections_disjoint(a, 3, apart, 3));
    CHECK_FALSE(projections_disjoint(a, 3, crossing, 3));
    // The bounding boxes of `a` and `apart` overlap: only an edge normal separates them.
    // A plane through three corners: its own corners and a shared edge's lie on it.
    const glm::dvec4 p0(0.3, -0.2, 0.4, 1.0), p1(0.5, 0.1, 0.6, 1.2), p2(-0.1, 0.4, 0.2, 0.9);
    const glm::dvec4 plane = painter::oriented_plane(p0, p1, p2);
    CHECK(plane.z < 0.0);
    const painter::ClipVertex corners[] = {{p0, {0, 0}}, {p1, {1, 0}}, {p2, {0, 1}}};
    const painter::Sides s = painter::sides_of(plane, corners, 3);
    CHECK(s.all_near);
    CHECK(s.all_far);
    // A point nearer the viewer (smaller NDC z at the same x, y) is on the positive side.
    const glm::dvec4 mid = (p0 + p1 + p2) / 3.0;
    CHECK(glm::dot(plane, mid - glm::dvec4(0, 0, 0.01, 0)) > 0.0);
}

TEST_CASE("painter: every placement of an instanced scene is painted", "[painter]") {
    // A 3 x 2 x 3 grid of turned cubes, stored once: faces and instances as zbuffer's.
    const hsr::SceneData& cube = model("cube.obj");
    const hsr::SceneData grid = hsr::make_instance_grid(cube, {3, 2, 3, 0.3f, 25.0f});
    REQUIRE(grid.instances.size() == 18);
    for (const bool ortho : {false, true}) {
        INFO((ortho ? "orthographic" : "perspective"));
        const hsr_camera camera = orbit(grid, 30, 20, 1, ortho, 160);
        const Picture p = check_newell(grid, camera);
        const hsr::Frame& frame = p.frame;
        std::vector<bool> seen(grid.instances.size(), false);
        for (size_t p = 0; p < frame.face.size(); ++p)
            if (frame.face[p] != HSR_NO_FACE) seen.at(frame.instance[p]) = true;
        CHECK(std::count(seen.begin(), seen.end(), true) >= 6);  // at least the front layer shows
    }
}
