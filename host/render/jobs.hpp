// Running renders (render.hpp's RenderJob): the command line's one, or those of a --jobs file, each
// line the options of one hsr render. Each scene is loaded once for the jobs that share it; frames
// render one after another, each on every core, while the previous frame's files are written
// (docs/many-frames.md).
#pragma once

#include "render/render.hpp"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hsr::host {

// What a failing job does to the others: stop them (the command line's render: its error is thrown),
// or be reported with its FILE:LINE and let them run (a --jobs file: an hsr::Error at the end).
enum class JobFailures { kStop, kReportAndGoOn };

// Runs the jobs in order; returns the exit status (0). With `kept`, sized as jobs, a failing job's
// message goes there instead of to standard error, and no error is thrown at the end.
int run_jobs(std::vector<RenderJob>& jobs, JobFailures failures,
             std::vector<std::optional<std::string>>* kept = nullptr);

// The jobs run going on past failures, as a --jobs file's are: each job's error message, or none.
std::vector<std::optional<std::string>> run_jobs_keeping_errors(std::vector<RenderJob>& jobs);

// The longest line a --jobs file may hold, in bytes: a line is read whole before it is split, and the
// options of one render, paths included, fit in a small part of it.
inline constexpr std::size_t kMaxJobLineBytes = 64 * 1024;
// The largest --jobs file, in bytes: far more than the frames limit's 100,000 lines need, and read
// no further than this even if the file grows meanwhile.
inline constexpr std::size_t kMaxJobFileBytes = 64 << 20;

// The words of one --jobs line, split and unquoted as a POSIX shell does without expansions: blanks
// (space, tab) between words; a backslash outside quotes keeps the next character as it is; '...'
// keeps everything to the next '; "..." keeps everything to the next unescaped ", a backslash in it
// escaping only ", \, $ and `. An empty pair of quotes is an empty word. Throws hsr::UsageError for
// a quote without its end or a line that ends in a backslash.
std::vector<std::string> split_job_line(std::string_view line);

// Reads the file and prepares every job (prepare_render_job) before any is run, so that a mistake on
// any line stops the run before it starts, with the line's FILE:LINE; then runs them, going on past
// one that fails. Each line's words are taken as job_line_arguments says: the files it reads from the
// file's folder, and the options of `defaults` (hsr render's command line) it does not give itself.
// FILE must be a regular file (a pipe or a device is refused before it is read) of at most
// kMaxJobFileBytes; a line may end in CR LF.
int run_job_file(const std::filesystem::path& file, const std::vector<std::string>& defaults);

}  // namespace hsr::host
