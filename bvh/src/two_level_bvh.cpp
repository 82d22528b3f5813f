// Two-level BVH: the per-frame top level over instances and its single-ray traversal. Box
// tests are the conservative ones of the triangle BVH (Ize 2013, robust_box_test.h); the
// instances' trees are traced with bvh::intersect_closest / intersect_any unchanged.

#include "dynrt/bvh/two_level_bvh.h"

#include "dynrt/bvh/binned_sah_builder.h"

#include "robust_box_test.h"

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace dynrt::bvh {
namespace {

using detail::BoxRay;
using detail::hit_box;
using detail::kFarScale;
using detail::octant_of;

// ---- World boxes ----------------------------------------------------------------------------
//
// For an identity instance the world box is the tree's root box itself. The top level tests it
// with the world ray, which is the very ray the tree's traversal tests its root with, by the
// same arithmetic (robust_box_test.h); an inner top-level box contains it, and the slab
// distances are monotone in the planes, so the top level never rejects a ray the tree's own
// root test accepts. No padding is needed.
//
// A transformed instance is traced with o' = fl(B o + b), d' = fl(B d), where (B, b) is the
// float world_to_object and (A, a) the float object_to_world (linear part, translation). A hit
// at parameter s means the point p' = o' + s d' lies in the object-space root box R (up to the
// watertight test's own rounding, handled below), so q = A p' + a lies in the exact image of R,
// whose bounding box we compute from R's 8 corners in double. The top level however tests the
// world ray o + s d; it must not miss that box by more than the padding. With e_o, e_d the
// rounding errors of o', d' (|e_o| <= g4 (|B||o| + |b|), |e_d| <= g4 |B||d| componentwise,
// g4 = 4u / (1 - 4u), u = 2^-24: dot products of at most four terms), infinity norms, and
// C = A B - I the residual of the caller's inverse:
//     q - (o + s d) = C o + (A b + a) + A e_o + s (C d + A e_d),
//     |q - (o + s d)| <= E_o |o| + E_c + E_d s|d|,
// E_o = |C| + g4 |A||B|, E_c = |A b + a| + g4 |A||b|, E_d = |C| + g4 |A||B|. And s|d| (the
// world distance from o to about q) is at most |o| + M with M the largest coordinate of the
// world box. So padding the box by
//     (E_o + E_d) |o| + E_c + E_d M
// makes the world ray meet the padded box at s. We double the E terms (second-order terms,
// the double-precision corners) and add a relative 1e-6 (about 17 ulps) times the condition
// |A||B| of the map, on the origin term and on M + |A|(|b| + m) (m: the largest object-space
// coordinate of R): it covers the watertight test accepting a ray a few ulps of |p' - o'|
// outside the triangle, and t differing from the exact s by a few ulps (the padded box's
// entry distance is then lower by far more than that). The constant part is applied to the
// world box once; the part proportional to |o| depends on the ray, so the box tests grow every
// box by origin_pad_rel |o| (top_level_pad), where origin_pad_rel is the largest coefficient
// over the instances. Float boxes are rounded outward, and padding is applied one float step
// outward (grow_box), so it never rounds away.

constexpr double kUnitRoundoffD = 0x1p-24;
constexpr double kGamma4 = 4.0 * kUnitRoundoffD / (1.0 - 4.0 * kUnitRoundoffD);
constexpr double kSlackRel = 1e-6;

/// Infinity norm (largest row sum of absolute values) of the 3x3 linear part of `m`, in
/// double. glm is column-major: m[column][row].
double linear_norm(const glm::mat4& m) {
    double norm = 0.0;
    for (int row = 0; row < 3; ++row) {
        double sum = 0.0;
        for (int col = 0; col < 3; ++col) sum += std::fabs(static_cast<double>(m[col][row]));
        norm = std::max(norm, sum);
    }
    return norm;
}

double max_abs(const glm::dvec3& v) {
    return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

/// `m` (float) applied to point `p` in double: exact products up to double rounding.
glm::dvec3 transform_point_d(const glm::mat4& m, const glm::dvec3& p) {
    glm::dvec3 out;
    for (int row = 0; row < 3; ++row) {
        out[row] = static_cast<double>(m[0][row]) * p.x + static_cast<double>(m[1][row]) * p.y +
                   static_cast<double>(m[2][row]) * p.z + static_cast<double>(m[3][row]);
    }
    return out;
}

/// Largest float <= x, and smallest float >= x.
float round_down(double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) <= x ? f : std::nextafter(f, -std::numeric_limits<float>::infinity());
}
float round_up(double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) >= x ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

/// The world box of a transformed instance with root box `root`, and the coefficient of |o|
/// its padding needs (see above).
Aabb transformed_world_box(const Instance& instance, const Aabb& root, double& origin_coeff) {
    const glm::mat4& to_world = instance.object_to_world;
    const glm::mat4& to_object = instance.world_to_object;
    const double norm_a = linear_norm(to_world);
    const double norm_b = linear_norm(to_object);
    const glm::dvec3 b(to_object[3][0], to_object[3][1], to_object[3][2]);
    const glm::dvec3 a(to_world[3][0], to_world[3][1], to_world[3][2]);
    // C = A B - I and A b + a, in double (exact up to negligible double rounding).
    double norm_c = 0.0;
    glm::dvec3 ab_plus_a = a;
    for (int row = 0; row < 3; ++row) {
        double sum = 0.0;
        for (int col = 0; col < 3; ++col) {
            double c = row == col ? -1.0 : 0.0;
            for (int k = 0; k < 3; ++k) {
                c += static_cast<double>(to_world[k][row]) * static_cast<double>(to_object[col][k]);
            }
            sum += std::fabs(c);
        }
        norm_c = std::max(norm_c, sum);
        for (int k = 0; k < 3; ++k) ab_plus_a[row] += static_cast<double>(to_world[k][row]) * b[k];
    }
    const double condition = norm_a * norm_b;
    const double e_o = norm_c + kGamma4 * condition;
    const double e_d = e_o;
    const double e_c = max_abs(ab_plus_a) + kGamma4 * norm_a * max_abs(b);

    glm::dvec3 lo(std::numeric_limits<double>::infinity());
    glm::dvec3 hi(-std::numeric_limits<double>::infinity());
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p(corner & 1 ? root.hi.x : root.lo.x, corner & 2 ? root.hi.y : root.lo.y,
                           corner & 4 ? root.hi.z : root.lo.z);
        const glm::dvec3 q = transform_point_d(to_world, p);
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    const double world_max = std::max(max_abs(lo), max_abs(hi));
    const double object_max =
        std::max(max_abs(glm::dvec3(root.lo)), max_abs(glm::dvec3(root.hi)));
    const double pad = 2.0 * (e_c + e_d * world_max) +
                       kSlackRel * (world_max + norm_a * (max_abs(b) + object_max));
    origin_coeff = 2.0 * (e_o + e_d) + kSlackRel * std::max(1.0, condition);

    Aabb box;
    box.lo = glm::vec3(round_down(lo.x - pad), round_down(lo.y - pad), round_down(lo.z - pad));
    box.hi = glm::vec3(round_up(hi.x + pad), round_up(hi.y + pad), round_up(hi.z + pad));
    return box;
}

// ---- Traversal ------------------------------------------------------------------------------

constexpr int kStackSize = 2 * static_cast<int>(kMaxDepth);

/// The tie rule across instances: (t, object, prim) lexicographically smallest wins. Before the
/// first hit `best.object` is kInvalidId and `best_t` the ray's tmax, so any hit within the
/// segment wins.
inline bool wins(const Hit& candidate, std::uint32_t object, const InstanceHit& best, float best_t) {
    if (candidate.t != best_t) return candidate.t < best_t;
    if (object != best.object) return object < best.object;
    return candidate.prim < best.hit.prim;
}

/// Front-to-back traversal of the top level, as the triangle BVH's traverse(): the nearer child
/// next, the farther pushed with its entry distance and popped only if that distance is within
/// the current best t (<=, not <: a tie may still win on the object). At a leaf, the instance's
/// tree is traced with tmax = the best t so far.
template <bool kAnyHit, int kOctant>
bool traverse_top(const TwoLevelBvh& tlas, const Ray& ray, InstanceHit& best,
                  TraversalStats* stats) {
    const BvhNode* nodes = tlas.top.nodes.data();
    const BoxRay box_ray(ray);
    const float pad = top_level_pad(tlas, ray.org);
    const float tmin = ray.tmin;
    float tmax = ray.tmax;
    auto hit_node = [&](std::uint32_t index, float& tnear) {
        return hit_box<kOctant>(grow_box(nodes[index].box, pad), box_ray, tmin, tmax, tnear);
    };

    struct Entry {
        std::uint32_t node;
        float tnear;
    };
    Entry stack[kStackSize];
    int top = 0;
    bool found = false;

    float tnear;
    if (!hit_node(0, tnear)) return false;
    std::uint32_t index = 0;
    while (true) {
        const BvhNode& node = nodes[index];
        if (stats) ++stats->nodes_visited;
        if (!node.is_leaf()) {
            const std::uint32_t left = node.first;
            float t_left, t_right;
            const bool hit_left = hit_node(left, t_left);
            const bool hit_right = hit_node(left + 1, t_right);
            if (hit_left && hit_right) {
                const bool right_first = t_right < t_left;
                stack[top++] = Entry{right_first ? left : left + 1, right_first ? t_left : t_right};
                index = right_first ? left + 1 : left;
                continue;
            }
            if (hit_left || hit_right) {
                index = hit_left ? left : left + 1;
                continue;
            }
        } else {
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                const Instance& instance = tlas.instances[tlas.top.prim_ids[k]];
                Ray local = to_object_space(instance, ray);
                if constexpr (kAnyHit) {
                    const bool hit = stats ? bvh::intersect_any(*instance.blas, local, *stats)
                                           : bvh::intersect_any(*instance.blas, local);
                    if (hit) return true;
                } else {
                    local.tmax = tmax;
                    const Hit candidate = stats
                                              ? bvh::intersect_closest(*instance.blas, local, *stats)
                                              : bvh::intersect_closest(*instance.blas, local);
                    if (candidate.is_hit() && wins(candidate, instance.object, best, tmax)) {
                        best.hit = candidate;
                        best.object = instance.object;
                        tmax = candidate.t;
                        found = true;
                    }
                }
            }
        }
        while (true) {
            if (top == 0) return found;
            const Entry e = stack[--top];
            if (e.tnear <= tmax * kFarScale) {
                index = e.node;
                break;
            }
        }
    }
}

template <bool kAnyHit>
bool traverse_top_octant(const TwoLevelBvh& tlas, const Ray& ray, InstanceHit& best,
                         TraversalStats* stats) {
    if (tlas.top.empty()) return false;
    switch (octant_of(ray.dir)) {
        case 0: return traverse_top<kAnyHit, 0>(tlas, ray, best, stats);
        case 1: return traverse_top<kAnyHit, 1>(tlas, ray, best, stats);
        case 2: return traverse_top<kAnyHit, 2>(tlas, ray, best, stats);
        case 3: return traverse_top<kAnyHit, 3>(tlas, ray, best, stats);
        case 4: return traverse_top<kAnyHit, 4>(tlas, ray, best, stats);
        case 5: return traverse_top<kAnyHit, 5>(tlas, ray, best, stats);
        case 6: return traverse_top<kAnyHit, 6>(tlas, ray, best, stats);
        default: return traverse_top<kAnyHit, 7>(tlas, ray, best, stats);
    }
}

}  // namespace

void build_top_level(TwoLevelBvh& tlas, std::vector<Instance> instances) {
    tlas.instances = std::move(instances);
    const std::size_t n = tlas.instances.size();
    tlas.world_boxes.assign(n, Aabb{});
    double origin_coeff_max = 0.0;

    // The builder wants non-empty boxes: instances that can never be hit stay out of the tree.
    std::vector<Aabb> boxes;
    std::vector<glm::vec3> centers;
    std::vector<std::uint32_t> instance_of;
    boxes.reserve(n);
    centers.reserve(n);
    instance_of.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Instance& instance = tlas.instances[i];
        const Aabb root = instance.blas->root_box();
        if (root.is_empty()) continue;
        Aabb box = root;
        if (!instance.identity) {
            double origin_coeff = 0.0;
            box = transformed_world_box(instance, root, origin_coeff);
            origin_coeff_max = std::max(origin_coeff_max, origin_coeff);
        }
        tlas.world_boxes[i] = box;
        boxes.push_back(box);
        centers.push_back(box.center());
        instance_of.push_back(static_cast<std::uint32_t>(i));
    }
    BuildConfig config;
    config.leaf_size_max = 1;
    tlas.top = build_binned_sah(boxes, centers, config);
    for (std::uint32_t& id : tlas.top.prim_ids) id = instance_of[id];
    tlas.origin_pad_rel = round_up(origin_coeff_max);
}

Ray to_object_space(const Instance& instance, const Ray& world) {
    if (instance.identity) return world;
    // Written out rather than glm's operator*, whose evaluation order (and SIMD use) is glm's
    // business: both tracers call this one function, so its bits are the contract.
    const glm::mat4& m = instance.world_to_object;
    const glm::vec3& o = world.org;
    const glm::vec3& d = world.dir;
    Ray local;
    local.org = glm::vec3(m[0][0] * o.x + m[1][0] * o.y + m[2][0] * o.z + m[3][0],
                          m[0][1] * o.x + m[1][1] * o.y + m[2][1] * o.z + m[3][1],
                          m[0][2] * o.x + m[1][2] * o.y + m[2][2] * o.z + m[3][2]);
    local.dir = glm::vec3(m[0][0] * d.x + m[1][0] * d.y + m[2][0] * d.z,
                          m[0][1] * d.x + m[1][1] * d.y + m[2][1] * d.z,
                          m[0][2] * d.x + m[1][2] * d.y + m[2][2] * d.z);
    local.tmin = world.tmin;
    local.tmax = world.tmax;
    return local;
}

float top_level_pad(const TwoLevelBvh& tlas, const glm::vec3& org) {
    if (tlas.origin_pad_rel == 0.0f) return 0.0f;
    const double m = std::max({std::fabs(org.x), std::fabs(org.y), std::fabs(org.z)});
    return round_up(static_cast<double>(tlas.origin_pad_rel) * m);
}

Aabb grow_box(const Aabb& box, float pad) {
    if (pad == 0.0f) return box;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    Aabb out;
    for (int a = 0; a < 3; ++a) {
        out.lo[a] = std::nextafter(box.lo[a] - pad, -kInf);
        out.hi[a] = std::nextafter(box.hi[a] + pad, kInf);
    }
    return out;
}

const Instance* sole_identity_instance(const TwoLevelBvh& tlas) {
    if (tlas.top.nodes.size() != 1 || tlas.top.prim_ids.size() != 1) return nullptr;
    const Instance& instance = tlas.instances[tlas.top.prim_ids[0]];
    return instance.identity ? &instance : nullptr;
}

InstanceHit intersect_closest(const TwoLevelBvh& tlas, const Ray& ray) {
    InstanceHit best;
    if (const Instance* sole = sole_identity_instance(tlas)) {
        best.hit = intersect_closest(*sole->blas, ray);
        if (best.hit.is_hit()) best.object = sole->object;
        return best;
    }
    traverse_top_octant<false>(tlas, ray, best, nullptr);
    return best;
}

bool intersect_any(const TwoLevelBvh& tlas, const Ray& ray) {
    if (const Instance* sole = sole_identity_instance(tlas)) return intersect_any(*sole->blas, ray);
    InstanceHit unused;
    return traverse_top_octant<true>(tlas, ray, unused, nullptr);
}

InstanceHit intersect_closest(const TwoLevelBvh& tlas, const Ray& ray, TraversalStats& stats) {
    InstanceHit best;
    if (const Instance* sole = sole_identity_instance(tlas)) {
        best.hit = intersect_closest(*sole->blas, ray, stats);
        if (best.hit.is_hit()) best.object = sole->object;
        return best;
    }
    traverse_top_octant<false>(tlas, ray, best, &stats);
    return best;
}

bool intersect_any(const TwoLevelBvh& tlas, const Ray& ray, TraversalStats& stats) {
    if (const Instance* sole = sole_identity_instance(tlas)) {
        return intersect_any(*sole->blas, ray, stats);
    }
    InstanceHit unused;
    return traverse_top_octant<true>(tlas, ray, unused, &stats);
}

}  // namespace dynrt::bvh
