#include "rendering/approximate_reuse.h"

#include "dynrt/engine/stopwatch.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/tiling.h"
#include "rendering/changed_space.h"
#include "rendering/same_view.h"
#include "rendering/tile_pass.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <atomic>
#include <cmath>
#include <limits>

namespace dynrt::detail {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
/// Rank of a block: the age of its oldest pixel (0..kOldest); above, a block with holes,
/// kHoleLevel plus the number of its holes (the emptiest first); on top, one that must change.
constexpr int kHoleLevel = 512, kChangedLevel = 1023, kLevels = 1024;
/// The side of the square blocks pixels are ranked and traced in (a tile holds 2x2 of them).
constexpr int kBlock = 8;
/// The most changed boxes whose rays the ranking tests (see trace_frame_approximate).
constexpr std::size_t kMostChangedBoxes = 1024;
/// A hole with at least this many sampled neighbours (of 8) is a crack, kept as a sample.
constexpr int kCrackNeighbours = 6;
/// A block with at least 1 / kHoleShare of its pixels holes ranks as a hole.
constexpr int kHoleShare = 8;
/// Depth culling: a neighbour nearer than this share of a sample's depth is in front of it.
constexpr float kDepthCullRatio = 0.9f;

/// splitmix64's finaliser: the tie-break of equal ranks, per pixel and frame.
std::uint32_t hash(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return std::uint32_t((x ^ (x >> 31)) >> 32);
}

/// World point to pixel under a camera: the inverse of PinholeRays' mapping.
struct Projection {
    glm::vec3 eye, fwd, right, up;
    float tan_half_fov, aspect;
    int width, height;

    Projection(const Camera& c, int w, int h)
        : eye(c.eye), fwd(glm::normalize(c.target - c.eye)),
          right(glm::normalize(glm::cross(fwd, c.up))), up(glm::cross(right, fwd)),
          tan_half_fov(std::tan(glm::radians(c.fov_y_deg) * 0.5f)), aspect(float(w) / float(h)),
          width(w), height(h) {}

    /// The pixel the point falls in, or false when it is behind the eye or off the image.
    bool pixel_of(const glm::vec3& p, int& x, int& y) const {
        const glm::vec3 v = p - eye;
        const float z = glm::dot(v, fwd);
        if (!(z > 0.0f)) return false;
        const float sx = glm::dot(v, right) / (z * tan_half_fov * aspect);
        const float sy = glm::dot(v, up) / (z * tan_half_fov);
        const float fx = (sx + 1.0f) * 0.5f * float(width), fy = (1.0f - sy) * 0.5f * float(height);
        if (!(fx >= 0.0f && fx < float(width) && fy >= 0.0f && fy < float(height))) return false;
        x = int(fx);
        y = int(fy);
        return true;
    }
};

/// One pixel's sample, moved around by reprojection: for a hit its world point, for a miss
/// (object -1) the direction of its ray.
struct Sample {
    glm::vec3 color, point, normal;
    std::int32_t object, prim;
    std::uint8_t age;
};

Sample empty_sample(const glm::vec3& background) {
    return Sample{background, glm::vec3(0.0f), glm::vec3(0.0f), -1, -1, PixelCache::kEmpty};
}

Sample sample_at(const PixelCache& c, std::size_t p) {
    return Sample{c.color[p], c.point[p], c.normal[p], c.object[p], c.prim[p], c.age[p]};
}

void store(PixelCache& c, std::size_t p, const Sample& s) {
    c.color[p] = s.color;
    c.point[p] = s.point;
    c.normal[p] = s.normal;
    c.object[p] = s.object;
    c.prim[p] = s.prim;
    c.age[p] = s.age;
}

void resize(PixelCache& c, std::size_t pixels) {
    c.color.resize(pixels);
    c.point.resize(pixels);
    c.normal.resize(pixels);
    c.object.resize(pixels);
    c.prim.resize(pixels);
    c.age.resize(pixels);
}

/// Calls f(p) for every pixel index p < pixels, in parallel chunks (one call per chunk to the
/// scheduler, not per pixel).
template <typename F>
void for_each_pixel(std::size_t pixels, F&& f) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels, 8192),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t p = range.begin(); p < range.end(); ++p) f(p);
                      });
}

/// Calls f(q) for every pixel q of the 3x3 block around (x, y) that is inside the image,
/// (x, y) itself left out.
template <typename F>
void for_each_neighbour(int x, int y, int width, int height, F&& f) {
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            f(std::size_t(ny) * std::size_t(width) + std::size_t(nx));
        }
    }
}

/// What the phases of an approximate trace share.
struct ApproximateFrame {
    const TraceInputs& in;
    const Camera& camera;
    const TraceSettings& options;
    const packet::PinholeRays& pinhole;
    const packet::Tiling& tiling;
    PixelCache& cache;
    int width, height;
    std::size_t pixels;
    bool render_cache;  ///< PixelReuse::render_cache (else frameless)
};

/// The render cache after the camera moved: each sample forward-reprojected to `f.camera`,
/// the nearest winning per pixel, then depth-culled.
void reproject(const ApproximateFrame& f) {
    const Camera& camera = f.camera;
    const TraceSettings& options = f.options;
    PixelCache& cache = f.cache;
    const int width = f.width, height = f.height;
    const std::size_t pixels = f.pixels;
    // Forward reprojection with a depth test: per target pixel the nearest sample wins,
    // by an atomic minimum over (depth bits, source pixel), the same whatever the order.
    const Projection to(camera, width, height);
    std::vector<std::uint64_t>& nearest = cache.nearest_scratch;
    nearest.assign(pixels, ~std::uint64_t{0});
    for_each_pixel(pixels, [&](std::size_t p) {
        if (cache.age[p] == PixelCache::kEmpty) return;
        // A miss keeps its direction, a point at infinity: it lands where that direction
        // is seen from the new eye, behind every hit.
        const bool hit = cache.object[p] >= 0;
        int x, y;
        if (!to.pixel_of(hit ? cache.point[p] : camera.eye + cache.point[p], x, y)) return;
        const float depth = hit ? glm::length(cache.point[p] - camera.eye) : kInf;
        const std::uint64_t key = (std::uint64_t(std::bit_cast<std::uint32_t>(depth)) << 32) | p;
        std::atomic_ref<std::uint64_t> slot(nearest[std::size_t(y) * width + x]);
        std::uint64_t seen = slot.load(std::memory_order_relaxed);
        while (key < seen && !slot.compare_exchange_weak(seen, key, std::memory_order_relaxed)) {
        }
    });
    // Gathered into the spare arrays, which then become the cache's, with each sample's
    // depth (-1 for none) for the depth culling below.
    PixelCache& to_cache = cache.spare();
    resize(to_cache, pixels);
    std::vector<float>& depth = to_cache.depth_scratch;
    depth.resize(pixels);
    const Sample none = empty_sample(options.background);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels, 4096),
                      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t p = range.begin(); p < range.end(); ++p) {
            if (nearest[p] == ~std::uint64_t{0}) {
                store(to_cache, p, none);
                depth[p] = -1.0f;
                continue;
            }
            Sample s = sample_at(cache, std::size_t(nearest[p] & 0xffffffffu));
            s.age = std::uint8_t(std::min<int>(s.age + 1, PixelCache::kOldest));
            store(to_cache, p, s);
            depth[p] = s.object < 0 ? kInf : glm::length(s.point - camera.eye);
        }
    });
    // Depth culling (Walter et al. 1999, section 4.3): forward reprojection leaves cracks
    // in a surface that comes nearer, and what lies behind it shows through them. A sample
    // much farther than most of its neighbours is such a point: dropped, it becomes a hole
    // that the fill below closes from the surface around it.
    const auto nearer = [&](float n, float d) { return int(n >= 0.0f && n < kDepthCullRatio * d); };
    tbb::parallel_for(0, height, [&](int y) {
        const float* row = &depth[std::size_t(y) * width];
        for (int x = 0; x < width; ++x) {
            const float d = row[x];
            if (d < 0.0f) continue;
            int count = 0;
            if (x > 0 && y > 0 && x + 1 < width && y + 1 < height) {
                // Inside the image: the eight neighbours without bounds checks.
                const float* up = row - width;
                const float* down = row + width;
                count = nearer(up[x - 1], d) + nearer(up[x], d) + nearer(up[x + 1], d) +
                        nearer(row[x - 1], d) + nearer(row[x + 1], d) +
                        nearer(down[x - 1], d) + nearer(down[x], d) + nearer(down[x + 1], d);
            } else {
                for_each_neighbour(x, y, width, height,
                                   [&](std::size_t q) { count += nearer(depth[q], d); });
            }
            // Six of eight: a sample at a silhouette has three to five nearer neighbours.
            if (count >= 6) to_cache.age[std::size_t(y) * width + x] = PixelCache::kEmpty;
        }
    });
    cache.swap_samples();
}

/// The samples as this frame starts: kept (a step older), reprojected, or none (new image
/// settings); all made oldest when the lights changed. Sets stats.reuse_reason.
void start_samples(const ApproximateFrame& f, std::span<const bvh::Aabb> boxes, TraceStats& stats) {
    PixelCache& cache = f.cache;
    const TraceSettings& options = f.options;
    const std::size_t pixels = f.pixels;
    const bool fresh = !cache.valid || cache.settings.width != f.width ||
                       cache.settings.height != f.height || cache.settings.tracer != options.tracer ||
                       cache.settings.background != options.background ||
                       cache.settings.ambient != options.ambient ||
                       cache.settings.smooth_normals != options.smooth_normals ||
                       boxes.size() < cache.object_boxes.size();
    const bool moved = !fresh && !same_camera(cache.camera, f.camera);
    const bool relit = !fresh && !same_lights(cache.lights, f.in.lights);
    if (fresh) {
        resize(cache, pixels);
        const Sample none = empty_sample(options.background);
        for_each_pixel(pixels, [&](std::size_t p) { store(cache, p, none); });
        cache.object_boxes.clear();
        cache.object_versions.clear();
        stats.reuse_reason = cache.valid ? "image settings changed" : "first frame";
    } else if (moved && f.render_cache) {
        reproject(f);
        stats.reuse_reason = "camera moved: reprojected";
    } else {
        for_each_pixel(pixels, [&](std::size_t p) {
            if (cache.age[p] != PixelCache::kEmpty) {
                cache.age[p] = std::uint8_t(std::min<int>(cache.age[p] + 1, PixelCache::kOldest));
            }
        });
        stats.reuse_reason = moved ? "camera moved: samples kept in place" : "camera still";
    }
    if (relit) {
        // Every sample's shading is stale: all are refreshed oldest first.
        for (std::uint8_t& age : cache.age) {
            if (age != PixelCache::kEmpty) age = PixelCache::kOldest;
        }
        stats.reuse_reason += ", lights changed";
    }
}

/// The objects changed since the cache's frame, and the space their boxes (then and now) take.
struct Changes {
    std::vector<std::uint8_t> changed;  ///< per object
    std::vector<bvh::Aabb> changed_boxes;
    float scale = 0.0f;
};

Changes changes_since(const ApproximateFrame& f, std::span<const bvh::Aabb> boxes,
                      std::span<const std::uint64_t> versions) {
    const PixelCache& cache = f.cache;
    const Camera& camera = f.camera;
    Changes c;
    std::vector<std::uint8_t>& changed = c.changed;
    std::vector<bvh::Aabb>& changed_boxes = c.changed_boxes;
    float& scale = c.scale;
    changed.assign(boxes.size(), 0);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        const bool known = i < cache.object_versions.size();
        if (known && cache.object_versions[i] == versions[i]) continue;
        changed[i] = 1;
        if (known) changed_boxes.push_back(cache.object_boxes[i]);
        changed_boxes.push_back(boxes[i]);
    }
    for (const bvh::Aabb& b : changed_boxes) {
        if (b.is_empty()) continue;
        for (int a = 0; a < 3; ++a) scale = std::max({scale, std::fabs(b.lo[a]), std::fabs(b.hi[a])});
    }
    for (int a = 0; a < 3; ++a) scale = std::max(scale, std::fabs(camera.eye[a]));
    // Every tile is tested against every box: past kMostChangedBoxes (BART robots: 3,600)
    // the tests cost more than tracing, and pixels rank as changed only by the object their
    // sample shows (an approximation: an object moving into a pixel is seen once it is
    // traced for its age or as a hole).
    if (changed_boxes.size() > kMostChangedBoxes) changed_boxes.clear();
    return c;
}

/// Every 8x8 block's rank: the most urgent of its pixels' (changed, hole, then by age).
struct Ranking {
    int blocks_x = 0;
    std::vector<std::uint16_t> level;
    std::array<std::size_t, kLevels> histogram{};

    std::size_t block_of(int x, int y) const { return std::size_t(y / kBlock) * blocks_x + x / kBlock; }
};

Ranking rank_blocks(const ApproximateFrame& f, const Changes& changes) {
    const PixelCache& cache = f.cache;
    const Camera& camera = f.camera;
    const packet::PinholeRays& pinhole = f.pinhole;
    const int width = f.width;
    const std::vector<std::uint8_t>& changed = changes.changed;
    const ChangedSpace space(changes.changed_boxes, changes.scale);
    tbb::combinable<ChangedSpace> nearby;
    Ranking ranking;
    ranking.blocks_x = (f.width + kBlock - 1) / kBlock;
    const int blocks_y = (f.height + kBlock - 1) / kBlock;
    ranking.level.assign(std::size_t(ranking.blocks_x) * blocks_y, 0);
    std::vector<std::uint16_t>& level = ranking.level;
    const auto block_of = [&](int x, int y) { return ranking.block_of(x, y); };
    tbb::combinable<std::array<std::size_t, kLevels>> histograms([] {
        std::array<std::size_t, kLevels> h{};
        return h;
    });
    tbb::parallel_for(0, f.tiling.count(), [&](int t) {
        const packet::Tile tile = f.tiling.tile(t);
    packet::LaneMask must;
    if (!space.empty()) {
        packet::RayPacket rays;
        pinhole.fill_tile(tile, rays);
        const glm::vec3 corners[4] = {
            rays.ray(packet::tile_lane(tile, tile.x0, tile.y0)).dir,
            rays.ray(packet::tile_lane(tile, tile.x1 - 1, tile.y0)).dir,
            rays.ray(packet::tile_lane(tile, tile.x0, tile.y1 - 1)).dir,
            rays.ray(packet::tile_lane(tile, tile.x1 - 1, tile.y1 - 1)).dir};
        ChangedSpace& near = nearby.local();
        if (space.select_pyramid(camera.eye, corners, near)) {
            alignas(64) float until[packet::kPacketRays];
            std::fill(std::begin(until), std::end(until), 0.0f);
            for (int y = tile.y0; y < tile.y1; ++y) {
                for (int x = tile.x0; x < tile.x1; ++x) {
                    const glm::vec3& q = cache.point[std::size_t(y) * width + x];
                    // A reprojected point is near, not on, the new ray: a little beyond.
                    until[packet::tile_lane(tile, x, y)] =
                        cache.object[std::size_t(y) * width + x] >= 0
                            ? 1.01f * glm::length(q - camera.eye)
                            : kInf;
                }
            }
            must = near.meets_rays(rays, until, rays.active);
        }
    }
    // Pixels are ranked, then traced, in 8x8 blocks: a block takes its most urgent pixel's
    // rank. Scattered single pixels would leave every packet sparse and incoherent (a 25%
    // budget of random pixels cost as much as tracing all of them on BART kitchen).
    std::array<std::size_t, kLevels>& histogram = histograms.local();
    for (int by = tile.y0; by < tile.y1; by += kBlock) {
        for (int bx = tile.x0; bx < tile.x1; bx += kBlock) {
            // A block ranks as a hole when a good part of it is one: scattered cracks
            // are filled well from their neighbours, and would otherwise put nearly every
            // block of a moving view above the oldest.
            int block_level = 0, holes = 0, inside = 0;
            for (int y = by; y < std::min(by + kBlock, tile.y1); ++y) {
                for (int x = bx; x < std::min(bx + kBlock, tile.x1); ++x) {
                    const std::size_t p = std::size_t(y) * width + x;
                    const std::int32_t object = cache.object[p];
                    const bool empty = cache.age[p] == PixelCache::kEmpty;
                    const bool shows_change =
                        !empty && object >= 0 &&
                        (std::size_t(object) >= changed.size() || changed[std::size_t(object)]);
                    ++inside;
                    holes += empty;
                    const int l = must.test(packet::tile_lane(tile, x, y)) || shows_change
                                      ? kChangedLevel
                                      : empty ? 0 : cache.age[p];
                    block_level = std::max(block_level, l);
                }
            }
            if (block_level < kHoleLevel && holes * kHoleShare >= inside) block_level = kHoleLevel + holes;
            level[block_of(bx, by)] = std::uint16_t(block_level);
            ++histogram[std::size_t(block_level)];
        }
    }
    });
    histograms.combine_each([&](const std::array<std::size_t, kLevels>& h) {
        for (int l = 0; l < kLevels; ++l) ranking.histogram[std::size_t(l)] += h[std::size_t(l)];
    });
    return ranking;
}

/// The blocks this frame traces: every block above the threshold rank, and of those at it,
/// the ones whose hash falls below the cut-off, so that the budget is met exactly.
struct Selection {
    const Ranking& ranking;
    int threshold = 0;
    std::uint64_t frame_seed = 0, cutoff = 0;

    bool operator()(int x, int y) const {
        const std::size_t b = ranking.block_of(x, y);
        const int level = ranking.level[b];
        return level > threshold || (level == threshold && hash(frame_seed ^ b) < cutoff);
    }
};

Selection choose_blocks(const ApproximateFrame& f, const Ranking& ranking) {
    const PixelCache& cache = f.cache;
    const TraceSettings& options = f.options;
    const std::size_t pixels = f.pixels;
    const bool render_cache = f.render_cache;
    const std::array<std::size_t, kLevels>& histogram = ranking.histogram;
    const std::vector<std::uint16_t>& level = ranking.level;
    std::size_t budget = pixels;
    if (options.reuse.budget_ms > 0.0) {
        if (cache.ns_per_pixel > 0.0) budget = std::size_t(options.reuse.budget_ms * 1e6 / cache.ns_per_pixel);
    } else {
        budget = std::size_t(std::ceil(double(options.reuse.budget_share) * double(pixels)));
    }
    // In blocks from here on.
    budget = (budget + kBlock * kBlock - 1) / (kBlock * kBlock);
    if (render_cache) budget = std::max(budget, histogram[kChangedLevel]);
    budget = std::clamp<std::size_t>(budget, 1, level.size());
    int threshold = kLevels - 1;
    std::size_t above = 0;
    while (threshold > 0 && above + histogram[std::size_t(threshold)] < budget) {
        above += histogram[std::size_t(threshold)];
        --threshold;
    }
    // Of the blocks at the threshold rank, those with the smallest hashes fill the budget
    // exactly: a random draw per frame, reproducible, and never short of the budget.
    const std::uint64_t frame_seed = (cache.frames + 1) * 0x632be59bd9b4e019ull;
    const std::size_t need = budget - std::min(budget, above);
    std::uint64_t cutoff = 0;  // blocks at the threshold rank with hash < cutoff are taken
    if (need > 0) {
        std::vector<std::uint32_t> hashes;
        hashes.reserve(histogram[std::size_t(threshold)]);
        for (std::size_t b = 0; b < level.size(); ++b) {
            if (level[b] == threshold) hashes.push_back(hash(frame_seed ^ b));
        }
        if (need >= hashes.size()) {
            cutoff = std::uint64_t{1} << 32;
        } else {
            std::nth_element(hashes.begin(), hashes.begin() + std::ptrdiff_t(need), hashes.end());
            cutoff = hashes[need];
        }
    }
    return Selection{ranking, threshold, frame_seed, cutoff};
}

/// The approximate modes' choice of rays for trace_tile (tile_pass.h): the selected pixels of
/// a tile traced into `out`, the others keeping what it holds, and the traced pixels' samples
/// stored in the cache.
class SelectedTile {
public:
    SelectedTile(const ApproximateFrame& f, const TilePass& pass, const Selection& selected,
                 const packet::Tile& tile, RenderedFrame& out)
        : f_(f), pass_(pass), selected_(selected), tile_(tile), out_(out) {}

    packet::LaneMask camera_lanes(TileRays&) {
        for (int y = tile_.y0; y < tile_.y1; ++y) {
            for (int x = tile_.x0; x < tile_.x1; ++x) {
                const std::size_t p = std::size_t(y) * f_.width + x;
                const int lane = packet::tile_lane(tile_, x, y);
                if (selected_(x, y)) {
                    lanes_.set(lane);
                    continue;
                }
                pass_.hits[p] = bvh::InstanceHit{};  // shaded as a miss, then restored
                kept_[std::size_t(lane)] = f_.options.hit_buffers
                                               ? Kept{out_.color[p], out_.normal[p], out_.depth[p],
                                                      out_.object[p], out_.prim[p]}
                                               : Kept{out_.color[p], glm::vec3(0.0f), 0.0f, 0, 0};
            }
        }
        return lanes_;
    }
    bool may_change(const packet::LaneMask& traced) { return traced.any(); }
    bool shadows(TileShadowOrigins& origins, const packet::LaneMask&, TileRays&,
                 std::vector<packet::LaneMask>& visible, StageWork& work) {
        packet::RayPacket shadow;
        work.add_shadows(trace_tile_shadows(pass_.in.tracer, RayCoherence::tile, origins, pass_.shading.lights,
                                            pass_.shading.glass, shadow, visible, pass_.trace_work(work)));
        return true;
    }
    /// What the pixels not traced showed restored, the traced ones' samples stored.
    void written(const TileShadowOrigins& origins, TileRays& rays, RenderedFrame& out);
    bool gathers_secondary() const { return false; }

private:
    /// A pixel's values as the frame held them before the tile was written.
    struct Kept {
        glm::vec3 color, normal;
        float depth;
        std::int32_t object, prim;
    };
    const ApproximateFrame& f_;
    const TilePass& pass_;
    const Selection& selected_;
    const packet::Tile& tile_;
    RenderedFrame& out_;
    packet::LaneMask lanes_;
    std::array<Kept, packet::kPacketRays> kept_;
};

void SelectedTile::written(const TileShadowOrigins& origins, TileRays& rays, RenderedFrame& out) {
    const bool hit_buffers = f_.options.hit_buffers;
    for (int lane = 0; lane < packet::kPacketRays; ++lane) {
        const packet::LanePixel px = packet::tile_pixel(tile_, lane);
        if (!px.inside) continue;
        const std::size_t p = std::size_t(px.y) * f_.width + px.x;
        if (!lanes_.test(lane)) {
            const Kept& k = kept_[std::size_t(lane)];
            out.color[p] = k.color;
            if (hit_buffers) {
                out.depth[p] = k.depth;
                out.normal[p] = k.normal;
                out.object[p] = k.object;
                out.prim[p] = k.prim;
            }
            continue;
        }
        // The traced sample, for the next frames.
        const bool hit = origins.surface.hit.test(lane);
        const bvh::InstanceHit& h = pass_.hits[p];
        store(f_.cache, p,
              Sample{out.color[p],
                     hit ? glm::vec3(origins.surface.point[0][lane], origins.surface.point[1][lane],
                                     origins.surface.point[2][lane])
                         : rays.get().ray(lane).dir,
                     hit ? glm::vec3(origins.surface.normal[0][lane], origins.surface.normal[1][lane],
                                     origins.surface.normal[2][lane])
                         : glm::vec3(0.0f),
                     hit ? std::int32_t(h.object) : -1, hit ? std::int32_t(h.hit.prim) : -1, 0});
    }
}

/// Holes left (pixels without a sample): the mean of their known neighbours, a few passes
/// out; the render cache keeps a crack's fill as a sample.
struct HoleFill {
    std::size_t holes = 0, filled = 0;
};

HoleFill fill_holes(const ApproximateFrame& f, RenderedFrame& out) {
    PixelCache& cache = f.cache;
    const Camera& camera = f.camera;
    const int width = f.width, height = f.height;
    const std::size_t pixels = f.pixels;
    const bool render_cache = f.render_cache;
    std::vector<std::uint8_t>& known = cache.known_scratch;
    known.resize(pixels);
    for_each_pixel(pixels, [&](std::size_t p) { known[p] = cache.age[p] != PixelCache::kEmpty; });
    const std::size_t holes = pixels - std::size_t(std::count(known.begin(), known.end(), 1));
    // A crack (a hole amid samples, where a nearing surface spread its samples apart) is kept
    // as a sample of the render cache: the nearest neighbour's surface (object, triangle,
    // normal, age) at the mean point of the neighbours on that surface, with the mean colour.
    // Otherwise the same cracks open again at every reprojection and take the budget.
    const auto keep_crack = [&](int x, int y) {
        const std::size_t p = std::size_t(y) * width + x;
        std::size_t nearest = p;
        float nearest_depth = kInf;
        for_each_neighbour(x, y, width, height, [&](std::size_t q) {
            if (!known[q]) return;
            const float d = cache.object[q] < 0 ? kInf : glm::length(cache.point[q] - camera.eye);
            if (nearest == p || d < nearest_depth) {
                nearest = q;
                nearest_depth = d;
            }
        });
        if (nearest == p) return;
        glm::vec3 point(0.0f);
        int on_surface = 0;
        for_each_neighbour(x, y, width, height, [&](std::size_t q) {
            if (!known[q] || cache.object[q] != cache.object[nearest]) return;
            if (cache.object[q] >= 0 &&
                kDepthCullRatio * glm::length(cache.point[q] - camera.eye) > nearest_depth) {
                return;
            }
            point += cache.point[q];
            ++on_surface;
        });
        Sample s = sample_at(cache, nearest);
        s.color = out.color[p];
        s.point = point / float(on_surface);
        if (s.object < 0) s.point = glm::normalize(s.point);  // a mean direction
        // Written at once: this pass reads only pixels that were known when it started.
        store(cache, p, s);
    };
    std::size_t filled = 0;
    for (int pass = 0; pass < 3 && filled < holes; ++pass) {
        std::vector<std::uint8_t>& next = cache.next_scratch;
        next = known;
        std::atomic<std::size_t> filled_now{0};
        tbb::parallel_for(0, height, [&](int y) {
            std::size_t filled_in_row = 0;
            for (int x = 0; x < width; ++x) {
                const std::size_t p = std::size_t(y) * width + x;
                if (known[p]) continue;
                glm::vec3 sum_color(0.0f);
                int n = 0;
                for_each_neighbour(x, y, width, height, [&](std::size_t q) {
                    if (!known[q]) return;
                    sum_color += out.color[q];
                    ++n;
                });
                if (n == 0) continue;
                out.color[p] = sum_color / float(n);
                next[p] = 1;
                ++filled_in_row;
                if (pass == 0 && render_cache && n >= kCrackNeighbours) keep_crack(x, y);
            }
            filled_now += filled_in_row;
        });
        filled += filled_now.load();
        known.swap(next);
    }

    return HoleFill{holes, filled};
}

}  // namespace

void trace_frame_approximate(const TraceInputs& in, const Camera& camera,
                             const TraceSettings& options, std::span<const bvh::Aabb> boxes,
                             std::span<const std::uint64_t> versions, PixelCache& cache,
                             TraceScratch& scratch, RenderedFrame& out) {
    const Stopwatch wall;
    const int width = options.width, height = options.height;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const packet::PinholeRays pinhole(camera, width, height);
    const packet::Tiling tiling(width, height);
    TraceStats& stats = out.stats;
    stats.reuse_mode = pixel_reuse_name(options.reuse.mode);
    stats.interpolated_pixels = 0;
    const ApproximateFrame f{in, camera, options, pinhole, tiling, cache, width, height, pixels,
                             options.reuse.mode == PixelReuse::render_cache};

    start_samples(f, boxes, stats);
    const Ranking ranking = rank_blocks(f, changes_since(f, boxes, versions));
    const Selection selected = choose_blocks(f, ranking);

    // ---- The frame as it stands, then the selected pixels traced into it ----
    size_frame(options, scratch, out);
    for_each_pixel(pixels, [&](std::size_t p) {
        out.color[p] = cache.color[p];
        if (!options.hit_buffers) return;
        const bool point = cache.age[p] != PixelCache::kEmpty && cache.object[p] >= 0;
        out.depth[p] = point ? glm::length(cache.point[p] - camera.eye) : kInf;
        out.object[p] = point ? cache.object[p] : -1;
        out.prim[p] = point ? cache.prim[p] : -1;
        out.normal[p] = point ? cache.normal[p] : glm::vec3(0.0f);
    });
    const double prepare_ms = wall.elapsed_ms();
    const TileShading shading = frame_shading(in, options, scratch);
    tbb::combinable<StageWork> work;
    const Stopwatch trace_clock;
    const TilePass pass{in, pinhole, shading, nullptr, scratch.hits, width, options.count_packet_work};
    tbb::parallel_for(0, tiling.count(), [&](int t) {
        const packet::Tile tile = tiling.tile(t);
        SelectedTile choice(f, pass, selected, tile, out);
        trace_tile(pass, t, tile, choice, work.local(), out);
    });
    const double trace_ms = trace_clock.elapsed_ms();
    const StageWork sum = work.combine([](StageWork a, const StageWork& b) { return a += b; });
    if (sum.primary_rays > 0) {
        const double ns = (prepare_ms + trace_ms) * 1e6 / double(sum.primary_rays);
        cache.ns_per_pixel = cache.ns_per_pixel > 0.0 ? 0.5 * (cache.ns_per_pixel + ns) : ns;
    }
    const HoleFill fill = fill_holes(f, out);

    // ---- Remember ----
    cache.valid = true;
    cache.camera = camera;
    cache.settings = options;
    cache.lights.assign(in.lights.begin(), in.lights.end());
    cache.object_boxes.assign(boxes.begin(), boxes.end());
    cache.object_versions.assign(versions.begin(), versions.end());
    ++cache.frames;

    const double wall_ms = wall.elapsed_ms();
    const double thread_total = sum.primary_ms + sum.shadow_ms + sum.shade_ms;
    const double scale_ms = thread_total > 0.0 ? trace_ms / thread_total : 0.0;
    // Ranking counts as choosing the primary rays; reprojection and filling as shading.
    stats.primary_ms = sum.primary_ms * scale_ms + prepare_ms * 0.5;
    stats.shadow_ms = sum.shadow_ms * scale_ms;
    stats.shade_ms = wall_ms - stats.primary_ms - stats.shadow_ms;
    stats.primary_rays = sum.primary_rays;
    stats.shadow_rays = sum.shadow_rays;
    stats.shadow_rays_back_side = sum.shadow_back_side;
    stats.shadow_rays_shading_side = sum.shadow_shading_side;
    stats.shadow_rays_dark_light = sum.shadow_dark_light;
    stats.pixels_traced = sum.primary_rays;
    stats.pixels_shadows_retraced = 0;
    stats.pixels_filled = fill.filled;
    stats.pixels_reused = pixels - sum.primary_rays - fill.holes;
    stats.primary_mrays_per_s = mrays_per_s(stats.primary_rays, stats.primary_ms);
    stats.shadow_mrays_per_s = mrays_per_s(stats.shadow_rays, stats.shadow_ms);
    if (options.count_packet_work) sum.trace.report(stats);
}

}  // namespace dynrt::detail
