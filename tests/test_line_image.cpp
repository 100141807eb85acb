// Line drawings written through Cairo (hsr/line_image.hpp): what is drawn where, read back from the
// PNG; the SVG's structure; bad paths.
#include "hsr/error.hpp"
#include "hsr/image.hpp"
#include "hsr/line_image.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

// A 100 x 60 drawing: a visible horizontal crease at y = 20.5, a hidden one at y = 40.5, a visible
// silhouette at x = 80.5 (vertical).
hsr::LineDrawing sample_drawing() {
    hsr::LineDrawing d;
    d.width = 100;
    d.height = 60;
    d.segments.push_back({{10.0f, 20.5f}, {70.0f, 20.5f}, 0, HSR_EDGE_CREASE, 0});
    d.segments.push_back({{10.0f, 40.5f}, {70.0f, 40.5f}, 1, HSR_EDGE_CREASE, 2});
    d.segments.push_back({{80.5f, 5.0f}, {80.5f, 55.0f}, 2, HSR_EDGE_SILHOUETTE, 0});
    return d;
}

int darkness(const hsr::Image& image, int x, int y) {
    const uint8_t* p = &image.pixels[3 * (size_t(y) * image.width + size_t(x))];
    return 255 - (p[0] + p[1] + p[2]) / 3;
}

std::filesystem::path temp_file(const std::string& name) {
    return std::filesystem::temp_directory_path() / ("hsr-test-line-image-" + name);
}

}  // namespace

TEST_CASE("line image: visible lines drawn, hidden lines dashed or left out", "[line-image]") {
    const hsr::LineDrawing d = sample_drawing();
    hsr::LineStyle style;
    const auto png = temp_file("hidden.png");
    const hsr::LineImageStats stats = hsr::write_line_drawing(png, d, style);
    CHECK(stats.visible == 2);
    CHECK(stats.outline == 1);
    CHECK(stats.hidden == 0);
    const hsr::Image image = hsr::read_png_rgb(png);
    REQUIRE(image.width == 100);
    REQUIRE(image.height == 60);
    CHECK(darkness(image, 40, 20) > 150);  // on the visible crease
    CHECK(darkness(image, 40, 10) == 0);   // background
    CHECK(darkness(image, 80, 30) > 150);  // on the silhouette
    int hidden_ink = 0;
    for (int x = 12; x < 68; ++x) hidden_ink += darkness(image, x, 40);
    CHECK(hidden_ink == 0);  // left out

    style.hidden = hsr::HiddenLines::kDashed;
    const auto dashed_png = temp_file("dashed.png");
    CHECK(hsr::write_line_drawing(dashed_png, d, style).hidden == 1);
    const hsr::Image dashed = hsr::read_png_rgb(dashed_png);
    int inked = 0, blank = 0;
    for (int x = 12; x < 68; ++x) (darkness(dashed, x, 40) > 40 ? inked : blank) += 1;
    CHECK(inked > 15);  // dashes ...
    CHECK(blank > 10);  // ... and gaps
    // The silhouette is drawn heavier than the crease: more ink across it.
    int across_crease = 0, across_silhouette = 0;
    for (int k = -4; k <= 4; ++k) {
        across_crease += darkness(dashed, 40, 20 + k);
        across_silhouette += darkness(dashed, 80 + k, 30);
    }
    CHECK(across_silhouette > across_crease + 100);
    std::filesystem::remove(png);
    std::filesystem::remove(dashed_png);
}

TEST_CASE("line image: the SVG has one path per style, in pixel units", "[line-image]") {
    hsr::LineStyle style;
    style.hidden = hsr::HiddenLines::kDashed;
    const auto svg = temp_file("lines.svg");
    hsr::write_line_drawing(svg, sample_drawing(), style);
    std::ifstream in(svg);
    std::stringstream text;
    text << in.rdbuf();
    const std::string s = text.str();
    CHECK(s.find("width=\"100px\"") != std::string::npos);
    CHECK(s.find("stroke-dasharray") != std::string::npos);
    size_t paths = 0;
    for (size_t at = s.find("<path"); at != std::string::npos; at = s.find("<path", at + 1)) ++paths;
    CHECK(paths == 3);  // hidden, visible, outline
    CHECK(s.find("M 10 20.5 L 70 20.5") != std::string::npos);
    std::filesystem::remove(svg);
}

TEST_CASE("line image: bad paths are errors", "[line-image]") {
    CHECK_THROWS_WITH(hsr::write_line_drawing("drawing.jpg", sample_drawing(), {}), Catch::Contains(".svg or .png"));
    CHECK_THROWS_AS(hsr::write_line_drawing("/nonexistent-dir/x.svg", sample_drawing(), {}), hsr::Error);
    CHECK_THROWS_AS(hsr::write_line_drawing("/nonexistent-dir/x.png", sample_drawing(), {}), hsr::Error);
    CHECK(hsr::is_line_drawing_path("a/B.SVG"));
    CHECK(!hsr::is_line_drawing_path("a.pdf"));
}
