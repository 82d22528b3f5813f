#pragma once
// What the library API's tests share: small meshes, a mirror of an Engine's geometry from
// which the exact reference tracer (tests/reference) is built at every step, ray batches
// (coherent runs that the engine traces as packets, incoherent ones traced ray by ray) and the
// comparison of an Engine's answers with the reference's.
//
// The mirror computes world positions as the engine does (transform in double, rounded to
// float once), so for static, deformable and exploding meshes the reference sees exactly the
// engine's triangles. Rigid meshes are traced by the engine in object space through a float
// instance transform; the reference's tolerances (relative to the scene scale) cover that.

#include "dynrt/dynrt.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/scene/scene.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <numbers>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace dynrt::api_test {

/// A mesh as the API takes it: x, y, z per vertex and three indices per triangle.
struct MeshData {
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;

    std::size_t vertices() const { return positions.size() / 3; }
    std::size_t triangles() const { return indices.size() / 3; }
};

/// A closed UV sphere: `rings` latitude bands of `segments` quads, one vertex per pole.
inline MeshData sphere(Vec3 centre, float radius, int rings = 12, int segments = 24) {
    MeshData m;
    const auto vertex = [&](double theta, double phi) {
        m.positions.push_back(centre.x + radius * float(std::sin(theta) * std::cos(phi)));
        m.positions.push_back(centre.y + radius * float(std::cos(theta)));
        m.positions.push_back(centre.z + radius * float(std::sin(theta) * std::sin(phi)));
    };
    vertex(0.0, 0.0);  // north pole: vertex 0
    for (int r = 1; r < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            vertex(std::numbers::pi * r / rings, 2.0 * std::numbers::pi * s / segments);
        }
    }
    vertex(std::numbers::pi, 0.0);  // south pole: the last vertex
    const auto ring = [&](int r, int s) {
        return std::uint32_t(1 + (r - 1) * segments + (s % segments));
    };
    const std::uint32_t south = std::uint32_t(m.vertices() - 1);
    for (int s = 0; s < segments; ++s) {
        m.indices.insert(m.indices.end(), {0u, ring(1, s + 1), ring(1, s)});
        m.indices.insert(m.indices.end(), {south, ring(rings - 1, s), ring(rings - 1, s + 1)});
    }
    for (int r = 1; r + 1 < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            m.indices.insert(m.indices.end(), {ring(r, s), ring(r, s + 1), ring(r + 1, s)});
            m.indices.insert(m.indices.end(), {ring(r, s + 1), ring(r + 1, s + 1), ring(r + 1, s)});
        }
    }
    return m;
}

/// A square sheet of n x n quads in the plane z = `z`, centred on (cx, cy), `size` wide.
inline MeshData sheet(float cx, float cy, float z, float size, int n = 16) {
    MeshData m;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            m.positions.insert(m.positions.end(), {cx + size * (float(i) / float(n) - 0.5f),
                                                   cy + size * (float(j) / float(n) - 0.5f), z});
        }
    }
    const auto at = [&](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
            m.indices.insert(m.indices.end(), {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    return m;
}

/// `count` triangles with their own vertices, each within `extent` of a random point of the
/// box centred on `centre` with half-size `half`.
inline MeshData soup(std::mt19937& rng, int count, Vec3 centre, float half, float extent) {
    std::uniform_real_distribution<float> box(-half, half), local(-extent, extent);
    MeshData m;
    for (int t = 0; t < count; ++t) {
        const float x = centre.x + box(rng), y = centre.y + box(rng), z = centre.z + box(rng);
        for (int k = 0; k < 3; ++k) {
            m.positions.insert(m.positions.end(), {x + local(rng), y + local(rng), z + local(rng)});
            m.indices.push_back(std::uint32_t(3 * t + k));
        }
    }
    return m;
}

/// The sheet `base` waved at `phase`: z += amplitude sin(x + phase) cos(y).
inline std::vector<float> waved(const MeshData& base, float phase, float amplitude = 0.15f) {
    std::vector<float> p = base.positions;
    for (std::size_t v = 0; v < base.vertices(); ++v) {
        p[3 * v + 2] += amplitude * std::sin(3.0f * p[3 * v] + phase) * std::cos(3.0f * p[3 * v + 1]);
    }
    return p;
}

/// `base` scaled by `factor` about `centre` (a pulsing sphere).
inline std::vector<float> scaled(const MeshData& base, Vec3 centre, float factor) {
    std::vector<float> p = base.positions;
    const float c[3] = {centre.x, centre.y, centre.z};
    for (std::size_t i = 0; i < p.size(); ++i) p[i] = c[i % 3] + factor * (p[i] - c[i % 3]);
    return p;
}

/// The vertices of `base` in a random order (the triangles keep their indices): every triangle
/// jumps across the mesh, which degrades a refitted tree as much as anything can.
inline std::vector<float> scrambled(const MeshData& base, std::mt19937& rng) {
    std::vector<std::size_t> order(base.vertices());
    for (std::size_t v = 0; v < order.size(); ++v) order[v] = v;
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<float> p(base.positions.size());
    for (std::size_t v = 0; v < order.size(); ++v) {
        for (int k = 0; k < 3; ++k) p[3 * v + k] = base.positions[3 * order[v] + k];
    }
    return p;
}

inline glm::dmat4 to_dmat4(const Transform& t) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) m[c][r] = double(t.m[std::size_t(c * 4 + r)]);
    }
    return m;
}

/// What the test has given an Engine, mesh by mesh (index = MeshId value): the geometry the
/// engine's last update must be tracing.
class Mirror {
public:
    struct Entry {
        std::string name;
        std::vector<float> positions;  ///< object space
        std::vector<std::uint32_t> indices;
        Transform transform;
        bool removed = false;
    };

    MeshId add(Engine& engine, const std::string& name, const MeshData& mesh, Motion motion,
               const Transform& transform = {}, Ownership ownership = Ownership::copy,
               std::span<const float> borrowed = {}) {
        MeshDesc desc;
        desc.name = name;
        desc.positions = ownership == Ownership::borrow ? borrowed : std::span<const float>(mesh.positions);
        desc.indices = mesh.indices;
        desc.motion = motion;
        desc.ownership = ownership;
        desc.transform = transform;
        const MeshId id = engine.add_mesh(desc);
        EXPECT_EQ(id.value, entries.size());
        entries.push_back(Entry{name, std::vector<float>(desc.positions.begin(), desc.positions.end()),
                                mesh.indices, transform, false});
        return id;
    }
    void set_positions(Engine& engine, MeshId id, std::span<const float> positions) {
        engine.set_positions(id, positions);
        entries[id.value].positions.assign(positions.begin(), positions.end());
    }
    void set_transform(Engine& engine, MeshId id, const Transform& transform) {
        engine.set_transform(id, transform);
        entries[id.value].transform = transform;
    }
    void remove(Engine& engine, MeshId id) {
        engine.remove_mesh(id);
        entries[id.value].removed = true;
    }

    /// World positions as the engine computes them: in double, rounded once.
    std::vector<glm::vec3> world(std::size_t i) const {
        const Entry& e = entries[i];
        const glm::dmat4 m = to_dmat4(e.transform);
        std::vector<glm::vec3> out(e.positions.size() / 3);
        for (std::size_t v = 0; v < out.size(); ++v) {
            const glm::dvec3 p(e.positions[3 * v], e.positions[3 * v + 1], e.positions[3 * v + 2]);
            out[v] = glm::vec3(m * glm::dvec4(p, 1.0));
        }
        return out;
    }

    /// The scene as the engine's last update saw it, in world space (removed meshes empty), so
    /// object i of the scene is mesh i.
    Scene scene() const {
        Scene scene;
        scene.source = "api test mirror";
        scene.materials.push_back(Material{});
        for (std::size_t i = 0; i < entries.size(); ++i) {
            Object object;
            object.name = entries[i].name;
            if (!entries[i].removed) {
                object.mesh.positions = world(i);
                const std::vector<std::uint32_t>& idx = entries[i].indices;
                for (std::size_t k = 0; k < idx.size(); k += 3) {
                    object.mesh.triangles.emplace_back(idx[k], idx[k + 1], idx[k + 2]);
                }
            }
            scene.objects.push_back(std::move(object));
        }
        return scene;
    }

    std::vector<Entry> entries;
};

/// The exact reference over a mirror's current geometry.
struct Reference {
    Scene scene;
    anim::PosedScene posed;
    std::unique_ptr<reference::ReferenceTracer> tracer;

    explicit Reference(const Mirror& mirror) : scene(mirror.scene()) {
        anim::pose_scene(scene, 0, posed);
        tracer = std::make_unique<reference::ReferenceTracer>(scene, posed);
    }
};

inline bvh::Ray to_bvh(const Ray& r) {
    return bvh::Ray{{r.origin.x, r.origin.y, r.origin.z},
                    {r.direction.x, r.direction.y, r.direction.z},
                    r.tmin,
                    r.tmax};
}

inline std::string describe(const Ray& r) {
    std::ostringstream s;
    s.precision(9);
    s << "ray org (" << r.origin.x << ", " << r.origin.y << ", " << r.origin.z << ") dir ("
      << r.direction.x << ", " << r.direction.y << ", " << r.direction.z << ") t [" << r.tmin
      << ", " << r.tmax << "]";
    return s.str();
}

inline std::string describe(const RayHit& h) {
    std::ostringstream s;
    s.precision(9);
    if (!h.hit()) return "miss";
    s << "mesh " << h.mesh.value << " prim " << h.primitive << " t " << h.t << " u " << h.u
      << " v " << h.v;
    return s.str();
}

/// Bit-for-bit equality of two answers.
inline bool identical(const RayHit& a, const RayHit& b) {
    return std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
           a.mesh == b.mesh && a.primitive == b.primitive &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

/// `count` rays from `eye` whose directions spread at most `half_angle` radians around the
/// direction to `target`, with lengths between 0.5 and 3 (the engine must not care): a run
/// the engine traces as a packet.
inline std::vector<Ray> coherent_rays(std::mt19937& rng, Vec3 eye, Vec3 target, float half_angle,
                                      std::size_t count) {
    const glm::vec3 e(eye.x, eye.y, eye.z), forward = glm::normalize(glm::vec3(target.x, target.y, target.z) - e);
    const glm::vec3 side = glm::normalize(glm::cross(forward, glm::vec3(0.0f, 1.0f, 0.0f)));
    const glm::vec3 up = glm::cross(side, forward);
    std::uniform_real_distribution<float> spread(-1.0f, 1.0f), length(0.5f, 3.0f);
    std::vector<Ray> rays(count);
    for (Ray& ray : rays) {
        const float a = std::tan(half_angle) * 0.7f;
        const glm::vec3 d = length(rng) * glm::normalize(forward + a * spread(rng) * side + a * spread(rng) * up);
        ray.origin = eye;
        ray.direction = {d.x, d.y, d.z};
    }
    return rays;
}

/// `count` rays from random points on a sphere of radius `radius` around `centre`, towards
/// random points of the box of half-size `half` around it (so many hit), or in random
/// directions for every fourth ray; lengths between 0.5 and 3. Consecutive rays go every which
/// way: the engine traces them one by one.
inline std::vector<Ray> incoherent_rays(std::mt19937& rng, Vec3 centre, float radius, float half,
                                        std::size_t count) {
    std::normal_distribution<float> gauss;
    std::uniform_real_distribution<float> box(-half, half), length(0.5f, 3.0f);
    const glm::vec3 c(centre.x, centre.y, centre.z);
    std::vector<Ray> rays(count);
    for (std::size_t i = 0; i < count; ++i) {
        const glm::vec3 o = c + radius * glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
        glm::vec3 d = i % 4 == 3 ? glm::vec3(gauss(rng), gauss(rng), gauss(rng))
                                 : c + glm::vec3(box(rng), box(rng), box(rng)) - o;
        d = length(rng) * glm::normalize(d);
        rays[i].origin = {o.x, o.y, o.z};
        rays[i].direction = {d.x, d.y, d.z};
    }
    return rays;
}

/// How a batch compared with the reference.
struct Agreement {
    std::size_t checked = 0;    ///< rays whose answer the reference determines
    std::size_t hits = 0;       ///< of which hits
    std::size_t ambiguous = 0;  ///< rays skipped: the reference allows either answer
    std::size_t mismatches = 0;
};

/// The reference's answer for one ray, and whether it determines what a float tracer must
/// answer (no kAny ambiguity, and no hit within rounding of tmin or tmax).
struct Verdict {
    bool determined = false;
    reference::ReferenceHit hit;
};

namespace detail {

/// The reference's closest hit for `ray` restricted to [tmin + margin, tmax - margin] (inner)
/// or widened by the margin (outer): a float tracer's answer is determined only when both
/// agree, since t near either end may round across it.
inline reference::ReferenceHit closest_within(const reference::ReferenceTracer& ref, Ray ray, double margin,
                                              int widen) {
    const double tmin = double(ray.tmin) - widen * margin, tmax = double(ray.tmax) + widen * margin;
    ray.tmin = float(std::max(0.0, tmin));
    ray.tmax = std::isinf(ray.tmax) ? ray.tmax : float(std::max(double(ray.tmin), tmax));
    return ref.closest(to_bvh(ray));
}

inline Verdict reference_verdict(const reference::ReferenceTracer& ref, const Ray& ray) {
    const glm::dvec3 org(ray.origin.x, ray.origin.y, ray.origin.z);
    const double dir_len = glm::length(glm::dvec3(ray.direction.x, ray.direction.y, ray.direction.z));
    const double margin = 1e-5 * ref.scale_at(org) / dir_len;
    Verdict v;
    v.hit = ref.closest(to_bvh(ray));
    const reference::ReferenceHit inner = closest_within(ref, ray, margin, -1);
    const reference::ReferenceHit outer = closest_within(ref, ray, margin, +1);
    v.determined = v.hit.ambiguity != reference::Ambiguity::kAny &&
                   inner.ambiguity != reference::Ambiguity::kAny &&
                   outer.ambiguity != reference::Ambiguity::kAny && inner.is_hit() == outer.is_hit() &&
                   inner.object == outer.object && inner.is_hit() == v.hit.is_hit();
    return v;
}

}  // namespace detail

/// The reference's verdict on every ray of a batch, in parallel.
inline std::vector<Verdict> verdicts_for(const reference::ReferenceTracer& ref, std::span<const Ray> rays) {
    std::vector<Verdict> out(rays.size());
    tbb::parallel_for(std::size_t(0), rays.size(),
                      [&](std::size_t i) { out[i] = detail::reference_verdict(ref, rays[i]); });
    return out;
}

/// Compares closest hits with the reference. Where it says the answer is determined: hit or
/// miss and mesh; t within 1e-5 of the scene scale (in the ray's units); for kNone also the
/// primitive and the barycentrics (within 1e-3: a float watertight test and the double edge
/// functions differ by rounding only, a swapped or misassigned coordinate is off by far more).
inline Agreement check_closest(const reference::ReferenceTracer& ref, std::span<const Ray> rays,
                               std::span<const Verdict> verdicts, std::span<const RayHit> hits,
                               const std::string& what) {
    Agreement a;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Verdict& v = verdicts[i];
        if (!v.determined) {
            ++a.ambiguous;
            continue;
        }
        ++a.checked;
        const reference::ReferenceHit& want = v.hit;
        const RayHit& got = hits[i];
        std::string bad;
        if (got.hit() != want.is_hit()) {
            bad = got.hit() ? "hit where the reference misses" : "miss where the reference hits";
        } else if (want.is_hit()) {
            ++a.hits;
            const double dir_len = glm::length(glm::dvec3(rays[i].direction.x, rays[i].direction.y,
                                                          rays[i].direction.z));
            const double t_tol = 1e-5 * ref.scale_at(glm::dvec3(rays[i].origin.x, rays[i].origin.y,
                                                                 rays[i].origin.z)) / dir_len;
            if (got.mesh.value != std::uint32_t(want.object)) {
                bad = "other mesh";
            } else if (!(std::fabs(double(got.t) - want.t) <= t_tol + want.t_spread_rel * want.t)) {
                bad = "t off";
            } else if (got.t < rays[i].tmin || got.t > rays[i].tmax) {
                bad = "t outside [tmin, tmax]";
            } else if (want.ambiguity == reference::Ambiguity::kNone &&
                       (got.primitive != std::uint32_t(want.prim) || std::fabs(got.u - want.u) > 1e-3 ||
                        std::fabs(got.v - want.v) > 1e-3)) {
                bad = "other primitive or barycentrics";
            }
        }
        if (bad.empty()) continue;
        if (++a.mismatches <= 5) {
            ADD_FAILURE() << what << ": ray " << i << ": " << bad << ": " << describe(rays[i])
                          << " got " << describe(got) << ", reference object " << want.object
                          << " prim " << want.prim << " t " << want.t << " u " << want.u << " v "
                          << want.v << " (" << reference::to_string(want.ambiguity) << ")";
        }
    }
    return a;
}

/// Compares any-hit answers with the reference where it determines them.
inline Agreement check_occluded(std::span<const Ray> rays, std::span<const Verdict> verdicts,
                                std::span<const std::uint8_t> occluded, const std::string& what) {
    Agreement a;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!verdicts[i].determined) {
            ++a.ambiguous;
            continue;
        }
        ++a.checked;
        a.hits += verdicts[i].hit.is_hit();
        if (bool(occluded[i]) != verdicts[i].hit.is_hit() && ++a.mismatches <= 5) {
            ADD_FAILURE() << what << ": ray " << i << ": occluded " << int(occluded[i])
                          << " but the reference says " << verdicts[i].hit.is_hit() << ": "
                          << describe(rays[i]);
        }
    }
    return a;
}

/// Throws unless `call` throws dynrt::Error with `code` and a message holding every string of
/// `fragments`; returns the message.
template <typename Call>
std::string expect_error(Call&& call, Error::Code code, std::initializer_list<std::string> fragments) {
    try {
        call();
    } catch (const Error& e) {
        EXPECT_EQ(int(e.code()), int(code)) << e.what();
        for (const std::string& f : fragments) {
            EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
                << "message '" << e.what() << "' lacks '" << f << "'";
        }
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "threw another exception: " << e.what();
        return {};
    }
    ADD_FAILURE() << "did not throw";
    return {};
}

}  // namespace dynrt::api_test
