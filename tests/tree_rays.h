#pragma once
// Rays about a tree and the bit-for-bit comparison of hits, for the tests that check one tree
// layout against another (compact_leaves_test.cpp, quantized_nodes_test.cpp).

#include "dynrt/bvh/aabb.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/wide_bvh.h"

#include "bvh_test_geometry.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

namespace dynrt::bvh::testing {

/// The same hit bit for bit: t, u, v and primitive.
inline bool same_hit(const Hit& a, const Hit& b) {
    return a.prim == b.prim && std::memcmp(&a.t, &b.t, sizeof a.t) == 0 &&
           std::memcmp(&a.u, &b.u, sizeof a.u) == 0 && std::memcmp(&a.v, &b.v, sizeof a.v) == 0;
}

/// `count` random rays from inside and around `box` (half its size beyond each side): half
/// aimed at a point of the box (they mostly hit), half in any direction; every fifth with a
/// short segment.
inline std::vector<Ray> rays_about(const Aabb& box, int count) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const glm::vec3 pad = 0.5f * box.extent();
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        const glm::vec3 org = random_point(rng, box.lo - pad, box.hi + pad);
        const glm::vec3 dir = i % 2 == 0 ? glm::normalize(random_point(rng, box.lo, box.hi) - org)
                                         : random_direction(rng);
        const float tmax = i % 5 == 0 ? 3.0f * unit(rng) : kInf;
        rays.push_back(make_ray(org, dir, 0.0f, tmax));
    }
    return rays;
}

/// `candidate` gives `reference`'s closest hits bit for bit and its any-hit answers on 3,000
/// rays about the reference's box, enough of which hit (so the comparison compares hits);
/// with `same_work`, after testing the same number of triangles for each ray.
inline void expect_same_hits(const WideBvh& reference, const WideBvh& candidate, bool same_work) {
    const std::vector<Ray> rays = rays_about(reference.root_box, 3000);
    int hits = 0, occluded = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& ray = rays[i];
        WideTraversalStats reference_work, candidate_work;
        const Hit expected = intersect_closest(reference, ray, reference_work);
        const Hit got = intersect_closest(candidate, ray, candidate_work);
        ASSERT_TRUE(same_hit(got, expected)) << "ray " << i << ": prim " << got.prim << " t " << got.t
                                             << ", reference: prim " << expected.prim << " t " << expected.t;
        if (same_work) {
            EXPECT_EQ(candidate_work.triangles_tested, reference_work.triangles_tested) << "ray " << i;
        }
        hits += expected.is_hit() ? 1 : 0;
        const bool any = intersect_any(reference, ray);
        ASSERT_EQ(intersect_any(candidate, ray), any) << "ray " << i;
        occluded += any ? 1 : 0;
    }
    EXPECT_GT(hits, 600);
    EXPECT_GT(occluded, 600);
}

}  // namespace dynrt::bvh::testing
