#include "adaptive_tile.h"

#include "dynrt/packet/two_level_packet.h"
#include "stopwatch.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace dynrt::detail {
namespace {

/// Samples every kSpacing pixels (and on the tile's last row and column).
constexpr int kSpacing = 4;
constexpr int kMaxGrid = packet::kTileSize / kSpacing + 1;

/// The sample offsets along a tile side of `n` pixels: 0, 4, 8, ... and n - 1. Returns how many.
int grid_of(int n, int out[kMaxGrid]) {
    int count = 0;
    for (int k = 0; k < n; k += kSpacing) out[count++] = k;
    if (out[count - 1] != n - 1) out[count++] = n - 1;
    return count;
}

/// The cell (index of its first grid line) that offset `d` falls in, given `n` >= 2 lines.
int cell_of(const int grid[kMaxGrid], int n, int d) {
    int i = 0;
    while (i + 1 < n - 1 && grid[i + 1] <= d) ++i;
    return i;
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
                         AdaptiveTileWork& work, packet::PacketStats* stats) {
    Stopwatch clock;
    const bvh::TwoLevelBvh& top = f.accel.top_level();
    const auto pixel_of = [&](int lane) {
        const packet::LanePixel px = packet::tile_pixel(tile, lane);
        return std::size_t(px.y) * std::size_t(f.width) + std::size_t(px.x);
    };
    int gx[kMaxGrid], gy[kMaxGrid];
    const int nx = grid_of(tile.x1 - tile.x0, gx), ny = grid_of(tile.y1 - tile.y0, gy);
    const auto lane_at = [&](int dx, int dy) { return packet::tile_lane(tile, tile.x0 + dx, tile.y0 + dy); };

    // ---- Pass 1: the samples ----
    packet::RayPacket rays;
    f.pinhole.fill_tile(tile, rays);
    const packet::LaneMask all = rays.active;
    packet::LaneMask samples;
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) samples.set(lane_at(gx[i], gy[j]));
    }
    packet::InstanceHits packet_hits;
    const auto trace_primary = [&](const packet::LaneMask& lanes) {
        rays.active = lanes;
        packet::intersect_closest(top, rays, packet_hits, f.packet, stats);
        for (int lane = 0; lane < packet::kPacketRays; ++lane) {
            if (!lanes.test(lane)) continue;
            bvh::InstanceHit& hit = hits[pixel_of(lane)];
            hit = packet_hits.hit(lane);
            f.accel.resolve(hit);
        }
        work.primary_rays += std::size_t(lanes.count());
    };
    for (int lane = 0; lane < packet::kPacketRays; ++lane) {
        if (all.test(lane)) hits[pixel_of(lane)] = bvh::InstanceHit{};
    }
    trace_primary(samples);
    work.primary_ms += clock.lap_ms();

    TileShadowOrigins origins;
    origins.compute(f.accel, hits, f.width, tile, rays, f.object_material);
    std::vector<packet::LaneMask> visible(f.lights.size());
    packet::RayPacket shadow;
    const auto trace_shadows = [&](const packet::LaneMask& lanes) {
        for (std::size_t l = 0; l < f.lights.size() && origins.surface.hit.any(); ++l) {
            origins.rays_to(f.lights[l], shadow);
            for (int k = 0; k < packet::kPacketRays / 64; ++k) shadow.active.words[k] &= lanes.words[k];
            if (!shadow.active.any()) continue;
            work.shadow_rays += std::size_t(shadow.active.count());
            packet::LaneMask occluded;
            packet::intersect_any(top, shadow, occluded, f.packet, stats);
            for (int k = 0; k < packet::kPacketRays / 64; ++k) {
                visible[l].words[k] |= shadow.active.words[k] & ~occluded.words[k];
            }
        }
    };
    trace_shadows(samples);
    work.shadow_ms += clock.lap_ms();

    // ---- Which cells the samples describe well enough ----
    const packet::SurfacePacket& surface = origins.surface;
    packet::ShadedColors corner_colors;
    if (surface.hit.any()) {
        packet::shade(surface, f.shading.materials, f.shading.lights, visible, f.shading.ambient,
                      corner_colors, f.shading.lanes);
    }
    const auto color_of = [&](const packet::ShadedColors& c, int lane) {
        return surface.hit.test(lane) ? glm::vec3(c.rgb[0][lane], c.rgb[1][lane], c.rgb[2][lane])
                                      : f.shading.background;
    };
    const auto normal_of = [&](int lane) {
        return glm::vec3(surface.normal[0][lane], surface.normal[1][lane], surface.normal[2][lane]);
    };
    // Corner lanes of cell (i, j), around the quad: top left, top right, bottom right, bottom left.
    const auto corners_of = [&](int i, int j) {
        return std::array<int, 4>{lane_at(gx[i], gy[j]), lane_at(gx[i + 1], gy[j]),
                                  lane_at(gx[i + 1], gy[j + 1]), lane_at(gx[i], gy[j + 1])};
    };
    bool smooth[kMaxGrid][kMaxGrid] = {};
    if (nx >= 2 && ny >= 2) {
        const glm::dvec3 eye(rays.org_x[0], rays.org_y[0], rays.org_z[0]);
        const auto frustum_of = [&](const std::array<int, 4>& lanes) {
            std::array<glm::dvec3, 4> d;
            for (int k = 0; k < 4; ++k) {
                d[k] = glm::dvec3(rays.dir_x[lanes[k]], rays.dir_y[lanes[k]], rays.dir_z[lanes[k]]);
            }
            return Frustum(eye, d);
        };
        // The objects that reach into the tile at all; each cell checks only these.
        const std::vector<bvh::Aabb>& boxes = f.accel.object_world_boxes();
        const int w = tile.x1 - tile.x0 - 1, h = tile.y1 - tile.y0 - 1;
        const Frustum tile_frustum =
            frustum_of({lane_at(0, 0), lane_at(w, 0), lane_at(w, h), lane_at(0, h)});
        std::vector<std::uint32_t> reaching;
        for (std::size_t k = 0; k < boxes.size(); ++k) {
            if (tile_frustum.reaches(boxes[k])) reaching.push_back(std::uint32_t(k));
        }
        const float tol = f.tolerance;
        for (int j = 0; j + 1 < ny; ++j) {
            for (int i = 0; i + 1 < nx; ++i) {
                const std::array<int, 4> c = corners_of(i, j);
                const bool hit = surface.hit.test(c[0]);
                std::uint32_t object = bvh::kInvalidId;
                bool agree = true;
                if (hit) object = hits[pixel_of(c[0])].object;
                for (int k = 1; k < 4 && agree; ++k) {
                    if (surface.hit.test(c[k]) != hit) {
                        agree = false;
                    } else if (hit) {
                        agree = hits[pixel_of(c[k])].object == object &&
                                glm::dot(normal_of(c[k]), normal_of(c[0])) >= 1.0f - tol;
                        for (std::size_t l = 0; l < visible.size() && agree; ++l) {
                            agree = visible[l].test(c[k]) == visible[l].test(c[0]);
                        }
                        const glm::vec3 diff = glm::abs(color_of(corner_colors, c[k]) -
                                                        color_of(corner_colors, c[0]));
                        agree = agree && std::max(std::max(diff.x, diff.y), diff.z) <= tol;
                    }
                }
                if (agree) {
                    // Another object can show in the cell only where it reaches into the
                    // frustum; for a cell on one object, only in front of that object's
                    // farthest corner hit (the rays are unit, so t is distance). Behind it,
                    // only a fold of the object itself could uncover it: the approximation.
                    double farthest = std::numeric_limits<double>::infinity();
                    if (hit) {
                        farthest = 0.0;
                        for (int k = 0; k < 4; ++k) {
                            farthest = std::max(farthest, double(hits[pixel_of(c[k])].hit.t));
                        }
                        farthest *= 1.0 + 1e-5;
                    }
                    const Frustum cell = frustum_of(c);
                    for (std::uint32_t k : reaching) {
                        if (k != object && cell.distance_to(boxes[k]) <= farthest &&
                            cell.reaches(boxes[k])) {
                            agree = false;
                            break;
                        }
                    }
                }
                smooth[j][i] = agree;

            }
        }
    }
    // Every pixel that is not a sample and not in a smooth cell is traced.
    packet::LaneMask refine;
    for (int lane = 0; lane < packet::kPacketRays; ++lane) {
        if (!all.test(lane) || samples.test(lane)) continue;
        const packet::LanePixel px = packet::tile_pixel(tile, lane);
        const bool in_smooth_cell = nx >= 2 && ny >= 2 &&
                                    smooth[cell_of(gy, ny, px.y - tile.y0)][cell_of(gx, nx, px.x - tile.x0)];
        if (!in_smooth_cell) refine.set(lane);
    }
    work.shade_ms += clock.lap_ms();

    // ---- Pass 2: the cells the samples do not describe ----
    if (refine.any()) {
        trace_primary(refine);
        work.primary_ms += clock.lap_ms();
        origins.compute(f.accel, hits, f.width, tile, rays, f.object_material);
        trace_shadows(refine);
        work.shadow_ms += clock.lap_ms();
    }

    // ---- Shading: traced pixels as in the exact path, then the interpolated ones ----
    packet::ShadedColors colors;
    shade_tile(f.shading, tile, origins, visible, hits, colors, out);
    const bool hit_buffers = !out.depth.empty();
    for (int lane = 0; lane < packet::kPacketRays; ++lane) {
        if (!all.test(lane) || samples.test(lane) || refine.test(lane)) continue;
        const packet::LanePixel px = packet::tile_pixel(tile, lane);
        const int i = cell_of(gx, nx, px.x - tile.x0), j = cell_of(gy, ny, px.y - tile.y0);
        const std::array<int, 4> c = corners_of(i, j);
        const float fx = float(px.x - tile.x0 - gx[i]) / float(gx[i + 1] - gx[i]);
        const float fy = float(px.y - tile.y0 - gy[j]) / float(gy[j + 1] - gy[j]);
        const float weight[4] = {(1.0f - fx) * (1.0f - fy), fx * (1.0f - fy), fx * fy,
                                 (1.0f - fx) * fy};
        const std::size_t p = std::size_t(px.y) * std::size_t(f.width) + std::size_t(px.x);
        glm::vec3 color(0.0f);
        for (int k = 0; k < 4; ++k) color += weight[k] * color_of(corner_colors, c[k]);
        out.color[p] = color;
        ++work.interpolated;
        if (!hit_buffers || !surface.hit.test(c[0])) continue;  // a miss is already written
        float depth = 0.0f;
        glm::vec3 normal(0.0f);
        for (int k = 0; k < 4; ++k) {
            depth += weight[k] * hits[pixel_of(c[k])].hit.t;
            normal += weight[k] * normal_of(c[k]);
        }
        const bvh::InstanceHit& first = hits[pixel_of(c[0])];
        out.depth[p] = depth;
        out.object[p] = std::int32_t(first.object);
        out.prim[p] = std::int32_t(first.hit.prim);
        out.normal[p] = glm::normalize(normal);
    }
    work.shade_ms += clock.lap_ms();
}

}  // namespace dynrt::detail
