#include "dynrt/bvh/block_triangles.h"

#include "dynrt/bvh/prefetch.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace dynrt::bvh {

BlockTriangles BlockTriangles::index(const TriangleBvh& tree, const TriangleSource& tris) {
    BlockTriangles out;
    const std::vector<TriangleBlock, UninitializedAllocator<TriangleBlock>>& blocks = tree.wide.blocks;
    if (tree.wide.empty() && tris.size() != tree.degenerate_skipped) return out;
    if (blocks.size() * kBlockLanes >= kInvalidId) return out;
    out.lane_.assign(tris.size(), kInvalidId);
    // Every used lane names a distinct triangle: the blocks are written in parallel.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t b = r.begin(); b < r.end(); ++b) {
                              for (int lane = 0; lane < kBlockLanes; ++lane) {
                                  const std::uint32_t prim = blocks[b].prim[lane];
                                  if (prim != kInvalidId) out.lane_[prim] = std::uint32_t(b * kBlockLanes + lane);
                              }
                          }
                      });
    out.skipped_.reserve(tree.skipped_ids.size());
    for (const std::uint32_t id : tree.skipped_ids) out.skipped_.push_back(tris[id]);
    out.indexed_ = true;
    return out;
}

Triangle BlockTriangles::skipped(const TriangleBvh& tree, std::uint32_t prim) const {
    // Never hit by dynrt's tracers, but another backend may report one, so it is kept.
    const auto it = std::lower_bound(tree.skipped_ids.begin(), tree.skipped_ids.end(), prim);
    return skipped_[std::size_t(it - tree.skipped_ids.begin())];
}

void BlockTriangles::prefetch(const TriangleBvh& tree, std::uint32_t prim) const {
    const std::uint32_t slot = lane_[prim];
    if (slot == kInvalidId) return;
    // A lane's nine coordinates are spread over the block's first 144 bytes.
    const char* block = reinterpret_cast<const char*>(&tree.wide.blocks[slot / kBlockLanes]);
    prefetch_line(block);
    prefetch_line(block + 64);
    prefetch_line(block + sizeof(TriangleBlock) - sizeof(TriangleBlock::prim) - 1);
}

std::size_t BlockTriangles::bytes() const {
    return lane_.capacity() * sizeof(std::uint32_t) + skipped_.capacity() * sizeof(Triangle);
}

}  // namespace dynrt::bvh
