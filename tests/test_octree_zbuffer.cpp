// The octree-zbuffer plugin (hierarchical z-buffer with object-space octrees, Greene, Kass & Miller
// 1993) against the plain zbuffer plugin, both loaded through the real ABI: the same face (and
// instance), bit for bit the same depth and barycentrics, at every pixel except exact depth ties, on
// real models, hand-made views with the eye inside the octree, and a deep instanced scene where it
// must cull. The octree itself is checked directly (its build code is compiled into this test).
#include "hsr/abi.h"
#include "hsr/camera.hpp"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/raster.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "surface_test_support.hpp"

#include "../plugins/hidden-surface/octree-zbuffer/octree.cpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <tbb/global_control.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <bit>
#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

namespace {

using namespace surface_tests;

const Agreement kOctree{.plugin = "octree-zbuffer", .label = "octree"};

// Counters that account for triangles the z-pyramid and the octree spared drawing.
constexpr std::initializer_list<const char*> kCulled = {"triangles-culled-by-pyramid", "triangles-in-culled-nodes"};

// Octree and zbuffer agree at every pixel but ties (fewer than 0.1 % of the covered pixels).
void check_same_picture(const hsr_scene& scene, const hsr_camera& camera, const Settings& octree_settings = {},
                        const Settings& zbuffer_settings = {}) {
    check_against_zbuffer(kOctree, scene, camera, octree_settings, zbuffer_settings);
}

}  // namespace

TEST_CASE("octree-zbuffer: the bunny from several views matches zbuffer", "[octree-zbuffer]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr_scene scene = bunny.view();
    check_same_picture(scene, orbit(bunny, 0, 0, 1, false, 384));
    check_same_picture(scene, orbit(bunny, 120, 35, 1.3f, false, 320));
    check_same_picture(scene, orbit(bunny, -60, -20, 1, true, 320));
    check_same_picture(scene, orbit(bunny, 200, 10, 4, false, 256));  // zoomed in: much off screen
    check_same_picture(scene, orbit(bunny, 30, 20, 1, false, 320), {{"cull-backfaces", "true"}},
                       {{"cull-backfaces", "true"}});
}

TEST_CASE("octree-zbuffer: the eye inside the octree's bounds", "[octree-zbuffer]") {
    // Boxes behind the eye and boxes crossing the near plane must be drawn (clipped), not culled.
    for (const char* file : {"bunny.obj", "monkey.obj"}) {
        const hsr::SceneData& data = model(file);
        const hsr_scene scene = data.view();
        const glm::vec3 lo = data.bounds_min, hi = data.bounds_max, centre = 0.5f * (lo + hi);
        const float size = glm::length(hi - lo);
        INFO(file);
        // At the centre (inside the mesh), looking out in several directions.
        check_same_picture(scene, look(centre, centre + glm::vec3(0, 0, 1), 1e-3f * size, 4 * size, 256, 256));
        check_same_picture(scene, look(centre, centre + glm::vec3(1, 0.3f, -0.5f), 1e-3f * size, 4 * size, 256, 256));
        // Just inside a corner of the bounds, looking across the model.
        const glm::vec3 corner = lo + 0.15f * (hi - lo);
        check_same_picture(scene, look(corner, centre, 1e-3f * size, 4 * size, 256, 192, 90.0f));
        const glm::vec3 upper = hi - glm::vec3(0.1f, 0.05f, 0.3f) * (hi - lo);
        check_same_picture(scene, look(upper, lo, 1e-2f * size, 4 * size, 200, 256, 60.0f));
    }
}

TEST_CASE("octree-zbuffer: a box reaching behind the eye is judged by all of it", "[octree-zbuffer]") {
    // A floor running from behind the eye far ahead, and a wall across it further on, drawn first
    // (it is nearer along the axis the placements are ordered by). The part of the floor's box in
    // front of the eye projects behind the wall, but the floor near the eye is in plain view.
    hsr::SceneBuilder builder;
    const glm::vec3 floor[] = {{-10, -1, 5}, {10, -1, 5}, {10, -1, -50}, {-10, -1, -50}};
    const glm::vec3 wall[] = {{-10, -1, -20}, {10, -1, -20}, {10, 0, -20}, {-10, 0, -20}};
    builder.add_polygon(floor, {0.5f, 0.5f, 0.5f}, "floor");
    builder.add_polygon(wall, {0.8f, 0.2f, 0.2f}, "wall");
    hsr::SceneData scene = builder.build();
    const hsr_camera camera = look({0, 0, 0}, {0, -0.2f, -1}, 0.05f, 100.0f, 256, 256, 60.0f);
    check_same_picture(scene.view(), camera, {{"leaf-triangles", "1"}});
    // The same two objects as instances (each its own octree, under the placement hierarchy).
    for (uint32_t object = 0; object < 2; ++object) {
        uint32_t first = scene.triangle_count(), last = 0, lo_v = scene.vertex_count(), hi_v = 0;
        glm::vec3 lo(1e30f), hi(-1e30f);
        for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
            if (scene.face_object[t] != object) continue;
            first = std::min(first, t);
            last = std::max(last, t);
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = scene.indices[3 * t + k];
                lo_v = std::min(lo_v, v);
                hi_v = std::max(hi_v, v);
                const glm::vec3 p(scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]);
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
        }
        scene.instances.push_back(hsr::make_instance(first, last - first + 1, lo_v, hi_v - lo_v + 1, glm::mat3(1.0f),
                                                     1.0f, glm::vec3(0.0f), lo, hi));
    }
    check_same_picture(scene.view(), camera);
    const hsr::Frame frame = render("octree-zbuffer", scene.view(), camera);
    CHECK(counter(frame, "triangles-in-culled-nodes") == 0);
}

TEST_CASE("octree-zbuffer: the monkey and the intersecting boxes match zbuffer", "[octree-zbuffer]") {
    const hsr::SceneData& monkey = model("monkey.obj");
    check_same_picture(monkey.view(), orbit(monkey, 0, 0, 1, false, 320));
    check_same_picture(monkey.view(), orbit(monkey, 145, -30, 1.5f, true, 256));

    const hsr::SceneData& boxes = model("boxes.scene");
    check_same_picture(boxes.view(), orbit(boxes, 35, 25, 1, false, 320));
    check_same_picture(boxes.view(), orbit(boxes, -80, 60, 2.5f, false, 256));
    // Small octree cells: each box's 12 triangles end up in several leaves.
    check_same_picture(boxes.view(), orbit(boxes, 35, 25, 1, true, 256), {{"leaf-triangles", "1"}});
    const glm::vec3 centre = 0.5f * (boxes.bounds_min + boxes.bounds_max);
    check_same_picture(boxes.view(), look(centre + glm::vec3(0.1f, 0.05f, 0.02f), centre + glm::vec3(1, 0.2f, 0.4f),
                                          1e-3f, 20.0f, 256, 256),
                       {{"leaf-triangles", "2"}});
}

TEST_CASE("octree-zbuffer: build parameters shape the octree, not the picture", "[octree-zbuffer]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr_scene scene = bunny.view();
    const hsr_camera camera = orbit(bunny, 20, 10, 1, false, 256);
    const hsr::Frame reference = render("zbuffer", scene, camera);
    uint64_t previous_nodes = 0;
    for (const char* leaf : {"4096", "256", "16"}) {
        const hsr::Frame frame = render("octree-zbuffer", scene, camera, {{"leaf-triangles", leaf}});
        const Comparison c = compare(frame, reference, kOctree);
        INFO("leaf-triangles=" << leaf << " " << c.first_difference);
        CHECK(c.different == 0);
        const uint64_t nodes = counter(frame, "octree-nodes");
        CHECK(nodes > previous_nodes);  // smaller leaves, more nodes
        previous_nodes = nodes;
        check_triangle_accounting(frame, kCulled);
    }
    const hsr::Frame flat = render("octree-zbuffer", scene, camera, {{"max-depth", "0"}});
    CHECK(counter(flat, "octree-nodes") == 1);
    CHECK(compare(flat, reference, kOctree).different == 0);
    const hsr::Frame shallow = render("octree-zbuffer", scene, camera, {{"max-depth", "2"}, {"leaf-triangles", "1"}});
    CHECK(counter(shallow, "octree-nodes") <= 1 + 8 + 64);
    CHECK(compare(shallow, reference, kOctree).different == 0);
}

TEST_CASE("octree-zbuffer: every triangle in exactly one leaf, leaves list the exact vertex copies they use",
          "[octree-zbuffer]") {
    using namespace octree_zbuffer;
    for (const char* file : {"bunny.obj", "boxes.scene"}) {
        const hsr::SceneData& data = model(file);
        const hsr_scene scene = data.view();
        for (const BuildParams params : {BuildParams{8, 64}, BuildParams{3, 1}, BuildParams{12, 7}}) {
            INFO(file << " max-depth " << params.max_depth << " leaf-triangles " << params.leaf_triangles);
            OctreeForest forest;
            const uint32_t index = forest.add_object(scene, 0, scene.triangle_count, 0, scene.vertex_count, params);
            const ObjectTree& object = forest.objects.at(index);
            REQUIRE(object.has_root);
            CHECK(object.non_finite == 0);
            CHECK(object.depth <= params.max_depth);
            std::vector<int> seen(scene.triangle_count, 0);
            std::vector<uint32_t> copy_of(scene.vertex_count, ~0u);  // one copy per scene vertex
            uint64_t problems = 0;
            // Walk from the root: children's triangle ranges partition their parent's, boxes nest.
            std::vector<uint32_t> stack{object.root};
            while (!stack.empty()) {
                const OctreeNode& node = forest.nodes.at(stack.back());
                stack.pop_back();
                if (node.is_leaf()) {
                    if (node.triangle_count > params.leaf_triangles && node.depth < params.max_depth) ++problems;
                    // The leaf's vertex list: each vertex once, each used by one of its triangles.
                    REQUIRE(size_t(node.first_vertex) + node.vertex_count <= forest.mesh.leaf_vertices.size());
                    std::vector<uint32_t> listed(forest.mesh.leaf_vertices.begin() + node.first_vertex,
                                                 forest.mesh.leaf_vertices.begin() + node.first_vertex + node.vertex_count);
                    std::vector<uint32_t> used;
                    for (uint32_t t = node.first_triangle; t < node.first_triangle + node.triangle_count; ++t)
                        for (int k = 0; k < 3; ++k) used.push_back(forest.mesh.indices.at(3 * t + k));
                    std::sort(listed.begin(), listed.end());
                    std::sort(used.begin(), used.end());
                    used.erase(std::unique(used.begin(), used.end()), used.end());
                    if (listed != used) ++problems;
                    for (uint32_t t = node.first_triangle; t < node.first_triangle + node.triangle_count; ++t) {
                        const uint32_t face = forest.mesh.face.at(t);
                        ++seen.at(face);
                        for (int k = 0; k < 3; ++k) {
                            const uint32_t copy = forest.mesh.indices.at(3 * t + k);
                            const uint32_t original = scene.indices[3 * face + k];
                            if (copy_of.at(original) == ~0u) copy_of[original] = copy;
                            if (copy_of[original] != copy) ++problems;
                            for (int a = 0; a < 3; ++a) {
                                const float v = forest.mesh.positions.at(3 * copy + a);
                                if (std::memcmp(&v, &scene.positions[3 * original + a], sizeof v) != 0) ++problems;
                                if (!(v >= node.lo[a] && v <= node.hi[a])) ++problems;
                            }
                        }
                    }
                    continue;
                }
                uint32_t next = node.first_triangle;
                const int children = std::popcount(node.child_mask);
                if (children < 2) ++problems;  // levels that split nothing are skipped
                for (int c = 0; c < children; ++c) {
                    const OctreeNode& child = forest.nodes.at(node.first_child + c);
                    if (child.first_triangle != next || child.depth <= node.depth) ++problems;
                    for (int a = 0; a < 3; ++a)
                        if (child.lo[a] < node.lo[a] || child.hi[a] > node.hi[a]) ++problems;
                    next += child.triangle_count;
                    stack.push_back(node.first_child + c);
                }
                if (next != node.first_triangle + node.triangle_count) ++problems;
            }
            CHECK(problems == 0);
            CHECK(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
            CHECK(forest.mesh.face.size() == scene.triangle_count);
            const auto copied = std::count_if(copy_of.begin(), copy_of.end(), [](uint32_t c) { return c != ~0u; });
            CHECK(size_t(copied) * 3 == forest.mesh.positions.size());
        }
    }
}

TEST_CASE("octree-zbuffer: leaf planes tell front faces from back faces as the rasterizer does", "[octree-zbuffer]") {
    // The plugin draws a leaf's back faces, and leaves with no front face, after the rest of their
    // placement, judging facing in object space from LeafMesh::planes. A wrong sign would not change
    // the picture, only the cost, so it is checked here against the clip-space test of hsr/raster.hpp,
    // under a plain, a mirrored and a sheared placement transform, in perspective and orthographic.
    using namespace octree_zbuffer;
    const hsr::SceneData& data = model("bunny.obj");
    const hsr_scene scene = data.view();
    OctreeForest forest;
    forest.add_object(scene, 0, scene.triangle_count, 0, scene.vertex_count, BuildParams{8, 64});
    REQUIRE(forest.mesh.planes.size() == forest.mesh.face.size());
    const glm::dmat4 mirrored = glm::scale(glm::dmat4(1.0), glm::dvec3(-1.0, 1.0, 1.0));
    const glm::dmat4 sheared(glm::dvec4(1, 0, 0, 0), glm::dvec4(0.4, 0.8, 0, 0), glm::dvec4(0, 0.3, 1.5, 0),
                             glm::dvec4(0.1, 0, 0, 1));
    const glm::dmat4 transforms[] = {glm::dmat4(1.0), mirrored, sheared};
    for (const bool ortho : {false, true}) {
        for (int k = 0; k < 3; ++k) {
            INFO((ortho ? "orthographic" : "perspective") << ", transform " << k);
            const hsr_camera camera = orbit(data, 35, 20, 1, ortho, 256);
            const glm::dmat4 view(hsr::sdk::load_matrix(camera.view));
            const glm::dmat4 view_projection(hsr::sdk::load_matrix(camera.view_projection));
            const glm::dmat4 clip_from_object = view_projection * transforms[k];
            const glm::dmat4 object_from_world = glm::inverse(transforms[k]);
            const double mirror = glm::determinant(glm::dmat3(transforms[k])) < 0.0 ? -1.0 : 1.0;
            const glm::dvec4 viewer =
                mirror * (ortho ? object_from_world * glm::dvec4(view[0][2], view[1][2], view[2][2], 0.0)
                                : object_from_world * glm::inverse(view)[3]);
            size_t front = 0, disagree = 0;
            for (size_t t = 0; t < forest.mesh.face.size(); ++t) {
                glm::dvec4 clip[3];
                for (int c = 0; c < 3; ++c) {
                    const float* p = &forest.mesh.positions[3 * size_t(forest.mesh.indices[3 * t + c])];
                    clip[c] = clip_from_object * glm::dvec4(p[0], p[1], p[2], 1.0);
                }
                const bool rasterizer = hsr::raster::is_front_facing(clip[0], clip[1], clip[2]);
                const bool plane = glm::dot(glm::dvec4(forest.mesh.planes[t]), viewer) > 0.0;
                front += rasterizer;
                disagree += rasterizer != plane;
            }
            INFO(front << " front faces, " << disagree << " judged otherwise by the planes");
            CHECK(front > forest.mesh.face.size() / 4);
            CHECK(front < 3 * forest.mesh.face.size() / 4);
            CHECK(disagree * 1000 < forest.mesh.face.size());  // only triangles seen edge-on
        }
    }
}

TEST_CASE("octree-zbuffer: built once, reused, rebuilt for another scene", "[octree-zbuffer]") {
    const hsr::SceneData& bunny = model("bunny.obj");
    const hsr::SceneData& monkey = model("monkey.obj");
    hsr::HiddenSurfaceRemover octree(plugin("octree-zbuffer"), {});
    const hsr_camera camera = orbit(bunny, 10, 10, 1, false, 200);
    const hsr::Frame first = render(octree, bunny.view(), camera, true);
    const hsr::Frame second = render(octree, bunny.view(), camera, true);
    CHECK(counter(first, "build-time-us") > 0);
    CHECK(counter(second, "build-time-us") == 0);
    CHECK(second.face == first.face);
    CHECK(second.depth == first.depth);
    // depth_tests counts every comparison the counter reports.
    uint64_t sum = 0;
    for (uint32_t n : second.depth_tests) sum += n;
    CHECK(sum == counter(second, "pixels-depth-tested"));
    check_triangle_accounting(second, kCulled);

    // Another scene through the same instance: rebuilt, and right.
    const hsr_camera monkey_camera = orbit(monkey, -30, 15, 1, false, 200);
    const hsr::Frame other = render(octree, monkey.view(), monkey_camera);
    CHECK(counter(other, "build-time-us") > 0);
    CHECK(compare(other, render("zbuffer", monkey.view(), monkey_camera), kOctree).different == 0);
    // A copy of the bunny at another address is recognised as another scene, too.
    const hsr::SceneData copy = bunny;
    const hsr::Frame again = render(octree, copy.view(), camera);
    CHECK(counter(again, "octree-nodes") == counter(first, "octree-nodes"));
    CHECK(again.face == first.face);
}

TEST_CASE("octree-zbuffer: instances, including one moved between frames", "[octree-zbuffer]") {
    // A small grid where instances overlap on screen, jittered so that their octrees turn.
    hsr::SceneData grid = hsr::make_instance_grid(model("monkey.obj"), {3, 2, 4, 0.0f, 40.0f});
    const hsr_camera camera = orbit(grid, 25, 15, 1, false, 256);
    check_same_picture(grid.view(), camera);
    check_same_picture(grid.view(), orbit(grid, 0, 0, 1, true, 256));

    check_same_picture(grid.view(), camera, {{"cull-backfaces", "true"}, {"leaf-triangles", "16"}},
                       {{"cull-backfaces", "true"}});
    // The eye among the instances: boxes of the placement hierarchy and of the octrees reach
    // behind it and through the near plane.
    const glm::vec3 lo = grid.bounds_min, hi = grid.bounds_max, middle = 0.5f * (lo + hi);
    const float size = glm::length(hi - lo);
    check_same_picture(grid.view(), look(middle, middle - glm::vec3(0.2f, 0.1f, 1.0f), 1e-3f * size, 2 * size, 256, 256));
    check_same_picture(grid.view(), look(glm::vec3(middle.x, middle.y, hi.z - 0.05f * (hi.z - lo.z)),
                                         glm::vec3(lo.x, lo.y, lo.z), 1e-2f * size, 2 * size, 240, 200, 100.0f));

    hsr::HiddenSurfaceRemover octree(plugin("octree-zbuffer"), {});
    (void)render(octree, grid.view(), camera);
    // Move one instance in place (same arrays, same counts): the plugin must notice.
    hsr_instance& moved = grid.instances.at(5);
    moved.transform[12] += 0.7f;
    moved.transform[13] += 0.3f;
    for (int a = 0; a < 2; ++a) {
        moved.bounds_min[a] += a == 0 ? 0.7f : 0.3f;
        moved.bounds_max[a] += a == 0 ? 0.7f : 0.3f;
    }
    const hsr::Frame after = render(octree, grid.view(), camera);
    CHECK(counter(after, "build-time-us") > 0);
    const Comparison c = compare(after, render("zbuffer", grid.view(), camera), kOctree);
    INFO(c.first_difference);
    CHECK(c.different == 0);
}

TEST_CASE("octree-zbuffer: a deep scene is culled, not drawn", "[octree-zbuffer][deep]") {
    // As models/deep-monkeys.scene: 6 x 4 x 20 monkeys receding from the camera.
    const hsr::SceneData deep = hsr::make_instance_grid(model("monkey.obj"), {6, 4, 20, 0.05f, 25.0f});
    REQUIRE(deep.instances.size() == 480);
    const hsr_scene scene = deep.view();
    const hsr_camera camera = orbit(deep, 0, 0, 3.2f, false, 512);
    const hsr::Frame reference = render("zbuffer", scene, camera);
    const hsr::Frame octree = render("octree-zbuffer", scene, camera);
    const Comparison c = compare(octree, reference, kOctree);
    INFO(c.first_difference);
    CHECK(c.different == 0);
    CHECK(double(c.ties) < 0.001 * double(c.covered));
    check_triangle_accounting(octree, kCulled);

    CHECK(counter(octree, "octree-nodes-culled") + counter(octree, "instance-nodes-culled") > 0);
    CHECK(counter(octree, "triangles-in-culled-nodes") > counter(octree, "triangles-in") / 2);
    CHECK(counter(octree, "octree-leaves-deferred") > 0);  // leaves facing away, drawn after their placement's front
    const uint64_t octree_tests = counter(octree, "pixels-depth-tested");
    const uint64_t zbuffer_tests = counter(reference, "pixels-depth-tested");
    INFO("depth tests: octree " << octree_tests << ", zbuffer " << zbuffer_tests);
    CHECK(octree_tests * 4 < zbuffer_tests);
}

TEST_CASE("octree-zbuffer: a deep scene of large triangles is culled block by block", "[octree-zbuffer][deep]") {
    // 4 x 4 x 12 cubes: a cube's faces cover thousands of pixels, so triangles are tested in 32 x 32
    // blocks, then 8 x 8 tiles; the hidden cubes' faces are rejected a block at a time.
    const hsr::SceneData deep = hsr::make_instance_grid(model("cube.obj"), {4, 4, 12, 0.05f, 25.0f});
    const hsr_scene scene = deep.view();
    const hsr_camera camera = orbit(deep, 0, 0, 2.5f, false, 512);
    const hsr::Frame reference = render("zbuffer", scene, camera);
    const hsr::Frame octree = render("octree-zbuffer", scene, camera, {{"leaf-triangles", "1"}});
    const Comparison c = compare(octree, reference, kOctree);
    INFO(c.first_difference);
    CHECK(c.different == 0);
    check_triangle_accounting(octree, kCulled);
    CHECK(counter(octree, "tiles-culled") > 0);
    const uint64_t octree_tests = counter(octree, "pixels-depth-tested");
    const uint64_t zbuffer_tests = counter(reference, "pixels-depth-tested");
    INFO("depth tests: octree " << octree_tests << ", zbuffer " << zbuffer_tests);
    CHECK(octree_tests * 4 < zbuffer_tests);
}

TEST_CASE("octree-zbuffer: screen tiles give zbuffer's buffers, on one thread or two", "[octree-zbuffer][tiles]") {
    // Small tiles (64 pixels, and 40: not a power of two) cut the views below into many, drawn in
    // parallel, each with its own traversal and z-pyramid; none may show in the buffers.
    const hsr::SceneData deep = hsr::make_instance_grid(model("monkey.obj"), {6, 4, 8, 0.05f, 25.0f});
    const hsr::SceneData cubes = hsr::make_instance_grid(model("cube.obj"), {4, 4, 6, 0.05f, 25.0f});
    const hsr::SceneData& bunny = model("bunny.obj");
    const glm::vec3 centre = 0.5f * (bunny.bounds_min + bunny.bounds_max);
    const float size = glm::length(bunny.bounds_max - bunny.bounds_min);
    for (const int threads : {1, 2}) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        for (const char* tile : {"64", "40"}) {
            INFO(threads << " thread(s), tile-size " << tile);
            check_same_picture(deep.view(), orbit(deep, 0, 0, 3.2f, false, 300), {{"tile-size", tile}});
            check_same_picture(cubes.view(), orbit(cubes, 0, 0, 2.5f, false, 256),
                               {{"tile-size", tile}, {"leaf-triangles", "1"}});
            check_same_picture(bunny.view(), orbit(bunny, 200, 10, 4, false, 256), {{"tile-size", tile}});
            check_same_picture(bunny.view(), orbit(bunny, -60, -20, 1, true, 200), {{"tile-size", tile}});
            // The eye inside the model: boxes behind the eye and across the near plane.
            check_same_picture(bunny.view(),
                               look(centre, centre + glm::vec3(1, 0.3f, -0.5f), 1e-3f * size, 4 * size, 256, 192),
                               {{"tile-size", tile}});
        }
    }
}

TEST_CASE("octree-zbuffer: tiles count their own work, the same on any number of threads", "[octree-zbuffer][tiles]") {
    const hsr::SceneData deep = hsr::make_instance_grid(model("monkey.obj"), {6, 4, 8, 0.05f, 25.0f});
    const hsr_camera camera = orbit(deep, 0, 0, 3.2f, false, 300);
    auto frame_on = [&](int threads, const char* tile) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return render("octree-zbuffer", deep.view(), camera, {{"tile-size", tile}});
    };
    const hsr::Frame one = frame_on(1, "64"), two = frame_on(2, "64"), whole = frame_on(2, "0");
    for (const auto& [name, value] : one.counters)
        if (name != "build-time-us") CHECK(counter(two, name) == value);
    // A triangle reaching k tiles is counted in each: every triangle at least once.
    uint64_t accounted = counter(one, "triangles-backface-culled") + counter(one, "triangles-outside") +
                         counter(one, "triangles-degenerate") + counter(one, "triangles-rasterized");
    for (const char* name : kCulled) accounted += counter(one, name);
    CHECK(accounted >= counter(one, "triangles-in"));
    check_triangle_accounting(whole, kCulled);  // one tile: exactly once
    CHECK(counter(one, "pixels-written") >= counter(whole, "pixels-written") / 2);
    CHECK(counter(one, "octree-nodes-visited") > counter(whole, "octree-nodes-visited"));
}
