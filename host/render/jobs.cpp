// Running render jobs (jobs.hpp): scenes loaded once and shared, frames rendered in order, each
// frame's files written on another thread while the next frame renders.
#include "render/jobs.hpp"

#include "common/commands.hpp"
#include "common/options.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <boost/program_options/errors.hpp>
#include <fmt/format.h>
#include <tbb/task_group.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <optional>
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

std::string error_message(const std::exception_ptr& error) {
    try {
        std::rethrow_exception(error);
    } catch (const std::bad_alloc&) {
        return "out of memory";
    } catch (const std::exception& e) {
        return message_line(e.what());
    }
}

// A failed job's error: printed with its origin, or kept for the caller when `kept` is given.
void report(const RenderJob& job, std::size_t index, const std::exception_ptr& error,
            std::vector<std::optional<std::string>>* kept) {
    const std::string message = error_message(error);
    // The origin of a command line's model is its path, which the model's own errors name already.
    const bool named = message.rfind(job.origin + ":", 0) == 0;
    if (kept) (*kept)[index] = message;
    else if (named) std::fprintf(stderr, "hsr: error: %s\n", message.c_str());
    else std::fprintf(stderr, "hsr: error: %s: %s\n", job.origin.c_str(), message.c_str());
}

// A file descriptor, closed when it goes.
class FileDescriptor {
public:
    explicit FileDescriptor(int fd) : fd_(fd) {}
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    ~FileDescriptor() {
        if (fd_ >= 0) ::close(fd_);
    }
    int get() const { return fd_; }

private:
    int fd_;
};

// Hands each line of the --jobs file to `take` (its number and its text without the line end: LF,
// or CR LF). The file is opened without waiting (a FIFO would wait for a writer) and checked to be a
// regular file before a byte is read; a line is refused past kMaxJobLineBytes and the file past
// kMaxJobFileBytes, whatever its size said.
void read_job_lines(const fs::path& file, const std::function<void(uint64_t, std::string_view)>& take) {
    const std::string shown = hsr::printable(file.string(), hsr::kMaxQuotedPathChars);
    const FileDescriptor fd(::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
    if (fd.get() < 0) throw hsr::Error("--jobs '{}': cannot read it ({})", shown, std::strerror(errno));
    struct stat status {};
    if (::fstat(fd.get(), &status) != 0) throw hsr::Error("--jobs '{}': cannot read it ({})", shown, std::strerror(errno));
    if (S_ISDIR(status.st_mode)) throw UsageError("--jobs '{}': is a folder, not a file of renders", shown);
    if (!S_ISREG(status.st_mode))
        throw UsageError("--jobs '{}': is not a regular file (a pipe, device or socket), not a file of renders", shown);
    if (uint64_t(status.st_size) > kMaxJobFileBytes)
        throw UsageError("--jobs '{}': {} bytes, more than a jobs file may hold ({} bytes)", shown,
                         uint64_t(status.st_size), kMaxJobFileBytes);
    // A regular file never blocks; the flag is dropped only to read it the ordinary way.
    ::fcntl(fd.get(), F_SETFL, ::fcntl(fd.get(), F_GETFL) & ~O_NONBLOCK);

    std::string line;
    uint64_t number = 1;
    std::size_t total = 0;
    const auto finish_line = [&] {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        take(number++, line);
        line.clear();
    };
    std::vector<char> chunk(1 << 16);
    for (;;) {
        const ssize_t got = ::read(fd.get(), chunk.data(), chunk.size());
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw hsr::Error("--jobs '{}': a read error ({})", shown, std::strerror(errno));
        if (got == 0) break;
        total += std::size_t(got);
        if (total > kMaxJobFileBytes)
            throw UsageError("--jobs '{}': more than a jobs file may hold ({} bytes)", shown, kMaxJobFileBytes);
        for (std::string_view rest(chunk.data(), std::size_t(got)); !rest.empty();) {
            const std::size_t end = rest.find('\n');
            const std::string_view part = rest.substr(0, end);
            if (line.size() + part.size() > kMaxJobLineBytes)
                throw UsageError("{}:{}: the line is longer than a jobs line may be ({} bytes)", shown, number,
                                 kMaxJobLineBytes);
            line.append(part);
            if (end == std::string_view::npos) break;
            finish_line();
            rest.remove_prefix(end + 1);
        }
    }
    if (!line.empty()) finish_line();
}

}  // namespace

std::vector<std::string> split_job_line(std::string_view line) {
    std::vector<std::string> words;
    std::string word;
    bool in_word = false;  // a word has begun, perhaps with empty quotes
    for (std::size_t at = 0; at < line.size(); ++at) {
        const char c = line[at];
        if (c == ' ' || c == '\t') {
            if (in_word) words.push_back(std::move(word));
            word.clear();
            in_word = false;
            continue;
        }
        in_word = true;
        if (c == '\\') {
            if (++at == line.size()) throw UsageError("the line ends in a backslash, which escapes nothing");
            word += line[at];
        } else if (c == '\'') {
            const std::size_t end = line.find('\'', at + 1);
            if (end == std::string_view::npos)
                throw UsageError("a quote (') at column {} is not closed on its line", at + 1);
            word.append(line.substr(at + 1, end - at - 1));
            at = end;
        } else if (c == '"') {
            const std::size_t open = at;
            for (++at;; ++at) {
                if (at == line.size()) throw UsageError("a quote (\") at column {} is not closed on its line", open + 1);
                char d = line[at];
                if (d == '"') break;
                if (d == '\\' && at + 1 < line.size() && std::string_view("\"\\$`").find(line[at + 1]) != std::string_view::npos)
                    d = line[++at];
                word += d;
            }
        } else {
            word += c;
        }
    }
    if (in_word) words.push_back(std::move(word));
    return words;
}

int run_jobs(std::vector<RenderJob>& jobs, JobFailures failures, std::vector<std::optional<std::string>>* kept) {
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
        if (!failed[written.first]) report(jobs[written.first], written.first, written.second, kept);
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
                if (failures == JobFailures::kReportAndGoOn && !kept)
                    std::fprintf(stderr, "loaded %s once for %zu job%s (%llu triangles, %.1f ms)\n",
                                 hsr::printable(model_path(job.options).string(), std::string::npos).c_str(), shared.jobs_left,
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
            report(job, j, error, kept);
            failed[j] = true;
        }
        if (--shared.jobs_left == 0) shared.renderer.reset();  // the writer may keep it a little longer
    }
    check(writer.wait());
    const std::size_t failures_count = std::size_t(std::count(failed.begin(), failed.end(), true));
    if (failures_count > 0 && !kept)
        throw hsr::Error("{} of {} jobs failed (the errors above)", failures_count, jobs.size());
    return 0;
}

int run_job_file(const fs::path& file, const std::vector<std::string>& defaults) {
    const std::string shown = hsr::printable(file.string(), hsr::kMaxQuotedPathChars);
    const fs::path folder = file.parent_path();
    PluginRegistries registries;
    std::vector<RenderJob> jobs;
    std::unordered_map<std::string, std::string> writers;  // each file written, and the line that writes it
    uint64_t frames = 0;
    read_job_lines(file, [&](uint64_t number, std::string_view line) {
        const std::size_t first = line.find_first_not_of(" \t");
        if (first == std::string_view::npos || line[first] == '#') return;
        const std::string origin = fmt::format("{}:{}", shown, number);
        try {
            const std::vector<std::string> args = job_line_arguments(split_job_line(line), folder, defaults);
            check_argument_count(args.size());
            std::vector<fs::path> files;
            RenderJob job = prepare_render_job(args, registries, files);
            if (job.options.model == "-" || job.options.output == "-")
                throw UsageError("a --jobs line reads and writes files: standard {} ('-') is for a render of its own",
                                 job.options.model == "-" ? "input" : "output");
            job.origin = origin;
            frames += job.frames.size();
            hsr::check_limit(&hsr::Limits::frames, frames, "the lines so far");
            for (const fs::path& path : files) {
                const auto [other, inserted] = writers.emplace(path.string(), origin);
                if (!inserted)
                    throw UsageError("'{}' is written by {} too", hsr::printable(path.string(), hsr::kMaxQuotedPathChars),
                                     other->second);
            }
            jobs.push_back(std::move(job));
        } catch (const UsageError& e) {
            throw UsageError("{}: {}", origin, e.what());
        } catch (const boost::program_options::error& e) {
            throw UsageError("{}: {}", origin, e.what());
        } catch (const hsr::Error& e) {
            throw hsr::Error("{}: {}", origin, e.what());
        }
    });
    if (jobs.empty())
        throw UsageError("--jobs '{}': no jobs in the file (each line holds the options of one render)", shown);
    return run_jobs(jobs, JobFailures::kReportAndGoOn);
}

std::vector<std::optional<std::string>> run_jobs_keeping_errors(std::vector<RenderJob>& jobs) {
    std::vector<std::optional<std::string>> errors(jobs.size());
    run_jobs(jobs, JobFailures::kReportAndGoOn, &errors);
    return errors;
}

}  // namespace hsr::host
