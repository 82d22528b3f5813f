// The Embree bench drivers (embree_bench.h): every build quality on one frame beside dynrt's,
// and Embree stepping through a sequence beside dynrt's frame loop.

#include "dynrt/embree/embree_bench.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/stopwatch.h"

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace dynrt::embree {

std::vector<EmbreeRow> bench_embree(const Scene& scene, const Camera& camera,
                                    const RenderOptions& options, int repeat, int warmup,
                                    const RenderedFrame& dynrt_frame,
                                    std::vector<PixelAgreement>* disagreement) {
    if (repeat < 1) throw std::invalid_argument("bench: repeat must be at least 1");
    const int width = options.width, height = options.height;
    const std::vector<PointLight> lights = effective_lights(scene, options);
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    if (disagreement) disagreement->assign(pixels, PixelAgreement::same);
    EmbreeTracer tracer;
    PixelHits single, packet;
    std::vector<std::uint32_t> occluded_single, occluded_packet;
    std::vector<EmbreeRow> rows;
    for (BuildQuality quality : {BuildQuality::low, BuildQuality::medium, BuildQuality::high}) {
        std::vector<double> build, i1, i16, o1, o16, mrays;
        std::size_t shadow_rays = 0, shadow_rays_single = 0;
        // Only the first quality warms up (device, thread pool, first-touch memory); the
        // others start warm, as later configurations of a dynrt sweep do.
        const int warmup_runs = quality == BuildQuality::low ? warmup : 0;
        for (int run = 0; run < warmup_runs + repeat; ++run) {
            // Single rays and packets alternate within each run, so load on a shared machine
            // falls on both alike.
            const double build_ms = tracer.build(scene, quality);
            const double i1_ms = tracer.intersect1(camera, width, height, single);
            const double i16_ms = tracer.intersect16(camera, width, height, packet);
            const double o1_ms = tracer.occluded1(camera, width, height, lights, single,
                                                  shadow_rays_single, &occluded_single);
            const double o16_ms = tracer.occluded16(camera, width, height, lights, single,
                                                    shadow_rays, &occluded_packet);
            if (run < warmup_runs) continue;
            build.push_back(build_ms);
            i1.push_back(i1_ms);
            i16.push_back(i16_ms);
            o1.push_back(o1_ms);
            o16.push_back(o16_ms);
            const double ms = i16_ms + o16_ms;
            mrays.push_back(ms > 0 ? double(pixels + shadow_rays) / (ms * 1e3) : 0.0);
        }
        EmbreeRow row;
        row.quality = quality;
        row.build_ms = spread_of(build);
        row.intersect1_ms = spread_of(i1);
        row.intersect16_ms = spread_of(i16);
        row.occluded1_ms = spread_of(o1);
        row.occluded16_ms = spread_of(o16);
        row.mrays_per_s = spread_of(mrays);
        row.shadow_rays = shadow_rays;
        const std::vector<PixelAgreement> per_pixel =
            classify_hits(dynrt_frame.object, dynrt_frame.prim, single.object, single.prim);
        row.vs_dynrt = count_disagreements(per_pixel);
        if (disagreement) {
            for (std::size_t p = 0; p < per_pixel.size(); ++p) {
                (*disagreement)[p] = std::max((*disagreement)[p], per_pixel[p]);
            }
        }
        const HitAgreement packets =
            compare_hits(single.object, single.prim, packet.object, packet.prim);
        std::size_t shadows_differ = shadow_rays == shadow_rays_single ? 0 : 1;
        for (std::size_t p = 0; p < occluded_single.size(); ++p) {
            shadows_differ += occluded_single[p] != occluded_packet[p] ? 1 : 0;
        }
        row.packet_vs_single_differs =
            packets.object_differs + packets.prim_only_differs + shadows_differ;
        rows.push_back(row);
    }
    return rows;
}

SecondaryComparison bench_secondary_embree(const Scene& scene, const Camera& camera,
                                           const RenderOptions& options, int repeat, int warmup) {
    if (repeat < 1) throw std::invalid_argument("bench: repeat must be at least 1");
    SecondaryComparison c;
    SecondaryRayLog log;
    RenderOptions logging = options;
    logging.secondary_log = &log;
    logging.reuse.mode = PixelReuse::off;
    Renderer renderer(logging);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);
    c.reflection_rays = frame.stats.reflection_rays;
    c.refraction_rays = frame.stats.refraction_rays;
    c.primary_mrays_per_s = frame.stats.primary_mrays_per_s;
    c.packets = log.packets.size();
    if (log.packets.empty()) return c;
    EmbreeTracer tracer;
    tracer.build(scene, BuildQuality::high);
    std::vector<bvh::InstanceHit> dynrt_hits;
    PixelHits coherent, incoherent, single;
    std::vector<double> d, e16c, e16, e1;
    for (int run = 0; run < warmup + repeat; ++run) {
        // The four alternate within each run, so load on a shared machine falls on all alike.
        const double d_ms = renderer.trace_logged_rays(log, run == 0 ? &dynrt_hits : nullptr);
        const double e16c_ms = tracer.intersect16_logged(log, true, coherent);
        const double e16_ms = tracer.intersect16_logged(log, false, incoherent);
        const double e1_ms = tracer.intersect1_logged(log, single);
        if (run < warmup) continue;
        d.push_back(d_ms);
        e16c.push_back(e16c_ms);
        e16.push_back(e16_ms);
        e1.push_back(e1_ms);
    }
    c.dynrt_ms = spread_of(d);
    c.embree16_coherent_ms = spread_of(e16c);
    c.embree16_ms = spread_of(e16);
    c.embree1_ms = spread_of(e1);
    std::vector<std::int32_t> object(dynrt_hits.size(), -1), prim(dynrt_hits.size(), -1);
    for (std::size_t i = 0; i < dynrt_hits.size(); ++i) {
        if (!dynrt_hits[i].is_hit()) continue;
        object[i] = std::int32_t(dynrt_hits[i].object);
        prim[i] = std::int32_t(dynrt_hits[i].hit.prim);
    }
    c.vs_dynrt = compare_hits(object, prim, single.object, single.prim);
    return c;
}

namespace {

class EmbreeSequenceTracer : public SequenceTracer {
public:
    EmbreeSequenceTracer(const Scene& scene, const RenderOptions& options, BuildQuality quality)
        : scene_(scene), width_(options.width), height_(options.height),
          lights_(effective_lights(scene, options)), quality_(quality),
          poser_(scene, full_pose(options.pose)) {
        check_embree_fits(scene);  // before the first frame poses every vertex
    }

    std::string name() const override { return std::string("embree ") + quality_name(quality_); }

    SequenceFrameTimes frame(int frame, const Camera& camera,
                             const RenderedFrame& dynrt_frame) override {
        SequenceFrameTimes times;
        Stopwatch clock;
        poser_.pose(frame, posed_);
        times.update_ms = clock.lap_ms();
        const FrameLoad load = tracer_.load_frame(scene_, posed_, quality_);
        times.build_ms = load.upload_ms + load.commit_ms;
        times.primary_ms = tracer_.intersect16(camera, width_, height_, hits_);
        std::size_t rays = 0;
        times.shadow_ms = tracer_.occluded16(camera, width_, height_, lights_, hits_, rays);
        times.vs_dynrt = compare_hits(dynrt_frame.object, dynrt_frame.prim, hits_.object, hits_.prim);
        return times;
    }

private:
    /// Embree needs every object's world positions each frame.
    static anim::PoseSettings full_pose(anim::PoseSettings settings) {
        settings.skip_fixed_positions = false;
        return settings;
    }

    const Scene& scene_;
    int width_, height_;
    std::vector<PointLight> lights_;
    BuildQuality quality_;
    anim::ScenePoser poser_;
    anim::PosedScene posed_;
    EmbreeTracer tracer_;
    PixelHits hits_;
};

}  // namespace

std::unique_ptr<SequenceTracer> make_sequence_tracer(const Scene& scene, const RenderOptions& options,
                                                     BuildQuality quality) {
    return std::make_unique<EmbreeSequenceTracer>(scene, options, quality);
}

}  // namespace dynrt::embree
