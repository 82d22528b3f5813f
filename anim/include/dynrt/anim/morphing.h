#pragma once
// Morph target evaluation (glTF 2.0 section 3.7.2.2).

#include "dynrt/scene/morph_targets.h"
#include "dynrt/scene/vertex_normals.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <span>

namespace dynrt::anim {

/// base_v + sum_i weights[i] * delta_i,v in double, targets in order. Preconditions:
/// v < base_positions.size(), weights.size() == position_deltas.size().
inline glm::dvec3 morphed_position(const MorphTargets& morph, std::span<const double> weights, std::size_t v) {
    glm::dvec3 p(morph.base_positions[v]);
    for (std::size_t i = 0; i < weights.size(); ++i) {
        if (weights[i] != 0.0) p += weights[i] * glm::dvec3(morph.position_deltas[i][v]);
    }
    return p;
}

/// normalize(base_normal_v + sum_i weights[i] * normal_delta_i,v) in double (0 when that sum
/// is 0). Preconditions: morph.normal_deltas is not empty, v < base_normals.size(),
/// weights.size() == normal_deltas.size().
inline glm::dvec3 morphed_normal(const MorphTargets& morph, std::span<const double> weights, std::size_t v) {
    glm::dvec3 n(morph.base_normals[v]);
    for (std::size_t i = 0; i < weights.size(); ++i) {
        if (weights[i] != 0.0) n += weights[i] * glm::dvec3(morph.normal_deltas[i][v]);
    }
    return normalize_or_zero(n);
}

}  // namespace dynrt::anim
