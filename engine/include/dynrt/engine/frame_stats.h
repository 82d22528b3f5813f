#pragma once
// One frame's report. Field names are the JSON keys of the report schema (README.md, "Report"):
// later work adds fields but never renames one.

#include <cstddef>
#include <cstdint>

namespace dynrt {

struct FrameStats {
    int frame = 0;
    std::size_t triangles = 0;           ///< triangles in the scene at this frame
    std::size_t degenerate_skipped = 0;  ///< zero-area triangles kept out of the BVH
    double update_ms = 0;                ///< evaluating the scene at the frame (posing)
    double build_ms = 0;                 ///< BVH construction
    double primary_ms = 0;               ///< tracing camera rays
    double shadow_ms = 0;                ///< tracing shadow rays
    double shade_ms = 0;                 ///< Phong shading and image assembly
    double total_ms = 0;                 ///< the whole frame, wall clock
    std::size_t primary_rays = 0;
    std::size_t shadow_rays = 0;
    double primary_mrays_per_s = 0;
    double shadow_mrays_per_s = 0;
    double sah_cost = 0;                 ///< SAH cost of the tree (bvh::sah_cost)
    std::size_t nodes = 0;
    std::size_t leaves = 0;
    double leaf_tris_mean = 0;
    std::uint32_t leaf_tris_max = 0;
    std::uint32_t depth = 0;
    /// Packet tracer work over primary and shadow rays, counted only when
    /// RenderOptions::count_packet_work is set (0 otherwise): ray/triangle tests performed, and
    /// tests the culling stages avoided (packet::PacketStats has the breakdown).
    std::uint64_t ray_triangle_tests = 0;
    std::uint64_t ray_triangle_culled = 0;
};

}  // namespace dynrt
