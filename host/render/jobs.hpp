// Running renders (render.hpp's RenderJob): the command line's one, or those of a --jobs file, each
// line the options of one hsr render. Each scene is loaded once for the jobs that share it; frames
// render one after another, each on every core, while the previous frame's files are written
// (docs/many-frames.md).
#pragma once

#include "render/render.hpp"

#include <filesystem>
#include <vector>

namespace hsr::host {

// What a failing job does to the others: stop them (the command line's render: its error is thrown),
// or be reported with its FILE:LINE and let them run (a --jobs file: an hsr::Error at the end).
enum class JobFailures { kStop, kReportAndGoOn };

// Runs the jobs in order; returns the exit status (0).
int run_jobs(std::vector<RenderJob>& jobs, JobFailures failures);

// Reads the file and prepares every job (prepare_render_job) before any is run, so that a mistake on
// any line stops the run before it starts, with the line's FILE:LINE; then runs them, going on past
// one that fails.
int run_job_file(const std::filesystem::path& file);

}  // namespace hsr::host
