// `dynrt bench --frames --error`'s driver (engine/include/dynrt/bench/sequence_error_bench.h):
// exact configurations measure no error against the full renders, an approximate one does, and
// the table, JSON and CSV carry the documented fields.

#include "dynrt/bench/sequence_error_bench.h"

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt {
namespace {

Scene waving_sphere() {
    Scene scene = load_scene("sphere:2000");
    const std::vector<std::string> wave{"wave"};
    anim::add_procedural_motions(scene, wave);
    return scene;
}

RenderOptions sequence_bench_options() {
    RenderOptions options;
    // Large enough that adaptive sampling finds cells to interpolate (at 64x64 every cell of
    // the sphere's tiles meets its outline and is traced).
    options.width = 128;
    options.height = 96;
    // A fixed update method: the automatic one decides from measured times.
    options.method = UpdateMethod::threshold;
    return options;
}

RenderOptions with(RenderOptions options, const char* reuse, float adaptive = 0.0f) {
    options.reuse = parse_reuse(reuse);
    options.adaptive_tolerance = adaptive;
    return options;
}

CameraSource fixed_view(const Scene& scene) {
    return CameraSource::fixed(default_camera(scene_bounds(scene)));
}

TEST(SequenceErrorBench, ExactConfigurationsEqualTheFullRenders) {
    const Scene scene = waving_sphere();
    const RenderOptions base = sequence_bench_options();
    const SequenceErrorBench bench = bench_sequence_error(
        scene, fixed_view(scene), base, {with(base, "off"), with(base, "exact")},
        FrameRange{2, 5}, 1, 0);
    EXPECT_EQ(bench.width, 128);
    EXPECT_EQ(bench.height, 96);
    ASSERT_EQ(bench.rows.size(), 2u);
    EXPECT_EQ(bench.reference.label, "off (full render)");
    EXPECT_EQ(bench.rows[0].label, "off");
    EXPECT_EQ(bench.rows[1].label, "exact");
    for (const SequenceErrorRow* row : {&bench.reference, &bench.rows[0], &bench.rows[1]}) {
        ASSERT_EQ(row->frames.size(), 4u) << row->label;
        for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(row->frames[i].frame, 2 + int(i));
        EXPECT_TRUE(std::isinf(row->psnr_db)) << row->label;
        EXPECT_TRUE(std::isinf(row->worst_psnr_db)) << row->label;
        EXPECT_EQ(row->mean_ssim, 1.0) << row->label;
        EXPECT_EQ(row->min_ssim, 1.0) << row->label;
        EXPECT_EQ(row->mean_wrong_share, 0.0) << row->label;
        EXPECT_EQ(row->max_wrong_share, 0.0) << row->label;
        EXPECT_GT(row->total_ms.median, 0.0) << row->label;
        EXPECT_GT(row->speedup, 0.0) << row->label;
    }
    EXPECT_EQ(bench.reference.speedup, 1.0);
}

TEST(SequenceErrorBench, AdaptiveSamplingShowsItsError) {
    const Scene scene = waving_sphere();
    const RenderOptions base = sequence_bench_options();
    const SequenceErrorBench bench = bench_sequence_error(
        scene, fixed_view(scene), base, {with(base, "off", 0.5f)}, FrameRange{0, 2}, 2, 1);
    ASSERT_EQ(bench.rows.size(), 1u);
    const SequenceErrorRow& row = bench.rows[0];
    EXPECT_EQ(row.label, "off + adaptive 0.5");
    ASSERT_EQ(row.frames.size(), 6u);  // 3 frames, 2 runs
    EXPECT_EQ(row.frames[3].frame, 0);
    EXPECT_TRUE(std::isfinite(row.psnr_db));
    EXPECT_TRUE(std::isfinite(row.worst_psnr_db));
    EXPECT_LE(row.worst_psnr_db, row.psnr_db);  // the worst frame is no better than the mean
    EXPECT_LT(row.min_ssim, 1.0);
    EXPECT_LE(row.min_ssim, row.mean_ssim);
    EXPECT_LE(row.mean_wrong_share, row.max_wrong_share);
    // The worst frame is one of the frames, with that frame's figure.
    bool found = false;
    for (const SequenceErrorFrame& f : row.frames) {
        found |= f.frame == row.worst_psnr_frame && f.psnr_db == row.worst_psnr_db;
    }
    EXPECT_TRUE(found);
    // The chart: the full render at error 0, then the configuration at 1 - mean SSIM.
    const std::vector<ErrorPoint> points = sequence_error_points(bench);
    ASSERT_EQ(points.size(), 2u);
    EXPECT_EQ(points[0].label, "off (full render)");
    EXPECT_EQ(points[0].error, 0.0);
    EXPECT_DOUBLE_EQ(points[1].error, 1.0 - row.mean_ssim);
    EXPECT_GT(points[1].error, 0.0);
}

// Levels of detail over a sequence: the full render stays exact (full_render_options turns
// them off), and the row with them is labelled and measured against it.
TEST(SequenceErrorBench, LevelsOfDetailAreMeasuredAgainstExactFullRenders) {
    const Scene scene = load_scene("sphere:20000");
    RenderOptions base = sequence_bench_options();
    base.lod_pixels = 4.0f;
    EXPECT_EQ(full_render_options(base).lod_pixels, 0.0f);
    Camera camera;
    camera.eye = glm::vec3(0.0f, 0.0f, 8.0f);
    const SequenceErrorBench bench =
        bench_sequence_error(scene, CameraSource::fixed(camera), base, {base}, FrameRange{0, 1}, 1, 0);
    ASSERT_EQ(bench.rows.size(), 1u);
    const SequenceErrorRow& row = bench.rows[0];
    EXPECT_EQ(row.label, "exact + lod 4");
    EXPECT_EQ(row.lod_pixels, 4.0f);
    EXPECT_LT(row.mean_ssim, 1.0);
    EXPECT_GT(row.mean_wrong_share, 0.0);
}

TEST(SequenceErrorBench, TableJsonAndCsvHaveTheDocumentedFields) {
    const Scene scene = waving_sphere();
    const RenderOptions base = sequence_bench_options();
    const SequenceErrorBench bench = bench_sequence_error(
        scene, fixed_view(scene), base, {with(base, "exact"), with(base, "off", 0.5f)},
        FrameRange{0, 1}, 1, 0);
    std::ostringstream table;
    print_sequence_error_table(table, bench);
    for (const char* text : {"configuration", "ms/frame", "speedup", "PSNR dB", "worst PSNR (fr)",
                             "mean SSIM", "min SSIM (fr)", "wrong %", "max wrong % (fr)",
                             "traced/frame", "off (full render)", "exact", "off + adaptive 0.5"}) {
        EXPECT_NE(table.str().find(text), std::string::npos) << text << "\n" << table.str();
    }
    const nlohmann::json doc = nlohmann::json::parse(sequence_error_json(bench));
    EXPECT_EQ(doc["frames"]["first"], 0);
    EXPECT_EQ(doc["frames"]["last"], 1);
    EXPECT_EQ(doc["runs"], 1);
    EXPECT_EQ(doc["width"], 128);
    EXPECT_EQ(doc["height"], 96);
    ASSERT_EQ(doc["rows"].size(), 2u);
    EXPECT_EQ(doc["full_render"]["reuse"], "off");
    EXPECT_TRUE(doc["full_render"]["psnr_db"].is_null());  // infinite
    for (const nlohmann::json& row : {doc["full_render"], doc["rows"][0], doc["rows"][1]}) {
        for (const char* key :
             {"label", "reuse", "adaptive_tolerance", "lod_pixels", "total_ms", "mean_ms", "speedup", "psnr_db",
              "worst_psnr_db", "worst_psnr_frame", "mean_ssim", "min_ssim", "min_ssim_frame",
              "mean_wrong_pct", "max_wrong_pct", "max_wrong_frame", "mean_pixels_traced",
              "mean_pixels_reused", "per_frame"}) {
            EXPECT_TRUE(row.contains(key)) << key;
        }
        EXPECT_TRUE(row["total_ms"].contains("median"));
        ASSERT_EQ(row["per_frame"].size(), 2u);
        for (const char* key : {"frame", "total_ms", "psnr_db", "ssim", "wrong_pct",
                                "pixels_traced", "pixels_reused"}) {
            EXPECT_TRUE(row["per_frame"][1].contains(key)) << key;
        }
        EXPECT_EQ(row["per_frame"][1]["frame"], 1);
    }
    EXPECT_EQ(doc["rows"][0]["mean_ssim"], 1.0);
    EXPECT_TRUE(doc["rows"][1]["psnr_db"].is_number());
    const std::string csv = sequence_error_csv(bench);
    EXPECT_EQ(csv.rfind("label,reuse,adaptive_tolerance,lod_pixels,spp,aa_contrast,total_ms_median,", 0), 0u) << csv;
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);  // header, full render, 2 rows
}

TEST(SequenceErrorBench, BadInputIsRefused) {
    const Scene scene = waving_sphere();
    const RenderOptions base = sequence_bench_options();
    const CameraSource view = fixed_view(scene);
    EXPECT_THROW(bench_sequence_error(scene, view, base, {}, FrameRange{0, 1}, 1, 0),
                 std::invalid_argument);
    RenderOptions other_size = base;
    other_size.width = 32;
    EXPECT_THROW(bench_sequence_error(scene, view, base, {other_size}, FrameRange{0, 1}, 1, 0),
                 std::invalid_argument);
    RenderOptions tiny = base;
    tiny.width = 8;
    EXPECT_THROW(bench_sequence_error(scene, view, tiny, {tiny}, FrameRange{0, 1}, 1, 0),
                 std::invalid_argument);
    EXPECT_THROW(bench_sequence_error(scene, view, base, {base}, FrameRange{0, 1}, 0, 0),
                 std::invalid_argument);
    EXPECT_THROW(bench_sequence_error(scene, CameraSource::scene(), base, {base},
                                      FrameRange{0, 1}, 1, 0),
                 std::invalid_argument);
}

}  // namespace
}  // namespace dynrt
