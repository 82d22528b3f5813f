#pragma once
// Cut-out materials (glTF alphaMode MASK; the rule is dynrt/engine/alpha_mask.h) behind the
// trace seam: a TraceBackend wrapping the frame's tracer that answers every ray as if the cut
// parts of those surfaces were not there. A closest hit that is cut out is traced again from
// just past it (the next float t), lane by lane, until a hit that is not cut out or a miss;
// an occluded ray is one whose closest hit, found the same way, exists. So camera, shadow,
// reflection and refraction rays, in every mode of the frame and through any backend, see the
// same cut-outs, and a scene without cut-out materials is traced without the wrapper: the
// opaque fast path does not change at all.
//
// Cut-outs are decided after traversal, on resolved hits, rather than inside the traversal
// kernels (Embree's filter functions do the latter): the kernels stay free of a per-triangle
// test that opaque geometry would pay for, and every backend is covered by one piece of code.
// The price is a traversal per cut layer a ray crosses, paid only by rays that meet one.

#include "dynrt/engine/trace_backend.h"
#include "dynrt/scene/scene.h"
#include "rendering/tile_shading.h"

#include <cstdint>
#include <span>

namespace dynrt::detail {

/// Whether a frame's hits are cut out: the scene's materials, each object's material and the
/// frame's texture lookups, borrowed for the frame.
class AlphaCutouts {
public:
    /// `textures`: the frame's textures (null when no material maps one; then a cut-out's
    /// alpha is its base_alpha).
    AlphaCutouts(std::span<const Material> materials, std::span<const std::int32_t> object_material,
                 const SurfaceTextures* textures)
        : materials_(materials), object_material_(object_material), textures_(textures) {}

    /// Whether `hit` (a hit, not a miss) is on a cut-out material where its alpha is below
    /// the cutoff (cut_out).
    bool cut(const bvh::InstanceHit& hit) const;

private:
    std::span<const Material> materials_;
    std::span<const std::int32_t> object_material_;
    const SurfaceTextures* textures_;
};

/// `inner`'s answers without the hits `cutouts` cuts out. Borrows both.
class CutoutTracer final : public TraceBackend {
public:
    /// The cut layers a ray is traced through at most: a ray still on a cut hit after this
    /// many stops there (a hang guard for pathological stacks, far past real foliage).
    static constexpr int kLayersMax = 256;

    CutoutTracer(const TraceBackend& inner, const AlphaCutouts& cutouts) : inner_(inner), cutouts_(cutouts) {}

    int closest(const packet::RayPacket& rays, RayCoherence coherence, HitTarget hits,
                TraceWork* work) const override;
    /// The lanes `inner` finds blocked whose closest hit (closest()) is not cut out: a lane
    /// nothing blocks needs no more work.
    packet::LaneMask occluded(const packet::RayPacket& rays, RayCoherence coherence,
                              TraceWork* work) const override;

private:
    const TraceBackend& inner_;
    const AlphaCutouts& cutouts_;
};

}  // namespace dynrt::detail
