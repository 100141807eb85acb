// The hsr executable as a user meets it: every bad input gives one line on stderr and a non-zero
// exit status; a good one writes a picture whose pixels make sense.
#include "hsr/abi.h"
#include "cli_support.hpp"
#include "hsr/image.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

using cli::Run;
using cli::require_one_line_error;
using cli::run_hsr;
using cli::scratch_dir;
using cli::slurp;
using cli::write_file;

std::string model(const char* name) { return std::string(HSR_MODELS_DIR) + "/" + name; }

}  // namespace

TEST_CASE("cli: a missing model file", "[cli]") {
    require_one_line_error(run_hsr("render /nonexistent/model.obj -o x.png", "missing"), "/nonexistent/model.obj");
}

TEST_CASE("cli: a malformed mesh", "[cli]") {
    const fs::path bad = write_file("garbage.off", "OFF\nthis is not a mesh\n");
    require_one_line_error(run_hsr("render " + bad.string() + " -o x.png", "malformed"), "garbage.off");
}

TEST_CASE("cli: an empty mesh", "[cli]") {
    const fs::path empty = write_file("empty.off", "OFF\n0 0 0\n");
    require_one_line_error(run_hsr("render " + empty.string() + " -o x.png", "empty"), "empty.off");
}

TEST_CASE("cli: NaN vertices", "[cli]") {
    const fs::path nan = write_file("nan.off", "OFF\n3 1 0\n0 0 0\nnan 1 0\n1 0 0\n3 0 1 2\n");
    require_one_line_error(run_hsr("render " + nan.string() + " -o x.png", "nan"), "nan.off");
}

TEST_CASE("cli: every model in tests/data/bad is refused with exit status 1 and one line", "[cli]") {
    int files = 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(fs::path(HSR_SOURCE_DIR) / "tests/data/bad")) {
        const std::string name = entry.path().filename().string();
        INFO(name);
        const Run r = run_hsr("render " + entry.path().string() + " -o x.png", "bad-" + name);
        require_one_line_error(r, name);
        CHECK(r.status == 1);
        ++files;
    }
    CHECK(files >= 5);
}

TEST_CASE("cli: an OBJ naming a pipe as its material library does not wait on it", "[cli]") {
    const fs::path pipe = scratch_dir() / "materials.fifo";
    fs::remove(pipe);
    REQUIRE(std::system(("mkfifo " + pipe.string()).c_str()) == 0);
    const fs::path obj = write_file("pipe-materials.obj", "mtllib materials.fifo\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Run r = run_hsr("render " + obj.string() + " -o " + (scratch_dir() / "pipe-materials.png").string(), "pipe-materials");
    INFO("stderr: " << r.err);
    CHECK(r.status == 0);
    fs::remove(pipe);
}

TEST_CASE("cli: an unknown plugin says where it looked and what it found", "[cli]") {
    const Run r = run_hsr("render " + model("cube.obj") + " --algorithm no-such-algorithm -o x.png", "unknown-plugin");
    require_one_line_error(r, "no hidden-surface or hidden-line plugin named 'no-such-algorithm'");
    CHECK_THAT(r.err, Catch::Contains("searched:") && Catch::Contains("zbuffer") && Catch::Contains("appel"));
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --lighting toon -o x.png", "unknown-lighting"),
                           "no lighting plugin named 'toon'");
}

TEST_CASE("cli: output files are checked before the render, and nothing is written when one is wrong", "[cli]") {
    const fs::path picture = scratch_dir() / "outputs-ok.png";
    fs::remove(picture);
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -o " + picture.string() +
                                       " --overdraw-out /nonexistent/folder/o.png", "outputs-folder"),
                           "the folder '/nonexistent/folder' does not exist");
    CHECK_FALSE(fs::exists(picture));
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -o " + scratch_dir().string(), "outputs-dir"),
                           "is a folder");
    // A hidden-surface plugin writes PNG: another name would lie about the format.
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -o cube.svg", "outputs-ext"),
                           "--output 'cube.svg': the name must end in .png");
    // The same file twice: one would overwrite the other.
    const std::string same = (scratch_dir() / "same.png").string();
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -o " + same + " --depth-out " + same, "outputs-same"),
                           "--output and --depth-out name the same file");
    // A line drawing may be SVG or PNG, nothing else.
    require_one_line_error(run_hsr("render " + model("cube.obj") + " -a appel -o cube.pdf", "outputs-lines"),
                           "must end in .svg or .png");
}

TEST_CASE("cli: options that need another, and numbers out of range, are named", "[cli]") {
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --repeat-gap 0.5 -o x.png", "gap-alone"),
                           "--repeat-gap goes with --repeat");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --repeat 99999999999x1x1 -o x.png", "repeat-big"),
                           "at most 100000 along each side");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --zoom nan -o x.png", "zoom-nan"),
                           "--zoom must be a finite number");
    require_one_line_error(run_hsr("plugins extra", "plugins-extra"), "extra");
    const fs::path scene = write_file("repeated.scene", "mesh " + model("cube.obj") + "\nrepeat 2 2 2\n");
    require_one_line_error(run_hsr("render " + scene.string() + " --repeat 2x2x2 -o x.png", "repeat-twice"),
                           "use one or the other");
    // Coordinates near the largest float: the camera cannot be made in single precision.
    const fs::path huge = write_file("huge.off", "OFF\n3 1 0\n-3e38 0 0\n3e38 0 0\n0 3e38 0\n3 0 1 2\n");
    require_one_line_error(run_hsr("render " + huge.string() + " -o x.png", "huge"), "too large");
}

TEST_CASE("cli: an empty picture is rendered with a warning", "[cli]") {
    // A triangle seen exactly edge-on covers no pixel centre.
    const fs::path edge_on = write_file("edge-on.off", "OFF\n3 1 0\n0 0 0\n0 1 0\n0 0 1\n3 0 1 2\n");
    const Run r = run_hsr("render " + edge_on.string() + " -o " + (scratch_dir() / "edge-on.png").string(), "edge-on");
    INFO("stderr: " << r.err);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Catch::Contains("hsr: warning: no triangle covers a pixel centre"));
    // A tiny model is not empty: the camera frames it whatever its size.
    const fs::path tiny = write_file("tiny.off", "OFF\n3 1 0\n0 0 0\n1e-12 0 0\n0 1e-12 0\n3 0 1 2\n");
    const Run t = run_hsr("render " + tiny.string() + " -o " + (scratch_dir() / "tiny.png").string(), "tiny");
    INFO("stderr: " << t.err);
    CHECK(t.status == 0);
    CHECK_THAT(t.err, !Catch::Contains("warning"));
}

TEST_CASE("cli: unknown and out-of-range plugin parameters", "[cli]") {
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --algorithm zbuffer:colour=red -o x.png", "unknown-param"),
                           "plugin 'zbuffer' has no parameter 'colour'");
    require_one_line_error(
        run_hsr("render " + model("cube.obj") + " --lighting blinn-phong:shininess=-3 -o x.png", "range-param"),
        "out of range");
    require_one_line_error(
        run_hsr("render " + model("cube.obj") + " --algorithm zbuffer:depth-test=sideways -o x.png", "enum-param"),
        "not one of less|greater");
}

TEST_CASE("cli: zero and absurd image sizes are refused before allocating", "[cli]") {
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --width 0 -o x.png", "zero-size"), "image size");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --width 1000000 --height 1000000 -o x.png", "huge"),
                           "image size");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --height -5 -o x.png", "negative"), "image size");
}

TEST_CASE("cli: unknown commands and options", "[cli]") {
    require_one_line_error(run_hsr("paint", "unknown-command"), "unknown command 'paint'");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --frobnicate", "unknown-option"), "frobnicate");
    require_one_line_error(run_hsr("render", "no-model"), "no model");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --zoom abc", "bad-number"), "zoom");
}

TEST_CASE("cli: a mistyped command, option or plugin is answered with the nearest one", "[cli]") {
    const std::string cube = model("cube.obj");
    require_one_line_error(run_hsr("rendr " + cube, "typo-command"),
                           "unknown command 'rendr' (did you mean render?) (see hsr --help)");
    require_one_line_error(run_hsr("--verison", "typo-version"), "(did you mean --version?)");
    require_one_line_error(run_hsr("render " + cube + " --algoritm zbuffer -o x.png", "typo-option"),
                           "unknown option --algoritm (did you mean --algorithm?) (see hsr render --help)");
    require_one_line_error(run_hsr("render " + cube + " --widht=64 -o x.png", "typo-option-value"),
                           "unknown option --widht (did you mean --width?)");
    require_one_line_error(run_hsr("render " + cube + " --frobnicate -o x.png", "no-near-option"),
                           "unknown option --frobnicate (see hsr render --help)");
    require_one_line_error(run_hsr("bench --modles cube", "typo-bench"),
                           "unknown option --modles (did you mean --models?) (see hsr bench --help)");
    require_one_line_error(run_hsr("plugins --plugin-pth x", "typo-plugins"),
                           "unknown option --plugin-pth (did you mean --plugin-path?) (see hsr plugins --help)");
    require_one_line_error(run_hsr("view --lisen 127.0.0.1:0", "typo-view"),
                           "unknown option --lisen (did you mean --listen?) (see hsr view --help)");
    require_one_line_error(run_hsr("render " + cube + " -a zbufer -o x.png", "typo-algorithm"),
                           "no hidden-surface or hidden-line plugin named 'zbufer' (did you mean zbuffer?)");
    require_one_line_error(run_hsr("render " + cube + " -l phnog -o x.png", "typo-lighting"),
                           "no lighting plugin named 'phnog' (did you mean phong?)");
    require_one_line_error(run_hsr("render " + cube + " -a zbuffer:cul-backfaces=true -o x.png", "typo-parameter"),
                           "has no parameter 'cul-backfaces' (did you mean cull-backfaces?)");
}

TEST_CASE("cli: a mistake points to the --help of its own command", "[cli]") {
    require_one_line_error(run_hsr("render", "hint-render"), "(see hsr render --help)");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --width 0", "hint-width"), "(see hsr render --help)");
    require_one_line_error(run_hsr("bench --sizes 0", "hint-bench"), "(see hsr bench --help)");
    require_one_line_error(run_hsr("plugins extra", "hint-plugins"), "(see hsr plugins --help)");
    require_one_line_error(run_hsr("view --listen nowhere", "hint-view"), "(see hsr view --help)");
    require_one_line_error(run_hsr("paint", "hint-command"), "(see hsr --help)");
}

TEST_CASE("cli: integer plugin parameters show whole-number ranges", "[cli]") {
    const Run r = run_hsr("plugins", "plugins-integers");
    CHECK(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("(integer 1..100000000)"));
    CHECK_THAT(r.out, !Catch::Contains("e+"));
}

TEST_CASE("cli: --plugin-path must name a folder", "[cli]") {
    require_one_line_error(run_hsr("plugins --plugin-path /nonexistent", "plugin-path-missing"),
                           "--plugin-path '/nonexistent': no such folder");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --plugin-path /nonexistent -o x.png",
                                   "plugin-path-render"),
                           "--plugin-path '/nonexistent': no such folder");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --plugin-path " + model("cube.obj") + " -o x.png",
                                   "plugin-path-file"),
                           "is not a folder");
    require_one_line_error(run_hsr("view --plugin-path /nonexistent --listen 127.0.0.1:0", "plugin-path-view"),
                           "--plugin-path '/nonexistent': no such folder (see hsr view --help)");
    require_one_line_error(run_hsr("bench --plugin-path /nonexistent", "plugin-path-bench"),
                           "--plugin-path '/nonexistent': no such folder (see hsr bench --help)");
}

TEST_CASE("cli: a folder or standard input named as the model has its own message", "[cli]") {
    require_one_line_error(run_hsr("render " + std::string(HSR_MODELS_DIR) + " -o x.png", "model-folder"),
                           "is a folder, not a model file");
    const fs::path dotted = cli::scratch_dir() / "folder.obj";
    fs::create_directories(dotted);
    require_one_line_error(run_hsr("render " + dotted.string() + " -o x.png", "model-folder-obj"),
                           "is a folder, not a model file");
    require_one_line_error(run_hsr("render /dev/stdin -o x.png", "model-stdin"),
                           "MODEL '/dev/stdin': standard input is read as MODEL '-', with --format");
}

TEST_CASE("cli: several models render in one run, each named by {stem}", "[cli]") {
    const fs::path dir = cli::scratch_dir() / "several";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string size = " --width 32 --height 24";
    const Run r = run_hsr("render " + model("cube.obj") + " " + model("pyramid.stl") + size + " -o '" +
                              (dir / "{stem}-zb.png").string() + "' --depth-out '" + (dir / "{stem}-depth.npy").string() + "'",
                          "several-models");
    INFO(r.err);
    REQUIRE(r.status == 0);
    for (const char* name : {"cube-zb.png", "pyramid-zb.png", "cube-depth.npy", "pyramid-depth.npy"})
        CHECK(fs::exists(dir / name));
    // Each picture is the one a render of its model alone writes.
    const Run alone = run_hsr("render " + model("pyramid.stl") + size + " -o " + (dir / "alone.png").string(),
                              "several-alone");
    REQUIRE(alone.status == 0);
    CHECK(slurp(dir / "pyramid-zb.png") == slurp(dir / "alone.png"));
    // A model that fails is reported once, by name, and the others still render.
    const std::string missing = (dir / "missing.obj").string();
    const Run failing = run_hsr("render " + missing + " " + model("cube.obj") + size + " -o '" +
                                    (dir / "{stem}-after.png").string() + "'", "several-failing");
    CHECK(failing.status == 1);
    CHECK_THAT(failing.err, Catch::Contains("hsr: error: " + missing + ": no such file\n"));
    CHECK_THAT(failing.err, Catch::Contains("1 of 2 jobs failed"));
    CHECK(fs::exists(dir / "cube-after.png"));
    // {stem} for one model too.
    const Run one = run_hsr("render " + model("cube.obj") + size + " -o '" + (dir / "{stem}-one.png").string() + "'",
                            "stem-one");
    CHECK(one.status == 0);
    CHECK(fs::exists(dir / "cube-one.png"));
}

TEST_CASE("cli: several models with one fixed file name are refused before any render", "[cli]") {
    const std::string two = "render " + model("cube.obj") + " " + model("pyramid.stl");
    require_one_line_error(run_hsr(two + " -o x.png", "several-fixed"),
                           "--output 'x.png': 2 models would each write it; put {stem}");
    require_one_line_error(run_hsr(two + " -o '{stem}.png' --depth-out d.png", "several-fixed-depth"),
                           "--depth-out 'd.png': 2 models would each write it");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " " + model("cube.obj") + " -o '{stem}.png'",
                                   "several-same-stem"),
                           "is written by the render of");
    require_one_line_error(run_hsr(two + " - -o '{stem}.png'", "several-stdin"), "standard input");
    CHECK_FALSE(fs::exists("x.png"));
}

TEST_CASE("cli: plugins of another ABI version are listed as refused", "[cli]") {
    const Run r = run_hsr(std::string("plugins --plugin-path ") + HSR_TEST_PLUGIN_DIR, "plugins-refused");
    CHECK(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("refused:") && Catch::Contains("built for ABI 2."));
    CHECK_THAT(r.out, Catch::Contains("needs ABI 1." + std::to_string(HSR_ABI_MINOR + 1)));
    CHECK_THAT(r.out, Catch::Contains("no-entry.so: not an hsr plugin"));
}

TEST_CASE("cli: plugins lists every plugin with its parameters", "[cli]") {
    const Run r = run_hsr("plugins", "plugins");
    CHECK(r.status == 0);
    for (const char* name : {"zbuffer", "lambert", "phong", "blinn-phong", "facecolor", "gooch"})
        CHECK_THAT(r.out, Catch::Contains(name));
    CHECK_THAT(r.out, Catch::Contains("ABI 1." + std::to_string(HSR_ABI_MINOR)));
    CHECK_THAT(r.out, Catch::Contains("depth-test=less (less|greater)"));
    CHECK_THAT(r.out, Catch::Contains("interpolation="));
    const Run help = run_hsr("render --help", "render-help");
    CHECK(help.status == 0);
    CHECK_THAT(help.out, Catch::Contains("--algorithm") && Catch::Contains("--depth-out") &&
                             Catch::Contains("shininess="));
}

TEST_CASE("cli: --eye looks from a point, and the cube covers the square worked out by hand", "[cli][look-at]") {
    // Eye at (0, 0, 5) looking at the origin, 90 degrees of field of view, 96 x 96 pixels: the
    // front face (z = 1, x and y in [-1, 1]) is 4 away, so it spans 1/4 of the half-width (48) each
    // side of the centre: 36 to 60, so columns and rows 36 to 59 hold its pixel centres. The side
    // faces are hidden behind it (they recede from the eye inside that square).
    const fs::path png = scratch_dir() / "eye.png";
    const Run r = run_hsr("render " + model("cube.obj") + " --eye 0,0,5 --target 0,0,0 --up 0,1,0 --fov 90 "
                          "--width 96 --height 96 --background 0/0/0 -o " + png.string(), "eye");
    INFO(r.err);
    REQUIRE(r.status == 0);
    const hsr::Image img = hsr::read_png_rgb(png);
    uint32_t left = img.width, right = 0, top = img.height, bottom = 0;
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x) {
            const uint8_t* p = &img.pixels[3 * (size_t(y) * img.width + x)];
            if (p[0] == 0 && p[1] == 0 && p[2] == 0) continue;
            left = std::min(left, x), right = std::max(right, x);
            top = std::min(top, y), bottom = std::max(bottom, y);
        }
    CHECK(left == 36);
    CHECK(right == 59);
    CHECK(top == 36);
    CHECK(bottom == 59);

    require_one_line_error(run_hsr("render " + model("cube.obj") + " --eye 0,0,5 --yaw 10 -o x.png", "eye-yaw"),
                           "--eye replaces --yaw: give one or the other");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --target 0,0,0 -o x.png", "target-alone"),
                           "--target goes with --eye");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --eye 0,0 -o x.png", "eye-two"),
                           "--eye '0,0': expected x,y,z (three finite numbers)");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --eye 0,5,0 -o x.png", "eye-up"),
                           "is zero or along the line of sight");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --fov 0 -o x.png", "fov"),
                           "--fov must be between 0 and 180 degrees");
    // A .scene file's look-at camera is used unless the command line orbits.
    const fs::path scene = write_file("look.scene", "mesh " + model("cube.obj") + "\ncamera look-at eye 0 0 5 fov 90\n");
    const fs::path from_scene = scratch_dir() / "eye-scene.png";
    REQUIRE(run_hsr("render " + scene.string() + " --width 96 --height 96 --background 0/0/0 -o " +
                    from_scene.string(), "eye-scene").status == 0);
    CHECK(hsr::read_png_rgb(from_scene).pixels == img.pixels);
}

TEST_CASE("cli: a render writes a PNG with the model in the middle and background at the corners", "[cli]") {
    const fs::path png = scratch_dir() / "cube.png";
    const fs::path depth = scratch_dir() / "cube-depth.png";
    fs::remove(png);
    const Run r = run_hsr("render " + model("cube.obj") + " --yaw 30 --pitch 20 --width 96 --height 64 --background 0/0/1 "
                      "--lighting lambert -o " + png.string() + " --depth-out " + depth.string(), "render-cube");
    INFO(r.err);
    REQUIRE(r.status == 0);
    const hsr::Image img = hsr::read_png_rgb(png);
    REQUIRE(img.width == 96);
    REQUIRE(img.height == 64);
    auto pixel = [&](uint32_t x, uint32_t y) {
        const uint8_t* p = &img.pixels[3 * (size_t(y) * img.width + x)];
        return std::array<int, 3>{p[0], p[1], p[2]};
    };
    CHECK(pixel(0, 0) == std::array<int, 3>{0, 0, 255});
    CHECK(pixel(95, 63) == std::array<int, 3>{0, 0, 255});
    CHECK(pixel(48, 32) != std::array<int, 3>{0, 0, 255});
    const hsr::Image d = hsr::read_png_rgb(depth);
    CHECK(d.pixels[0] == 0);                                  // uncovered: black
    CHECK(d.pixels[3 * (32 * 96 + 48)] >= 64);                // covered: grey to white
}

TEST_CASE("cli: --repeat makes a deep scene, and --stats, --overdraw-out and --depth-tests-out show it", "[cli]") {
    const fs::path dir = scratch_dir();
    const fs::path picture = dir / "deep.png", overdraw = dir / "deep-overdraw.png", tests = dir / "deep-tests.png";
    const Run r = run_hsr("render " + model("cube.obj") + " --repeat 2x1x5 --ortho --width 64 --height 48 --stats -o " +
                              picture.string() + " --overdraw-out " + overdraw.string() + " --depth-tests-out " +
                              tests.string(),
                          "repeat");
    INFO(r.err);
    REQUIRE(r.status == 0);
    // 10 cubes of 12 triangles, stored once; seen straight along the layers, every covered pixel
    // has the front and back face of each of the 5 cubes in its column.
    CHECK_THAT(r.err, Catch::Contains("120 triangles (10 instances of 12 stored)"));
    CHECK_THAT(r.err, Catch::Contains("depth complexity") && Catch::Contains("10.00 (max 10"));
    const hsr::Image heat = hsr::read_png_rgb(overdraw);
    CHECK(heat.width == 64);
    CHECK(heat.height == 48 + hsr::heat_map_legend_height);  // the picture and the legend strip below it
    const hsr::Image work = hsr::read_png_rgb(tests);
    CHECK(work.height == 48 + hsr::heat_map_legend_height);
    // Under the ramp, tick marks in white at its ends (and labels, when a font is installed).
    auto heat_pixel = [&](uint32_t x, uint32_t y) { return heat.pixels[3 * (size_t(y) * heat.width + x)]; };
    const uint32_t label_row = 48 + hsr::heat_map_legend_height - 15;
    CHECK(heat_pixel(0, label_row) == 255);
    CHECK(heat_pixel(62, label_row) == 255);
    CHECK(heat_pixel(30, label_row) == 0);
    // zbuffer depth-tests every covered sample: its work map equals the depth complexity map.
    CHECK(work.pixels == heat.pixels);
}

TEST_CASE("cli: a malformed --repeat is a one-line error", "[cli]") {
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --repeat 3x0x2 -o x.png", "repeat-zero"), "--repeat");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --repeat 3x2 -o x.png", "repeat-short"), "COLUMNSxROWSxLAYERS");
}

TEST_CASE("cli: a hidden-line plugin draws SVG or PNG lines and writes its trace", "[cli][lines]") {
    // handmade-lines (tests/plugins) returns every requested edge as visible.
    const std::string plugins = std::string(" --plugin-path ") + HSR_TEST_PLUGIN_DIR;
    const fs::path svg = scratch_dir() / "cube-lines.svg", png = scratch_dir() / "cube-lines.png";
    const fs::path trace = scratch_dir() / "cube-lines.jsonl";
    fs::remove(svg);
    const Run r = run_hsr("render " + model("cube.obj") + plugins + " -a handmade-lines --edges all --hidden dashed "
                          "--yaw 30 --pitch 20 --width 120 --height 90 --stats -o " + svg.string() + " --trace " +
                          trace.string(), "lines-svg");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.err, Catch::Contains("12 edges asked for") && Catch::Contains("edges-in"));
    const std::string text = slurp(svg);
    CHECK_THAT(text, Catch::Contains("<svg") && Catch::Contains("width=\"120px\""));
    const std::string steps = slurp(trace);
    CHECK(std::count(steps.begin(), steps.end(), '\n') == 12);
    CHECK(steps.rfind("{\"type\":\"edge-begin\"", 0) == 0);

    const Run p = run_hsr("render " + model("cube.obj") + plugins + " -a handmade-lines --yaw 30 --pitch 20 "
                          "--width 120 --height 90 -o " + png.string(), "lines-png");
    INFO(p.err);
    REQUIRE(p.status == 0);
    const hsr::Image img = hsr::read_png_rgb(png);
    CHECK(img.width == 120);
    int dark = 0;
    for (size_t k = 0; k < img.pixels.size(); k += 3) dark += img.pixels[k] < 128;
    CHECK(dark > 100);  // the cube's outline
}

TEST_CASE("cli: options of the wrong family and bad line options are one-line errors", "[cli][lines]") {
    const std::string plugins = std::string(" --plugin-path ") + HSR_TEST_PLUGIN_DIR;
    const std::string cube = model("cube.obj");
    require_one_line_error(run_hsr("render " + cube + " --edges all -o x.png", "edges-surface"),
                           "--edges is for hidden-line plugins");
    require_one_line_error(run_hsr("render " + cube + plugins + " -a handmade-lines --lighting phong", "lighting-lines"),
                           "--lighting is for hidden-surface plugins");
    require_one_line_error(run_hsr("render " + cube + plugins + " -a handmade-lines --edges some", "edges-bad"),
                           "--edges 'some'");
    require_one_line_error(run_hsr("render " + cube + plugins + " -a handmade-lines --hidden dotted", "hidden-bad"),
                           "--hidden 'dotted'");
    require_one_line_error(run_hsr("render " + cube + plugins + " -a handmade-lines -o x.jpg", "lines-jpg"),
                           ".svg or .png");
    require_one_line_error(
        run_hsr("render " + cube + plugins + " -a handmade-lines -o x.svg --trace /nonexistent-dir/t.jsonl", "trace-bad"),
        "/nonexistent-dir/t.jsonl");
}

TEST_CASE("cli: --surface draws a formula, bad formulas and ranges are one-line errors", "[cli][surface]") {
    const fs::path png = scratch_dir() / "surface.png";
    fs::remove(png);
    const Run r = run_hsr("render --surface \"sin(x)*cos(y)\" --range -3:3,-3:3,24x24 --pitch 30 --width 80 --height 60 "
                          "-o " + png.string(), "surface");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(hsr::read_png_rgb(png).width == 80);
    require_one_line_error(run_hsr("render --surface \"sin(x\"", "surface-bad"), "Missing parenthesis");
    require_one_line_error(run_hsr("render --surface \"x+q\"", "surface-name"), "x+q");
    require_one_line_error(run_hsr("render --surface x --range 3:1,0:1", "surface-range"), "3:1,0:1");
    require_one_line_error(run_hsr("render " + model("cube.obj") + " --surface x", "surface-two"), "one of MODEL");
    require_one_line_error(run_hsr("render --heightmap /nonexistent/h.png", "heightmap-missing"), "/nonexistent/h.png");
    require_one_line_error(run_hsr("render --range 0:1,0:1 " + model("cube.obj"), "range-alone"), "--range goes with");
}

// ---------------------------------------------------------------------------------------------
// hsr bench: bad input fails before anything is timed, and leaves existing files as they were.

namespace {

const std::string bench_models = std::string(" --models-dir ") + HSR_MODELS_DIR;

// A model that fails to load or to be viewed: its error is the last line, after nothing but the
// progress lines of loading, so nothing was timed.
void require_bench_error_before_timing(const Run& r, const std::string& expected) {
    INFO("stderr: " << r.err);
    CHECK(r.status == 1);
    const std::size_t error = r.err.find("hsr: error: ");
    REQUIRE(error != std::string::npos);
    CHECK(r.err.find('\n', error) + 1 == r.err.size());
    CHECK_THAT(r.err.substr(error), Catch::Contains(expected));
    std::istringstream before(r.err.substr(0, error));
    for (std::string line; std::getline(before, line);) CHECK(line.rfind("hsr bench: loading ", 0) == 0);
}

void require_bench_usage_error(const std::string& args, const std::string& tag, const std::string& expected) {
    const Run r = run_hsr("bench --quick" + bench_models + " " + args, tag);
    require_one_line_error(r, expected);
    CHECK(r.status == 2);
}

}  // namespace

TEST_CASE("cli: bench loads every model and makes its cameras before timing any", "[cli][bench]") {
    const fs::path csv = write_file("bench-kept.csv", "keep\n");
    const fs::path nan = write_file("bench-nan.obj", "v 0 0 0\nv nan 1 0\nv 1 0 0\nf 1 2 3\n");
    require_bench_error_before_timing(
        run_hsr("bench --models deep-63:cube," + nan.string() + bench_models + " --csv " + csv.string(), "bench-nan"),
        "bench-nan.obj:2: vertex coordinate 'nan' is not a finite number");
    // Loads, but no camera can view it in single precision.
    const fs::path huge = write_file("bench-huge.obj", "v 0 0 0\nv 1e38 1e38 0\nv -1e38 0 1e38\nf 1 2 3\n");
    require_bench_error_before_timing(
        run_hsr("bench --models deep-63:cube," + huge.string() + bench_models + " --csv " + csv.string(), "bench-huge"),
        "model '" + huge.string() + "': ");
    CHECK(slurp(csv) == "keep\n");
}

TEST_CASE("cli: bench writes its CSV and SVG only once the results are ready", "[cli][bench]") {
    const fs::path csv = write_file("bench-outputs.csv", "keep\n"), svg = scratch_dir() / "bench-outputs.svg";
    fs::remove(svg);
    const fs::path empty = write_file("bench-empty.obj", "");
    require_bench_error_before_timing(run_hsr("bench --csv " + csv.string() + " --svg " + svg.string() + " --models " +
                                                  empty.string() + bench_models, "bench-empty"),
                                      "bench-empty.obj");
    CHECK(slurp(csv) == "keep\n");
    CHECK_FALSE(fs::exists(svg));

    // Checked up front: one file for both (the SVG used to overwrite the CSV), or the other format's name.
    const fs::path same = write_file("bench-one-file.dat", "keep\n");
    require_bench_usage_error("--csv " + same.string() + " --svg " + same.string(), "bench-same",
                              "the name must end in .csv");
    CHECK(slurp(same) == "keep\n");
    require_bench_usage_error("--csv " + csv.string() + " --svg " + csv.string(), "bench-csv-svg",
                              "the name must end in .svg");

    const Run r = run_hsr("bench --quick --algorithms zbuffer --models cube --sizes 32 -r 1" + bench_models + " --csv " +
                              csv.string() + " --svg " + svg.string(), "bench-written");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(slurp(csv).rfind("algorithm,model,", 0) == 0);
    CHECK(slurp(svg).find("<svg xmlns=") < 100);  // after the XML declaration
}

TEST_CASE("cli: bench refuses arguments, an empty list and a size named twice", "[cli][bench]") {
    require_bench_usage_error("extra", "bench-extra", "unexpected argument 'extra'");
    require_bench_usage_error("bunny", "bench-bunny", "unexpected argument 'bunny'");
    require_bench_usage_error("--models ''", "bench-no-models", "--models: the list is empty");
    require_bench_usage_error("--models ,", "bench-comma", "--models: the list is empty");
    require_bench_usage_error("--algorithms ''", "bench-no-algorithms", "--algorithms: the list is empty");
    require_bench_usage_error("--sizes 64,64", "bench-size-twice", "size 64x64 is named twice");
    require_bench_usage_error("--sizes 512,512x512", "bench-square-twice", "size 512x512 is named twice");
}

TEST_CASE("cli: in a terminal, a bench error is printed on a line of its own, not after the progress bar",
          "[cli][bench]") {
    if (std::system("command -v script > /dev/null") != 0) {
        WARN("no script(1) to give hsr a terminal");
        return;
    }
    const fs::path nan = write_file("bench-terminal-nan.obj", "v 0 0 0\nv nan 1 0\nv 1 0 0\nf 1 2 3\n");
    const fs::path out = scratch_dir() / "bench-terminal.out";
    const std::string command = "timeout 60 script -qec '" + std::string(HSR_BINARY_DIR) + "/hsr bench --models cube," +
                                nan.string() + bench_models + "' /dev/null > " + out.string() + " < /dev/null";
    const int raw = std::system(command.c_str());
    CHECK((WIFEXITED(raw) && WEXITSTATUS(raw) == 1));  // script -e: hsr's status
    const std::string terminal = slurp(out);  // the bar is redrawn in place: "\r\033[K[###...] ..."
    INFO(terminal);
    const std::size_t error = terminal.find("hsr: error: ");
    REQUIRE(error != std::string::npos);
    REQUIRE(terminal.substr(0, error).find("loading") != std::string::npos);
    CHECK(terminal.compare(error - 4, 4, "\r\033[K") == 0);  // the bar cleared first
}
