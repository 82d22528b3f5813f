#pragma once
// How the packet tracer runs: its culling stages, SIMD width and switching thresholds, and its
// work counters. Free of the SIMD wrapper (simd.h), whose types depend on the instruction set
// the build targets, so that the engine's public headers can carry these settings.

#include <cstdint>
#include <string>
#include <string_view>

namespace dynrt::packet {

/// The SIMD width this build's kernels use (simd::kNativeLanes: 16 with AVX-512, 8 with AVX2,
/// 4 with SSE or NEON, 1 without).
int native_simd_lanes();

/// Switches for the packet tracer's culling stages. Each only skips work; results never depend
/// on them. All on by default. Spelled on the command line as a list of the short names:
/// "ab,bp,edge,nf", "all" or "none". The three triangle stages (bp, edge, nf) apply to packets
/// whose rays share their origin (and the watertight test's axis order), such as camera
/// packets; other packets (shadow rays from many points, incoherent rays) rely on ab and on the
/// interval-arithmetic early miss.
struct PacketCulling {
    /// "ab": at a leaf, test only the rays of the active range whose own box test hits the leaf
    /// (per-ray masks); off, every active ray of the packet is tested at every leaf reached.
    bool active_bounds = true;
    /// "bp": skip a triangle when it lies outside one of the four planes bounding the rays
    /// tested at the leaf (their beam), for every such ray.
    bool beam_planes = true;
    /// "edge": skip a triangle when all those rays pass outside one of its edges and inside
    /// another.
    bool triangle_edges = true;
    /// "nf": skip a triangle lying entirely beyond the farthest current hit (or tmax) of those
    /// rays, or before their nearest tmin.
    bool near_far = true;

    static PacketCulling none() { return PacketCulling{false, false, false, false}; }
    /// Parses a comma-separated list of ab, bp, edge, nf, or "all" / "none". Throws
    /// std::invalid_argument naming an unknown item.
    static PacketCulling parse(std::string_view list);
    /// The list form ("ab,bp,edge,nf", "none" when all are off); parse(to_string()) round-trips.
    std::string to_string() const;
    bool operator==(const PacketCulling&) const = default;
};

/// Work counters of packet traces, for tables of culling combinations and tuning. "Tests" are
/// ray/triangle pairs (one lane against one triangle); a culled pair is one a stage removed
/// before the SIMD test, counted at the first stage that removed it.
struct PacketStats {
    std::uint64_t packets = 0;
    /// Node visits (one per node popped for the packet, whatever the outcome), and of those
    /// the leaves whose triangles were tested.
    std::uint64_t nodes_visited = 0;
    std::uint64_t leaves_visited = 0;
    /// Decided by the first active ray alone (its box test hit), or by the beam (no ray can hit).
    std::uint64_t early_hits = 0;
    std::uint64_t early_misses = 0;
    /// Ray/box tests done lane by lane (SIMD lanes, counting only active ones).
    std::uint64_t ray_box_tests = 0;
    /// Ray/triangle pairs tested by the SIMD watertight test.
    std::uint64_t ray_triangle_tests = 0;
    /// Pairs not tested, per stage: active rays outside the leaf's active range or mask (ab),
    /// triangles outside the beam (bp), outside an edge for all rays (edge), beyond the near/far
    /// bounds (nf).
    std::uint64_t culled_active_bounds = 0;
    std::uint64_t culled_beam_planes = 0;
    std::uint64_t culled_triangle_edges = 0;
    std::uint64_t culled_near_far = 0;

    PacketStats& operator+=(const PacketStats& o);
};

/// How to trace: the culling stages, the SIMD width and two speed knobs. Results never depend
/// on any of them; only speed (and PacketStats) do.
struct PacketConfig {
    PacketCulling culling;
    /// Lanes per SIMD step: native_simd_lanes() or 1 (the scalar build of the same kernels).
    /// Other values throw std::invalid_argument.
    int lanes = native_simd_lanes();
    /// When the box test narrows the rays reaching a node to at most two SIMD steps holding at
    /// most this many hitting rays, those rays traverse the subtree one by one (Embree's
    /// "hybrid" traversal: per node, a single ray costs far less than the packet machinery),
    /// on the wide tree through its single-ray traversal. 0 never switches.
    int single_ray_max = 2;
    /// The leaf culling stages (bp, edge, nf) run only when at least this many SIMD steps of
    /// rays are to be tested at the leaf: culling one triangle costs about as much as testing
    /// a few steps, so for a handful of rays it does not pay. 1 always runs them.
    int cull_min_steps = 6;
};

}  // namespace dynrt::packet
