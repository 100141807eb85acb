// hsr render: one render of the command line, one of each of its models, or the renders of a --jobs
// file (jobs.hpp), each prepared (render.hpp) before any is run.
#include "common/commands.hpp"
#include "render/jobs.hpp"
#include "render/render.hpp"
#include "render/standard_streams.hpp"

#include "hsr/error.hpp"

#include <malloc.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace {

// A render allocates and frees tens of megabytes once each: the model's text, what is parsed from it,
// the mesh, the scene, the frame's buffers. Served from the heap instead of a fresh mapping each, a
// freed block is used again and the heap grows in large steps, with fewer new pages to fault in:
// about a sixth of the bunny's load time in a new process (docs/speed/loading.md). Bench and view
// keep glibc's defaults, which give memory back (bench measures peak memory).
void reuse_freed_memory() {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    mallopt(M_TOP_PAD, 64 << 20);
}

}  // namespace

namespace {

using hsr::host::RenderOptions;
using hsr::host::UsageError;

// hsr render MODEL MODEL...: one render of each model, going on past one that fails as the lines of
// a --jobs file do. A file name given must hold {stem}, or every model would write the same file.
int run_models(const RenderOptions& options) {
    for (const auto& [option, text] : {std::pair<const char*, const std::string&>{"output", options.output},
                                       {"depth-out", options.depth_out},
                                       {"id-out", options.id_out},
                                       {"normal-out", options.normal_out},
                                       {"overdraw-out", options.overdraw_out},
                                       {"depth-tests-out", options.depth_tests_out},
                                       {"trace", options.trace}})
        if (!text.empty() && text.find(hsr::host::stem_placeholder) == std::string::npos)
            throw UsageError("--{} '{}': {} models would each write it; put {} (the model's file name without its "
                             "extension) in the name, e.g. '{}-{}'",
                             option, hsr::printable(text), options.models.size(), hsr::host::stem_placeholder,
                             hsr::host::stem_placeholder, hsr::printable(fs::path(text).filename().string()));
    hsr::host::PluginRegistries registries;
    std::vector<hsr::host::RenderJob> jobs;
    std::map<fs::path, std::string> writers;  // each file written, and the model whose render writes it
    for (const std::string& model : options.models) {
        if (model == "-") throw UsageError("MODEL '-': standard input is read by a render of its own, with one model");
        const std::string origin = hsr::printable(model, hsr::kMaxQuotedPathChars);
        RenderOptions one = options;
        one.model = model;
        one.models = {model};
        std::vector<fs::path> files;
        try {
            hsr::host::RenderJob job = hsr::host::prepare_render_job(std::move(one), registries, files);
            job.origin = origin;
            for (const fs::path& path : files) {
                const auto [other, inserted] = writers.emplace(path, origin);
                if (!inserted)
                    throw UsageError("'{}' is written by the render of {} too",
                                     hsr::printable(path.string(), hsr::kMaxQuotedPathChars), other->second);
            }
            jobs.push_back(std::move(job));
        } catch (const UsageError& e) {
            throw UsageError("{}: {}", origin, e.what());
        } catch (const hsr::Error& e) {
            if (std::string_view(e.what()).starts_with(origin + ":")) throw;  // it names the model already
            throw hsr::Error("{}: {}", origin, e.what());
        }
    }
    return hsr::host::run_jobs(jobs, hsr::host::JobFailures::kReportAndGoOn);
}

}  // namespace

int hsr::host::run_render(const std::vector<std::string>& args) {
    reuse_freed_memory();
    const RenderOptions options = parse_render_options(args);
    if (options.help) {
        print_render_help(options.plugin_dirs);
        return 0;
    }
    if (!options.jobs.empty()) {
        if (!options.models.empty())
            throw UsageError("--jobs {}: the models go on the lines of the file ('{}' is on the command line)",
                             hsr::printable(options.jobs, hsr::kMaxQuotedPathChars),
                             hsr::printable(options.models.front(), hsr::kMaxQuotedPathChars));
        return run_job_file(options.jobs, args);
    }
    if (options.models.size() > 1) return run_models(options);
    PluginRegistries registries;
    std::vector<fs::path> files;
    std::vector<RenderJob> jobs;
    jobs.push_back(prepare_render_job(options, registries, files));
    RenderOptions& job_options = jobs.front().options;
    std::optional<StdinModel> stdin_model;
    if (job_options.model == "-") {
        stdin_model.emplace(job_options.format);
        job_options.model = stdin_model->path().string();
    }
    if (job_options.output == "-") reserve_standard_output();
    return run_jobs(jobs, JobFailures::kStop);
}
