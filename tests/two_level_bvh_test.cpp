// Two-level BVH, single rays: the top level against the brute force over instances (bit for
// bit), against the exact double-precision reference over the posed world-space triangles
// (within its ambiguity rules), the tie rule across instances, empty instances, any-hit, and a
// single identity instance against the plain TriangleBvh.

#include "two_level_test_world.h"

#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/two_level_bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>
#include <vector>

namespace dynrt::bvh::testing {
namespace {

/// Random rays: origins in `bounds` grown by half its extent (many inside the objects), random
/// directions, every fourth one a segment ending at a random distance.
std::vector<Ray> random_rays(std::uint32_t seed, const Aabb& bounds, int count) {
    std::mt19937 rng(seed);
    const glm::vec3 pad = bounds.extent() * 0.5f;
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        Ray r = make_ray(random_point(rng, bounds.lo - pad, bounds.hi + pad), random_direction(rng));
        if (i % 4 == 3) r.tmax = u(rng) * glm::length(bounds.extent());
        rays.push_back(r);
    }
    return rays;
}

/// Rays from far away aimed at the vertices of every instance's world-space triangles: they hit
/// silhouettes and box corners, where a top level padded too little would cull.
std::vector<Ray> vertex_rays(std::uint32_t seed, const TwoLevelWorld& w, float distance) {
    std::mt19937 rng(seed);
    std::vector<Ray> rays;
    for (const auto& tris : w.world_tris) {
        for (const Triangle& t : tris) {
            for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
                const glm::vec3 dir = random_direction(rng);
                rays.push_back(make_ray(v - distance * dir, dir));
            }
        }
    }
    return rays;
}

void expect_matches_brute_force(const TwoLevelWorld& w, const std::vector<Ray>& rays) {
    int mismatches = 0;
    for (const Ray& ray : rays) {
        const InstanceHit got = intersect_closest(w.tlas, ray);
        const InstanceHit want = brute_force_instances(w.tlas, ray);
        if (!same_bits(got, want) && ++mismatches <= 5) {
            ADD_FAILURE() << describe(ray) << ": top level " << describe(got) << ", brute force "
                          << describe(want);
        }
        if (intersect_any(w.tlas, ray) != want.is_hit() && ++mismatches <= 5) {
            ADD_FAILURE() << describe(ray) << ": any-hit says " << !want.is_hit();
        }
    }
    EXPECT_EQ(mismatches, 0);
}

/// Compares with the exact reference: where it is unambiguous, hit or miss, object, primitive
/// and t (relative to the scene scale seen from the origin, plus `t_abs`) must agree. The
/// reference sees the posed world-space float vertices, the instances their object-space ones:
/// far from the origin the two differ by the rounding of world coordinates, which `tol` and
/// `t_abs` must then cover.
void expect_matches_reference(const TwoLevelWorld& w, const std::vector<Ray>& rays,
                              int& hits_checked, const reference::Tolerances& tol = {},
                              double t_abs = 0.0, int ambiguous_per_mille = 20) {
    int mismatches = 0, ambiguous = 0;
    for (const Ray& ray : rays) {
        const InstanceHit got = intersect_closest(w.tlas, ray);
        const reference::ReferenceHit want = w.reference->closest(ray, tol);
        if (want.ambiguity == reference::Ambiguity::kAny) {
            ++ambiguous;
            continue;
        }
        bool ok = got.is_hit() == want.is_hit();
        if (ok && want.is_hit()) {
            const double scale = w.reference->scale_at(glm::dvec3(ray.org)) / glm::length(glm::dvec3(ray.dir));
            ok = got.object == static_cast<std::uint32_t>(want.object) &&
                 std::fabs(got.hit.t - want.t) <= 1e-5 * scale + t_abs;
            if (want.ambiguity == reference::Ambiguity::kNone) {
                ok = ok && got.hit.prim == static_cast<std::uint32_t>(want.prim);
            }
            ++hits_checked;
        }
        if (!ok && ++mismatches <= 5) {
            ADD_FAILURE() << describe(ray) << ": got " << describe(got) << ", reference t "
                          << want.t << " object " << want.object << " prim " << want.prim
                          << " ambiguity " << reference::to_string(want.ambiguity);
        }
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_LT(ambiguous, static_cast<int>(rays.size()) * ambiguous_per_mille / 1000)
        << "too many ambiguous rays";
}

TEST(TwoLevelBvh, TopLevelIsValidAndBoxesContainTheInstances) {
    TwoLevelWorld w = mixed_world();
    w.build();
    ASSERT_EQ(w.tlas.instances.size(), w.objects.size());
    ASSERT_EQ(w.tlas.world_boxes.size(), w.objects.size());
    // The empty and all-degenerate objects (6, 7, 8) have empty boxes and stay out of the tree.
    std::vector<Aabb> boxes;
    std::vector<std::uint32_t> in_tree;
    for (std::size_t i = 0; i < w.tlas.instances.size(); ++i) {
        const bool empty = w.tlas.instances[i].blas->empty();
        EXPECT_EQ(w.tlas.world_boxes[i].is_empty(), empty) << "instance " << i;
        if (!empty) {
            EXPECT_TRUE(w.tlas.world_boxes[i].contains(bounds_of(w.world_tris[i]))) << "instance " << i;
            in_tree.push_back(static_cast<std::uint32_t>(i));
        }
    }
    EXPECT_EQ(in_tree.size(), 7u);
    ASSERT_EQ(w.tlas.top.prim_ids.size(), in_tree.size());
    // validate() wants prim ids 0..n-1: map instance indices back to positions in in_tree.
    Bvh compact = w.tlas.top;
    for (std::uint32_t& id : compact.prim_ids) {
        id = static_cast<std::uint32_t>(std::find(in_tree.begin(), in_tree.end(), id) - in_tree.begin());
    }
    for (std::uint32_t i : in_tree) boxes.push_back(w.tlas.world_boxes[i]);
    EXPECT_EQ(validate(compact, boxes, 1), "");
    EXPECT_GT(w.tlas.origin_pad_rel, 0.0f);
}

TEST(TwoLevelBvh, ToObjectSpaceMapsWorldPointsToObjectPoints) {
    Instance instance;
    instance.identity = false;
    const glm::dmat4 place = placement({3.0, -2.0, 7.0}, 35.0, {1.0, 2.0, 3.0}, {2.0, -0.5, 1.0});
    instance.object_to_world = glm::mat4(place);
    instance.world_to_object = glm::mat4(glm::inverse(place));
    Ray world = make_ray({1.0f, 2.0f, 3.0f}, {0.25f, -1.0f, 0.5f}, 0.5f, 9.0f);
    const Ray local = to_object_space(instance, world);
    EXPECT_EQ(local.tmin, 0.5f);
    EXPECT_EQ(local.tmax, 9.0f);
    for (float t : {0.0f, 1.0f, 4.0f}) {
        const glm::dvec4 p = place * glm::dvec4(glm::dvec3(local.org) + double(t) * glm::dvec3(local.dir), 1.0);
        const glm::dvec3 q = glm::dvec3(world.org) + double(t) * glm::dvec3(world.dir);
        EXPECT_NEAR(p.x, q.x, 1e-5);
        EXPECT_NEAR(p.y, q.y, 1e-5);
        EXPECT_NEAR(p.z, q.z, 1e-5);
    }
    instance.identity = true;
    const Ray same = to_object_space(instance, world);
    EXPECT_EQ(same.org, world.org);
    EXPECT_EQ(same.dir, world.dir);
}

TEST(TwoLevelBvh, MatchesBruteForceOverInstancesBitForBit) {
    TwoLevelWorld w = mixed_world();
    w.build();
    expect_matches_brute_force(w, random_rays(1, w.world_bounds(), 20000));
    expect_matches_brute_force(w, vertex_rays(2, w, 30.0f));
}

TEST(TwoLevelBvh, MatchesExactReference) {
    TwoLevelWorld w = mixed_world();
    w.build();
    int hits = 0;
    expect_matches_reference(w, random_rays(3, w.world_bounds(), 6000), hits);
    EXPECT_GT(hits, 200);
}

TEST(TwoLevelBvh, FarFromOriginMatchesBruteForceAndReference) {
    TwoLevelWorld w = mixed_world(glm::dvec3(1.0e4, -2.0e4, 3.0e4));
    w.build();
    expect_matches_brute_force(w, random_rays(4, w.world_bounds(), 10000));
    expect_matches_brute_force(w, vertex_rays(5, w, 50.0f));
    // World coordinates near 3e4 are rounded to 2^-10 (about 1e-3): lateral and depth
    // tolerances of that order, relative to a scene scale of about 10.
    reference::Tolerances tol;
    tol.edge_rel = 1e-3;
    tol.layer_rel = 1e-3;
    int hits = 0;
    expect_matches_reference(w, random_rays(6, w.world_bounds(), 6000), hits, tol, 0.02, 200);
    EXPECT_GT(hits, 200);
}

TEST(TwoLevelBvh, FarCameraAtSmallSceneMatchesBruteForce) {
    // Origins far from a small scene at the origin: the padding proportional to |origin|.
    TwoLevelWorld w = mixed_world();
    w.build();
    expect_matches_brute_force(w, vertex_rays(7, w, 5.0e3f));
}

TEST(TwoLevelBvh, InstanceOrderDoesNotMatter) {
    TwoLevelWorld a = mixed_world();
    a.build();
    TwoLevelWorld b = mixed_world();
    b.instance_order = {9, 3, 8, 0, 5, 7, 1, 4, 6, 2};
    b.build();
    for (const Ray& ray : random_rays(8, a.world_bounds(), 5000)) {
        const InstanceHit ha = intersect_closest(a.tlas, ray), hb = intersect_closest(b.tlas, ray);
        ASSERT_TRUE(same_bits(ha, hb)) << describe(ray) << ": " << describe(ha) << " vs " << describe(hb);
    }
}

TEST(TwoLevelBvh, SharedTreePlacedTwiceHitsBothObjects) {
    TwoLevelWorld w = mixed_world();
    w.build();
    ASSERT_EQ(w.tlas.instances[1].blas, w.tlas.instances[5].blas);
    int hits1 = 0, hits5 = 0;
    for (const Ray& ray : random_rays(9, w.world_bounds(), 6000)) {
        const InstanceHit h = intersect_closest(w.tlas, ray);
        hits1 += h.object == 1 ? 1 : 0;
        hits5 += h.object == 5 ? 1 : 0;
    }
    EXPECT_GT(hits1, 10);
    EXPECT_GT(hits5, 10);
}

TEST(TwoLevelBvh, CoincidentInstancesTieToTheLowestObject) {
    // The same world triangles three times: two identity instances and one "transformed" by the
    // identity matrix (its object-space ray has the very same bits), with object ids in an
    // order unrelated to the instance order. Every hit is a tie in t; object 2 must win.
    const std::vector<Triangle> mesh = icosphere_mesh(2, 1.0f).triangles();
    const TriangleBvh tree = build_triangle_bvh(mesh, BuildConfig{});
    std::vector<Instance> instances(3);
    const std::uint32_t ids[3] = {9, 2, 5};
    for (int i = 0; i < 3; ++i) {
        instances[i].blas = &tree;
        instances[i].object = ids[i];
        instances[i].identity = i != 1;
    }
    TwoLevelBvh tlas;
    build_top_level(tlas, instances);
    int hits = 0;
    for (const Ray& ray : random_rays(10, bounds_of(mesh), 3000)) {
        const InstanceHit got = intersect_closest(tlas, ray);
        const Hit plain = intersect_closest(tree, ray);
        ASSERT_EQ(got.is_hit(), plain.is_hit());
        if (!plain.is_hit()) continue;
        ++hits;
        EXPECT_EQ(got.object, 2u);
        EXPECT_TRUE(same_bits(got, InstanceHit{plain, 2u})) << describe(got);
    }
    EXPECT_GT(hits, 300);
}

TEST(TwoLevelBvh, SingleIdentityInstanceEqualsTriangleBvh) {
    std::vector<Triangle> tris = icosphere_mesh(3, 2.0f).triangles();
    const std::vector<Triangle> soup = random_soup(12, 2000, 4.0f, 0.1f, glm::vec3(-2.0f));
    tris.insert(tris.end(), soup.begin(), soup.end());
    const TriangleBvh tree = build_triangle_bvh(tris, BuildConfig{});
    Instance instance;
    instance.blas = &tree;
    instance.object = 4;
    TwoLevelBvh tlas;
    build_top_level(tlas, {instance});
    EXPECT_EQ(tlas.origin_pad_rel, 0.0f);
    int hits = 0;
    for (const Ray& ray : random_rays(13, bounds_of(tris), 20000)) {
        const Hit plain = intersect_closest(tree, ray);
        const InstanceHit got = intersect_closest(tlas, ray);
        ASSERT_TRUE(same_bits(got, InstanceHit{plain, plain.is_hit() ? 4u : kInvalidId}))
            << describe(ray) << ": " << describe(got);
        ASSERT_EQ(intersect_any(tlas, ray), intersect_any(tree, ray)) << describe(ray);
        hits += plain.is_hit() ? 1 : 0;
    }
    EXPECT_GT(hits, 2000);
}

TEST(TwoLevelBvh, EmptyInstancesAndEmptyListsMiss) {
    const Ray ray = make_ray(glm::vec3(0.0f, 0.0f, -5.0f), glm::vec3(0.0f, 0.0f, 1.0f));
    TwoLevelBvh tlas;
    build_top_level(tlas, {});
    EXPECT_TRUE(tlas.top.empty());
    EXPECT_FALSE(intersect_closest(tlas, ray).is_hit());
    EXPECT_FALSE(intersect_any(tlas, ray));

    const TriangleBvh empty = build_triangle_bvh({}, BuildConfig{});
    const std::vector<Triangle> degenerate = {{glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f, 0.0f, 2.0f)}};
    const TriangleBvh all_degenerate = build_triangle_bvh(degenerate, BuildConfig{});
    ASSERT_TRUE(all_degenerate.bvh.empty());
    std::vector<Instance> instances(2);
    instances[0].blas = &empty;
    instances[1].blas = &all_degenerate;
    instances[1].identity = false;
    instances[1].object = 1;
    build_top_level(tlas, instances);
    EXPECT_TRUE(tlas.top.empty());
    EXPECT_TRUE(tlas.world_boxes[0].is_empty());
    EXPECT_TRUE(tlas.world_boxes[1].is_empty());
    const InstanceHit miss = intersect_closest(tlas, ray);
    EXPECT_FALSE(miss.is_hit());
    EXPECT_TRUE(same_bits(miss, InstanceHit{}));
    EXPECT_FALSE(intersect_any(tlas, ray));

    // Rebuilding with one real instance next to the empty ones finds it.
    const std::vector<Triangle> quad = cube_mesh(-1.0f, 1.0f).triangles();
    const TriangleBvh cube = build_triangle_bvh(quad, BuildConfig{});
    instances.push_back(Instance{&cube, true, glm::mat4(1.0f), glm::mat4(1.0f), 7});
    build_top_level(tlas, instances);
    const InstanceHit hit = intersect_closest(tlas, ray);
    EXPECT_EQ(hit.object, 7u);
    EXPECT_EQ(hit.hit.t, 4.0f);
    EXPECT_TRUE(intersect_any(tlas, ray));
}

TEST(TwoLevelBvh, AnyHitEqualsClosestHitWithinSegments) {
    TwoLevelWorld w = mixed_world();
    w.build();
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int occluded = 0, clear = 0;
    for (Ray ray : random_rays(15, w.world_bounds(), 10000)) {
        ray.tmin = u(rng) * 2.0f;
        ray.tmax = ray.tmin + u(rng) * 6.0f;
        const bool any = intersect_any(w.tlas, ray);
        ASSERT_EQ(any, intersect_closest(w.tlas, ray).is_hit()) << describe(ray);
        (any ? occluded : clear)++;
    }
    EXPECT_GT(occluded, 150);
    EXPECT_GT(clear, 1000);
}

}  // namespace
}  // namespace dynrt::bvh::testing
