#include "rendering/occluder_cache.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace dynrt::detail {

namespace {

constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

std::uint64_t pack(std::uint32_t instance, std::uint32_t prim) { return std::uint64_t(instance) << 32 | prim; }

}  // namespace

int OccluderCache::cell_of(float x, float y, float z) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return -1;
    const float d[3] = {x, y, z};
    const float a[3] = {std::fabs(x), std::fabs(y), std::fabs(z)};
    const int major = a[0] >= a[1] && a[0] >= a[2] ? 0 : a[1] >= a[2] ? 1 : 2;
    const float m = a[major];
    if (!(m > 0.0f)) return -1;
    // The other two coordinates over the major one, in [-1, 1], to cells.
    const auto index = [&](float c) {
        const int i = int((c / m + 1.0f) * (0.5f * float(kCellsPerSide)));
        return std::clamp(i, 0, kCellsPerSide - 1);
    };
    const int face = 2 * major + (d[major] < 0.0f ? 1 : 0);
    return (face * kCellsPerSide + index(d[(major + 1) % 3])) * kCellsPerSide + index(d[(major + 2) % 3]);
}

OccluderCache::Light* OccluderCache::light_at(const glm::vec3& origin) {
    // Bits compared as the tracer compares origins: a light is one position exactly.
    const auto same = [&](const Light& l) {
        return l.origin.x == origin.x && l.origin.y == origin.y && l.origin.z == origin.z &&
               std::signbit(l.origin.x) == std::signbit(origin.x) &&
               std::signbit(l.origin.y) == std::signbit(origin.y) &&
               std::signbit(l.origin.z) == std::signbit(origin.z);
    };
    const int known = light_count_.load(std::memory_order_acquire);
    for (int i = 0; i < known; ++i) {
        if (same(lights_[i])) return &lights_[i];
    }
    const std::lock_guard<std::mutex> lock(adding_);
    const int now = light_count_.load(std::memory_order_relaxed);
    for (int i = known; i < now; ++i) {
        if (same(lights_[i])) return &lights_[i];
    }
    if (now == kLightsMax) return nullptr;
    Light& light = lights_[now];
    light.origin = origin;
    light.cells = std::make_unique<std::atomic<std::uint64_t>[]>(std::size_t(kCells));
    for (int c = 0; c < kCells; ++c) light.cells[std::size_t(c)].store(kEmpty, std::memory_order_relaxed);
    light_count_.store(now + 1, std::memory_order_release);
    return &light;
}

void OccluderCache::guesses(const Light& light, const packet::RayPacket& rays, const SceneAccel& accel,
                            std::vector<packet::InstanceTriangle>& out) const {
    out.clear();
    const bvh::TwoLevelBvh& tlas = accel.top_level();
    std::uint64_t seen[kGuessesMax];
    int count = 0;
    int k = 0;
    bool all_held = true;
    rays.active.for_each([&](int lane) {
        if (k++ % kSampleStride != 0 || !all_held) return;
        const int cell = cell_of(rays.dir_x[lane], rays.dir_y[lane], rays.dir_z[lane]);
        const std::uint64_t entry = cell < 0 ? kEmpty : light.cells[std::size_t(cell)].load(std::memory_order_relaxed);
        if (entry == kEmpty || (count == kGuessesMax && std::find(seen, seen + count, entry) == seen + count)) {
            all_held = false;
            return;
        }
        if (std::find(seen, seen + count, entry) != seen + count) return;
        seen[count++] = entry;
        const auto instance = std::uint32_t(entry >> 32), prim = std::uint32_t(entry);
        if (instance >= tlas.instances.size()) return;
        const std::optional<bvh::Triangle> tri = accel.tree_triangle(tlas.instances[instance].object, prim);
        if (tri) out.push_back(packet::InstanceTriangle{instance, packet::PrimTriangle{*tri, prim}});
    });
    if (!all_held) out.clear();
}

void OccluderCache::learn(Light& light, const packet::RayPacket& rays, const packet::LaneMask& occluded,
                          const std::uint32_t* instance, const std::uint32_t* prim) {
    int k = 0;
    occluded.for_each([&](int lane) {
        if (k++ % kSampleStride != 0 || prim[lane] == bvh::kInvalidId) return;
        const int cell = cell_of(rays.dir_x[lane], rays.dir_y[lane], rays.dir_z[lane]);
        if (cell < 0) return;
        std::atomic<std::uint64_t>& slot = light.cells[std::size_t(cell)];
        const std::uint64_t entry = pack(instance[lane], prim[lane]);
        // Written only when it changes: the cells are shared by the threads.
        if (slot.load(std::memory_order_relaxed) != entry) slot.store(entry, std::memory_order_relaxed);
    });
}

}  // namespace dynrt::detail
