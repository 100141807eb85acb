// The worker's side of hsr view (view_workers.hpp): `hsr view-worker`, which scans the plugins,
// keeps models and plugin instances loaded between jobs (view_frames.hpp), and answers each job
// the server sends on fd 3: a frame, the outline of its steps, a comparison, the plugins' descriptions or a theory page.
#include "view/server/view_workers.hpp"

#include "common/child_process.hpp"
#include "common/plugins.hpp"
#include "common/threads.hpp"
#include "view/server/view_frames.hpp"
#include "view/server/view_models.hpp"
#include "view/server/view_theory.hpp"

#include "hsr/abi.h"
#include "hsr/error.hpp"
#include "hsr/limits.hpp"
#include "hsr/params.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/sanitizers.hpp"

#include <boost/program_options.hpp>
#include <fmt/format.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <map>
#include <new>

namespace po = boost::program_options;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using hsr::host::Answer;
using hsr::host::ViewError;

// A job is a request body the server has read within its own limits, and a little more.
constexpr uint64_t kMaxJobBytes = uint64_t(1) << 28;

json describe_plugin(const hsr::Plugin& plugin, bool steps) {
    const hsr_plugin_descriptor& d = plugin.descriptor;
    json params = json::array();
    for (uint32_t i = 0; i < d.param_count; ++i) {
        const hsr_param_desc& p = hsr::param_desc(d, i);
        json param{{"name", p.name ? p.name : ""}, {"default", p.default_value ? p.default_value : ""},
                   {"help", p.help ? p.help : ""}};
        switch (p.type) {
        case HSR_PARAM_BOOL: param["type"] = "bool"; break;
        case HSR_PARAM_INT: param["type"] = "int"; break;
        case HSR_PARAM_FLOAT: param["type"] = "float"; break;
        case HSR_PARAM_ENUM: param["type"] = "enum"; break;
        case HSR_PARAM_COLOR: param["type"] = "color"; break;
        default: param["type"] = "string"; break;
        }
        if (p.type == HSR_PARAM_INT || p.type == HSR_PARAM_FLOAT) {
            param["min"] = p.min;
            param["max"] = p.max;
        }
        if (p.type == HSR_PARAM_ENUM) param["choices"] = hsr::split_choices(p.choices);
        params.push_back(std::move(param));
    }
    json phases = json::array();
    for (const hsr::PluginPhase& phase : plugin.phases) phases.push_back({{"name", phase.name}, {"title", phase.title}});
    // {"ru": {"description": ..., "param:depth-test": ..., ...}}: the page looks a text up by its ABI key.
    json translations = json::object();
    for (const hsr::PluginTranslation& t : plugin.translations) translations[t.language][t.key] = t.text;
    return {{"name", d.name},
            {"translations", std::move(translations)},
            {"version", d.version ? d.version : ""},
            {"phases", std::move(phases)},
            {"description", d.description ? d.description : ""},
            {"abi", fmt::format("{}.{}", d.abi_major, d.abi_minor)},
            {"steps", steps},
            {"params", std::move(params)}};
}

// GET /api/plugins. Whether a hidden-surface plugin has steps is a property of an instance's
// table, so a default instance of each is made: one that kills the process is named by the fault
// line (hsr/plugin_faults.hpp), and the server asks again with it in `skip`.
json describe_plugins(const hsr::PluginRegistry& registry, const json& skip) {
    auto skipped = [&](const char* name) { return std::find(skip.begin(), skip.end(), json(name)) != skip.end(); };
    json out{{"hidden_surface", json::array()}, {"hidden_line", json::array()}, {"lighting", json::array()}};
    for (const hsr::Plugin& p : registry.plugins()) {
        if (skipped(p.descriptor.name)) continue;
        switch (p.descriptor.kind) {
        case HSR_KIND_HIDDEN_SURFACE_REMOVER: {
            bool steps = false;
            try {
                steps = hsr::HiddenSurfaceRemover(p, {}).has_steps();
            } catch (const hsr::Error&) {
            }
            out["hidden_surface"].push_back(describe_plugin(p, steps));
            break;
        }
        case HSR_KIND_HIDDEN_LINE_REMOVER: out["hidden_line"].push_back(describe_plugin(p, true)); break;
        case HSR_KIND_LIGHTING_MODEL: out["lighting"].push_back(describe_plugin(p, false)); break;
        default: break;
        }
    }
    return out;
}

struct WorkerOptions {
    std::vector<std::string> plugin_dirs, read_folders, limits;
    int64_t threads = 0;
    uint64_t memory_bytes = 0;
};

WorkerOptions parse_worker_options(const std::vector<std::string>& args) {
    WorkerOptions o;
    po::options_description options;
    options.add_options()
        ("plugin-path", po::value(&o.plugin_dirs)->composing())
        ("read-folder", po::value(&o.read_folders)->composing())
        ("limit", po::value(&o.limits)->composing())
        ("threads", po::value(&o.threads))
        ("memory-bytes", po::value(&o.memory_bytes));
    po::variables_map vm;
    po::store(po::command_line_parser(args).options(options).run(), vm);
    po::notify(vm);
    return o;
}

// The models a job may name: those the server found for it.
class JobModels {
public:
    void set(const json& models) {
        entries_.clear();
        if (!models.is_object()) return;
        for (const auto& [id, m] : models.items()) {
            hsr::host::ModelEntry entry;
            entry.id = id;
            entry.name = m.at("name").get<std::string>();
            entry.path = m.at("path").get<std::string>();
            entry.bytes = m.at("bytes").get<uint64_t>();
            entry.scene = m.at("scene").get<bool>();
            entries_[id] = std::move(entry);
        }
    }
    hsr::host::ModelEntry find(const std::string& id) const {
        const auto it = entries_.find(id);
        if (it == entries_.end())
            throw ViewError(404, "model", fmt::format("no model '{}'", hsr::printable(id, hsr::kMaxQuotedPathChars)));
        return it->second;
    }

private:
    std::map<std::string, hsr::host::ModelEntry> entries_;
};

Answer frame_answer(hsr::host::FrameAnswer frame) {
    if (frame.arrays.empty()) return hsr::host::json_answer(200, frame.body);
    return {200, hsr::host::kFrameWithArraysType, hsr::host::frame_with_arrays_head(frame), std::move(frame.arrays)};
}

// While a step request runs, its progress goes to the server every quarter second, as a message
// of its own: {"progress": {"steps": k, "total": n}} (total 0 while the steps are being counted).
class ProgressReporter {
public:
    explicit ProgressReporter(const hsr::StepProgress& progress)
        : progress_(progress), thread_([this] { report(); }) {}
    ~ProgressReporter() {
        {
            std::lock_guard lock(mutex_);
            done_ = true;
        }
        wake_.notify_one();
        thread_.join();
    }
    ProgressReporter(const ProgressReporter&) = delete;
    ProgressReporter& operator=(const ProgressReporter&) = delete;

private:
    void report() {
        uint64_t sent = 0;
        std::unique_lock lock(mutex_);
        while (!wake_.wait_for(lock, std::chrono::milliseconds(250), [this] { return done_; })) {
            const uint64_t steps = progress_.steps.load(std::memory_order_relaxed);
            const uint64_t total = progress_.total.load(std::memory_order_relaxed);
            if (steps == sent) continue;
            sent = steps;
            const json message{{"progress", {{"steps", steps}, {"total", total}}}};
            hsr::host::write_message(hsr::host::kChildSocketFd, message.dump() + "\n");
        }
    }

    const hsr::StepProgress& progress_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool done_ = false;
    std::thread thread_;
};

Answer run_job(const json& job, JobModels& models, hsr::host::FrameRenderer& frames, const hsr::PluginRegistry& registry) {
    const std::string op = job.at("op").get<std::string>();
    models.set(job.value("models", json::object()));
    if (op == "frame" && job.at("request").is_object() && job.at("request").contains("step") &&
        !job.at("request").at("step").is_null()) {
        hsr::StepProgress progress;
        const ProgressReporter reporter(progress);
        return frame_answer(frames.frame(job.at("request"), &progress));
    }
    if (op == "frame") return frame_answer(frames.frame(job.at("request")));
    if (op == "steps") {
        hsr::StepProgress progress;
        const ProgressReporter reporter(progress);
        return hsr::host::json_answer(200, frames.steps(job.at("request"), &progress));
    }
    if (op == "steps-zip") return {200, "application/zip", frames.steps_zip(job.at("request")), {}};
    if (op == "compare") return frame_answer(frames.compare(job.at("request")));
    if (op == "plugins") return hsr::host::json_answer(200, describe_plugins(registry, job.value("skip", json::array())));
    if (op == "theory") return hsr::host::json_answer(200, hsr::host::theory_page(registry, job.at("name").get<std::string>(), job.value("language", "en")));
    return hsr::host::error_answer(500, fmt::format("a worker got a job it does not know ('{}')", hsr::printable(op)));
}

Answer answer_job(const std::string& message, JobModels& models, hsr::host::FrameRenderer& frames,
                  const hsr::PluginRegistry& registry) {
    try {
        return run_job(json::parse(message), models, frames, registry);
    } catch (const ViewError& e) {
        return hsr::host::error_answer(e.status, e.what(), e.field);
    } catch (const hsr::Error& e) {
        // A limit hit, or a plugin that refuses this input, is the asker's to change.
        return hsr::host::error_answer(hsr::is_client_error(e) ? 400 : 500, e.what());
    } catch (const std::bad_alloc&) {
        return hsr::host::error_answer(500, "out of memory");
    } catch (const std::exception& e) {
        return hsr::host::error_answer(500, e.what());
    }
}

}  // namespace

int hsr::host::run_view_worker(const std::vector<std::string>& args) {
    // A worker lives no longer than its server, however the server ends.
    const pid_t server = ::getppid();
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != server) return 1;

    const WorkerOptions o = parse_worker_options(args);
    // AddressSanitizer reserves terabytes of address space for its shadow memory.
    if (o.memory_bytes > 0 && !hsr::kAddressSanitizer) {
        const rlimit bound{o.memory_bytes, o.memory_bytes};
        ::setrlimit(RLIMIT_AS, &bound);
    }
    hsr::set_limits(hsr::limits_from_settings(o.limits));
    const ThreadBound thread_bound(o.threads);
    const hsr::PluginRegistry registry = scan_plugins(o.plugin_dirs);
    std::vector<fs::path> read_folders(o.read_folders.begin(), o.read_folders.end());

    JobModels models;
    FrameRenderer frames(registry, [&models](const std::string& id) { return models.find(id); },
                         served_read_policy(std::move(read_folders)));
    std::string message;
    while (read_message(kChildSocketFd, message, kMaxJobBytes)) {
        const Answer answer = answer_job(message, models, frames, registry);
        const json header{{"status", answer.status}, {"content_type", answer.content_type}};
        if (!write_message(kChildSocketFd, {header.dump() + "\n", answer.body, answer.body_tail})) break;
    }
    return 0;
}
