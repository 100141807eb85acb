// hsr bench's worker processes (bench_worker.hpp): the parent's loop over workers, the worker
// command, and the messages between them, JSON objects:
//
//   parent -> worker  {"job": {...WorkerJob...}, "cells": [[size, algorithm], ...]}
//   worker -> parent  {"loaded": true}            the model is loaded, the first cell starts
//                     {"call": I}                 call I of the current cell starts
//                     {"timing": {...}}           the current cell's outcome; the next one starts
//                     {"refused": "REASON"}       the same, for a plugin that refused the scene
//                     {"error": "MESSAGE"}        the job cannot be done (the model does not load)
#include "bench/bench_worker.hpp"

#include "common/child_process.hpp"
#include "common/options.hpp"
#include "common/plugins.hpp"
#include "common/threads.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"
#include "hsr/plugin_faults.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/prctl.h>

#include <regex>

namespace fs = std::filesystem;
using nlohmann::json;

namespace hsr::bench {
namespace {

constexpr uint64_t kMaxMessageBytes = uint64_t(1) << 24;

json timing_json(const Timing& t) {
    return {{"render_ms", t.render_ms},           {"shading_ms", t.shading_ms},
            {"total_ms", t.total_ms},             {"build_ms", t.build_ms},
            {"build_calls", t.build_calls},       {"counters", t.counters},
            {"memory_before", t.memory.before},   {"memory_peak", t.memory.peak}};
}

// The timed calls' figures, as make_result() reads them; the per-call list stays in the worker.
Timing timing_from(const json& j) {
    Timing t;
    j.at("render_ms").get_to(t.render_ms);
    j.at("shading_ms").get_to(t.shading_ms);
    j.at("total_ms").get_to(t.total_ms);
    j.at("build_ms").get_to(t.build_ms);
    j.at("build_calls").get_to(t.build_calls);
    j.at("counters").get_to(t.counters);
    j.at("memory_before").get_to(t.memory.before);
    j.at("memory_peak").get_to(t.memory.peak);
    return t;
}

json job_json(const WorkerJob& job, const std::vector<Cell>& cells) {
    json sizes = json::array(), cell_list = json::array();
    for (const auto& [width, height] : job.sizes) sizes.push_back({width, height});
    for (const Cell& cell : cells) cell_list.push_back({cell.size, cell.algorithm});
    return {{"job",
             {{"model", job.model},
              {"models_dir", job.models_dir.string()},
              {"sizes", sizes},
              {"algorithms", job.algorithms},
              {"lighting", job.lighting},
              {"warmup", job.timing.warmup},
              {"repetitions", job.timing.repetitions},
              {"threads", job.threads},
              {"plugin_dirs", job.plugin_dirs},
              {"limits", job.limit_settings}}},
            {"cells", cell_list}};
}

std::pair<WorkerJob, std::vector<Cell>> job_from(const json& j) {
    const json& o = j.at("job");
    WorkerJob job;
    o.at("model").get_to(job.model);
    job.models_dir = o.at("models_dir").get<std::string>();
    for (const json& size : o.at("sizes")) job.sizes.emplace_back(size.at(0).get<uint32_t>(), size.at(1).get<uint32_t>());
    o.at("algorithms").get_to(job.algorithms);
    o.at("lighting").get_to(job.lighting);
    o.at("warmup").get_to(job.timing.warmup);
    o.at("repetitions").get_to(job.timing.repetitions);
    o.at("threads").get_to(job.threads);
    o.at("plugin_dirs").get_to(job.plugin_dirs);
    o.at("limits").get_to(job.limit_settings);
    job.timing.frame.threads = job.threads;
    std::vector<Cell> cells;
    for (const json& cell : j.at("cells")) {
        cells.push_back({cell.at(0).get<std::size_t>(), cell.at(1).get<std::size_t>()});
        if (cells.back().size >= job.sizes.size() || cells.back().algorithm >= job.algorithms.size())
            throw Error("bench-worker: a cell outside the job");
    }
    return {std::move(job), std::move(cells)};
}

void send(const json& message) {
    if (!host::write_message(host::kChildSocketFd, message.dump())) throw Error("bench-worker: hsr bench is gone");
}

// The worker's work, once its job is read.
void time_job(const WorkerJob& job, const std::vector<Cell>& cells) {
    set_limits(limits_from_settings(job.limit_settings));
    const host::ThreadBound thread_bound(job.threads);
    const PluginRegistry registry = host::scan_plugins(job.plugin_dirs);
    const PluginSpec lighting_spec = parse_plugin_spec(job.lighting);
    LightingModel lighting(registry.find(HSR_KIND_LIGHTING_MODEL, lighting_spec.name), lighting_spec.settings);
    const PreparedModel model = prepare_model(parse_model_spec(job.model, job.models_dir), job.sizes,
                                              [](const std::string&) {});  // the parent showed them
    send({{"loaded", true}});
    for (const Cell& cell : cells) {
        const PluginSpec algorithm = parse_plugin_spec(job.algorithms[cell.algorithm]);
        const Plugin& plugin = registry.find(HSR_KIND_HIDDEN_SURFACE_REMOVER, algorithm.name);
        const CellOutcome outcome = time_cell(model, cell.size, plugin, algorithm.settings, lighting, job.timing,
                                              [](unsigned call) { send({{"call", call}}); });
        // Sent once the remover is destroyed: a crash in destroy is this cell's.
        send(outcome.measured() ? json{{"timing", timing_json(outcome.timing)}} : json{{"refused", outcome.refused}});
    }
}

CellOutcome faulted(std::string mark, std::string detail) {
    CellOutcome outcome;
    outcome.fault = std::move(mark);
    outcome.fault_detail = std::move(detail);
    return outcome;
}

// The last line of what a worker wrote, for a worker that ended without naming a plugin.
std::string last_line(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    const std::size_t newline = text.rfind('\n');
    return newline == std::string::npos ? text : text.substr(newline + 1);
}

}  // namespace

std::string fault_mark(const std::optional<std::string>& fault_line, const std::string& ending) {
    static const std::regex signalled(R"(plugin '.*' (crashed|aborted) in \w+ \(([^()]+)\))");
    static const std::regex called_exit(R"(plugin '.*' called exit\((-?\d+)\) in \w+)");
    std::smatch m;
    if (fault_line && std::regex_match(*fault_line, m, signalled)) return fmt::format("{} ({})", m.str(1), m.str(2));
    if (fault_line && std::regex_match(*fault_line, m, called_exit)) return fmt::format("exited (status {})", m.str(1));
    const std::string killed = "was killed by ", exited = "exited with status ";
    if (ending.rfind(killed, 0) == 0) {
        const std::string signal = ending.substr(killed.size());
        if (signal == "SIGABRT") return "aborted (SIGABRT)";
        if (signal == "SIGKILL") return "killed (SIGKILL)";
        return fmt::format("crashed ({})", signal);
    }
    if (ending.rfind(exited, 0) == 0) return fmt::format("exited (status {})", ending.substr(exited.size()));
    return ending;
}

std::vector<CellOutcome> time_cells_apart(const WorkerJob& job, std::chrono::duration<double> cell_time_limit,
                                          const std::function<void(const Cell&, unsigned)>& calling,
                                          const std::function<void(const Cell&, const CellOutcome&)>& finished,
                                          const std::function<std::optional<std::string>(const Cell&)>& skip) {
    using Clock = std::chrono::steady_clock;
    const auto limit = std::chrono::duration_cast<Clock::duration>(cell_time_limit);
    std::vector<Cell> cells;
    for (std::size_t size = 0; size < job.sizes.size(); ++size)
        for (std::size_t algorithm = 0; algorithm < job.algorithms.size(); ++algorithm) cells.push_back({size, algorithm});
    std::vector<CellOutcome> outcomes;
    auto conclude = [&](CellOutcome outcome) {
        if (finished) finished(cells[outcomes.size()], outcome);
        outcomes.push_back(std::move(outcome));
    };
    // The cells from the next one on that are to be timed; those before the first of them that
    // `skip` passes over are concluded as skipped here. A cell's skipping can change only when a
    // cell times out, which ends its worker, so it is decided as each worker starts.
    auto cells_to_time = [&] {
        std::vector<Cell> timed;
        std::vector<std::optional<std::string>> skipped;
        for (std::size_t k = outcomes.size(); k < cells.size(); ++k) {
            skipped.push_back(skip ? skip(cells[k]) : std::nullopt);
            if (!skipped.back()) timed.push_back(cells[k]);
        }
        return std::pair{std::move(timed), std::move(skipped)};
    };

    const fs::path executable = host::running_executable();
    while (outcomes.size() < cells.size()) {
        const std::pair<std::vector<Cell>, std::vector<std::optional<std::string>>> cut = cells_to_time();
        const std::vector<Cell>& timed = cut.first;
        const std::vector<std::optional<std::string>>& skipped = cut.second;
        const std::size_t first = outcomes.size();
        // Concludes the skipped cells up to the next one the worker times.
        auto pass_skipped = [&] {
            while (outcomes.size() < cells.size() && skipped[outcomes.size() - first])
                conclude(faulted("skipped", *skipped[outcomes.size() - first]));
        };
        pass_skipped();
        if (timed.empty()) break;
        host::ChildProcess worker(executable, {host::kBenchWorkerCommand});
        worker.send(job_json(job, timed).dump());
        Clock::time_point deadline = Clock::now() + limit;
        for (std::string text;;) {
            const host::ChildProcess::Received received = worker.receive(text, deadline, nullptr, kMaxMessageBytes);
            const bool all_done = outcomes.size() == cells.size();
            if (received == host::ChildProcess::Received::kTimedOut) {
                worker.kill_and_reap();
                if (!all_done)
                    conclude(faulted("timed out", fmt::format("no end within {:g} s (--cell-time-limit)",
                                                              cell_time_limit.count())));
                break;
            }
            if (received != host::ChildProcess::Received::kMessage) {
                const std::string ending = worker.reap();
                if (all_done) break;
                const std::optional<std::string> fault_line = plugin_fault_in(worker.output_tail());
                const std::string said = last_line(worker.output_tail());
                conclude(faulted(fault_mark(fault_line, ending),
                                 fault_line ? *fault_line
                                            : fmt::format("its worker process {}{}", ending, said.empty() ? "" : ": " + said)));
                break;
            }
            json message;
            try {
                message = json::parse(text);
            } catch (const json::exception&) {
                throw Error("hsr bench: a worker process sent a message that is not JSON");
            }
            if (message.contains("error")) throw Error("{}", message["error"].get<std::string>());
            if (all_done) continue;
            if (message.contains("call")) {
                if (calling) calling(cells[outcomes.size()], message["call"].get<unsigned>());
            } else if (message.contains("timing")) {
                CellOutcome outcome;
                outcome.timing = timing_from(message["timing"]);
                conclude(std::move(outcome));
                pass_skipped();
                deadline = Clock::now() + limit;
            } else if (message.contains("refused")) {
                CellOutcome outcome;
                outcome.refused = message["refused"].get<std::string>();
                conclude(std::move(outcome));
                pass_skipped();
                deadline = Clock::now() + limit;
            } else if (message.contains("loaded")) {
                deadline = Clock::now() + limit;
            }
        }
    }
    return outcomes;
}

}  // namespace hsr::bench

int hsr::host::run_bench_worker(const std::vector<std::string>& args) {
    if (!args.empty()) throw UsageError("bench-worker takes no arguments (hsr bench starts it)");
    // A worker whose plugin hangs must not outlive an hsr bench killed meanwhile.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    std::string text;
    if (!read_message(kChildSocketFd, text, hsr::bench::kMaxMessageBytes))
        throw hsr::Error("bench-worker: no job on fd {} (hsr bench starts it)", kChildSocketFd);
    try {
        const auto [job, cells] = hsr::bench::job_from(json::parse(text));
        hsr::bench::time_job(job, cells);
    } catch (const std::exception& e) {
        hsr::bench::send({{"error", e.what()}});
        return 1;
    }
    return 0;
}
