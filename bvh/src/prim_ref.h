#pragma once
// Build-time primitive references: the compact records the binned SAH builder bins and
// partitions in place (Wald 2007, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", works on such an array of boxes). Moving a 32-byte record is cheaper than
// chasing an index into the caller's boxes at every level, because each level then streams
// through memory in order.

#include "float4.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <type_traits>

namespace dynrt::bvh::detail {

/// A primitive binned by the centre of its box. 32 bytes: the layout used for triangles.
/// `lo4()` and `hi4()` load the id and `bin_ids` as a fourth lane (as Embree's PrimRef does);
/// the builder never reads that lane.
struct BoxCenterRef {
    glm::vec3 lo;
    std::uint32_t id;
    glm::vec3 hi;
    /// Scratch for the builder: the bins of the node being split, one byte per axis, written
    /// while binning so partitioning need not recompute them.
    std::uint32_t bin_ids;

    Float4 lo4() const { return load4(&lo); }
    Float4 hi4() const { return load4(&hi); }
    Float4 center4() const {
        Float4 sum = lo4() + hi4();
        // Lane 3 holds the sum of the id's and bin_ids' bits, a denormal as a float;
        // multiplying it would cost a microcode assist on every primitive.
        sum[3] = 0.0f;
        return sum * splat4(0.5f);
    }
    /// Same arithmetic as one lane of center4(), so binning and partitioning agree bit for bit.
    float center(int axis) const { return (lo[axis] + hi[axis]) * 0.5f; }
};

/// A primitive binned by a centre the caller chose (build_binned_sah's `centers`). 48 bytes so
/// each vec3 can be loaded as four lanes without reading past the record.
struct ExplicitCenterRef {
    glm::vec3 lo;
    std::uint32_t id;
    glm::vec3 hi;
    std::uint32_t bin_ids;  // as in BoxCenterRef
    glm::vec3 c;
    std::uint32_t unused1;

    Float4 lo4() const { return load4(&lo); }
    Float4 hi4() const { return load4(&hi); }
    Float4 center4() const {
        Float4 v = load4(&c);
        v[3] = 0.0f;  // never feed padding bits (possibly denormal) to arithmetic
        return v;
    }
    float center(int axis) const { return c[axis]; }
};

// Trivial types, so the builder can allocate millions of them without initialising the memory
// twice (first touch happens in the parallel loop that fills them).
static_assert(std::is_trivially_default_constructible_v<BoxCenterRef>);
static_assert(std::is_trivially_default_constructible_v<ExplicitCenterRef>);
static_assert(sizeof(BoxCenterRef) == 32);
static_assert(sizeof(ExplicitCenterRef) == 48);

}  // namespace dynrt::bvh::detail
