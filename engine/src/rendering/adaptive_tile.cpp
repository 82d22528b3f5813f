#include "adaptive_tile.h"

#include "dynrt/engine/stopwatch.h"
#include "rendering/tile_tracing.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace dynrt::detail {
namespace {

/// Samples every kSpacing pixels (and on the tile's last row and column). Measured on the
/// bundled scene: with 4 (25 samples, 16 cells per tile) the samples and the bookkeeping cost
/// more than the interpolated pixels save, since a packet traces a whole tile for little
/// more than a few scattered rays cost.
constexpr int kSpacing = 8;
constexpr int kMaxGrid = packet::kTileSize / kSpacing + 1;

/// The sample offsets along a tile side of `n` pixels: 0, 4, 8, ... and n - 1. Returns how many.
int grid_of(int n, int out[kMaxGrid]) {
    int count = 0;
    for (int k = 0; k < n; k += kSpacing) out[count++] = k;
    if (out[count - 1] != n - 1) out[count++] = n - 1;
    return count;
}

/// The last offset along one side that belongs to cell i (of n grid lines): a pixel on a grid
/// line inside the tile belongs to the cell that starts there, one on the last line to the last
/// cell.
int cell_end(const int grid[kMaxGrid], int n, int i) {
    return i + 2 == n ? grid[i + 1] : grid[i + 1] - 1;
}

/// Calls visit(dx, dy) for the tile offsets of the pixels of cell (i, j), samples included.
template <typename Visit>
void for_each_pixel_of_cell(const int gx[kMaxGrid], int nx, const int gy[kMaxGrid], int ny, int i,
                            int j, Visit&& visit) {
    for (int dy = gy[j]; dy <= cell_end(gy, ny, j); ++dy) {
        for (int dx = gx[i]; dx <= cell_end(gx, nx, i); ++dx) visit(dx, dy);
    }
}

/// The pyramid from the eye through four corner rays (in order around the quad), in double.
/// Holds every ray whose direction lies between them, so a box outside it cannot be hit by
/// any pixel ray of the quad.
class Frustum {
public:
    Frustum(const glm::dvec3& eye, const std::array<glm::dvec3, 4>& corners) : eye_(eye) {
        const glm::dvec3 centre = corners[0] + corners[1] + corners[2] + corners[3];
        for (int i = 0; i < 4; ++i) {
            glm::dvec3 n = glm::cross(corners[i], corners[(i + 1) % 4]);
            const double length = glm::length(n);
            n = length > 0.0 ? n / length : glm::dvec3(0.0);
            plane_[i] = glm::dot(n, centre) < 0.0 ? -n : n;
        }
    }

    /// True unless `box` lies entirely outside one side plane. The margin (1e-5 of the distance,
    /// in radians about 100 float ulps of a direction) covers the rounding of the float pixel
    /// rays, which may stray from the exact pyramid of the float corner rays.
    bool reaches(const bvh::Aabb& box) const {
        if (box.is_empty()) return false;
        for (const glm::dvec3& n : plane_) {
            const glm::dvec3 far(n.x >= 0.0 ? box.hi.x : box.lo.x, n.y >= 0.0 ? box.hi.y : box.lo.y,
                                 n.z >= 0.0 ? box.hi.z : box.lo.z);
            const glm::dvec3 to = far - eye_;
            if (glm::dot(n, to) < -1e-5 * glm::length(to)) return false;
        }
        return true;
    }

    /// Distance from the eye to the nearest point of `box` (0 inside it).
    double distance_to(const bvh::Aabb& box) const {
        const glm::dvec3 lo(box.lo), hi(box.hi);
        const glm::dvec3 nearest = glm::clamp(eye_, lo, hi);
        return glm::length(nearest - eye_);
    }

private:
    glm::dvec3 eye_;
    std::array<glm::dvec3, 4> plane_;
};

}  // namespace

void trace_tile_adaptive(const AdaptiveFrame& f, const packet::Tile& tile,
                         std::vector<bvh::InstanceHit>& hits, RenderedFrame& out,
                         StageWork& work, bool count) {
    TraceWork* trace_work = count ? &work.trace : nullptr;
    Stopwatch clock;
    const auto pixel_of = [&](int lane) {
        const packet::LanePixel px = packet::tile_pixel(tile, lane);
        return std::size_t(px.y) * std::size_t(f.width) + std::size_t(px.x);
    };
    int gx[kMaxGrid], gy[kMaxGrid];
    const int nx = grid_of(tile.x1 - tile.x0, gx), ny = grid_of(tile.y1 - tile.y0, gy);
    const auto lane_at = [&](int dx, int dy) { return packet::tile_lane(tile, tile.x0 + dx, tile.y0 + dy); };
    // Corner lanes of cell (i, j), around the quad: top left, top right, bottom right, bottom left.
    const auto corners_of = [&](int i, int j) {
        return std::array<int, 4>{lane_at(gx[i], gy[j]), lane_at(gx[i + 1], gy[j]),
                                  lane_at(gx[i + 1], gy[j + 1]), lane_at(gx[i], gy[j + 1])};
    };

    packet::RayPacket rays;
    f.pinhole.fill_tile(tile, rays);
    const packet::LaneMask all = rays.active;
    TileShadowOrigins origins;
    std::vector<packet::LaneMask> visible(f.lights.size());
    packet::RayPacket shadow;
    packet::ShadedColors colors;
    const auto trace_primary = [&](const packet::LaneMask& lanes) {
        rays.active = lanes;
        trace_tile_hits(f.tracer, tile, f.width, rays, hits, trace_work);
        rays.active = all;
        work.primary_rays += std::size_t(lanes.count());
    };
    const auto trace_shadows = [&] {
        work.shadow_rays += trace_tile_shadows(f.tracer, RayCoherence::tile, origins, f.lights,
                                               shadow, visible, trace_work);
    };
    // The exact path for the whole tile, as the renderer's packet tracer does it.
    const auto trace_whole_tile = [&] {
        trace_primary(all);
        work.primary_ms += clock.lap_ms();
        origins.compute(f.accel, hits, f.width, tile, rays, f.object_material);
        trace_shadows();
        work.shadow_ms += clock.lap_ms();
        shade_tile(f.shading, tile, origins, visible, hits, colors, out);
        work.shade_ms += clock.lap_ms();
    };
    if (nx < 2 || ny < 2) {  // a tile one pixel wide or high: no cells
        trace_whole_tile();
        return;
    }

    // ---- The samples, and what their hits alone say about each cell ----
    packet::LaneMask samples;
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) samples.set(lane_at(gx[i], gy[j]));
    }
    trace_primary(samples);
    work.primary_ms += clock.lap_ms();
    const auto hit_at = [&](int lane) -> const bvh::InstanceHit& { return hits[pixel_of(lane)]; };
    const glm::dvec3 eye(rays.org_x[0], rays.org_y[0], rays.org_z[0]);
    const auto frustum_of = [&](const std::array<int, 4>& lanes) {
        std::array<glm::dvec3, 4> d;
        for (int k = 0; k < 4; ++k) {
            d[k] = glm::dvec3(rays.dir_x[lanes[k]], rays.dir_y[lanes[k]], rays.dir_z[lanes[k]]);
        }
        return Frustum(eye, d);
    };
    const std::vector<bvh::Aabb>& boxes = f.accel.object_world_boxes();
    bool smooth = true;  // the whole tile, cell by cell
    for (int j = 0; j + 1 < ny && smooth; ++j) {
        for (int i = 0; i + 1 < nx && smooth; ++i) {
            const std::array<int, 4> c = corners_of(i, j);
            const std::uint32_t object = hit_at(c[0]).object;  // kInvalidId for a miss
            for (int k = 1; k < 4; ++k) smooth = smooth && hit_at(c[k]).object == object;
            if (!smooth) break;
            // Another object can show in the cell only where it reaches into the frustum;
            // for a cell on one object, only in front of that object's farthest corner hit
            // (the rays are unit, so t is distance). Behind it, only a fold of the object
            // itself could uncover it: the approximation.
            double farthest = std::numeric_limits<double>::infinity();
            if (object != bvh::kInvalidId) {
                farthest = 0.0;
                for (int k = 0; k < 4; ++k) farthest = std::max(farthest, double(hit_at(c[k]).hit.t));
                farthest *= 1.0 + 1e-5;
            }
            const Frustum cell = frustum_of(c);
            for (std::size_t k = 0; k < boxes.size() && smooth; ++k) {
                if (k == object) continue;
                smooth = !(cell.distance_to(boxes[k]) <= farthest && cell.reaches(boxes[k]));
            }
        }
    }
    work.shade_ms += clock.lap_ms();
    // A tile is interpolated whole or traced whole: tracing part of a tile costs about as much
    // as tracing all of it (a packet's cost is mostly per node, not per ray).
    if (!smooth) {
        trace_whole_tile();
        return;
    }

    // ---- The samples' shadows and colours ----
    origins.compute(f.accel, hits, f.width, tile, rays, f.object_material);
    trace_shadows();
    work.shadow_ms += clock.lap_ms();
    const packet::SurfacePacket& surface = origins.surface;
    shade_lanes(f.shading, origins, visible, colors);
    const auto color_of = [&](int lane) {
        return surface.hit.test(lane)
                   ? glm::vec3(colors.rgb[0][lane], colors.rgb[1][lane], colors.rgb[2][lane])
                   : f.shading.background;
    };
    const auto normal_of = [&](int lane) {
        return glm::vec3(surface.normal[0][lane], surface.normal[1][lane], surface.normal[2][lane]);
    };
    const float tol = f.tolerance;
    for (int j = 0; j + 1 < ny && smooth; ++j) {
        for (int i = 0; i + 1 < nx && smooth; ++i) {
            const std::array<int, 4> c = corners_of(i, j);
            if (!surface.hit.test(c[0])) continue;  // all four miss
            for (int k = 1; k < 4 && smooth; ++k) {
                for (const packet::LaneMask& v : visible) smooth = smooth && v.test(c[k]) == v.test(c[0]);
                const glm::vec3 diff = glm::abs(color_of(c[k]) - color_of(c[0]));
                smooth = smooth && glm::dot(normal_of(c[k]), normal_of(c[0])) >= 1.0f - tol &&
                         std::max(std::max(diff.x, diff.y), diff.z) <= tol;
            }
        }
    }
    work.shade_ms += clock.lap_ms();
    if (!smooth) {
        trace_whole_tile();
        return;
    }

    // ---- Every other pixel from its cell's corners ----
    const bool hit_buffers = !out.depth.empty();
    for (int j = 0; j + 1 < ny; ++j) {
        for (int i = 0; i + 1 < nx; ++i) {
            const std::array<int, 4> c = corners_of(i, j);
            const bool hit = surface.hit.test(c[0]);
            glm::vec3 color[4], normal[4];
            float depth[4];
            for (int k = 0; k < 4; ++k) {
                color[k] = color_of(c[k]);
                normal[k] = hit ? normal_of(c[k]) : glm::vec3(0.0f);
                depth[k] = hit_at(c[k]).hit.t;
            }
            const bvh::InstanceHit& first = hit_at(c[0]);
            const float width = float(gx[i + 1] - gx[i]), height = float(gy[j + 1] - gy[j]);
            for_each_pixel_of_cell(gx, nx, gy, ny, i, j, [&](int dx, int dy) {
                const bool sample = samples.test(lane_at(dx, dy));
                const float fx = float(dx - gx[i]) / width, fy = float(dy - gy[j]) / height;
                const float weight[4] = {(1.0f - fx) * (1.0f - fy), fx * (1.0f - fy), fx * fy,
                                         (1.0f - fx) * fy};
                const std::size_t p = std::size_t(tile.y0 + dy) * std::size_t(f.width) +
                                      std::size_t(tile.x0 + dx);
                // Samples take their own values: the weights of a corner are exactly 1 and 0.
                out.color[p] = weight[0] * color[0] + weight[1] * color[1] +
                               weight[2] * color[2] + weight[3] * color[3];
                if (!sample) ++work.interpolated;
                if (!hit_buffers) return;
                if (!hit) {
                    write_miss(out, p);
                    return;
                }
                const bvh::InstanceHit& own = sample ? hit_at(lane_at(dx, dy)) : first;
                out.depth[p] = weight[0] * depth[0] + weight[1] * depth[1] +
                               weight[2] * depth[2] + weight[3] * depth[3];
                out.object[p] = std::int32_t(own.object);
                out.prim[p] = std::int32_t(own.hit.prim);
                out.normal[p] = glm::normalize(weight[0] * normal[0] + weight[1] * normal[1] +
                                               weight[2] * normal[2] + weight[3] * normal[3]);
            });
        }
    }
    work.shade_ms += clock.lap_ms();
}

}  // namespace dynrt::detail
