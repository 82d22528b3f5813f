#include "rendering/sampled_frame.h"

#include "dynrt/packet/tiling.h"
#include "rendering/pixel_samples.h"
#include "rendering/stage_work.h"

#include <glm/common.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace dynrt::detail {

namespace {

/// The time a rate of `rays` stood for (0 when there were none).
double ms_of(std::size_t rays, double mrays_per_s) {
    return mrays_per_s > 0.0 ? double(rays) / (mrays_per_s * 1e3) : 0.0;
}

/// Adds per-depth figures element by element.
template <typename T>
void add_per_depth(std::vector<T>& sum, const std::vector<T>& pass) {
    if (sum.size() < pass.size()) sum.resize(pass.size(), T{});
    for (std::size_t k = 0; k < pass.size(); ++k) sum[k] += pass[k];
}

/// A frame's trace figures over its sample passes: times and counts added, rates made again
/// from the sums (each pass's rate stands for its rays over its time).
class PassFigures {
public:
    void add(const TraceStats& pass) {
        TraceStats& s = sum_;
        s.primary_ms += pass.primary_ms;
        s.shadow_ms += pass.shadow_ms;
        s.shade_ms += pass.shade_ms;
        s.secondary_ms += pass.secondary_ms;
        s.primary_rays += pass.primary_rays;
        s.shadow_rays += pass.shadow_rays;
        s.ray_triangle_tests += pass.ray_triangle_tests;
        s.ray_triangle_culled += pass.ray_triangle_culled;
        s.nodes_visited += pass.nodes_visited;
        s.reflection_rays += pass.reflection_rays;
        s.refraction_rays += pass.refraction_rays;
        s.secondary_shadow_rays += pass.secondary_shadow_rays;
        s.secondary_packet_rays += pass.secondary_packet_rays;
        s.secondary_single_rays += pass.secondary_single_rays;
        s.shadow_rays_back_side += pass.shadow_rays_back_side;
        s.shadow_rays_shading_side += pass.shadow_rays_shading_side;
        s.shadow_rays_dark_light += pass.shadow_rays_dark_light;
        add_per_depth(s.secondary_rays_per_depth, pass.secondary_rays_per_depth);
        add_per_depth(s.secondary_packet_rays_per_depth, pass.secondary_packet_rays_per_depth);
        reflection_ms_ += ms_of(pass.reflection_rays, pass.reflection_mrays_per_s);
        refraction_ms_ += ms_of(pass.refraction_rays, pass.refraction_mrays_per_s);
        secondary_shadow_ms_ += ms_of(pass.secondary_shadow_rays, pass.secondary_shadow_mrays_per_s);
        std::vector<double> depth_ms(pass.secondary_mrays_per_s_per_depth.size());
        for (std::size_t k = 0; k < depth_ms.size(); ++k) {
            depth_ms[k] = ms_of(pass.secondary_rays_per_depth[k], pass.secondary_mrays_per_s_per_depth[k]);
        }
        add_per_depth(depth_ms_, depth_ms);
    }

    /// Writes the sums into `out`'s trace figures (the rest of `out` is left as it is).
    void write(TraceStats& out) const {
        const TraceStats& s = sum_;
        out.primary_ms = s.primary_ms;
        out.shadow_ms = s.shadow_ms;
        out.shade_ms = s.shade_ms;
        out.secondary_ms = s.secondary_ms;
        out.primary_rays = s.primary_rays;
        out.shadow_rays = s.shadow_rays;
        out.primary_mrays_per_s = mrays_per_s(s.primary_rays, s.primary_ms);
        out.shadow_mrays_per_s = mrays_per_s(s.shadow_rays, s.shadow_ms);
        out.ray_triangle_tests = s.ray_triangle_tests;
        out.ray_triangle_culled = s.ray_triangle_culled;
        out.nodes_visited = s.nodes_visited;
        out.reflection_rays = s.reflection_rays;
        out.refraction_rays = s.refraction_rays;
        out.reflection_mrays_per_s = mrays_per_s(s.reflection_rays, reflection_ms_);
        out.refraction_mrays_per_s = mrays_per_s(s.refraction_rays, refraction_ms_);
        out.secondary_shadow_rays = s.secondary_shadow_rays;
        out.secondary_shadow_mrays_per_s = mrays_per_s(s.secondary_shadow_rays, secondary_shadow_ms_);
        out.secondary_packet_rays = s.secondary_packet_rays;
        out.secondary_single_rays = s.secondary_single_rays;
        out.secondary_rays_per_depth = s.secondary_rays_per_depth;
        out.secondary_packet_rays_per_depth = s.secondary_packet_rays_per_depth;
        out.secondary_mrays_per_s_per_depth.clear();
        for (std::size_t k = 0; k < depth_ms_.size(); ++k) {
            out.secondary_mrays_per_s_per_depth.push_back(mrays_per_s(s.secondary_rays_per_depth[k], depth_ms_[k]));
        }
        out.shadow_rays_back_side = s.shadow_rays_back_side;
        out.shadow_rays_shading_side = s.shadow_rays_shading_side;
        out.shadow_rays_dark_light = s.shadow_rays_dark_light;
    }

private:
    TraceStats sum_;
    double reflection_ms_ = 0.0, refraction_ms_ = 0.0, secondary_shadow_ms_ = 0.0;
    std::vector<double> depth_ms_;
};

/// Calls visit(p) for every pixel of the tiles `tiling` covers, tiles in parallel.
template <typename Visit>
void for_each_covered_pixel(const packet::Tiling& tiling, int width, Visit&& visit) {
    tbb::parallel_for(0, tiling.count(), [&](int i) {
        const packet::Tile tile = tiling.tile(i);
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) visit(std::size_t(y) * std::size_t(width) + std::size_t(x));
        }
    });
}

/// `in` for the samples of a pixel taking `spp`: each sample's texture footprint is a pixel's
/// over sqrt(spp), as its samples lie that much closer together (`textures` holds the
/// footprint's copy of in.textures).
TraceInputs sample_inputs(const TraceInputs& in, int spp, std::optional<SurfaceTextures>& textures) {
    TraceInputs sample_in = in;
    if (in.textures != nullptr) {
        textures.emplace(*in.textures);
        textures->pixel_angle = in.textures->pixel_angle / std::sqrt(float(spp));
        sample_in.textures = &*textures;
    }
    return sample_in;
}

}  // namespace

std::size_t refine_pixels(const RenderedFrame& first, const std::vector<bvh::InstanceHit>& hits, float contrast,
                          std::vector<std::uint8_t>& refined) {
    const int width = first.width, height = first.height;
    const auto w = std::size_t(width);
    refined.assign(w * std::size_t(height), 0);
    // Whether pixels a and b differ: another object (read from the frame's object buffer when
    // it has one: 4 bytes a pixel against a whole hit), or a channel of their clamped colours.
    const bool objects = !first.object.empty();
    const auto differ = [&](std::size_t a, std::size_t b) {
        if (objects ? first.object[a] != first.object[b] : hits[a].object != hits[b].object) return true;
        if (first.color[a] == first.color[b]) return false;  // most neighbours: the background, a flat face
        for (int c = 0; c < 3; ++c) {
            const float ca = std::clamp(first.color[a][c], 0.0f, 1.0f), cb = std::clamp(first.color[b][c], 0.0f, 1.0f);
            if (std::abs(ca - cb) > contrast) return true;
        }
        return false;
    };
    // Rows in parallel, each pixel against its right and lower neighbours; a difference marks
    // both. Row y also marks row y + 1, so even rows go first and odd rows second.
    for (int parity = 0; parity < 2; ++parity) {
        tbb::parallel_for(0, (height + 1 - parity) / 2, [&](int i) {
            const int y = 2 * i + parity;
            const std::size_t row = std::size_t(y) * w;
            for (int x = 0; x < width; ++x) {
                const std::size_t p = row + std::size_t(x);
                if (x + 1 < width && differ(p, p + 1)) refined[p] = refined[p + 1] = 1;
                if (y + 1 < height && differ(p, p + w)) refined[p] = refined[p + w] = 1;
            }
        });
    }
    std::size_t count = 0;
    for (const std::uint8_t r : refined) count += r;
    return count;
}

void trace_sampled_frame(const TraceInputs& in, const Camera& camera, const TraceSettings& options,
                         TraceScratch& scratch, RenderedFrame& out) {
    const PixelSampling& sampling = options.sampling;
    const int spp = sampling.spp;
    const bool adaptive = sampling.adaptive_contrast > 0.0f;
    const packet::Tiling tiling(options.width, options.height, options.tiles);

    // The first pass keeps a pixel's footprint under adaptive anti-aliasing.
    std::optional<SurfaceTextures> sample_textures;
    const TraceInputs sample_in = sample_inputs(in, spp, sample_textures);

    PassFigures figures;
    // Sample 0 of every pixel, into `out`: its hit buffers are the frame's.
    trace_frame(adaptive ? in : sample_in, camera, options, scratch, out, SamplePass{sampling, 0, nullptr});
    figures.add(out.stats);
    TraceSettings pass_options = options;
    pass_options.hit_buffers = false;  // the frame's are sample 0's
    RenderedFrame& pass = scratch.sample_pass;
    const float inv_spp = 1.0f / float(spp);
    std::size_t refined = tiling.pixel_count();
    if (!adaptive) {
        // Every pixel takes every sample: a pass of the image per sample, each pixel's samples
        // added in sample order.
        std::vector<glm::vec3>& sum = scratch.sample_sum;
        sum.assign(out.color.begin(), out.color.end());
        for (int s = 1; s < spp; ++s) {
            pass.stats = out.stats;
            trace_frame(sample_in, camera, pass_options, scratch, pass, SamplePass{sampling, s});
            figures.add(pass.stats);
            for_each_covered_pixel(tiling, options.width, [&](std::size_t p) { sum[p] += pass.color[p]; });
        }
        for_each_covered_pixel(tiling, options.width, [&](std::size_t p) { out.color[p] = sum[p] * inv_spp; });
    } else if ((refined = refine_pixels(out, scratch.hits, sampling.adaptive_contrast, scratch.refined)) > 0) {
        // The refined pixels' other samples, listed tile by tile and pixel by pixel, traced as
        // one frame a tile wide: each of its packets holds 256 samples of a few neighbouring
        // pixels (the image's own tiles would hold a handful of refined lanes each, and a
        // packet costs nearly as much for those as for 256).
        std::vector<PixelSample>& list = scratch.refined_samples;
        list.clear();
        tiling.for_each_pixel([&](std::size_t p) {
            if (!scratch.refined[p]) return;
            for (int s = 1; s < spp; ++s) list.push_back(PixelSample{std::uint32_t(p), std::uint32_t(s)});
        });
        pass_options.width = packet::kTileSize;
        pass_options.height = int((list.size() + packet::kTileSize - 1) / packet::kTileSize);
        pass_options.tiles = {};
        std::vector<std::uint8_t>& listed = scratch.listed;
        listed.assign(std::size_t(pass_options.width) * std::size_t(pass_options.height), 0);
        std::fill(listed.begin(), listed.begin() + std::ptrdiff_t(list.size()), std::uint8_t{1});
        pass.stats = out.stats;
        // The frame's progress learns of this pass's tiles now that they are known.
        if (in.progress != nullptr) in.progress->add_tiles(std::size_t(packet::Tiling(pass_options.width, pass_options.height).count()));
        trace_frame(sample_in, camera, pass_options, scratch, pass,
                    SamplePass{sampling, 0, &listed, &list, options.width, options.height});
        figures.add(pass.stats);
        // Each pixel's samples lie together in the list, in sample order: added to its first
        // as the passes above add them.
        const auto per_pixel = std::size_t(spp - 1);
        tbb::parallel_for(std::size_t{0}, list.size() / per_pixel, [&](std::size_t k) {
            const std::size_t p = list[k * per_pixel].pixel;
            glm::vec3 sum = out.color[p];
            for (std::size_t v = k * per_pixel; v < (k + 1) * per_pixel; ++v) sum += pass.color[v];
            out.color[p] = sum * inv_spp;
        });
    }
    figures.write(out.stats);
    out.stats.samples_per_pixel = spp;
    out.stats.pixels_refined = refined;
}

ReusePlan SampledReuse::trace(const TraceInputs& in, const ReuseInputs& now, const TraceSettings& options,
                             RenderedFrame& out) {
    const int spp = options.sampling.spp;
    samples_.resize(std::size_t(spp));
    std::optional<SurfaceTextures> sample_textures;
    const TraceInputs sample_in = sample_inputs(in, spp, sample_textures);
    TraceSettings pass_options = options;
    PassFigures figures;
    ReusePlan first_plan;
    std::size_t traced = 0, shadows_retraced = 0, reused = 0;
    for (int s = 0; s < spp; ++s) {
        Sample& sample = samples_[std::size_t(s)];
        pass_options.hit_buffers = s == 0 && options.hit_buffers;  // the frame's are sample 0's
        ReuseInputs sample_now = now;
        sample_now.frame_stamp = sample.frame.reuse_stamp;
        ReusePlan plan = plan_exact_reuse(sample.memory, sample_now);
        sample.frame.stats = out.stats;
        trace_frame_reusing(sample_in, now.camera, pass_options, plan, sample.memory, sample.scratch, sample.frame,
                            SamplePass{options.sampling, s});
        remember_inputs(sample_now, sample.memory, sample.frame);
        figures.add(sample.frame.stats);
        traced += sample.frame.stats.pixels_traced;
        shadows_retraced += sample.frame.stats.pixels_shadows_retraced;
        reused += sample.frame.stats.pixels_reused;
        if (s == 0) first_plan = std::move(plan);
    }

    // Each pixel the mean of its samples, in sample order (as trace_sampled_frame adds them).
    const packet::Tiling tiling(options.width, options.height, options.tiles);
    const RenderedFrame& first = samples_[0].frame;
    size_image(options, out);
    const bool hit_buffers = options.hit_buffers;
    const float inv_spp = 1.0f / float(spp);
    for_each_covered_pixel(tiling, options.width, [&](std::size_t p) {
        glm::vec3 sum = first.color[p];
        for (std::size_t s = 1; s < samples_.size(); ++s) sum += samples_[s].frame.color[p];
        out.color[p] = sum * inv_spp;
        if (!hit_buffers) return;
        out.depth[p] = first.depth[p];
        out.object[p] = first.object[p];
        out.prim[p] = first.prim[p];
        out.normal[p] = first.normal[p];
    });
    out.reuse_stamp = 0;  // the passes' own frames hold what the next trace compares
    figures.write(out.stats);
    out.stats.samples_per_pixel = spp;
    out.stats.pixels_refined = tiling.pixel_count();
    out.stats.reuse_mode = first.stats.reuse_mode;
    out.stats.reuse_reason = first.stats.reuse_reason;
    out.stats.pixels_traced = traced / std::size_t(spp);
    out.stats.pixels_shadows_retraced = shadows_retraced / std::size_t(spp);
    out.stats.pixels_reused = reused / std::size_t(spp);
    out.stats.pixels_filled = 0;
    out.stats.interpolated_pixels = 0;
    return first_plan;
}

}  // namespace dynrt::detail
