// `dynrt bench --error`'s machinery (engine/include/dynrt/bench/error_bench.h): every exact setting (cost
// ratios, packet culling combinations, refit against rebuild on an animated scene) must give
// zero determined hit differences against the exact reference; that is what "accurate" means
// for them. The adaptive sweep is not checked here: it is approximate by design.

#include "dynrt/bench/error_bench.h"

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/bench/bench.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dynrt::reference {
namespace {

RenderOptions small_options() {
    RenderOptions options;
    options.width = 64;
    options.height = 64;
    return options;
}

/// Every subset of the four packet culling stages, as culling sweep items.
std::vector<std::string> all_culling_items() {
    const char* stages[] = {"ab", "bp", "edge", "nf"};
    std::vector<std::string> items;
    for (int mask = 0; mask < 16; ++mask) {
        std::string item;
        for (int s = 0; s < 4; ++s) {
            if (!(mask & (1 << s))) continue;
            if (!item.empty()) item += '+';
            item += stages[s];
        }
        items.push_back(item.empty() ? "none" : item);
    }
    return items;
}

TEST(ErrorBench, CostRatiosAndEveryCullingCombinationShowNoDeterminedHitDifference) {
    const Scene scene = load_scene("sphere:2000");
    const Camera camera = default_camera(scene_bounds(scene));
    const RenderOptions base = small_options();
    const SampledReference reference = sample_reference(scene, camera, base, 0, 1);
    ASSERT_EQ(reference.pixels.size(), 64u * 64u);
    std::vector<ErrorRow> rows;
    for (float cost_ratio : {0.1f, 1.0f}) {
        for (const std::string& culling : all_culling_items()) {
            ErrorConfiguration config{base, BenchUpdate::rebuild};
            config.options.build.cost_ratio = cost_ratio;
            config.options.packet.culling = parse_culling_item(culling);
            rows.push_back(bench_error_row(scene, camera, config, 1, 0, reference));
            const FrameError& e = rows.back().error;
            EXPECT_EQ(e.samples, 64 * 64);
            EXPECT_EQ(e.determined_differs, 0) << "cost " << cost_ratio << ", " << culling;
            EXPECT_LT(e.rmse, 1e-3) << "cost " << cost_ratio << ", " << culling;
        }
    }
    // The single-ray tracer too.
    ErrorConfiguration single{base, BenchUpdate::rebuild};
    single.options.tracer = Tracer::single;
    EXPECT_EQ(bench_error_row(scene, camera, single, 1, 0, reference).error.determined_differs, 0);

    const std::vector<std::string> labels = error_row_labels(rows);
    EXPECT_EQ(labels.front(), "cost 0.1, none");
    EXPECT_EQ(labels.back(), "cost 1, ab+bp+edge+nf");
}

// Levels of detail are approximate: fewer triangles, an error above the exact floor that grows
// with the allowance, and every row labelled with its allowance.
TEST(ErrorBench, LevelsOfDetailTradeTrianglesForError) {
    const Scene scene = load_scene("sphere:20000");
    Camera camera;
    camera.eye = glm::vec3(0.0f, 0.0f, 6.0f);
    const RenderOptions base = small_options();
    const SampledReference reference = sample_reference(scene, camera, base, 0, 1);
    std::vector<ErrorRow> rows;
    for (const float pixels : {0.0f, 1.0f, 16.0f}) {
        ErrorConfiguration config{base, BenchUpdate::rebuild};
        config.options.lod_pixels = pixels;
        rows.push_back(bench_error_row(scene, camera, config, 1, 0, reference));
        EXPECT_EQ(rows.back().timing.lod_pixels, pixels);
    }
    EXPECT_EQ(rows[0].timing.triangles, scene.triangle_count());
    EXPECT_EQ(rows[0].error.determined_differs, 0);
    EXPECT_LT(rows[1].timing.triangles, rows[0].timing.triangles);
    EXPECT_LT(rows[2].timing.triangles, rows[1].timing.triangles);
    EXPECT_GT(rows[1].error.rmse, 10.0 * rows[0].error.rmse);
    EXPECT_GT(rows[2].error.rmse, rows[1].error.rmse);
    const std::vector<std::string> labels = error_row_labels(rows);
    EXPECT_EQ(labels, (std::vector<std::string>{"lod 0", "lod 1", "lod 16"}));
}

TEST(ErrorBench, RefitAndRebuildOfAWavingMeshShowNoDeterminedHitDifference) {
    Scene scene = load_scene("sphere:2000");
    const std::vector<std::string> wave = {"wave"};
    anim::add_procedural_motions(scene, wave);
    const Camera camera = default_camera(scene_bounds(scene));
    const RenderOptions base = small_options();
    const SampledReference reference = sample_reference(scene, camera, base, 6, 1);
    // Frame 0's reference labelled frame 6: a frame-6 render compared with frame 0's hits.
    SampledReference wrong_frame = sample_reference(scene, camera, base, 0, 1);
    wrong_frame.frame = 6;
    std::vector<ErrorRow> rows;
    for (BenchUpdate update : {BenchUpdate::rebuild, BenchUpdate::refit}) {
        rows.push_back(
            bench_error_row(scene, camera, ErrorConfiguration{base, update}, 1, 0, reference));
        EXPECT_EQ(rows.back().frame, 6);
        EXPECT_EQ(rows.back().error.determined_differs, 0) << to_string(update);
        // The wave's phase at frame 6 is 3 rad, nearly opposite to frame 0's: hits differ.
        const ErrorRow wrong =
            bench_error_row(scene, camera, ErrorConfiguration{base, update}, 1, 0, wrong_frame);
        EXPECT_GT(wrong.error.determined_differs, 0) << to_string(update);
    }
    EXPECT_EQ(error_row_labels(rows), (std::vector<std::string>{"rebuild", "refit"}));
}

TEST(ErrorBench, CsvAndJsonCarryTheErrorFieldsAndTheReference) {
    const Scene scene = load_scene("sphere:200");
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions base = small_options();
    base.width = 32;
    base.height = 16;
    const SampledReference reference = sample_reference(scene, camera, base, 0, 4);
    EXPECT_EQ(reference.pixels.size(), 8u * 4u);
    const std::vector<ErrorRow> rows = {
        bench_error_row(scene, camera, ErrorConfiguration{base}, 1, 0, reference)};
    const std::string csv = error_csv(rows);
    EXPECT_NE(csv.find(",update,frame,samples,ambiguous_samples,hit_differs,determined_differs,"
                       "ambiguous_differs,hit_differs_determined_pct,rmse,psnr_db\n"),
              std::string::npos)
        << csv;
    EXPECT_NE(csv.find(",rebuild,0,32,"), std::string::npos) << csv;
    const nlohmann::json doc = nlohmann::json::parse(error_json(rows, reference));
    EXPECT_EQ(doc["rows"][0]["samples"], 32);
    EXPECT_EQ(doc["rows"][0]["determined_differs"], 0);
    EXPECT_TRUE(doc["rows"][0].contains("total_ms"));
    EXPECT_EQ(doc["reference"]["block"], 4);
    EXPECT_EQ(doc["reference"]["samples"], 32);

    RenderOptions other = base;
    other.width = 16;
    EXPECT_THROW(bench_error_row(scene, camera, ErrorConfiguration{other}, 1, 0, reference),
                 std::invalid_argument);
}

}  // namespace
}  // namespace dynrt::reference
