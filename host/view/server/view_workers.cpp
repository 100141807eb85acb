// The server's side of hsr view's workers (view_workers.hpp): a pool of child processes, a job to a
// free one, and an answer whatever becomes of it.
#include "view/server/view_workers.hpp"

#include "common/child_process.hpp"

#include "hsr/error.hpp"
#include "hsr/plugin_faults.hpp"

#include <fmt/format.h>

#include <condition_variable>
#include <iostream>
#include <mutex>
#include <optional>

using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// The longest answer a worker may send: a 4096² frame with every buffer is about 400 MB.
constexpr uint64_t kMaxAnswerBytes = uint64_t(2) << 30;
// How often a waiting call looks at its cancel flag and at shutdown.
constexpr auto kCancelSlice = std::chrono::milliseconds(50);
// A job cancelled sooner than this after it started is left to finish (its answer dropped): a new
// worker and its loading cost more than a short frame.
constexpr auto kCancelGrace = std::chrono::milliseconds(300);
// Plugins left out of /api/plugins, at most, before hsr view gives up starting.
constexpr int kMaxPluginsLeftOut = 16;

std::string one_line(std::string text) {
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    return text;
}

std::string seconds(std::chrono::milliseconds ms) {
    return ms.count() % 1000 == 0 ? fmt::format("{} s", ms.count() / 1000) : fmt::format("{:.1f} s", ms.count() / 1000.0);
}

// "plugin 'NAME' …" → NAME.
std::string plugin_named_in(const std::string& fault) {
    const std::size_t open = fault.find('\'');
    const std::size_t close = open == std::string::npos ? open : fault.find('\'', open + 1);
    return close == std::string::npos ? "" : fault.substr(open + 1, close - open - 1);
}

}  // namespace

hsr::host::Answer hsr::host::json_answer(int status, const json& body) {
    return {status, "application/json; charset=utf-8", body.dump(-1, ' ', false, json::error_handler_t::replace), {}};
}

hsr::host::Answer hsr::host::error_answer(int status, const std::string& message, const std::string& field) {
    json body{{"error", one_line(message)}};
    if (!field.empty()) body["field"] = field;
    return json_answer(status, body);
}

struct hsr::host::WorkerPool::Worker {
    std::unique_ptr<ChildProcess> process;
    std::string affinity;  // what it served last
    bool busy = false;
};

struct hsr::host::WorkerPool::State {
    std::mutex mutex;
    std::condition_variable freed;
    std::vector<std::unique_ptr<Worker>> workers;
    std::atomic<bool> stopping{false};
    std::mutex plugins_mutex;
    std::optional<json> plugins;
};

hsr::host::WorkerPool::WorkerPool(WorkerSettings settings)
    : settings_(std::move(settings)), state_(std::make_unique<State>()) {
    if (settings_.max_workers == 0) settings_.max_workers = 1;
}

hsr::host::WorkerPool::~WorkerPool() { shutdown(); }

void hsr::host::WorkerPool::shutdown() {
    state_->stopping = true;
    std::lock_guard lock(state_->mutex);
    // Busy workers are the calls' to kill: each returns within a cancel slice.
    for (auto& worker : state_->workers)
        if (!worker->busy && worker->process) worker->process.reset();
    state_->freed.notify_all();
}

hsr::host::Answer hsr::host::WorkerPool::call(const json& job, const std::string& affinity, const std::string& doing,
                                              const std::atomic<bool>* cancel,
                                              const std::function<void(const json&)>& on_progress) {
    const auto deadline = Clock::now() + settings_.time_limit;
    auto cancelled = [&] { return state_->stopping.load() || (cancel != nullptr && cancel->load()); };
    auto cancelled_answer = [&] {
        return state_->stopping ? error_answer(503, "hsr view is stopping")
                                : error_answer(409, fmt::format("{}: cancelled by the page (a newer request, or Stop)", doing));
    };

    // A free worker: the one that served the same affinity last, else any, else a new one.
    Worker* worker = nullptr;
    {
        std::unique_lock lock(state_->mutex);
        for (;;) {
            if (cancelled()) return cancelled_answer();
            Worker* any = nullptr;
            for (auto& w : state_->workers) {
                if (w->busy) continue;
                if (w->affinity == affinity) {
                    worker = w.get();
                    break;
                }
                if (any == nullptr || w->affinity.empty()) any = w.get();
            }
            if (worker == nullptr) worker = any;
            if (worker == nullptr && state_->workers.size() < settings_.max_workers)
                worker = state_->workers.emplace_back(std::make_unique<Worker>()).get();
            if (worker != nullptr) break;
            if (Clock::now() >= deadline)
                return error_answer(503, fmt::format("{}: every worker of hsr view stayed busy for {} (raise --workers or "
                                                     "--time-limit)", doing, seconds(settings_.time_limit)));
            state_->freed.wait_for(lock, kCancelSlice);
        }
        worker->busy = true;
    }
    auto release = [&](bool keep) {
        std::lock_guard lock(state_->mutex);
        if (!keep) worker->process.reset();
        worker->affinity = keep ? affinity : "";
        worker->busy = false;
        if (state_->stopping) worker->process.reset();
        state_->freed.notify_all();
    };

    const std::string message = job.dump(-1, ' ', false, json::error_handler_t::replace);
    // An idle worker may have died (killed from outside): then one new one gets the job.
    bool sent = false;
    for (int attempt = 0; attempt < 2 && !sent; ++attempt) {
        if (!worker->process || !worker->process->running() || attempt > 0) {
            worker->process.reset();
            try {
                worker->process = std::make_unique<ChildProcess>(settings_.executable, worker_arguments());
            } catch (const hsr::Error& e) {
                release(false);
                return error_answer(500, fmt::format("{}: cannot start a worker ({})", doing, e.what()));
            }
        }
        sent = worker->process->send(message);
    }
    if (!sent) {
        const std::string how = worker->process->kill_and_reap();
        release(false);
        return error_answer(500, fmt::format("{}: the worker {} before taking the job", doing, how));
    }

    const auto job_start = Clock::now();
    std::string received;
    for (;;) {
        const auto slice_end = std::min(deadline, Clock::now() + kCancelSlice);
        const ChildProcess::Received result = worker->process->receive(received, slice_end, nullptr, kMaxAnswerBytes);
        if (result == ChildProcess::Received::kMessage) {
            // A progress message is a header line of its own; the answer's header starts otherwise.
            if (!received.starts_with("{\"progress\":")) break;
            if (on_progress) {
                try {
                    on_progress(json::parse(received).at("progress"));
                } catch (const json::exception&) {
                }
            }
            continue;
        }
        if (result == ChildProcess::Received::kGone) {
            ChildProcess& process = *worker->process;
            const std::string how = process.reap();
            const std::optional<std::string> fault = hsr::plugin_fault_in(process.output_tail());
            release(false);
            if (fault) return error_answer(500, fmt::format("{}: {}", doing, *fault));
            return error_answer(500, fmt::format("{}: the worker {}", doing, how));
        }
        if (cancelled() && (state_->stopping || Clock::now() - job_start >= kCancelGrace)) {
            worker->process->kill_and_reap();
            release(false);
            return cancelled_answer();
        }
        if (Clock::now() >= deadline) {
            worker->process->kill_and_reap();
            release(false);
            return error_answer(504, fmt::format("{}: over the time limit of {}, stopped (hsr view --time-limit "
                                                 "SECONDS)", doing, seconds(settings_.time_limit)));
        }
    }
    release(true);
    if (cancelled()) return cancelled_answer();

    Answer answer;
    const std::size_t newline = received.find('\n');
    try {
        const json header = json::parse(received.substr(0, newline));
        answer.status = header.at("status").get<int>();
        answer.content_type = header.at("content_type").get<std::string>();
    } catch (const json::exception&) {
        return error_answer(500, fmt::format("{}: the worker's answer is not understood", doing));
    }
    received.erase(0, newline == std::string::npos ? received.size() : newline + 1);
    answer.body = std::move(received);
    return answer;
}

std::vector<std::string> hsr::host::WorkerPool::worker_arguments() const {
    std::vector<std::string> args{"view-worker", "--threads", std::to_string(settings_.threads), "--memory-bytes",
                                  std::to_string(settings_.memory_bytes)};
    for (const std::string& dir : settings_.plugin_dirs) args.insert(args.end(), {"--plugin-path", dir});
    for (const auto& folder : settings_.read_folders) args.insert(args.end(), {"--read-folder", folder.string()});
    for (const std::string& limit : settings_.limits) args.insert(args.end(), {"--limit", limit});
    return args;
}

const json& hsr::host::WorkerPool::plugins() {
    std::lock_guard lock(state_->plugins_mutex);
    if (state_->plugins) return *state_->plugins;
    json skip = json::array();
    for (int left_out = 0; left_out <= kMaxPluginsLeftOut; ++left_out) {
        const Answer answer = call({{"op", "plugins"}, {"skip", skip}}, "", "describing the plugins");
        if (answer.status == 200) {
            state_->plugins = json::parse(answer.body);
            return *state_->plugins;
        }
        std::string error = answer.body;
        try {
            error = json::parse(answer.body).at("error").get<std::string>();
        } catch (const json::exception&) {
        }
        const std::string name = plugin_named_in(error);
        if (name.empty() || answer.status != 500) throw hsr::Error("hsr view: {}", error);
        std::cerr << fmt::format("hsr view: {}; it is left out\n", error);
        skip.push_back(name);
    }
    throw hsr::Error("hsr view: over {} plugins kill the process that describes them", kMaxPluginsLeftOut);
}
