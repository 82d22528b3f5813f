#pragma once
// BART's AFF model (aff_parser.h) turned into the scene model every later stage reads.
//
// Geometry: polygons are fanned from their first vertex (as BART's own converters do), mesh
// blocks keep their triangles, cones and spheres are tessellated (kAffConeSegments around,
// no end caps, as NFF cones have none), `tt`/`ttp` are single triangles.
// Textures: a shape that names a texture file (`tt`, `ttp`, `m`'s `texturecoords n file`) and
// has texture coordinates goes into an object of its own per (anchor, material, file), whose
// material is a copy of the shape's with the file as its diffuse map (Material::diffuse_map;
// the file resolves next to the .aff that names it, repeating outside [0, 1]). BART's (u, v)
// are taken as OpenImageIO's (s, t) unchanged: BART's previewer hands the image rows to
// OpenGL in file order, so v = 0 is the file's first (top) row, as t = 0 is. An `m` block
// whose triangles index texture coordinates apart gets one vertex per distinct (position,
// normal, texture coordinate) triple. Names without coordinates, or coordinates without a
// name, map nothing and are listed in Scene::ignored.
// Normals: the file's per-vertex normals (`pp`, `ttp`, `m` with `normals`, `tpa` keys, whose
// normals morph with their positions) go through the static transforms by their cofactor
// matrix (vertex_normals.h) and are normalised; an `m` block whose triangles index normals
// apart from positions gets one vertex per distinct (position, normal) pair. Shapes without
// normals (`p`, `tt`, `s`, `c`, `m` without) get their own area-weighted ones, computed per
// shape: a polygon stays flat, a sphere or cone is smooth, and no two shapes smooth each other.
//
// Motion, following BART's classification by data:
//  - An `x NAME` transform with a `k NAME` block is an animated node: translation and scale
//    keys become Kochanek-Bartels splines, rotation keys BART's squad (aff_keyframes.h).
//    Everything under it is one rigid object per material, its vertices baked through the
//    static `xs` transforms between it and the shapes.
//  - `tpa` triangles sharing key times, node and material become one deformable object:
//    key 0's positions plus one morph target per later key, with weights that move linearly
//    from key to key, which is BART's linear interpolation of animated triangles.
//  - Everything else is static, baked to world space, one object per material.
//  - `k camera` animates the viewpoint, a node with the camera's translation and rotation.
// Materials (`f`, `fm`; aff_parser.h gives `f`'s diffuse as colour * Kd, specular as colour * Ks):
//  - diffuse, specular = the file's, clamped to [0, 1]; shininess = max(shine, 1);
//  - reflectance = the specular colour: in NFF and the SPD, Ks also weighs the reflected ray;
//  - transmittance = grey T, clamped to [0, 1];
//  - ior = the file's index of refraction, except that ior <= 0 (BART writes 0.0 for opaque
//    materials) reads as 1. A non-finite value is left for check_scene to refuse.
//  The material's ambient colour is not used (dynrt's ambient term is a fraction of diffuse).
// Time: BART's frame f is at start + f (end - start) / (frames - 1); the scene's key times are
// shifted by -start and SceneSetup::fps set to (frames - 1) / (end - start), so dynrt's frame f
// (time f / fps) is BART's.

#include "aff_parser.h"
#include "dynrt/scene/scene.h"

namespace dynrt::aff {

/// Segments around a cone or sphere.
inline constexpr int kAffConeSegments = 32;

/// The scene `model` describes; `source` names it in messages. Throws SceneError naming the
/// file and line for what the scene model cannot hold: an `x` whose keys are malformed, an
/// animated light (`la`), a light under an animated transform, a zero rotation axis, a
/// non-finite number, a viewpoint whose up vector is parallel to its view direction.
[[nodiscard]] Scene scene_from_aff(const AffModel& model, const std::string& source);

}  // namespace dynrt::aff
