#include "dynrt/engine/report.h"

#include "dynrt/engine/atomic_file.h"
#include "dynrt/engine/spread.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace dynrt {

namespace {

/// Calls visit(key, field) for every report column in schema order: the one list of the keys,
/// shared by the JSON writer, its reader and the summary. `Stats` is FrameStats, const or not.
template <typename Stats, typename Visit>
void for_each_field(Stats& s, Visit&& visit) {
    visit("frame", s.frame);
    visit("triangles", s.triangles);
    visit("degenerate_skipped", s.degenerate_skipped);
    visit("update_ms", s.update_ms);
    visit("build_ms", s.build_ms);
    visit("primary_ms", s.primary_ms);
    visit("shadow_ms", s.shadow_ms);
    visit("shade_ms", s.shade_ms);
    visit("total_ms", s.total_ms);
    visit("primary_rays", s.primary_rays);
    visit("shadow_rays", s.shadow_rays);
    visit("interpolated_pixels", s.interpolated_pixels);
    visit("pixels_traced", s.pixels_traced);
    visit("pixels_shadows_retraced", s.pixels_shadows_retraced);
    visit("pixels_reused", s.pixels_reused);
    visit("pixels_filled", s.pixels_filled);
    visit("samples_per_pixel", s.samples_per_pixel);
    visit("pixels_refined", s.pixels_refined);
    visit("primary_mrays_per_s", s.primary_mrays_per_s);
    visit("shadow_mrays_per_s", s.shadow_mrays_per_s);
    visit("secondary_ms", s.secondary_ms);
    visit("reflection_rays", s.reflection_rays);
    visit("refraction_rays", s.refraction_rays);
    visit("reflection_mrays_per_s", s.reflection_mrays_per_s);
    visit("refraction_mrays_per_s", s.refraction_mrays_per_s);
    visit("secondary_shadow_rays", s.secondary_shadow_rays);
    visit("secondary_shadow_mrays_per_s", s.secondary_shadow_mrays_per_s);
    visit("secondary_packet_rays", s.secondary_packet_rays);
    visit("secondary_single_rays", s.secondary_single_rays);
    visit("shadow_rays_back_side", s.shadow_rays_back_side);
    visit("shadow_rays_shading_side", s.shadow_rays_shading_side);
    visit("shadow_rays_dark_light", s.shadow_rays_dark_light);
    visit("shadow_rays_cache_tested", s.shadow_rays_cache_tested);
    visit("shadow_rays_cache_answered", s.shadow_rays_cache_answered);
    visit("sah_cost", s.sah_cost);
    visit("nodes", s.nodes);
    visit("leaves", s.leaves);
    visit("leaf_tris_mean", s.leaf_tris_mean);
    visit("leaf_tris_max", s.leaf_tris_max);
    visit("depth", s.depth);
    visit("refit_ms", s.refit_ms);
    visit("rebuild_ms", s.rebuild_ms);
    visit("top_level_ms", s.top_level_ms);
    visit("static_objects", s.static_objects);
    visit("static_triangles", s.static_triangles);
    visit("rigid_objects", s.rigid_objects);
    visit("rigid_triangles", s.rigid_triangles);
    visit("deformable_objects", s.deformable_objects);
    visit("deformable_triangles", s.deformable_triangles);
    visit("exploding_objects", s.exploding_objects);
    visit("exploding_triangles", s.exploding_triangles);
    visit("objects_skipped", s.objects_skipped);
    visit("objects_refitted", s.objects_refitted);
    visit("objects_rebuilt", s.objects_rebuilt);
    visit("triangles_refitted", s.triangles_refitted);
    visit("triangles_rebuilt", s.triangles_rebuilt);
    visit("write_ms", s.write_ms);
}

/// Calls visit(key, field) for every key of the report's "memory" object but "largest", in
/// order (the writer's and the reader's one list). `Memory` is MemoryStats, const or not.
template <typename Memory, typename Visit>
void for_each_memory_field(Memory& m, Visit&& visit) {
    visit("scene_bytes", m.scene_bytes);
    visit("tree_bytes", m.tree_bytes);
    visit("build_triangle_bytes", m.build_triangle_bytes);
    visit("renderer_bytes", m.renderer_bytes);
    visit("rss_bytes", m.rss_bytes);
    visit("peak_rss_bytes", m.peak_rss_bytes);
}

/// The same for each of "largest"'s holders (ObjectMemory, const or not).
template <typename Holder, typename Visit>
void for_each_holder_field(Holder& h, Visit&& visit) {
    visit("object", h.object);
    visit("name", h.name);
    visit("triangles", h.triangles);
    visit("scene_bytes", h.scene_bytes);
    visit("tree_bytes", h.tree_bytes);
    visit("build_triangle_bytes", h.build_triangle_bytes);
}

nlohmann::ordered_json frame_json(const FrameStats& s) {
    nlohmann::ordered_json j;
    for_each_field(s, [&](const char* key, const auto& value) { j[key] = value; });
    // Not columns (no median of reasons): the pixel reuse mode and why the frame re-traced what
    // it did, and the list of this frame's tree builds.
    // Reflection and refraction rays per depth (index 0: depth 1); empty without any.
    j["secondary_rays_per_depth"] = s.secondary_rays_per_depth;
    j["secondary_packet_rays_per_depth"] = s.secondary_packet_rays_per_depth;
    j["secondary_mrays_per_s_per_depth"] = s.secondary_mrays_per_s_per_depth;
    if (s.backend != "dynrt") {  // a frame traced by another backend (Renderer::use_backend)
        j["backend"] = s.backend;
        j["backend_load_ms"] = s.backend_load_ms;
    }
    j["reuse_mode"] = s.reuse_mode;
    j["reuse_reason"] = s.reuse_reason;
    j["rebuilds"] = nlohmann::ordered_json::array();
    for (const TreeRebuild& r : s.rebuilds) {
        nlohmann::ordered_json event = {{"object", r.object}, {"name", r.name}, {"reason", rebuild_reason_name(r.reason)}};
        event["builder"] = r.builder;
        if (r.reason == RebuildReason::sah_degraded || r.reason == RebuildReason::refits_cost_more) {
            event["sah_refitted"] = r.sah_refitted;
            event["sah_at_last_build"] = r.sah_at_last_build;
        }
        j["rebuilds"].push_back(event);
    }
    // The automatic update method's choices and the predictions behind them.
    j["choices"] = nlohmann::ordered_json::array();
    for (const TreeChoice& c : s.choices) {
        j["choices"].push_back(
            {{"object", c.object}, {"name", c.name}, {"chosen", c.chosen}, {"why", c.why}});
    }
    // The static group's layout chosen by a memory budget (only on a frame that built it so).
    if (!s.static_layout.empty()) {
        j["static_layout"] = {{"chosen", s.static_layout},
                              {"why", s.static_layout_why},
                              {"predicted_peak_bytes", s.static_layout_predicted_peak}};
    }
    // Memory after the frame (an object of its own: reports written before it lack it).
    nlohmann::ordered_json& memory = j["memory"];
    for_each_memory_field(static_cast<const MemoryStats&>(s), [&](const char* key, const auto& value) { memory[key] = value; });
    memory["largest"] = nlohmann::ordered_json::array();
    for (const ObjectMemory& m : s.largest) {
        nlohmann::ordered_json holder;
        for_each_holder_field(m, [&](const char* key, const auto& value) { holder[key] = value; });
        memory["largest"].push_back(holder);
    }
    // A frame rendered across processes: which one made it and what the distribution cost.
    if (s.rank >= 0) {
        j["rank"] = s.rank;
        if (s.rank_trace_ms.empty()) {
            j["handout_ms"] = s.handout_ms;
        } else {
            j["rank_trace_ms"] = s.rank_trace_ms;
            j["wait_ms"] = s.wait_ms;
            j["gather_ms"] = s.gather_ms;
        }
    }
    return j;
}

FrameStats frame_from_json(const nlohmann::json& j) {
    FrameStats s;
    for_each_field(s, [&](const char* key, auto& value) {
        value = j.at(key).get<std::remove_reference_t<decltype(value)>>();
    });
    j.at("secondary_rays_per_depth").get_to(s.secondary_rays_per_depth);
    j.at("secondary_packet_rays_per_depth").get_to(s.secondary_packet_rays_per_depth);
    j.at("secondary_mrays_per_s_per_depth").get_to(s.secondary_mrays_per_s_per_depth);
    j.at("reuse_mode").get_to(s.reuse_mode);
    j.at("reuse_reason").get_to(s.reuse_reason);
    if (j.contains("memory")) {
        const nlohmann::json& memory = j["memory"];
        for_each_memory_field(static_cast<MemoryStats&>(s), [&](const char* key, auto& value) { memory.at(key).get_to(value); });
        for (const nlohmann::json& holder : memory.at("largest")) {
            ObjectMemory& m = s.largest.emplace_back();
            for_each_holder_field(m, [&](const char* key, auto& value) { holder.at(key).get_to(value); });
        }
    }
    for (const nlohmann::json& event : j.at("rebuilds")) {
        TreeRebuild& r = s.rebuilds.emplace_back();
        event.at("object").get_to(r.object);
        event.at("name").get_to(r.name);
        if (!parse_rebuild_reason(event.at("reason").get<std::string>(), r.reason)) {
            throw std::invalid_argument("unknown rebuild reason " + event.at("reason").dump());
        }
        event.at("builder").get_to(r.builder);
        r.sah_refitted = event.value("sah_refitted", 0.0);
        r.sah_at_last_build = event.value("sah_at_last_build", 0.0);
    }
    for (const nlohmann::json& choice : j.at("choices")) {
        s.choices.push_back(TreeChoice{choice.at("object").get<std::size_t>(),
                                       choice.at("name").get<std::string>(),
                                       choice.at("chosen").get<std::string>(),
                                       choice.at("why").get<std::string>()});
    }
    if (j.contains("static_layout")) {
        const nlohmann::json& layout = j.at("static_layout");
        layout.at("chosen").get_to(s.static_layout);
        layout.at("why").get_to(s.static_layout_why);
        layout.at("predicted_peak_bytes").get_to(s.static_layout_predicted_peak);
    }
    s.backend = j.value("backend", std::string("dynrt"));
    s.backend_load_ms = j.value("backend_load_ms", 0.0);
    s.rank = j.value("rank", -1);
    s.handout_ms = j.value("handout_ms", 0.0);
    s.wait_ms = j.value("wait_ms", 0.0);
    s.gather_ms = j.value("gather_ms", 0.0);
    if (j.contains("rank_trace_ms")) j.at("rank_trace_ms").get_to(s.rank_trace_ms);
    return s;
}

/// Field-wise median, min and max over frames, as JSON objects with the frame keys.
nlohmann::ordered_json summary_json(const std::vector<FrameStats>& frames) {
    nlohmann::ordered_json median, lo, hi;
    if (frames.empty()) return {{"median", median}, {"min", lo}, {"max", hi}};
    std::vector<std::vector<double>> columns;
    std::vector<const char*> keys;
    for (const FrameStats& f : frames) {
        std::size_t c = 0;
        for_each_field(f, [&](const char* key, auto value) {
            if (columns.size() <= c) { columns.emplace_back(); keys.push_back(key); }
            columns[c++].push_back(double(value));
        });
    }
    for (std::size_t c = 0; c < columns.size(); ++c) {
        const Spread s = spread_of(std::move(columns[c]));
        median[keys[c]] = s.median;
        lo[keys[c]] = s.min;
        hi[keys[c]] = s.max;
    }
    return {{"median", median}, {"min", lo}, {"max", hi}};
}

void print_row(std::ostream& out, const std::string& label, double triangles, double update_ms,
               double build_ms, double primary_ms, double shadow_ms, double shade_ms, double total_ms,
               double mrays, double sah, double nodes, double leaf_mean, double leaf_max,
               double depth) {
    out << std::left << std::setw(7) << label << std::right << std::fixed
        << std::setw(10) << std::setprecision(0) << triangles
        << std::setw(9) << std::setprecision(2) << update_ms << std::setw(9) << build_ms
        << std::setw(9) << primary_ms << std::setw(9) << shadow_ms << std::setw(9) << shade_ms
        << std::setw(9) << total_ms << std::setw(9) << mrays
        << std::setw(9) << std::setprecision(1) << sah
        << std::setw(10) << std::setprecision(0) << nodes
        << std::setw(7) << std::setprecision(2) << leaf_mean
        << std::setw(6) << std::setprecision(0) << leaf_max << std::setw(6) << depth << '\n';
}

}  // namespace

std::string frame_report_json(const FrameStats& stats) { return frame_json(stats).dump(); }

bool parse_rebuild_reason(const std::string& name, RebuildReason& reason) {
    for (int r = 0; r <= int(RebuildReason::update_method); ++r) {
        if (name == rebuild_reason_name(RebuildReason(r))) {
            reason = RebuildReason(r);
            return true;
        }
    }
    return false;
}

FrameStats parse_frame_report_json(const std::string& record) {
    try {
        return frame_from_json(nlohmann::json::parse(record));
    } catch (const nlohmann::json::exception& e) {
        throw std::invalid_argument(std::string("not a frame record of the report: ") + e.what());
    }
}

std::string report_json(const RunInfo& run, const std::vector<FrameStats>& frames) {
    nlohmann::ordered_json doc;
    doc["dynrt_report_version"] = 1;
    doc["run"] = {{"scene", run.scene},       {"width", run.width},
                  {"height", run.height},     {"cost_ratio", run.cost_ratio},
                  {"leaf_size_max", run.leaf_size_max}, {"threads", run.threads},
                  {"ignored", run.ignored}, {"startup_ms", run.startup_ms},
                  {"writer_wait_ms", run.writer_wait_ms}};
    // Always written, zeros included, so that tools read one shape whatever the scene.
    doc["run"]["textures"] = {{"count", run.textures.count},
                              {"bytes", run.textures.bytes},
                              {"load_ms", run.textures.load_ms}};
    doc["frames"] = nlohmann::ordered_json::array();
    for (const FrameStats& f : frames) doc["frames"].push_back(frame_json(f));
    doc["summary"] = summary_json(frames);
    return doc.dump(2) + "\n";
}

void write_report(const std::filesystem::path& path, const RunInfo& run,
                  const std::vector<FrameStats>& frames) {
    write_file_atomically(path, report_json(run, frames), "the report");
}

std::string describe_textures(const TextureFigures& textures) {
    std::ostringstream text;
    text << textures.count << (textures.count == 1 ? " image, " : " images, ") << std::fixed;
    const double bytes = double(textures.bytes);
    if (bytes >= 1e6) {
        text << std::setprecision(1) << bytes / 1e6 << " MB";
    } else if (bytes >= 1e3) {
        text << std::setprecision(1) << bytes / 1e3 << " kB";
    } else {
        text << textures.bytes << " B";
    }
    text << ", read in " << std::setprecision(1) << textures.load_ms << " ms";
    return text.str();
}

void print_memory(std::ostream& out, const std::vector<FrameStats>& frames) {
    if (frames.empty()) return;
    // The last frame's holdings, and the peak of the whole run (the resident peak never falls).
    const FrameStats& last = frames.back();
    if (last.renderer_bytes == 0 && last.peak_rss_bytes == 0) return;
    const double triangles = double(std::max<std::size_t>(last.triangles, 1));
    // Whole bytes, but two decimals below 10 (instanced triangles cost a fraction of a byte).
    const auto per = [&](std::size_t bytes) {
        const double value = double(bytes) / triangles;
        std::ostringstream text;
        text << std::fixed << std::setprecision(value < 10.0 ? 2 : 0) << value;
        return text.str();
    };
    std::size_t peak = 0;
    for (const FrameStats& f : frames) peak = std::max(peak, f.peak_rss_bytes);
    out << "memory per triangle: scene " << per(last.scene_bytes) << " B, trees " << per(last.tree_bytes)
        << " B, build triangles " << per(last.build_triangle_bytes) << " B, renderer in all "
        << per(last.renderer_bytes) << " B; resident peak " << per(peak) << " B (" << std::fixed
        << std::setprecision(1) << double(peak) / 1e9 << " GB)\n";
    // The last layout a memory budget chose, its prediction beside the measured peak.
    for (auto f = frames.rbegin(); f != frames.rend(); ++f) {
        if (f->static_layout.empty()) continue;
        out << "memory budget, frame " << f->frame << ": static objects' tree with " << f->static_layout << " ("
            << f->static_layout_why << "; measured peak " << std::setprecision(2) << double(peak) / 1e9 << " GB)\n";
        break;
    }
    if (last.largest.size() < 2) return;  // one holder: the line above says it all
    out << "largest:";
    for (std::size_t i = 0; i < last.largest.size(); ++i) {
        const ObjectMemory& m = last.largest[i];
        out << (i == 0 ? " " : ", ") << m.name << ' ' << std::setprecision(1) << double(m.bytes()) / 1e6 << " MB";
    }
    out << "\n";
}

void print_textures(std::ostream& out, const TextureFigures& textures) {
    if (textures.count == 0) return;
    out << "textures: " << describe_textures(textures) << "\n";
}

void print_writer_summary(std::ostream& out, const std::vector<FrameStats>& frames, double wait_ms) {
    if (frames.empty()) return;
    std::vector<double> ms;
    for (const FrameStats& f : frames) ms.push_back(f.write_ms);
    const Spread s = spread_of(std::move(ms));
    out << std::fixed << std::setprecision(1) << "writing: " << s.median << " ms/frame (max "
        << s.max << ") on the writer thread, beside the render; the render waited "
        << wait_ms << " ms for it in all\n";
}

void print_frame_header(std::ostream& out) {
    out << std::left << std::setw(7) << "frame" << std::right << std::setw(10) << "tris"
        << std::setw(9) << "update" << std::setw(9) << "build" << std::setw(9) << "primary" << std::setw(9) << "shadow"
        << std::setw(9) << "shade" << std::setw(9) << "total" << std::setw(9) << "Mrays/s"
        << std::setw(9) << "SAH" << std::setw(10) << "nodes" << std::setw(7) << "leaf"
        << std::setw(6) << "max" << std::setw(6) << "depth" << '\n'
        << std::left << std::setw(7) << "" << std::right << std::setw(10) << ""
        << std::setw(9) << "ms" << std::setw(9) << "ms" << std::setw(9) << "ms" << std::setw(9) << "ms"
        << std::setw(9) << "ms" << std::setw(9) << "ms" << std::setw(9) << "primary"
        << std::setw(9) << "cost" << std::setw(10) << "" << std::setw(7) << "mean"
        << std::setw(6) << "tris" << std::setw(6) << "" << '\n';
}

void print_frame_row(std::ostream& out, const FrameStats& s) {
    print_row(out, std::to_string(s.frame), double(s.triangles), s.update_ms, s.build_ms, s.primary_ms,
              s.shadow_ms, s.shade_ms, s.total_ms, s.primary_mrays_per_s, s.sah_cost,
              double(s.nodes), s.leaf_tris_mean, double(s.leaf_tris_max), double(s.depth));
}

void print_summary(std::ostream& out, const std::vector<FrameStats>& frames) {
    if (frames.size() < 2) return;
    // The first frame builds every tree (cold): its row stands alone, and the summary rows
    // cover the frames after it (steady state), so that neither hides the other.
    const FrameStats& first = frames.front();
    print_row(out, "first", double(first.triangles), first.update_ms, first.build_ms,
              first.primary_ms, first.shadow_ms, first.shade_ms, first.total_ms,
              first.primary_mrays_per_s, first.sah_cost, double(first.nodes), first.leaf_tris_mean,
              double(first.leaf_tris_max), double(first.depth));
    const std::vector<FrameStats> steady(frames.begin() + 1, frames.end());
    const nlohmann::ordered_json summary = summary_json(steady);
    for (const char* which : {"median", "min", "max"}) {
        const nlohmann::ordered_json& j = summary[which];
        print_row(out, which, j["triangles"], j["update_ms"], j["build_ms"], j["primary_ms"], j["shadow_ms"],
                  j["shade_ms"], j["total_ms"], j["primary_mrays_per_s"], j["sah_cost"],
                  j["nodes"], j["leaf_tris_mean"], j["leaf_tris_max"], j["depth"]);
    }
}

namespace {

/// The median over `frames` of field(frame).
template <class Field>
double median_over(const std::vector<FrameStats>& frames, Field&& field) {
    std::vector<double> values;
    for (const FrameStats& f : frames) values.push_back(double(field(f)));
    return spread_of(std::move(values)).median;
}

}  // namespace

void print_secondary_summary(std::ostream& out, const std::vector<FrameStats>& frames) {
    if (frames.empty()) return;
    const auto median = [&](auto field) { return median_over(frames, field); };
    if (median([](const FrameStats& f) { return f.reflection_rays + f.refraction_rays; }) == 0.0) {
        return;
    }
    const double in_packets = median([](const FrameStats& f) { return f.secondary_packet_rays; });
    const double one_by_one = median([](const FrameStats& f) { return f.secondary_single_rays; });
    out << std::fixed << std::setprecision(0) << "secondary rays (median per frame): reflection "
        << median([](const FrameStats& f) { return f.reflection_rays; }) << " at "
        << std::setprecision(2) << median([](const FrameStats& f) { return f.reflection_mrays_per_s; })
        << " Mrays/s, refraction " << std::setprecision(0)
        << median([](const FrameStats& f) { return f.refraction_rays; }) << " at "
        << std::setprecision(2) << median([](const FrameStats& f) { return f.refraction_mrays_per_s; })
        << " Mrays/s (camera rays "
        << median([](const FrameStats& f) { return f.primary_mrays_per_s; }) << "); "
        << std::setprecision(0) << 100.0 * in_packets / std::max(1.0, in_packets + one_by_one)
        << "% in packets; shadow rays at their hits "
        << median([](const FrameStats& f) { return f.secondary_shadow_rays; }) << " at " << std::setprecision(2)
        << median([](const FrameStats& f) { return f.secondary_shadow_mrays_per_s; }) << " Mrays/s; "
        << std::setprecision(2) << median([](const FrameStats& f) { return f.secondary_ms; })
        << " ms\n  rays per depth:";
    std::size_t depths = 0;
    for (const FrameStats& f : frames) depths = std::max(depths, f.secondary_rays_per_depth.size());
    for (std::size_t k = 0; k < depths; ++k) {
        const double rays = median([&](const FrameStats& f) {
            return k < f.secondary_rays_per_depth.size() ? f.secondary_rays_per_depth[k] : 0;
        });
        const double packed = median([&](const FrameStats& f) {
            return k < f.secondary_packet_rays_per_depth.size() ? f.secondary_packet_rays_per_depth[k] : 0;
        });
        const double rate = median([&](const FrameStats& f) {
            return k < f.secondary_mrays_per_s_per_depth.size() ? f.secondary_mrays_per_s_per_depth[k] : 0.0;
        });
        out << ' ' << (k + 1) << ": " << std::setprecision(0) << rays << " ("
            << 100.0 * packed / std::max(1.0, rays) << "% in packets, " << std::setprecision(2) << rate
            << " Mrays/s)";
    }
    out << '\n';
}

void print_shadow_summary(std::ostream& out, const std::vector<FrameStats>& frames) {
    if (frames.empty()) return;
    const auto median = [&](auto field) { return median_over(frames, field); };
    const double camera = median([](const FrameStats& f) { return f.shadow_rays; });
    const double secondary = median([](const FrameStats& f) { return f.secondary_shadow_rays; });
    const double back = median([](const FrameStats& f) { return f.shadow_rays_back_side; });
    const double shading = median([](const FrameStats& f) { return f.shadow_rays_shading_side; });
    const double dark = median([](const FrameStats& f) { return f.shadow_rays_dark_light; });
    if (camera + secondary + back + shading + dark == 0.0) return;
    const double tested = median([](const FrameStats& f) { return f.shadow_rays_cache_tested; });
    const double answered = median([](const FrameStats& f) { return f.shadow_rays_cache_answered; });
    out << std::fixed << std::setprecision(0) << "shadow rays (median per frame): cast " << camera
        << " at camera hits, " << secondary << " at secondary hits; not cast: " << back
        << " facing away from their light, " << shading << " whose shading normal does, " << dark
        << " where their light is dark (intensity 0, outside a spot's cone, past its range); occluder cache: "
        << answered << " of " << tested << " answered (" << std::setprecision(1)
        << 100.0 * answered / std::max(1.0, tested) << "%)\n";
}

void print_sampling_summary(std::ostream& out, const std::vector<FrameStats>& frames) {
    if (frames.empty()) return;
    const auto median = [&](auto field) { return median_over(frames, field); };
    const double spp = median([](const FrameStats& f) { return f.samples_per_pixel; });
    if (spp <= 1.0) return;
    const double refined = median([](const FrameStats& f) { return f.pixels_refined; });
    const double traced = median([](const FrameStats& f) { return f.pixels_traced; });
    const double rays = median([](const FrameStats& f) { return f.primary_rays; });
    out << std::fixed << std::setprecision(0) << "samples (median per frame): " << spp
        << " per pixel, taken by " << refined << " of " << traced << " pixels (" << std::setprecision(1)
        << 100.0 * refined / std::max(1.0, traced) << "%; the others took one); camera rays "
        << std::setprecision(2) << rays / std::max(1.0, traced) << " per pixel\n";
}

}  // namespace dynrt
