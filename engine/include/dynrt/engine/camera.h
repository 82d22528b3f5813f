#pragma once
// Pinhole camera and the exact primary-ray convention (README.md, "Camera convention"), which
// other tools reproduce to compare images pixel by pixel.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/aabb.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/packet/pinhole.h"

#include <glm/vec3.hpp>

#include <string_view>

namespace dynrt {

/// The one camera value: eye, target, up and vertical field of view (packet/pinhole.h), which
/// the ray generators take directly (packet::PinholeRays: ray(x, y) for single rays,
/// fill_tile for 16x16 packets; it throws std::invalid_argument for a degenerate camera).
using Camera = packet::PinholeCamera;

/// eye = c + 2.5 R normalize(0.6, 0.5, 1.0), target c, up +Y, fov 45, where c is the box
/// centre and R half its diagonal. A box that is one point (a scene collapsed by a zero scale)
/// is framed with R = 1, and an empty one (no triangles) as the unit box around the origin,
/// so that such a scene renders (empty) instead of failing on a camera whose eye is its target.
Camera default_camera(const bvh::Aabb& scene_bounds);

/// The centre and radius default_camera and default_light frame: the box's, with the fallbacks
/// described there.
struct Framing {
    glm::vec3 center;
    float radius;
};
Framing framing_of(const bvh::Aabb& scene_bounds);

/// The pinhole camera of a scene camera posed at some frame: eye, a target one unit along its
/// view direction, its up vector and vertical field of view. (The image's own aspect ratio is
/// used, as for every dynrt camera, not the file's.)
Camera camera_from_scene(const anim::PosedCamera& posed);

/// Parses "eye=x,y,z,target=x,y,z,up=x,y,z,fov=deg"; any subset of the keys, in any order,
/// overriding `base`. Throws std::invalid_argument naming the bad part.
Camera parse_camera(std::string_view spec, const Camera& base);

}  // namespace dynrt
