#pragma once
// The automatic update method's memory across frames (update_cost.h holds its rules): the build
// rates measured so far, and what the last frame measured of the whole scene, its trace time
// and its trees' SAH cost. Each object's own history (its last build and refit times, its
// refits' penalty) is an ObjectCosts kept with its tree (object_tree.h); this is the part the
// objects share. SceneAccel owns one and feeds it as frames go by.

#include "dynrt/bvh/aabb.h"
#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/engine/update_cost.h"

#include <algorithm>
#include <cstddef>

namespace dynrt {

class CostMemory {
public:
    const BuildRates& rates() const { return rates_; }

    /// A build of `triangles` triangles with `method` took `ms`: recorded as the object's last
    /// build time of that builder (in `costs`, whose refit penalty starts again), and as the
    /// builder's rate when the tree is large enough to say something about it.
    void note_build(bvh::BuildMethod method, std::size_t triangles, double ms, ObjectCosts& costs) {
        costs.penalty_ms = 0.0;
        costs.last_extra_ms = -1.0;
        // Small trees say little about the rate: their time is mostly fixed costs.
        const double per_triangle_ns = triangles >= 10000 ? ms * 1e6 / double(triangles) : -1.0;
        if (method == bvh::BuildMethod::morton) {
            costs.fast_ms = ms;
            if (per_triangle_ns > 0.0) rates_.fast_ns = per_triangle_ns;
        } else {
            costs.sah_ms = ms;
            if (per_triangle_ns > 0.0) rates_.sah_ns = per_triangle_ns;
        }
    }

    /// The trace time (primary + shadow rays) of the frame just traced: the next frames'
    /// trace times are predicted from it.
    void note_trace_ms(double ms) { trace_ms_ = ms; }

    /// The last update's SAH cost of the two levels as one tree, and its root's half area.
    void note_scene(double sah, double root_area) {
        scene_sah_ = sah;
        root_area_ = root_area;
    }

    /// An object's inputs to a choice: the last frame's trace time, and the object's share of
    /// it (its SAH cost `sah` weighted by the chance of reaching its world box `box`, over the
    /// scene's) and its tree's degradation since its build (`built_sah`), when its tree was
    /// `measured` at the last update.
    TraceCost trace_cost(const bvh::Aabb& box, double sah, double built_sah, bool measured) const {
        TraceCost cost;
        cost.trace_ms = trace_ms_;
        if (!measured || scene_sah_ <= 0.0 || root_area_ <= 0.0 || box.is_empty()) return cost;
        cost.share = std::min(1.0, double(box.half_area()) / root_area_ * sah / scene_sah_);
        if (built_sah > 0.0) cost.degradation = std::max(1.0, sah / built_sah);
        return cost;
    }

private:
    BuildRates rates_;
    double trace_ms_ = 0.0;
    double scene_sah_ = 0.0;
    double root_area_ = 0.0;
};

}  // namespace dynrt
