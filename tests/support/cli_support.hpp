// Running the hsr executable from a test: exit status and output of one command, a scratch folder
// per test program, and the check that an error is one line that names the problem.
#pragma once

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace cli {

struct Run {
    int status = -1;  // the exit status; -1 when hsr died from a signal or ran out of time
    std::string out, err;
};

// <build>/<test program>-scratch, made on first use.
inline std::filesystem::path scratch_dir() {
    const std::string program = std::filesystem::read_symlink("/proc/self/exe").filename().string();
    const std::filesystem::path dir = std::filesystem::path(HSR_BINARY_DIR) / (program + "-scratch");
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::string slurp(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Writes bytes to <name> in the scratch folder; returns its path.
inline std::filesystem::path write_file(const std::string& name, const std::string& bytes) {
    const std::filesystem::path path = scratch_dir() / name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

// Runs `hsr <args>` with no input and a time limit, in folder `cwd` when one is given; stdout and
// stderr go to <tag>.out and <tag>.err in the scratch folder.
inline Run run_hsr(const std::string& args, const std::string& tag, int timeout_seconds = 60,
                   const std::filesystem::path& cwd = {}) {
    const std::filesystem::path dir = scratch_dir();
    const std::filesystem::path out = dir / (tag + ".out"), err = dir / (tag + ".err");
    const std::string command = (cwd.empty() ? "" : "cd '" + cwd.string() + "' && ") + "timeout " + std::to_string(timeout_seconds) + " " + std::string(HSR_BINARY_DIR) +
                                "/hsr " + args + " > " + out.string() + " 2> " + err.string() + " < /dev/null";
    const int raw = std::system(command.c_str());
    Run r;
    r.status = WIFEXITED(raw) && WEXITSTATUS(raw) != 124 ? WEXITSTATUS(raw) : -1;  // 124: timed out
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

// One line, naming the problem, exit status 1 or 2 (not a crash: a signal gives -1).
inline void require_one_line_error(const Run& r, const std::string& expected) {
    INFO("stderr: " << r.err);
    CHECK((r.status == 1 || r.status == 2));
    CHECK(r.err.rfind("hsr: error: ", 0) == 0);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_THAT(r.err, Catch::Contains(expected));
}

}  // namespace cli
