#pragma once
// An occluder cache per light, for one frame's shadow rays (after Haines and Greenberg 1986,
// "The Light Buffer: A Shadow-Testing Accelerator", whose cells around a light list the
// objects seen through them; here each cell keeps only the last triangle found blocking a ray
// through it, a "shadow cache").
//
// A light's shadow rays leave its position (TileShadowOrigins::rays_to), so the direction of a
// ray picks a cell of a cube around the light: 6 faces of kCellsPerSide^2 cells. A packet of
// one light's rays looks up the cells of a sample of its lanes, and the distinct triangles
// found there are tested against every ray before the packet traverses anything
// (packet::InstanceOccluderSearch::test_first); the triangles the traversal then finds
// blocking rays are written back to their rays' cells.
//
// Why the answer is exactly the uncached one: a cell holds a triangle of the frame's trees by
// its instance and primitive index, and the triangle tested is read from that very tree's
// storage at the time of the test (SceneAccel::tree_triangle), in the tree's space, with the
// ray carried there as the traversal carries it. The packet test is the traversal's own leaf
// test, so a ray it blocks is one the traversal would have found blocked; rays it does not
// block are traced as before. A stale entry can only cost a useless test, never a wrong
// answer; and the cache lives for one frame (CpuTracer is made per frame), so no entry outlives
// the trees it names.

#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/two_level_packet.h"
#include "update/scene_accel.h"

#include <glm/vec3.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace dynrt::detail {

class OccluderCache {
public:
    /// Cells along a cube face's side: 32 makes a cell about 3 degrees across.
    static constexpr int kCellsPerSide = 32;
    static constexpr int kCells = 6 * kCellsPerSide * kCellsPerSide;
    /// Lights with a cache; shadow rays of further lights are traced without one.
    static constexpr int kLightsMax = 64;
    /// One lane in kSampleStride of a packet is looked up and learnt from: a packet's rays
    /// fall in a few neighbouring cells.
    static constexpr int kSampleStride = 16;
    /// Distinct triangles tested first per packet, at most.
    static constexpr int kGuessesMax = 8;

    /// One light's cells.
    struct Light {
        glm::vec3 origin{0.0f};
        std::unique_ptr<std::atomic<std::uint64_t>[]> cells;
    };

    /// The cells of the light at `origin` (made on first use), or null when kLightsMax lights
    /// already have cells. Thread-safe.
    Light* light_at(const glm::vec3& origin);

    /// Into `out`: the distinct triangles held by the cells of a sample of `rays`' active lanes,
    /// as `accel`'s trees store them now (entries naming no triangle of them are skipped).
    void guesses(const Light& light, const packet::RayPacket& rays, const SceneAccel& accel,
                 std::vector<packet::InstanceTriangle>& out) const;

    /// Writes, for a sample of the `occluded` lanes of `rays`, the occluder the trace found
    /// (`instance[lane]`, `prim[lane]`; kInvalidId where unknown) into the lane's cell.
    void learn(Light& light, const packet::RayPacket& rays, const packet::LaneMask& occluded,
               const std::uint32_t* instance, const std::uint32_t* prim);

    /// Counts for the report, added by the tracer: rays traced with the cache, and of them those
    /// its triangles blocked.
    void count(std::size_t traced, std::size_t answered) {
        traced_.fetch_add(traced, std::memory_order_relaxed);
        answered_.fetch_add(answered, std::memory_order_relaxed);
    }
    std::size_t traced() const { return traced_.load(std::memory_order_relaxed); }
    std::size_t answered() const { return answered_.load(std::memory_order_relaxed); }

    /// The cell of direction (x, y, z) from a light, or -1 for a zero or non-finite direction.
    static int cell_of(float x, float y, float z);

private:
    std::mutex adding_;
    Light lights_[kLightsMax];
    std::atomic<int> light_count_{0};
    std::atomic<std::size_t> traced_{0}, answered_{0};
};

}  // namespace dynrt::detail
