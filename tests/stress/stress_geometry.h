#pragma once
// Closed meshes for the stress suite, made in code: a UV sphere with single pole vertices, a
// box with every face tessellated into a grid, and (from the unit tests) the subdivided
// icosahedron. Shared vertices are bit-identical because every triangle indexes one vertex
// array, and every transform below maps each vertex once, so transformed meshes stay closed.

#include "bvh_test_geometry.h"

#include "dynrt/bvh/triangle.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

namespace dynrt::stress {

using bvh::testing::ClosedMesh;

/// A UV sphere: `stacks` rings of `slices` quads, split into triangles, with one vertex per
/// pole (the rings next to the poles are fans). 2 * slices * (stacks - 1) triangles.
inline ClosedMesh uv_sphere_mesh(int slices, int stacks, float radius = 1.0f, glm::vec3 center = glm::vec3(0.0f)) {
    ClosedMesh m;
    m.vertices.push_back(center + glm::vec3(0.0f, radius, 0.0f));  // north pole
    for (int i = 1; i < stacks; ++i) {
        const double theta = std::numbers::pi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / slices;
            m.vertices.push_back(center + radius * glm::vec3(glm::dvec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                                       std::sin(theta) * std::sin(phi))));
        }
    }
    m.vertices.push_back(center + glm::vec3(0.0f, -radius, 0.0f));  // south pole
    const auto ring = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * slices + (j % slices)); };
    const auto south = std::uint32_t(m.vertices.size() - 1);
    for (int j = 0; j < slices; ++j) m.faces.push_back({0, ring(1, j + 1), ring(1, j)});
    for (int i = 1; i + 1 < stacks; ++i) {
        for (int j = 0; j < slices; ++j) {
            m.faces.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
            m.faces.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
        }
    }
    for (int j = 0; j < slices; ++j) m.faces.push_back({south, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
    return m;
}

/// The box [lo, hi] with each face an n x n grid of quads (two triangles each): 12 n^2
/// triangles. Vertices sit on the lattice lo + (hi - lo) * (i, j, k) / n, one per lattice point
/// of the surface, so face borders share theirs.
inline ClosedMesh box_mesh(int n, glm::vec3 lo = glm::vec3(-1.0f), glm::vec3 hi = glm::vec3(1.0f)) {
    ClosedMesh m;
    std::map<std::tuple<int, int, int>, std::uint32_t> index;
    const auto vertex = [&](int i, int j, int k) {
        const auto key = std::make_tuple(i, j, k);
        const auto it = index.find(key);
        if (it != index.end()) return it->second;
        const glm::vec3 f(float(i) / float(n), float(j) / float(n), float(k) / float(n));
        m.vertices.push_back(lo + (hi - lo) * f);
        const auto id = std::uint32_t(m.vertices.size() - 1);
        index.emplace(key, id);
        return id;
    };
    // Each face: a fixed axis at 0 or n, and two running axes (u, v) in right-handed order so
    // the normals point out.
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
            for (int u = 0; u < n; ++u) {
                for (int v = 0; v < n; ++v) {
                    const auto at = [&](int du, int dv) {
                        int c[3];
                        c[axis] = side * n;
                        c[ua] = u + du;
                        c[va] = v + dv;
                        return vertex(c[0], c[1], c[2]);
                    };
                    const std::uint32_t a = at(0, 0), b = at(1, 0), c = at(1, 1), d = at(0, 1);
                    if (side == 1) {
                        m.faces.push_back({a, b, c});
                        m.faces.push_back({a, c, d});
                    } else {
                        m.faces.push_back({a, c, b});
                        m.faces.push_back({a, d, c});
                    }
                }
            }
        }
    }
    return m;
}

/// `mesh` with every vertex mapped through p -> scale * p + offset in double, rounded to float
/// once per vertex (so the result is still closed).
inline ClosedMesh transformed(const ClosedMesh& mesh, double scale, glm::dvec3 offset) {
    ClosedMesh out = mesh;
    for (glm::vec3& v : out.vertices) v = glm::vec3(scale * glm::dvec3(v) + offset);
    return out;
}

/// The same for a general affine map (rounded once per vertex).
inline ClosedMesh transformed(const ClosedMesh& mesh, const glm::dmat4& m) {
    ClosedMesh out = mesh;
    for (glm::vec3& v : out.vertices) v = glm::vec3(glm::dvec3(m * glm::dvec4(glm::dvec3(v), 1.0)));
    return out;
}

/// Whether the triangles form closed surfaces: after welding vertices by their exact bits,
/// every undirected edge of a non-degenerate triangle is used an even number of times.
inline bool is_closed(std::span<const bvh::Triangle> tris) {
    using Key = std::tuple<float, float, float>;
    std::map<std::pair<Key, Key>, int> uses;
    for (const bvh::Triangle& t : tris) {
        if (bvh::is_degenerate(t)) continue;
        const glm::vec3 v[3] = {t.v0, t.v1, t.v2};
        for (int k = 0; k < 3; ++k) {
            Key a{v[k].x, v[k].y, v[k].z}, b{v[(k + 1) % 3].x, v[(k + 1) % 3].y, v[(k + 1) % 3].z};
            if (b < a) std::swap(a, b);
            ++uses[{a, b}];
        }
    }
    for (const auto& [edge, n] : uses) {
        if (n % 2 != 0) return false;
    }
    return !uses.empty();
}

/// Targets for rays from inside: every vertex, every edge midpoint and `along` more points
/// spread along each edge (at fractions k / (along + 1), k = 1..along, the midpoint included
/// only once when along is odd).
inline std::vector<glm::vec3> edge_and_vertex_targets(const ClosedMesh& mesh, int along) {
    std::vector<glm::vec3> out(mesh.vertices.begin(), mesh.vertices.end());
    for (const auto& [a, b] : mesh.edges()) {
        const glm::vec3 pa = mesh.vertices[a], pb = mesh.vertices[b];
        out.push_back(0.5f * (pa + pb));
        for (int k = 1; k <= along; ++k) {
            const float f = float(k) / float(along + 1);
            if (2 * k == along + 1) continue;
            out.push_back(glm::vec3(glm::dvec3(pa) + double(f) * (glm::dvec3(pb) - glm::dvec3(pa))));
        }
    }
    return out;
}

}  // namespace dynrt::stress
