// hsr bench --vs-llvmpipe (bench_llvmpipe.hpp): runs llvmpipe/'s hsr-llvmpipe on each scene
// of the run and sets its frame time beside hsr's. The program is a separate process so that hsr
// itself never needs OSMesa.
#include "bench/bench_llvmpipe.hpp"

#include "common/options.hpp"

#include "hsr/error.hpp"
#include "hsr/params.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <fmt/format.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <ostream>
#include <string>
#include <vector>

extern char** environ;

namespace fs = std::filesystem;

namespace hsr::host {
namespace {

// The program's standard output; its standard error goes to ours. Throws hsr::Error when it cannot
// be started or fails.
std::string run_program(const fs::path& program, const std::vector<std::string>& args) {
    int pipe_ends[2];
    if (pipe(pipe_ends) != 0) throw Error("--vs-llvmpipe: cannot make a pipe");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipe_ends[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, pipe_ends[0]);
    posix_spawn_file_actions_addclose(&actions, pipe_ends[1]);
    std::vector<std::string> words = {program.string()};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, words[0].c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(pipe_ends[1]);
    std::string output;
    if (spawned == 0) {
        char buffer[4096];
        for (ssize_t n; (n = read(pipe_ends[0], buffer, sizeof buffer)) != 0;) {
            if (n > 0) output.append(buffer, size_t(n));
            else if (errno != EINTR) break;
        }
    }
    close(pipe_ends[0]);
    if (spawned != 0) throw Error("--vs-llvmpipe: cannot run {}", program.string());
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw Error("--vs-llvmpipe: {} failed (its message is above)", program.filename().string());
    return output;
}

// The value of key=... in the program's --machine line; the renderer's runs to the end of the line.
std::string field(const std::string& line, const std::string& key, bool to_end = false) {
    const std::size_t at = line.find(key + "=");
    if (at == std::string::npos) throw Error("--vs-llvmpipe: hsr-llvmpipe printed no {} ('{}')", key, line);
    const std::size_t start = at + key.size() + 1;
    const std::size_t end = to_end ? line.find('\n', start) : line.find_first_of(" \n", start);
    return line.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

std::string ms(double v) { return fmt::format("{:.{}f}", v, v < 10 ? 2 : 1); }

}  // namespace

fs::path find_llvmpipe_program(const std::vector<std::string>& algorithm_labels, const std::string& lighting) {
    if (std::find(algorithm_labels.begin(), algorithm_labels.end(), "zbuffer") == algorithm_labels.end())
        throw UsageError("--vs-llvmpipe compares zbuffer (with its default parameters): add -a zbuffer");
    if (parse_plugin_spec(lighting).name != "blinn-phong")
        throw UsageError("--vs-llvmpipe compares blinn-phong lighting, not {}", parse_plugin_spec(lighting).name);
    if (const char* given = std::getenv("HSR_LLVMPIPE_PROGRAM"); given && *given) {
        if (access(given, X_OK) != 0) throw UsageError("HSR_LLVMPIPE_PROGRAM: '{}' is not a program", given);
        return given;
    }
    const fs::path beside = fs::path(boost::dll::program_location().parent_path().string()) / "hsr-llvmpipe";
    if (access(beside.c_str(), X_OK) != 0)
        throw UsageError("--vs-llvmpipe: hsr-llvmpipe is not built: build with -DHSR_LLVMPIPE=ON (needs libosmesa6-dev)");
    return beside;
}

void print_llvmpipe_comparison(const fs::path& program, const std::vector<bench::Result>& results,
                               const LlvmpipeRun& run, std::ostream& out) {
    struct Row {
        std::string model, size;
        double hsr_ms, llvmpipe_ms;
    };
    std::vector<Row> rows;
    std::string threads, renderer;
    for (const bench::Result& r : results) {
        if (r.algorithm != "zbuffer" || !r.refused.empty()) continue;
        const std::string size = fmt::format("{}x{}", r.width, r.height);
        std::fprintf(stderr, "hsr bench: llvmpipe on %s %s\n", r.model.c_str(), size.c_str());
        std::vector<std::string> args = {"--machine", "--model", r.model, "--models-dir", run.models_dir.string(),
                                         "--size", size, "-l", run.lighting,
                                         "-w", std::to_string(run.warmup), "-r", std::to_string(run.repetitions),
                                         "--threads", std::to_string(run.threads)};
        for (const std::string& dir : run.plugin_dirs) args.insert(args.end(), {"--plugin-path", dir});
        for (const std::string& limit : run.limit_settings) args.insert(args.end(), {"--limit", limit});
        const std::string line = run_program(program, args);
        const std::string frame = field(line, "frame-ms");
        threads = field(line, "threads");
        renderer = field(line, "renderer", true);
        rows.push_back({r.model, size, r.total.median, std::strtod(frame.c_str(), nullptr)});
    }
    if (rows.empty()) return;
    std::size_t model_width = 5;
    for (const Row& row : rows) model_width = std::max(model_width, row.model.size());
    out << fmt::format("\nzbuffer + {} against {}, {} thread{} each (LP_NUM_THREADS); ratio = hsr / llvmpipe:\n",
                       run.lighting, renderer, threads, threads == "1" ? "" : "s");
    out << fmt::format("{:<{}}  {:>9}  {:>11}  {:>11}  {:>5}\n", "model", model_width, "size", "hsr ms", "llvmpipe ms",
                       "ratio");
    for (const Row& row : rows)
        out << fmt::format("{:<{}}  {:>9}  {:>11}  {:>11}  {:>5.2f}\n", row.model, model_width, row.size, ms(row.hsr_ms),
                           ms(row.llvmpipe_ms), row.hsr_ms / row.llvmpipe_ms);
}

}  // namespace hsr::host
