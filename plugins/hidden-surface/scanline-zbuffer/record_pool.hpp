// scanline-zbuffer's memory for the y-sorted polygon table of an instanced scene: a polygon set up
// before its first scanline waits there as a 64-byte record, in the bucket of that scanline. The
// buckets are chains of blocks taken from a pool and given back as soon as their scanline is
// activated, so memory follows what is pending below the sweep, not what is drawn; records are
// written with streaming stores (they are read back scanlines later) into chunks on huge pages.
// The polygon table itself is that of Wylie, Romney, Evans & Erdahl (1967) and Watkins (1970);
// this is only its storage. Included by scanline_zbuffer.cpp only.
#pragma once

#include "hsr/sdk.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace scanline_zbuffer {

inline constexpr uint32_t kNoPiece = ~uint32_t(0);  // PolygonRecord::piece of a whole triangle
inline constexpr uint32_t kSmall = kNoPiece - 1;    // PolygonRecord::piece of a small polygon, given by its spans

// A polygon whose setup was made before its first scanline: a polygon of an instanced scene that
// does not start on the scanline its placement is activated on (the next placement overwrites the
// geometry stage's vertices), and the pieces of clipped triangles. It holds what its edge pair and
// its depth start from, in one cache line. The planes of the barycentrics are not kept: most
// polygons of a deep scene are hidden, and those that win a pixel have them made again, bit for
// bit, from their placement's vertices.
struct alignas(64) PolygonRecord {
    int32_t x[3], y[3];     // snapped corners, in the setup's corner order (interior on the left of
                            // each edge k, from corner k+1 to corner k+2, seen with y down)
    double z_origin;        // depth at the centre of its setup's origin pixel (min_x, min_y)
    double dzdx, dzdy;
    uint32_t face;
    uint32_t placement;
    uint32_t piece;         // kNoPiece, or the setup of a clipped piece (clipping is not repeated),
                            // or kSmall: then x holds left, right and the left step, y the right
                            // step, the last scanline and 2 min_x + (first scanline - min_y)
                            // (see small_spans)
    uint32_t id;            // drawing order (instances only; with one placement it is the table index)
};
static_assert(sizeof(PolygonRecord) == 64);

// The spans of a small polygon (small_coverage's `covered` over the pixels from (min_x, min_y))
// into its record: on its first scanline [left, right] = x[0], x[1]; on the next, if y[1] (its
// last scanline) is that one, moved by x[2] and y[0]. Its edges then step without error terms.
// Returns the first scanline (min_y, or the one below when no centre of the top row is covered);
// y[2] keeps the depth plane's origin pixel: 2 min_x plus the first scanline's offset from min_y.
inline int32_t small_spans(uint32_t covered, int32_t min_x, int32_t min_y, PolygonRecord& r) {
    const uint32_t top = covered & 3, bottom = covered >> 2;
    const int32_t top_left = min_x + int32_t(~top & 1), top_right = min_x + int32_t(top >> 1);
    const int32_t bottom_left = min_x + int32_t(~bottom & 1), bottom_right = min_x + int32_t(bottom >> 1);
    r.y[1] = min_y + (bottom ? 1 : 0);
    r.y[2] = 2 * min_x;
    if (top == 0) {
        r.x[0] = bottom_left;
        r.x[1] = bottom_right;
        r.x[2] = 0;
        r.y[0] = 0;
        r.y[2] += 1;
        return min_y + 1;
    }
    r.x[0] = top_left;
    r.x[1] = top_right;
    r.x[2] = bottom_left - top_left;
    r.y[0] = bottom_right - top_right;
    return min_y;
}

// Asks for transparent huge pages over the 2 MB pages inside [p, p + bytes). The record pool of a
// deep scene grows to 100 MB and more, written fresh by a new instance: on 4 KB pages that is a
// page fault per 64 records and many TLB misses.
inline void advise_huge_pages([[maybe_unused]] const void* p, [[maybe_unused]] size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr uintptr_t kHuge = uintptr_t(2) << 20;
    const uintptr_t begin = (uintptr_t(p) + kHuge - 1) & ~(kHuge - 1);
    const uintptr_t end = (uintptr_t(p) + bytes) & ~(kHuge - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // only a hint
#endif
}

// Writes a record past the caches. Records are written to the tails of a thousand buckets at once
// and read back scanlines later: ordinary stores would first read every line from memory.
inline void store_streaming(PolygonRecord& to, const PolygonRecord& from) {
#if defined(__SSE2__)
    const __m128i* const source = reinterpret_cast<const __m128i*>(&from);
    __m128i* const target = reinterpret_cast<__m128i*>(&to);
    for (int k = 0; k < 4; ++k) _mm_stream_si128(target + k, _mm_load_si128(source + k));
#else
    to = from;
#endif
}

// Orders the streamed stores before the records are read.
inline void end_streaming() {
#if defined(__SSE2__)
    _mm_sfence();
#endif
}

// The records waiting for their first scanline, by scanline, in chains of blocks taken from a
// pool; a scanline's blocks go back to the pool when it is activated, so the pool holds only what
// is pending below the current scanline.
class RecordPool {
public:
    static constexpr uint32_t kBlockRecords = 32;   // 2 KB

    // Every scanline of an image `height` rows high empty; the chunks stay allocated.
    void reset(int32_t height) {
        rows_.assign(size_t(height), RowChain{});
        free_blocks_.clear();
        for (uint32_t b = uint32_t(block_next_.size()); b-- > 0;) free_blocks_.push_back(b);
        blocks_used_max_ = 0;
    }

    // A new record at the end of scanline `row`'s chain.
    PolygonRecord& new_record(int32_t row) {
        RowChain& c = rows_[size_t(row)];
        if (c.fill == kBlockRecords) {
            if (free_blocks_.empty()) [[unlikely]]
                grow_pool();
            const uint32_t b = free_blocks_.back();
            free_blocks_.pop_back();
            blocks_used_max_ = std::max(blocks_used_max_, block_next_.size() - free_blocks_.size());
            if (c.head == kNoBlock)
                c.head = b;
            else
                block_next_[c.tail] = b;
            c.tail = b;
            c.fill = 0;
        }
        return block(c.tail)[c.fill++];
    }

    // visit(record) for the records of scanline `row` in the order they were added, read block
    // after block (each in order: the hardware prefetcher follows); the blocks go back to the pool.
    template <class Visit>
    void drain(int32_t row, Visit&& visit) {
        RowChain& c = rows_[size_t(row)];
        for (uint32_t b = c.head; b != kNoBlock;) {
            const bool last = b == c.tail;
            const uint32_t next = last ? kNoBlock : block_next_[b];
            const uint32_t count = last ? c.fill : kBlockRecords;
            if (!last) __builtin_prefetch(block(next));
            const PolygonRecord* const records = block(b);
            for (uint32_t k = 0; k < count; ++k) visit(records[k]);
            free_blocks_.push_back(b);
            b = next;
        }
        c = RowChain{};
    }

    // The most records the pool held at once since reset (in whole blocks).
    uint64_t records_max() const { return uint64_t(blocks_used_max_) * kBlockRecords; }

private:
    static constexpr uint32_t kNoBlock = ~uint32_t(0);
    static constexpr uint32_t kChunkBlocks = 2048;  // 4 MB, allocated as the pool grows
    static constexpr size_t kChunkAlign = size_t(2) << 20;
    struct RowChain {
        uint32_t head = kNoBlock, tail = kNoBlock;
        uint32_t fill = kBlockRecords;  // records in the tail block
    };
    struct ChunkDelete {
        void operator()(PolygonRecord* p) const { ::operator delete[](p, std::align_val_t(kChunkAlign)); }
    };

    PolygonRecord* block(uint32_t b) {
        return chunks_[b / kChunkBlocks].get() + size_t(b % kChunkBlocks) * kBlockRecords;
    }

    [[gnu::noinline]] void grow_pool() {
        constexpr size_t bytes = size_t(kChunkBlocks) * kBlockRecords * sizeof(PolygonRecord);
        if (block_next_.size() + kChunkBlocks > kNoBlock)
            throw hsr::sdk::Unsupported("scanline-zbuffer: too many polygons waiting for their first scanline");
        auto* p = static_cast<PolygonRecord*>(::operator new[](bytes, std::align_val_t(kChunkAlign)));
        chunks_.emplace_back(p);
        advise_huge_pages(p, bytes);
        const uint32_t first = uint32_t(block_next_.size());
        block_next_.resize(block_next_.size() + kChunkBlocks, kNoBlock);
        for (uint32_t b = first + kChunkBlocks; b-- > first;) free_blocks_.push_back(b);
    }

    std::vector<RowChain> rows_;                                         // per scanline, its pending records
    std::vector<std::unique_ptr<PolygonRecord[], ChunkDelete>> chunks_;  // the pool of record blocks
    std::vector<uint32_t> block_next_;                                   // per block: the next of its chain
    std::vector<uint32_t> free_blocks_;
    size_t blocks_used_max_ = 0;
};

}  // namespace scanline_zbuffer
