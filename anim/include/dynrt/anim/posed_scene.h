#pragma once
// The scene evaluated at one frame: world-space vertex positions of every object, the geometry
// every tracer (the BVH, the reference, Embree) sees for that frame, plus what the engine needs
// to update its trees cheaply: each object's motion class, its world transform (so rigid
// objects can be instanced without touching their vertices) and whether it changed since the
// previous frame.
//
// One frame: time t = frame / fps -> every chosen clip sampled at t (clamped to its keys) ->
// node local transforms -> node world matrices -> per object: morph weights, joint matrices,
// world transform -> vertices (morph, then skinning or the world transform, then procedural
// motions). Static and rigid objects' vertices are computed in double and rounded to float
// once; moving vertices in float from constants computed once in double (posed_scene.cpp
// says which), within a few float roundings of the double evaluation. Objects that did not
// move keep the positions the previous pose() wrote.

#include "dynrt/anim/motion_class.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/scene/scene.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace dynrt::anim {

/// Frames per second when none is given: 24, the rate Blender and most other tools author
/// animation at, so clips exported from them have their keys on whole frames (the sample
/// models' keys are 1/24 s apart) and frame f shows exactly key f.
inline constexpr double kDefaultFps = 24.0;

/// How to evaluate a scene over a sequence. Fixed for the life of a ScenePoser.
struct PoseSettings {
    /// Frame f is evaluated at t = f / fps seconds. Finite and positive.
    double fps = kDefaultFps;
    /// Indices into Scene::clips that play, first listed wins where two drive the same node
    /// property. nullopt: every clip of the scene together, in file order. Empty: none (rest
    /// pose). find_clip turns a name into an index.
    std::optional<std::vector<std::size_t>> clips;
    /// The chosen clips repeat: frame f is evaluated at clip time (f / fps) modulo their end
    /// time (ScenePoser::end_time), so a sequence longer than the animation plays it again
    /// rather than holding the last pose. Procedural motions are not wrapped.
    bool loop = false;
    /// Objects to treat as a more general class than their animation implies (parse them with
    /// parse_class_overrides). Lowering a class is refused.
    std::vector<ClassOverride> class_overrides;
    /// When true, positions of static and rigid objects are not computed (left empty): use
    /// `transform` with ScenePoser::object_space_positions instead (and their normals with
    /// object_space_normals).
    bool skip_fixed_positions = false;
    /// Pose the objects' vertex normals (Mesh::normals) with their positions, into
    /// PosedObject::normals. Off, no normals are posed (flat shading needs none).
    bool normals = true;
};

struct PosedObject {
    /// World-space positions, same indexing as the object's mesh.positions. Empty when
    /// PoseSettings::skip_fixed_positions skipped this static or rigid object.
    std::vector<glm::vec3> positions;
    /// World-space unit vertex normals, same indexing (0 where a normal vanished). Empty when
    /// the mesh has none, PoseSettings::normals is off, or positions were skipped. Every
    /// transform turns them by its cofactor matrix (dynrt/scene/vertex_normals.h): a static or
    /// rigid object's by its world transform, in double, rounded once; a moving object's in
    /// float through the stages its positions go through (morph displacements, the blended
    /// joint matrix, the node transform, rigid motion, the wave's Jacobian; explode only
    /// moves triangles), normalised last.
    std::vector<glm::vec3> normals;
    /// Static and rigid objects: world = transform * ScenePoser::object_space_positions(i),
    /// in double (includes procedural rigid motion). Deformable and exploding objects: the
    /// identity, their positions are world positions already.
    glm::dmat4 transform{1.0};
    /// The class the object is treated as (derived from the animation, or raised by the user).
    MotionClass motion_class = MotionClass::static_;
    /// False when nothing that moves this object differs from the previous call on this
    /// PosedScene (transform, node transform, joint matrices, morph weights, procedural motion
    /// frame); true on the first call. Decided without looking at vertices. When false,
    /// pose() leaves `positions` as the previous call wrote them (it does not touch them).
    bool changed = true;

    /// Its node's world transform at this frame, before procedural motion (Object::transform
    /// for objects no channel reaches; the identity for skinned objects, whose node transform
    /// glTF ignores).
    glm::dmat4 node_transform{1.0};
    /// Skinned objects: world(joint_j) * inverse_bind_j per joint at this frame; else empty.
    std::vector<glm::dmat4> joint_matrices;
    /// Objects with morph targets: the weights at this frame; else empty.
    std::vector<double> morph_weights;
    /// The frame procedural motions were evaluated at, when they move vertices; else 0.
    /// Kept for `changed`.
    int motion_frame = 0;
    /// Whether this entry holds a previous evaluation; kept for `changed`.
    bool evaluated = false;
};

/// The scene's first camera at this frame, in world space.
struct PosedCamera {
    /// Index into Scene::cameras (always 0: the scene's first camera).
    std::size_t camera = 0;
    glm::dvec3 eye{0.0};
    /// Unit view direction: the node's -Z axis.
    glm::dvec3 forward{0.0, 0.0, -1.0};
    /// Unit up direction: the node's +Y axis (not necessarily orthogonal to `forward` when the
    /// node is sheared; the camera basis orthogonalises it).
    glm::dvec3 up{0.0, 1.0, 0.0};
    /// Vertical field of view in radians (glTF cameras do not animate it).
    double yfov_rad = 0.0;
    /// Width over height from the file, 0 when it gives none.
    double aspect_ratio = 0.0;
};

struct PosedScene {
    int frame = 0;
    /// frame / fps, in seconds.
    double time_s = 0.0;
    /// One entry per scene object, in scene order.
    std::vector<PosedObject> objects;
    /// World matrix of every scene node at this frame, same indexing as Scene::nodes.
    std::vector<glm::dmat4> node_world;
    /// The scene's first camera (Scene::cameras[0]) when it has one.
    std::optional<PosedCamera> camera;
    /// Morph weights of every node at this frame, laid out by ScenePoser; working storage.
    std::vector<double> node_weights;
    /// Which ScenePoser filled it last (0: none). A poser only trusts `changed` and keeps the
    /// positions of unmoved objects in a PosedScene it filled itself.
    std::uint64_t poser_id = 0;
};

/// Evaluates one scene under fixed settings, frame after frame. Construction checks the
/// settings and the animation data, classifies every object and precomputes what never changes
/// (unanimated node matrices, frame-0 references of procedural motions, object-space positions
/// of static skinned or morphed objects); each pose() then does only per-frame work.
/// Borrows `scene`, which must outlive the poser and stay unchanged. pose() is const and may run
/// concurrently on different PosedScenes; it runs in parallel on the caller's oneTBB arena.
class ScenePoser {
public:
    /// Throws std::invalid_argument for bad settings (fps not finite and positive, a clip index
    /// out of range, a class override below the object's derived class or naming no object)
    /// and SceneError for inconsistent animation data in a hand-built scene.
    ScenePoser(const Scene& scene, PoseSettings settings);
    ~ScenePoser();
    ScenePoser(ScenePoser&&) noexcept;
    ScenePoser& operator=(ScenePoser&&) noexcept;

    /// Evaluates frame `frame` (any integer; time frame / fps) into `out`, reusing its storage.
    /// `changed` compares with what the previous call left in `out`, so reuse one PosedScene
    /// per sequence; the positions of objects not changed are kept, not recomputed, so the
    /// caller must not modify them between calls. Throws SceneError naming the object (or camera), frame and vertex when a
    /// result is not finite.
    void pose(int frame, PosedScene& out) const;

    /// The class object `object` is treated as (after overrides).
    MotionClass motion_class(std::size_t object) const;
    /// The class its animation implies, before overrides.
    MotionClass derived_class(std::size_t object) const;

    /// Object-space vertices of a static or rigid object: world = transform * these. The mesh's
    /// own positions, except for skinned objects (their fixed skinned pose in world space, with
    /// transform = procedural rigid motion only) and objects whose morph weights a clip holds
    /// constant (the morphed shape). Stable for the poser's life. Empty for deformable and
    /// exploding objects.
    std::span<const glm::vec3> object_space_positions(std::size_t object) const;

    /// The unit normals of those object-space vertices, indexed alike: the mesh's own, or
    /// those of its fixed skinned or morphed shape. Empty for deformable and exploding objects,
    /// objects without normals, and when PoseSettings::normals is off. World normals are
    /// normalize(cof(transform) n) (fixed_world_normals).
    std::span<const glm::vec3> object_space_normals(std::size_t object) const;

    /// World positions of static or rigid object `object` in `posed` (filled by pose()):
    /// transform * object_space_positions(object), computed exactly as pose() computes them
    /// when it does not skip them. Lets a caller that skips fixed positions build a static
    /// object's tree in world space once. Throws std::invalid_argument for an object that is
    /// not static or rigid, SceneError naming object, frame and vertex for a non-finite result.
    void fixed_world_positions(std::size_t object, const PosedScene& posed,
                               std::vector<glm::vec3>& out) const;
    /// The same for its normals (empty without), exactly as pose() computes them. Throws
    /// std::invalid_argument for an object that is not static or rigid.
    void fixed_world_normals(std::size_t object, const PosedScene& posed,
                             std::vector<glm::vec3>& out) const;
    /// Frame f's time in seconds: f / fps.
    double time_of(int frame) const;
    /// The last key time over the chosen clips (0 without any): frames past
    /// ceil(end_time * fps) repeat the last pose.
    double end_time() const;

    const PoseSettings& settings() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Evaluates `scene` at frame `frame` with default settings: every clip, 24 fps, all positions.
/// Same as ScenePoser(scene, {}).pose(frame, out), so a caller posing many frames should keep
/// a ScenePoser instead. For a scene without animation, skins, morph targets or motions the
/// positions are exactly transform * mesh.positions, computed in double and rounded once.
/// Throws SceneError naming the object, vertex and frame when a posed position is not finite.
void pose_scene(const Scene& scene, int frame, PosedScene& out);

/// The same with explicit settings.
void pose_scene(const Scene& scene, const PoseSettings& settings, int frame, PosedScene& out);

}  // namespace dynrt::anim
