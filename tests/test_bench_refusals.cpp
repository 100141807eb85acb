// hsr bench with a plugin that fails on a scene: the run goes on, the table shows n/a and the
// plugin's one-line reason, and the CSV marks those rows n/a with the reason.
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <sstream>
#include <string>

namespace fs = std::filesystem;

TEST_CASE("cli: bench shows a plugin that refuses a scene as n/a with its reason", "[bench][cli]") {
    const fs::path csv = cli::scratch_dir() / "refusals.csv";
    const std::string common = std::string("bench --plugin-path ") + HSR_TEST_PLUGIN_DIR + " --models-dir " +
                               HSR_MODELS_DIR + " --models cube,octahedron --sizes 32 -r 2 -w 1 ";
    const cli::Run r = cli::run_hsr(common + "-a zbuffer -a throwing:what=invalid-argument --csv " + csv.string(),
                                    "bench-refusals");
    INFO("stderr: " << r.err);
    REQUIRE(r.status == 0);
    // Each row of the table: zbuffer timed on both models, the throwing plugin n/a on both.
    std::istringstream table(r.out);
    int zbuffer_rows = 0, refused_rows = 0, reasons = 0;
    for (std::string line; std::getline(table, line);) {
        if (line.rfind("zbuffer ", 0) == 0) {
            ++zbuffer_rows;
            CHECK(line.find("n/a") == std::string::npos);
        }
        if (line.rfind("throwing:what=invalid-argument ", 0) == 0) {
            ++refused_rows;
            CHECK(line.find("n/a") != line.rfind("n/a"));  // one per model
        }
        if (line.rfind("n/a: throwing:what=invalid-argument on ", 0) == 0) {
            ++reasons;
            CHECK_THAT(line, Catch::Contains("deliberate invalid argument"));
        }
    }
    CHECK(zbuffer_rows == 4);   // visibility, shading, total, peak memory
    CHECK(refused_rows == 4);
    CHECK(reasons == 2);        // cube and octahedron
    const std::string written = cli::slurp(csv);
    CHECK_THAT(written, Catch::Contains("\nzbuffer,cube,") && Catch::Contains("\nzbuffer,octahedron,"));
    // The refused cells are rows too, marked n/a with the plugin's reason and no time.
    std::istringstream rows(written);
    int refused_csv_rows = 0;
    for (std::string line; std::getline(rows, line);)
        if (line.rfind("throwing:what=invalid-argument,", 0) == 0) {
            ++refused_csv_rows;
            CHECK_THAT(line, Catch::Contains(",n/a,hidden-surface plugin 'throwing'") &&
                                 Catch::Contains("deliberate invalid argument,,,"));
        }
    CHECK(refused_csv_rows == 2);

    // Only refusals: still a table, and the files written (empty of measurements).
    const cli::Run alone = cli::run_hsr(common + "-a throwing --svg " + (cli::scratch_dir() / "refusals.svg").string(),
                                        "bench-refusals-alone");
    CHECK(alone.status == 0);
    CHECK_THAT(alone.out, Catch::Contains("n/a: throwing on cube: ") && Catch::Contains("deliberate failure"));
}
