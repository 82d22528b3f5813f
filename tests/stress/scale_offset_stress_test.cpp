// Scale and offset: small closed meshes (a UV sphere, a tessellated box, an icosphere, a few
// hundred triangles each) scaled by 1e-6 ... 1e6 and moved 10 and 1000 times their size, and
// 1e6, from the origin. On every configuration, every tracing path must let no ray escape from
// inside (rays at vertices and along edges) and must agree with the exact double-precision
// reference wherever the reference says the answer is determined (Ambiguity::kNone: hit,
// triangle and t; kPrimitive: a hit and t). The two-level paths trace the mesh twice: once as
// an instance near the origin placed far away (leaks), once as an untransformed instance of
// the very world triangles (agreement, bit for bit the same geometry as the reference).

#include "stress_geometry.h"
#include "stress_mode.h"
#include "stress_tracers.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace dynrt::stress {
namespace {

struct NamedMesh {
    std::string name;
    ClosedMesh mesh;  ///< unit size, centred near the origin
};

std::vector<NamedMesh> small_meshes() {
    return {{"uv sphere 16x12", uv_sphere_mesh(16, 12, 1.0f, glm::vec3(0.01f, -0.02f, 0.03f))},
            {"box 4x4", box_mesh(4, glm::vec3(-1.0f, -0.75f, -0.5f), glm::vec3(1.0f, 0.75f, 0.5f))},
            {"icosphere 2", bvh::testing::icosphere_mesh(2, 1.0f)}};
}

/// Rays from inside (the centre and `origins - 1` random points within 0.3 radii, inside every
/// mesh here) toward
/// every vertex and edge midpoint and one more point per edge, plus `outside` rays from a
/// sphere of three radii around the mesh toward random points inside it: in world space.
std::vector<bvh::Ray> inside_rays(const ClosedMesh& world, glm::dvec3 c, double r, std::int64_t origins,
                                  std::uint32_t seed) {
    std::mt19937 rng(seed);
    const std::vector<glm::vec3> targets = edge_and_vertex_targets(world, 2);
    std::vector<bvh::Ray> rays;
    for (std::int64_t k = 0; k < origins; ++k) {
        const glm::dvec3 o = k == 0 ? c : c + 0.3 * r * glm::dvec3(bvh::testing::random_direction(rng)) *
                                                      std::uniform_real_distribution<double>(0.0, 1.0)(rng);
        for (const glm::vec3& t : targets) {
            bvh::Ray ray;
            ray.org = glm::vec3(o);
            ray.dir = t - ray.org;
            if (ray.dir != glm::vec3(0.0f)) rays.push_back(ray);
        }
    }
    return rays;
}

std::vector<bvh::Ray> outside_rays(glm::dvec3 c, double r, std::int64_t count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<bvh::Ray> rays;
    for (std::int64_t k = 0; k < count; ++k) {
        const glm::dvec3 o = c + 3.0 * r * glm::dvec3(bvh::testing::random_direction(rng));
        const glm::dvec3 t = c + 0.8 * r * glm::dvec3(bvh::testing::random_direction(rng)) *
                                     std::uniform_real_distribution<double>(0.0, 1.0)(rng);
        bvh::Ray ray;
        ray.org = glm::vec3(o);
        ray.dir = glm::vec3(t - o);
        if (ray.dir != glm::vec3(0.0f)) rays.push_back(ray);
    }
    return rays;
}

bool has_degenerate(const ClosedMesh& mesh) {
    for (const bvh::Triangle& t : mesh.triangles()) {
        if (bvh::is_degenerate(t)) return true;
    }
    return false;
}

TEST(ScaleOffsetStress, NoLeaksAndReferenceAgreementFrom1em6To1e6) {
    const double scales[] = {1e-6, 1e-3, 1.0, 1e3, 1e6};
    const glm::dvec3 direction(0.6, -0.48, 0.64);  // unit length
    std::uint64_t leak_rays = 0, leaks = 0, agreement_rays = 0, disagreements = 0, ambiguous = 0;
    int configurations = 0, unresolved = 0;
    std::uint32_t seed = 100;
    for (const NamedMesh& named : small_meshes()) {
        for (const double s : scales) {
            for (const double offset : {0.0, 10.0 * s, 1000.0 * s, 1e6}) {
                const std::string what = named.name + " scale " + std::to_string(s) + " offset " + std::to_string(offset);
                SCOPED_TRACE(what);
                ++seed;
                // The object near the origin at its scale, and where the world has it.
                const ClosedMesh object = transformed(named.mesh, s, glm::dvec3(0.0));
                glm::dmat4 place = glm::translate(glm::dmat4(1.0), offset * direction);
                place = glm::rotate(place, glm::radians(23.0), glm::dvec3(0.0, 1.0, 0.0));
                const ClosedMesh world = transformed(object, place);
                // A mesh 1e-6 across seen 1e6 away collapses to a few float values: there is
                // no surface left to test.
                if (has_degenerate(world) || has_degenerate(object) || !is_closed(world.triangles())) {
                    ++unresolved;
                    continue;
                }
                ++configurations;
                bvh::Aabb box;
                for (const glm::vec3& v : world.vertices) box.extend(v);
                const glm::dvec3 c = glm::dvec3(box.center());
                const double r = 0.5 * glm::length(glm::dvec3(box.extent()));

                // Leaks: every path, the two-level ones through the placement.
                const Tracers placed(world.triangles(), object.triangles(), place);
                const std::vector<bvh::Ray> in = inside_rays(world, c, r, scaled(3, 20), seed);
                Answers answers;
                for (const Path path : kPaths) {
                    LeakCount count;
                    placed.trace(path, in, answers);
                    count_leaks(in, answers, count);
                    EXPECT_EQ(count.leaks(), 0u) << path_name(path) << ": " << count.closest_misses
                                                 << " closest and " << count.any_misses
                                                 << " any-hit misses; first: " << count.first;
                    leak_rays += count.rays;
                    leaks += count.leaks();
                }

                // Agreement with the reference, on the very world triangles everywhere.
                const Tracers exact(world.triangles());
                const ReferenceWorld reference(exact.world());
                std::vector<bvh::Ray> rays = outside_rays(c, r, scaled(600, 20), seed + 7);
                rays.insert(rays.end(), in.begin(), in.begin() + std::min<std::size_t>(in.size(), scaled(400, 20)));
                const std::vector<reference::ReferenceHit> want = reference_hits(*reference.tracer, rays);
                for (const Path path : kPaths) {
                    Agreement agreement;
                    exact.trace(path, rays, answers);
                    check_against_reference(rays, want, answers, agreement);
                    EXPECT_EQ(agreement.disagreements, 0u) << path_name(path) << ": first " << agreement.first;
                    agreement_rays += agreement.rays;
                    disagreements += agreement.disagreements;
                    ambiguous += agreement.ambiguous_any + agreement.ambiguous_primitive;
                }
            }
        }
    }
    std::printf("scale/offset: %d configurations (%d left out: the mesh collapses in float), "
                "%llu inside rays traced, %llu leaks; %llu rays against the reference, %llu ambiguous, "
                "%llu disagreements\n",
                configurations, unresolved, static_cast<unsigned long long>(leak_rays),
                static_cast<unsigned long long>(leaks), static_cast<unsigned long long>(agreement_rays),
                static_cast<unsigned long long>(ambiguous), static_cast<unsigned long long>(disagreements));
    RecordProperty("configurations", configurations);
    RecordProperty("leak_rays", std::to_string(leak_rays));
    RecordProperty("leaks", std::to_string(leaks));
    RecordProperty("reference_rays", std::to_string(agreement_rays));
    RecordProperty("disagreements", std::to_string(disagreements));
    // Every scale must keep some configurations: a sweep that silently leaves out whole scales
    // tests nothing there.
    EXPECT_GE(configurations, 3 * 5 * 2);
}

}  // namespace
}  // namespace dynrt::stress
