#pragma once
// dynrt rays in Embree 3's ray layout, shared by the Embree backend (embree_tracer.cpp) and the
// benchmarks (bm_trace), so every comparison hands Embree exactly the rays dynrt traces.
// Includes <embree3/rtcore.h>: for code built with Embree (DYNRT_HAVE_EMBREE) only.

#include "dynrt/bvh/ray.h"

#include <embree3/rtcore.h>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

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

/// `ray` in lane `lane` of a 16-ray packet for rtcOccluded16: the fields of to_rtc_ray_hit's ray
/// (ray id `id`).
inline void set_rtc_ray16(RTCRay16& r, int lane, const bvh::Ray& ray, unsigned id) {
    r.org_x[lane] = ray.org.x;
    r.org_y[lane] = ray.org.y;
    r.org_z[lane] = ray.org.z;
    r.dir_x[lane] = ray.dir.x;
    r.dir_y[lane] = ray.dir.y;
    r.dir_z[lane] = ray.dir.z;
    r.tnear[lane] = ray.tmin;
    r.tfar[lane] = ray.tmax;
    r.time[lane] = 0.0f;
    r.mask[lane] = ~0u;
    r.id[lane] = id;
    r.flags[lane] = 0;
}

/// `ray` in lane `lane` of a 16-ray packet for rtcIntersect16 / rtcOccluded16, the same fields
/// as to_rtc_ray_hit (ray id `id`).
inline void set_rtc_ray_hit16(RTCRayHit16& rh, int lane, const bvh::Ray& ray, unsigned id) {
    rh.ray.org_x[lane] = ray.org.x;
    rh.ray.org_y[lane] = ray.org.y;
    rh.ray.org_z[lane] = ray.org.z;
    rh.ray.dir_x[lane] = ray.dir.x;
    rh.ray.dir_y[lane] = ray.dir.y;
    rh.ray.dir_z[lane] = ray.dir.z;
    rh.ray.tnear[lane] = ray.tmin;
    rh.ray.tfar[lane] = ray.tmax;
    rh.ray.time[lane] = 0.0f;
    rh.ray.mask[lane] = ~0u;
    rh.ray.id[lane] = id;
    rh.ray.flags[lane] = 0;
    rh.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
}

/// Embree asks every thread that traces or builds to run with denormals flushed to zero and
/// read as zero (its device warns otherwise: "This can have a severe performance impact").
/// The mode is per thread, so it is set for the lifetime of this guard, inside each of
/// Embree's trace tasks and around commits, and then restored: dynrt's own code, on the same
/// oneTBB threads, keeps IEEE denormals.
class EmbreeFloatMode {
public:
#if defined(__SSE__)
    EmbreeFloatMode() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero); }
    ~EmbreeFloatMode() { _mm_setcsr(saved_); }
    EmbreeFloatMode(const EmbreeFloatMode&) = delete;
    EmbreeFloatMode& operator=(const EmbreeFloatMode&) = delete;

private:
    static constexpr unsigned kFlushToZero = 0x8000;      // MXCSR.FZ
    static constexpr unsigned kDenormalsAreZero = 0x0040;  // MXCSR.DAZ
    unsigned saved_;
#endif
};

}  // namespace dynrt::embree
