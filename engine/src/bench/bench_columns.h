#pragma once
// The columns of `dynrt bench`'s rows (BenchRow), in output order: the one list the CSV and
// JSON writers (columns.h) and `bench --error`'s rows share.

#include "dynrt/bench/bench.h"

#include <charconv>

namespace dynrt {

/// The float as the double of its shortest decimal form, so a cost ratio of 0.1f is written as
/// 0.1, not 0.100000001.
inline double shortest_decimal(float value) {
    char text[32];
    const auto [end, ec] = std::to_chars(text, text + sizeof(text), value);
    double out = value;
    std::from_chars(text, end, out);
    return out;
}

/// Calls visit(key, value) for every column of a row, in output order: the one list of the
/// columns, shared by the CSV and JSON writers.
struct ForEachBenchColumn {
    template <typename Visit>
    void operator()(const BenchRow& row, Visit&& visit) const {
        visit("cost_ratio", shortest_decimal(row.build.cost_ratio));
        visit("leaf_size_max", row.build.leaf_size_max);
        visit("triangles", row.triangles);
        visit("update_ms", row.update_ms);
        visit("build_ms", row.build_ms);
        visit("trace_ms", row.trace_ms);
        visit("primary_ms", row.primary_ms);
        visit("shadow_ms", row.shadow_ms);
        visit("shade_ms", row.shade_ms);
        visit("secondary_ms", row.secondary_ms);
        visit("total_ms", row.total_ms);
        visit("mrays_per_s", row.mrays_per_s);
        visit("first_ms", row.first_ms);
        visit("sah_cost", row.sah_cost);
        visit("leaf_tris_mean", row.leaf_tris_mean);
        visit("depth", row.depth);
        visit("adaptive_tolerance", shortest_decimal(row.adaptive_tolerance));
        visit("lod_pixels", shortest_decimal(row.lod_pixels));
        visit("packet_culling", row.packet_culling);
        visit("ray_triangle_tests", row.ray_triangle_tests);
        visit("ray_triangle_culled", row.ray_triangle_culled);
        visit("nodes_visited", row.nodes_visited);
        visit("rays", row.rays);
        visit("tree_width", row.tree_width);
        visit("bytes_per_triangle", row.bytes_per_triangle);
        visit("scene_bytes_per_triangle", row.scene_bytes_per_triangle);
        visit("renderer_bytes_per_triangle", row.renderer_bytes_per_triangle);
        visit("peak_bytes_per_triangle", row.peak_bytes_per_triangle);
    }
};

/// The columns of a BenchRow: for_each_column(row, visit).
inline constexpr ForEachBenchColumn for_each_column{};

}  // namespace dynrt
