// hsr parallel: coarse parallel loops for plugins (over tiles, bands, chunks of triangles) on oneTBB,
// the one task scheduler of the process. The host bounds every thread with tbb::global_control
// (from --threads), so a plugin never takes a thread count: it splits its work into items and lets
// these helpers spread them over the threads allowed. Header-only; link hsr::sdk_parallel
// (hsr::sdk + TBB::tbb).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hsr::sdk {

// How many threads a parallel loop started here may use (the host's bound, the task arena, the CPU
// affinity mask): a plugin whose parallel path costs more work than its serial one takes the serial
// path when this is 1.
inline size_t allowed_threads() {
    return std::min(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism),
                    size_t(std::max(1, tbb::this_task_arena::max_concurrency())));
}

// Calls work(k) once for every k < count, spread over the threads oneTBB allows, each k a task of
// its own (items are meant to be coarse). Returns when all are done; an exception thrown by work
// reaches the caller (the first one thrown; items not yet started are then skipped).
template <class Work>
void parallel_for_each(uint32_t count, Work&& work) {
    if (count == 0) return;
    if (count == 1) {
        work(uint32_t(0));
        return;
    }
    tbb::parallel_for(
        tbb::blocked_range<uint32_t>(0, count, 1),
        [&](const tbb::blocked_range<uint32_t>& range) {
            for (uint32_t k = range.begin(); k != range.end(); ++k) work(k);
        },
        tbb::simple_partitioner());
}

// parallel_for_each where each item k counts into stats[k] (cleared first, resized to count): the
// caller adds them up in order of k, so the totals do not depend on the threads (even for floating
// point). `stats` can be kept between calls so that steady state allocates nothing.
template <class Stats, class Work>
void parallel_for_each(uint32_t count, std::vector<Stats>& stats, Work&& work) {
    stats.assign(count, Stats{});
    parallel_for_each(count, [&](uint32_t k) { work(k, stats[k]); });
}

// Scratch space of each thread (a buffer a task fills and drops again), made on a thread's first
// local() and kept until the PerThread object goes.
template <class T>
using PerThread = tbb::enumerable_thread_specific<T>;

}  // namespace hsr::sdk
