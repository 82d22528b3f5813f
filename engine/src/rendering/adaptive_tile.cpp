#include "adaptive_tile.h"

#include "dynrt/engine/stopwatch.h"
#include "rendering/tile_pass.h"

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

namespace {

/// One tile under adaptive sampling: its sample grid, camera rays and the state its stages
/// share (trace_tile_adaptive).
class AdaptiveTile {
public:
    AdaptiveTile(const AdaptiveFrame& frame, int index, const packet::Tile& tile, RenderedFrame& out,
                 StageWork& work)
        : f_(frame.pass), tolerance_(frame.tolerance), index_(index), tile_(tile), hits_(frame.pass.hits),
          out_(out), work_(work), trace_work_(frame.pass.trace_work(work)),
          visible_(frame.pass.in.lights.size()) {
        nx_ = grid_of(tile.x1 - tile.x0, gx_);
        ny_ = grid_of(tile.y1 - tile.y0, gy_);
        f_.pinhole.fill_tile(tile, rays_);
        all_ = rays_.active;
    }

    void run() {
        if (nx_ < 2 || ny_ < 2) {  // a tile one pixel wide or high: no cells
            trace_whole_tile();
            return;
        }
        for (int j = 0; j < ny_; ++j) {
            for (int i = 0; i < nx_; ++i) samples_.set(lane_at(gx_[i], gy_[j]));
        }
        trace_primary(samples_);
        work_.primary_ms += clock_.lap_ms();
        // A tile is interpolated whole or traced whole: tracing part of a tile costs about as
        // much as tracing all of it (a packet's cost is mostly per node, not per ray).
        const bool one_object_per_cell = cells_see_one_object();
        work_.shade_ms += clock_.lap_ms();
        if (!one_object_per_cell) {
            trace_whole_tile();
            return;
        }
        // The samples' shadows and colours.
        origins_.compute(f_.in.accel, hits_, f_.width, tile_, rays_, f_.in.object_material);
        f_.sample_lights(tile_, origins_);
        trace_shadows();
        work_.shadow_ms += clock_.lap_ms();
        shade_lanes(f_.shading, origins_, visible_, colors_);
        const bool smooth = cells_shade_alike();
        work_.shade_ms += clock_.lap_ms();
        if (!smooth) {
            trace_whole_tile();
            return;
        }
        interpolate();
        work_.shade_ms += clock_.lap_ms();
    }

private:
    const TilePass& f_;
    float tolerance_;
    int index_;
    const packet::Tile& tile_;
    std::vector<bvh::InstanceHit>& hits_;
    RenderedFrame& out_;
    StageWork& work_;
    TraceWork* trace_work_;
    Stopwatch clock_;
    int gx_[kMaxGrid], gy_[kMaxGrid];
    int nx_ = 0, ny_ = 0;
    packet::RayPacket rays_;
    packet::LaneMask all_, samples_;
    TileShadowOrigins origins_;
    std::vector<packet::LaneMask> visible_;
    packet::RayPacket shadow_;
    packet::ShadedColors colors_;

    int lane_at(int dx, int dy) const { return packet::tile_lane(tile_, tile_.x0 + dx, tile_.y0 + dy); }
    /// Corner lanes of cell (i, j), around the quad: top left, top right, bottom right, bottom left.
    std::array<int, 4> corners_of(int i, int j) const {
        return std::array<int, 4>{lane_at(gx_[i], gy_[j]), lane_at(gx_[i + 1], gy_[j]),
                                  lane_at(gx_[i + 1], gy_[j + 1]), lane_at(gx_[i], gy_[j + 1])};
    }
    const bvh::InstanceHit& hit_at(int lane) const {
        const packet::LanePixel px = packet::tile_pixel(tile_, lane);
        return hits_[std::size_t(px.y) * std::size_t(f_.width) + std::size_t(px.x)];
    }
    glm::vec3 color_of(int lane) const {
        return origins_.surface.hit.test(lane)
                   ? glm::vec3(colors_.rgb[0][lane], colors_.rgb[1][lane], colors_.rgb[2][lane])
                   : f_.shading.miss(-glm::vec3(origins_.surface.view[0][lane], origins_.surface.view[1][lane],
                                                origins_.surface.view[2][lane]));
    }
    glm::vec3 normal_of(int lane) const {
        const packet::SurfacePacket& s = origins_.surface;
        return glm::vec3(s.normal[0][lane], s.normal[1][lane], s.normal[2][lane]);
    }

    void trace_primary(const packet::LaneMask& lanes) {
        rays_.active = lanes;
        trace_tile_hits(f_.in.tracer, tile_, f_.width, rays_, hits_, trace_work_);
        rays_.active = all_;
        work_.primary_rays += std::size_t(lanes.count());
    }
    void trace_shadows() {
        work_.add_shadows(trace_tile_shadows(f_.in.tracer, RayCoherence::tile, origins_, f_.shading.lights,
                                             f_.shading.glass, shadow_, visible_, trace_work_));
    }
    /// The exact path for the whole tile: the full frame's tile pass.
    void trace_whole_tile() {
        EveryRay every{f_};
        trace_tile(f_, index_, tile_, every, work_, out_);
    }

    /// What the samples' hits alone say: every cell's four corners hit one object (or all
    /// miss) and no other object's box reaches into the cell's frustum in front of them.
    bool cells_see_one_object() const {
        const glm::dvec3 eye(rays_.org_x[0], rays_.org_y[0], rays_.org_z[0]);
        const std::vector<bvh::Aabb>& boxes = f_.in.accel.object_world_boxes();
        for (int j = 0; j + 1 < ny_; ++j) {
            for (int i = 0; i + 1 < nx_; ++i) {
                const std::array<int, 4> c = corners_of(i, j);
                const std::uint32_t object = hit_at(c[0]).object;  // kInvalidId for a miss
                for (int k = 1; k < 4; ++k) {
                    if (hit_at(c[k]).object != object) return false;
                }
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
                std::array<glm::dvec3, 4> d;
                for (int k = 0; k < 4; ++k) {
                    d[k] = glm::dvec3(rays_.dir_x[c[k]], rays_.dir_y[c[k]], rays_.dir_z[c[k]]);
                }
                const Frustum cell(eye, d);
                for (std::size_t k = 0; k < boxes.size(); ++k) {
                    if (k == object) continue;
                    if (cell.distance_to(boxes[k]) <= farthest && cell.reaches(boxes[k])) return false;
                }
            }
        }
        return true;
    }

    /// Every hit cell's corners are lit by the same lights and agree within the tolerance in
    /// normal and colour.
    bool cells_shade_alike() const {
        const packet::SurfacePacket& surface = origins_.surface;
        const float tol = tolerance_;
        for (int j = 0; j + 1 < ny_; ++j) {
            for (int i = 0; i + 1 < nx_; ++i) {
                const std::array<int, 4> c = corners_of(i, j);
                if (!surface.hit.test(c[0])) continue;  // all four miss
                for (int k = 1; k < 4; ++k) {
                    for (const packet::LaneMask& v : visible_) {
                        if (v.test(c[k]) != v.test(c[0])) return false;
                    }
                    const glm::vec3 diff = glm::abs(color_of(c[k]) - color_of(c[0]));
                    // Written so that a NaN fails it.
                    const bool alike = glm::dot(normal_of(c[k]), normal_of(c[0])) >= 1.0f - tol &&
                                       std::max(std::max(diff.x, diff.y), diff.z) <= tol;
                    if (!alike) return false;
                }
            }
        }
        return true;
    }

    /// Every other pixel from its cell's corners.
    void interpolate() {
        const bool hit_buffers = !out_.depth.empty();
        for (int j = 0; j + 1 < ny_; ++j) {
            for (int i = 0; i + 1 < nx_; ++i) {
                const std::array<int, 4> c = corners_of(i, j);
                const bool hit = origins_.surface.hit.test(c[0]);
                glm::vec3 color[4], normal[4];
                float depth[4];
                for (int k = 0; k < 4; ++k) {
                    color[k] = color_of(c[k]);
                    normal[k] = hit ? normal_of(c[k]) : glm::vec3(0.0f);
                    depth[k] = hit_at(c[k]).hit.t;
                }
                const bvh::InstanceHit& first = hit_at(c[0]);
                const float width = float(gx_[i + 1] - gx_[i]), height = float(gy_[j + 1] - gy_[j]);
                for_each_pixel_of_cell(gx_, nx_, gy_, ny_, i, j, [&](int dx, int dy) {
                    const bool sample = samples_.test(lane_at(dx, dy));
                    const float fx = float(dx - gx_[i]) / width, fy = float(dy - gy_[j]) / height;
                    const float weight[4] = {(1.0f - fx) * (1.0f - fy), fx * (1.0f - fy), fx * fy,
                                             (1.0f - fx) * fy};
                    const std::size_t p = std::size_t(tile_.y0 + dy) * std::size_t(f_.width) +
                                          std::size_t(tile_.x0 + dx);
                    // Samples take their own values: the weights of a corner are exactly 1 and 0.
                    out_.color[p] = weight[0] * color[0] + weight[1] * color[1] +
                                    weight[2] * color[2] + weight[3] * color[3];
                    if (!sample) ++work_.interpolated;
                    if (!hit_buffers) return;
                    if (!hit) {
                        write_miss(out_, p);
                        return;
                    }
                    const bvh::InstanceHit& own = sample ? hit_at(lane_at(dx, dy)) : first;
                    out_.depth[p] = weight[0] * depth[0] + weight[1] * depth[1] +
                                    weight[2] * depth[2] + weight[3] * depth[3];
                    out_.object[p] = std::int32_t(own.object);
                    out_.prim[p] = std::int32_t(own.hit.prim);
                    out_.normal[p] = glm::normalize(weight[0] * normal[0] + weight[1] * normal[1] +
                                                    weight[2] * normal[2] + weight[3] * normal[3]);
                });
            }
        }
    }
};

}  // namespace

void trace_tile_adaptive(const AdaptiveFrame& frame, int index, const packet::Tile& tile,
                         RenderedFrame& out, StageWork& work) {
    AdaptiveTile(frame, index, tile, out, work).run();
}

}  // namespace dynrt::detail
