#pragma once
// The terms of the surface area heuristic (MacDonald and Booth 1990) shared by the functions
// that sum them: sah_cost and the refits, which must give the same bits for the same tree.

#include "dynrt/bvh/aabb.h"
#include "dynrt/bvh/bvh.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace dynrt::bvh::detail {

/// Half area in double, so a sum over millions of small nodes loses nothing to float rounding.
/// 0 for the empty box.
inline double half_area_d(const Aabb& b) {
    if (b.is_empty()) return 0.0;
    const glm::dvec3 e = glm::dvec3(b.hi) - glm::dvec3(b.lo);
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

/// A wide subtree's SAH terms, unnormalised: `area` weighs each node and leaf by its box's
/// half area, `unit` by 1 (the weights of a root with zero area, see sah_cost).
struct WideSahSum {
    double area = 0.0;
    double unit = 0.0;
};

/// Adds one used slot of a wide node: a leaf of `prims` triangles, or an inner node whose own
/// subtree sums are `below`. Slots are added in slot order, by sah_cost and refit_wide alike.
inline void add_wide_slot(WideSahSum& sum, const Aabb& box, bool leaf, std::uint32_t prims,
                          const WideSahSum& below, const SahCosts& costs) {
    if (leaf) {
        const double weight = static_cast<double>(prims) * costs.intersection;
        sum.area += half_area_d(box) * weight;
        sum.unit += weight;
    } else {
        sum.area += half_area_d(box) * costs.traversal + below.area;
        sum.unit += costs.traversal + below.unit;
    }
}

/// The tree's cost from the root node's sums: the root node's own traversal step plus its
/// slots', over the root's area.
inline double wide_sah_total(const WideSahSum& root_node, const Aabb& root_box,
                             const SahCosts& costs) {
    const double root_area = half_area_d(root_box);
    if (root_area > 0.0) return (root_area * costs.traversal + root_node.area) / root_area;
    return costs.traversal + root_node.unit;
}

}  // namespace dynrt::bvh::detail
