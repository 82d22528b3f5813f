// ScenePoser's fast paths (issue 20, posing at memory speed) against a straightforward
// double-precision evaluation of the same definitions (procedural_motion.h, skinning.h,
// morphing.h), frame by frame: explode and wave from their precomputed tables, several motions
// through the general kernel, skinning and morphing in float. Then the finiteness check, which
// must still name object, frame and vertex, and objects that did not move, which must not be
// touched. Vertex normals go through the same stages (PosedObject::normals) and are checked
// alike, to 1e-5 of their unit length.
//
// Tolerance: the fast paths round to float a few times where the definition rounds once, so a
// coordinate may differ from the double evaluation by a few float ulps of the magnitudes
// involved; the tests allow 1e-6 (about 8 ulps) of the largest of them: the distance of the
// object's box from the origin plus its radius plus the farthest a motion moves it.

#include "dynrt/anim/morphing.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/anim/skinning.h"
#include "dynrt/engine/scene_loading.h"
#include "shared_scene_files.h"
#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/vertex_normals.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace dynrt::anim {
namespace {


constexpr double kRelativeTolerance = 1e-6;

glm::dvec3 transform_point(const glm::dmat4& m, const glm::dvec3& p) {
    const glm::dvec4 h = m * glm::dvec4(p, 1.0);
    return glm::dvec3(h) / h.w;
}

/// Expects every posed vertex within `tolerance` of `expected`, reporting the worst.
void expect_close(std::span<const glm::vec3> actual, std::span<const glm::dvec3> expected, double tolerance,
                  const std::string& what) {
    ASSERT_EQ(actual.size(), expected.size()) << what;
    double worst = 0.0;
    std::size_t worst_vertex = 0;
    for (std::size_t v = 0; v < actual.size(); ++v) {
        for (int c = 0; c < 3; ++c) {
            const double error = std::abs(double(actual[v][c]) - expected[v][c]);
            if (!(error <= worst)) {
                worst = error;
                worst_vertex = v;
            }
        }
    }
    EXPECT_LE(worst, tolerance) << what << ": vertex " << worst_vertex;
}

/// sphere:2000 moved away from the origin and scaled, so the object's transform is not the
/// identity, with the given `--anim` specs.
Scene moved_sphere(const std::vector<std::string>& motions) {
    Scene scene = make_procedural_scene("sphere:2000");
    glm::mat4& m = scene.objects[0].transform;
    m = glm::mat4(1.0f);
    m[0][0] = 3.0f;
    m[1][1] = 2.5f;
    m[2][2] = 0.75f;
    m[3] = glm::vec4(40.0f, -7.0f, 12.5f, 1.0f);
    add_procedural_motions(scene, motions);
    return scene;
}

/// The double evaluation of the scene's one object's motions at `frame`, from its rest world
/// positions (its transform in double) and the frame-0 reference the poser uses.
std::vector<glm::dvec3> double_evaluation(const Scene& scene, int frame) {
    const Object& object = scene.objects[0];
    std::vector<glm::dvec3> rest;
    std::vector<glm::vec3> rest_float;
    for (const glm::vec3& p : object.mesh.positions) {
        rest.push_back(transform_point(glm::dmat4(object.transform), glm::dvec3(p)));
        rest_float.push_back(glm::vec3(rest.back()));
    }
    const MotionReference reference = motion_reference(rest_float);
    std::vector<glm::dvec3> out = rest;
    for (std::size_t v = 0; v < out.size(); ++v) {
        for (const ProceduralMotion& motion : scene.motions) {
            switch (motion.kind) {
                case MotionKind::rigid:
                    out[v] = rigid_motion(out[v], reference, frame);
                    break;
                case MotionKind::wave:
                    out[v] = wave_motion(out[v], reference, frame);
                    break;
                case MotionKind::explode: {
                    const std::size_t t = v / 3;
                    const glm::dvec3 n = face_normal(glm::dvec3(rest_float[3 * t]), glm::dvec3(rest_float[3 * t + 1]),
                                                     glm::dvec3(rest_float[3 * t + 2]));
                    out[v] += explode_offset(n, static_cast<std::uint32_t>(t), reference, frame);
                    break;
                }
            }
        }
    }
    return out;
}

/// The same for the object's vertex normals (PosedObject::normals): the rest normals through
/// the transform's cofactor matrix, each rigid motion's, the wave's Jacobian at the x the wave
/// sees, explode's none, normalised.
std::vector<glm::dvec3> double_normals(const Scene& scene, int frame) {
    const Object& object = scene.objects[0];
    const glm::dmat4 transform(object.transform);
    std::vector<glm::vec3> rest_float;
    for (const glm::vec3& p : object.mesh.positions) rest_float.push_back(glm::vec3(transform_point(transform, glm::dvec3(p))));
    const MotionReference reference = motion_reference(rest_float);
    const glm::dmat3 rigid = normal_matrix(glm::dmat3(rigid_motion_matrix(reference, frame)));
    std::vector<glm::dvec3> out(object.mesh.normals.size());
    for (std::size_t v = 0; v < out.size(); ++v) {
        glm::dvec3 p = transform_point(transform, glm::dvec3(object.mesh.positions[v]));
        glm::dvec3 n = normal_matrix(glm::dmat3(transform)) * glm::dvec3(object.mesh.normals[v]);
        for (const ProceduralMotion& motion : scene.motions) {
            switch (motion.kind) {
                case MotionKind::rigid:
                    p = rigid_motion(p, reference, frame);
                    n = rigid * n;
                    break;
                case MotionKind::wave:
                    if (reference.radius > 0.0) {
                        n.x -= 0.3 * std::cos(6.0 * p.x / reference.radius + 0.5 * frame) * n.y;
                    }
                    p = wave_motion(p, reference, frame);
                    break;
                case MotionKind::explode: {  // moves the point (which a later wave sees), not n
                    const std::size_t t = v / 3;
                    const glm::dvec3 face = face_normal(glm::dvec3(rest_float[3 * t]), glm::dvec3(rest_float[3 * t + 1]),
                                                        glm::dvec3(rest_float[3 * t + 2]));
                    p += explode_offset(face, static_cast<std::uint32_t>(t), reference, frame);
                    break;
                }
            }
        }
        out[v] = glm::normalize(n);
    }
    return out;
}

class MotionPrecision : public ::testing::TestWithParam<std::vector<std::string>> {};

TEST_P(MotionPrecision, FastPathEqualsTheDoubleEvaluation) {
    const Scene scene = moved_sphere(GetParam());
    const ScenePoser poser(scene, {});
    PosedScene posed;
    for (const int frame : {0, 1, 7, -5, 100, 10000}) {
        poser.pose(frame, posed);
        const std::vector<glm::dvec3> expected = double_evaluation(scene, frame);
        // Box centre (40, -7, 12.5), radius about 3: explode moves up to 0.03 R per frame.
        const double size = glm::length(glm::dvec3(40.0, -7.0, 12.5)) + 3.0 * (1.0 + 0.03 * std::abs(frame));
        expect_close(posed.objects[0].positions, expected, kRelativeTolerance * size,
                     "frame " + std::to_string(frame));
        // Unit normals: a few float roundings of numbers of order 1, plus what a wave's slope
        // 0.3 cos(6x/R + f/2) makes of the position's own error: 1.8 / R per unit of x.
        expect_close(posed.objects[0].normals, double_normals(scene, frame),
                     1e-5 + 1.8 / 3.0 * kRelativeTolerance * size, "normals, frame " + std::to_string(frame));
    }
}

INSTANTIATE_TEST_SUITE_P(Motions, MotionPrecision,
                         ::testing::Values(std::vector<std::string>{"explode"}, std::vector<std::string>{"wave"},
                                           std::vector<std::string>{"wave", "rigid"},
                                           std::vector<std::string>{"explode", "wave"},
                                           std::vector<std::string>{"rigid", "explode"}));


/// The double evaluation of object i from the posed inputs: morph, then skinning or the node
/// transform (morphing.h's and skinning.h's definitions, term by term).
std::vector<glm::dvec3> double_evaluation(const Scene& scene, std::size_t i, const PosedObject& posed) {
    const Object& object = scene.objects[i];
    std::vector<glm::dvec3> out(object.mesh.positions.size());
    for (std::size_t v = 0; v < out.size(); ++v) {
        glm::dvec3 p = object.morph && !posed.morph_weights.empty() ? morphed_position(*object.morph, posed.morph_weights, v)
                                                                    : glm::dvec3(object.mesh.positions[v]);
        out[v] = object.skin ? skinned_position(*object.skin, posed.joint_matrices, v, p)
                             : transform_point(posed.node_transform, p);
    }
    return out;
}

/// The same for its normals: morphed by the normal displacements, through the skinned
/// cofactor matrix or the node transform's, normalised.
std::vector<glm::dvec3> double_normals(const Scene& scene, std::size_t i, const PosedObject& posed) {
    const Object& object = scene.objects[i];
    std::vector<glm::dvec3> out(object.mesh.normals.size());
    const bool morphed = object.morph && !object.morph->normal_deltas.empty() && !posed.morph_weights.empty();
    for (std::size_t v = 0; v < out.size(); ++v) {
        const glm::dvec3 n = morphed ? morphed_normal(*object.morph, posed.morph_weights, v) : glm::dvec3(object.mesh.normals[v]);
        out[v] = normalize_or_zero(object.skin ? skinned_normal(*object.skin, posed.joint_matrices, v, n)
                                               : normal_matrix(glm::dmat3(posed.node_transform)) * n);
    }
    return out;
}

/// Every deformable object of a sample model at several frames of its clips.
void expect_deformables_match(const Scene& scene) {
    const ScenePoser poser(scene, {});
    PosedScene posed;
    std::size_t checked = 0;
    for (const int frame : {0, 5, 13, 29}) {
        poser.pose(frame, posed);
        for (std::size_t i = 0; i < scene.objects.size(); ++i) {
            if (poser.motion_class(i) != MotionClass::deformable) continue;
            const std::vector<glm::dvec3> expected = double_evaluation(scene, i, posed.objects[i]);
            double size = 0.0;
            for (const glm::dvec3& p : expected) size = std::max(size, glm::length(p));
            expect_close(posed.objects[i].positions, expected, kRelativeTolerance * size,
                         scene.objects[i].name + ", frame " + std::to_string(frame));
            // Normals are posed exactly when the mesh has some (a soup, the Fox's, has none).
            ASSERT_EQ(posed.objects[i].normals.empty(), scene.objects[i].mesh.normals.empty()) << scene.objects[i].name;
            expect_close(posed.objects[i].normals, double_normals(scene, i, posed.objects[i]), 1e-5,
                         scene.objects[i].name + " normals, frame " + std::to_string(frame));
            ++checked;
        }
    }
    EXPECT_GT(checked, 0u);
}

TEST(SkinningPrecision, CesiumManEqualsTheDoubleEvaluation) {
    LOAD_SHARED_OR_SKIP(scene, "cesiumman/CesiumMan.glb");
    expect_deformables_match(scene);
}

TEST(SkinningPrecision, FoxWithEightInfluencesOrFourEqualsTheDoubleEvaluation) {
    LOAD_SHARED_OR_SKIP(scene, "fox/Fox.glb");
    expect_deformables_match(scene);
}

TEST(MorphingPrecision, AnimatedMorphSphereEqualsTheDoubleEvaluation) {
    LOAD_SHARED_OR_SKIP(scene, "animatedmorphsphere/AnimatedMorphSphere.glb");
    expect_deformables_match(scene);
}

// ---- The finiteness check ----------------------------------------------------------------------

/// Two unshared triangles: one small at the origin, one in the plane y = `y` (near the largest
/// float, 3.40e38) with normal +y, so a motion that lifts it overflows there only.
Scene near_overflow(const std::string& motion, float y = 3.4e38f) {
    Scene scene;
    scene.source = "hand-made";
    scene.materials.push_back(Material{});
    Object object;
    object.name = "edge";
    object.mesh.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, y, 0}, {0, y, 1}, {1, y, 0}};
    object.mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
    scene.objects.push_back(object);
    add_procedural_motions(scene, std::vector<std::string>{motion});
    return scene;
}

void expect_error_at(const ScenePoser& poser, PosedScene& posed, int frame, const std::string& message) {
    try {
        poser.pose(frame, posed);
        ADD_FAILURE() << "no error at frame " << frame;
    } catch (const SceneError& e) {
        EXPECT_EQ(std::string(e.what()), message);
    }
}

TEST(PosingFiniteness, ExplodeOverflowNamesObjectFrameAndVertex) {
    // R ~ 1.5e38; triangle 1 rises by 0.02 R (0.5 + h(1)) ~ 2.7e36 per frame: 3.27e38 at
    // frame 10, past 3.40e38 at frame 20, while triangle 0 moves by at most 20 * 0.03 R.
    const Scene scene = near_overflow("explode", 3.0e38f);
    const ScenePoser poser(scene, {});
    PosedScene posed;
    poser.pose(10, posed);
    const std::string message = "hand-made: object 'edge', frame 20: vertex 3 has a non-finite position";
    expect_error_at(poser, posed, 20, message);
    // Asked again, the same frame fails the same way (a failed result is never kept).
    expect_error_at(poser, posed, 20, message);
}

TEST(PosingFiniteness, WaveOverflowNamesObjectFrameAndVertex) {
    const Scene scene = near_overflow("wave");
    const ScenePoser poser(scene, {});
    PosedScene posed;
    poser.pose(0, posed);  // sin(6x/R) ~ 0 at x = 0: finite
    // Frame 3: sin(6x/R + 1.5) ~ 1 lifts y = 3.4e38 by 0.05 R ~ 8.5e36, past the largest float;
    // vertices 3 and 4 (x = 0) overflow, vertex 5 (x = 1, negligible next to R) too.
    expect_error_at(poser, posed, 3, "hand-made: object 'edge', frame 3: vertex 3 has a non-finite position");
}

TEST(PosingFiniteness, SeveralMotionsOverflowNamesObjectFrameAndVertex) {
    Scene scene = near_overflow("wave");
    add_procedural_motions(scene, std::vector<std::string>{"rigid"});  // the general kernel
    const ScenePoser poser(scene, {});
    PosedScene posed;
    poser.pose(0, posed);
    expect_error_at(poser, posed, 3, "hand-made: object 'edge', frame 3: vertex 3 has a non-finite position");
}

// ---- Objects that did not move are not touched --------------------------------------------------

TEST(PosingUnmoved, UnchangedObjectsKeepTheirPositionsUntouched) {
    // A static sphere, a waving one and one exploding, all positions computed.
    Scene scene = make_procedural_scene("sphere:200+sphere:300@3,0,0+sphere:400@-3,0,0");
    add_procedural_motions(scene, std::vector<std::string>{"wave:sphere:300@3,0,0", "explode:sphere:400@-3,0,0"});
    ASSERT_EQ(scene.objects.size(), 3u);
    const ScenePoser poser(scene, {});
    PosedScene posed;
    poser.pose(4, posed);
    const glm::vec3 sentinel(1234.0f, 5678.0f, 9.0f);
    std::vector<const glm::vec3*> storage;
    for (PosedObject& object : posed.objects) {
        EXPECT_TRUE(object.changed);
        storage.push_back(object.positions.data());
        object.positions[0] = sentinel;  // pose() must not write an unchanged object again
    }
    poser.pose(4, posed);  // same frame: nothing moved
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_FALSE(posed.objects[i].changed) << i;
        EXPECT_EQ(posed.objects[i].positions.data(), storage[i]) << i;
        EXPECT_EQ(posed.objects[i].positions[0], sentinel) << i;
    }
    poser.pose(5, posed);  // the moving objects are posed again, the static one is not
    EXPECT_FALSE(posed.objects[0].changed);
    EXPECT_EQ(posed.objects[0].positions[0], sentinel);
    for (std::size_t i = 1; i < 3; ++i) {
        EXPECT_TRUE(posed.objects[i].changed) << i;
        EXPECT_NE(posed.objects[i].positions[0], sentinel) << i;
    }
}

TEST(PosingUnmoved, AnotherPoserRecomputesEverything) {
    // A PosedScene filled by one poser holds nothing another poser may keep, even when the
    // objects' inputs are equal (same transform, same frame).
    Scene scene = make_procedural_scene("sphere:200");
    const ScenePoser first(scene, {});
    PosedScene posed;
    first.pose(0, posed);
    posed.objects[0].positions[0] = glm::vec3(1234.0f);
    const ScenePoser second(scene, {});
    second.pose(0, posed);
    EXPECT_TRUE(posed.objects[0].changed);
    EXPECT_NE(posed.objects[0].positions[0], glm::vec3(1234.0f));
}

}  // namespace
}  // namespace dynrt::anim
