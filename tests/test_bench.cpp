// hsr bench and what it is built from: Loop subdivision (face counts known exactly: every level
// splits each triangle into four), the statistics (medians and quartiles worked out by hand), the
// CSV and SVG writers (parsed back), the timing loop through the real zbuffer plugin, and one small
// `hsr bench` run end to end.
#include "hsr/bench.hpp"
#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
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
}

TEST_CASE("bench: the SVG plot has labelled log axes, a legend and one line per algorithm", "[bench][svg]") {
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
    std::ostringstream out;
    hsr::bench::write_svg(out, plot);
    const std::string svg = out.str();

    CHECK(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0) == 0);
    CHECK(svg.find("</svg>") == svg.size() - 7);
    CHECK(count_of(svg, "<polyline") == 2);
    CHECK(count_of(svg, "<circle") == 6 + 2);  // the points, and a marker per legend entry
    CHECK_THAT(svg, Contains(">zbuffer</text>"));
    CHECK_THAT(svg, Contains(">a&lt;b&amp;c</text>"));  // escaped
    CHECK(svg.find("a<b") == std::string::npos);
    CHECK_THAT(svg, Contains(">faces drawn (log scale)</text>"));
    CHECK_THAT(svg, Contains(">render time, ms (log scale)</text>"));
    CHECK_THAT(svg, Contains(">linear in faces</text>"));
    for (const char* tick : {">10<", ">100<", ">1k<", ">10k<", ">100k<", ">1M<", ">0.01<", ">1<", ">1000<"})
        CHECK_THAT(svg, Contains(tick));
    for (const char* model : {">cube</text>", ">bunny</text>", ">deep-20</text>"}) CHECK_THAT(svg, Contains(model));
    // Balanced tags: as many opening <g as closing.
    CHECK(count_of(svg, "<g") == count_of(svg, "</g>"));

    // Every data point inside the plot frame, and in the right order: more faces further right,
    // more time further up (smaller y).
    const std::regex frame_re(R"re(<rect x="([0-9.]+)" y="([0-9.]+)" width="([0-9.]+)" height="([0-9.]+)" fill="none")re");
    std::smatch frame;
    REQUIRE(std::regex_search(svg, frame, frame_re));
    const double fx = std::stod(frame[1]), fy = std::stod(frame[2]), fw = std::stod(frame[3]), fh = std::stod(frame[4]);
    const std::string series_part = svg.substr(svg.find("<g class=\"series\">"), svg.find("<g class=\"legend\"") - svg.find("<g class=\"series\">"));
    const std::regex circle_re(R"re(<circle cx="([0-9.]+)" cy="([0-9.]+)")re");
    std::vector<std::pair<double, double>> points;
    for (auto it = std::sregex_iterator(series_part.begin(), series_part.end(), circle_re); it != std::sregex_iterator(); ++it)
        points.emplace_back(std::stod((*it)[1]), std::stod((*it)[2]));
    REQUIRE(points.size() == 6);
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

// ---------------------------------------------------------------------------------------------
// The command

TEST_CASE("bench: hsr bench --quick writes a table, CSV and SVG", "[bench][cli]") {
    TempDir dir;
    const fs::path csv = dir.path / "bench.csv", svg = dir.path / "bench.svg";
    const Run r = run_hsr("bench --quick --algorithms zbuffer --sizes 64,48x32 --repetitions 2 --models-dir " +
                              models_dir.string() + " --csv " + csv.string() + " --svg " + svg.string(),
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

    const std::string plot = slurp(svg);
    CHECK(plot.rfind("<svg", 0) == 0);
    CHECK_THAT(plot, Contains("</svg>"));
    // One panel per size, each with a line through the single models and a dashed one through the
    // deep scene.
    CHECK_THAT(plot, Contains(">Render time against face count, 64x64</text>"));
    CHECK_THAT(plot, Contains(">Render time against face count, 48x32</text>"));
    CHECK(count_of(plot, "<polyline") == 4);
    CHECK(count_of(plot, ">zbuffer</text>") == 2);
    CHECK(count_of(plot, ">deep scenes</text>") == 2);
    CHECK_THAT(plot, Contains(">deep-3:cube</text>"));
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
    const Run unknown_option = run_hsr("bench --frobnicate", dir.path);
    require_one_line_error(unknown_option, "frobnicate");
    CHECK(unknown_option.status == 2);
}
