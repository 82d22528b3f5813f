#pragma once
// Two rendered frames the same bit for bit in every buffer (colour, depth, object, triangle,
// normal), for the tests that require one way of rendering to give exactly what another gives
// (exact reuse, compact layouts). One definition for the unity batches of dynrt_tests.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/scene/scene.h"

#include "same_bits.h"

#include <gtest/gtest.h>

namespace dynrt::test {

/// Every buffer of the two frames, bit for bit.
inline void expect_same_frame(const RenderedFrame& a, const RenderedFrame& b) {
    EXPECT_TRUE(same_bits(a.color, b.color)) << "colour";
    EXPECT_TRUE(same_bits(a.depth, b.depth)) << "depth";
    EXPECT_TRUE(same_bits(a.object, b.object)) << "object";
    EXPECT_TRUE(same_bits(a.prim, b.prim)) << "prim";
    EXPECT_TRUE(same_bits(a.normal, b.normal)) << "normal";
}

/// One frame from a renderer and from another that must draw it alike.
struct FramePair {
    RenderedFrame reference, candidate;
};

/// Frame `frame` of `scene` from `camera` by both renderers, expected the same bit for bit.
inline FramePair render_alike(Renderer& reference, Renderer& candidate, const Scene& scene, const Camera& camera,
                              int frame) {
    FramePair frames;
    reference.render(scene, camera, frame, frames.reference);
    candidate.render(scene, camera, frame, frames.candidate);
    expect_same_frame(frames.candidate, frames.reference);
    return frames;
}

}  // namespace dynrt::test
