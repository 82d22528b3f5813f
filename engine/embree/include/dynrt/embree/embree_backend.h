#pragma once
// Embree behind dynrt's trace seam (dynrt/engine/trace_backend.h): `dynrt render|bench
// --backend embree-QUALITY` renders the same frames, rays and shading with Embree's hits, and
// `bench --vs embree` compares the two backends stage by stage. Each frame's geometry goes
// into one Embree scene (one triangle geometry per object, world space) at the chosen build
// quality; camera tiles and their shadow rays are traced as 4x4-pixel rtcIntersect16 /
// rtcOccluded16 packets with a coherent context (Embree's tutorials' arrangement, its best
// on camera rays), scattered rays as 16 consecutive lanes of dynrt's sorted packets with the
// default context, which was Embree's fastest on the same secondary rays (benchmarks/README.md).

#include "dynrt/embree/embree_tracer.h"
#include "dynrt/engine/trace_backend.h"

#include <memory>
#include <string>

namespace dynrt::embree {

/// A backend for Renderer::use_backend loading every frame at `quality` (refit: rebuilt at the
/// first frame, refitted after). Throws std::runtime_error if Embree cannot create a device.
std::shared_ptr<FrameBackend> make_embree_backend(BuildQuality quality);

/// "embree-low", "embree-medium", "embree-high", "embree-refit": the backend's name, as
/// --backend takes it; parse_backend_quality is its inverse (false for another name).
std::string embree_backend_name(BuildQuality quality);
bool parse_backend_quality(const std::string& name, BuildQuality& quality);

}  // namespace dynrt::embree
