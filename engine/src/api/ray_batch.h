#pragma once
// Tracing a caller's batch of arbitrary rays through a SceneAccel (Engine::intersect and
// Engine::occluded): the batch is cut into runs of 256 consecutive rays, checked, and each run
// handed to dynrt's tracer behind the trace seam (rendering/cpu_tracer.h) as rays of unknown
// coherence, which splits it into groups by the signs of the directions and traces a coherent
// group as one packet, any other ray by ray (CpuTracer::as_packet, the one rule). Both give the
// same hits bit for bit (the packet tracer's contract), so the grouping only changes the time.

#include "dynrt/api/engine.h"
#include "dynrt/api/types.h"
#include "update/scene_accel.h"

#include <cstdint>
#include <span>

namespace dynrt::api_detail {

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
