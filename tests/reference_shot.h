#pragma once
// One frame of a scene seen by one camera, rendered by dynrt's Renderer and by the exact
// reference (tests/reference) under the same options: what the tests that compare a shading
// feature with the reference (lights, alpha, the environment's lights) render.

#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"

namespace dynrt::test {

/// The reference's frame `frame` of `scene` from `camera` at options' size, shaded as options
/// say (reference::shading_from), or with `shading` when given.
inline reference::ReferenceFrame reference_shot(const Scene& scene, const Camera& camera, const RenderOptions& options,
                                                const reference::ReferenceShading* shading = nullptr,
                                                int frame = 0) {
    anim::PosedScene posed;
    anim::pose_scene(scene, options.pose, frame, posed);
    const reference::ReferenceTracer tracer(scene, posed);
    return reference::render_reference(scene, tracer, camera, options.width, options.height,
                                       shading != nullptr ? *shading : reference::shading_from(scene, options));
}

/// dynrt's frame `frame` of `scene` from `camera` under `options`, from a Renderer of its own.
inline RenderedFrame renderer_shot(const Scene& scene, const Camera& camera, const RenderOptions& options,
                                   int frame = 0) {
    Renderer renderer(options);
    RenderedFrame out;
    renderer.render(scene, camera, frame, out);
    return out;
}

}  // namespace dynrt::test
