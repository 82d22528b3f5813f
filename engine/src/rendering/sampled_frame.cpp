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

}  // namespace

std::size_t refine_pixels(const RenderedFrame& first, const std::vector<bvh::InstanceHit>& hits, float contrast,
                          std::vector<std::uint8_t>& refined) {
    const int width = first.width, height = first.height;
    refined.assign(std::size_t(width) * std::size_t(height), 0);
    std::size_t count = 0;
    const auto differ = [&](std::size_t a, std::size_t b) {
        if (hits[a].object != hits[b].object) return true;
        const glm::vec3 ca = glm::clamp(first.color[a], 0.0f, 1.0f), cb = glm::clamp(first.color[b], 0.0f, 1.0f);
        const glm::vec3 d = glm::abs(ca - cb);
        return std::max({d.x, d.y, d.z}) > contrast;
    };
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(width) + std::size_t(x);
            // Each neighbour pair once: the pixel and its right and lower neighbours.
            if (x + 1 < width && differ(p, p + 1)) refined[p] = refined[p + 1] = 1;
            if (y + 1 < height && differ(p, p + std::size_t(width))) refined[p] = refined[p + std::size_t(width)] = 1;
        }
    }
    for (const std::uint8_t r : refined) count += r;
    return count;
}

void trace_sampled_frame(const TraceInputs& in, const Camera& camera, const TraceSettings& options,
                         TraceScratch& scratch, RenderedFrame& out) {
    const PixelSampling& sampling = options.sampling;
    const int spp = sampling.spp;
    const bool adaptive = sampling.adaptive_contrast > 0.0f;
    const packet::Tiling tiling(options.width, options.height, options.tiles);

    // Each sample's texture footprint: a pixel's over sqrt(spp), as its samples are that much
    // closer together (the first pass keeps a pixel's under adaptive anti-aliasing).
    std::optional<SurfaceTextures> sample_textures;
    if (in.textures != nullptr) {
        sample_textures.emplace(*in.textures);
        sample_textures->pixel_angle = in.textures->pixel_angle / std::sqrt(float(spp));
    }
    TraceInputs sample_in = in;
    if (sample_textures) sample_in.textures = &*sample_textures;

    PassFigures figures;
    // Sample 0 of every pixel, into `out`: its hit buffers are the frame's.
    trace_frame(adaptive ? in : sample_in, camera, options, scratch, out, SamplePass{sampling, 0, nullptr});
    figures.add(out.stats);
    std::vector<glm::vec3>& sum = scratch.sample_sum;
    sum.assign(out.color.begin(), out.color.end());
    const std::vector<std::uint8_t>* chosen = nullptr;
    std::size_t refined = tiling.pixel_count();
    if (adaptive) {
        refined = refine_pixels(out, scratch.hits, sampling.adaptive_contrast, scratch.refined);
        chosen = &scratch.refined;
    }

    TraceSettings pass_options = options;
    pass_options.hit_buffers = false;  // the frame's are sample 0's
    RenderedFrame& pass = scratch.sample_pass;
    for (int s = 1; s < spp && refined > 0; ++s) {
        pass.stats = out.stats;
        trace_frame(sample_in, camera, pass_options, scratch, pass, SamplePass{sampling, s, chosen});
        figures.add(pass.stats);
        for_each_covered_pixel(tiling, options.width, [&](std::size_t p) {
            if (chosen == nullptr || (*chosen)[p] != 0) sum[p] += pass.color[p];
        });
    }
    const float inv_spp = 1.0f / float(spp);
    for_each_covered_pixel(tiling, options.width, [&](std::size_t p) {
        if (chosen == nullptr || (*chosen)[p] != 0) out.color[p] = sum[p] * inv_spp;
    });
    figures.write(out.stats);
    out.stats.samples_per_pixel = spp;
    out.stats.pixels_refined = refined;
}

}  // namespace dynrt::detail
