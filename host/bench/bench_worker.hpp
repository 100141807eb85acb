// hsr bench's cells timed in worker processes, so that a plugin that crashes, aborts, calls exit()
// or hangs costs only its own cells. A worker is `hsr bench-worker` (a command of its own, not
// listed in the help) started from the running executable: it is sent the job of one model (what to
// load, the sizes, the algorithms, the cells still to time), loads the model itself, times the cells
// one after the other as `hsr --in-process` would, and sends each cell's timing back. When it dies
// or overruns a cell's time limit, that cell is marked with how it ended and a new worker takes the
// cells after it.
#pragma once

#include "bench/bench_cell.hpp"

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hsr::host {

inline constexpr const char* kBenchWorkerCommand = "bench-worker";

// The worker's side: one job read from the socket on fd 3, its messages written there.
int run_bench_worker(const std::vector<std::string>& args);

}  // namespace hsr::host

namespace hsr::bench {

// Everything a worker needs to time the cells of one model as the parent's command line asked.
struct WorkerJob {
    std::string model;  // as --models names it
    std::filesystem::path models_dir;
    std::vector<ImageSize> sizes;
    std::vector<std::string> algorithms;  // NAME[:key=value,...]
    std::string lighting;                 // NAME[:key=value,...]
    TimingSettings timing;
    unsigned threads = 0;
    std::vector<std::string> plugin_dirs, limit_settings;
};

struct Cell {
    std::size_t size = 0, algorithm = 0;  // indices into WorkerJob::sizes and ::algorithms
};

// The cells of job's model, size after size and within a size algorithm after algorithm (the order
// of the returned outcomes), each in a worker and within cell_time_limit from its first call's
// start (the worker's start for the first). calling(cell, i) runs when the worker begins call i of
// the cell, finished(cell, outcome) once it has its outcome. skip(cell), asked again after each
// time-out, gives the reason a cell is not to be timed (its outcome's fault is then "skipped"), or
// none. Throws hsr::Error when a worker cannot load the model or scan the plugins.
std::vector<CellOutcome> time_cells_apart(const WorkerJob& job, std::chrono::duration<double> cell_time_limit,
                                          const std::function<void(const Cell&, unsigned)>& calling,
                                          const std::function<void(const Cell&, const CellOutcome&)>& finished,
                                          const std::function<std::optional<std::string>(const Cell&)>& skip = {});

// How a worker that ended mid-cell is shown: from the fault line hsr/plugin_faults.hpp makes it
// write ("plugin 'x' crashed in render (SIGSEGV)" becomes "crashed (SIGSEGV)"), else from how it
// ended as ChildProcess::reap() tells it ("was killed by SIGKILL" becomes "killed (SIGKILL)").
std::string fault_mark(const std::optional<std::string>& fault_line, const std::string& ending);

}  // namespace hsr::bench
