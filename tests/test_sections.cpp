// Sections (ABI 1.4 clip planes): the SDK's polygon clipping and splitting, every z-buffer plugin
// against a ray cast of the clipped scene, and the command line (--section, --clip-plane, --near,
// `clip-plane` and `section` in a .scene file).
#include "cli_support.hpp"
#include "ray_reference.hpp"
#include "surface_test_support.hpp"

#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace raster = hsr::raster;
using surface_tests::model;
using surface_tests::orbit;
using surface_tests::render;

void add_clip_plane(hsr_camera& camera, glm::vec4 plane) {
    REQUIRE(camera.clip_plane_count < HSR_MAX_CLIP_PLANES);
    for (int c = 0; c < 4; ++c) camera.clip_planes[camera.clip_plane_count][c] = plane[c];
    ++camera.clip_plane_count;
}

struct RayCastComparison {
    int covered = 0;      // pixels the ray cast finds a surface at, unambiguously
    int uncovered = 0;    // pixels it finds none at, unambiguously
    int ambiguous = 0;    // rays 0.01 pixel apart disagree: an edge, a cut or a tie
    int mismatches = 0;   // unambiguous pixels where the frame differs
    std::string first_mismatch;
};

RayCastComparison compare_with_clipped_ray_cast(const hsr_scene& scene, const hsr_camera& camera, const hsr::Frame& frame) {
    RayCastComparison r;
    constexpr double d = 0.01;
    const double offsets[5][2] = {{0, 0}, {d, 0}, {-d, 0}, {0, d}, {0, -d}};
    for (uint32_t y = 0; y < camera.height; ++y)
        for (uint32_t x = 0; x < camera.width; ++x) {
            const auto centre = ray_reference::nearest_surface(scene, camera, x + 0.5, y + 0.5);
            bool agree = true;
            for (int k = 1; k < 5 && agree; ++k)
                agree = ray_reference::nearest_surface(scene, camera, x + 0.5 + offsets[k][0], y + 0.5 + offsets[k][1]) == centre;
            if (!agree) {
                ++r.ambiguous;
                continue;
            }
            (centre.first == HSR_NO_FACE ? r.uncovered : r.covered) += 1;
            const size_t p = size_t(y) * camera.width + x;
            const uint32_t instance = frame.instance.empty() ? 0 : frame.instance[p];
            if (frame.face[p] != centre.first || (centre.first != HSR_NO_FACE && instance != centre.second)) {
                if (++r.mismatches == 1)
                    r.first_mismatch = "pixel " + std::to_string(x) + "," + std::to_string(y) + ": face " +
                                       std::to_string(frame.face[p]) + ", ray cast " + std::to_string(centre.first);
            }
        }
    return r;
}

// The pixels a GeometryStage emits for a set of pieces, with how often each is covered.
using Coverage = std::map<std::pair<int32_t, int32_t>, int>;

void add_coverage(const raster::TriangleSetup& s, Coverage& coverage) {
    raster::for_each_covered_pixel(s, [&](int32_t x, int32_t y, double, double) { ++coverage[{x, y}]; });
}

}  // namespace

TEST_CASE("sections: plane_through holds its three points, split_by_plane shares the cut", "[sections]") {
    const glm::dvec4 a(0.3, -0.2, 0.5, 1.7), b(-0.4, 0.9, 0.1, 2.2), c(0.8, 0.4, -0.6, 1.1);
    const glm::dvec4 plane = raster::plane_through(a, b, c);
    const double scale = glm::length(plane);
    REQUIRE(scale > 0.0);
    for (const glm::dvec4& p : {a, b, c}) CHECK(std::abs(glm::dot(plane, p)) <= 1e-12 * scale);
    CHECK(std::abs(glm::dot(plane, glm::dvec4(0.0, 0.0, 0.0, 1.0))) > 1e-3 * scale);
    CHECK(glm::length(raster::plane_through(a, 2.0 * a, c)) <= 1e-12 * scale);  // a, 2a and c: no single plane

    // A square split by a diagonal-ish plane: both parts hold the two crossing corners bit for bit,
    // corners on the plane go to both, and no corner is lost.
    const raster::ClipVertex square[4] = {{{0, 0, 0, 1}, {0, 0}}, {{2, 0, 0, 1}, {1, 0}}, {{2, 2, 0, 1}, {1, 1}},
                                          {{0, 2, 0, 1}, {0, 1}}};
    raster::ClipVertex front[6], back[6];
    int nf = 0, nb = 0;
    raster::split_by_plane(square, 4, {1.0, 0.5, 0.0, -1.5}, front, nf, back, nb);  // x + y/2 = 1.5
    REQUIRE(nf == 4);
    REQUIRE(nb == 4);
    std::set<std::pair<double, double>> shared;
    for (int i = 0; i < nf; ++i)
        for (int j = 0; j < nb; ++j)
            if (front[i].position == back[j].position && front[i].bary == back[j].bary)
                shared.insert({front[i].position.x, front[i].position.y});
    CHECK(shared == std::set<std::pair<double, double>>{{1.5, 0.0}, {0.5, 2.0}});
    raster::split_by_plane(square, 4, {1.0, 0.0, 0.0, 0.0}, front, nf, back, nb);  // the edge x = 0
    CHECK(nf == 4);
    CHECK(nb == 2);  // only the corners on the plane: nothing behind it
}

TEST_CASE("sections: pieces of a triangle cover its pixels exactly once", "[sections]") {
    const hsr::SceneData& cube = model("cube.obj");
    const hsr_scene scene = cube.view();
    hsr_camera camera = orbit(cube, 30, 20, 1, false, 64);
    raster::GeometryStage geometry;
    geometry.begin_frame(scene, camera, false);
    const hsr::sdk::Scene view(scene);
    geometry.place(view.placement(0));
    int triangles_split = 0;
    for (uint32_t t = 0; t < scene.triangle_count; ++t) {
        Coverage whole, pieces;
        geometry.process(t, [&](const raster::TriangleSetup& s) { add_coverage(s, whole); });
        raster::ClipVertex polygon[raster::kMaxClipVertices];
        const int count = geometry.clipped_polygon(t, polygon);
        if (count == 0) continue;
        // Cut by the clip-space plane through two of its corners and a point off the triangle.
        const glm::dvec4 cut = raster::plane_through(polygon[0].position, 0.5 * (polygon[1].position + polygon[2].position),
                                                     polygon[0].position + glm::dvec4(0.0, 0.0, 0.3, 0.0));
        raster::ClipVertex front[raster::kMaxClipVertices + 2], back[raster::kMaxClipVertices + 2];
        int nf = 0, nb = 0;
        raster::split_by_plane(polygon, count, cut, front, nf, back, nb);
        if (nf >= 3 && nb >= 3) ++triangles_split;
        for (auto [piece, n] : {std::pair{front, nf}, {back, nb}})
            if (n >= 3) geometry.rasterize_polygon(piece, n, [&](const raster::TriangleSetup& s) { add_coverage(s, pieces); });
        // The crossing corners are snapped to the 1/256-pixel grid like any corner, so a pixel centre
        // within a grid step of the triangle's outline may fall either way; any other must agree.
        auto near_outline = [&](std::pair<int32_t, int32_t> pixel) {
            const glm::dvec2 centre(pixel.first + 0.5, pixel.second + 0.5);
            for (int k = 0; k < 3; ++k) {
                const raster::WindowVertex& a = geometry.window_vertex(scene.indices[3 * t + k]);
                const raster::WindowVertex& b = geometry.window_vertex(scene.indices[3 * t + (k + 1) % 3]);
                const glm::dvec2 pa(a.exact_x, a.exact_y), pb(b.exact_x, b.exact_y);
                const glm::dvec2 edge = pb - pa;
                const double distance = std::abs(edge.x * (centre.y - pa.y) - edge.y * (centre.x - pa.x)) / glm::length(edge);
                if (distance < 2.0 / raster::kSubpixelScale) return true;
            }
            return false;
        };
        size_t differing = 0, differing_away_from_outline = 0;
        for (const auto& [pixel, times] : whole)
            if (pieces.count(pixel) == 0) ++differing, differing_away_from_outline += near_outline(pixel) ? 0 : 1;
        for (const auto& [pixel, times] : pieces)
            if (whole.count(pixel) == 0) ++differing, differing_away_from_outline += near_outline(pixel) ? 0 : 1;
        INFO("triangle " << t << ": " << whole.size() << " pixels whole, " << pieces.size() << " in pieces");
        CHECK(differing_away_from_outline == 0);
        CHECK(differing <= 2);
        for (const auto& [pixel, times] : pieces) CHECK(times == 1);
    }
    CHECK(triangles_split >= 6);
}

TEST_CASE("sections: every z-buffer plugin draws what a ray cast of the clipped scene sees", "[sections]") {
    const hsr::SceneData& boxes = model("boxes.scene");
    const hsr_scene scene = boxes.view();
    for (bool ortho : {false, true}) {
        hsr_camera camera = orbit(boxes, 35, 25, 1, ortho, 72);
        add_clip_plane(camera, {0.0f, 0.0f, -1.0f, 0.1f});        // the section z <= 0.1
        add_clip_plane(camera, {0.8f, 0.3f, 0.0f, 0.4f});         // and an oblique cut
        const hsr::Frame reference = render("zbuffer", scene, orbit(boxes, 35, 25, 1, ortho, 72));
        for (const char* name : {"zbuffer", "scanline-zbuffer", "hierarchical-zbuffer", "octree-zbuffer"}) {
            const hsr::Frame frame = render(name, scene, camera);
            const RayCastComparison c = compare_with_clipped_ray_cast(scene, camera, frame);
            INFO(name << (ortho ? " orthographic" : " perspective") << ": " << c.first_mismatch);
            CHECK(c.mismatches == 0);
            CHECK(c.covered > 500);
            CHECK(c.ambiguous < c.covered / 5);
            size_t changed = 0;  // the planes must change the picture, or the test proves nothing
            for (size_t p = 0; p < frame.face.size(); ++p) changed += frame.face[p] != reference.face[p] ? 1 : 0;
            CHECK(changed > 300);
        }
    }
}

TEST_CASE("sections: a plane through the eye's side of the near plane changes nothing it keeps", "[sections]") {
    // A plane keeping everything (the whole model on its kept side) leaves the picture bit for bit.
    const hsr::SceneData& cube = model("cube.obj");
    const hsr_scene scene = cube.view();
    hsr_camera camera = orbit(cube, 20, 30, 1, false, 48);
    const hsr::Frame plain = render("zbuffer", scene, camera);
    add_clip_plane(camera, {0.0f, 1.0f, 0.0f, 100.0f});
    const hsr::Frame kept = render("zbuffer", scene, camera);
    CHECK(kept.face == plain.face);
    CHECK(kept.depth == plain.depth);
    CHECK(kept.bary == plain.bary);
}

TEST_CASE("sections: a plugin built before ABI 1.4 is not handed clip planes", "[sections]") {
    // frozen-1.3.so is handmade.c compiled against the ABI 1.3 header kept in tests/plugins/abi-1.3.
    auto plugins = hsr::load_plugin_library(std::string(HSR_TEST_PLUGIN_DIR) + "/frozen-1.3.so");
    REQUIRE(plugins.size() == 1);
    hsr::HiddenSurfaceRemover remover(plugins[0], {});
    const hsr::SceneData& cube = model("cube.obj");
    const hsr_scene scene = cube.view();
    hsr_camera camera = orbit(cube, 0, 0, 1, false, 16);
    add_clip_plane(camera, {0.0f, 0.0f, -1.0f, 0.0f});
    hsr::Frame frame;
    CHECK_THROWS_WITH(hsr::resolve_visibility(scene, camera, remover, frame, false),
                      Catch::Contains("'frozen-1.3'") && Catch::Contains("no clip planes"));
    camera.clip_plane_count = 0;  // without planes it renders as ever
    hsr::resolve_visibility(scene, camera, remover, frame, false);
    CHECK(std::count_if(frame.face.begin(), frame.face.end(), [](uint32_t f) { return f != HSR_NO_FACE; }) > 0);
}

TEST_CASE("sections: the command line and .scene files", "[sections][cli]") {
    using cli::require_one_line_error;
    using cli::run_hsr;
    const std::string cube_path = std::string(HSR_MODELS_DIR) + "/cube.obj";
    const std::string cube = "render " + cube_path;
    const std::string out = (cli::scratch_dir() / "section.png").string();
    const std::string plain_png = (cli::scratch_dir() / "section-plain.png").string();
    REQUIRE(run_hsr(cube + " --width 64 --height 64 -o " + plain_png, "section-plain").status == 0);
    REQUIRE(run_hsr(cube + " --width 64 --height 64 --section 0 --clip-plane 1,0,0,0.5 -o " + out, "section-cut").status == 0);
    CHECK(cli::slurp(plain_png) != cli::slurp(out));

    require_one_line_error(run_hsr(cube + " --clip-plane 0,0,0,1 -o " + out, "plane-zero"), "normal a,b,c is zero");
    require_one_line_error(run_hsr(cube + " --clip-plane 1,2,3 -o " + out, "plane-short"), "a,b,c,d");
    require_one_line_error(run_hsr(cube + " --clip-plane 1,2,3,nan -o " + out, "plane-nan"), "a,b,c,d");
    std::string nine;
    for (int k = 0; k < 9; ++k) nine += " --section " + std::to_string(k);
    require_one_line_error(run_hsr(cube + nine + " -o " + out, "planes-nine"), "at most 8");
    require_one_line_error(run_hsr(cube + " --near 0 -o " + out, "near-zero"), "--near must be a distance");
    require_one_line_error(run_hsr(cube + " --near 1000 -o " + out, "near-far"), "beyond the far plane");
    const std::string svg = (cli::scratch_dir() / "section.svg").string();
    require_one_line_error(run_hsr(cube + " -a roberts --section 0 -o " + svg, "roberts-section"),
                           "roberts: clip planes (sections) are not supported");

    const auto scene_file = cli::write_file("section.scene", "mesh " + cube_path + "\nsection 0\nclip-plane 1 0 0 0.2\n");
    CHECK(run_hsr("render " + scene_file.string() + " --width 64 --height 64 -o " + out, "section-scene").status == 0);
    const auto bad_scene = cli::write_file("bad-section.scene", "mesh " + cube_path + "\nclip-plane 0 0 0 1\n");
    require_one_line_error(run_hsr("render " + bad_scene.string() + " -o " + out, "section-scene-bad"), "normal (a, b, c) is zero");
}

TEST_CASE("sections: --near moves the near plane into the model", "[sections][cli]") {
    // The cube spans [-1, 1]^3 and the orbit camera at yaw 0 sits on +z: a near plane past the
    // cube's front face (z = 1) cuts the front away, and the back faces inside show instead.
    const hsr::SceneData& cube = model("cube.obj");
    const hsr_scene scene = cube.view();
    hsr::CameraSettings settings;
    settings.width = settings.height = 32;
    const hsr_camera plain = hsr::make_camera(cube.bounds_min, cube.bounds_max, settings);
    const float eye_distance = plain.eye[2];
    settings.near_plane = eye_distance - 0.5f;  // half-way into the cube
    const hsr_camera cutting = hsr::make_camera(cube.bounds_min, cube.bounds_max, settings);
    CHECK(cutting.near_plane == Approx(eye_distance - 0.5f));
    const hsr::Frame before = render("zbuffer", scene, plain);
    const hsr::Frame after = render("zbuffer", scene, cutting);
    const size_t centre = 16 * 32 + 16;
    REQUIRE(before.face[centre] != HSR_NO_FACE);
    REQUIRE(after.face[centre] != HSR_NO_FACE);
    CHECK(cube.face_normals[3 * before.face[centre] + 2] == Approx(1.0f));  // the front face, seen head on
    CHECK(cube.face_normals[3 * after.face[centre] + 2] == Approx(-1.0f));  // the back face, from inside
}
