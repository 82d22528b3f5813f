#include "dynrt/engine/report.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>

namespace dynrt {
namespace {

TEST(Report, JsonHasTheDocumentedSchema) {
    FrameStats a;
    a.frame = 0; a.triangles = 10; a.build_ms = 3.0; a.sah_cost = 7.5; a.depth = 4;
    const nlohmann::json doc =
        nlohmann::json::parse(report_json(RunInfo{"sphere:10", 8, 4, 1.0f, 8, 2, {"textures of 2 shapes"}}, {a}));
    ASSERT_TRUE(doc.contains("frames"));
    ASSERT_EQ(doc["frames"].size(), 1u);
    for (const char* key : {"frame", "triangles", "update_ms", "build_ms", "primary_ms",
                            "shadow_ms", "shade_ms", "total_ms", "primary_rays", "shadow_rays",
                            "interpolated_pixels", "pixels_traced", "pixels_shadows_retraced",
                            "pixels_reused", "pixels_filled",
                            "primary_mrays_per_s", "shadow_mrays_per_s", "sah_cost", "nodes",
                            "leaves", "leaf_tris_mean", "leaf_tris_max", "depth", "write_ms"}) {
        EXPECT_TRUE(doc["frames"][0].contains(key)) << key;
        for (const char* which : {"median", "min", "max"}) {
            EXPECT_TRUE(doc["summary"][which].contains(key)) << which << "." << key;
        }
    }
    EXPECT_TRUE(doc["frames"][0].contains("reuse_mode"));
    EXPECT_TRUE(doc["frames"][0].contains("reuse_reason"));
    EXPECT_EQ(doc["frames"][0]["triangles"], 10);
    EXPECT_EQ(doc["frames"][0]["sah_cost"], 7.5);
    EXPECT_EQ(doc["run"]["scene"], "sphere:10");
    EXPECT_EQ(doc["run"]["ignored"], nlohmann::json::array({"textures of 2 shapes"}));
}

TEST(Report, SummaryIsFieldwiseMedianMinMax) {
    std::vector<FrameStats> frames(3);
    const double build[] = {5.0, 1.0, 3.0};
    const std::size_t nodes[] = {7, 9, 8};
    for (int i = 0; i < 3; ++i) {
        frames[i].frame = i;
        frames[i].build_ms = build[i];
        frames[i].nodes = nodes[i];
    }
    const nlohmann::json doc = nlohmann::json::parse(report_json(RunInfo{}, frames));
    EXPECT_EQ(doc["summary"]["median"]["build_ms"], 3.0);
    EXPECT_EQ(doc["summary"]["min"]["build_ms"], 1.0);
    EXPECT_EQ(doc["summary"]["max"]["build_ms"], 5.0);
    EXPECT_EQ(doc["summary"]["median"]["nodes"], 8.0);
    EXPECT_EQ(doc["summary"]["max"]["frame"], 2.0);

    std::ostringstream table;
    print_frame_header(table);
    for (const FrameStats& f : frames) print_frame_row(table, f);
    print_summary(table, frames);
    EXPECT_NE(table.str().find("median"), std::string::npos);
    // The table's summary rows leave the first (cold) frame to its own row: over frames 1 and
    // 2 the max build is 3, not frame 0's 5.
    std::istringstream lines(table.str());
    std::string line, first_row, max_row;
    while (std::getline(lines, line)) {
        if (line.rfind("first", 0) == 0) first_row = line;
        if (line.rfind("max", 0) == 0) max_row = line;
    }
    EXPECT_NE(first_row.find(" 5.00 "), std::string::npos) << table.str();
    EXPECT_EQ(max_row.find(" 5.00 "), std::string::npos) << table.str();
    EXPECT_NE(max_row.find(" 3.00 "), std::string::npos) << table.str();
}

}  // namespace
}  // namespace dynrt

namespace dynrt {
namespace report_record_test {

/// A frame with every kind of field set: columns, lists, reasons, a rebuild and a choice.
FrameStats full_record() {
    FrameStats s;
    s.frame = 17;
    s.triangles = 123456;
    s.build_ms = 1.0 / 3.0;
    s.primary_mrays_per_s = 41.25;
    s.sah_cost = 12.75;
    s.leaf_tris_mean = 2.5f;
    s.pixels_reused = 99;
    s.secondary_rays_per_depth = {5, 3};
    s.secondary_packet_rays_per_depth = {4, 0};
    s.reuse_mode = "exact";
    s.reuse_reason = "camera moved";
    s.rebuilds.push_back(TreeRebuild{2, "cloth", RebuildReason::sah_degraded, 9.5, 7.25, "morton"});
    s.rebuilds.push_back(TreeRebuild{0, "floor", RebuildReason::first_build, 0, 0, "sah"});
    s.choices.push_back(TreeChoice{2, "cloth", "refit", "refits' extra trace 0.1 ms < 3 ms"});
    return s;
}

TEST(ReportRecord, ReadingARecordBackGivesItsTextAgain) {
    FrameStats s = full_record();
    const std::string once = frame_report_json(s);
    const FrameStats back = parse_frame_report_json(once);
    EXPECT_EQ(frame_report_json(back), once);
    EXPECT_EQ(back.frame, 17);
    EXPECT_EQ(back.build_ms, 1.0 / 3.0);
    EXPECT_EQ(back.rebuilds.at(0).reason, RebuildReason::sah_degraded);
    EXPECT_EQ(back.rank, -1);
    EXPECT_EQ(once.find("\"rank\""), std::string::npos);  // one process: no rank in the report
    // A frame of a render across processes keeps its rank and distribution figures.
    s.rank = 2;
    s.handout_ms = 0.125;
    const FrameStats handed = parse_frame_report_json(frame_report_json(s));
    EXPECT_EQ(handed.rank, 2);
    EXPECT_EQ(handed.handout_ms, 0.125);
    s.rank = 0;
    s.rank_trace_ms = {10.5, 11.0, 9.75};
    s.wait_ms = 2.25;
    s.gather_ms = 1.5;
    const FrameStats gathered = parse_frame_report_json(frame_report_json(s));
    EXPECT_EQ(gathered.rank_trace_ms, s.rank_trace_ms);
    EXPECT_EQ(gathered.gather_ms, 1.5);
    EXPECT_EQ(gathered.wait_ms, 2.25);
    EXPECT_EQ(frame_report_json(gathered), frame_report_json(s));
}

TEST(ReportRecord, TheWritersTimeAndTheRunsStartUpAreKept) {
    FrameStats s = full_record();
    s.write_ms = 12.625;
    const FrameStats back = parse_frame_report_json(frame_report_json(s));
    EXPECT_EQ(back.write_ms, 12.625);
    RunInfo run{"sphere:10", 8, 4, 1.0f, 8, 2, {}};
    run.startup_ms = 250.5;
    run.writer_wait_ms = 3.25;
    const nlohmann::json doc = nlohmann::json::parse(report_json(run, {s}));
    EXPECT_EQ(doc["run"]["startup_ms"], 250.5);
    EXPECT_EQ(doc["run"]["writer_wait_ms"], 3.25);
    EXPECT_EQ(doc["frames"][0]["write_ms"], 12.625);
    std::ostringstream line;
    print_writer_summary(line, {s}, 3.25);
    EXPECT_EQ(line.str(), "writing: 12.6 ms/frame (max 12.6) on the writer thread, beside the "
                          "render; the render waited 3.2 ms for it in all\n");
}

TEST(ReportRecord, WhatIsNotARecordIsRefused) {
    for (const char* text : {"", "{\"frame\": 1", "[]", "{\"frame\": 1}"}) {
        EXPECT_THROW(parse_frame_report_json(text), std::invalid_argument) << text;
    }
    std::string torn = frame_report_json(full_record());
    torn.resize(torn.size() / 2);
    EXPECT_THROW(parse_frame_report_json(torn), std::invalid_argument);
}

}  // namespace report_record_test
}  // namespace dynrt
