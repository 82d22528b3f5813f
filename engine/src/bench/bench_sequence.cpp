#include "dynrt/bench/bench_sequence.h"

#include "dynrt/engine/report.h"
#include "dynrt/engine/stopwatch.h"
#include "dynrt/bench/columns.h"

#include <nlohmann/json.hpp>

#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace dynrt {

namespace {

/// Per-frame samples of one tracer.
struct Samples {
    std::vector<double> update, build, primary, shadow, trace, frame, shade, secondary, total;
    HitAgreement agreement;

    void add(const SequenceFrameTimes& t) {
        update.push_back(t.update_ms);
        build.push_back(t.build_ms);
        primary.push_back(t.primary_ms);
        shadow.push_back(t.shadow_ms);
        trace.push_back(t.primary_ms + t.shadow_ms);
        frame.push_back(t.update_ms + t.build_ms + t.primary_ms + t.shadow_ms);
        shade.push_back(t.shade_ms);
        secondary.push_back(t.secondary_ms);
        total.push_back(frame.back() + t.shade_ms + t.secondary_ms);
        agreement.object_differs += t.vs_dynrt.object_differs;
        agreement.prim_only_differs += t.vs_dynrt.prim_only_differs;
    }

    SequenceRow row(std::string tracer) const {
        SequenceRow r;
        r.tracer = std::move(tracer);
        r.update_ms = spread_of(update);
        r.build_ms = spread_of(build);
        r.trace_ms = spread_of(trace);
        r.primary_ms = spread_of(primary);
        r.shadow_ms = spread_of(shadow);
        r.frame_ms = spread_of(frame);
        r.shade_ms = spread_of(shade);
        r.secondary_ms = spread_of(secondary);
        r.total_ms = spread_of(total);
        r.vs_dynrt = agreement;
        return r;
    }
};

/// The JSON columns of a sequence row, in output order.
struct ForEachSequenceColumn {
    template <typename Visit>
    void operator()(const SequenceRow& r, Visit&& visit) const {
        visit("tracer", r.tracer);
        visit("update_ms", r.update_ms);
        visit("build_ms", r.build_ms);
        visit("trace_ms", r.trace_ms);
        visit("primary_ms", r.primary_ms);
        visit("shadow_ms", r.shadow_ms);
        visit("frame_ms", r.frame_ms);
        visit("shade_ms", r.shade_ms);
        visit("secondary_ms", r.secondary_ms);
        visit("total_ms", r.total_ms);
        visit("hit_object_differs", r.vs_dynrt.object_differs);
        visit("hit_prim_only_differs", r.vs_dynrt.prim_only_differs);
    }
};
constexpr ForEachSequenceColumn for_each_sequence_column{};

}  // namespace

SequenceBench bench_sequence(const Scene& scene, const CameraSource& view,
                             const RenderOptions& options, FrameRange range, int runs, int warmup,
                             const std::vector<std::unique_ptr<SequenceTracer>>& others) {
    if (runs < 1) throw std::invalid_argument("bench: repeat must be at least 1");
    if (view.from_scene && scene.cameras.empty()) {
        throw std::invalid_argument("bench: " + scene.source + " has no camera of its own to follow");
    }
    Renderer renderer(options);
    RenderedFrame frame;
    // The renderer poses frame f once and reads the scene's camera, if used, from that pose.
    const auto render = [&](int f) { return renderer.render(scene, f, view, frame); };
    SequenceBench bench;
    // The start-up frame reads the scene's textures, which the runs keep (forget_trees): a
    // render reads them once, at start-up, not once per sequence.
    const Stopwatch first_clock;
    render(range.first);
    bench.first_ms = first_clock.elapsed_ms();
    bench.textures = renderer.texture_figures();
    for (int i = 0; i < warmup; ++i) {
        renderer.forget_trees();
        render(range.first);
    }
    Samples dynrt;
    std::vector<Samples> other(others.size());
    for (int run = 0; run < runs; ++run) {
        // A new sequence: empty trees, so frame `first` pays its builds as it would in an
        // application. (Other tracers are created per bench and also start empty once.)
        renderer.forget_trees();
        bench.frames.clear();
        for (int f = range.first; f <= range.last; ++f) {
            const Camera c = render(f);
            const FrameStats& s = frame.stats;
            dynrt.add(SequenceFrameTimes{s.update_ms, s.build_ms, s.primary_ms, s.shadow_ms, s.shade_ms, {},
                                         s.secondary_ms});
            bench.frames.push_back(s);
            for (std::size_t k = 0; k < others.size(); ++k) other[k].add(others[k]->frame(f, c, frame));
        }
    }
    bench.rows.push_back(dynrt.row("dynrt"));
    for (std::size_t k = 0; k < others.size(); ++k) bench.rows.push_back(other[k].row(others[k]->name()));
    return bench;
}

void print_sequence_table(std::ostream& out, const SequenceBench& bench) {
    // The stages side by side (update, build, primary and shadow rays), then their sum, the
    // figure compared between tracers.
    out << std::left << std::setw(14) << "tracer" << std::right << std::setw(24) << "update ms"
        << std::setw(24) << "build/refit ms" << std::setw(24) << "primary ms" << std::setw(24)
        << "shadow ms" << std::setw(26) << "frame ms (no shading)" << std::setw(12)
        << "dynrt/this" << std::setw(24) << "shade ms" << std::setw(24) << "secondary ms" << std::setw(24)
        << "total ms" << std::setw(8) << "fps" << '\n';
    const double dynrt_frame = bench.rows.empty() ? 0.0 : bench.rows.front().frame_ms.median;
    for (const SequenceRow& r : bench.rows) {
        out << std::left << std::setw(14) << r.tracer << std::right << std::setw(24)
            << format_spread(r.update_ms) << std::setw(24) << format_spread(r.build_ms)
            << std::setw(24) << format_spread(r.primary_ms) << std::setw(24)
            << format_spread(r.shadow_ms) << std::setw(26)
            << format_spread(r.frame_ms) << std::setw(12) << format_ratio(dynrt_frame, r.frame_ms.median);
        // A tracer that does not shade (Embree's rows time rays only) shows no shading figures.
        if (r.shade_ms.max > 0.0) {
            // fps: of the median whole frame.
            std::ostringstream fps;
            fps << std::fixed << std::setprecision(2) << (r.total_ms.median > 0.0 ? 1000.0 / r.total_ms.median : 0.0);
            out << std::setw(24) << format_spread(r.shade_ms) << std::setw(24) << format_spread(r.secondary_ms)
                << std::setw(24) << format_spread(r.total_ms) << std::setw(8) << fps.str();
        } else {
            out << std::setw(24) << "-" << std::setw(24) << "-" << std::setw(24) << "-" << std::setw(8) << "-";
        }
        out << '\n';
    }
    for (std::size_t k = 1; k < bench.rows.size(); ++k) {
        const SequenceRow& r = bench.rows[k];
        out << "hit agreement (" << r.tracer << ", all frames): " << r.vs_dynrt.object_differs
            << " pixels differ in hit/object, " << r.vs_dynrt.prim_only_differs
            << " only in primitive\n";
    }
}

std::string sequence_json(const SequenceBench& bench) {
    nlohmann::ordered_json doc;
    doc["sequence"] = nlohmann::ordered_json::array();
    for (const SequenceRow& r : bench.rows) {
        nlohmann::ordered_json j;
        bench_columns::json_fields(j, r, for_each_sequence_column);
        doc["sequence"].push_back(j);
    }
    // dynrt's per-frame records, in the --report schema.
    const nlohmann::ordered_json report = nlohmann::ordered_json::parse(report_json(RunInfo{}, bench.frames));
    doc["frames"] = report["frames"];
    doc["summary"] = report["summary"];
    return doc.dump(2) + "\n";
}

}  // namespace dynrt
