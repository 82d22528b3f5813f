#pragma once
// Embree 3 counterparts of the dynrt figures (only when CMake found Embree): one device per
// process with Embree's default thread count, and a scene of one triangle geometry per object
// over shared (not copied) vertex and index buffers, built with RTC_BUILD_QUALITY_MEDIUM unless
// asked for another quality (or set up for refitting).

#include "bm_scenes.h"

#include <embree3/rtcore.h>

#include <stdexcept>
#include <vector>

namespace dynrt::bench {

inline RTCDevice embree_device() {
    static RTCDevice device = [] {
        RTCDevice d = rtcNewDevice(nullptr);
        if (d == nullptr) throw std::runtime_error("rtcNewDevice failed");
        return d;
    }();
    return device;
}

/// An uncommitted scene over `input`'s index buffers and `positions` (input.positions unless
/// given; same sizes), geometry i holding object i; the caller commits (that is the build) and
/// releases it. With `refit`, the geometries use RTC_BUILD_QUALITY_REFIT in a dynamic scene of
/// low quality: after the first commit, a commit following rtcUpdateGeometryBuffer of the
/// vertices refits instead of rebuilding.
inline RTCScene make_embree_scene(const SceneInput& input, bool refit = false,
                                  const std::vector<std::vector<float>>* positions = nullptr,
                                  RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM) {
    const std::vector<std::vector<float>>& vertices = positions ? *positions : input.positions;
    RTCDevice device = embree_device();
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, refit ? RTC_BUILD_QUALITY_LOW : quality);
    if (refit) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_DYNAMIC);
    for (std::size_t o = 0; o < input.positions.size(); ++o) {
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuildQuality(geometry,
                                   refit ? RTC_BUILD_QUALITY_REFIT : quality);
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                   vertices[o].data(), 0, 3 * sizeof(float),
                                   vertices[o].size() / 3);
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
