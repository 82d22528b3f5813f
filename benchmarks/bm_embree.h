#pragma once
// Embree 3 counterparts of the dynrt figures (only when CMake found Embree): one device per
// process with Embree's default thread count, and a scene of one triangle geometry per object
// over shared (not copied) vertex and index buffers, built with RTC_BUILD_QUALITY_MEDIUM.

#include "bm_scenes.h"

#include <embree3/rtcore.h>

#include <stdexcept>

namespace dynrt::bench {

inline RTCDevice embree_device() {
    static RTCDevice device = [] {
        RTCDevice d = rtcNewDevice(nullptr);
        if (d == nullptr) throw std::runtime_error("rtcNewDevice failed");
        return d;
    }();
    return device;
}

/// An uncommitted scene over `input`'s buffers; the caller commits (that is the build) and
/// releases it.
inline RTCScene make_embree_scene(const SceneInput& input) {
    RTCDevice device = embree_device();
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
    for (std::size_t o = 0; o < input.positions.size(); ++o) {
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_MEDIUM);
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                   input.positions[o].data(), 0, 3 * sizeof(float),
                                   input.positions[o].size() / 3);
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                   input.indices[o].data(), 0, 3 * sizeof(std::uint32_t),
                                   input.indices[o].size() / 3);
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(scene, geometry);
        rtcReleaseGeometry(geometry);
    }
    return scene;
}

}  // namespace dynrt::bench
