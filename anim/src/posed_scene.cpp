// One frame of the scene (see posed_scene.h for the pipeline). The per-object work is split in
// two: a cheap serial-per-object part that decides the object's transform, joint matrices and
// morph weights (and from them `changed`), and the vertex loop, run in parallel blocks. Every
// vertex is computed on its own, so results never depend on the thread count.
//
// Posing at memory speed (issue 20): what never changes is computed once, at construction, in
// double and rounded once: the world positions before procedural motion of objects whose
// node, skin and weights never move (`rest`), explode's per-triangle step
// 0.02 R (0.5 + h(i)) n_i, and wave's sin and cos of 6 x / R per vertex. A frame is then one
// float multiply-add per coordinate it moves (explode: rest + f * step; wave:
// y + 0.05 R (sin(6x/R) cos(f/2) + cos(6x/R) sin(f/2))), skinning and morphing run in float
// over float joint matrices and weights, and an object whose inputs did not change is not
// touched at all. Static and rigid objects keep their exact double transform. The finiteness
// check is one vectorisable pass per block over the exponent bits; only a failing block is
// searched for the vertex the error names.

#include "dynrt/anim/posed_scene.h"

#include "dynrt/anim/morphing.h"
#include "dynrt/anim/skinning.h"
#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/vertex_normals.h"

#include "animation_data_check.h"
#include "node_animation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace dynrt::anim {

namespace {

/// Vertices per parallel block: large enough that scheduling costs little next to skinning a
/// block, small enough that one big object still spreads over every core.
constexpr std::size_t kVertexBlock = 4096;
constexpr std::size_t kNoVertex = std::numeric_limits<std::size_t>::max();

bool is_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool is_finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c) {
        if (!is_finite(glm::vec3(m[c])) || !std::isfinite(m[c][3])) return false;
    }
    return true;
}

bool is_finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) return false;
        }
    }
    return true;
}

/// Copies `values` into `out`; true when that changed `out`.
template <class T>
bool assign_if_different(std::vector<T>& out, std::span<const T> values) {
    if (std::equal(out.begin(), out.end(), values.begin(), values.end())) return false;
    out.assign(values.begin(), values.end());
    return true;
}

/// The lowest v in [first, last) whose p[v] is not finite, or kNoVertex. The first pass only
/// ORs whether any coordinate's exponent bits are all ones (inf or NaN), which vectorises; the
/// second, per vertex, runs only for a block that failed.
std::size_t first_non_finite(const glm::vec3* p, std::size_t first, std::size_t last) {
    constexpr std::uint32_t kExponent = 0x7f800000u;
    const auto all_ones = [](float x) { return std::uint32_t((std::bit_cast<std::uint32_t>(x) & kExponent) == kExponent); };
    std::uint32_t bad = 0;
    for (std::size_t v = first; v < last; ++v) bad |= all_ones(p[v].x) | all_ones(p[v].y) | all_ones(p[v].z);
    if (bad == 0) return kNoVertex;
    for (std::size_t v = first; v < last; ++v) {
        if (!is_finite(p[v])) return v;
    }
    return kNoVertex;
}

/// Runs body(first, last) over [0, count) in parallel blocks; returns the lowest index for
/// which body reported a non-finite result (body returns that index or kNoVertex), else
/// kNoVertex. The lowest, so the error message does not depend on scheduling.
template <class Body>
std::size_t for_vertex_blocks(std::size_t count, const Body& body) {
    std::atomic<std::size_t> first_bad{kNoVertex};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kVertexBlock),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          const std::size_t bad = body(range.begin(), range.end());
                          std::size_t seen = first_bad.load();
                          while (bad < seen && !first_bad.compare_exchange_weak(seen, bad)) {
                          }
                      });
    return first_bad.load();
}

/// The homogeneous transform of p, divided by w, as pose_scene has always computed it.
glm::dvec3 transform_point(const glm::dmat4& m, const glm::dvec3& p) {
    const glm::dvec4 h = m * glm::dvec4(p, 1.0);
    return glm::dvec3(h) / h.w;
}

/// result[v] = transform * source[v] in double, rounded once; returns the lowest vertex whose
/// result is not finite, or kNoVertex.
std::size_t transform_positions(const glm::dmat4& m, std::span<const glm::vec3> source, glm::vec3* result) {
    return for_vertex_blocks(source.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t v = first; v < last; ++v) result[v] = glm::vec3(transform_point(m, glm::dvec3(source[v])));
        return first_non_finite(result, first, last);
    });
}

/// out[v] = normalize(cof(M) source[v]) for the linear part M of `m` (vertex_normals.h), in
/// double, rounded once; a vertex whose normal vanishes gets 0.
void transform_normals(const glm::dmat4& m, std::span<const glm::vec3> source, glm::vec3* out) {
    const glm::dmat3 cof = normal_matrix(glm::dmat3(m));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, source.size(), kVertexBlock),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t v = range.begin(); v < range.end(); ++v) {
                              out[v] = glm::vec3(normalize_or_zero(cof * glm::dvec3(source[v])));
                          }
                      });
}

/// The wave's derivative dy/dx = 0.05 R (6 / R) cos(6x/R + f/2) = 0.3 cos(...) turns a normal
/// by the inverse transpose of its Jacobian (I + k e_y e_x^T): n' = (n.x - k n.y, n.y, n.z).
glm::vec3 wave_normal(const glm::vec3& n, float k) { return glm::vec3(n.x - k * n.y, n.y, n.z); }

/// A double matrix rounded to float, for the per-vertex work of a frame.
glm::mat4 to_float(const glm::dmat4& m) { return glm::mat4(m); }

/// Eight floats as one value (the GCC and Clang vector extension; no instruction set named).
/// GCC 12 left a plain 16-float blend loop in 2-wide pieces: bm_posing's skinned mesh took
/// 11.6 ms per 1M vertices with it, 6.5 ms with this.
typedef float Float8 __attribute__((vector_size(32)));

/// The rows of a joint matrix, row after row: row r . (p, 1) is coordinate r of m * (p, 1).
/// Rows 0-1 in lo, 2-3 in hi.
struct JointRows {
    Float8 lo, hi;
};

JointRows joint_rows_of(const glm::mat4& m) {
    float e[16];
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) e[4 * r + c] = m[c][r];
    }
    JointRows rows;
    std::memcpy(&rows.lo, e, sizeof(rows.lo));
    std::memcpy(&rows.hi, e + 8, sizeof(rows.hi));
    return rows;
}

}  // namespace

struct ScenePoser::Impl {
    /// What ScenePoser decided about one object at construction.
    struct ObjectPlan {
        MotionClass derived = MotionClass::static_;
        MotionClass effective = MotionClass::static_;
        bool skinned = false;
        /// Not skinned, and a channel drives its node or an ancestor: its world matrix comes from
        /// the evaluated nodes instead of Object::transform.
        bool node_driven = false;
        /// Has morph targets whose weights a channel on its node drives.
        bool morph_driven = false;
        /// Indices into Scene::motions of this object's procedural motions, in order.
        std::vector<std::size_t> motions;
        /// Frame-0 box centre and radius.
        MotionReference reference;
        /// Static or rigid but skinned or with clip-held morph weights: its fixed object-space shape
        /// (and normals, when the mesh has some).
        std::vector<glm::vec3> own_object_space;
        std::vector<glm::vec3> own_object_space_normals;
        bool uses_own_object_space = false;

        /// Deformable or exploding, not skinned, no driven weights or node transform: its world
        /// positions before procedural motion never change. `rest` holds them (Object::transform
        /// applied in double, rounded once): the mesh's own positions when that transform is the
        /// identity, else `own_rest`.
        bool fixed_rest = false;
        std::span<const glm::vec3> rest;
        std::vector<glm::vec3> own_rest;
        /// Its normals likewise (cof(Object::transform) n, normalised), when the mesh has some.
        std::span<const glm::vec3> rest_normals;
        std::vector<glm::vec3> own_rest_normals;
        /// Explode: per triangle 0.02 R (0.5 + h(i)) n_i in double, rounded once; frame f moves
        /// the triangle by f times it.
        std::vector<glm::vec3> explode_step;
        /// A fixed-rest object whose first motion is wave: per vertex sin and cos of 6 x / R of
        /// its rest position (in double, rounded once), so that a frame needs no sine:
        /// sin(6x/R + f/2) = sin(6x/R) cos(f/2) + cos(6x/R) sin(f/2).
        std::vector<float> wave_sin, wave_cos;

        bool fixed() const { return effective <= MotionClass::rigid; }
    };

    Impl(const Scene& s, PoseSettings p, std::vector<std::size_t> c)
        : scene(s), settings(std::move(p)), clips(std::move(c)), nodes(s, clips), id(next_poser_id()) {}

    /// A number no other poser of this process has, for PosedScene::poser_id.
    static std::uint64_t next_poser_id() {
        static std::atomic<std::uint64_t> last{0};
        return ++last;
    }

    const Scene& scene;
    PoseSettings settings;
    std::vector<std::size_t> clips;
    NodeAnimation nodes;
    std::vector<ObjectPlan> plans;
    double end_time = 0.0;
    const std::uint64_t id;

    /// The time the clips are evaluated at for scene time `t`: t itself, or with
    /// PoseSettings::loop, t modulo the clips' end time (fmod is exact, so whole periods
    /// repeat bit for bit).
    double clip_time(double t) const {
        if (!settings.loop || !(end_time > 0.0)) return t;
        return std::fmod(t, end_time);
    }

    /// A non-finite result found while posing one object.
    struct Failure {
        std::size_t vertex = kNoVertex;
        bool transform = false;
    };

    std::span<const glm::vec3> object_space(std::size_t i) const {
        const ObjectPlan& plan = plans[i];
        if (!plan.fixed()) return {};
        if (plan.uses_own_object_space) return plan.own_object_space;
        return scene.objects[i].mesh.positions;
    }

    std::span<const glm::vec3> object_space_normals(std::size_t i) const {
        const ObjectPlan& plan = plans[i];
        if (!plan.fixed() || !settings.normals) return {};
        if (plan.uses_own_object_space) return plan.own_object_space_normals;
        return scene.objects[i].mesh.normals;
    }

    /// The object's world matrix before procedural motion: its node's evaluated world matrix,
    /// or Object::transform when no channel reaches it (exactly as pose_scene always did), or
    /// the identity for skinned objects.
    glm::dmat4 base_world(std::size_t i, const PosedScene& out) const {
        const Object& object = scene.objects[i];
        if (plans[i].skinned) return glm::dmat4(1.0);
        if (plans[i].node_driven) return out.node_world[static_cast<std::size_t>(object.node)];
        return glm::dmat4(object.transform);
    }

    /// Decides transform, joint matrices, morph weights and `changed` of object i.
    void pose_inputs(std::size_t i, int frame, bool with_motions, PosedScene& out) const {
        const Object& object = scene.objects[i];
        const ObjectPlan& plan = plans[i];
        PosedObject& posed = out.objects[i];
        bool changed = !posed.evaluated;

        if (object.morph) {
            const std::span<const double> weights =
                plan.morph_driven ? nodes.weights(static_cast<std::size_t>(object.node), out.node_weights)
                                  : std::span<const double>(object.morph->default_weights);
            changed |= assign_if_different(posed.morph_weights, weights);
        } else {
            posed.morph_weights.clear();
        }

        if (plan.skinned) {
            const Skin& skin = scene.skins[object.skin->skin];
            if (posed.joint_matrices.size() != skin.joints.size()) {
                posed.joint_matrices.resize(skin.joints.size());
                changed = true;
            }
            for (std::size_t j = 0; j < skin.joints.size(); ++j) {
                const glm::dmat4 joint = out.node_world[skin.joints[j]] * skin.inverse_bind_matrices[j];
                if (joint != posed.joint_matrices[j]) {
                    posed.joint_matrices[j] = joint;
                    changed = true;
                }
            }
        } else {
            posed.joint_matrices.clear();
        }

        const glm::dmat4 node_transform = base_world(i, out);
        glm::dmat4 transform(1.0);
        int motion_frame = 0;
        if (plan.fixed()) {
            transform = node_transform;
            // A fixed object's motions are all rigid: fold them into its transform.
            if (with_motions) {
                for (std::size_t k = 0; k < plan.motions.size(); ++k) {
                    transform = rigid_motion_matrix(plan.reference, frame) * transform;
                }
            }
        } else if (with_motions && !plan.motions.empty()) {
            motion_frame = frame;
        }
        changed |= transform != posed.transform || node_transform != posed.node_transform ||
                   motion_frame != posed.motion_frame;
        posed.transform = transform;
        posed.node_transform = node_transform;
        posed.motion_frame = motion_frame;
        posed.motion_class = plan.effective;
        posed.changed = changed;
        posed.evaluated = true;
    }

    /// World positions of object i; returns what was not finite. An object whose inputs did not
    /// change since the previous call on `out` keeps the positions that call wrote.
    Failure pose_positions(std::size_t i, int frame, bool with_motions, bool skip_fixed, PosedScene& out) const {
        const Object& object = scene.objects[i];
        const ObjectPlan& plan = plans[i];
        PosedObject& posed = out.objects[i];
        Failure failure;
        if (plan.fixed() && skip_fixed) {
            posed.positions.clear();
            posed.normals.clear();
            failure.transform = !is_finite(posed.transform);
            return failure;
        }
        const std::size_t count = object.mesh.positions.size();
        const std::size_t normal_count = settings.normals && !object.mesh.normals.empty() ? count : 0;
        // Nothing that moves it changed: the positions written from the same inputs stand.
        if (!posed.changed && posed.positions.size() == count && posed.normals.size() == normal_count) {
            return failure;
        }
        posed.positions.resize(count);
        posed.normals.resize(normal_count);
        glm::vec3* const result = posed.positions.data();
        glm::vec3* const normals = normal_count > 0 ? posed.normals.data() : nullptr;

        if (plan.fixed()) {
            failure.vertex = transform_positions(posed.transform, object_space(i), result);
            if (normals) transform_normals(posed.transform, object_space_normals(i), normals);
            return failure;
        }
        const std::span<const std::size_t> motions =
            with_motions ? std::span<const std::size_t>(plan.motions) : std::span<const std::size_t>();
        const bool one_motion = plan.fixed_rest && motions.size() == 1;
        if (one_motion && scene.motions[motions[0]].kind == MotionKind::explode &&
            count == 3 * plan.explode_step.size()) {
            failure.vertex = pose_explode(plan, frame, result);
            // The triangles only move: their normals are the rest pose's.
            if (normals) std::copy(plan.rest_normals.begin(), plan.rest_normals.end(), normals);
        } else if (one_motion && scene.motions[motions[0]].kind == MotionKind::wave && !plan.wave_sin.empty()) {
            failure.vertex = pose_wave(plan, frame, result, normals);
        } else {
            failure.vertex = pose_general(i, frame, motions, posed, result, normals);
        }
        return failure;
    }

    /// rest + f * step, triangle by triangle: one multiply-add per coordinate.
    std::size_t pose_explode(const ObjectPlan& plan, int frame, glm::vec3* result) const {
        const float f = static_cast<float>(frame);
        const glm::vec3* const rest = plan.rest.data();
        const glm::vec3* const step = plan.explode_step.data();
        return for_vertex_blocks(plan.explode_step.size(), [&](std::size_t first, std::size_t last) {
            for (std::size_t t = first; t < last; ++t) {
                const glm::vec3 d = f * step[t];
                result[3 * t] = rest[3 * t] + d;
                result[3 * t + 1] = rest[3 * t + 1] + d;
                result[3 * t + 2] = rest[3 * t + 2] + d;
            }
            return first_non_finite(result, 3 * first, 3 * last);
        });
    }

    /// y + 0.05 R sin(6x/R + f/2) by the angle sum, from the tables of the rest positions;
    /// normals (when not null) turned by wave_normal with 0.3 cos(6x/R + f/2) alike.
    std::size_t pose_wave(const ObjectPlan& plan, int frame, glm::vec3* result, glm::vec3* normals) const {
        const double amplitude = 0.05 * plan.reference.radius;
        const double phase = 0.5 * static_cast<double>(frame);
        const float by_sin = static_cast<float>(amplitude * std::cos(phase));
        const float by_cos = static_cast<float>(amplitude * std::sin(phase));
        // cos(6x/R + f/2) = cos(6x/R) cos(f/2) - sin(6x/R) sin(f/2); the tables are zero when
        // R = 0, which does not wave.
        const float slope_cos = static_cast<float>(0.3 * std::cos(phase));
        const float slope_sin = static_cast<float>(0.3 * std::sin(phase));
        const glm::vec3* const rest = plan.rest.data();
        const glm::vec3* const rest_normals = plan.rest_normals.data();
        const float* const s = plan.wave_sin.data();
        const float* const c = plan.wave_cos.data();
        return for_vertex_blocks(plan.rest.size(), [&](std::size_t first, std::size_t last) {
            for (std::size_t v = first; v < last; ++v) {
                result[v] = glm::vec3(rest[v].x, rest[v].y + (s[v] * by_sin + c[v] * by_cos), rest[v].z);
            }
            if (normals) {
                for (std::size_t v = first; v < last; ++v) {
                    normals[v] = normalize_or_zero(wave_normal(rest_normals[v], c[v] * slope_cos - s[v] * slope_sin));
                }
            }
            return first_non_finite(result, first, last);
        });
    }

    /// Any object: morph, then skinning or the node transform (or the rest pose), then the
    /// motions in order, stage by stage over each block, in float (rigid motion as a float
    /// matrix; wave after another motion in double, as it needs a sine of a moved x). Normals,
    /// when `normals` is not null, go through the same stages: morphed by their own
    /// displacements, turned by the cofactor matrix of the blended joint matrix, of the node
    /// transform and of the rigid motion (vertex_normals.h), by the wave's Jacobian, not at all
    /// by explode (a translation per triangle), then normalised.
    std::size_t pose_general(std::size_t i, int frame, std::span<const std::size_t> motions,
                             const PosedObject& posed, glm::vec3* result, glm::vec3* normals) const {
        const Object& object = scene.objects[i];
        const ObjectPlan& plan = plans[i];
        // The frame's matrices and weights in float, once per object (a few dozen at most).
        std::vector<glm::mat4> joints(posed.joint_matrices.size());
        std::transform(posed.joint_matrices.begin(), posed.joint_matrices.end(), joints.begin(), to_float);
        std::vector<JointRows> joint_rows(joints.size());
        std::transform(joints.begin(), joints.end(), joint_rows.begin(), joint_rows_of);
        const bool finite_joints =
            std::all_of(joints.begin(), joints.end(), [](const glm::mat4& m) { return is_finite(m); });
        std::vector<float> weights(posed.morph_weights.begin(), posed.morph_weights.end());
        const glm::mat4 base = to_float(posed.node_transform);
        const glm::dmat4 rigid_double = rigid_motion_matrix(plan.reference, frame);
        const glm::mat4 rigid = to_float(rigid_double);
        const glm::mat3 base_normal = glm::mat3(normal_matrix(glm::dmat3(posed.node_transform)));
        const glm::mat3 rigid_normal = glm::mat3(normal_matrix(glm::dmat3(rigid_double)));
        const bool morph_normals = normals && plan.morph_driven && !object.morph->normal_deltas.empty();
        // Whether any stage turns the normals: when none does (a fixed rest pose and no rigid
        // or wave motion), they are the rest normals exactly, as computed in double.
        bool normals_turn = morph_normals || plan.skinned || !plan.fixed_rest;
        for (const std::size_t m : motions) normals_turn |= scene.motions[m].kind != MotionKind::explode;
        const float f = static_cast<float>(frame);
        const double radius = plan.reference.radius;

        return for_vertex_blocks(object.mesh.positions.size(), [&](std::size_t first, std::size_t last) {
            // ---- The object-space shape: morphed, the rest pose, or the mesh ----
            if (plan.morph_driven) {
                const MorphTargets& morph = *object.morph;
                std::copy(morph.base_positions.begin() + std::ptrdiff_t(first),
                          morph.base_positions.begin() + std::ptrdiff_t(last), result + first);
                for (std::size_t k = 0; k < weights.size(); ++k) {
                    const float w = weights[k];
                    if (w == 0.0f) continue;
                    const glm::vec3* const delta = morph.position_deltas[k].data();
                    for (std::size_t v = first; v < last; ++v) result[v] += w * delta[v];
                }
            }
            if (morph_normals) {
                const MorphTargets& morph = *object.morph;
                std::copy(morph.base_normals.begin() + std::ptrdiff_t(first),
                          morph.base_normals.begin() + std::ptrdiff_t(last), normals + first);
                for (std::size_t k = 0; k < weights.size(); ++k) {
                    const float w = weights[k];
                    if (w == 0.0f) continue;
                    const glm::vec3* const delta = morph.normal_deltas[k].data();
                    for (std::size_t v = first; v < last; ++v) normals[v] += w * delta[v];
                }
            }
            // The shape to transform: the morphed one just written, else read in place.
            const glm::vec3* const source = plan.morph_driven ? result
                                            : plan.fixed_rest ? plan.rest.data()
                                                              : object.mesh.positions.data();
            const glm::vec3* const normal_source = morph_normals      ? normals
                                                   : plan.fixed_rest ? plan.rest_normals.data()
                                                                     : object.mesh.normals.data();
            // ---- To world space: skinning or the node transform ----
            if (plan.skinned && finite_joints) {
                // sum_k w_k (J_k h) = (sum_k w_k J_k) h: blend the influences' matrices first,
                // two 8-wide multiply-adds per influence, then one matrix times (p, 1) and
                // the division by its w. Zero weights are added rather than skipped (no
                // unpredictable branch): with finite joints that adds exactly +0.
                const SkinWeights& skin = *object.skin;
                const std::size_t n = skin.influences;
                for (std::size_t v = first; v < last; ++v) {
                    Float8 lo = {}, hi = {};
                    for (std::size_t k = v * n; k < v * n + n; ++k) {
                        const float w = skin.weights[k];
                        const JointRows& j = joint_rows[skin.joints[k]];
                        lo += w * j.lo;
                        hi += w * j.hi;
                    }
                    const glm::vec3 p = source[v];
                    float b[16];
                    std::memcpy(b, &lo, sizeof(lo));
                    std::memcpy(b + 8, &hi, sizeof(hi));
                    result[v] = glm::vec3(b[0] * p.x + b[1] * p.y + b[2] * p.z + b[3],
                                          b[4] * p.x + b[5] * p.y + b[6] * p.z + b[7],
                                          b[8] * p.x + b[9] * p.y + b[10] * p.z + b[11]) /
                                (b[12] * p.x + b[13] * p.y + b[14] * p.z + b[15]);
                    if (normals) {
                        // The blended matrix's linear part, by columns (b holds rows).
                        const glm::mat3 blended(b[0], b[4], b[8], b[1], b[5], b[9], b[2], b[6], b[10]);
                        normals[v] = normal_matrix(blended) * normal_source[v];
                    }
                }
            } else if (plan.skinned) {
                const SkinWeights& skin = *object.skin;
                const std::size_t n = skin.influences;
                for (std::size_t v = first; v < last; ++v) {
                    const glm::vec4 h(source[v], 1.0f);
                    glm::vec4 sum(0.0f);
                    glm::mat3 blended(0.0f);
                    for (std::size_t k = v * n; k < v * n + n; ++k) {
                        const float w = skin.weights[k];
                        if (w != 0.0f) {
                            sum += w * (joints[skin.joints[k]] * h);
                            blended += w * glm::mat3(joints[skin.joints[k]]);
                        }
                    }
                    result[v] = glm::vec3(sum) / sum.w;
                    if (normals) normals[v] = normal_matrix(blended) * normal_source[v];
                }
            } else if (!plan.fixed_rest) {
                for (std::size_t v = first; v < last; ++v) {
                    const glm::vec4 h = base * glm::vec4(source[v], 1.0f);
                    result[v] = glm::vec3(h) / h.w;
                }
                if (normals) {
                    for (std::size_t v = first; v < last; ++v) normals[v] = base_normal * normal_source[v];
                }
            } else {
                std::copy(source + first, source + last, result + first);
                if (normals) std::copy(normal_source + first, normal_source + last, normals + first);
            }
            // ---- Procedural motions, in order ----
            for (const std::size_t m : motions) {
                switch (scene.motions[m].kind) {
                    case MotionKind::rigid:
                        for (std::size_t v = first; v < last; ++v) result[v] = glm::vec3(rigid * glm::vec4(result[v], 1.0f));
                        if (normals) {
                            for (std::size_t v = first; v < last; ++v) normals[v] = rigid_normal * normals[v];
                        }
                        break;
                    case MotionKind::wave:
                        if (!(radius > 0.0)) break;
                        for (std::size_t v = first; v < last; ++v) {
                            const double angle = 6.0 * double(result[v].x) / radius + 0.5 * double(frame);
                            result[v].y += static_cast<float>(0.05 * radius * std::sin(angle));
                            if (normals) normals[v] = wave_normal(normals[v], static_cast<float>(0.3 * std::cos(angle)));
                        }
                        break;
                    case MotionKind::explode:
                        for (std::size_t v = first; v < last; ++v) result[v] += f * plan.explode_step[v / 3];
                        break;
                }
            }
            if (normals && normals_turn) {
                for (std::size_t v = first; v < last; ++v) normals[v] = normalize_or_zero(normals[v]);
            }
            return first_non_finite(result, first, last);
        });
    }

    void pose_camera(int frame, PosedScene& out) const {
        if (scene.cameras.empty()) {
            out.camera.reset();
            return;
        }
        const SceneCamera& camera = scene.cameras.front();
        const glm::dmat4& world = out.node_world[camera.node];
        const glm::dmat3 axes(world);
        PosedCamera posed;
        posed.eye = transform_point(world, glm::dvec3(0.0));
        posed.forward = glm::normalize(axes * glm::dvec3(0.0, 0.0, -1.0));
        posed.up = glm::normalize(axes * glm::dvec3(0.0, 1.0, 0.0));
        posed.yfov_rad = camera.yfov_rad;
        posed.aspect_ratio = camera.aspect_ratio;
        const auto finite = [](const glm::dvec3& v) {
            return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
        };
        if (!finite(posed.eye) || !finite(posed.forward) || !finite(posed.up)) {
            throw SceneError(scene.source + ": camera '" + camera.name + "', frame " + std::to_string(frame) +
                             ": its node's world transform is not finite or collapses an axis");
        }
        out.camera = posed;
    }

    /// Poses every object (or only those with procedural motions), applying their motions or
    /// not (the frame-0 reference the motions are defined from is the pose without them).
    void pose(int frame, PosedScene& out, bool with_motions, bool skip_fixed, bool motion_objects_only) const {
        out.frame = frame;
        out.time_s = static_cast<double>(frame) / settings.fps;
        nodes.evaluate(clip_time(out.time_s), out.node_world, out.node_weights);
        const std::size_t count = scene.objects.size();
        out.objects.resize(count);
        if (out.poser_id != id) {
            // Filled by another poser (or none): nothing in it is this poser's previous result.
            for (PosedObject& object : out.objects) object.evaluated = false;
            out.poser_id = id;
        }
        std::vector<Failure> failures(count);
        tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
            if (motion_objects_only && plans[i].motions.empty()) return;
            pose_inputs(i, frame, with_motions, out);
            failures[i] = pose_positions(i, frame, with_motions, skip_fixed, out);
            // A failed object's positions are not a result: the next call computes them again
            // (and fails again at the same frame).
            if (failures[i].vertex != kNoVertex || failures[i].transform) out.objects[i].evaluated = false;
        });
        for (std::size_t i = 0; i < count; ++i) throw_if_failed(i, frame, failures[i]);
        pose_camera(frame, out);
    }

    void throw_if_failed(std::size_t i, int frame, const Failure& failure) const {
        const std::string where =
            scene.source + ": object '" + scene.objects[i].name + "', frame " + std::to_string(frame) + ": ";
        if (failure.vertex != kNoVertex) {
            throw SceneError(where + "vertex " + std::to_string(failure.vertex) + " has a non-finite position");
        }
        if (failure.transform) throw SceneError(where + "world transform is not finite");
    }

    void classify();
    void apply_overrides();
    void prepare_object_spaces();
    void prepare_rests();
    void prepare_motion_references();
};

void ScenePoser::Impl::classify() {
    plans.resize(scene.objects.size());
    for (std::size_t m = 0; m < scene.motions.size(); ++m) plans[scene.motions[m].object].motions.push_back(m);
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& object = scene.objects[i];
        ObjectPlan& plan = plans[i];
        const bool has_node = object.node >= 0;
        const auto node = static_cast<std::size_t>(object.node);
        plan.skinned = object.skin.has_value();
        plan.node_driven = !plan.skinned && has_node && nodes.transform_driven(node);
        plan.morph_driven = object.morph && has_node && nodes.weights_driven(node);

        bool deforms = plan.morph_driven && nodes.weights_vary(node);
        if (plan.skinned) {
            for (const std::uint32_t joint : scene.skins[object.skin->skin].joints) {
                deforms = deforms || nodes.transform_varies(joint);
            }
        }
        const bool moves = !plan.skinned && has_node && nodes.transform_varies(node);
        MotionClass derived = deforms ? MotionClass::deformable : moves ? MotionClass::rigid : MotionClass::static_;
        for (const std::size_t m : plan.motions) {
            switch (scene.motions[m].kind) {
                case MotionKind::rigid:
                    derived = std::max(derived, MotionClass::rigid);
                    break;
                case MotionKind::wave:
                    derived = std::max(derived, MotionClass::deformable);
                    break;
                case MotionKind::explode:
                    // Same triangles every frame, only their vertices move: deformable. Its
                    // refits do degrade, but the SAH threshold catches that: on
                    // sphere:1000000 over 32 frames, refitting and rebuilding on a 30% SAH rise
                    // (5 rebuilds) cost 887 ms per frame against 1108 for a rebuild every
                    // frame (README, "Animation"). `--treat NAME=exploding` still rebuilds
                    // every frame.
                    derived = std::max(derived, MotionClass::deformable);
                    break;
            }
        }
        plan.derived = plan.effective = derived;
    }
}

void ScenePoser::Impl::apply_overrides() {
    for (const ClassOverride& override_ : settings.class_overrides) {
        if (override_.object >= plans.size()) {
            throw std::invalid_argument("class override '" + override_.spec + "': object index " +
                                        std::to_string(override_.object) + " out of range");
        }
        ObjectPlan& plan = plans[override_.object];
        if (override_.motion_class < plan.derived) {
            throw std::invalid_argument(
                "class override '" + override_.spec + "': object '" + scene.objects[override_.object].name +
                "' is " + motion_class_name(plan.derived) + " and a class can only be raised (static < rigid < " +
                "deformable < exploding), not lowered to " + motion_class_name(override_.motion_class));
        }
        plan.effective = override_.motion_class;
    }
}

void ScenePoser::Impl::prepare_object_spaces() {
    // Static or rigid objects whose shape is not mesh.positions: skinned ones (their skinned
    // pose, which no joint changes) and those whose weights a clip holds constant. Any time
    // gives the same shape; t = 0 is as good as any.
    std::vector<glm::dmat4> node_world, joints;
    std::vector<double> node_weights;
    bool evaluated = false;
    for (std::size_t i = 0; i < plans.size(); ++i) {
        ObjectPlan& plan = plans[i];
        if (!plan.fixed() || !(plan.skinned || plan.morph_driven)) continue;
        if (!evaluated) nodes.evaluate(0.0, node_world, node_weights);
        evaluated = true;
        const Object& object = scene.objects[i];
        const std::span<const double> weights =
            plan.morph_driven ? nodes.weights(static_cast<std::size_t>(object.node), node_weights)
                              : std::span<const double>();
        if (plan.skinned) compute_joint_matrices(scene.skins[object.skin->skin], node_world, joints);
        plan.own_object_space.resize(object.mesh.positions.size());
        for (std::size_t v = 0; v < object.mesh.positions.size(); ++v) {
            glm::dvec3 p = plan.morph_driven ? morphed_position(*object.morph, weights, v)
                                             : glm::dvec3(object.mesh.positions[v]);
            if (plan.skinned) p = skinned_position(*object.skin, joints, v, p);
            plan.own_object_space[v] = glm::vec3(p);
        }
        plan.own_object_space_normals.resize(object.mesh.normals.size());
        const bool morph_normals = plan.morph_driven && !object.morph->normal_deltas.empty();
        for (std::size_t v = 0; v < object.mesh.normals.size(); ++v) {
            glm::dvec3 n = morph_normals ? morphed_normal(*object.morph, weights, v) : glm::dvec3(object.mesh.normals[v]);
            if (plan.skinned) n = skinned_normal(*object.skin, joints, v, n);
            plan.own_object_space_normals[v] = glm::vec3(normalize_or_zero(n));
        }
        plan.uses_own_object_space = true;
    }
}

void ScenePoser::Impl::prepare_rests() {
    for (std::size_t i = 0; i < plans.size(); ++i) {
        ObjectPlan& plan = plans[i];
        plan.fixed_rest = !plan.fixed() && !plan.skinned && !plan.morph_driven && !plan.node_driven;
        if (!plan.fixed_rest) continue;
        const Object& object = scene.objects[i];
        const glm::dmat4 transform(object.transform);
        if (transform == glm::dmat4(1.0)) {
            // transform_point by the identity gives every finite vertex back exactly.
            plan.rest = object.mesh.positions;
            plan.rest_normals = object.mesh.normals;
            continue;
        }
        plan.own_rest.resize(object.mesh.positions.size());
        // A non-finite vertex is reported by pose(), which names the frame.
        transform_positions(transform, object.mesh.positions, plan.own_rest.data());
        plan.rest = plan.own_rest;
        plan.own_rest_normals.resize(object.mesh.normals.size());
        transform_normals(transform, object.mesh.normals, plan.own_rest_normals.data());
        plan.rest_normals = plan.own_rest_normals;
    }
}

void ScenePoser::Impl::prepare_motion_references() {
    if (scene.motions.empty()) return;
    PosedScene frame0;
    pose(0, frame0, false, false, true);
    for (std::size_t i = 0; i < plans.size(); ++i) {
        ObjectPlan& plan = plans[i];
        if (plan.motions.empty()) continue;
        const std::vector<glm::vec3>& p = frame0.objects[i].positions;
        plan.reference = motion_reference(p);
        const bool explodes = std::any_of(plan.motions.begin(), plan.motions.end(), [&](std::size_t m) {
            return scene.motions[m].kind == MotionKind::explode;
        });
        if (explodes) {
            const std::vector<glm::uvec3>& triangles = scene.objects[i].mesh.triangles;
            plan.explode_step.resize(triangles.size());
            tbb::parallel_for(std::size_t(0), triangles.size(), [&](std::size_t t) {
                const glm::dvec3 n = face_normal(glm::dvec3(p[triangles[t].x]), glm::dvec3(p[triangles[t].y]),
                                                 glm::dvec3(p[triangles[t].z]));
                plan.explode_step[t] = glm::vec3(explode_offset(n, static_cast<std::uint32_t>(t), plan.reference, 1));
            });
        }
        if (plan.fixed_rest && scene.motions[plan.motions.front()].kind == MotionKind::wave) {
            // The rest x in double, as wave_motion sees it before any rounding.
            const Object& object = scene.objects[i];
            const glm::dmat4 transform(object.transform);
            const double r = plan.reference.radius;
            plan.wave_sin.assign(p.size(), 0.0f);
            plan.wave_cos.assign(p.size(), 0.0f);
            if (!(r > 0.0)) continue;  // a zero-size object does not wave: y + 0
            tbb::parallel_for(std::size_t(0), p.size(), [&](std::size_t v) {
                const double x = transform_point(transform, glm::dvec3(object.mesh.positions[v])).x;
                plan.wave_sin[v] = static_cast<float>(std::sin(6.0 * x / r));
                plan.wave_cos[v] = static_cast<float>(std::cos(6.0 * x / r));
            });
        }
    }
}

ScenePoser::ScenePoser(const Scene& scene, PoseSettings settings) {
    if (!std::isfinite(settings.fps) || !(settings.fps > 0.0)) {
        throw std::invalid_argument("fps must be finite and positive, not " + std::to_string(settings.fps));
    }
    std::vector<std::size_t> clips(scene.clips.size());
    std::iota(clips.begin(), clips.end(), std::size_t(0));
    if (settings.clips) {
        for (const std::size_t c : *settings.clips) {
            if (c >= scene.clips.size()) {
                throw std::invalid_argument("clip index " + std::to_string(c) + " out of range (" + scene.source +
                                            " has " + std::to_string(scene.clips.size()) + " clips)");
            }
        }
        clips = *settings.clips;
    }
    check_animation_data(scene);
    impl_ = std::make_unique<Impl>(scene, std::move(settings), std::move(clips));
    for (const std::size_t c : impl_->clips) impl_->end_time = std::max(impl_->end_time, scene.clips[c].end_time());
    impl_->classify();
    impl_->apply_overrides();
    impl_->prepare_object_spaces();
    impl_->prepare_rests();
    impl_->prepare_motion_references();
}

ScenePoser::~ScenePoser() = default;
ScenePoser::ScenePoser(ScenePoser&&) noexcept = default;
ScenePoser& ScenePoser::operator=(ScenePoser&&) noexcept = default;

void ScenePoser::pose(int frame, PosedScene& out) const {
    impl_->pose(frame, out, true, impl_->settings.skip_fixed_positions, false);
}

MotionClass ScenePoser::motion_class(std::size_t object) const { return impl_->plans.at(object).effective; }

MotionClass ScenePoser::derived_class(std::size_t object) const { return impl_->plans.at(object).derived; }

std::span<const glm::vec3> ScenePoser::object_space_positions(std::size_t object) const {
    return impl_->object_space(object);
}

std::span<const glm::vec3> ScenePoser::object_space_normals(std::size_t object) const {
    return impl_->object_space_normals(object);
}

void ScenePoser::fixed_world_normals(std::size_t object, const PosedScene& posed,
                                     std::vector<glm::vec3>& out) const {
    if (!impl_->plans.at(object).fixed()) {
        throw std::invalid_argument("ScenePoser::fixed_world_normals: object '" +
                                    impl_->scene.objects[object].name + "' is not static or rigid");
    }
    const std::span<const glm::vec3> source = impl_->object_space_normals(object);
    out.resize(source.size());
    transform_normals(posed.objects.at(object).transform, source, out.data());
}

void ScenePoser::fixed_world_positions(std::size_t object, const PosedScene& posed,
                                       std::vector<glm::vec3>& out) const {
    if (!impl_->plans.at(object).fixed()) {
        throw std::invalid_argument("ScenePoser::fixed_world_positions: object '" +
                                    impl_->scene.objects[object].name + "' is not static or rigid");
    }
    const std::span<const glm::vec3> source = impl_->object_space(object);
    out.resize(source.size());
    Impl::Failure failure;
    failure.vertex = transform_positions(posed.objects.at(object).transform, source, out.data());
    impl_->throw_if_failed(object, posed.frame, failure);
}

double ScenePoser::time_of(int frame) const { return static_cast<double>(frame) / impl_->settings.fps; }

double ScenePoser::end_time() const { return impl_->end_time; }

const PoseSettings& ScenePoser::settings() const { return impl_->settings; }

void pose_scene(const Scene& scene, const PoseSettings& settings, int frame, PosedScene& out) {
    ScenePoser(scene, settings).pose(frame, out);
}

void pose_scene(const Scene& scene, int frame, PosedScene& out) { pose_scene(scene, PoseSettings{}, frame, out); }

}  // namespace dynrt::anim
