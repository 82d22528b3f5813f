#pragma once
// One tile's pass through a frame's stages, written once for every mode that traces pixels:
//
//   camera rays -> closest hits -> hit records -> shadow rays per light -> shading -> writes
//   -> the hits' first reflection and refraction rays gathered for the secondary stage
//
// run in one task per 16x16 tile, each stage timed on its own thread (stage_work.h). A mode is
// a choice of which rays enter and what is kept (the `choice` of trace_tile):
//
//   a full frame     every camera ray, every shadow ray (EveryRay, below);
//   exact reuse      the camera rays that may see something else, the shadow rays that may be
//                    blocked otherwise, the other pixels kept (exact_reuse.cpp, ReuseTile);
//   render cache,    the pixels of the chosen blocks, whose samples are stored; the others
//   frameless        keep what the frame shows (approximate_reuse.cpp, SelectedTile).
//
// Adaptive sampling (adaptive_tile.h) traces a tile's sample grid first and decides from what
// it shows whether to interpolate the rest; a tile it cannot interpolate takes this pass with
// every ray.

#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/engine/stopwatch.h"
#include "rendering/frame_tracer.h"
#include "rendering/pixel_samples.h"
#include "rendering/secondary_rays.h"
#include "rendering/stage_work.h"
#include "rendering/tile_shading.h"
#include "rendering/tile_tracing.h"

#include <vector>

namespace dynrt::detail {

/// A tile's camera rays, made only when something needs them: most tiles of a frame that
/// reuses pixels are decided by their corner rays alone, and filling 256 rays for each was
/// most of the cost of such a frame.
class TileRays {
public:
    /// The rays of `sample`'s pass through the tile's pixels of an image `width` wide.
    TileRays(const packet::PinholeRays& pinhole, const packet::Tile& tile, const SamplePass& sample, int width)
        : pinhole_(pinhole), tile_(tile), sample_(sample), width_(width) {}

    packet::RayPacket& get() {
        if (!filled_) fill();
        filled_ = true;
        return rays_;
    }

private:
    void fill() {
        if (sample_.sampling.spp <= 1) {
            pinhole_.fill_tile(tile_, rays_);
            return;
        }
        // Each lane's sample: its offset in the pixel, and for a list of samples also how far
        // the image's pixel lies from the lane's place in the pass's frame.
        thread_local packet::PixelOffsets offsets;
        const std::size_t listed = sample_.samples != nullptr ? sample_.samples->size() : 0;
        const SampleOffsets pass_offsets(sample_.sampling, sample_.index);
        for (int lane = 0; lane < packet::kPacketRays; ++lane) {
            const packet::LanePixel px = packet::tile_pixel(tile_, lane);
            const std::uint32_t v = pixel_index(px, width_);
            glm::vec2 d(0.0f);
            if (px.inside && (sample_.samples == nullptr || v < listed)) {
                const PixelSample at = sample_.at(v);
                d = sample_.samples == nullptr ? pass_offsets.at(at.pixel)
                                               : pixel_sample_offset(sample_.sampling, at.pixel, int(at.sample));
                if (sample_.samples != nullptr) {
                    const auto w = std::uint32_t(sample_.image_width);
                    d += glm::vec2(float(int(at.pixel % w) - px.x), float(int(at.pixel / w) - px.y));
                }
            }
            offsets.dx[lane] = d.x;
            offsets.dy[lane] = d.y;
        }
        pinhole_.fill_tile(tile_, offsets, rays_);
    }

    const packet::PinholeRays& pinhole_;
    const packet::Tile& tile_;
    const SamplePass& sample_;
    int width_;
    packet::RayPacket rays_;
    bool filled_ = false;
};

/// What every tile of a frame reads, whatever the mode.
struct TilePass {
    const TraceInputs& in;
    const packet::PinholeRays& pinhole;
    const TileShading& shading;
    SecondaryStage* secondary;  ///< null: no secondary rays
    /// The frame's per-pixel hits, which the camera rays' hits are written into in place.
    std::vector<bvh::InstanceHit>& hits;
    int width;
    bool count;  ///< traversal counters (TraceSettings::count_packet_work)
    /// Which sample of its pixels the pass traces (pixel_samples.h): by default their centres.
    SamplePass sample = {};

    TraceWork* trace_work(StageWork& work) const { return count ? &work.trace : nullptr; }

    /// Makes `origins`' area-light points for its tile's hits (TileShadowOrigins::sample_lights).
    void sample_lights(const packet::Tile& tile, TileShadowOrigins& origins) const {
        origins.sample_lights(
            in.lights, [&](int lane) { return sample.at(pixel_index(packet::tile_pixel(tile, lane), width)); },
            sample.sampling.spp);
    }
};

/// Tile number `index` of a frame: `choice` says, in this order, once each,
///
///   packet::LaneMask camera_lanes(TileRays&)          the camera rays traced (their hits
///                                                     written in place), none to keep all;
///   bool may_change(const packet::LaneMask& traced)   whether any pixel may show something
///                                                     else; if not, the tile stops here;
///   bool shadows(TileShadowOrigins&, const packet::LaneMask& traced, TileRays&,
///                std::vector<packet::LaneMask>& visible, StageWork&)
///                                                     visible[l]: the hit lanes light l
///                                                     reaches (traced, or kept); whether to
///                                                     shade and write the tile;
///   void written(const TileShadowOrigins&, TileRays&, RenderedFrame&)
///                                                     after the whole tile was written;
///   bool gathers_secondary()                          whether its hits' secondary rays join
///                                                     the secondary stage.
template <class Choice>
void trace_tile_stages(const TilePass& f, int index, const packet::Tile& tile, Choice& choice,
                       StageWork& work, RenderedFrame& out) {
    Stopwatch clock;
    TileRays rays(f.pinhole, tile, f.sample, f.width);
    const packet::LaneMask traced = choice.camera_lanes(rays);
    if (traced.any()) {
        packet::RayPacket& camera = rays.get();
        const packet::LaneMask tile_lanes = camera.active;
        camera.active = traced;
        trace_tile_hits(f.in.tracer, tile, f.width, camera, f.hits, f.trace_work(work));
        camera.active = tile_lanes;
        work.primary_rays += std::size_t(traced.count());
    }
    work.primary_ms += clock.lap_ms();
    if (!choice.may_change(traced)) {
        work.shadow_ms += clock.lap_ms();
        return;  // the tile keeps every pixel
    }

    // The shadow rays start from the hit points, made from the camera rays' directions.
    TileShadowOrigins origins;
    origins.compute(f.in.accel, f.hits, f.width, tile, rays.get(), f.in.object_material);
    f.sample_lights(tile, origins);
    thread_local std::vector<packet::LaneMask> visible;
    const bool shade = choice.shadows(origins, traced, rays, visible, work);
    work.shadow_ms += clock.lap_ms();
    if (!shade) return;

    // Shading, on the normals and hit points the shadow rays were made from while they are
    // still in cache; the whole tile, which gives the same bits where nothing changed.
    packet::ShadedColors colors;
    shade_lanes(f.shading, origins, visible, colors);
    write_tile(f.shading, tile, origins, f.hits, colors, out);
    choice.written(origins, rays, out);
    if (f.secondary != nullptr && choice.gathers_secondary()) f.secondary->gather(index, tile, f.width, origins);
    work.shade_ms += clock.lap_ms();
}

/// trace_tile_stages, then the tile counted done for the frame's progress (render_progress.h).
template <class Choice>
void trace_tile(const TilePass& f, int index, const packet::Tile& tile, Choice& choice,
                StageWork& work, RenderedFrame& out) {
    trace_tile_stages(f, index, tile, choice, work, out);
    if (f.in.progress != nullptr) f.in.progress->tile_done();
}

/// A full frame's choice of rays for trace_tile: every camera ray and every shadow ray of the
/// tile.
struct EveryRay {
    const TilePass& f;

    packet::LaneMask camera_lanes(TileRays& rays) { return rays.get().active; }
    bool may_change(const packet::LaneMask&) { return true; }
    bool shadows(TileShadowOrigins& origins, const packet::LaneMask&, TileRays& rays,
                 std::vector<packet::LaneMask>& visible, StageWork& work) {
        packet::RayPacket& shadow = rays.get();  // the camera rays are done with
        work.add_shadows(trace_tile_shadows(f.in.tracer, RayCoherence::tile, origins, f.shading.lights, f.shading.glass, shadow,
                                            visible, f.trace_work(work)));
        return true;
    }
    void written(const TileShadowOrigins&, TileRays&, RenderedFrame&) {}
    bool gathers_secondary() const { return true; }
};

/// A sample pass's choice of rays when it traces only some pixels (SamplePass::pixels: those
/// adaptive anti-aliasing refines): their camera rays and shadow rays; the tile's other pixels
/// are made misses, so that nothing is traced or gathered for them (their colours in this
/// pass's frame are the background's, and unused).
struct SomePixels {
    const TilePass& f;
    const std::vector<std::uint8_t>& pixels;
    const packet::Tile& tile;

    packet::LaneMask camera_lanes(TileRays& rays) {
        packet::LaneMask chosen;
        rays.get().active.for_each([&](int lane) {
            const std::size_t p = pixel_index(packet::tile_pixel(tile, lane), f.width);
            if (pixels[p] != 0) {
                chosen.set(lane);
            } else {
                f.hits[p] = bvh::InstanceHit{};
            }
        });
        return chosen;
    }
    bool may_change(const packet::LaneMask& traced) { return traced.any(); }
    bool shadows(TileShadowOrigins& origins, const packet::LaneMask& traced, TileRays& rays,
                 std::vector<packet::LaneMask>& visible, StageWork& work) {
        return EveryRay{f}.shadows(origins, traced, rays, visible, work);
    }
    void written(const TileShadowOrigins&, TileRays&, RenderedFrame&) {}
    bool gathers_secondary() const { return true; }
};

}  // namespace dynrt::detail
