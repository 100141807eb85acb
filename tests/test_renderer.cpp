// The renderer (hsr/renderer.hpp), the one place where every front end's render is assembled,
// checked against the pipeline's own calls: a step with what the step before left in one run of the
// plugin equals two separate runs, for every built-in plugin with steps; what a .scene file says
// applies where a request leaves it open; a read policy keeps a .scene file's meshes inside its
// folders; a line drawing's step past the end is its last step; a frame loop draws what one frame
// does.
#include "surface_test_support.hpp"
#include "test_models.hpp"

#include "hsr/error.hpp"
#include "hsr/lines.hpp"
#include "hsr/pipeline.hpp"
#include "hsr/renderer.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;
using surface_tests::plugin;

namespace {

std::shared_ptr<hsr::Renderer> renderer_of(const std::string& model) {
    hsr::SceneSource source;
    source.model = test_models::path(model);
    return std::make_shared<hsr::Renderer>(hsr::LoadedScene::load(source));
}

hsr::ViewRequest small_view(uint32_t side) {
    hsr::ViewRequest view;
    view.width = side;
    view.height = side;
    view.yaw_degrees = 30.0f;
    view.pitch_degrees = 20.0f;
    return view;
}

bool same_camera(const hsr_camera& a, const hsr_camera& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A scratch folder of this process, removed at the end.
struct ScratchFolder {
    fs::path path;
    explicit ScratchFolder(const std::string& name)
        : path(fs::temp_directory_path() / ("hsr-test-renderer-" + std::to_string(::getpid()) + "-" + name)) {
        fs::create_directories(path);
    }
    ~ScratchFolder() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

}  // namespace

TEST_CASE("renderer: a step and the step before in one run equal two separate runs", "[renderer][steps]") {
    const auto renderer = renderer_of("boxes.scene");
    const hsr::Plugin& lighting_plugin = plugin("facecolor");
    for (const char* name : {"zbuffer", "scanline-zbuffer", "hierarchical-zbuffer", "octree-zbuffer", "painter", "bsp",
                             "warnock", "weiler-atherton", "raycast", "a-buffer"}) {
        INFO(name);
        hsr::HiddenSurfaceRemover remover(plugin(name), {});
        hsr::LightingModel lighting(lighting_plugin, {});
        hsr::PictureRequest request;
        request.view = small_view(48);
        request.count_depth_tests = true;
        request.step_context = true;
        const hsr_camera camera = renderer->camera(request.view);
        const hsr_scene scene = renderer->loaded().scene().view();

        hsr::Frame counted;
        hsr::resolve_visibility_steps(scene, camera, remover, counted, 0);
        const uint64_t total = counted.steps->taken;
        REQUIRE(total > 3);
        for (uint64_t step : {uint64_t(1), uint64_t(2), total / 2, total - 1, total, total + 5}) {
            INFO("step " << step);
            request.step = step;
            const hsr::Picture picture = renderer->picture(request, remover, lighting);
            const uint64_t shown = std::min(step, total);
            CHECK(picture.step_total == total);
            CHECK(picture.step_shown == shown);
            CHECK(picture.frame.steps->last.index == shown);

            hsr::Frame at;
            hsr::resolve_visibility_steps(scene, camera, remover, at, shown, true);
            CHECK(picture.frame.face == at.face);
            CHECK(picture.frame.depth == at.depth);
            CHECK(picture.frame.depth_tests == at.depth_tests);
            CHECK(picture.frame.steps->last.text == at.steps->last.text);
            CHECK(picture.frame.counters.size() >= at.counters.size());
            if (shown < 2) {
                CHECK(picture.before.face.empty());
                continue;
            }
            hsr::Frame before;
            hsr::resolve_visibility_steps(scene, camera, remover, before, shown - 1, true);
            CHECK(picture.before.face == before.face);
            CHECK(picture.before.depth == before.depth);
            CHECK(picture.before.depth_tests == before.depth_tests);
        }
    }
}

TEST_CASE("renderer: a .scene file's view applies where the request leaves it open", "[renderer]") {
    ScratchFolder folder("view");
    const fs::path scene = folder.path / "view.scene";
    std::ofstream(scene) << "size 40 30\ncamera orbit yaw 25 pitch -10 zoom 1.5\nmesh \"" << test_models::path("cube.obj").string()
                         << "\"\n";
    hsr::SceneSource source;
    source.model = scene;
    const hsr::Renderer renderer(hsr::LoadedScene::load(source));
    const hsr::SceneData& data = renderer.loaded().scene();

    hsr::CameraSettings file_view;
    file_view.width = 40;
    file_view.height = 30;
    file_view.yaw_degrees = 25;
    file_view.pitch_degrees = -10;
    file_view.zoom = 1.5f;
    CHECK(same_camera(renderer.camera({}), hsr::make_camera(data.bounds_min, data.bounds_max, file_view)));

    hsr::ViewRequest request;
    request.width = 64;
    request.yaw_degrees = 90.0f;
    request.yaw_turn_degrees = 10.0;
    hsr::CameraSettings mixed = file_view;
    mixed.width = 64;
    mixed.yaw_degrees = 100;
    CHECK(same_camera(renderer.camera(request), hsr::make_camera(data.bounds_min, data.bounds_max, mixed)));
}

TEST_CASE("renderer: a read policy keeps a .scene file's meshes inside its folders", "[renderer]") {
    ScratchFolder inside("inside"), outside("outside");
    fs::copy_file(test_models::path("cube.obj"), inside.path / "cube.obj");
    fs::copy_file(test_models::path("cube.obj"), outside.path / "cube.obj");
    const hsr::ReadPolicy policy({inside.path}, "the test's folder");
    std::ofstream(inside.path / "near.scene") << "mesh cube.obj\n";
    std::ofstream(inside.path / "far.scene") << "# a mesh elsewhere\nmesh \"" << (outside.path / "cube.obj").string()
                                             << "\"\n";
    std::ofstream(inside.path / "up.scene") << "mesh ../" << outside.path.filename().string() << "/cube.obj\n";

    hsr::SceneSource source;
    source.model = inside.path / "near.scene";
    CHECK(hsr::LoadedScene::load(source, policy)->scene().triangle_count() == 12);
    for (const char* name : {"far.scene", "up.scene"}) {
        source.model = inside.path / name;
        CHECK_THROWS_WITH(hsr::LoadedScene::load(source, policy),
                          Catch::Contains(": mesh '") && Catch::Contains("lies outside the test's folder"));
        CHECK(hsr::LoadedScene::load(source)->scene().triangle_count() == 12);  // no policy: any file
    }
    source.model = outside.path / "cube.obj";
    CHECK_THROWS_WITH(hsr::LoadedScene::load(source, policy), Catch::Contains("lies outside the test's folder"));
}

TEST_CASE("renderer: a line drawing's step past the end is its last step", "[renderer][steps]") {
    const auto renderer = renderer_of("boxes.scene");
    hsr::HiddenLineRemover remover(plugin("appel"), {});
    hsr::LineRequest request;
    request.view = small_view(64);
    const hsr::LinePicture full = renderer->lines(request, remover);
    const uint64_t events = full.drawing.trace_events;
    request.step = 1;
    const uint64_t total = renderer->lines(request, remover).drawing.trace_events;
    REQUIRE(total > 2);
    CHECK(events == 0);  // no events asked for

    hsr::LineSettings last = request.settings;
    last.stop_after_event = total;
    const hsr::LineDrawing expected = hsr::render_lines(full.scene, full.camera, remover, last);
    request.step = total + 7;
    const hsr::LinePicture past = renderer->lines(request, remover);
    REQUIRE(past.drawing.stopped_at);
    CHECK(past.drawing.stopped_at->index == total);
    CHECK(past.drawing.stopped_at->type == expected.stopped_at->type);
    CHECK(past.drawing.stopped_at->edge == expected.stopped_at->edge);
    CHECK(past.drawing.segments.size() == expected.segments.size());
}

TEST_CASE("renderer: a frame loop draws what one frame draws, again and again", "[renderer]") {
    const auto renderer = renderer_of("monkey.obj");
    hsr::HiddenSurfaceRemover remover(plugin("zbuffer"), {});
    hsr::LightingModel lighting(plugin("blinn-phong"), {});
    hsr::PictureRequest request;
    request.view = small_view(96);
    const hsr::Picture picture = renderer->picture(request, remover, lighting);

    const std::vector<hsr_light> lights = renderer->lights({}, picture.camera);
    const hsr_shading_context context = hsr::make_shading_context(picture.camera, lights);
    hsr::FrameSettings settings;
    settings.background = hsr::default_background_color();
    hsr::FrameLoop loop(picture.scene, picture.camera, context, settings, remover, lighting);
    for (int call = 0; call < 3; ++call) {
        const hsr::Frame& frame = loop.render();
        CHECK(frame.rgb == picture.frame.rgb);
        CHECK(frame.face == picture.frame.face);
    }
}

TEST_CASE("renderer: the depth complexity of a view, measured once and kept", "[renderer]") {
    const auto renderer = renderer_of("boxes.scene");
    hsr::LightingModel lighting(plugin("facecolor"), {});
    hsr::PictureRequest request;
    request.depth_complexity = true;
    for (int yaw : {0, 40, 0, 80, 120, 160, 0}) {  // the first view again after more than it keeps
        request.view = small_view(40);
        request.view.yaw_degrees = float(yaw);
        for (const char* name : {"zbuffer", "painter"}) {
            hsr::HiddenSurfaceRemover remover(plugin(name), {});
            const hsr::Picture picture = renderer->picture(request, remover, lighting);
            REQUIRE(picture.depth_complexity);
            const hsr::DepthComplexity expected = hsr::measure_depth_complexity(picture.scene, picture.camera);
            CHECK(picture.depth_complexity->count == expected.count);
            CHECK(picture.depth_complexity->max == expected.max);
        }
    }
}

namespace {

// The counts of a rectangle are the whole picture's there, and its totals are theirs.
void check_region(const hsr::DepthComplexity& whole, const hsr::DepthComplexity& part, hsr::PixelRegion r) {
    REQUIRE(part.x == r.x);
    REQUIRE(part.y == r.y);
    REQUIRE(part.width == r.width);
    REQUIRE(part.height == r.height);
    REQUIRE(part.count.size() == std::size_t(r.width) * r.height);
    uint64_t fragments = 0, covered = 0;
    uint32_t max = 0;
    for (uint32_t y = 0; y < r.height; ++y)
        for (uint32_t x = 0; x < r.width; ++x) {
            const uint32_t c = whole.count[std::size_t(r.y + y) * whole.width + r.x + x];
            CHECK(part.count[std::size_t(y) * r.width + x] == c);
            fragments += c;
            covered += c > 0;
            max = std::max(max, c);
        }
    CHECK(part.fragments == fragments);
    CHECK(part.covered_pixels == covered);
    CHECK(part.max == max);
}

}  // namespace

TEST_CASE("renderer: depth complexity over a rectangle of the picture", "[renderer]") {
    const auto renderer = renderer_of("boxes.scene");
    hsr::LightingModel lighting(plugin("facecolor"), {});
    hsr::HiddenSurfaceRemover remover(plugin("zbuffer"), {});
    hsr::PictureRequest request;
    request.view = small_view(40);
    request.view.yaw_degrees = 30;
    request.depth_complexity = true;
    const hsr::Picture whole = renderer->picture(request, remover, lighting);
    REQUIRE(whole.depth_complexity);
    REQUIRE(whole.depth_complexity->max >= 2);
    const uint32_t side = whole.camera.width;
    for (const hsr::PixelRegion r : {hsr::PixelRegion{0, 0, side, side}, hsr::PixelRegion{5, 7, 16, 9},
                                     hsr::PixelRegion{side - 1, side - 1, 1, 1}, hsr::PixelRegion{12, 0, 3, side}}) {
        check_region(*whole.depth_complexity, hsr::measure_depth_complexity(whole.scene, whole.camera, r), r);
        request.depth_complexity_region = r;
        const hsr::Picture part = renderer->picture(request, remover, lighting);
        REQUIRE(part.depth_complexity);
        check_region(*whole.depth_complexity, *part.depth_complexity, r);
    }
    // The request's rectangle is clipped to the picture; nothing left of it, nothing measured.
    request.depth_complexity_region = hsr::PixelRegion{side - 4, 2, 100, 3};
    const hsr::Picture clipped = renderer->picture(request, remover, lighting);
    REQUIRE(clipped.depth_complexity);
    check_region(*whole.depth_complexity, *clipped.depth_complexity, {side - 4, 2, 4, 3});
    request.depth_complexity_region = hsr::PixelRegion{side, 0, 4, 4};
    CHECK_FALSE(renderer->picture(request, remover, lighting).depth_complexity);
    // measure_depth_complexity itself takes only a rectangle inside the picture.
    for (const hsr::PixelRegion r : {hsr::PixelRegion{0, 0, 0, 4}, hsr::PixelRegion{side, 0, 1, 1},
                                     hsr::PixelRegion{side - 2, 0, 3, 1}, hsr::PixelRegion{0, 1, 1, UINT32_MAX}})
        CHECK_THROWS_AS(hsr::measure_depth_complexity(whole.scene, whole.camera, r), hsr::Error);
}
