#pragma once
// dynrt rays in Embree 3's ray layout, shared by the Embree backend (embree_tracer.cpp) and the
// benchmarks (bm_trace), so every comparison hands Embree exactly the rays dynrt traces.
// Includes <embree3/rtcore.h>: for code built with Embree (DYNRT_HAVE_EMBREE) only.

#include "dynrt/bvh/ray.h"

#include <embree3/rtcore.h>

namespace dynrt::embree {

/// `ray` as an RTCRayHit ready for rtcIntersect1: the same origin, direction (not normalised,
/// so Embree's t is in dynrt's units) and segment ([tmin, tmax] as [tnear, tfar]), time 0, every
/// mask bit set, id and flags 0, and no hit yet (geomID and instID[0] invalid).
inline RTCRayHit to_rtc_ray_hit(const bvh::Ray& ray) {
    RTCRayHit rh;
    rh.ray.org_x = ray.org.x;
    rh.ray.org_y = ray.org.y;
    rh.ray.org_z = ray.org.z;
    rh.ray.dir_x = ray.dir.x;
    rh.ray.dir_y = ray.dir.y;
    rh.ray.dir_z = ray.dir.z;
    rh.ray.tnear = ray.tmin;
    rh.ray.tfar = ray.tmax;
    rh.ray.time = 0.0f;
    rh.ray.mask = ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

}  // namespace dynrt::embree
