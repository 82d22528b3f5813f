#pragma once
// Fills a leaf's consecutive triangle blocks lane by lane: the wide builders' one way of
// writing a leaf (the collapse from a binary tree and the direct Morton build).

#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/wide_bvh.h"

#include <cstdint>

namespace dynrt::bvh::detail {

class BlockWriter {
public:
    explicit BlockWriter(TriangleBlock* first) : first_(first), block_(first) {}

    /// Writes `t`, the caller's triangle `prim`, into the next lane.
    void add(const Triangle& t, std::uint32_t prim) {
        for (int axis = 0; axis < 3; ++axis) {
            block_->v0[axis][lane_] = t.v0[axis];
            block_->v1[axis][lane_] = t.v1[axis];
            block_->v2[axis][lane_] = t.v2[axis];
        }
        block_->prim[lane_] = prim;
        if (++lane_ == kBlockLanes) {
            lane_ = 0;
            ++block_;
        }
    }

    /// Ends the leaf: the last block's unused lanes repeat lane 0 and are marked kInvalidId.
    /// Returns the number of blocks written.
    std::uint32_t finish() {
        if (lane_ != 0) {
            for (; lane_ < kBlockLanes; ++lane_) {
                for (int axis = 0; axis < 3; ++axis) {
                    block_->v0[axis][lane_] = block_->v0[axis][0];
                    block_->v1[axis][lane_] = block_->v1[axis][0];
                    block_->v2[axis][lane_] = block_->v2[axis][0];
                }
                block_->prim[lane_] = kInvalidId;
            }
            lane_ = 0;
            ++block_;
        }
        return static_cast<std::uint32_t>(block_ - first_);
    }

private:
    TriangleBlock* first_;
    TriangleBlock* block_;
    int lane_ = 0;
};

}  // namespace dynrt::bvh::detail
