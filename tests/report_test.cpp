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
                            "leaves", "leaf_tris_mean", "leaf_tris_max", "depth"}) {
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
