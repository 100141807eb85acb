// Instanced scenes (ABI 1.1) and the framework pieces around them, each checked against an answer
// computed another way: instance grids against the plain triangles flatten_instances() copies out,
// depth complexity against hand-counted overlaps, and the ABI policy against a plugin frozen at 1.0.
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

const hsr::Plugin& plugin(hsr_plugin_kind kind, const std::string& name) {
    static const hsr::PluginRegistry registry = [] {
        hsr::PluginRegistry r;
        r.scan_directory(HSR_PLUGIN_DIR);
        return r;
    }();
    return registry.find(kind, name);
}

hsr::SceneData cube() { return hsr::load_model(std::string(HSR_MODELS_DIR) + "/cube.obj"); }

hsr::SceneData small_grid() {
    return hsr::make_instance_grid(cube(), {3, 2, 4, 0.5f, 40.0f});
}

hsr_camera camera_for(const hsr::SceneData& scene, uint32_t size, float yaw, float pitch) {
    hsr::CameraSettings settings;
    settings.width = settings.height = size;
    settings.yaw_degrees = yaw;
    settings.pitch_degrees = pitch;
    return hsr::make_orbit_camera(scene.bounds_min, scene.bounds_max, settings);
}

// An axis-aligned square [x0, x1] x [y0, y1] at height z, facing the pixel camera (+z).
void add_square(hsr::SceneBuilder& builder, float x0, float y0, float x1, float y1, float z) {
    const glm::vec3 corners[] = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
    builder.add_polygon(corners, glm::vec3(0.5f));
}

}  // namespace

TEST_CASE("an instance grid stores the mesh once and places it on the grid", "[instancing]") {
    const hsr::SceneData model = cube();
    const hsr::SceneData grid = hsr::make_instance_grid(model, {3, 2, 4, 0.5f, 0.0f});
    CHECK(grid.triangle_count() == model.triangle_count());
    CHECK(grid.vertex_count() == model.vertex_count());
    REQUIRE(grid.instances.size() == 24);
    // The cube spans [-1, 1]^3 (2 units), so a gap of 0.5 * 2 makes a step of 3 units on every axis.
    const glm::vec3 extent = model.bounds_max - model.bounds_min;
    REQUIRE(extent.x == Approx(2.0f));
    const hsr_instance& first = grid.instances.front();
    const hsr_instance& last = grid.instances.back();
    CHECK(first.bounds_min[0] == Approx(-4.0f));  // column 0 of 3 is centred at -3
    CHECK(first.bounds_max[2] == Approx(1.0f));   // layer 0 at z = 0
    CHECK(last.bounds_min[2] == Approx(-10.0f));  // layer 3 at z = -9
    CHECK(grid.bounds_min.z == Approx(-10.0f));
    CHECK(grid.bounds_max.y == Approx(2.5f));     // rows at y = -1.5 and 1.5
    for (const hsr_instance& i : grid.instances) {
        CHECK(i.struct_size == sizeof(hsr_instance));
        CHECK(i.scale == 1.0f);
        CHECK(i.triangle_count == model.triangle_count());
    }
    const hsr_scene view = grid.view();
    CHECK(view.instance_count == 24);
    CHECK(view.instances == grid.instances.data());
}

TEST_CASE("flatten_instances copies every instance out into world space", "[instancing]") {
    const hsr::SceneData grid = small_grid();
    const hsr::SceneData flat = hsr::flatten_instances(grid);
    REQUIRE(flat.instances.empty());
    REQUIRE(flat.triangle_count() == grid.triangle_count() * grid.instances.size());
    for (size_t k = 0; k < grid.instances.size(); ++k) {
        const hsr_instance& instance = grid.instances[k];
        for (uint32_t t = 0; t < grid.triangle_count(); ++t) {
            const uint32_t ft = uint32_t(k) * grid.triangle_count() + t;
            const uint32_t v = grid.indices[3 * t], fv = flat.indices[3 * ft];
            const glm::vec4 p(grid.positions[3 * v], grid.positions[3 * v + 1], grid.positions[3 * v + 2], 1.0f);
            glm::vec3 expected(0.0f);
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c) expected[r] += instance.transform[4 * c + r] * p[c];
            for (int r = 0; r < 3; ++r) CHECK(flat.positions[3 * fv + r] == Approx(expected[r]).margin(1e-5));
            const glm::vec3 n(flat.face_normals[3 * ft], flat.face_normals[3 * ft + 1], flat.face_normals[3 * ft + 2]);
            CHECK(glm::length(n) == Approx(1.0f).epsilon(1e-5));
            // Adjacency stays inside the copy of the same instance.
            for (int e = 0; e < 3; ++e) {
                const int32_t neighbour = flat.edge_neighbors[3 * ft + e];
                REQUIRE(neighbour >= 0);
                CHECK(uint32_t(neighbour) / grid.triangle_count() == k);
            }
        }
    }
}

TEST_CASE("zbuffer sees an instanced scene as it sees the same triangles copied out", "[instancing]") {
    const hsr::SceneData grid = small_grid();
    const hsr::SceneData flat = hsr::flatten_instances(grid);
    const hsr::Plugin& zbuffer = plugin(HSR_KIND_HIDDEN_SURFACE_REMOVER, "zbuffer");
    hsr::HiddenSurfaceRemover remover(zbuffer, {});
    const uint32_t triangles = grid.triangle_count();
    for (auto [yaw, pitch] : {std::pair{0.0f, 0.0f}, {35.0f, 20.0f}, {-60.0f, -10.0f}}) {
        const hsr_camera camera = camera_for(grid, 200, yaw, pitch);
        hsr::Frame instanced, copied;
        hsr::resolve_visibility(grid.view(), camera, remover, instanced);
        hsr::resolve_visibility(flat.view(), camera, remover, copied);
        REQUIRE(instanced.instance.size() == instanced.face.size());
        CHECK(copied.instance.empty());
        size_t covered = 0, differ = 0;
        for (size_t p = 0; p < instanced.face.size(); ++p) {
            const uint32_t a = instanced.face[p], b = copied.face[p];
            if (a == HSR_NO_FACE && b == HSR_NO_FACE) continue;
            ++covered;
            const uint32_t a_flat = a == HSR_NO_FACE ? HSR_NO_FACE : instanced.instance[p] * triangles + a;
            if (a_flat != b) ++differ;
        }
        INFO("yaw " << yaw << " pitch " << pitch << ": " << differ << " of " << covered << " pixels differ");
        CHECK(covered > 5000);
        // Transforming on the fly (double) and copying out (float) round differently: a few pixels
        // on silhouettes may flip, nothing more.
        CHECK(differ <= covered / 500);
    }
}

TEST_CASE("lighting an instanced scene matches lighting its copied-out triangles", "[instancing][lighting]") {
    const hsr::SceneData grid = small_grid();
    const hsr::SceneData flat = hsr::flatten_instances(grid);
    hsr::HiddenSurfaceRemover remover(plugin(HSR_KIND_HIDDEN_SURFACE_REMOVER, "zbuffer"), {});
    const hsr_camera camera = camera_for(grid, 160, 30.0f, 25.0f);
    const std::vector<hsr_light> lights = {
        hsr::resolve_light(hsr::parse_light_spec("point:2,3,4"), camera),
        hsr::resolve_light(hsr::parse_light_spec("dir:-0.5,0.6,1,intensity=0.7"), camera)};
    const hsr_shading_context context = hsr::make_shading_context(camera, lights);
    for (const char* interpolation : {"flat", "gouraud", "phong"}) {
        hsr::LightingModel lighting(plugin(HSR_KIND_LIGHTING_MODEL, "blinn-phong"),
                                    {{"interpolation", interpolation}});
        hsr::Frame a, b;
        hsr::resolve_visibility(grid.view(), camera, remover, a);
        hsr::resolve_visibility(flat.view(), camera, remover, b);
        hsr::shade_frame(grid.view(), lighting, context, {}, a);
        hsr::shade_frame(flat.view(), lighting, context, {}, b);
        size_t compared = 0, differ = 0;
        for (size_t p = 0; p < a.face.size(); ++p) {
            if (a.face[p] == HSR_NO_FACE || a.instance[p] * grid.triangle_count() + a.face[p] != b.face[p]) continue;
            ++compared;
            for (int c = 0; c < 3; ++c)
                if (std::abs(int(a.rgb[3 * p + c]) - int(b.rgb[3 * p + c])) > 2) {
                    ++differ;
                    break;
                }
        }
        INFO(interpolation << ": " << differ << " of " << compared << " pixels differ by more than 2/255");
        CHECK(compared > 5000);
        CHECK(differ == 0);
    }
}

TEST_CASE("a plugin frozen at ABI 1.0 gets instanced scenes copied out", "[instancing][abi]") {
    const std::vector<hsr::Plugin> plugins =
        hsr::load_plugin_library(std::string(HSR_TEST_PLUGIN_DIR) + "/frozen-1.0.so");
    REQUIRE(plugins.size() == 1);
    const hsr::Plugin& frozen = plugins[0];
    REQUIRE(frozen.descriptor.abi_minor == 0);
    const hsr::SceneData grid = small_grid();
    const hsr_scene view = grid.view();
    const hsr_camera camera = camera_for(grid, 32, 0.0f, 0.0f);
    hsr::HiddenSurfaceRemover remover(frozen, {});
    hsr::LightingModel lighting(plugin(HSR_KIND_LIGHTING_MODEL, "facecolor"), {});
    hsr::FrameSettings settings;
    settings.count_depth_tests = true;  // a 1.0 visibility buffer has no such array: must be harmless
    const hsr::Frame frame = hsr::render_frame(view, camera, remover, lighting,
                                               hsr::make_shading_context(camera, {}), settings);
    // The handmade plugin claims face 0 at every pixel: face 0 of the copied-out scene.
    CHECK(frame.instance.empty());
    for (uint32_t f : frame.face) REQUIRE(f == 0u);
    CHECK(frame.rgb[0] == 204);  // the cube's default colour 0.8, unlit

    hsr::Frame direct;
    CHECK_THROWS_WITH(hsr::resolve_visibility(view, camera, remover, direct),
                      Catch::Contains("ABI 1.0") && Catch::Contains("instances"));
}

TEST_CASE("depth complexity counts the surfaces over each pixel", "[depth-complexity]") {
    // Three squares in a pixel camera: A [0,8]^2, B [4,12]^2, C [6,10] x [0,16]. Pixel centres never
    // lie on their edges, so the count at a pixel is the number of squares holding its centre; each
    // square's diagonal does run through pixel centres, and the fill rule must give those to
    // exactly one of its two triangles.
    hsr::SceneBuilder builder;
    add_square(builder, 0, 0, 8, 8, 1);
    add_square(builder, 4, 4, 12, 12, 2);
    add_square(builder, 6, 0, 10, 16, 3);
    const hsr::SceneData scene = builder.build();
    const hsr_camera camera = hsr::make_pixel_camera(16, 16, 0.0f, 4.0f);
    const hsr::DepthComplexity dc = hsr::measure_depth_complexity(scene.view(), camera);
    auto inside = [](float x, float y, float x0, float y0, float x1, float y1) {
        return x > x0 && x < x1 && y > y0 && y < y1;
    };
    uint64_t fragments = 0, covered = 0;
    uint32_t max = 0;
    for (int row = 0; row < 16; ++row) {
        for (int column = 0; column < 16; ++column) {
            const float x = column + 0.5f, y = 15 - row + 0.5f;  // world y is up, image rows go down
            const uint32_t expected = inside(x, y, 0, 0, 8, 8) + inside(x, y, 4, 4, 12, 12) + inside(x, y, 6, 0, 10, 16);
            INFO("pixel (" << column << ", " << row << ")");
            REQUIRE(dc.count[size_t(row) * 16 + column] == expected);
            fragments += expected;
            covered += expected > 0;
            max = std::max(max, expected);
        }
    }
    CHECK(dc.fragments == fragments);
    CHECK(dc.covered_pixels == covered);
    CHECK(dc.max == 3u);
    CHECK(dc.mean_over_covered() == Approx(double(fragments) / double(covered)));
}

TEST_CASE("depth complexity of a deep grid grows with its layers", "[depth-complexity][instancing]") {
    const hsr::SceneData model = cube();
    double previous = 0.0;
    for (uint32_t layers : {1u, 4u, 8u}) {
        const hsr::SceneData grid = hsr::make_instance_grid(model, {2, 2, layers, 0.2f, 0.0f});
        hsr::CameraSettings settings;
        settings.width = settings.height = 96;
        settings.orthographic = true;
        const hsr_camera camera = hsr::make_orbit_camera(grid.bounds_min, grid.bounds_max, settings);
        const hsr::DepthComplexity dc = hsr::measure_depth_complexity(grid.view(), camera);
        // Seen along the layers in orthographic projection, every covered pixel lies in front of and
        // behind each cube of its column exactly once: two surfaces per layer.
        CHECK(dc.max == 2 * layers);
        CHECK(dc.mean_over_covered() == Approx(2.0 * layers));
        CHECK(dc.mean_over_covered() > previous);
        previous = dc.mean_over_covered();
    }
}
