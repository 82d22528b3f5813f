#pragma once
// What a build or a refit reads its triangles from: the caller's array of triangles, indexed
// meshes (vertices and index triples; several meshes are numbered one after another), or a
// soup's vertices, three per triangle in order. A caller that holds indexed geometry, as a
// scene does, can then build without first gathering a copy of every triangle (36 bytes each,
// at the build's peak). Either way a triangle reads the same floats, so the tree is the same
// bit for bit.

#include "dynrt/bvh/prefetch.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/triangle.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dynrt::bvh {

class TriangleSource {
public:
    /// One mesh: triangle t's corners are positions[triangles[t].x], .y and .z. Every index
    /// must be within positions (the caller's to check, as for its own gathers).
    struct IndexedMesh {
        std::span<const glm::vec3> positions;
        std::span<const glm::uvec3> triangles;
    };

    /// No triangles.
    TriangleSource() = default;
    /// The caller's triangles, viewed (they must outlive the source).
    TriangleSource(std::span<const Triangle> tris) : tris_(tris), count_(tris.size()) {}
    TriangleSource(const std::vector<Triangle>& tris) : TriangleSource(std::span<const Triangle>(tris)) {}
    /// Meshes numbered one after another: mesh k's triangle t is triangle first(k) + t. The
    /// meshes and what they view must outlive the source.
    explicit TriangleSource(std::span<const IndexedMesh> meshes);
    /// A soup: triangle t's corners are corners[3t], [3t + 1] and [3t + 2] (a mesh whose index
    /// triples are (3t, 3t + 1, 3t + 2), read without them: one line a triangle, as a copy's,
    /// where the triples would add a second). `corners.size()` must be a multiple of 3; they
    /// must outlive the source.
    static TriangleSource soup(std::span<const glm::vec3> corners) {
        TriangleSource source;
        source.soup_ = corners;
        source.count_ = corners.size() / 3;
        return source;
    }
    /// Whether `triangles` are (3t, 3t + 1, 3t + 2) for every t: a mesh to read as a soup.
    static bool is_soup(std::span<const glm::uvec3> triangles);

    std::size_t size() const { return count_; }
    /// Heap bytes the source holds itself (its meshes' first numbers; what it views is the
    /// caller's).
    std::size_t bytes() const {
        return first_.capacity() * sizeof(std::size_t) + bucket_mesh_.capacity() * sizeof(std::uint32_t);
    }
    /// Whether the triangles are read through index triples.
    bool indexed() const { return !meshes_.empty(); }

    Triangle operator[](std::size_t i) const {
        if (meshes_.empty()) {
            if (!soup_.empty()) return Triangle{soup_[3 * i], soup_[3 * i + 1], soup_[3 * i + 2]};
            return tris_[i];
        }
        const std::size_t k = mesh_of(i);
        const IndexedMesh& m = meshes_[k];
        const glm::uvec3 v = m.triangles[i - first_[k]];
        return Triangle{m.positions[v.x], m.positions[v.y], m.positions[v.z]};
    }

    /// Most triangles gather() reads at once.
    static constexpr int kGatherMax = 16;

    /// Reads triangles ids[0], ..., ids[n - 1] (n <= kGatherMax; each below size(), or
    /// kInvalidId to pass over), the same floats operator[] reads, handing triangle ids[j]'s
    /// corners to `corners(j, v0, v1, v2)`. Each stage's loads are all issued before the next
    /// stage waits on them: every index triple is asked for, then each is read and its
    /// vertices asked for, then the vertices are read, so a trace's misses at a leaf overlap
    /// instead of following one another. Each triangle's mesh is found once, trying the last
    /// one found first (a leaf's triangles mostly share a mesh).
    template <class Corners>
    void gather(const std::uint32_t* ids, int n, Corners&& corners) const;

    /// Asks the cache for the corners operator[](i) reads: a triangle's lines, or an indexed
    /// mesh's three vertices (reading the index triple, which should be cached by then, or
    /// the wait is the caller's).
    void prefetch_corners(std::size_t i) const {
        if (meshes_.empty()) {
            const char* p = !soup_.empty() ? reinterpret_cast<const char*>(soup_.data() + 3 * i)
                                           : reinterpret_cast<const char*>(tris_.data() + i);
            prefetch_line(p);
            prefetch_line(p + sizeof(Triangle) - 1);
            return;
        }
        const std::size_t k = mesh_of(i);
        const IndexedMesh& m = meshes_[k];
        const glm::uvec3 v = m.triangles[i - first_[k]];
        prefetch_line(m.positions.data() + v.x);
        prefetch_line(m.positions.data() + v.y);
        prefetch_line(m.positions.data() + v.z);
    }

    /// Asks the cache for what operator[](i) reads first (a triangle, or an index triple).
    void prefetch(std::size_t i) const {
        if (!indexed()) {
            prefetch_corners(i);
            return;
        }
        const std::size_t k = mesh_of(i);
        prefetch_line(meshes_[k].triangles.data() + (i - first_[k]));
    }

private:
    /// The mesh of triangle i: the last whose first number is at most i (empty meshes are
    /// passed over). From the mesh at the start of i's bucket on: a trace reads triangles this
    /// way (compact leaves, wide_bvh.h), where a binary search over a scene's thousand meshes
    /// cost a fifth of the frame.
    std::size_t mesh_of(std::size_t i) const {
        if (first_.size() == 1) return 0;
        std::size_t k = bucket_mesh_[i >> kBucketShift];
        while (k + 1 < first_.size() && first_[k + 1] <= i) ++k;
        return k;
    }

    /// Triangles per bucket of bucket_mesh_ (a bucket's scan passes at most the meshes that
    /// start within it; the table costs 4 bytes per 64 triangles).
    static constexpr int kBucketShift = 6;

    std::span<const Triangle> tris_;
    std::span<const glm::vec3> soup_;
    std::span<const IndexedMesh> meshes_;
    /// Mesh k's first triangle's number.
    std::vector<std::size_t> first_;
    /// Per bucket of 2^kBucketShift triangles, the mesh of the bucket's first triangle.
    std::vector<std::uint32_t> bucket_mesh_;
    std::size_t count_ = 0;
};

inline TriangleSource::TriangleSource(std::span<const IndexedMesh> meshes) : meshes_(meshes) {
    first_.reserve(meshes.size());
    for (const IndexedMesh& m : meshes) {
        first_.push_back(count_);
        count_ += m.triangles.size();
    }
    if (first_.size() <= 1) return;
    bucket_mesh_.resize((count_ >> kBucketShift) + 1);
    std::size_t k = 0;
    for (std::size_t b = 0; b < bucket_mesh_.size(); ++b) {
        const std::size_t i = b << kBucketShift;
        while (k + 1 < first_.size() && first_[k + 1] <= i) ++k;
        bucket_mesh_[b] = static_cast<std::uint32_t>(k);
    }
}

template <class Corners>
inline void TriangleSource::gather(const std::uint32_t* ids, int n, Corners&& corners) const {
    if (meshes_.empty()) {
        for (int j = 0; j < n; ++j) {
            if (ids[j] != kInvalidId) prefetch_corners(ids[j]);
        }
        for (int j = 0; j < n; ++j) {
            if (ids[j] == kInvalidId) continue;
            const Triangle t = (*this)[ids[j]];
            corners(j, t.v0, t.v1, t.v2);
        }
        return;
    }
    const glm::uvec3* triple[kGatherMax];
    const glm::vec3* positions[kGatherMax];
    const IndexedMesh* mesh = nullptr;
    std::size_t lo = 0, count = 0;  // the mesh found last: triangles [lo, lo + count)
    for (int j = 0; j < n; ++j) {
        const std::size_t i = ids[j];
        if (i == kInvalidId) continue;
        if (i - lo >= count) {
            const std::size_t k = mesh_of(i);
            mesh = &meshes_[k];
            lo = first_[k];
            count = mesh->triangles.size();
        }
        triple[j] = mesh->triangles.data() + (i - lo);
        positions[j] = mesh->positions.data();
        prefetch_line(triple[j]);
    }
    glm::uvec3 v[kGatherMax];
    for (int j = 0; j < n; ++j) {
        if (ids[j] == kInvalidId) continue;
        v[j] = *triple[j];
        prefetch_line(positions[j] + v[j].x);
        prefetch_line(positions[j] + v[j].y);
        prefetch_line(positions[j] + v[j].z);
    }
    for (int j = 0; j < n; ++j) {
        if (ids[j] != kInvalidId) corners(j, positions[j][v[j].x], positions[j][v[j].y], positions[j][v[j].z]);
    }
}

}  // namespace dynrt::bvh
