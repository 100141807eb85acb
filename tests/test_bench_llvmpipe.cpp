// hsr bench --vs-llvmpipe: the comparison table when host/bench/llvmpipe/'s hsr-llvmpipe is built
// (-DHSR_LLVMPIPE=ON), a one-line error naming the build option when it is not, and the runs it
// cannot compare refused before anything is timed.
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdlib>
#include <sstream>
#include <string>

namespace {

const std::string common =
    std::string("bench --models-dir ") + HSR_MODELS_DIR + " --models cube --sizes 32x24 -r 1 -w 0 ";

bool llvmpipe_built() { return access((std::string(HSR_BINARY_DIR) + "/hsr-llvmpipe").c_str(), X_OK) == 0; }

}  // namespace

TEST_CASE("cli: bench --vs-llvmpipe prints hsr's and llvmpipe's frame times and their ratio", "[bench][cli]") {
    const cli::Run r = cli::run_hsr(common + "--vs-llvmpipe", "vs-llvmpipe");
    if (!llvmpipe_built()) {
        cli::require_one_line_error(r, "build with -DHSR_LLVMPIPE=ON (needs libosmesa6-dev)");
        return;
    }
    INFO("stdout: " << r.out << "\nstderr: " << r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("ratio = hsr / llvmpipe"));
    CHECK_THAT(r.out, Catch::Contains("llvmpipe"));
    std::istringstream lines(r.out);
    int rows = 0;
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string model, size;
        double hsr_ms = 0, llvmpipe_ms = 0, ratio = 0;
        if (!(words >> model >> size >> hsr_ms >> llvmpipe_ms >> ratio) || model != "cube" || size != "32x24") continue;
        ++rows;
        CHECK(hsr_ms > 0);
        CHECK(llvmpipe_ms > 0);
        // The printed times are rounded to 2 decimals (3 significant digits at least).
        CHECK(ratio == Approx(hsr_ms / llvmpipe_ms).epsilon(0.02).margin(0.01));
    }
    CHECK(rows == 1);
}

TEST_CASE("cli: bench --vs-llvmpipe refuses a run without zbuffer or blinn-phong", "[bench][cli]") {
    cli::require_one_line_error(cli::run_hsr(common + "--vs-llvmpipe -a scanline-zbuffer", "vs-llvmpipe-algorithm"),
                                "--vs-llvmpipe compares zbuffer");
    cli::require_one_line_error(cli::run_hsr(common + "--vs-llvmpipe -l lambert", "vs-llvmpipe-lighting"),
                                "--vs-llvmpipe compares blinn-phong lighting, not lambert");
}

TEST_CASE("cli: bench --vs-llvmpipe with HSR_LLVMPIPE_PROGRAM naming no program", "[bench][cli]") {
    const std::string missing = (cli::scratch_dir() / "no-such-program").string();
    setenv("HSR_LLVMPIPE_PROGRAM", missing.c_str(), 1);
    const cli::Run r = cli::run_hsr(common + "--vs-llvmpipe", "vs-llvmpipe-missing");
    unsetenv("HSR_LLVMPIPE_PROGRAM");
    cli::require_one_line_error(r, "HSR_LLVMPIPE_PROGRAM: '" + missing + "' is not a program");
}
