// hsr bench with plugins that crash, abort, call exit() or hang: each such cell is marked with how
// its worker process ended, in the table, the CSV and the plot, and every other cell is timed. The
// misbehaving plugins are tests/plugins/misbehaving.cpp's; their faults are known by construction.
#include "bench/bench_plot.hpp"
#include "bench/bench_report.hpp"
#include "bench/bench_worker.hpp"
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// A CSV without quoted fields (the names below have no comma) as rows of column -> value.
std::vector<std::map<std::string, std::string>> parse_simple_csv(const std::string& text) {
    auto split = [](const std::string& line) {
        std::vector<std::string> fields(1);
        for (char c : line) {
            if (c == ',') fields.emplace_back();
            else fields.back() += c;
        }
        return fields;
    };
    const std::vector<std::string> lines = lines_of(text);
    REQUIRE(!lines.empty());
    const std::vector<std::string> header = split(lines[0]);
    std::vector<std::map<std::string, std::string>> rows;
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::vector<std::string> fields = split(lines[i]);
        REQUIRE(fields.size() == header.size());
        std::map<std::string, std::string> row;
        for (std::size_t k = 0; k < header.size(); ++k) row[header[k]] = fields[k];
        rows.push_back(row);
    }
    return rows;
}

// The table's row of an algorithm in its first block: the first line that starts with the label.
std::string table_row(const std::string& table, const std::string& label) {
    for (const std::string& line : lines_of(table))
        if (line.rfind(label + " ", 0) == 0) return line;
    return "";
}

hsr::bench::Result cell(const std::string& algorithm, const std::string& model, uint64_t faces) {
    hsr::bench::Result r;
    r.algorithm = algorithm;
    r.model = model;
    r.width = r.height = 64;
    r.faces = faces;
    return r;
}

hsr::bench::Result timed_cell(const std::string& algorithm, const std::string& model, uint64_t faces, double ms) {
    hsr::bench::Result r = cell(algorithm, model, faces);
    r.warmup = 1;
    r.repetitions = 3;
    r.visibility = r.shading = r.total = hsr::bench::summarize({ms, ms, ms});
    return r;
}

}  // namespace

TEST_CASE("bench isolation: how a worker that ended mid-cell is marked", "[bench][isolation]") {
    using hsr::bench::fault_mark;
    // The line hsr/plugin_faults.hpp makes the worker write comes first...
    CHECK(fault_mark("plugin 'x' crashed in render (SIGSEGV)", "was killed by SIGSEGV") == "crashed (SIGSEGV)");
    CHECK(fault_mark("plugin 'x' crashed in create (SIGBUS)", "was killed by SIGBUS") == "crashed (SIGBUS)");
    CHECK(fault_mark("plugin 'x' aborted in render (SIGABRT)", "was killed by SIGABRT") == "aborted (SIGABRT)");
    // ... as the status of a worker whose plugin called exit(0) is the fault reporter's, not the plugin's.
    CHECK(fault_mark("plugin 'it's' called exit(0) in render", "exited with status 3") == "exited (status 0)");
    // Without it, how the process ended.
    CHECK(fault_mark(std::nullopt, "was killed by SIGSEGV") == "crashed (SIGSEGV)");
    CHECK(fault_mark(std::nullopt, "was killed by SIGABRT") == "aborted (SIGABRT)");
    CHECK(fault_mark(std::nullopt, "was killed by SIGKILL") == "killed (SIGKILL)");
    CHECK(fault_mark(std::nullopt, "exited with status 0") == "exited (status 0)");
}

TEST_CASE("bench isolation: a cell without a time in the table, CSV and plot", "[bench][isolation]") {
    hsr::bench::Result crashed = cell("segv", "cube", 12);
    crashed.fault = "crashed (SIGSEGV)";
    crashed.fault_detail = "plugin 'segv' crashed in render (SIGSEGV)";
    const std::vector<hsr::bench::Result> results = {timed_cell("zbuffer", "cube", 12, 2.5), crashed,
                                                     timed_cell("zbuffer", "bunny", 69666, 10.0),
                                                     timed_cell("segv", "bunny", 69666, 12.0)};

    const std::string table = hsr::bench::format_table(results);
    CHECK_THAT(table_row(table, "segv"), Contains("crashed (SIGSEGV)") && Contains("12.0 [12.0-12.0]"));
    CHECK_THAT(table, Contains("crashed (SIGSEGV): segv on cube: plugin 'segv' crashed in render (SIGSEGV)\n"));

    std::ostringstream csv;
    hsr::bench::write_csv(csv, results);
    const auto rows = parse_simple_csv(csv.str());
    REQUIRE(rows.size() == 4);
    CHECK(rows[0].at("status") == "measured");
    CHECK(rows[0].at("visibility_median_ms") == "2.5000");
    CHECK(rows[1].at("status") == "crashed (SIGSEGV)");
    CHECK(rows[1].at("reason") == "plugin 'segv' crashed in render (SIGSEGV)");
    CHECK(rows[1].at("faces") == "12");
    for (const char* column : {"visibility_median_ms", "total_max_ms", "build_ms", "peak_memory_mb"})
        CHECK(rows[1].at(column).empty());

    // One panel: zbuffer's line through both models, segv's point on the bunny only, and a cross
    // in segv's colour at the cube's face count.
    const std::vector<hsr::bench::LogLogPlot> plots = hsr::bench::plot_results(results);
    REQUIRE(plots.size() == 1);
    const hsr::bench::LogLogPlot& plot = plots[0];
    REQUIRE(plot.series.size() == 2);
    CHECK(plot.series[0].points.size() == 2);
    REQUIRE(plot.series[1].points.size() == 1);
    CHECK(plot.series[1].points[0].first == 69666.0);
    REQUIRE(plot.misses.size() == 1);
    CHECK(plot.misses[0].x == 12.0);
    CHECK(plot.misses[0].color == plot.series[1].color);
    CHECK_FALSE(plot.miss_label.empty());

    // An algorithm with no time at all keeps its colour in the legend.
    hsr::bench::Result hung = cell("hangs", "cube", 12);
    hung.fault = "timed out";
    const auto only_misses = hsr::bench::plot_results({timed_cell("zbuffer", "cube", 12, 2.5), hung});
    REQUIRE(only_misses.size() == 1);
    REQUIRE(only_misses[0].series.size() == 2);
    CHECK(only_misses[0].series[1].label == "hangs");
    CHECK(only_misses[0].series[1].points.empty());
    CHECK(only_misses[0].misses.at(0).color == only_misses[0].series[1].color);
}

TEST_CASE("bench isolation: misbehaving plugins mark their cells, the others are timed", "[bench][isolation][cli]") {
    const fs::path csv = cli::scratch_dir() / "isolation.csv", svg = cli::scratch_dir() / "isolation.svg";
    const std::string common = std::string("bench --plugin-path ") + HSR_MISBEHAVING_PLUGIN_DIR + " --models-dir " +
                               HSR_MODELS_DIR + " --models cube,octahedron --sizes 32 -r 2 -w 1 --cell-time-limit 2 ";
    // Crashes in create on its own; the others are told what to do in render.
    const std::vector<std::pair<std::string, std::string>> expected = {
        {"zbuffer", "measured"},
        {"crashes-in-create", "crashed (SIGSEGV)"},
        {"misbehaving:fault=segfault", "crashed (SIGSEGV)"},
        {"misbehaving:fault=abort", "aborted (SIGABRT)"},
        {"misbehaving:fault=exit", "exited (status 0)"},
        {"hangs-in-render", "timed out"},
        {"octree-zbuffer", "measured"},
    };
    std::string algorithms;
    for (const auto& [label, status] : expected) algorithms += " -a " + label;
    // A generous limit: two time-outs of 2 s each and a few workers started.
    const cli::Run r = cli::run_hsr(common + algorithms + " --csv " + csv.string() + " --svg " + svg.string(),
                                    "isolation", 120);
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);

    for (const auto& [label, status] : expected) {
        INFO(label);
        const std::string row = table_row(r.out, label);
        if (status == "measured") {
            CHECK_THAT(row, Contains("["));
            CHECK(row.find("n/a") == std::string::npos);
        } else {
            CHECK(row.find(status) != row.rfind(status));  // cube and octahedron
        }
    }
    CHECK_THAT(r.out, Contains("timed out: hangs-in-render on cube: "));

    const auto rows = parse_simple_csv(cli::slurp(csv));
    REQUIRE(rows.size() == 2 * expected.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const auto& [label, status] = expected[i % expected.size()];
        INFO(label);
        CHECK(rows[i].at("algorithm") == label);
        CHECK(rows[i].at("model") == (i < expected.size() ? "cube" : "octahedron"));
        CHECK(rows[i].at("status") == status);
        if (status == "measured") {
            CHECK(std::stod(rows[i].at("visibility_median_ms")) > 0.0);
            CHECK(rows[i].at("repetitions") == "2");
        } else {
            CHECK(rows[i].at("visibility_median_ms").empty());
            CHECK_FALSE(rows[i].at("reason").empty());
        }
    }
    // A plugin that wrote the fault line names itself and the call.
    for (const auto& row : rows)
        if (row.at("algorithm") == "crashes-in-create")
            CHECK(row.at("reason") == "plugin 'crashes-in-create' crashed in create (SIGSEGV)");
    CHECK_THAT(cli::slurp(svg), Contains("</svg>"));
}

TEST_CASE("bench isolation: the default list of every plugin found survives the bad ones", "[bench][isolation][cli]") {
    // The study as the issue ran it: no -a, so the misbehaving folder's plugins are in the list.
    const cli::Run r = cli::run_hsr(std::string("bench --plugin-path ") + HSR_MISBEHAVING_PLUGIN_DIR +
                                        " --models-dir " + HSR_MODELS_DIR +
                                        " --models cube --sizes 16 -r 1 -w 0 --cell-time-limit 2",
                                    "isolation-default", 120);
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(table_row(r.out, "zbuffer"), !Contains("n/a"));
    CHECK_THAT(table_row(r.out, "crashes-in-create"), Contains("crashed (SIGSEGV)"));
    CHECK_THAT(table_row(r.out, "hangs-in-render"), Contains("timed out"));
}

TEST_CASE("bench isolation: after a time-out, no larger cell of that algorithm is timed", "[bench][isolation][cli]") {
    // octahedron 8 triangles, cube 12, tetrahedron 4: the plugin runs out of time on octahedron at
    // 16x16 and on tetrahedron at 16x16, and every other cell of it is at least as large as one of them.
    const fs::path csv = cli::scratch_dir() / "isolation-skipped.csv";
    const cli::Run r = cli::run_hsr(std::string("bench --plugin-path ") + HSR_MISBEHAVING_PLUGIN_DIR + " --models-dir " +
                                        HSR_MODELS_DIR +
                                        " --models octahedron,cube,tetrahedron --sizes 16,24 -r 1 -w 0 "
                                        "--cell-time-limit 2 -a zbuffer -a hangs-in-render --csv " + csv.string(),
                                    "isolation-skipped", 120);
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);
    struct Expected {
        const char* model;
        const char* size;
        const char* status;
        const char* reason;
    };
    const Expected expected[] = {
        {"octahedron", "16", "timed out", "no end within 2 s (--cell-time-limit)"},
        {"octahedron", "24", "skipped", "timed out on octahedron at 16x16 (a cell no larger)"},
        {"cube", "16", "skipped", "timed out on octahedron at 16x16 (a cell no larger)"},
        {"cube", "24", "skipped", "timed out on octahedron at 16x16 (a cell no larger)"},
        {"tetrahedron", "16", "timed out", "no end within 2 s (--cell-time-limit)"},
        {"tetrahedron", "24", "skipped", "timed out on tetrahedron at 16x16 (a cell no larger)"},
    };
    const auto rows = parse_simple_csv(cli::slurp(csv));
    REQUIRE(rows.size() == 12);
    std::size_t k = 0;
    for (const auto& row : rows) {
        if (row.at("algorithm") == "zbuffer") {
            CHECK(row.at("status") == "measured");
            continue;
        }
        REQUIRE(k < std::size(expected));
        INFO(row.at("model") << " " << row.at("width"));
        CHECK(row.at("model") == expected[k].model);
        CHECK(row.at("width") == expected[k].size);
        CHECK(row.at("status") == expected[k].status);
        CHECK(row.at("reason") == expected[k].reason);
        ++k;
    }
    CHECK(k == std::size(expected));
    CHECK_THAT(r.out, Contains("skipped: hangs-in-render on cube: timed out on octahedron at 16x16 (a cell no larger)"));
}

TEST_CASE("bench isolation: the time limit's bad values", "[bench][isolation][cli]") {
    const std::string quick = std::string("bench --quick --models-dir ") + HSR_MODELS_DIR + " ";
    cli::require_one_line_error(cli::run_hsr(quick + "--cell-time-limit 0", "limit-zero"), "--cell-time-limit");
    cli::require_one_line_error(cli::run_hsr(quick + "--cell-time-limit -1", "limit-negative"), "--cell-time-limit");
    cli::require_one_line_error(cli::run_hsr(quick + "--cell-time-limit 5 --in-process", "limit-in-process"),
                                "--in-process");
}
