#pragma once
// Tracing a caller's batch of arbitrary rays through a SceneAccel (Engine::intersect and
// Engine::occluded): the batch is cut into runs of 256 consecutive rays, each run into groups
// by the signs of the directions; a group whose rays are coherent is traced as one packet
// (packet/, with the group's lanes active), any other ray by ray. Both give the same hits bit
// for bit (the packet tracer's contract), so the grouping only changes the time.

#include "dynrt/api/engine.h"
#include "dynrt/api/types.h"
#include "update/scene_accel.h"

#include <cstdint>
#include <span>

namespace dynrt::api_detail {

/// A group of rays is traced as a packet when every direction lies within this cosine of the
/// group's middle ray's direction (about 25 degrees): packets share one traversal, which pays
/// while the rays visit mostly the same nodes. Measured in benchmarks/bm_api.cpp.
inline constexpr float kCoherentCosine = 0.9f;

/// Smaller groups go ray by ray: the packet machinery costs more than it saves for a few rays.
inline constexpr int kPacketRaysMin = 16;

/// Closest hits (`hits` sized as `rays`). A hit's mesh is mesh_ids[object] for the object
/// (slot) it hit, or the object index itself when `mesh_ids` is empty (MeshSlots::ids_of_slots).
/// Throws Error naming the first invalid ray found (rays are checked in parallel, so "first"
/// is in the order found). Thread-safe.
QueryStats intersect_batch(const SceneAccel& accel, std::span<const Ray> rays,
                           std::span<RayHit> hits, std::span<const std::uint32_t> mesh_ids);

/// Any hit: occluded[i] = 1 when rays[i] hits anything within [tmin, tmax], else 0.
QueryStats occluded_batch(const SceneAccel& accel, std::span<const Ray> rays,
                          std::span<std::uint8_t> occluded);

/// The same on rays held as arrays (RayArrays, read in place); also throws Error when the
/// arrays' sizes disagree. Same results bit for bit as on the equal Ray batch.
QueryStats intersect_batch(const SceneAccel& accel, const RayArrays& rays,
                           std::span<RayHit> hits, std::span<const std::uint32_t> mesh_ids);
QueryStats occluded_batch(const SceneAccel& accel, const RayArrays& rays,
                          std::span<std::uint8_t> occluded);

}  // namespace dynrt::api_detail
