// hsr tiles: an image cut into square tiles, and the tiles shared out among threads (hsr/parallel.hpp),
// for plugins that work tile by tile (the ray casters, zbuffer). Header-only; link hsr::sdk_parallel.
#pragma once

#include "hsr/parallel.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
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

// Calls work(k, stats) for every tile k < tiles on the threads oneTBB allows, at most `threads` of
// them (0: no further bound), each tile with its own Stats; returns them in order of k.
template <class Stats, class Work>
std::vector<Stats> share_tiles(uint32_t tiles, uint32_t threads, Work&& work) {
    std::vector<Stats> stats;
    auto run = [&] { parallel_for_each(tiles, stats, work); };
    if (threads == 0)
        run();
    else
        tbb::task_arena(int(std::min(threads, 1024u))).execute(run);
    return stats;
}

}  // namespace hsr::sdk
