// hsr tiles: an image cut into square tiles, and the tiles shared out among threads, each thread
// taking the next tile left, for plugins that work tile by tile (the ray casters). Header-only, part
// of hsr::sdk.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <functional>
#include <system_error>
#include <thread>
#include <vector>

namespace hsr::sdk {

struct TileGrid {
    uint32_t width = 0, height = 0;
    uint32_t size = 1;  // pixels a side

    uint32_t across() const { return (width + size - 1) / size; }
    uint32_t count() const { return across() * ((height + size - 1) / size); }
    // Tile k's pixels [x0, x1) x [y0, y1); tiles run in rows from the top left.
    void rect(uint32_t k, uint32_t& x0, uint32_t& y0, uint32_t& x1, uint32_t& y1) const {
        x0 = (k % across()) * size;
        y0 = (k / across()) * size;
        x1 = std::min(x0 + size, width);
        y1 = std::min(y0 + size, height);
    }
};

// Calls work(k, stats) for every tile k < tiles on up to `threads` threads (0: one per core), the
// calling thread among them, each with its own Stats, which it returns. Should a thread fail to
// start, the others do its tiles.
template <class Stats, class Work>
std::vector<Stats> share_tiles(uint32_t tiles, uint32_t threads, Work&& work) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    threads = std::max(1u, std::min(threads, tiles));
    std::atomic<uint32_t> next{0};
    std::vector<Stats> stats(threads);
    auto worker = [&](Stats& s) {
        for (uint32_t k = next.fetch_add(1); k < tiles; k = next.fetch_add(1)) work(k, s);
    };
    std::vector<std::thread> pool;
    try {
        for (uint32_t t = 1; t < threads; ++t) pool.emplace_back(worker, std::ref(stats[t]));
    } catch (const std::system_error&) {
    }
    worker(stats[0]);
    for (std::thread& t : pool) t.join();
    return stats;
}

}  // namespace hsr::sdk
