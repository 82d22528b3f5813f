#pragma once
// Fills a leaf's consecutive triangle blocks lane by lane: the wide builders' one way of
// writing a leaf (the collapse from a binary tree and the direct Morton build), into full
// blocks or, with compact leaves, into the blocks' indices only.

#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/wide_bvh.h"

#include "huge_pages.h"

#include <cstdint>

namespace dynrt::bvh::detail {

/// Where a tree's leaf blocks are written: full blocks, or compact ones (one is null).
struct BlockTarget {
    TriangleBlock* full = nullptr;
    PrimBlock* compact = nullptr;

    /// Whether the writer needs the triangles at all (compact blocks hold indices only).
    bool wants_triangles() const { return full != nullptr; }
    BlockTarget operator+(std::uint32_t b) const {
        return full != nullptr ? BlockTarget{full + b, nullptr} : BlockTarget{nullptr, compact + b};
    }
};

/// Sizes `wide`'s block array of its kind (wide.compact) to `count` blocks and returns where
/// they are written. The other kind's storage, a recycled tree's of the other layout, is freed
/// (kept, it held a full tree's blocks under a compact one).
template <int N>
BlockTarget allocate_blocks(WideBvhOf<N>& wide, std::size_t count) {
    if (wide.compact) {
        decltype(wide.blocks)().swap(wide.blocks);
        resize_with_huge_pages(wide.prim_blocks, count);
        return BlockTarget{nullptr, wide.prim_blocks.data()};
    }
    decltype(wide.prim_blocks)().swap(wide.prim_blocks);
    resize_with_huge_pages(wide.blocks, count);
    return BlockTarget{wide.blocks.data(), nullptr};
}

class BlockWriter {
public:
    explicit BlockWriter(BlockTarget first) : target_(first) {}

    /// Writes `t`, the caller's triangle `prim`, into the next lane (a compact block keeps
    /// `prim` only: `t` is not read).
    void add(const Triangle& t, std::uint32_t prim) {
        if (target_.compact != nullptr) {
            add_prim(prim);
            return;
        }
        TriangleBlock* block = target_.full + written_;
        for (int axis = 0; axis < 3; ++axis) {
            block->v0[axis][lane_] = t.v0[axis];
            block->v1[axis][lane_] = t.v1[axis];
            block->v2[axis][lane_] = t.v2[axis];
        }
        block->prim[lane_] = prim;
        next_lane();
    }

    /// Writes the caller's triangle `prim` into the next lane of a compact block.
    void add_prim(std::uint32_t prim) {
        target_.compact[written_].prim[lane_] = prim;
        next_lane();
    }

    /// Ends the leaf: the last block's unused lanes repeat lane 0 and are marked kInvalidId.
    /// Returns the number of blocks written.
    std::uint32_t finish() {
        if (lane_ != 0) {
            for (; lane_ < kBlockLanes; ++lane_) {
                if (target_.compact != nullptr) {
                    target_.compact[written_].prim[lane_] = kInvalidId;
                    continue;
                }
                TriangleBlock* block = target_.full + written_;
                for (int axis = 0; axis < 3; ++axis) {
                    block->v0[axis][lane_] = block->v0[axis][0];
                    block->v1[axis][lane_] = block->v1[axis][0];
                    block->v2[axis][lane_] = block->v2[axis][0];
                }
                block->prim[lane_] = kInvalidId;
            }
            lane_ = 0;
            ++written_;
        }
        return written_;
    }

private:
    void next_lane() {
        if (++lane_ == kBlockLanes) {
            lane_ = 0;
            ++written_;
        }
    }

    BlockTarget target_;
    std::uint32_t written_ = 0;
    int lane_ = 0;
};

}  // namespace dynrt::bvh::detail
