#pragma once
// An environment map as lights (the image-based light, TraceSettings::environment_lights): the
// map's sphere of directions cut into `count` regions of equal energy, each a directional light
// from the region's energy centroid carrying the region's whole light (Debevec 2005, "A Median
// Cut Algorithm for Light Probe Sampling"). A few dozen such suns light a scene as its sky does,
// with sharp shadows from each, deterministically: the same lights every frame, so that exact
// pixel reuse and the reference renderer treat them as any other light.
//
// Units: dynrt's Phong has kd where a Lambertian BRDF has kd / pi (as for glTF's lights,
// renderer.h "Lights"), so a region R becomes a light of colour (1 / pi) * sum over its texels
// of L * d_omega, L the texel's radiance (times the map's scale) and d_omega its solid angle,
// (2 pi / width) (pi / height) sin(theta) at polar angle theta. Under an environment of uniform
// radiance L a white surface facing up then shows L * (sum of the suns above it, weighted by
// their cosines), which tends to L as the regions shrink, as the integral does.
//
// The cut: start from the whole image; while there are fewer than `count` regions, split the
// one of most energy (luminance times solid angle) across its longer side (its width measured
// at its middle latitude, sin(theta) times the angle across) where its energy is halved.
// Regions without energy are dropped (their light would add nothing), so fewer lights may come
// back.

#include "dynrt/engine/environment_map.h"
#include "dynrt/scene/scene.h"

#include <vector>

namespace dynrt {

/// The most lights environment_lights makes (each casts a shadow ray per hit).
inline constexpr int kEnvironmentLightsMax = 256;

/// `map` as at most `count` directional lights (1 <= count <= kEnvironmentLightsMax), named
/// "environment k". Throws std::invalid_argument for a count out of range.
std::vector<PointLight> environment_lights(const EnvironmentMap& map, int count);

}  // namespace dynrt
