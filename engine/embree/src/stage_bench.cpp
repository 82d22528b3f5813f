#include "dynrt/embree/stage_bench.h"

#include "dynrt/embree/embree_backend.h"

#include <nlohmann/json.hpp>

#include <iomanip>
#include <memory>
#include <ostream>

namespace dynrt::embree {

namespace {

/// One backend's renderer and its runs' stage times.
struct Lane {
    std::string name;
    std::unique_ptr<Renderer> renderer;
    std::vector<double> update, camera, shadow, shade, secondary, frame;
    RenderedFrame image;
};

}  // namespace

std::vector<StageRow> bench_stages(const Scene& scene, const Camera& camera,
                                   const RenderOptions& options, int repeat, int warmup) {
    RenderOptions base = options;
    base.hit_buffers = true;  // for the hit agreement
    std::vector<Lane> lanes;
    const auto add_lane = [&](std::string name, const RenderOptions& with) {
        Lane& lane = lanes.emplace_back();
        lane.name = std::move(name);
        lane.renderer = std::make_unique<Renderer>(with);
    };
    add_lane("dynrt", base);
    for (const BuildQuality q : {BuildQuality::low, BuildQuality::medium, BuildQuality::high}) {
        RenderOptions with = base;
        with.backend = [q] { return make_embree_backend(q); };
        add_lane(embree_backend_name(q), with);
    }
    for (int run = 0; run < warmup + repeat; ++run) {
        for (Lane& lane : lanes) {
            lane.renderer->forget_trees();
            lane.renderer->render(scene, camera, 0, lane.image);
            if (run < warmup) continue;
            const FrameStats& s = lane.image.stats;
            const double update = s.backend == "dynrt" ? s.update_ms + s.build_ms : s.backend_load_ms;
            lane.update.push_back(update);
            lane.camera.push_back(s.primary_ms);
            lane.shadow.push_back(s.shadow_ms);
            lane.shade.push_back(s.shade_ms);
            lane.secondary.push_back(s.secondary_ms);
            lane.frame.push_back(update + s.primary_ms + s.shadow_ms + s.shade_ms + s.secondary_ms);
        }
    }
    std::vector<StageRow> rows;
    const RenderedFrame& ours = lanes.front().image;
    for (const Lane& lane : lanes) {
        StageRow row;
        row.backend = lane.name;
        row.update_ms = spread_of(lane.update);
        row.camera_ms = spread_of(lane.camera);
        row.shadow_ms = spread_of(lane.shadow);
        row.shade_ms = spread_of(lane.shade);
        row.secondary_ms = spread_of(lane.secondary);
        row.frame_ms = spread_of(lane.frame);
        row.vs_dynrt = compare_hits(ours.object, ours.prim, lane.image.object, lane.image.prim);
        rows.push_back(row);
    }
    return rows;
}

void print_stage_table(std::ostream& out, const std::vector<StageRow>& rows) {
    out << "whole frames, stage by stage: the same frame, rays and shading through each backend "
           "(trace seam), runs interleaved; update = dynrt's posing and trees / Embree's load "
           "and commit; x = dynrt / backend, medians\n";
    out << std::left << std::setw(15) << "backend" << std::right;
    for (const char* h : {"update ms", "camera ms", "shadow ms", "shade ms", "secondary ms", "frame ms"}) {
        out << std::setw(22) << h;
    }
    for (const char* h : {"upd x", "cam x", "shd x", "sec x", "frame x"}) out << std::setw(8) << h;
    out << std::setw(16) << "hits differ" << '\n';
    const StageRow& dynrt = rows.front();
    for (const StageRow& r : rows) {
        out << std::left << std::setw(15) << r.backend << std::right;
        for (const Spread* s : {&r.update_ms, &r.camera_ms, &r.shadow_ms, &r.shade_ms, &r.secondary_ms, &r.frame_ms}) {
            out << ' ' << std::setw(21) << format_spread(*s);
        }
        out << std::setw(8) << format_ratio(dynrt.update_ms.median, r.update_ms.median)
            << std::setw(8) << format_ratio(dynrt.camera_ms.median, r.camera_ms.median)
            << std::setw(8) << format_ratio(dynrt.shadow_ms.median, r.shadow_ms.median)
            << std::setw(8) << format_ratio(dynrt.secondary_ms.median, r.secondary_ms.median)
            << std::setw(8) << format_ratio(dynrt.frame_ms.median, r.frame_ms.median)
            << std::setw(16)
            << (std::to_string(r.vs_dynrt.object_differs) + " / " + std::to_string(r.vs_dynrt.prim_only_differs))
            << '\n';
    }
    out << "(hits differ: pixels whose hit or object differs / whose triangle alone differs)\n";
}

std::string stages_json(const std::vector<StageRow>& rows) {
    nlohmann::ordered_json doc = nlohmann::ordered_json::array();
    for (const StageRow& r : rows) {
        nlohmann::ordered_json j;
        j["backend"] = r.backend;
        j["update_ms"] = spread_json(r.update_ms);
        j["camera_ms"] = spread_json(r.camera_ms);
        j["shadow_ms"] = spread_json(r.shadow_ms);
        j["shade_ms"] = spread_json(r.shade_ms);
        j["secondary_ms"] = spread_json(r.secondary_ms);
        j["frame_ms"] = spread_json(r.frame_ms);
        j["hit_object_differs"] = r.vs_dynrt.object_differs;
        j["hit_prim_only_differs"] = r.vs_dynrt.prim_only_differs;
        doc.push_back(j);
    }
    return doc.dump(2);
}

}  // namespace dynrt::embree
