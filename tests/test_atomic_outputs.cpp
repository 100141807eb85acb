// Outputs are replaced whole or not at all (hsr/atomic_file.hpp), seen from outside through the hsr
// executable: killed while it writes, failing part-way through a command's outputs, and four of it
// writing one file at once. Each case compares the files with the bytes that were there before, or
// with what each render writes on its own.
#include "hsr/image.hpp"

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace fs = std::filesystem;

namespace {

// An empty folder of its own for each case.
fs::path fresh_dir(const std::string& name) {
    const fs::path dir = fs::path(HSR_BINARY_DIR) / "test-atomic-outputs-scratch" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// Starts `hsr args...` with stdin from /dev/null and stdout and stderr into log.
pid_t start_hsr(const std::vector<std::string>& args, const fs::path& log) {
    std::vector<std::string> argv_text{std::string(HSR_BINARY_DIR) + "/hsr"};
    argv_text.insert(argv_text.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_text) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t pid = -1;
    const int failed = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    REQUIRE(failed == 0);
    return pid;
}

// The raw wait status.
int wait_for(pid_t pid) {
    int status = 0;
    REQUIRE(waitpid(pid, &status, 0) == pid);
    return status;
}

struct Run {
    int exit_status = -1;  // -1 when ended by a signal
    std::string err;
};

Run run_hsr(const std::vector<std::string>& args, const fs::path& log) {
    const int status = wait_for(start_hsr(args, log));
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(log)};
}

// The temporary files in dir: ".<name>.tmp-<pid>-<random>".
std::vector<fs::path> temporaries(const fs::path& dir) {
    std::vector<fs::path> found;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (name.front() == '.' && name.find(".tmp-") != std::string::npos) found.push_back(entry.path());
    }
    return found;
}

// Detailed enough that its two 2048x2048 PNGs take tens of milliseconds to encode, and no fetched model.
// The depth picture is written after the picture's temporary and before either is renamed, which
// widens the moment in which the picture's temporary holds bytes.
std::vector<std::string> slow_to_write_render(const fs::path& output, const fs::path& depth_output) {
    return {"render", "--surface", "sin(9*x)*cos(9*y)", "--range", "-1:1,-1:1,300x300", "--width", "2048",
            "--height", "2048", "-o", output.string(), "--depth-out", depth_output.string()};
}

bool temporary_holds_bytes(const fs::path& dir) {
    for (const fs::path& t : temporaries(dir)) {
        std::error_code ec;
        if (fs::file_size(t, ec) > 0 && !ec) return true;
    }
    return false;
}

// A render into dir/picture.png, which holds an older picture, sent a signal while it writes.
// The render is stopped (SIGSTOP) as soon as its temporary holds bytes, and the state is checked while
// it cannot move: the temporary is there and the picture is still the old one. Only then is the signal
// sent and the render let go on, so the signal always lands in the middle of the write. A render that
// finished its write before it could be stopped proves nothing and is run again.
struct Interrupted {
    std::string old_bytes;  // the picture before
    int wait_status = 0;
};

Interrupted interrupt_while_writing(const fs::path& dir, int signal_number) {
    const fs::path picture = dir / "picture.png";
    REQUIRE(run_hsr({"render", std::string(HSR_MODELS_DIR) + "/cube.obj", "--width", "40", "--height", "30", "-o",
                     picture.string()},
                    dir / "old.log")
                .exit_status == 0);
    Interrupted result;
    result.old_bytes = slurp(picture);
    constexpr int attempts = 20;
    for (int attempt = 0; attempt < attempts; ++attempt) {
        fs::remove(dir / "depth.png");
        const pid_t pid = start_hsr(slow_to_write_render(picture, dir / "depth.png"), dir / "render.log");
        bool stopped_while_writing = false;
        for (;;) {
            if (temporary_holds_bytes(dir)) {
                REQUIRE(kill(pid, SIGSTOP) == 0);
                int status = 0;
                REQUIRE(waitpid(pid, &status, WUNTRACED) == pid);
                if (WIFSTOPPED(status)) {
                    stopped_while_writing = temporary_holds_bytes(dir) && slurp(picture) == result.old_bytes;
                    if (stopped_while_writing) break;
                    REQUIRE(kill(pid, SIGCONT) == 0);
                    wait_for(pid);
                }
                break;  // it ended, or was stopped too late: run it again
            }
            int status = 0;
            if (waitpid(pid, &status, WNOHANG) == pid) break;  // ended between two looks: run it again
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        if (!stopped_while_writing) {
            // A render that finished replaced the picture: put the old one back for the next attempt.
            std::ofstream(picture, std::ios::binary) << result.old_bytes;
            for (const fs::path& t : temporaries(dir)) fs::remove(t);
            continue;
        }
        REQUIRE(kill(pid, signal_number) == 0);
        REQUIRE(kill(pid, SIGCONT) == 0);
        result.wait_status = wait_for(pid);
        return result;
    }
    FAIL("the render was never caught while writing in " << attempts << " attempts");
    return result;
}

// Two unit cubes apart in one mesh: one object that is not convex, which roberts refuses.
const char* two_cubes_obj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "v 3 0 0\nv 4 0 0\nv 4 1 0\nv 3 1 0\nv 3 0 1\nv 4 0 1\nv 4 1 1\nv 3 1 1\n"
    "f 5 6 7 8\nf 1 4 3 2\nf 2 3 7 6\nf 1 5 8 4\nf 4 8 7 3\nf 1 2 6 5\n"
    "f 13 14 15 16\nf 9 12 11 10\nf 10 11 15 14\nf 9 13 16 12\nf 12 16 15 11\nf 9 10 14 13\n";

}  // namespace

TEST_CASE("atomic outputs: a render killed with SIGKILL while it writes leaves the old file as it was",
          "[atomic-outputs]") {
    const fs::path dir = fresh_dir("sigkill");
    const Interrupted run = interrupt_while_writing(dir, SIGKILL);
    CHECK(WIFSIGNALED(run.wait_status));
    CHECK(slurp(dir / "picture.png") == run.old_bytes);
    // SIGKILL cannot be caught: what it leaves are the temporaries, one named after the picture.
    const std::vector<fs::path> left = temporaries(dir);
    REQUIRE(!left.empty());
    CHECK(std::any_of(left.begin(), left.end(), [](const fs::path& t) {
        return t.filename().string().rfind(".picture.png.tmp-", 0) == 0;
    }));
}

TEST_CASE("atomic outputs: SIGTERM or SIGINT while it writes removes the temporary and keeps the old file",
          "[atomic-outputs]") {
    for (const int signal_number : {SIGTERM, SIGINT}) {
        INFO("signal " << signal_number);
        const fs::path dir = fresh_dir("signal-" + std::to_string(signal_number));
        const Interrupted run = interrupt_while_writing(dir, signal_number);
        // The handler removes the temporary, then lets the signal end the process as it would have.
        CHECK((WIFSIGNALED(run.wait_status) && WTERMSIG(run.wait_status) == signal_number));
        CHECK(slurp(dir / "picture.png") == run.old_bytes);
        CHECK(!fs::exists(dir / "depth.png"));
        CHECK(temporaries(dir).empty());
    }
}

TEST_CASE("atomic outputs: an output that fails to write leaves all the command's files as they were",
          "[atomic-outputs]") {
    const fs::path dir = fresh_dir("failing-output");
    // /dev/full takes no byte: the last of the three outputs fails once the first two are written.
    const fs::path picture = dir / "picture.png", depth = dir / "depth.png", overdraw = dir / "overdraw.png";
    write_text(picture, "the old picture\n");
    write_text(depth, "the old depth\n");
    fs::create_symlink("/dev/full", overdraw);
    const std::vector<std::string> args{"render", std::string(HSR_MODELS_DIR) + "/cube.obj", "--width", "64",
                                        "--height", "64", "-o", picture.string(), "--depth-out", depth.string(),
                                        "--overdraw-out", overdraw.string()};
    const Run failed = run_hsr(args, dir / "failed.log");
    INFO(failed.err);
    CHECK(failed.exit_status == 1);
    CHECK_THAT(failed.err, Catch::StartsWith("hsr: error: cannot write " + overdraw.string()));
    CHECK(slurp(picture) == "the old picture\n");
    CHECK(slurp(depth) == "the old depth\n");
    CHECK(temporaries(dir).empty());

    // The same command with a file that can be written: all three replaced, nothing else left.
    fs::remove(overdraw);
    const Run written = run_hsr(args, dir / "written.log");
    INFO(written.err);
    REQUIRE(written.exit_status == 0);
    for (const fs::path& p : {picture, depth, overdraw}) CHECK(hsr::read_png_rgb(p).width == 64);
    CHECK(temporaries(dir).empty());
}

TEST_CASE("atomic outputs: a line plugin that fails leaves the drawing and the --trace file as they were",
          "[atomic-outputs]") {
    const fs::path dir = fresh_dir("failing-plugin");
    const fs::path model = dir / "two-cubes.obj", drawing = dir / "drawing.svg", trace = dir / "trace.jsonl";
    write_text(model, two_cubes_obj);
    write_text(drawing, "the old drawing\n");
    write_text(trace, "the old trace\n");
    const Run failed = run_hsr({"render", model.string(), "-a", "roberts", "--width", "64", "--height", "64", "-o",
                                drawing.string(), "--trace", trace.string()},
                               dir / "failed.log");
    INFO(failed.err);
    CHECK(failed.exit_status == 1);
    CHECK_THAT(failed.err, Catch::Contains("not one convex body"));
    CHECK(slurp(drawing) == "the old drawing\n");
    CHECK(slurp(trace) == "the old trace\n");
    CHECK(temporaries(dir).empty());

    // A plugin that succeeds replaces both, the trace with one JSON object per line.
    const Run written = run_hsr({"render", std::string(HSR_MODELS_DIR) + "/cube.obj", "-a", "roberts", "--width",
                                 "64", "--height", "64", "-o", drawing.string(), "--trace", trace.string()},
                                dir / "written.log");
    INFO(written.err);
    REQUIRE(written.exit_status == 0);
    CHECK(slurp(drawing).find("<svg") != std::string::npos);
    CHECK(slurp(trace).rfind("{\"type\":", 0) == 0);
    CHECK(temporaries(dir).empty());
}

TEST_CASE("atomic outputs: bench replaces its CSV, SVG and PNG together or not at all", "[atomic-outputs]") {
    const fs::path dir = fresh_dir("bench");
    const fs::path csv = dir / "times.csv", svg = dir / "plot.svg", png = dir / "plot.png";
    write_text(csv, "the old table\n");
    write_text(svg, "the old plot\n");
    fs::create_symlink("/dev/full", png);
    const std::vector<std::string> args{"bench", "--quick", "--algorithms", "zbuffer", "--models", "cube",
                                        "--sizes", "32", "-r", "1", "--models-dir", HSR_MODELS_DIR,
                                        "--csv", csv.string(), "--svg", svg.string(), "--png", png.string()};
    const Run failed = run_hsr(args, dir / "failed.log");
    INFO(failed.err);
    CHECK(failed.exit_status == 1);
    CHECK_THAT(failed.err, Catch::Contains("hsr: error: ") && Catch::Contains("PNG"));
    CHECK(slurp(csv) == "the old table\n");
    CHECK(slurp(svg) == "the old plot\n");
    CHECK(temporaries(dir).empty());

    fs::remove(png);
    const Run written = run_hsr(args, dir / "written.log");
    INFO(written.err);
    REQUIRE(written.exit_status == 0);
    CHECK(slurp(csv).rfind("algorithm,model,", 0) == 0);
    CHECK(slurp(svg).find("<svg") != std::string::npos);
    CHECK(hsr::read_png_rgb(png).width > 0);
    CHECK(temporaries(dir).empty());
}

TEST_CASE("atomic outputs: four renders to one file at once leave one of their pictures, whole",
          "[atomic-outputs][slow]") {
    const fs::path dir = fresh_dir("concurrent");
    // Four different pictures of one size, each first rendered alone to a file of its own.
    const std::vector<std::string> yaws{"0", "25", "50", "75"};
    auto render = [&](const std::string& yaw, const fs::path& output) {
        return std::vector<std::string>{"render", "--surface", "sin(9*x)*cos(9*y)", "--range", "-1:1,-1:1,200x200",
                                        "--width", "800", "--height", "600", "--yaw", yaw, "-o", output.string()};
    };
    std::vector<std::string> alone;
    for (const std::string& yaw : yaws) {
        const fs::path own = dir / ("yaw-" + yaw + ".png");
        REQUIRE(run_hsr(render(yaw, own), dir / ("yaw-" + yaw + ".log")).exit_status == 0);
        alone.push_back(slurp(own));
    }
    // Written in place, four writers at once left a corrupt file in 9 rounds out of 10 here.
    const fs::path shared = dir / "shared.png";
    for (int round = 0; round < 3; ++round) {
        INFO("round " << round);
        std::vector<pid_t> pids;
        for (std::size_t k = 0; k < yaws.size(); ++k)
            pids.push_back(start_hsr(render(yaws[k], shared), dir / ("shared-" + std::to_string(k) + ".log")));
        for (const pid_t pid : pids) {
            const int status = wait_for(pid);
            CHECK((WIFEXITED(status) && WEXITSTATUS(status) == 0));
        }
        const hsr::Image image = hsr::read_png_rgb(shared);
        CHECK(image.width == 800);
        CHECK(image.height == 600);
        CHECK(std::find(alone.begin(), alone.end(), slurp(shared)) != alone.end());
        CHECK(temporaries(dir).empty());
    }
}
