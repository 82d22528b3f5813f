#pragma once
// A wide tree's triangles read back from its own leaf blocks, by the index the caller gave
// each triangle at the build. The blocks hold every triangle of the tree bit for bit (the
// collapse copies them, a refit rewrites them in place, each in its lane), so a caller can
// free its own copy of the triangles it built from, 36 bytes each, and keep this index, 4
// bytes each, for the few reads it still makes (a hit's corners for shading).
//
// Embree makes the same trade in its compact mode (RTC_SCENE_FLAG_COMPACT): leaves that refer
// to the application's vertices rather than a copy of them. Here the copy kept is the tree's
// own, so the trace is unchanged.

#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/triangle_source.h"
#include "dynrt/bvh/wide_bvh.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace dynrt::bvh {

class BlockTriangles {
public:
    /// Indexes the blocks of `tree`, built by build_triangle_bvh from `tris` (which it reads
    /// only for the degenerate triangles the tree left out, kept here as copies). Empty (not
    /// usable, see indexed()) when the tree has no wide blocks or more lanes than 32-bit
    /// indices reach: the caller then keeps its triangles.
    static BlockTriangles index(const TriangleBvh& tree, const TriangleSource& tris);

    /// Whether the index was made (so the caller's triangles may be dropped).
    bool indexed() const { return indexed_; }
    /// The number of triangles the tree was built from (the degenerate ones included).
    std::size_t size() const { return lane_.size(); }

    /// Triangle `prim` (< size()), exactly as it was given to the build or the last refit.
    /// `tree` is the tree indexed, refitted since at most (a degenerate triangle it left out
    /// then reads as it was built). (Inline: shading reads one per hit.)
    Triangle at(const TriangleBvh& tree, std::uint32_t prim) const {
        const std::uint32_t slot = lane_[prim];
        if (slot == kInvalidId) return skipped(tree, prim);
        return tree.wide.blocks[slot / kBlockLanes].triangle(int(slot % kBlockLanes));
    }
    /// Asks the cache for the lines triangle `prim` is read from.
    void prefetch(const TriangleBvh& tree, std::uint32_t prim) const;

    /// Heap bytes held.
    std::size_t bytes() const;

private:
    /// A degenerate triangle the tree left out, from its copy.
    Triangle skipped(const TriangleBvh& tree, std::uint32_t prim) const;

    /// Per triangle: block * kBlockLanes + lane in tree.wide.blocks, or kInvalidId for a
    /// degenerate triangle the tree left out (kept in skipped_, in tree.skipped_ids' order).
    std::vector<std::uint32_t> lane_;
    std::vector<Triangle> skipped_;
    bool indexed_ = false;
};

}  // namespace dynrt::bvh
