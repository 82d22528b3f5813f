// The Embree rows as a table beside dynrt's row, and as JSON (embree_bench.h).

#include "dynrt/embree/embree_bench.h"

#include "dynrt/bench/columns.h"
#include "dynrt/engine/spread.h"

#include <nlohmann/json.hpp>

#include <iomanip>
#include <ostream>

namespace dynrt::embree {

namespace {

/// The JSON columns of an Embree row, in output order.
struct ForEachEmbreeColumn {
    template <typename Visit>
    void operator()(const EmbreeRow& r, Visit&& visit) const {
        visit("quality", std::string(quality_name(r.quality)));
        visit("build_ms", r.build_ms);
        visit("intersect1_ms", r.intersect1_ms);
        visit("intersect16_ms", r.intersect16_ms);
        visit("occluded1_ms", r.occluded1_ms);
        visit("occluded16_ms", r.occluded16_ms);
        visit("mrays_per_s", r.mrays_per_s);
        visit("shadow_rays", r.shadow_rays);
        visit("hit_object_differs", r.vs_dynrt.object_differs);
        visit("hit_prim_only_differs", r.vs_dynrt.prim_only_differs);
        visit("packet_vs_single_differs", r.packet_vs_single_differs);
    }
};
constexpr ForEachEmbreeColumn for_each_embree_column{};

}  // namespace

void print_embree_table(std::ostream& out, const std::vector<EmbreeRow>& rows,
                        const BenchRow& dynrt_row) {
    out << "embree 3 (build = rtcCommitScene only, buffer upload excluded; 16-ray packets of 4x4 "
           "pixels with a coherent context; Mrays/s = primary + shadow rays over intersect16 + "
           "occluded16; ratios dynrt/embree of medians, dynrt row 1: build "
        << std::fixed << std::setprecision(2) << dynrt_row.build_ms.median << " ms, primary "
        << dynrt_row.primary_ms.median << " ms, shadow " << dynrt_row.shadow_ms.median
        << " ms)\n";
    out << std::left << std::setw(8) << "quality" << std::right << std::setw(22) << "build ms"
        << std::setw(22) << "intersect1 ms" << std::setw(22) << "intersect16 ms"
        << std::setw(22) << "occluded1 ms" << std::setw(22) << "occluded16 ms" << std::setw(22)
        << "Mrays/s" << std::setw(9) << "build x" << std::setw(9) << "i1 x" << std::setw(9)
        << "i16 x" << std::setw(9) << "o1 x" << std::setw(9) << "o16 x" << '\n';
    for (const EmbreeRow& r : rows) {
        out << std::left << std::setw(8) << quality_name(r.quality) << std::right;
        for (const Spread* spread : {&r.build_ms, &r.intersect1_ms, &r.intersect16_ms,
                                     &r.occluded1_ms, &r.occluded16_ms, &r.mrays_per_s}) {
            out << ' ' << std::setw(21) << format_spread(*spread);
        }
        out << std::setw(9) << format_ratio(dynrt_row.build_ms.median, r.build_ms.median)
            << std::setw(9) << format_ratio(dynrt_row.primary_ms.median, r.intersect1_ms.median)
            << std::setw(9) << format_ratio(dynrt_row.primary_ms.median, r.intersect16_ms.median)
            << std::setw(9) << format_ratio(dynrt_row.shadow_ms.median, r.occluded1_ms.median)
            << std::setw(9) << format_ratio(dynrt_row.shadow_ms.median, r.occluded16_ms.median)
            << '\n';
    }
    for (const EmbreeRow& r : rows) {
        out << "hit agreement (" << quality_name(r.quality) << "): " << r.vs_dynrt.object_differs
            << " pixels differ in hit/object, " << r.vs_dynrt.prim_only_differs
            << " only in primitive; packets vs single rays: " << r.packet_vs_single_differs
            << " differ\n";
    }
}

std::string embree_json(const std::vector<EmbreeRow>& rows) {
    nlohmann::ordered_json array = nlohmann::ordered_json::array();
    for (const EmbreeRow& r : rows) {
        nlohmann::ordered_json j;
        bench_columns::json_fields(j, r, for_each_embree_column);
        array.push_back(j);
    }
    return array.dump(2);
}


void print_secondary_table(std::ostream& out, const SecondaryComparison& c) {
    const double rays = double(c.reflection_rays + c.refraction_rays);
    out << "secondary rays of frame 0: " << c.reflection_rays << " reflection + "
        << c.refraction_rays << " refraction in " << c.packets
        << " packets, the same rays replayed by each (Embree: high-quality tree; Mrays/s "
           "from medians; camera rays in the render: "
        << std::fixed << std::setprecision(2) << c.primary_mrays_per_s << " Mrays/s)\n";
    out << std::left << std::setw(26) << "tracer" << std::right << std::setw(22) << "ms"
        << std::setw(10) << "Mrays/s" << std::setw(12) << "dynrt x" << '\n';
    const auto row = [&](const char* name, const Spread& ms) {
        out << std::left << std::setw(26) << name << std::right << ' ' << std::setw(21)
            << format_spread(ms) << std::setw(10) << std::setprecision(2)
            << (ms.median > 0 ? rays / (ms.median * 1e3) : 0.0) << std::setw(12)
            << format_ratio(ms.median, c.dynrt_ms.median) << '\n';
    };
    row("dynrt (as rendered)", c.dynrt_ms);
    row("embree rtcIntersect16 coh", c.embree16_coherent_ms);
    row("embree rtcIntersect16", c.embree16_ms);
    row("embree rtcIntersect1", c.embree1_ms);
    out << "hit agreement: " << c.vs_dynrt.object_differs << " rays differ in hit/object, "
        << c.vs_dynrt.prim_only_differs << " only in primitive\n";
}

std::string secondary_json(const SecondaryComparison& c) {
    nlohmann::ordered_json j;
    j["reflection_rays"] = c.reflection_rays;
    j["refraction_rays"] = c.refraction_rays;
    j["packets"] = c.packets;
    j["primary_mrays_per_s"] = c.primary_mrays_per_s;
    for (const auto& [key, spread] : {std::pair{"dynrt_ms", &c.dynrt_ms},
                                      std::pair{"embree16_coherent_ms", &c.embree16_coherent_ms},
                                      std::pair{"embree16_ms", &c.embree16_ms},
                                      std::pair{"embree1_ms", &c.embree1_ms}}) {
        j[key] = {{"median", spread->median}, {"min", spread->min}, {"max", spread->max}};
    }
    j["hit_object_differs"] = c.vs_dynrt.object_differs;
    j["hit_prim_only_differs"] = c.vs_dynrt.prim_only_differs;
    return j.dump(2);
}

}  // namespace dynrt::embree
