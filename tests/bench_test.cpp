#include "dynrt/anim/procedural_motion.h"
#include "dynrt/bvh/wide_bvh.h"
#include "dynrt/bench/bench.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt {
namespace {

TEST(Bench, SpreadIsLowerMedianMinMax) {
    const Spread odd = spread_of({5.0, 1.0, 3.0});
    EXPECT_EQ(odd.median, 3.0);
    EXPECT_EQ(odd.min, 1.0);
    EXPECT_EQ(odd.max, 5.0);
    EXPECT_EQ(spread_of({4.0, 2.0}).median, 2.0);
    EXPECT_THROW(spread_of({}), std::invalid_argument);
}

TEST(Bench, SweepsExpandToTheCrossProductFirstSweepSlowest) {
    bvh::BuildConfig base;
    base.cost_ratio = 3.0f;
    base.leaf_size_max = 5;
    EXPECT_EQ(expand_sweeps({}, base).size(), 1u);
    const std::vector<bvh::BuildConfig> configs =
        expand_sweeps({"cost-ratio=0.1,2", "leaf=1,4,16"}, base);
    ASSERT_EQ(configs.size(), 6u);
    const float ratios[] = {0.1f, 0.1f, 0.1f, 2.0f, 2.0f, 2.0f};
    const unsigned leaves[] = {1, 4, 16, 1, 4, 16};
    for (std::size_t i = 0; i < configs.size(); ++i) {
        EXPECT_EQ(configs[i].cost_ratio, ratios[i]) << i;
        EXPECT_EQ(configs[i].leaf_size_max, leaves[i]) << i;
        EXPECT_EQ(configs[i].bin_count, base.bin_count);
    }
    const std::vector<bvh::BuildConfig> leaf_only = expand_sweeps({"leaf=2"}, base);
    ASSERT_EQ(leaf_only.size(), 1u);
    EXPECT_EQ(leaf_only[0].cost_ratio, 3.0f);  // unswept parameters keep the base value
}

TEST(Bench, MalformedSweepsAreErrors) {
    for (const char* bad : {"cost-ratio", "cost-ratio=", "cost-ratio=0", "cost-ratio=-1",
                            "cost-ratio=x", "cost-ratio=1,,2", "leaf=0", "leaf=2.5", "leaf=2000",
                            "depth=3", "=1"}) {
        EXPECT_THROW(expand_sweeps({bad}, bvh::BuildConfig{}), std::invalid_argument) << bad;
    }
    EXPECT_THROW(expand_sweeps({"leaf=1", "leaf=2"}, bvh::BuildConfig{}), std::invalid_argument);
}

TEST(Bench, CullingSweepIsTakenOutOfTheBuildSweeps) {
    std::vector<std::string> sweeps = {"leaf=2,4", "culling=none,ab,ab+bp,ab+bp+nf,all",
                                       "cost-ratio=1"};
    const std::vector<std::string> items = take_culling_sweep(sweeps);
    EXPECT_EQ(items, (std::vector<std::string>{"none", "ab", "ab+bp", "ab+bp+nf", "all"}));
    EXPECT_EQ(sweeps, (std::vector<std::string>{"leaf=2,4", "cost-ratio=1"}));
    EXPECT_EQ(expand_sweeps(sweeps, bvh::BuildConfig{}).size(), 2u);

    using packet::PacketCulling;
    EXPECT_EQ(parse_culling_item("none"), PacketCulling::none());
    EXPECT_EQ(parse_culling_item("all"), PacketCulling{});
    PacketCulling ab_bp_nf = PacketCulling::none();
    ab_bp_nf.active_bounds = ab_bp_nf.beam_planes = ab_bp_nf.near_far = true;
    EXPECT_EQ(parse_culling_item("ab+bp+nf"), ab_bp_nf);

    std::vector<std::string> none_swept = {"leaf=2"};
    EXPECT_TRUE(take_culling_sweep(none_swept).empty());
    EXPECT_EQ(none_swept.size(), 1u);
}

TEST(Bench, MalformedCullingSweepsAreErrors) {
    for (const char* bad : {"culling=", "culling=ab,,nf", "culling=ab+xy", "culling=ab+",
                            "culling=fast"}) {
        std::vector<std::string> sweeps = {bad};
        EXPECT_THROW(take_culling_sweep(sweeps), std::invalid_argument) << bad;
    }
    std::vector<std::string> twice = {"culling=ab", "culling=nf"};
    EXPECT_THROW(take_culling_sweep(twice), std::invalid_argument);
    // Left in the build sweeps, culling is an unknown build parameter.
    EXPECT_THROW(expand_sweeps({"culling=ab"}, bvh::BuildConfig{}), std::invalid_argument);
}

TEST(Bench, RowsCountPacketWorkPerCullingConfiguration) {
    const Scene scene = load_scene("sphere:2000");
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = options.height = 48;
    options.packet.culling = parse_culling_item("none");
    const BenchRow none = bench_configuration(scene, camera, options, 1, 0);
    options.packet.culling = parse_culling_item("ab+bp+nf");
    const BenchRow culled = bench_configuration(scene, camera, options, 1, 0);
    EXPECT_EQ(none.packet_culling, "none");
    EXPECT_EQ(culled.packet_culling, "ab+bp+nf");
    EXPECT_GT(none.ray_triangle_tests, 0u);
    EXPECT_EQ(none.ray_triangle_culled, 0u);
    EXPECT_GT(culled.ray_triangle_culled, 0u);
    EXPECT_LT(culled.ray_triangle_tests, none.ray_triangle_tests);

    EXPECT_GT(none.nodes_visited, 0u);
    EXPECT_GT(none.rays, 48u * 48u - 1u);

    // The single-ray tracer counts its work too, on the wide tree or the binary one: the wide
    // tree visits fewer nodes per ray and costs fewer bytes per triangle (the binary tree it
    // was collapsed from is not kept).
    options.tracer = Tracer::single;
    const BenchRow single = bench_configuration(scene, camera, options, 1, 0);
    EXPECT_EQ(single.packet_culling, "");
    EXPECT_EQ(single.tree_width, bvh::kWideWidth);
    EXPECT_GT(single.ray_triangle_tests, 0u);
    EXPECT_EQ(single.ray_triangle_culled, 0u);
    options.build.wide = false;
    const BenchRow binary = bench_configuration(scene, camera, options, 1, 0);
    EXPECT_EQ(binary.tree_width, 2);
    EXPECT_EQ(binary.rays, single.rays);
    EXPECT_LT(single.nodes_visited, binary.nodes_visited);
    EXPECT_LT(single.bytes_per_triangle, binary.bytes_per_triangle);
    EXPECT_GT(single.bytes_per_triangle, 36.0);

    const nlohmann::json doc = nlohmann::json::parse(bench_json({none, culled}));
    EXPECT_EQ(doc["rows"][1]["packet_culling"], "ab+bp+nf");
    EXPECT_EQ(doc["rows"][1]["ray_triangle_tests"], culled.ray_triangle_tests);
    EXPECT_EQ(doc["rows"][1]["ray_triangle_culled"], culled.ray_triangle_culled);
    const std::string csv = bench_csv({none, culled});
    EXPECT_NE(csv.find(",packet_culling,ray_triangle_tests,ray_triangle_culled,nodes_visited,"
                       "rays,tree_width,bytes_per_triangle,scene_bytes_per_triangle,renderer_bytes_per_triangle,"
                       "peak_bytes_per_triangle\n"),
              std::string::npos)
        << csv;
    EXPECT_NE(csv.find(",ab+bp+nf," + std::to_string(culled.ray_triangle_tests) + "," +
                       std::to_string(culled.ray_triangle_culled) + "," +
                       std::to_string(culled.nodes_visited) + "," + std::to_string(culled.rays) +
                       ","),
              std::string::npos)
        << csv;
}

TEST(Bench, RowsSummariseRepeatedRendersAndSerialise) {
    const Scene scene = load_scene("sphere:500");
    RenderOptions options;
    options.width = options.height = 24;
    std::vector<BenchRow> rows;
    for (const bvh::BuildConfig& config : expand_sweeps({"cost-ratio=0.1,1"}, options.build)) {
        options.build = config;
        rows.push_back(bench_configuration(scene, default_camera(scene_bounds(scene)), options, 3, 1));
    }
    ASSERT_EQ(rows.size(), 2u);
    for (const BenchRow& row : rows) {
        EXPECT_EQ(row.triangles, scene.triangle_count());
        for (const Spread& s : {row.update_ms, row.build_ms, row.trace_ms, row.primary_ms,
                                row.shadow_ms, row.shade_ms, row.total_ms}) {
            EXPECT_LE(s.min, s.median);
            EXPECT_LE(s.median, s.max);
            EXPECT_GE(s.min, 0.0);
        }
        EXPECT_GT(row.sah_cost, 0.0);
        EXPECT_GT(row.depth, 0u);
    }
    // Cheaper intersections (ratio 0.1) make bigger leaves than ratio 1.
    EXPECT_GT(rows[0].leaf_tris_mean, rows[1].leaf_tris_mean);

    const std::string csv = bench_csv(rows);
    std::istringstream lines(csv);
    std::string header, line;
    std::getline(lines, header);
    EXPECT_EQ(header.rfind("cost_ratio,leaf_size_max,triangles,update_ms_median,update_ms_min,", 0), 0u)
        << header;
    int data_lines = 0;
    while (std::getline(lines, line)) ++data_lines;
    EXPECT_EQ(data_lines, 2);
    EXPECT_EQ(csv.find("0.100000001"), std::string::npos) << "cost ratio printed as a float";

    const nlohmann::json doc = nlohmann::json::parse(bench_json(rows));
    ASSERT_EQ(doc["rows"].size(), 2u);
    EXPECT_EQ(doc["rows"][0]["cost_ratio"], 0.1);
    EXPECT_EQ(doc["rows"][1]["triangles"], scene.triangle_count());
    EXPECT_EQ(doc["rows"][0]["trace_ms"]["median"], rows[0].trace_ms.median);
    EXPECT_EQ(doc["rows"][0]["update_ms"]["median"], rows[0].update_ms.median);

    std::ostringstream table;
    print_bench_table(table, rows);
    EXPECT_NE(table.str().find("trace ms"), std::string::npos);
    EXPECT_NE(table.str().find("update ms"), std::string::npos);
}

TEST(Bench, AdaptiveAndUpdateSweepsAreTakenOutOfTheBuildSweeps) {
    std::vector<std::string> sweeps = {"cost-ratio=1,2", "adaptive=0,0.01,0.5",
                                       "update=rebuild,refit"};
    EXPECT_EQ(take_adaptive_sweep(sweeps), (std::vector<float>{0.0f, 0.01f, 0.5f}));
    EXPECT_EQ(take_update_sweep(sweeps),
              (std::vector<BenchUpdate>{BenchUpdate::rebuild, BenchUpdate::refit}));
    EXPECT_EQ(sweeps, (std::vector<std::string>{"cost-ratio=1,2"}));
    EXPECT_TRUE(take_adaptive_sweep(sweeps).empty());
    EXPECT_TRUE(take_update_sweep(sweeps).empty());
    EXPECT_STREQ(to_string(BenchUpdate::refit), "refit");

    for (const char* bad : {"adaptive=-0.1", "adaptive=inf", "adaptive=1e39", "adaptive=x",
                            "adaptive=0,,1", "adaptive="}) {
        std::vector<std::string> s = {bad};
        EXPECT_THROW(take_adaptive_sweep(s), std::invalid_argument) << bad;
    }
    std::vector<std::string> twice = {"adaptive=0", "adaptive=1"};
    EXPECT_THROW(take_adaptive_sweep(twice), std::invalid_argument);
    std::vector<std::string> unknown = {"update=rebuild,morph"};
    EXPECT_THROW(take_update_sweep(unknown), std::invalid_argument);
}

TEST(Bench, ReuseSweepIsTakenOutOfTheBuildSweeps) {
    std::vector<std::string> sweeps = {"reuse=off,exact,cache:0.25,frameless:8ms", "leaf=4,8"};
    const std::vector<ReuseSettings> reuses = take_reuse_sweep(sweeps);
    ASSERT_EQ(reuses.size(), 4u);
    EXPECT_EQ(reuses[0].mode, PixelReuse::off);
    EXPECT_EQ(reuses[1].mode, PixelReuse::exact);
    EXPECT_EQ(reuses[2].mode, PixelReuse::render_cache);
    EXPECT_EQ(reuses[2].budget_share, 0.25f);
    EXPECT_EQ(reuses[3].mode, PixelReuse::frameless);
    EXPECT_EQ(reuses[3].budget_ms, 8.0);
    EXPECT_EQ(sweeps, (std::vector<std::string>{"leaf=4,8"}));
    EXPECT_TRUE(take_reuse_sweep(sweeps).empty());
    for (const char* bad :
         {"reuse=cache:2", "reuse=exact:0.5", "reuse=sometimes", "reuse=off,,exact", "reuse="}) {
        std::vector<std::string> s = {bad};
        EXPECT_THROW(take_reuse_sweep(s), std::invalid_argument) << bad;
    }
    std::vector<std::string> twice = {"reuse=off", "reuse=exact"};
    EXPECT_THROW(take_reuse_sweep(twice), std::invalid_argument);
}

TEST(Bench, RefitTimesTheMeasuredFrameAfterUpdatingTheFramesBefore) {
    Scene scene = load_scene("sphere:500");
    const std::vector<std::string> wave = {"wave"};
    anim::add_procedural_motions(scene, wave);
    RenderOptions options;
    options.width = 32;
    options.height = 32;
    options.adaptive_tolerance = 0.0f;
    const Camera camera = default_camera(scene_bounds(scene));
    RenderedFrame refitted, rebuilt;
    const BenchRow refit =
        bench_configuration(scene, camera, options, 1, 0, &refitted, 5, BenchUpdate::refit);
    bench_configuration(scene, camera, options, 1, 0, &rebuilt, 5, BenchUpdate::rebuild);
    EXPECT_EQ(refitted.stats.frame, 5);
    EXPECT_EQ(rebuilt.stats.frame, 5);
    EXPECT_EQ(refit.adaptive_tolerance, 0.0f);
    EXPECT_EQ(refitted.object, rebuilt.object);
    EXPECT_THROW(bench_configuration(scene, camera, options, 1, 0, nullptr, -1),
                 std::invalid_argument);
}

}  // namespace
}  // namespace dynrt
