// hsr view runs every plugin in worker processes, never in the server: a plugin that crashes,
// aborts, calls exit(), runs out of memory or loops forever ends or stalls one worker, whose request
// is answered with an error naming the plugin and what happened; the worker is replaced and every
// other client is served meanwhile.
//
// A worker is `hsr view-worker …` (run_view_worker), started from the same executable, with the
// plugin folders, the folders it may read, the limits and its memory bound. It scans the plugins
// itself and keeps models and plugin instances loaded between jobs, so the server sends each job to
// the worker that last served the same model when it is free. Jobs and answers travel as messages
// over a socket (common/child_process.hpp): a job is JSON, an answer is a line of JSON (status and
// content type) and then the body as its bytes, so a picture or a buffer crosses once, unencoded.
#pragma once

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hsr::host {

// An HTTP answer, made by a worker or by the server.
struct Answer {
    int status = 200;
    std::string content_type;
    std::string body;
    std::string body_tail;  // sent after body: a frame's arrays, kept apart to save a copy
};
Answer json_answer(int status, const nlohmann::json& body);
// {"error": message on one line, "field": field (when not empty)}
Answer error_answer(int status, const std::string& message, const std::string& field = "");

struct WorkerSettings {
    std::filesystem::path executable;                  // hsr
    std::vector<std::string> plugin_dirs;              // searched besides the default ones
    std::vector<std::filesystem::path> read_folders;   // the folders served and the uploads'
    std::vector<std::string> limits;                   // --limit NAME=N settings
    int64_t threads = 0;                               // --threads of each worker
    std::size_t max_workers = 3;
    std::chrono::milliseconds time_limit{std::chrono::seconds(60)};  // of one job
    uint64_t memory_bytes = uint64_t(8) << 30;         // address space of a worker; 0 for no bound
};

class WorkerPool {
public:
    explicit WorkerPool(WorkerSettings settings);
    ~WorkerPool();
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    // Runs a job on a free worker (the one that last served `affinity`, if it is free; a new one
    // while there are fewer than max_workers) and returns its answer. A worker that dies or runs past
    // the time limit is killed and replaced, and the answer says so, naming `doing` ("rendering
    // with 'zbuffer' and 'blinn-phong'") and, when the worker could tell, the plugin at fault.
    // `cancel` set: the answer is 409, and the job is stopped (its worker killed) unless it is
    // about to end anyway (it started less than 300 ms ago).
    // on_progress hears each progress message of the job ({"steps": k, "total": n}).
    Answer call(const nlohmann::json& job, const std::string& affinity, const std::string& doing,
                const std::atomic<bool>* cancel = nullptr,
                const std::function<void(const nlohmann::json&)>& on_progress = {});

    // The plugins' descriptions (GET /api/plugins), made once by a worker. A plugin whose first
    // instance kills the worker is left out, and named on stderr.
    const nlohmann::json& plugins();

    // Every waiting and running call returns at once (503), and every worker is killed.
    void shutdown();

    const WorkerSettings& settings() const { return settings_; }

private:
    struct Worker;
    struct State;
    std::vector<std::string> worker_arguments() const;
    WorkerSettings settings_;
    std::unique_ptr<State> state_;
};

// `hsr view-worker ARGS`: serves jobs on fd 3 until the server closes it. Not for people to type.
int run_view_worker(const std::vector<std::string>& args);

}  // namespace hsr::host
