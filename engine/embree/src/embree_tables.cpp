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


}  // namespace dynrt::embree
