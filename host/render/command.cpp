// hsr render: one render of the command line, or the renders of a --jobs file (jobs.hpp), each
// prepared (render.hpp) before any is run.
#include "common/commands.hpp"
#include "render/jobs.hpp"
#include "render/render.hpp"
#include "render/standard_streams.hpp"

#include <malloc.h>

#include <filesystem>
#include <optional>
#include <string>
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

int hsr::host::run_render(const std::vector<std::string>& args) {
    reuse_freed_memory();
    const RenderOptions options = parse_render_options(args);
    if (options.help) {
        print_render_help(options.plugin_dirs);
        return 0;
    }
    if (!options.jobs.empty()) {
        for (const std::string& option : options.given)
            if (option != "jobs")
                throw UsageError("--jobs {}: --{} goes on the lines of the file, which hold every option of each render",
                                 hsr::printable(options.jobs), option);
        return run_job_file(options.jobs);
    }
    PluginRegistries registries;
    std::vector<fs::path> files;
    std::vector<RenderJob> jobs;
    jobs.push_back(prepare_render_job(args, registries, files));
    RenderOptions& job_options = jobs.front().options;
    std::optional<StdinModel> stdin_model;
    if (job_options.model == "-") {
        stdin_model.emplace(job_options.format);
        job_options.model = stdin_model->path().string();
    }
    if (job_options.output == "-") reserve_standard_output();
    return run_jobs(jobs, JobFailures::kStop);
}
