// hsr bench and what it is built from: Loop subdivision (face counts known exactly: every level
// splits each triangle into four), the statistics (medians and quartiles worked out by hand), the
// table, CSV and plot writers (parsed back; the plot drawn on a recorder and as SVG and PNG), the timing loop through the real zbuffer plugin, and one small
// `hsr bench` run end to end.
#include "bench/bench_plot.hpp"
#include "bench/bench_report.hpp"
#include "bench/measure.hpp"
#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
#include "hsr/image.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/subdivide.hpp"
#include "test_models.hpp"

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

const fs::path models_dir = HSR_MODELS_DIR;

struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        std::random_device rd;
        path = fs::temp_directory_path() / ("hsr-test-bench-" + std::to_string(rd()) + "-" + std::to_string(counter++));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// Splits one CSV line, honouring double quotes ("" inside quotes is a quote).
std::vector<std::string> csv_split(const std::string& line) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') fields.back() += '"', ++i;
            else if (c == '"') quoted = false;
            else fields.back() += c;
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            fields.emplace_back();
        } else {
            fields.back() += c;
        }
    }
    return fields;
}

// A CSV file as rows of column name -> value.
std::vector<std::map<std::string, std::string>> parse_csv(const std::string& text) {
    const std::vector<std::string> lines = lines_of(text);
    REQUIRE(!lines.empty());
    const std::vector<std::string> header = csv_split(lines[0]);
    std::vector<std::map<std::string, std::string>> rows;
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::vector<std::string> fields = csv_split(lines[i]);
        REQUIRE(fields.size() == header.size());
        std::map<std::string, std::string> row;
        for (std::size_t k = 0; k < header.size(); ++k) row[header[k]] = fields[k];
        rows.push_back(row);
    }
    return rows;
}

std::size_t count_of(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + what.size())) ++n;
    return n;
}

bool edges_all_shared(const hsr::SceneData& s) {
    return std::none_of(s.edge_neighbors.begin(), s.edge_neighbors.end(),
                        [](int32_t n) { return n == HSR_NO_NEIGHBOR; });
}

hsr::bench::Result made_up_result(const std::string& algorithm, const std::string& model, uint64_t faces,
                                  double median_ms) {
    hsr::bench::Result r;
    r.algorithm = algorithm;
    r.model = model;
    r.width = r.height = 256;
    r.faces = r.stored_faces = static_cast<uint32_t>(faces);
    r.warmup = 1;
    r.repetitions = 3;
    r.visibility = hsr::bench::summarize({median_ms * 0.9, median_ms, median_ms * 1.5});
    r.shading = hsr::bench::summarize({1.0, 2.0, 3.0});
    r.total = hsr::bench::summarize({median_ms + 1.0, median_ms + 2.0, median_ms + 3.0});
    return r;
}

struct Run {
    int status = -1;
    std::string out, err;
};

Run run_hsr(const std::string& args, const fs::path& dir) {
    const fs::path out = dir / "out.txt", err = dir / "err.txt";
    const std::string command = "timeout 120 " + std::string(HSR_BINARY_DIR) + "/hsr " + args + " > " + out.string() +
                                " 2> " + err.string() + " < /dev/null";
    const int raw = std::system(command.c_str());
    Run r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

void require_one_line_error(const Run& r, const std::string& expected) {
    INFO("stderr: " << r.err);
    CHECK((r.status == 1 || r.status == 2));
    CHECK(r.err.rfind("hsr: error: ", 0) == 0);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_THAT(r.err, Contains(expected));
}

// What the plot draws, as drawn, for checking against the data.
struct RecordingCanvas : hsr::bench::PlotCanvas {
    struct Rect {
        Point corner;
        double width, height;
    };
    struct Marker {
        Point at;
        std::string color;
        bool hollow;
    };
    struct Text {
        Point at;
        std::string text;
        Font font;
    };
    std::vector<Rect> frames;
    std::vector<std::pair<std::vector<Point>, Pen>> polylines;
    std::vector<Marker> markers;
    std::vector<Text> texts;

    void fill(Point, double, double, const std::string&) override {}
    void frame(Point corner, double width, double height, const Pen&) override {
        frames.push_back({corner, width, height});
    }
    void segments(const std::vector<std::pair<Point, Point>>&, const Pen&) override {}
    void polyline(const std::vector<Point>& points, const Pen& pen) override { polylines.emplace_back(points, pen); }
    void marker(Point at, const std::string& color, bool hollow) override { markers.push_back({at, color, hollow}); }
    void text(Point at, const std::string& text, const Font& font) override { texts.push_back({at, text, font}); }

    std::size_t texts_reading(const std::string& text) const {
        return std::size_t(std::count_if(texts.begin(), texts.end(), [&](const Text& t) { return t.text == text; }));
    }
};

// The <path> elements of a Cairo SVG outside its glyph definitions, each as its properties: the
// style attribute's entries and the other attributes alike (Cairo versions write one or the other).
std::vector<std::map<std::string, std::string>> svg_paths(const std::string& svg) {
    const std::size_t defs_end = svg.find("</defs>");
    const std::string body = svg.substr(defs_end == std::string::npos ? 0 : defs_end);
    std::vector<std::map<std::string, std::string>> paths;
    const std::regex element_re(R"(<path\b[^>]*>)"), attribute_re(R"re(([\w:-]+)="([^"]*)")re");
    for (auto e = std::sregex_iterator(body.begin(), body.end(), element_re); e != std::sregex_iterator(); ++e) {
        const std::string element = e->str();
        std::map<std::string, std::string> properties;
        for (auto a = std::sregex_iterator(element.begin(), element.end(), attribute_re); a != std::sregex_iterator(); ++a)
            properties[(*a)[1]] = (*a)[2];
        std::istringstream style(properties["style"]);
        for (std::string entry; std::getline(style, entry, ';');) {
            const std::size_t colon = entry.find(':');
            if (colon == std::string::npos) continue;
            auto trim = [](std::string s) {
                s.erase(0, s.find_first_not_of(' '));
                s.erase(s.find_last_not_of(' ') + 1);
                return s;
            };
            properties[trim(entry.substr(0, colon))] = trim(entry.substr(colon + 1));
        }
        paths.push_back(properties);
    }
    return paths;
}

// An SVG colour, "rgb(12.2%,46.7%,70.6%)" or "#1f77b4", is the colour "#rrggbb".
bool same_color(const std::string& svg_color, const std::string& hex) {
    const unsigned long v = std::stoul(hex.substr(1), nullptr, 16);
    const double want[3] = {double(v >> 16 & 0xff), double(v >> 8 & 0xff), double(v & 0xff)};
    std::smatch m;
    const std::regex rgb_re(R"(rgb\(\s*([0-9.]+)%\s*,\s*([0-9.]+)%\s*,\s*([0-9.]+)%\s*\))");
    if (std::regex_match(svg_color, m, rgb_re)) {
        for (int k = 0; k < 3; ++k)
            if (std::fabs(std::stod(m[k + 1]) * 2.55 - want[k]) > 0.6) return false;
        return true;
    }
    return svg_color.size() == 7 && svg_color[0] == '#' && std::stoul(svg_color.substr(1), nullptr, 16) == v;
}

// The points a path's d visits with M and L (a circle's curves are C).
std::vector<std::pair<double, double>> path_vertices(const std::string& d) {
    std::vector<std::pair<double, double>> points;
    const std::regex move_re(R"(([ML])\s*(-?[0-9.]+)[ ,]+(-?[0-9.]+))");
    for (auto it = std::sregex_iterator(d.begin(), d.end(), move_re); it != std::sregex_iterator(); ++it)
        points.emplace_back(std::stod((*it)[2]), std::stod((*it)[3]));
    return points;
}

bool is_circle(const std::map<std::string, std::string>& path) {
    return path.count("d") && path.at("d").find('C') != std::string::npos;
}
std::string property(const std::map<std::string, std::string>& path, const std::string& name) {
    auto it = path.find(name);
    return it == path.end() ? "" : it->second;
}
// A series' line: stroked two pixels wide, not filled, in `color`, through `vertices` points.
std::size_t series_lines(const std::vector<std::map<std::string, std::string>>& paths, const std::string& color,
                         std::size_t vertices) {
    return std::size_t(std::count_if(paths.begin(), paths.end(), [&](const auto& p) {
        return !is_circle(p) && property(p, "fill") == "none" && property(p, "stroke-width") == "2" &&
               same_color(property(p, "stroke"), color) && path_vertices(property(p, "d")).size() == vertices;
    }));
}
// Markers filled with `color` (solid) or white with a `color` ring (hollow).
std::size_t markers(const std::vector<std::map<std::string, std::string>>& paths, const std::string& color,
                    bool hollow) {
    return std::size_t(std::count_if(paths.begin(), paths.end(), [&](const auto& p) {
        return is_circle(p) && (hollow ? same_color(property(p, "fill"), "#ffffff") &&
                                             same_color(property(p, "stroke"), color)
                                       : same_color(property(p, "fill"), color));
    }));
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Loop subdivision

TEST_CASE("subdivide: each Loop level makes four faces of one", "[bench][subdivide]") {
    struct Case {
        const char* file;
        uint32_t faces;
    };
    for (Case c : {Case{"cube.obj", 12}, Case{"tetrahedron.off", 4}, Case{"octahedron.ply", 8}}) {
        INFO(c.file);
        const hsr::SceneData base = hsr::load_model(models_dir / c.file);
        REQUIRE(base.triangle_count() == c.faces);
        const hsr::SceneData once = hsr::load_model_subdivided(models_dir / c.file, 1);
        const hsr::SceneData twice = hsr::load_model_subdivided(models_dir / c.file, 2);
        CHECK(once.triangle_count() == 4 * c.faces);
        CHECK(twice.triangle_count() == 16 * c.faces);
        // A closed mesh stays closed, and V - E + F = 2 still holds (E = 3F/2).
        CHECK(edges_all_shared(once));
        CHECK(edges_all_shared(twice));
        CHECK(int64_t(twice.vertex_count()) - int64_t(3 * twice.triangle_count() / 2) + int64_t(twice.triangle_count()) == 2);
        // Loop's new points are convex combinations of old ones: the surface stays inside the old
        // bounds, and shrinks away from the corners.
        for (int k = 0; k < 3; ++k) {
            CHECK(once.bounds_min[k] >= base.bounds_min[k] - 1e-5f);
            CHECK(once.bounds_max[k] <= base.bounds_max[k] + 1e-5f);
        }
        CHECK(once.object_names == base.object_names);
    }
}

TEST_CASE("subdivide: level 0 is the model as loaded, options apply after subdividing", "[bench][subdivide]") {
    const hsr::SceneData plain = hsr::load_model(models_dir / "cube.obj");
    const hsr::SceneData zero = hsr::load_model_subdivided(models_dir / "cube.obj", 0);
    CHECK(zero.positions == plain.positions);
    CHECK(zero.indices == plain.indices);

    hsr::MeshOptions options;
    options.transform = glm::mat4(2.0f);  // scale 2 about the origin
    options.transform[3][3] = 1.0f;
    options.color = {0.25f, 0.5f, 1.0f};
    options.name = "big cube";
    const hsr::SceneData unit = hsr::load_model_subdivided(models_dir / "cube.obj", 1);
    const hsr::SceneData big = hsr::load_model_subdivided(models_dir / "cube.obj", 1, options);
    REQUIRE(big.triangle_count() == unit.triangle_count());
    for (int k = 0; k < 3; ++k) {
        CHECK(big.bounds_min[k] == Approx(2.0f * unit.bounds_min[k]));
        CHECK(big.bounds_max[k] == Approx(2.0f * unit.bounds_max[k]));
    }
    CHECK(big.face_colors[0] == 0.25f);
    CHECK(big.face_colors[2] == 1.0f);
    CHECK(big.object_names == std::vector<std::string>{"big cube"});

    // The same through an already built scene.
    const hsr::SceneData again = hsr::loop_subdivide(plain, 1);
    CHECK(again.triangle_count() == 48);
    CHECK(again.positions == unit.positions);

    CHECK_THROWS_AS(hsr::load_model_subdivided(models_dir / "cube.obj", -1), hsr::Error);
    CHECK_THROWS_AS(hsr::load_model_subdivided(models_dir / "cube.obj", hsr::max_loop_levels + 1), hsr::Error);
    CHECK_THROWS_AS(hsr::load_model_subdivided(models_dir / "no-such-model.obj", 1), hsr::Error);
    CHECK_THROWS_AS(hsr::loop_subdivide(hsr::make_instance_grid(plain, {2, 1, 1, 0.25f, 0.0f}), 1), hsr::Error);
}

TEST_CASE("subdivide: the bunny once: 69,666 faces become 278,664", "[bench][subdivide]") {
    const hsr::SceneData bunny = hsr::load_model(test_models::path("bunny.obj"));
    REQUIRE(bunny.triangle_count() == 69666);
    const hsr::SceneData fine = hsr::load_model_subdivided(models_dir / "bunny.obj", 1);
    CHECK(fine.triangle_count() == 4 * 69666);
}

// ---------------------------------------------------------------------------------------------
// Statistics

TEST_CASE("bench: median, quartiles and range", "[bench][stats]") {
    using hsr::bench::summarize;
    const hsr::bench::Summary odd = summarize({5.0, 1.0, 3.0});
    CHECK(odd.count == 3);
    CHECK(odd.median == 3.0);
    CHECK(odd.min == 1.0);
    CHECK(odd.max == 5.0);
    CHECK(odd.q1 == 2.0);  // halfway between 1 and 3
    CHECK(odd.q3 == 4.0);

    const hsr::bench::Summary even = summarize({4.0, 2.0, 1.0, 3.0});
    CHECK(even.median == 2.5);
    CHECK(even.q1 == 1.75);
    CHECK(even.q3 == 3.25);
    CHECK(even.iqr() == 1.5);

    // One wild sample moves the median not at all and the quartiles little: why medians.
    const hsr::bench::Summary noisy = summarize({10.0, 10.2, 9.9, 10.1, 95.0});
    CHECK(noisy.median == 10.1);
    CHECK(noisy.max == 95.0);
    CHECK(noisy.q3 == Approx(10.2));

    const hsr::bench::Summary one = summarize({7.5});
    CHECK(one.median == 7.5);
    CHECK(one.q1 == 7.5);
    CHECK(one.q3 == 7.5);

    CHECK(hsr::bench::quantile({0.0, 10.0}, 0.3) == Approx(3.0));
    CHECK_THROWS_AS(summarize({}), hsr::Error);
    CHECK_THROWS_AS(summarize({1.0, std::nan("")}), hsr::Error);
}

// ---------------------------------------------------------------------------------------------
// Reports

TEST_CASE("bench: CSV has one row per measurement and every counter", "[bench][csv]") {
    hsr::bench::Result a = made_up_result("zbuffer", "cube", 12, 0.5);
    a.counters = {{"pixels-depth-tested", 1000}, {"pixels-written", 600}};
    a.depth_complexity = 2.0;
    a.depth_complexity_max = 3;
    hsr::bench::Result b = made_up_result("octree-zbuffer", "deep, \"5\"", 5000, 2.0);
    b.counters = {{"pixels-depth-tested", 400}, {"octree-nodes-culled", 17}};
    b.build_ms = 1.25;
    b.build_calls = 1;
    b.layers = 5;
    b.instances = 40;
    b.memory.before = uint64_t(50) << 20;
    b.memory.peak = uint64_t(80) << 20;

    std::ostringstream out;
    hsr::bench::write_csv(out, {a, b});
    const auto rows = parse_csv(out.str());
    REQUIRE(rows.size() == 2);
    CHECK(rows[0].at("algorithm") == "zbuffer");
    CHECK(rows[0].at("model") == "cube");
    CHECK(rows[0].at("faces") == "12");
    CHECK(rows[0].at("width") == "256");
    CHECK(std::stod(rows[0].at("depth_complexity")) == 2.0);
    CHECK(rows[0].at("depth_complexity_max") == "3");
    CHECK(std::stod(rows[0].at("visibility_median_ms")) == 0.5);
    CHECK(std::stod(rows[0].at("visibility_min_ms")) == Approx(0.45));
    CHECK(std::stod(rows[0].at("visibility_max_ms")) == 0.75);
    CHECK(std::stod(rows[0].at("shading_q1_ms")) == 1.5);
    CHECK(std::stod(rows[0].at("total_median_ms")) == 2.5);
    CHECK(rows[0].at("pixels-depth-tested") == "1000");
    CHECK(rows[0].at("pixels-written") == "600");
    CHECK(rows[0].at("octree-nodes-culled").empty());  // not reported: empty, not 0
    CHECK(rows[1].at("model") == "deep, \"5\"");      // quoted and read back intact
    CHECK(rows[1].at("depth_complexity").empty());   // not measured
    CHECK(std::stod(rows[1].at("build_ms")) == 1.25);
    CHECK(rows[1].at("build_calls") == "1");
    CHECK(rows[1].at("layers") == "5");
    CHECK(rows[1].at("pixels-written").empty());
    CHECK(rows[1].at("octree-nodes-culled") == "17");
    CHECK(rows[0].at("peak_memory_mb").empty());  // not measured
    CHECK(std::stod(rows[1].at("peak_memory_mb")) == 80.0);
    CHECK(std::stod(rows[1].at("memory_before_mb")) == 50.0);

    CHECK(hsr::bench::csv_field("plain") == "plain");
    CHECK(hsr::bench::csv_field("a,b") == "\"a,b\"");
    CHECK(hsr::bench::csv_field("say \"hi\"") == "\"say \"\"hi\"\"\"");
}

TEST_CASE("bench: the table has algorithms down and models across", "[bench][table]") {
    std::vector<hsr::bench::Result> results = {made_up_result("zbuffer", "cube", 12, 0.5),
                                               made_up_result("zbuffer", "bunny", 69666, 12.0),
                                               made_up_result("octree-zbuffer", "cube", 12, 0.8),
                                               made_up_result("octree-zbuffer", "bunny", 69666, 9.0)};
    results[3].build_ms = 40.0;
    results[3].memory.before = uint64_t(100) << 20;
    results[3].memory.peak = uint64_t(130) << 20;
    const std::string table = hsr::bench::format_table(results);
    const std::vector<std::string> lines = lines_of(table);
    REQUIRE(lines.size() > 5);
    CHECK_THAT(lines[0], Contains("256x256"));
    CHECK_THAT(lines[0], Contains("median [min-max] of 3 runs after 1 warm-up"));
    CHECK(lines[1].find("cube") < lines[1].find("bunny"));
    CHECK_THAT(table, Contains("69,666"));
    // zbuffer's row: 0.500 [0.450-0.750] under cube, 12.0 [10.8-18.0] under bunny.
    const auto zrow = std::find_if(lines.begin(), lines.end(), [](const std::string& l) { return l.rfind("zbuffer ", 0) == 0; });
    REQUIRE(zrow != lines.end());
    CHECK_THAT(*zrow, Contains("0.500 [0.450-0.750]"));
    CHECK_THAT(*zrow, Contains("12.0 [10.8-18.0]"));
    CHECK(zrow->find("0.500") < zrow->find("12.0"));
    CHECK_THAT(table, Contains("build time"));
    CHECK_THAT(table, Contains("40.0"));
    CHECK_THAT(table, Contains("peak memory, MB"));
    CHECK_THAT(table, Contains("130 (+30)"));
}

TEST_CASE("bench: the plot has labelled log axes, a legend and one line per algorithm", "[bench][plot]") {
    CHECK(hsr::bench::decade_ticks(3, 2000) == std::vector<double>{1, 10, 100, 1000, 10000});
    CHECK(hsr::bench::decade_ticks(10, 100) == std::vector<double>{10, 100});
    CHECK(hsr::bench::decade_ticks(0.05, 0.5) == std::vector<double>{0.01, 0.1, 1});
    CHECK(hsr::bench::tick_label(1000) == "1k");
    CHECK(hsr::bench::tick_label(100000) == "100k");
    CHECK(hsr::bench::tick_label(1e6) == "1M");
    CHECK(hsr::bench::tick_label(0.01) == "0.01");
    CHECK(hsr::bench::tick_label(20) == "20");

    const std::vector<hsr::bench::Result> results = {
        made_up_result("zbuffer", "cube", 12, 0.05),      made_up_result("zbuffer", "bunny", 69666, 12.0),
        made_up_result("zbuffer", "deep-20", 944640, 150.0), made_up_result("a<b&c", "cube", 12, 0.08),
        made_up_result("a<b&c", "bunny", 69666, 10.0),    made_up_result("a<b&c", "deep-20", 944640, 20.0)};
    const std::vector<hsr::bench::LogLogPlot> plots = hsr::bench::plot_results(results);
    REQUIRE(plots.size() == 1);  // one resolution
    const hsr::bench::LogLogPlot& plot = plots[0];
    REQUIRE(plot.series.size() == 2);
    CHECK(plot.series[0].points.size() == 3);
    CHECK(plot.guides.size() == 3);
    CHECK(hsr::bench::picture_size(plots) == std::pair{900, 600});

    // What is drawn.
    RecordingCanvas canvas;
    hsr::bench::draw_plots(canvas, plots);
    CHECK(canvas.polylines.size() == 2);
    CHECK(canvas.markers.size() == 6 + 2);  // the points, and a marker per legend entry
    for (const char* text : {"zbuffer", "a<b&c", "faces drawn (log scale)", "render time, ms (log scale)",
                             "linear in faces", "cube", "bunny", "deep-20"})
        CHECK(canvas.texts_reading(text) == 1);
    for (const char* tick : {"10", "100", "1k", "10k", "100k", "1M", "0.01", "1", "1000"})
        CHECK(canvas.texts_reading(tick) >= 1);

    // Every data point inside the plot frame, and in the right order: more faces further right,
    // more time further up (smaller y).
    REQUIRE(canvas.frames.size() == 1);
    const auto [corner, fw, fh] = canvas.frames[0];
    const auto [fx, fy] = corner;
    std::vector<std::pair<double, double>> points;  // the series' markers, drawn before the legend's
    for (std::size_t i = 0; i < 6; ++i) points.push_back(canvas.markers[i].at);
    for (auto [x, y] : points) {
        CHECK(x >= fx);
        CHECK(x <= fx + fw);
        CHECK(y >= fy);
        CHECK(y <= fy + fh);
    }
    CHECK(points[0].first < points[1].first);   // zbuffer: cube, bunny, deep-20
    CHECK(points[1].first < points[2].first);
    CHECK(points[0].second > points[1].second);
    CHECK(points[1].second > points[2].second);
    // Log axes: 12 -> 69,666 -> 944,640 faces are 3.76 and 1.13 decades apart.
    CHECK((points[1].first - points[0].first) / (points[2].first - points[1].first) ==
          Approx(std::log10(69666.0 / 12.0) / std::log10(944640.0 / 69666.0)).epsilon(0.01));
    // ... and 0.05 -> 12 -> 150 ms 2.38 and 1.10 decades.
    CHECK((points[0].second - points[1].second) / (points[1].second - points[2].second) ==
          Approx(std::log10(12.0 / 0.05) / std::log10(150.0 / 12.0)).epsilon(0.01));

    // The SVG: each series' line through the points drawn, each point's marker in its colour.
    std::ostringstream svg_out;
    hsr::bench::write_plot(svg_out, plots, hsr::bench::PlotFormat::svg);
    const std::string svg = svg_out.str();
    CHECK(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\"") != std::string::npos);
    CHECK(std::regex_search(svg, std::regex(R"(<svg [^>]*width="900(px|pt)?" height="600(px|pt)?")")));
    CHECK(svg.find("</svg>") == svg.size() - 7);
    CHECK(svg.find("a<b") == std::string::npos);  // text is drawn, never copied raw into the markup
    CHECK(count_of(svg, "<g") == count_of(svg, "</g>"));
    const auto paths = svg_paths(svg);
    for (const auto& [line, pen] : canvas.polylines) {
        CHECK(series_lines(paths, pen.color, 3) == 1);
        bool drawn = false;  // through the recorded points
        for (const auto& p : paths)
            if (series_lines({p}, pen.color, 3) == 1) {
                const auto vertices = path_vertices(p.at("d"));
                drawn = true;
                for (std::size_t k = 0; k < 3; ++k)
                    drawn = drawn && std::fabs(vertices[k].first - line[k].first) < 0.01 &&
                            std::fabs(vertices[k].second - line[k].second) < 0.01;
            }
        CHECK(drawn);
        CHECK(markers(paths, pen.color, false) == 3 + 1);
    }
    // The labels as glyphs, one use of a glyph per character drawn.
    std::size_t characters = 0;
    for (const auto& text : canvas.texts)
        characters += std::size_t(std::count_if(text.text.begin(), text.text.end(), [](char c) { return c != ' '; }));
    CHECK(count_of(svg, "<use") >= characters);

    // The PNG: the picture's size, white behind, each point's marker in its series' colour.
    std::ostringstream png_out;
    hsr::bench::write_plot(png_out, plots, hsr::bench::PlotFormat::png);
    TempDir dir;
    {
        std::ofstream file(dir.path / "plot.png", std::ios::binary);
        file << png_out.str();
    }
    const hsr::Image image = hsr::read_png_rgb(dir.path / "plot.png");
    REQUIRE(image.width == 900);
    REQUIRE(image.height == 600);
    auto pixel_is = [&](double x, double y, const std::string& color) {
        const std::size_t at = 3 * (std::size_t(y) * image.width + std::size_t(x));
        const unsigned long v = std::stoul(color.substr(1), nullptr, 16);
        return std::abs(int(image.pixels[at]) - int(v >> 16 & 0xff)) <= 2 &&
               std::abs(int(image.pixels[at + 1]) - int(v >> 8 & 0xff)) <= 2 &&
               std::abs(int(image.pixels[at + 2]) - int(v & 0xff)) <= 2;
    };
    CHECK(pixel_is(2, 2, "#ffffff"));
    for (const auto& m : canvas.markers) {
        INFO("marker at " << m.at.first << "," << m.at.second);
        CHECK(pixel_is(m.at.first, m.at.second, m.hollow ? "#ffffff" : m.color));  // a ring is white inside
    }
}

TEST_CASE("bench: one plot per size, the deep scenes dashed in their algorithm's colour", "[bench][plot]") {
    std::vector<hsr::bench::Result> results;
    for (uint32_t size : {64u, 48u})
        for (auto [model, faces] : {std::pair{"cube", 12}, {"cube-loop", 48}, {"deep-3:cube", 576}}) {
            hsr::bench::Result r = made_up_result("zbuffer", model, uint64_t(faces), 0.01 * faces);
            r.width = 64;
            r.height = size;
            if (faces == 576) r.instances = 48;
            results.push_back(r);
        }
    const std::vector<hsr::bench::LogLogPlot> plots = hsr::bench::plot_results(results);
    REQUIRE(plots.size() == 2);
    CHECK(hsr::bench::picture_size(plots) == std::pair{900, 1200});  // stacked
    RecordingCanvas canvas;
    hsr::bench::draw_plots(canvas, plots);
    CHECK(canvas.texts_reading("Render time against face count, 64x64") == 1);
    CHECK(canvas.texts_reading("Render time against face count, 64x48") == 1);
    CHECK(canvas.polylines.size() == 4);
    CHECK(canvas.texts_reading("zbuffer") == 2);
    CHECK(canvas.texts_reading("deep scenes") == 2);
    CHECK(canvas.texts_reading("deep-3:cube") == 2);
    for (const auto& [line, pen] : canvas.polylines) {
        CHECK(pen.color == canvas.polylines[0].second.color);
        CHECK(pen.dash.empty() == (line.size() == 2));  // the single models solid, the deep scene dashed
    }
    // The second plot below the first.
    REQUIRE(canvas.frames.size() == 2);
    CHECK(canvas.frames[1].corner.second >= canvas.frames[0].corner.second + canvas.frames[0].height);
}

// ---------------------------------------------------------------------------------------------
// Scenes and timing

TEST_CASE("bench: model names", "[bench][models]") {
    using hsr::bench::parse_model_spec;
    const hsr::bench::ModelSpec cube = parse_model_spec("cube", models_dir);
    CHECK(cube.file == models_dir / "cube.obj");
    CHECK(cube.loop_levels == 0);
    CHECK(cube.layers == 0);
    CHECK(parse_model_spec("octahedron", models_dir).file == models_dir / "octahedron.ply");
    test_models::require_fetched();
    const hsr::bench::ModelSpec loop = parse_model_spec("bunny-loop", models_dir);
    CHECK(loop.file == models_dir / "bunny.obj");
    CHECK(loop.loop_levels == 1);
    CHECK(parse_model_spec("cube-loop3", models_dir).loop_levels == 3);
    const hsr::bench::ModelSpec deep = parse_model_spec("deep-20", models_dir);
    CHECK(deep.file == models_dir / "monkey.obj");
    CHECK(deep.layers == 20);
    const hsr::bench::ModelSpec deep_cube = parse_model_spec("deep-7:cube-loop", models_dir);
    CHECK(deep_cube.file == models_dir / "cube.obj");
    CHECK(deep_cube.layers == 7);
    CHECK(deep_cube.loop_levels == 1);
    const std::string path = (models_dir / "pyramid.stl").string();
    CHECK(parse_model_spec(path, models_dir).file == path);
    CHECK(parse_model_spec(path, models_dir).name == path);

    CHECK_THROWS_WITH(parse_model_spec("teapot", models_dir), Contains("unknown model 'teapot'"));
    CHECK_THROWS_WITH(parse_model_spec("deep-0", models_dir), Contains("layer count"));
    CHECK_THROWS_WITH(parse_model_spec("deep-x", models_dir), Contains("layer count"));
    CHECK_THROWS_WITH(parse_model_spec("deep-3:deep-2", models_dir), Contains("deep scenes"));
    CHECK_THROWS_WITH(parse_model_spec("cube-loop99", models_dir), Contains("Loop levels"));
    CHECK_THROWS_WITH(parse_model_spec("/no/such/file.obj", models_dir), Contains("does not exist"));
    CHECK_THROWS_AS(parse_model_spec("", models_dir), hsr::Error);
}

TEST_CASE("bench: a deep scene is a grid of instances whose front layer fills the view", "[bench][models]") {
    const hsr::SceneData cube = hsr::load_model(models_dir / "cube.obj");
    hsr::bench::DeepGrid grid;
    grid.yaw_jitter_degrees = 0;
    const hsr::SceneData deep = hsr::bench::make_deep_scene(cube, 6, grid);
    // A cube is as tall as wide: as many columns as rows.
    CHECK(deep.instances.size() == 4 * 4 * 6);
    CHECK(hsr::drawn_triangle_count(deep.view()) == 12 * 4 * 4 * 6);
    hsr::CameraSettings settings;
    settings.width = settings.height = 200;
    settings.zoom = hsr::bench::front_layer_zoom(deep, settings);
    CHECK(settings.zoom > 1.0f);
    // At that zoom the front layer's outer edges sit on the image border: the picture is covered
    // to its edges (the left and right columns of pixels see a cube at the middle of each row of
    // cubes), and depth complexity grows with the layers behind.
    const hsr_camera camera = hsr::make_orbit_camera(deep.bounds_min, deep.bounds_max, settings);
    const hsr::DepthComplexity dc = hsr::measure_depth_complexity(deep.view(), camera);
    CHECK(dc.covered_pixels > 0.6 * 200 * 200);
    CHECK(dc.mean_over_covered() > 2.0);

    const hsr::bench::BenchScene scene = hsr::bench::load_bench_scene(hsr::bench::parse_model_spec("deep-3:cube", models_dir));
    CHECK(scene.layers == 3);
    CHECK(scene.scene.instances.size() == 4 * 4 * 3);
    CHECK(scene.camera.zoom > 1.0f);
}

TEST_CASE("bench: an unknown model's message names the folder it looked in", "[bench][models]") {
    using hsr::bench::parse_model_spec;
    CHECK_THROWS_WITH(parse_model_spec("nonesuch", models_dir),
                      Contains("unknown model 'nonesuch' (known in folder " + models_dir.string() + "/: ") &&
                          Contains("cube, ") && Contains("also NAME-loop"));
    // As hsr bench names its default folder, and with a slash already at the end.
    CHECK_THROWS_WITH(parse_model_spec("nonesuch", "models"), Contains("(known in folder models/: "));
    CHECK_THROWS_WITH(parse_model_spec("nonesuch", models_dir.string() + "/"),
                      Contains("(known in folder " + models_dir.string() + "/: "));
    TempDir empty;
    CHECK_THROWS_WITH(parse_model_spec("nonesuch", empty.path), Contains("/: none; "));
}

TEST_CASE("bench: a model's camera at each size, refused by name when coordinates overflow it", "[bench][models]") {
    using hsr::bench::load_bench_scene;
    using hsr::bench::parse_model_spec;
    const hsr::bench::BenchScene deep = load_bench_scene(parse_model_spec("deep-3:cube", models_dir));
    const hsr_camera camera = hsr::bench::make_bench_camera(deep, 80, 60);
    hsr::CameraSettings settings = deep.camera;  // the deep scene's zoom, the size asked for
    settings.width = 80;
    settings.height = 60;
    const hsr_camera expected = hsr::make_orbit_camera(deep.scene.bounds_min, deep.scene.bounds_max, settings);
    CHECK(camera.width == 80);
    CHECK(camera.height == 60);
    CHECK(std::equal(std::begin(camera.view_projection), std::end(camera.view_projection),
                     std::begin(expected.view_projection)));

    TempDir dir;
    const fs::path huge = dir.path / "huge.obj";
    std::ofstream(huge) << "v 0 0 0\nv 1e38 1e38 0\nv -1e38 0 1e38\nf 1 2 3\n";
    const hsr::bench::BenchScene scene = load_bench_scene(parse_model_spec(huge.string(), models_dir));
    CHECK_THROWS_WITH(hsr::bench::make_bench_camera(scene, 64, 64),
                      Contains("model '" + huge.string() + "': ") && Contains("too large"));
}

TEST_CASE("bench: the timing loop, through the zbuffer plugin", "[bench][timing]") {
    hsr::PluginRegistry registry;
    registry.scan_directory(HSR_PLUGIN_DIR);
    hsr::HiddenSurfaceRemover remover(registry.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, "zbuffer"), {});
    hsr::LightingModel lighting(registry.find(HSR_KIND_LIGHTING_MODEL, "lambert"), {});
    const hsr::SceneData cube = hsr::load_model(models_dir / "cube.obj");
    const hsr_scene scene = cube.view();
    hsr::CameraSettings settings;
    settings.width = settings.height = 64;
    const hsr_camera camera = hsr::make_orbit_camera(cube.bounds_min, cube.bounds_max, settings);
    const std::vector<hsr_light> lights;
    const hsr_shading_context context = hsr::make_shading_context(camera, lights);

    hsr::bench::TimingSettings timing_settings;
    timing_settings.warmup = 2;
    timing_settings.repetitions = 4;
    std::vector<unsigned> seen;
    const hsr::bench::Timing timing = hsr::bench::time_frames(
        scene, camera, remover, lighting, context, timing_settings,
        [&](const hsr::bench::CallTiming& c) { seen.push_back(c.index); });
    CHECK(seen == std::vector<unsigned>{0, 1, 2, 3, 4, 5});
    REQUIRE(timing.calls.size() == 6);
    CHECK(timing.calls[1].warmup);
    CHECK_FALSE(timing.calls[2].warmup);
    REQUIRE(timing.render_ms.size() == 4);
    CHECK(timing.shading_ms.size() == 4);
    for (std::size_t i = 0; i < 4; ++i) {
        CHECK(timing.render_ms[i] == timing.calls[i + 2].visibility_ms);  // zbuffer builds nothing
        CHECK(timing.total_ms[i] == Approx(timing.render_ms[i] + timing.shading_ms[i]));
        CHECK(timing.render_ms[i] > 0.0);
    }
    CHECK(timing.build_calls == 0);
    // The counters are one frame's, not summed over the calls: each visible pixel written once.
    uint64_t shaded = 0, tested = 0;
    for (const auto& [name, value] : timing.counters) {
        if (name == "fragments-shaded") shaded = value;
        if (name == "pixels-depth-tested") tested = value;
    }
    CHECK(shaded > 0);
    CHECK(shaded < 64 * 64);
    CHECK(tested >= shaded);

    const hsr::bench::Result result = hsr::bench::make_result("zbuffer", "cube", scene, camera, timing, 2, std::nullopt);
    CHECK(result.faces == 12);
    CHECK(result.repetitions == 4);
    CHECK(result.visibility.median > 0.0);
    CHECK_FALSE(result.depth_complexity);

    timing_settings.repetitions = 0;
    CHECK_THROWS_AS(hsr::bench::time_frames(scene, camera, remover, lighting, context, timing_settings), hsr::Error);
}

TEST_CASE("bench: a plugin's build time is reported apart from its render time", "[bench][timing]") {
    hsr::PluginRegistry registry;
    registry.scan_directory(HSR_PLUGIN_DIR);
    const hsr::Plugin* octree = nullptr;
    for (const hsr::Plugin& p : registry.plugins())
        if (std::string(p.descriptor.name) == "octree-zbuffer") octree = &p;
    if (!octree) {
        WARN("octree-zbuffer plugin not built: nothing reports build-time-us");
        return;
    }
    hsr::HiddenSurfaceRemover remover(*octree, {});
    hsr::LightingModel lighting(registry.find(HSR_KIND_LIGHTING_MODEL, "lambert"), {});
    const hsr::SceneData deep = hsr::bench::make_deep_scene(hsr::load_model(models_dir / "cube.obj"), 4);
    hsr::CameraSettings settings;
    settings.width = settings.height = 96;
    settings.zoom = hsr::bench::front_layer_zoom(deep, settings);
    const hsr_camera camera = hsr::make_orbit_camera(deep.bounds_min, deep.bounds_max, settings);
    const std::vector<hsr_light> lights;
    const hsr_shading_context context = hsr::make_shading_context(camera, lights);
    hsr::bench::TimingSettings timing_settings;
    timing_settings.warmup = 1;
    timing_settings.repetitions = 3;
    const hsr::bench::Timing timing =
        hsr::bench::time_frames(deep.view(), camera, remover, lighting, context, timing_settings);
    // Built once, in the warm-up call, then reused: the timed calls report no build.
    CHECK(timing.build_calls == 1);
    CHECK(timing.calls[0].build_ms > 0.0);
    CHECK(timing.calls[0].build_ms <= timing.calls[0].visibility_ms);
    CHECK(timing.build_ms == timing.calls[0].build_ms);
    for (std::size_t i = 1; i < timing.calls.size(); ++i) CHECK(timing.calls[i].build_ms == 0.0);
    for (const auto& c : timing.counters) CHECK(c.first != "build-time-us");
}

TEST_CASE("bench: each measurement's peak memory, larger for a larger image", "[bench][timing][memory]") {
    if (hsr::bench::reset_peak_memory() == 0) {
        WARN("the peak resident size cannot be reset here (/proc/self/clear_refs): not measured");
        return;
    }
    hsr::PluginRegistry registry;
    registry.scan_directory(HSR_PLUGIN_DIR);
    hsr::LightingModel lighting(registry.find(HSR_KIND_LIGHTING_MODEL, "lambert"), {});
    const hsr::SceneData cube = hsr::load_model(models_dir / "cube.obj");
    const std::vector<hsr_light> lights;
    auto measure = [&](uint32_t size) {
        hsr::HiddenSurfaceRemover remover(registry.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, "zbuffer"), {});
        hsr::CameraSettings settings;
        settings.width = settings.height = size;
        const hsr_camera camera = hsr::make_orbit_camera(cube.bounds_min, cube.bounds_max, settings);
        const hsr_shading_context context = hsr::make_shading_context(camera, lights);
        hsr::bench::TimingSettings timing_settings;
        timing_settings.warmup = 0;
        timing_settings.repetitions = 1;
        const hsr::bench::Timing timing =
            hsr::bench::time_frames(cube.view(), camera, remover, lighting, context, timing_settings);
        return hsr::bench::make_result("zbuffer", "cube", cube.view(), camera, timing, 0, std::nullopt).memory;
    };
    const hsr::bench::PeakMemory small = measure(32);
    const hsr::bench::PeakMemory large = measure(2048);
    for (const hsr::bench::PeakMemory& m : {small, large}) {
        REQUIRE(m.known());
        CHECK(m.before > 0);
        CHECK(m.peak >= m.before);
        CHECK(m.peak < (uint64_t(16) << 30));  // a cube's frame is not 16 GB
    }
    // 2048 x 2048: the depth buffer alone is 16 MB, and the frame holds more per pixel than that.
    CHECK(large.added() >= uint64_t(2048) * 2048 * sizeof(float));
    CHECK(large.added() > small.added());
    CHECK(large.peak > small.peak);
}

// ---------------------------------------------------------------------------------------------
// The command

TEST_CASE("bench: hsr bench --quick writes a table, CSV, SVG and PNG", "[bench][cli]") {
    TempDir dir;
    const fs::path csv = dir.path / "bench.csv", svg = dir.path / "bench.svg", png = dir.path / "bench.png";
    const Run r = run_hsr("bench --quick --algorithms zbuffer --sizes 64,48x32 --repetitions 2 --models-dir " +
                              models_dir.string() + " --csv " + csv.string() + " --svg " + svg.string() +
                              " --png " + png.string(),
                          dir.path);
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);

    // The table on stdout: one block per size, the quick models across.
    CHECK_THAT(r.out, Contains("64x64: visibility time"));
    CHECK_THAT(r.out, Contains("48x32: visibility time"));
    CHECK_THAT(r.out, Contains("of 2 runs after 1 warm-up"));
    for (const char* model : {"cube", "octahedron", "cube-loop", "deep-3:cube"}) CHECK_THAT(r.out, Contains(model));
    // Progress on stderr, one line per step since stderr is not a terminal here.
    CHECK_THAT(r.err, Contains("hsr bench: [1/8] zbuffer on cube 64x64"));
    CHECK_THAT(r.err, Contains("hsr bench: [8/8] zbuffer on deep-3:cube 48x32"));

    const auto rows = parse_csv(slurp(csv));
    REQUIRE(rows.size() == 8);
    std::map<std::string, std::string> faces;
    for (const auto& row : rows) {
        CHECK(row.at("algorithm") == "zbuffer");
        CHECK(row.at("repetitions") == "2");
        CHECK(row.at("warmup") == "1");
        CHECK(std::stod(row.at("visibility_median_ms")) > 0.0);
        CHECK(std::stod(row.at("visibility_min_ms")) <= std::stod(row.at("visibility_median_ms")));
        CHECK(std::stod(row.at("visibility_median_ms")) <= std::stod(row.at("visibility_max_ms")));
        CHECK(std::stod(row.at("total_median_ms")) > 0.0);
        CHECK(std::stod(row.at("depth_complexity")) >= 1.0);
        CHECK(std::stoull(row.at("pixels-depth-tested")) > 0);
        CHECK(std::stoull(row.at("fragments-shaded")) > 0);
        faces[row.at("model")] = row.at("faces");
    }
    CHECK(faces["cube"] == "12");
    CHECK(faces["octahedron"] == "8");
    CHECK(faces["cube-loop"] == "48");           // Loop: 4 x 12
    CHECK(faces["deep-3:cube"] == "576");        // 4 x 4 x 3 cubes of 12
    CHECK(rows[0].at("width") == "64");
    CHECK(rows[1].at("width") == "48");
    CHECK(rows[1].at("height") == "32");
    for (const auto& row : rows)
        if (row.at("model") == "deep-3:cube") {
            CHECK(row.at("layers") == "3");
            CHECK(row.at("instances") == "48");
            CHECK(std::stod(row.at("depth_complexity")) > 2.0);
        }

    // One panel per size, stacked (what each holds: "one plot per size" above), each with
    // zbuffer's line through the three single models and a hollow marker for the deep scene.
    const std::string plot = slurp(svg);
    CHECK(plot.find("<svg") != std::string::npos);
    CHECK_THAT(plot, Contains("</svg>"));
    CHECK(std::regex_search(plot, std::regex(R"(<svg [^>]*width="900(px|pt)?" height="1200(px|pt)?")")));
    const auto paths = svg_paths(plot);
    CHECK(series_lines(paths, "#1f77b4", 3) == 2);
    CHECK(markers(paths, "#1f77b4", false) == 2 * (3 + 1));  // the points and the legend's
    CHECK(markers(paths, "#1f77b4", true) == 2);
    const hsr::Image picture = hsr::read_png_rgb(png);
    CHECK(picture.width == 900);
    CHECK(picture.height == 1200);
}

TEST_CASE("bench: bad input is a one-line error", "[bench][cli]") {
    TempDir dir;
    const std::string quick = "bench --quick --models-dir " + models_dir.string() + " ";
    require_one_line_error(run_hsr(quick + "--repetitions 0", dir.path), "--repetitions");
    require_one_line_error(run_hsr(quick + "--repetitions -3", dir.path), "--repetitions");
    require_one_line_error(run_hsr(quick + "--models cube,teapot", dir.path), "unknown model 'teapot'");
    require_one_line_error(run_hsr(quick + "--algorithms zbuffer,no-such-algorithm", dir.path), "no-such-algorithm");
    require_one_line_error(run_hsr(quick + "--algorithms zbuffer,zbuffer", dir.path), "twice");
    require_one_line_error(run_hsr(quick + "--sizes 0", dir.path), "--sizes");
    require_one_line_error(run_hsr(quick + "--sizes big", dir.path), "--sizes");
    require_one_line_error(run_hsr(quick + "--lighting nope", dir.path), "nope");
    require_one_line_error(run_hsr(quick + "--csv /no/such/dir/x.csv", dir.path), "/no/such/dir/x.csv");
    require_one_line_error(run_hsr(quick + "--png " + (dir.path / "plot.svg").string(), dir.path), ".png");
    const Run unknown_option = run_hsr("bench --frobnicate", dir.path);
    require_one_line_error(unknown_option, "frobnicate");
    CHECK(unknown_option.status == 2);
}
