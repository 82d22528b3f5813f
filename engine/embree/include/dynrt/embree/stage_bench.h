#pragma once
// `dynrt bench --vs embree`, whole frames stage by stage: the same still frame rendered by
// dynrt's tracer and by Embree behind the trace seam (embree_backend.h) at each build quality,
// with the same rays and shading, runs interleaved backend by backend; per backend the
// median (min-max) of each stage: the update (dynrt: posing, checks and its trees; Embree:
// loading the frame and rtcCommitScene; under Embree dynrt's trees are still built, for the
// shading geometry, and left out of Embree's figures), camera rays, shadow rays, shading,
// secondary rays and their sum, and how Embree's hits agree with dynrt's.

#include "dynrt/bench/hit_agreement.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/spread.h"
#include "dynrt/scene/scene.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace dynrt::embree {

struct StageRow {
    std::string backend;  ///< "dynrt", "embree-low", ...
    Spread update_ms, camera_ms, shadow_ms, shade_ms, secondary_ms, frame_ms;
    /// Pixels whose hit object (or only triangle) differs from dynrt's frame; 0 on dynrt's row.
    HitAgreement vs_dynrt;
};

/// Renders frame 0 of `scene` seen by `camera` under `options`, `warmup` + `repeat` times per
/// backend (each run builds every tree from nothing), interleaving the backends run by run.
std::vector<StageRow> bench_stages(const Scene& scene, const Camera& camera,
                                   const RenderOptions& options, int repeat, int warmup);

/// The rows as a table (with each stage's ratio dynrt / backend of medians), and as JSON.
void print_stage_table(std::ostream& out, const std::vector<StageRow>& rows);
std::string stages_json(const std::vector<StageRow>& rows);

}  // namespace dynrt::embree
