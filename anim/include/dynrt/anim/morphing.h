#pragma once
// Morph target evaluation (glTF 2.0 section 3.7.2.2).

#include "dynrt/scene/morph_targets.h"

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

}  // namespace dynrt::anim
