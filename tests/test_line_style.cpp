// Line style of hidden-line drawings (--line-color, --line-width): the colour of the pixels on a
// line, line widths measured across a horizontal line, the SVG's stroke attributes, the default
// ink against light and dark backgrounds, and options of the other family refused.
#include "cli_support.hpp"
#include "hsr/image.hpp"
#include "hsr/line_image.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

namespace fs = std::filesystem;

namespace {

using cli::require_one_line_error;
using cli::run_hsr;

// A square [16, 48]^2 facing a 64x64 pixel camera: its four edges are boundaries (the outline). A
// file per tag: ctest runs the test cases in parallel.
fs::path square_scene(const std::string& tag) {
    return cli::write_file(tag + ".scene",
                           "camera pixel\nsize 64 64\npolygon\n  color 0.5 0.5 0.5\n"
                           "  vertex 16 16 0\n  vertex 48 16 0\n  vertex 48 48 0\n  vertex 16 48 0\n");
}

hsr::Image draw(const std::string& options, const std::string& tag) {
    const fs::path png = cli::scratch_dir() / (tag + ".png");
    const cli::Run r = run_hsr("render " + square_scene(tag).string() + " -a appel " + options + " -o " + png.string(), tag);
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);
    return hsr::read_png_rgb(png);
}

const uint8_t* pixel(const hsr::Image& image, uint32_t x, uint32_t y) {
    return &image.pixels[3 * (size_t(y) * image.width + x)];
}

// The ink across column x near window row y0 (the square's top edge is at window y 16): the sum
// over rows of how far each pixel's green channel went from the white background toward the red
// ink's 0. For an anti-aliased straight line this is its width.
double measured_width(const hsr::Image& image, uint32_t x, uint32_t y0) {
    double sum = 0;
    for (uint32_t y = y0 - 10; y <= y0 + 10; ++y) sum += (255.0 - pixel(image, x, y)[1]) / 255.0;
    return sum;
}

}  // namespace

TEST_CASE("line style: the pixels on a line have --line-color", "[lines][line-style]") {
    const hsr::Image image = draw("--line-color '#ff0000' --line-width 3", "red-lines");
    // The top edge at window y = 16 drawn 6 pixels wide (the outline is twice --line-width): rows
    // 13 to 18 are wholly inside it.
    for (uint32_t y = 14; y <= 17; ++y) {
        const uint8_t* p = pixel(image, 32, y);
        CHECK(int(p[0]) == 255);
        CHECK(int(p[1]) == 0);
        CHECK(int(p[2]) == 0);
    }
    const uint8_t* inside = pixel(image, 32, 32);  // the face itself is not painted: background
    CHECK((int(inside[0]) == 255 && int(inside[1]) == 255 && int(inside[2]) == 255));
}

TEST_CASE("line style: --line-width measured across a horizontal line", "[lines][line-style]") {
    for (double width : {0.5, 1.0, 2.0, 3.5}) {
        INFO("--line-width " << width);
        const hsr::Image image =
            draw("--line-color 1/0/0 --line-width " + std::to_string(width), "width-" + std::to_string(int(width * 10)));
        for (uint32_t x : {24u, 32u, 40u}) CHECK(measured_width(image, x, 16) == Approx(2 * width).margin(0.08));
    }
    // Without --line-width: 1 pixel, the outline 2.
    const hsr::Image plain = draw("--line-color 1/0/0", "width-default");
    CHECK(measured_width(plain, 32, 16) == Approx(2.0).margin(0.08));
}

TEST_CASE("line style: the SVG's strokes have the colour and widths", "[lines][line-style]") {
    const std::string cube = std::string(HSR_MODELS_DIR) + "/cube.obj";
    const fs::path svg = cli::scratch_dir() / "styled.svg";
    REQUIRE(run_hsr("render " + cube + " -a appel --yaw 30 --pitch 20 --hidden dashed --line-color '#0000ff' "
                    "--line-width 2.5 --background 1/1/1 -o " + svg.string(), "styled-svg").status == 0);
    const std::string text = cli::slurp(svg);
    CHECK_THAT(text, Catch::Contains("stroke-width:2.5;") && Catch::Contains("stroke-width:5;") &&
                         Catch::Contains("stroke:rgb(0%,0%,100%)"));
    // Hidden lines: halfway to the white background, dashed, 0.75 of the width, dashes scaled.
    CHECK_THAT(text, Catch::Contains("stroke:rgb(50%,50%,100%)") && Catch::Contains("stroke-width:1.875;") &&
                         Catch::Contains("stroke-dasharray:10,7.5"));
}

TEST_CASE("line style: the default ink contrasts with the background", "[lines][line-style]") {
    const hsr::Image light = draw("", "ink-on-white");
    const hsr::Image dark = draw("--background 0.1/0.1/0.12", "ink-on-dark");
    const uint8_t* on_light = pixel(light, 32, 16);
    const uint8_t* on_dark = pixel(dark, 32, 16);
    CHECK(int(on_light[0]) < 60);
    CHECK(int(on_dark[0]) > 200);
    CHECK(std::abs(int(pixel(dark, 2, 2)[0]) - 26) <= 1);  // the background itself, 0.1
    CHECK(hsr::relative_luminance(glm::vec3(1.0f)) == Approx(1.0f));
    CHECK(hsr::relative_luminance(glm::vec3(0.0f)) == 0.0f);
}

TEST_CASE("line style: options of the other family and bad values are one-line errors", "[lines][line-style][cli]") {
    const std::string model = std::string(HSR_MODELS_DIR) + "/cube.obj";
    for (const char* algorithm : {"appel", "roberts", "floating-horizon"}) {
        INFO(algorithm);
        const std::string lines = "render " + model + " -a " + algorithm + " -o x.svg ";
        require_one_line_error(run_hsr(lines + "--color 1/0/0", "lines-color"), "--color is for hidden-surface plugins");
        require_one_line_error(run_hsr(lines + "--samples 4", "lines-samples"), "--samples is for hidden-surface plugins");
        require_one_line_error(run_hsr(lines + "--light dir:0,0,1", "lines-light"), "--light is for hidden-surface plugins");
    }
    const std::string lines = "render " + model + " -a appel -o x.svg ";
    for (const char* bad : {"0", "-1", "65", "nan"})
        require_one_line_error(run_hsr(lines + "--line-width " + bad, "line-width-bad"), "--line-width");
    require_one_line_error(run_hsr(lines + "--line-color purple", "line-color-bad"), "--line-color");
    const std::string surface = "render " + model + " -o x.png ";
    require_one_line_error(run_hsr(surface + "--line-color 1/0/0", "surface-line-color"),
                           "--line-color is for hidden-line plugins");
    require_one_line_error(run_hsr(surface + "--line-width 2", "surface-line-width"),
                           "--line-width is for hidden-line plugins");
}
