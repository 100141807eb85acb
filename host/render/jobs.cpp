// Running render jobs (jobs.hpp): scenes loaded once and shared, frames rendered in order, each
// frame's files written on another thread while the next frame renders.
#include "render/jobs.hpp"

#include "common/options.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <boost/program_options/parsers.hpp>
#include <fmt/format.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>

namespace fs = std::filesystem;

namespace hsr::host {
namespace {

// A scene's renderer and the jobs that still need it; freed after the last of them.
struct SharedScene {
    std::shared_ptr<hsr::Renderer> renderer;
    std::size_t jobs_left = 0;
    bool tried = false;
    std::string error;  // why the load failed
};

// Writes one frame's files at a time on another thread (oneTBB), while the caller renders the next
// frame. An error is kept with the job it belongs to and handed back by wait().
class FrameWriter {
public:
    ~FrameWriter() { group_.wait(); }

    // Waits for the frame before, then starts write() for job `job`.
    template <typename Write>
    void start(std::size_t job, Write write) {
        wait();
        job_ = job;
        group_.run([this, write = std::move(write)] {
            try {
                write();
            } catch (...) {
                error_ = std::current_exception();
            }
        });
    }

    // Waits for the frame being written. Returns the job whose frame failed (and its error), if any.
    std::pair<std::size_t, std::exception_ptr> wait() {
        group_.wait();
        return {job_, std::exchange(error_, nullptr)};
    }

private:
    tbb::task_group group_;
    std::size_t job_ = 0;
    std::exception_ptr error_;
};

void report(const RenderJob& job, const std::exception_ptr& error) {
    try {
        std::rethrow_exception(error);
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "hsr: error: %s: out of memory\n", job.origin.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "hsr: error: %s: %s\n", job.origin.c_str(), e.what());
    }
}

}  // namespace

int run_jobs(std::vector<RenderJob>& jobs, JobFailures failures) {
    std::vector<std::string> keys;
    std::map<std::string, SharedScene> scenes;
    for (const RenderJob& job : jobs) {
        keys.push_back(scene_load_key(job.options));
        ++scenes[keys.back()].jobs_left;
    }
    std::vector<bool> failed(jobs.size(), false);
    FrameWriter writer;
    // A failure of the frame being written: thrown, or reported once for its job.
    const auto check = [&](std::pair<std::size_t, std::exception_ptr> written) {
        if (!written.second) return;
        if (failures == JobFailures::kStop) std::rethrow_exception(written.second);
        if (!failed[written.first]) report(jobs[written.first], written.second);
        failed[written.first] = true;
    };
    for (std::size_t j = 0; j < jobs.size(); ++j) {
        RenderJob& job = jobs[j];
        SharedScene& shared = scenes[keys[j]];
        try {
            hsr::set_limits(job.limits);
            if (!shared.tried) {
                shared.tried = true;
                check(writer.wait());  // the messages of the frame before come first
                const auto start = std::chrono::steady_clock::now();
                try {
                    const ThreadBound thread_bound(job.options.threads);
                    shared.renderer = std::make_shared<hsr::Renderer>(hsr::LoadedScene::load(scene_source(job.options)));
                } catch (const std::exception& e) {
                    shared.error = e.what();
                    throw;
                }
                const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - start;
                for (const std::string& warning : shared.renderer->loaded().scene().warnings)
                    std::fprintf(stderr, "hsr: warning: %s\n", warning.c_str());
                if (job.options.stats)
                    std::fprintf(stderr, "load time: scene %.2f ms (read, checked, normals and adjacency)\n",
                                 took.count());
                if (failures == JobFailures::kReportAndGoOn)
                    std::fprintf(stderr, "loaded %s once for %zu job%s (%llu triangles, %.1f ms)\n",
                                 model_path(job.options).string().c_str(), shared.jobs_left,
                                 shared.jobs_left == 1 ? "" : "s",
                                 static_cast<unsigned long long>(
                                     hsr::drawn_triangle_count(shared.renderer->loaded().scene().view())),
                                 took.count());
            }
            if (!shared.renderer) throw hsr::Error("{}", shared.error);
            for (std::size_t k = 0; k < job.frames.size() && !failed[j]; ++k) {
                RenderOptions o = job.frame_options(k);
                if (job.picture) {
                    auto picture = std::make_shared<hsr::Picture>(render_picture(o, *shared.renderer, *job.picture));
                    check(writer.wait());
                    writer.start(j, [o = std::move(o), picture, keep = shared.renderer, &plugins = *job.picture] {
                        write_picture(o, *picture, plugins, o.output);
                    });
                } else {
                    check(writer.wait());
                    render_line_drawing(o, *shared.renderer, *job.line_drawing, o.output);
                }
            }
        } catch (...) {
            if (failures == JobFailures::kStop) throw;
            const std::exception_ptr error = std::current_exception();
            check(writer.wait());
            report(job, error);
            failed[j] = true;
        }
        if (--shared.jobs_left == 0) shared.renderer.reset();  // the writer may keep it a little longer
    }
    check(writer.wait());
    const std::size_t failures_count = std::size_t(std::count(failed.begin(), failed.end(), true));
    if (failures_count > 0)
        throw hsr::Error("{} of {} jobs failed (the errors above)", failures_count, jobs.size());
    return 0;
}

int run_job_file(const fs::path& file) {
    std::ifstream in(file);
    if (!in) throw hsr::Error("--jobs '{}': cannot read it", hsr::printable(file.string(), hsr::kMaxQuotedPathChars));
    PluginRegistries registries;
    std::vector<RenderJob> jobs;
    std::unordered_map<std::string, std::string> writers;  // each file written, and the line that writes it
    uint64_t frames = 0;
    std::string line;
    for (uint64_t number = 1; std::getline(in, line); ++number) {
        const std::size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        const std::string origin = fmt::format("{}:{}", file.string(), number);
        try {
            std::vector<std::string> args;
            try {
                args = boost::program_options::split_unix(line);
            } catch (const std::exception& e) {  // Boost.Tokenizer's, for an unclosed quote
                throw UsageError("{}", e.what());
            }
            std::vector<fs::path> files;
            RenderJob job = prepare_render_job(args, registries, files);
            job.origin = origin;
            frames += job.frames.size();
            hsr::check_limit(&hsr::Limits::frames, frames, "the lines so far");
            for (const fs::path& path : files) {
                const auto [other, inserted] = writers.emplace(path.string(), origin);
                if (!inserted)
                    throw UsageError("'{}' is written by {} too", hsr::printable(path.string()), other->second);
            }
            jobs.push_back(std::move(job));
        } catch (const UsageError& e) {
            throw UsageError("{}: {}", origin, e.what());
        } catch (const boost::program_options::error& e) {
            throw UsageError("{}: {}", origin, e.what());
        } catch (const hsr::Error& e) {
            throw hsr::Error("{}: {}", origin, e.what());
        }
    }
    if (in.bad()) throw hsr::Error("--jobs '{}': a read error", hsr::printable(file.string()));
    if (jobs.empty())
        throw UsageError("--jobs '{}': no jobs in the file (each line holds the options of one render)",
                         hsr::printable(file.string()));
    return run_jobs(jobs, JobFailures::kReportAndGoOn);
}

}  // namespace hsr::host
