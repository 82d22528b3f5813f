// The exact mesh definitions of scenes/README.md, "Procedural scenes". Every floating-point step
// below is the one the README spells out, in the same order and precision.

#include "procedural_meshes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace dynrt {

namespace {

// The double nearest pi, 3.141592653589793 (M_PI).
constexpr double kPi = std::numbers::pi;

constexpr std::uint64_t kSaturated = std::numeric_limits<std::uint64_t>::max();

}  // namespace

std::uint64_t SplitMix64::next() {
    state_ += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

float SplitMix64::next_unit_float() {
    // 24 bits fill a float significand exactly, so the value is k / 2^24 with no rounding.
    return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f);
}

std::uint64_t sphere_stack_count(std::uint64_t n) {
    const double s = std::round((1.0 + std::sqrt(1.0 + static_cast<double>(n))) / 2.0);
    return std::max<std::uint64_t>(2, static_cast<std::uint64_t>(s));
}

std::uint64_t sphere_triangle_count(std::uint64_t n) {
    const std::uint64_t s = sphere_stack_count(n);
    if (s > (1ull << 30)) return kSaturated;
    return 4 * s * (s - 1);
}

std::uint64_t soup_triangle_count(std::uint64_t n) { return n; }

std::uint64_t plane_triangle_count(std::uint64_t n) {
    if (n > (1ull << 31)) return kSaturated;
    return 2 * n * n;
}

Mesh make_sphere_mesh(std::uint64_t n) {
    const std::uint64_t stacks = sphere_stack_count(n);
    const std::uint64_t slices = 2 * stacks;
    const std::uint64_t last = 1 + (stacks - 1) * slices;
    // Vertex of ring k (1..S-1), slice j (0..L-1; L wraps to 0).
    const auto ring = [&](std::uint64_t k, std::uint64_t j) {
        return static_cast<std::uint32_t>(1 + (k - 1) * slices + j % slices);
    };

    Mesh mesh;
    mesh.positions.reserve(last + 1);
    mesh.positions.emplace_back(0.0f, 1.0f, 0.0f);
    for (std::uint64_t k = 1; k < stacks; ++k) {
        const double theta = kPi * static_cast<double>(k) / static_cast<double>(stacks);
        for (std::uint64_t j = 0; j < slices; ++j) {
            const double phi = 2.0 * kPi * static_cast<double>(j) / static_cast<double>(slices);
            mesh.positions.emplace_back(static_cast<float>(std::sin(theta) * std::cos(phi)),
                                        static_cast<float>(std::cos(theta)),
                                        static_cast<float>(std::sin(theta) * std::sin(phi)));
        }
    }
    mesh.positions.emplace_back(0.0f, -1.0f, 0.0f);

    mesh.triangles.reserve(2 * slices * (stacks - 1));
    for (std::uint64_t j = 0; j < slices; ++j) mesh.triangles.emplace_back(0, ring(1, j + 1), ring(1, j));
    for (std::uint64_t k = 1; k + 1 < stacks; ++k) {
        for (std::uint64_t j = 0; j < slices; ++j) {
            const std::uint32_t a = ring(k, j), b = ring(k, j + 1);
            const std::uint32_t c = ring(k + 1, j), d = ring(k + 1, j + 1);
            mesh.triangles.emplace_back(a, b, d);
            mesh.triangles.emplace_back(a, d, c);
        }
    }
    for (std::uint64_t j = 0; j < slices; ++j) {
        mesh.triangles.emplace_back(ring(stacks - 1, j), ring(stacks - 1, j + 1),
                                    static_cast<std::uint32_t>(last));
    }
    return mesh;
}

Mesh make_soup_mesh(std::uint64_t n) {
    SplitMix64 rng(1);
    const float edge = 2.0f / std::cbrt(static_cast<float>(n));
    // centre + edge * (u - 0.5) with the product rounded to float before the sum, as defined.
    // GCC would contract this into one FMA (rounding once, changing the bits); the project
    // builds with -ffp-contract=off for exactly this reason (see the top-level CMakeLists.txt).
    const auto jitter = [&](float centre) {
        const float u = rng.next_unit_float();
        return centre + edge * (u - 0.5f);
    };

    Mesh mesh;
    mesh.positions.reserve(3 * n);
    mesh.triangles.reserve(n);
    for (std::uint64_t i = 0; i < n; ++i) {
        const float cx = rng.next_unit_float();
        const float cy = rng.next_unit_float();
        const float cz = rng.next_unit_float();
        for (int v = 0; v < 3; ++v) {
            // Separate statements fix the draw order x, y, z (argument order is unspecified).
            const float x = jitter(cx);
            const float y = jitter(cy);
            const float z = jitter(cz);
            mesh.positions.emplace_back(x, y, z);
        }
        const auto first = static_cast<std::uint32_t>(3 * i);
        mesh.triangles.emplace_back(first, first + 1, first + 2);
    }
    return mesh;
}

Mesh make_plane_mesh(std::uint64_t n) {
    const std::uint64_t row = n + 1;
    // Grid line g at float(2g - N) / float(N): one correctly rounded division of two exact
    // integers, so the grid is symmetric and any tool gets the same bits.
    const auto grid = [&](std::uint64_t g) {
        return static_cast<float>(2 * static_cast<std::int64_t>(g) - static_cast<std::int64_t>(n)) /
               static_cast<float>(n);
    };
    const auto vertex = [&](std::uint64_t r, std::uint64_t c) {
        return static_cast<std::uint32_t>(r * row + c);
    };

    Mesh mesh;
    mesh.positions.reserve(row * row);
    for (std::uint64_t r = 0; r <= n; ++r) {
        for (std::uint64_t c = 0; c <= n; ++c) mesh.positions.emplace_back(grid(c), 0.0f, grid(r));
    }
    mesh.triangles.reserve(2 * n * n);
    for (std::uint64_t r = 0; r < n; ++r) {
        for (std::uint64_t c = 0; c < n; ++c) {
            const std::uint32_t a = vertex(r, c), b = vertex(r, c + 1);
            const std::uint32_t cc = vertex(r + 1, c), d = vertex(r + 1, c + 1);
            // (a, c, d) and (a, d, b) wind counter-clockwise seen from +Y: normal +Y.
            mesh.triangles.emplace_back(a, cc, d);
            mesh.triangles.emplace_back(a, d, b);
        }
    }
    return mesh;
}

}  // namespace dynrt
