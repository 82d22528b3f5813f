#include "dynrt/api/engine.h"

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/stopwatch.h"
#include "dynrt/engine/update_plan.h"
#include "dynrt/scene/scene.h"
#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/vertex_normals.h"
#include "access_guard.h"
#include "mesh_slots.h"
#include "ray_batch.h"
#include "scene_texture.h"
#include "rendering/frame_pipeline.h"
#include "update/held_bytes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace dynrt {

// Borrowed positions are read in place as glm::vec3: three packed floats, like the caller's.
static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && alignof(glm::vec3) == alignof(float));
static_assert(std::is_standard_layout_v<glm::vec3>);

namespace {

using api_detail::AccessGuard;
using api_detail::MeshSlots;

anim::MotionClass to_class(Motion motion) {
    switch (motion) {
        case Motion::automatic:
        case Motion::static_: return anim::MotionClass::static_;
        case Motion::rigid: return anim::MotionClass::rigid;
        case Motion::deformable: return anim::MotionClass::deformable;
        case Motion::exploding: return anim::MotionClass::exploding;
    }
    return anim::MotionClass::exploding;
}

Motion to_motion(anim::MotionClass motion_class) {
    switch (motion_class) {
        case anim::MotionClass::static_: return Motion::static_;
        case anim::MotionClass::rigid: return Motion::rigid;
        case anim::MotionClass::deformable: return Motion::deformable;
        case anim::MotionClass::exploding: return Motion::exploding;
    }
    return Motion::exploding;
}

glm::vec3 to_glm(const Vec3& v) { return {v.x, v.y, v.z}; }

std::string format_vec(const glm::vec3& v) {
    std::ostringstream out;
    out << '(' << v.x << ", " << v.y << ", " << v.z << ')';
    return out.str();
}

Error invalid(const std::string& message) {
    return Error(Error::Code::invalid_argument, "dynrt::Engine: " + message);
}

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool finite_non_negative(const glm::vec3& v) {
    return finite(v) && v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f;
}

/// What is wrong with a Surface, or "" when add_mesh and set_surface may take it.
std::string surface_problem(const Surface& surface) {
    // A negative colour would shade with negative light: darker than black, and subtracted
    // from what its reflections add.
    if (!finite_non_negative(to_glm(surface.diffuse))) {
        return "diffuse " + format_vec(to_glm(surface.diffuse)) + " must be finite and >= 0";
    }
    if (!finite_non_negative(to_glm(surface.specular))) {
        return "specular " + format_vec(to_glm(surface.specular)) + " must be finite and >= 0";
    }
    if (!std::isfinite(surface.shininess) || !(surface.shininess >= 0.0f)) {
        std::ostringstream out;
        out << "shininess " << surface.shininess << " must be finite and >= 0";
        return out.str();
    }
    if (!finite_non_negative(to_glm(surface.reflectance))) {
        return "reflectance " + format_vec(to_glm(surface.reflectance)) + " must be finite and >= 0";
    }
    if (!finite_non_negative(to_glm(surface.transmittance))) {
        return "transmittance " + format_vec(to_glm(surface.transmittance)) + " must be finite and >= 0";
    }
    if (!std::isfinite(surface.ior) || !(surface.ior > 0.0f)) {
        std::ostringstream out;
        out << "ior " << surface.ior << " must be finite and > 0";
        return out.str();
    }
    if (!finite_non_negative(to_glm(surface.emission))) {
        return "emission " + format_vec(to_glm(surface.emission)) + " must be finite and >= 0";
    }
    for (const auto& [name, value] : {std::pair{"alpha_cutoff", surface.alpha_cutoff}, std::pair{"alpha", surface.alpha}}) {
        if (!(value >= 0.0f && value <= 1.0f)) {
            std::ostringstream out;
            out << name << ' ' << value << " must be in [0, 1]";
            return out.str();
        }
    }
    return {};
}

/// The caller's texture coordinates, checked (2 floats per vertex, finite); empty when none.
std::vector<glm::vec2> checked_texcoords(std::span<const float> given, std::size_t vertices,
                                         const std::string& what) {
    if (given.empty()) return {};
    if (given.size() != 2 * vertices) {
        throw invalid(what + ": texcoords hold " + std::to_string(given.size()) + " floats, " +
                      std::to_string(2 * vertices) + " expected (2 per vertex)");
    }
    std::vector<glm::vec2> out(vertices);
    for (std::size_t v = 0; v < vertices; ++v) {
        out[v] = {given[2 * v], given[2 * v + 1]};
        if (!std::isfinite(out[v].x) || !std::isfinite(out[v].y)) {
            std::ostringstream text;
            text << what << ": texcoord " << v << " is not finite (" << out[v].x << ", " << out[v].y << ')';
            throw invalid(text.str());
        }
    }
    return out;
}

/// The Material a Surface gives, named `name`.
Material material_of(const Surface& surface, const std::string& name) {
    Material material;
    material.name = name;
    material.diffuse = to_glm(surface.diffuse);
    material.specular = to_glm(surface.specular);
    material.shininess = surface.shininess;
    material.reflectance = to_glm(surface.reflectance);
    material.transmittance = to_glm(surface.transmittance);
    material.ior = surface.ior;
    material.emission = to_glm(surface.emission);
    if (surface.alpha_cutoff > 0.0f) material.alpha_cutoff = surface.alpha_cutoff;
    material.base_alpha = surface.alpha;
    if (surface.diffuse_texture.valid()) {
        material.diffuse_map = TextureMap{surface.diffuse_texture.value, api_detail::scene_wrap(surface.wrap_s),
                                          api_detail::scene_wrap(surface.wrap_t)};
    }
    return material;
}

/// The first non-finite position's index, or -1; parallel, for per-step checks of big meshes.
std::ptrdiff_t first_non_finite(std::span<const glm::vec3> positions) {
    std::atomic<std::ptrdiff_t> first{-1};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, positions.size(), 16384),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i < range.end(); ++i) {
                              const glm::vec3& p = positions[i];
                              if (finite(p)) continue;
                              std::ptrdiff_t seen = first.load();
                              while ((seen < 0 || std::ptrdiff_t(i) < seen) &&
                                     !first.compare_exchange_weak(seen, std::ptrdiff_t(i))) {
                              }
                              return;
                          }
                      });
    return first.load();
}

/// The transform in double, or an Error when it is not finite and affine.
glm::dmat4 checked_transform(const Transform& transform, const std::string& what) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            const float value = transform.m[std::size_t(c * 4 + r)];
            if (!std::isfinite(value)) throw invalid(what + ": transform is not finite");
            m[c][r] = double(value);
        }
    }
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) {
        throw invalid(what + ": transform is not affine (its last row must be 0, 0, 0, 1)");
    }
    return m;
}

}  // namespace

/// One mesh of the engine, at its slot: the index of its scene object, material, state and
/// tree (MeshSlots maps its MeshId to it).
struct MeshSlot {
    Motion declared = Motion::automatic;
    /// The class it is treated as now (raised from static for automatic meshes).
    anim::MotionClass motion_class = anim::MotionClass::static_;
    Ownership ownership = Ownership::copy;
    std::vector<glm::vec3> owned;       ///< Ownership::copy
    std::span<const glm::vec3> borrowed;  ///< Ownership::borrow
    glm::dmat4 transform{1.0};
    bool identity = true;
    bool removed = false;
    /// Whether an update has taken the mesh in (and checked its world positions if static).
    bool settled = false;
    /// Changes since the last update.
    bool positions_changed = false;
    bool transform_changed = false;
    /// Borrowed positions not yet checked for finite values.
    bool unchecked = false;
    /// In a slot freed by another mesh: the next update starts its tree afresh
    /// (FramePipeline::renew). `freed_class` is the class the slot had while free, kept should
    /// the mesh be removed before that update (the trees still know the slot by it).
    bool renew_at_update = false;
    anim::MotionClass freed_class = anim::MotionClass::static_;
    /// Updates in a row whose refit degraded past the threshold (Motion::automatic).
    int degraded_steps = 0;
    /// World positions of a deformable or exploding mesh with a transform (scratch).
    std::vector<glm::vec3> world;
    /// Unit object-space shading normals, one per vertex: the caller's (normalised) or, when
    /// computed_normals, missing_normals of the positions (area-weighted, or none for a soup;
    /// recomputed when they change).
    std::vector<glm::vec3> normals;
    bool computed_normals = true;
    /// World normals of a deformable or exploding mesh with a transform (scratch).
    std::vector<glm::vec3> world_normals;
    /// Object-space bounds of the positions, while box_known (for rigid meshes' world extent).
    glm::vec3 box_lo{0.0f}, box_hi{0.0f};
    bool box_known = false;

    std::span<const glm::vec3> positions() const {
        return ownership == Ownership::copy ? std::span<const glm::vec3>(owned) : borrowed;
    }
};

struct Engine::Impl final : FixedPositions {
    EngineOptions options;
    std::optional<tbb::task_arena> own_arena;
    tbb::task_arena* arena = nullptr;
    UpdatePolicy policy;

    /// Per slot (mesh_slots.h): scene object i is meshes[i], its material is material i.
    Scene scene;
    std::vector<MeshSlot> meshes;
    MeshSlots ids;
    std::size_t live = 0;
    /// Slots of meshes removed since the last update: the trees still hold them, so they are
    /// freed (free_slot) once an update has dropped them.
    std::vector<std::size_t> dropping;

    /// The engine's frame path (rendering/frame_pipeline.h): the trees, their update and the
    /// trace. Renders run one at a time (render_mutex), on its buffers and `frame`.
    mutable FramePipeline pipeline;
    std::vector<ObjectState> states;
    int step = 0;
    bool updated = false;
    /// An update failed after touching the trees: the next one starts afresh.
    bool broken = false;

    /// Normals and triangles replaced or removed since the last update: the trees' shading
    /// still reads them (SceneAccel borrows them until its next update), so they are freed
    /// only once an update has succeeded.
    std::vector<std::vector<glm::vec3>> retired_normals;
    std::vector<SharedArray<glm::uvec3>> retired_triangles;

    AccessGuard guard;
    mutable std::mutex render_mutex;
    mutable RenderedFrame frame;
    /// The environment the last render read (RenderSettings::environment), kept while its
    /// path and scale stay the same; under render_mutex.
    mutable std::shared_ptr<const EnvironmentMap> environment;
    mutable std::pair<std::string, float> environment_key;

    template <typename Work>
    decltype(auto) run(Work&& work) const {
        if (arena) return arena->execute(std::forward<Work>(work));
        return work();
    }

    /// The mesh in slot i, for messages.
    std::string describe(std::size_t i) const {
        return "mesh '" + scene.objects[i].name + "' (id " + std::to_string(ids.id_at(i)) + ")";
    }

    /// The slot of a live mesh, or Error naming the id for `call`.
    std::size_t slot_index(MeshId id, const char* call) const {
        if (const std::optional<std::size_t> i = ids.slot_of(id.value)) return *i;
        throw invalid(std::string(call) + ": no mesh with id " + std::to_string(id.value) +
                      (ids.issued(id.value) ? " (it was removed)" : ""));
    }

    /// What is wrong with `surface`'s texture for a mesh with or without texture coordinates,
    /// or "".
    std::string texture_problem(const Surface& surface, bool has_texcoords) const {
        if (!surface.diffuse_texture.valid()) return {};
        const std::uint32_t id = surface.diffuse_texture.value;
        if (id >= scene.textures.size()) {
            return "surface maps no texture with id " + std::to_string(id) + " (" +
                   std::to_string(scene.textures.size()) + " added)";
        }
        if (!has_texcoords) {
            return "surface maps texture " + std::to_string(id) + " ('" + scene.textures[id].name +
                   "') but the mesh has no texcoords";
        }
        return {};
    }

    /// Slot i holds no mesh any more and no tree shows it: everything it held is freed (its
    /// class stays, so that the planner sees no change in it) and add_mesh may take it.
    void free_slot(std::size_t i) {
        scene.objects[i] = Object{};
        scene.materials[i] = Material{};
        MeshSlot freed;
        freed.removed = true;
        freed.settled = true;
        freed.motion_class = meshes[i].renew_at_update ? meshes[i].freed_class : meshes[i].motion_class;
        freed.declared = to_motion(freed.motion_class);
        meshes[i] = std::move(freed);
        ids.free(i);
    }

    /// Slots in `stats` turned into the MeshId values the caller knows.
    void name_meshes(FrameStats& stats) const {
        if (ids.ids_are_slots()) return;
        for (TreeRebuild& rebuild : stats.rebuilds) rebuild.object = ids.id_at(rebuild.object);
        for (TreeChoice& choice : stats.choices) choice.object = ids.id_at(choice.object);
    }

    std::size_t memory_bytes() const;

    // ---- FixedPositions: static and rigid meshes' vertices, for their builds ----
    // A build reads a borrowed buffer again (the static group is rebuilt whenever a static mesh
    // joins or leaves it), and the caller may have changed it since add_mesh checked it.
    std::span<const glm::vec3> object_space(std::size_t object) const override {
        return fixed_positions(object);
    }
    std::span<const glm::vec3> world(std::size_t object,
                                     std::vector<glm::vec3>& scratch_positions) const override {
        const MeshSlot& mesh = meshes[object];
        if (mesh.identity) return fixed_positions(object);
        fixed_positions(object);
        transform_positions(mesh, scratch_positions);
        if (mesh.ownership == Ownership::borrow) {
            check_positions(object, scratch_positions, "transformed", true);
        }
        return scratch_positions;
    }
    std::span<const glm::vec3> object_space_normals(std::size_t object) const override {
        return meshes[object].normals;
    }
    std::span<const glm::vec3> world_normals(std::size_t object,
                                             std::vector<glm::vec3>& scratch) const override {
        const MeshSlot& mesh = meshes[object];
        if (mesh.identity) return mesh.normals;
        transform_normals(mesh, scratch);
        return scratch;
    }
    /// normalize(cof(M) n) for the transform's linear part M (vertex_normals.h), in double.
    static void transform_normals(const MeshSlot& mesh, std::vector<glm::vec3>& out) {
        const glm::dmat3 cof = normal_matrix(glm::dmat3(mesh.transform));
        out.resize(mesh.normals.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.size(), 16384),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              for (std::size_t i = range.begin(); i < range.end(); ++i) {
                                  out[i] = glm::vec3(normalize_or_zero(cof * glm::dvec3(mesh.normals[i])));
                              }
                          });
    }
    /// The caller's normals, checked (3 floats per vertex, finite) and normalised.
    static std::vector<glm::vec3> checked_normals(std::span<const float> given, std::size_t vertices,
                                                  const std::string& what) {
        if (given.size() != 3 * vertices) {
            throw invalid(what + ": normals hold " + std::to_string(given.size()) + " floats, " +
                          std::to_string(3 * vertices) + " expected (3 per vertex)");
        }
        const std::span<const glm::vec3> normals(reinterpret_cast<const glm::vec3*>(given.data()), vertices);
        if (const std::ptrdiff_t bad = first_non_finite(normals); bad >= 0) {
            throw invalid(what + ": normal " + std::to_string(bad) + " is not finite " +
                          format_vec(normals[std::size_t(bad)]));
        }
        std::vector<glm::vec3> out(vertices);
        for (std::size_t v = 0; v < vertices; ++v) out[v] = normalize_or_zero(normals[v]);
        return out;
    }

    std::span<const glm::vec3> fixed_positions(std::size_t object) const {
        const MeshSlot& mesh = meshes[object];
        if (mesh.ownership == Ownership::borrow) {
            check_positions(object, mesh.positions(), "borrowed", true);
        }
        return mesh.positions();
    }

    /// world = transform * positions, in double and rounded once (as the scene poser does).
    static void transform_positions(const MeshSlot& mesh, std::vector<glm::vec3>& out) {
        const std::span<const glm::vec3> in = mesh.positions();
        out.resize(in.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, in.size(), 16384),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              for (std::size_t i = range.begin(); i < range.end(); ++i) {
                                  out[i] = glm::vec3(mesh.transform * glm::dvec4(glm::dvec3(in[i]), 1.0));
                              }
                          });
    }

    void check_positions(std::size_t i, std::span<const glm::vec3> positions, const char* what,
                         bool at_update) const {
        const std::ptrdiff_t bad = first_non_finite(positions);
        if (bad < 0) return;
        const std::string where = describe(i) + (at_update ? ", step " + std::to_string(step) : "");
        throw Error(at_update ? Error::Code::invalid_geometry : Error::Code::invalid_argument,
                    "dynrt::Engine: " + where + ": " + what + " vertex " + std::to_string(bad) +
                        " is not finite " + format_vec(positions[std::size_t(bad)]));
    }

    /// Throws invalid_geometry when a rigid mesh's world extent is not finite in float. Traced
    /// in object space, its vertices are never transformed, but its world box is; the corners
    /// of its object-space box bound every transformed vertex, the transform being affine.
    void check_world_extent(std::size_t i, MeshSlot& mesh) const {
        const std::span<const glm::vec3> positions = mesh.positions();
        if (positions.empty()) return;
        if (!mesh.box_known) {
            mesh.box_lo = mesh.box_hi = positions[0];
            for (const glm::vec3& p : positions) {
                mesh.box_lo = glm::min(mesh.box_lo, p);
                mesh.box_hi = glm::max(mesh.box_hi, p);
            }
            mesh.box_known = true;
        }
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 p(corner & 1 ? mesh.box_hi.x : mesh.box_lo.x,
                               corner & 2 ? mesh.box_hi.y : mesh.box_lo.y,
                               corner & 4 ? mesh.box_hi.z : mesh.box_lo.z);
            const glm::vec3 world(mesh.transform * glm::dvec4(p, 1.0));
            if (finite(world)) continue;
            throw Error(Error::Code::invalid_geometry,
                        "dynrt::Engine: " + describe(i) + ", step " + std::to_string(step) +
                            ": its transform takes the corner " + format_vec(glm::vec3(p)) +
                            " of its bounds to " + format_vec(world) + ", not finite");
        }
    }

    FrameStats update();

    /// Throws invalid_state unless the last update() succeeded.
    void check_traced(const char* call) const {
        if (updated) return;
        throw Error(Error::Code::invalid_state,
                    std::string("dynrt::Engine: ") + call +
                        (broken ? " after an update() that failed while building trees: call "
                                  "update() again once the input is fixed"
                                : " before the first update()"));
    }
};

Engine::Engine(const EngineOptions& options) : impl_(std::make_unique<Impl>()) {
    Impl& s = *impl_;
    if (options.threads < 0) throw invalid("threads " + std::to_string(options.threads) + " < 0");
    if (!(options.cost_ratio > 0.0f && options.cost_ratio <= 1e6f)) {
        throw invalid("cost_ratio must be in (0, 1e6]");
    }
    if (!(options.cost_ratio_exploding > 0.0f && options.cost_ratio_exploding <= 1e6f)) {
        throw invalid("cost_ratio_exploding must be in (0, 1e6]");
    }
    if (options.leaf_size < 1 || options.leaf_size > 64) {
        throw invalid("leaf_size " + std::to_string(options.leaf_size) + " outside [1, 64]");
    }
    if (!(options.rebuild_threshold >= 0.0)) throw invalid("rebuild_threshold must be >= 0");
    s.options = options;
    // Warnings (a texture that cannot be read) name where they come from.
    s.scene.source = "dynrt::Engine";
    if (options.arena) {
        s.arena = options.arena;
    } else if (options.threads > 0) {
        s.own_arena.emplace(options.threads);
        s.arena = &*s.own_arena;
    }
    s.policy.build.cost_ratio = options.cost_ratio;
    s.policy.build.leaf_size_max = std::uint32_t(options.leaf_size);
    s.policy.exploding_cost_ratio = options.cost_ratio_exploding;
    s.policy.rebuild_threshold = options.rebuild_threshold;
    s.policy.compact_static_group = options.compact_leaves;
    s.policy.quantized_static_group = options.quantized_nodes;
    s.policy.memory_budget = options.memory_budget;
    // The API documents its rebuilds by the threshold (EngineOptions::rebuild_threshold), and
    // raises a mesh whose refits keep degrading past it to exploding.
    s.policy.method = UpdateMethod::threshold;
}

Engine::~Engine() = default;
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;

MeshId Engine::add_mesh(const MeshDesc& desc) {
    Impl& s = *impl_;
    const AccessGuard::Write write(s.guard);
    if (!s.ids.can_claim()) {
        throw Error(Error::Code::invalid_state, "dynrt::Engine: add_mesh: every MeshId (" +
                                                    std::to_string(MeshSlots::kMaxIds) +
                                                    ") has been issued; ids are never reused");
    }
    const std::uint32_t id = s.ids.next_id();
    const std::string name = desc.name.empty() ? "mesh " + std::to_string(id) : desc.name;
    const std::string what = "add_mesh '" + name + "'";
    if (desc.positions.size() % 3 != 0) {
        throw invalid(what + ": positions hold " + std::to_string(desc.positions.size()) +
                      " floats, not a multiple of 3");
    }
    if (desc.indices.size() % 3 != 0) {
        throw invalid(what + ": indices hold " + std::to_string(desc.indices.size()) +
                      " values, not a multiple of 3");
    }
    const std::size_t vertices = desc.positions.size() / 3;
    if (vertices > std::size_t(std::numeric_limits<std::uint32_t>::max()) ||
        desc.indices.size() / 3 > std::size_t(std::numeric_limits<std::uint32_t>::max() / 2)) {
        throw invalid(what + ": too many vertices or triangles");
    }
    for (std::size_t k = 0; k < desc.indices.size(); ++k) {
        if (desc.indices[k] >= vertices) {
            throw invalid(what + ": index " + std::to_string(k) + " (triangle " +
                          std::to_string(k / 3) + ") is " + std::to_string(desc.indices[k]) +
                          ", but the mesh has " + std::to_string(vertices) + " vertices");
        }
    }
    const glm::dmat4 transform = checked_transform(desc.transform, what);
    const std::span<const glm::vec3> positions(
        reinterpret_cast<const glm::vec3*>(desc.positions.data()), vertices);
    if (const std::ptrdiff_t bad = first_non_finite(positions); bad >= 0) {
        throw invalid(what + ": vertex " + std::to_string(bad) + " is not finite " +
                      format_vec(positions[std::size_t(bad)]));
    }
    if (const std::string problem = surface_problem(desc.surface); !problem.empty()) {
        throw invalid(what + ": surface " + problem);
    }
    std::vector<glm::vec2> texcoords = checked_texcoords(desc.texcoords, vertices, what);
    if (const std::string problem = s.texture_problem(desc.surface, !texcoords.empty()); !problem.empty()) {
        throw invalid(what + ": " + problem);
    }

    MeshSlot mesh;
    mesh.declared = desc.motion;
    mesh.motion_class = to_class(desc.motion);
    mesh.ownership = desc.ownership;
    if (desc.ownership == Ownership::copy) {
        mesh.owned.assign(positions.begin(), positions.end());
    } else {
        mesh.borrowed = positions;
    }
    mesh.transform = transform;
    mesh.identity = transform == glm::dmat4(1.0);

    Object object;
    object.name = name;
    object.mesh.texcoords = std::move(texcoords);
    std::vector<glm::uvec3>& corners = object.mesh.triangles.edit();
    corners.resize(desc.indices.size() / 3);
    for (std::size_t t = 0; t < corners.size(); ++t) {
        corners[t] = {desc.indices[3 * t], desc.indices[3 * t + 1],
                                    desc.indices[3 * t + 2]};
    }
    mesh.computed_normals = desc.normals.empty();
    mesh.normals = mesh.computed_normals ? missing_normals(positions, object.mesh.triangles)
                                         : Impl::checked_normals(desc.normals, vertices, what);
    Material material = material_of(desc.surface, name);
    // Every check passed: the mesh takes its id and a slot (a freed one when there is).
    const MeshSlots::Claim claim = s.ids.claim();
    object.material = std::uint32_t(claim.slot);
    if (claim.reused) {
        // The trees keep the slot as it was until the next update (queries until then see
        // nothing there); that update starts its tree afresh.
        mesh.renew_at_update = true;
        mesh.freed_class = s.meshes[claim.slot].motion_class;
        s.scene.objects[claim.slot] = std::move(object);
        s.scene.materials[claim.slot] = std::move(material);
        s.meshes[claim.slot] = std::move(mesh);
    } else {
        s.scene.objects.push_back(std::move(object));
        s.scene.materials.push_back(std::move(material));
        s.meshes.push_back(std::move(mesh));
    }
    ++s.live;
    return MeshId{claim.id};
}

TextureId Engine::add_texture(const TextureDesc& desc) {
    Impl& s = *impl_;
    const AccessGuard::Write write(s.guard);
    if (s.scene.textures.size() >= std::size_t(std::numeric_limits<std::uint32_t>::max())) {
        throw Error(Error::Code::invalid_state, "dynrt::Engine: add_texture: every TextureId has been issued");
    }
    const auto id = std::uint32_t(s.scene.textures.size());
    s.scene.textures.push_back(api_detail::texture_of(desc, id));
    return TextureId{id};
}

void Engine::set_positions(MeshId id, std::span<const float> positions, std::span<const float> normals) {
    Impl& s = *impl_;
    const AccessGuard::Write write(s.guard);
    const std::size_t i = s.slot_index(id, "set_positions");
    MeshSlot& mesh = s.meshes[i];
    const std::string what = "set_positions: " + s.describe(i);
    if (mesh.declared == Motion::static_ || mesh.declared == Motion::rigid) {
        throw invalid(what + " was added as " + motion_name(mesh.declared) +
                      ", so its vertices cannot move");
    }
    const std::size_t count = mesh.positions().size();
    if (positions.size() != 3 * count) {
        throw invalid(what + ": " + std::to_string(positions.size()) + " floats given, " +
                      std::to_string(3 * count) + " expected (3 per vertex, same vertex count)");
    }
    const std::span<const glm::vec3> given(reinterpret_cast<const glm::vec3*>(positions.data()),
                                           count);
    // Checked before anything changes; computed normals are redone at the update.
    std::vector<glm::vec3> new_normals;
    if (!normals.empty()) new_normals = Impl::checked_normals(normals, count, what);
    if (mesh.ownership == Ownership::copy) {
        s.run([&] { s.check_positions(i, given, "new", false); });
        std::copy(given.begin(), given.end(), mesh.owned.begin());
    } else {
        mesh.borrowed = given;
        mesh.unchecked = true;
    }
    if (!normals.empty()) {
        s.retired_normals.push_back(std::move(mesh.normals));
        mesh.normals = std::move(new_normals);
        mesh.computed_normals = false;
    }
    mesh.positions_changed = true;
    mesh.box_known = false;
}

void Engine::set_transform(MeshId id, const Transform& transform) {
    Impl& s = *impl_;
    const AccessGuard::Write write(s.guard);
    const std::size_t i = s.slot_index(id, "set_transform");
    MeshSlot& mesh = s.meshes[i];
    const std::string what = "set_transform: " + s.describe(i);
    if (mesh.declared == Motion::static_) throw invalid(what + " was added as static");
    mesh.transform = checked_transform(transform, what);
    mesh.identity = mesh.transform == glm::dmat4(1.0);
    mesh.transform_changed = true;
}

void Engine::set_surface(MeshId id, const Surface& surface) {
    Impl& s = *impl_;
    const AccessGuard::Write write(s.guard);
    const std::size_t i = s.slot_index(id, "set_surface");
    if (const std::string problem = surface_problem(surface); !problem.empty()) {
        throw invalid("set_surface: " + s.describe(i) + ": " + problem);
    }
    if (const std::string problem = s.texture_problem(surface, !s.scene.objects[i].mesh.texcoords.empty());
        !problem.empty()) {
        throw invalid("set_surface: " + s.describe(i) + ": " + problem);
    }
    Material& material = s.scene.materials[i];
    material = material_of(surface, material.name);
    // Every render reads the materials as they are, so the next one uses it without waiting
    // for an update (no render runs during this call).
}

void Engine::remove_mesh(MeshId id) {
    Impl& s = *impl_;
    const AccessGuard::Write write(s.guard);
    const std::size_t i = s.slot_index(id, "remove_mesh");
    MeshSlot& mesh = s.meshes[i];
    s.ids.retire(id.value);
    --s.live;
    if (!mesh.settled && !s.broken) {
        // Added since the last update: no tree or trace has seen it, so its slot is free now.
        s.free_slot(i);
        return;
    }
    // The trees of the last update still show it (queries until the next update hit it), so
    // the slot stays, with no triangles, until an update has rebuilt its tree empty; then
    // update() frees it. The trees' shading borrows its triangles and normals until then.
    mesh.removed = true;
    mesh.borrowed = {};
    mesh.owned = {};
    mesh.world = {};
    s.retired_normals.push_back(std::move(mesh.normals));
    s.retired_normals.push_back(std::move(mesh.world_normals));
    s.retired_triangles.push_back(std::move(s.scene.objects[i].mesh.triangles));
    mesh.normals = {};
    mesh.world_normals = {};
    s.scene.objects[i].mesh.triangles = {};
    s.pipeline.invalidate(i);
    s.dropping.push_back(i);
}

std::size_t Engine::Impl::memory_bytes() const {
    std::size_t bytes = held_bytes(meshes) + held_bytes(scene.objects) + held_bytes(scene.materials);
    for (const MeshSlot& mesh : meshes) {
        bytes += held_bytes(mesh.owned) + held_bytes(mesh.world) + held_bytes(mesh.normals) +
                 held_bytes(mesh.world_normals);
    }
    for (const Object& object : scene.objects) {
        bytes += held_bytes(object.name) + held_bytes(object.mesh.positions) +
                 held_bytes(object.mesh.triangles) + held_bytes(object.mesh.normals) +
                 held_bytes(object.mesh.texcoords);
    }
    for (const Material& material : scene.materials) bytes += held_bytes(material.name);
    bytes += held_bytes(scene.textures);
    for (const Texture& texture : scene.textures) {
        bytes += held_bytes(texture.name) + held_bytes(texture.path) + held_bytes(texture.encoded) +
                 held_bytes(texture.mime_type) + held_bytes(texture.texels.bytes);
    }
    bytes += held_bytes(retired_normals) + held_bytes(retired_triangles);
    for (const std::vector<glm::vec3>& normals : retired_normals) bytes += held_bytes(normals);
    for (const SharedArray<glm::uvec3>& triangles : retired_triangles) bytes += held_bytes(triangles);
    bytes += held_bytes(states) + held_bytes(dropping) + ids.memory_bytes();
    return bytes + pipeline.memory_bytes();
}

std::size_t Engine::memory_bytes() const {
    const Impl& s = *impl_;
    const AccessGuard::Read read(s.guard);
    // Renders refresh the pipeline's per-object records.
    const std::lock_guard<std::mutex> lock(s.render_mutex);
    return s.memory_bytes();
}

TextureFigures Engine::texture_figures() const {
    const Impl& s = *impl_;
    const AccessGuard::Read read(s.guard);
    // A render may be opening them.
    const std::lock_guard<std::mutex> lock(s.render_mutex);
    return s.pipeline.texture_figures();
}

Motion Engine::motion(MeshId id) const {
    return to_motion(impl_->meshes[impl_->slot_index(id, "motion")].motion_class);
}

std::size_t Engine::mesh_count() const { return impl_->live; }

FrameStats Engine::update() {
    Impl& s = *impl_;
    const AccessGuard::Write write(s.guard);
    return s.run([&] { return s.update(); });
}

FrameStats Engine::Impl::update() {
    const Stopwatch wall;
    // ---- Classes, world positions and checks: nothing is changed until all pass ----
    std::vector<anim::MotionClass> classes(meshes.size());
    states.resize(meshes.size());
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        MeshSlot& mesh = meshes[i];
        const anim::MotionClass motion_class =
            mesh.declared == Motion::automatic && !mesh.removed
                ? raise_automatic_class(mesh.motion_class, mesh.transform_changed,
                                        mesh.positions_changed)
                : mesh.motion_class;
        classes[i] = motion_class;
        ObjectState& state = states[i];
        state.motion_class = motion_class;
        state.changed = mesh.positions_changed || mesh.transform_changed;
        state.transform = mesh.transform;
        state.world_positions = {};
        state.world_normals = {};
        if (mesh.unchecked) check_positions(i, mesh.positions(), "borrowed", true);
        const bool moving = motion_class == anim::MotionClass::deformable ||
                            motion_class == anim::MotionClass::exploding;
        if (mesh.positions_changed && mesh.computed_normals && !mesh.removed) {
            retired_normals.push_back(std::move(mesh.normals));
            mesh.normals = missing_normals(mesh.positions(), scene.objects[i].mesh.triangles);
        }
        if (moving) {
            if (mesh.identity) {
                state.world_positions = mesh.positions();
                state.world_normals = mesh.normals;
            } else {
                if (state.changed || mesh.world.size() != mesh.positions().size()) {
                    transform_positions(mesh, mesh.world);
                    check_positions(i, mesh.world, "transformed", true);
                }
                if (state.changed || mesh.world_normals.size() != mesh.normals.size()) {
                    transform_normals(mesh, mesh.world_normals);
                }
                state.world_positions = mesh.world;
                state.world_normals = mesh.world_normals;
            }
        } else if (motion_class == anim::MotionClass::rigid && (state.changed || !mesh.settled)) {
            check_world_extent(i, mesh);
        } else if (motion_class == anim::MotionClass::static_ && !mesh.identity && !mesh.settled) {
            // Joining the static group: its world positions must be finite.
            std::vector<glm::vec3> world_positions;
            transform_positions(mesh, world_positions);
            check_positions(i, world_positions, "transformed", true);
        }
    }

    // ---- The trees ----
    // Everything above is checked before the trees are touched. What a build reads later (a
    // borrowed static or rigid buffer, checked as it is read) can still fail the update half
    // way: then the trees are a mix of two steps, so queries are refused until an update
    // succeeds, and that update starts afresh.
    if (broken) pipeline.clear();
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        if (meshes[i].renew_at_update) pipeline.renew(i);
    }
    broken = true;
    updated = false;
    const FrameStats& stats = pipeline.update(scene, states, *this, policy, step, wall);
    broken = false;
    retired_normals.clear();
    retired_triangles.clear();
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        MeshSlot& mesh = meshes[i];
        mesh.motion_class = classes[i];
        mesh.settled = true;
        mesh.renew_at_update = false;
        mesh.positions_changed = mesh.transform_changed = mesh.unchecked = false;
    }
    // Automatic deformable meshes whose refits keep degrading are rebuilt anyway: the planner
    // then treats them as exploding, which skips the refit.
    std::vector<bool> degraded(meshes.size(), false);
    for (const TreeRebuild& rebuild : stats.rebuilds) {
        if (rebuild.reason == RebuildReason::sah_degraded) degraded[rebuild.object] = true;
    }
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        MeshSlot& mesh = meshes[i];
        if (mesh.declared != Motion::automatic) continue;
        mesh.motion_class = class_after_update(mesh.motion_class, states[i].changed, degraded[i],
                                               mesh.degraded_steps);
    }
    // The removed meshes' trees are empty now: their slots and what they held are freed.
    for (const std::size_t i : dropping) {
        pipeline.release(i);
        free_slot(i);
    }
    dropping.clear();
    updated = true;
    ++step;
    FrameStats named = stats;
    name_meshes(named);
    return named;
}

void Engine::cancel_render() const { impl_->pipeline.cancel(); }

RenderProgress Engine::render_progress() const { return impl_->pipeline.progress(); }

FrameStats Engine::render(const View& view, const ImageView& image,
                          const RenderSettings& settings) const {
    const Impl& s = *impl_;
    const AccessGuard::Read read(s.guard);
    s.check_traced("render");
    if (image.width <= 0 || image.height <= 0 || image.width > 65536 || image.height > 65536) {
        throw invalid("render: image size " + std::to_string(image.width) + "x" +
                      std::to_string(image.height) + " outside 1..65536");
    }
    const std::size_t pixels = std::size_t(image.width) * std::size_t(image.height);
    const auto check_size = [&](std::size_t size, std::size_t per_pixel, const char* name) {
        if (size != pixels * per_pixel) {
            throw invalid(std::string("render: ") + name + " holds " + std::to_string(size) +
                          " values, " + std::to_string(pixels * per_pixel) + " expected");
        }
    };
    check_size(image.rgb.size(), 3, "rgb");
    if (!image.depth.empty()) check_size(image.depth.size(), 1, "depth");
    if (!image.mesh.empty()) check_size(image.mesh.size(), 1, "mesh");
    Camera camera;
    camera.eye = to_glm(view.eye);
    camera.target = to_glm(view.target);
    camera.up = to_glm(view.up);
    camera.fov_y_deg = view.fov_y_deg;
    TraceSettings options;
    options.width = image.width;
    options.height = image.height;
    options.background = to_glm(settings.background);
    options.ambient = settings.ambient;
    options.hit_buffers = !image.depth.empty() || !image.mesh.empty();
    options.reuse.mode = settings.reuse_pixels ? PixelReuse::exact : PixelReuse::off;
    if (!std::isfinite(options.ambient) || !finite(options.background)) {
        throw invalid("render: background and ambient must be finite");
    }
    if (settings.max_depth < 0 || settings.max_depth > 64 || !(settings.cutoff >= 0.0f) ||
        !(settings.cutoff <= 1.0f)) {
        throw invalid("render: max_depth must be 0 to 64 and cutoff in [0, 1]");
    }
    options.secondary.max_depth = settings.max_depth;
    options.secondary.cutoff = settings.cutoff;
    options.smooth_normals = settings.smooth_normals;
    // A bad share is refused by the trace (FramePipeline::trace), before it changes anything.
    options.tiles = packet::TileShare{settings.tile_share, settings.tile_shares};
    options.sampling.spp = settings.samples_per_pixel;
    options.sampling.adaptive_contrast = settings.aa_contrast;
    try {
        options.sampling.filter = parse_pixel_filter(settings.filter);
        check_sampling(options.sampling);
    } catch (const std::invalid_argument& e) {
        throw invalid(std::string("render: ") + e.what());
    }
    std::vector<PointLight> lights;
    for (const Light& light : settings.lights) {
        const glm::vec3 position = to_glm(light.position);
        if (!finite(position) || !std::isfinite(light.intensity)) {
            throw invalid("render: light position and intensity must be finite");
        }
        // Area lights are checked by the trace, which names the light.
        PointLight engine_light{position, light.intensity};
        engine_light.shape = light.shape == LightShape::sphere ? PointLight::Shape::sphere
                             : light.shape == LightShape::quad ? PointLight::Shape::quad
                                                               : PointLight::Shape::point;
        engine_light.radius = light.radius;
        engine_light.edge_u = to_glm(light.edge_u);
        engine_light.edge_v = to_glm(light.edge_v);
        engine_light.kind = light.kind == LightKind::spot          ? PointLight::Kind::spot
                            : light.kind == LightKind::directional ? PointLight::Kind::directional
                                                                   : PointLight::Kind::point;
        engine_light.color = to_glm(light.color);
        // Normalised here (a zero or non-finite one stays not unit, which the trace refuses).
        const glm::vec3 direction = to_glm(light.direction);
        const float length = glm::length(direction);
        engine_light.direction = length > 0.0f ? direction / length : direction;
        engine_light.inner_cone = glm::radians(light.inner_cone_deg);
        engine_light.outer_cone = glm::radians(light.outer_cone_deg);
        engine_light.inverse_square = light.inverse_square;
        engine_light.range = light.range;
        lights.push_back(engine_light);
    }
    if (lights.empty() && !(settings.environment_lights > 0 && !settings.environment.empty())) {
        const bvh::Aabb bounds = s.pipeline.accel().world_bounds();
        lights.push_back(bounds.is_empty() ? PointLight{} : default_light(bounds));
    }

    const std::lock_guard<std::mutex> lock(s.render_mutex);
    if (settings.environment.empty()) {
        s.environment.reset();
    } else if (!s.environment || s.environment_key != std::pair(settings.environment, settings.environment_scale)) {
        try {
            s.environment = EnvironmentMap::read(settings.environment, settings.environment_scale);
        } catch (const std::runtime_error& e) {
            throw invalid(std::string("render: ") + e.what());
        }
        s.environment_key = {settings.environment, settings.environment_scale};
    }
    options.environment = s.environment;
    options.environment_lights = settings.environment_lights;
    RenderedFrame& frame = s.frame;
    try {
        s.run([&] { s.pipeline.trace(s.scene, camera, options, lights, frame); });
    } catch (const std::invalid_argument& e) {
        throw invalid(std::string("render: ") + e.what());
    }
    FrameStats stats = frame.stats;
    if (stats.cancelled) return stats;  // the caller's image left as it was
    s.name_meshes(stats);
    // The frame's hits name slots; the caller's image names MeshId values.
    const bool ids_are_slots = s.ids.ids_are_slots();
    const auto mesh_at = [&](std::size_t p) {
        const std::int32_t slot = frame.object[p];
        return slot < 0 || ids_are_slots ? slot : std::int32_t(s.ids.id_at(std::size_t(slot)));
    };
    if (options.tiles.whole()) {
        std::copy_n(&frame.color[0].x, 3 * pixels, image.rgb.begin());
        if (!image.depth.empty()) std::copy(frame.depth.begin(), frame.depth.end(), image.depth.begin());
        if (!image.mesh.empty()) {
            for (std::size_t p = 0; p < pixels; ++p) image.mesh[p] = mesh_at(p);
        }
        return stats;
    }
    // A share: its pixels only, the caller's others untouched.
    packet::Tiling(image.width, image.height, options.tiles).for_each_pixel([&](std::size_t p) {
        std::copy_n(&frame.color[p].x, 3, image.rgb.begin() + std::ptrdiff_t(3 * p));
        if (!image.depth.empty()) image.depth[p] = frame.depth[p];
        if (!image.mesh.empty()) image.mesh[p] = mesh_at(p);
    });
    return stats;
}

QueryStats Engine::intersect(std::span<const Ray> rays, std::span<RayHit> hits) const {
    const Impl& s = *impl_;
    const AccessGuard::Read read(s.guard);
    s.check_traced("intersect");
    return s.run([&] {
        return api_detail::intersect_batch(s.pipeline.accel(), rays, hits, s.ids.ids_of_slots());
    });
}

QueryStats Engine::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const {
    const Impl& s = *impl_;
    const AccessGuard::Read read(s.guard);
    s.check_traced("occluded");
    return s.run([&] { return api_detail::occluded_batch(s.pipeline.accel(), rays, occluded); });
}

QueryStats Engine::intersect(const RayArrays& rays, std::span<RayHit> hits) const {
    const Impl& s = *impl_;
    const AccessGuard::Read read(s.guard);
    s.check_traced("intersect");
    return s.run([&] {
        return api_detail::intersect_batch(s.pipeline.accel(), rays, hits, s.ids.ids_of_slots());
    });
}

QueryStats Engine::occluded(const RayArrays& rays, std::span<std::uint8_t> occluded) const {
    const Impl& s = *impl_;
    const AccessGuard::Read read(s.guard);
    s.check_traced("occluded");
    return s.run([&] { return api_detail::occluded_batch(s.pipeline.accel(), rays, occluded); });
}

}  // namespace dynrt
