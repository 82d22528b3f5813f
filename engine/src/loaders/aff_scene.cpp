#include "aff_scene.h"

#include "aff_keyframes.h"
#include "message_text.h"

#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/vertex_normals.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <filesystem>
#include <array>
#include <map>
#include <numbers>
#include <span>
#include <tuple>

namespace dynrt::aff {
namespace {

glm::dvec3 to_dvec3(const Vec3& v) { return {v[0], v[1], v[2]}; }

std::string at(const SourceLocation& where) { return cat(where.file, ":", where.line, ": "); }

void check_finite(const Vec3& v, const SourceLocation& where, std::string_view what) {
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
        throw SceneError(cat(at(where), what, " (", v[0], ", ", v[1], ", ", v[2], ") is not finite"));
    }
}

/// xs: T * R * S, rotating by `deg` degrees about the (normalised) axis.
glm::dmat4 static_matrix(const TransformNode& n) {
    check_finite(n.scale, n.where, "'xs' scale");
    check_finite(n.rotation_axis, n.where, "'xs' rotation axis");
    check_finite(n.translation, n.where, "'xs' translation");
    const glm::dvec3 axis = to_dvec3(n.rotation_axis);
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), to_dvec3(n.translation));
    if (n.rotation_deg != 0.0f) {
        if (glm::length(axis) == 0.0) throw SceneError(cat(at(n.where), "'xs' rotates about a zero axis"));
        m = glm::rotate(m, glm::radians(double(n.rotation_deg)), glm::normalize(axis));
    }
    return glm::scale(m, to_dvec3(n.scale));
}

/// Whether the node is an `x` that some `k` block moves.
bool moves(const AffModel& model, const TransformNode& n) {
    if (n.kind != TransformNode::Kind::animated) return false;
    const Animation* a = model.find_animation(n.animation);
    return a && (!a->translations.empty() || !a->rotations.empty() || !a->scales.empty());
}

/// One triangle soup being gathered for an object: each shape's vertices with their normals
/// (the file's, or the shape's own area-weighted ones: shapes never smooth each other).
struct Soup {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> texcoords;
    std::vector<glm::uvec3> triangles;

    /// Adds a shape; `point_normals` is empty (computed) or one per point, and so is
    /// `point_uvs` (a textured soup's shapes all have them).
    void add(std::span<const glm::dvec3> points, std::span<const glm::uvec3> tris,
             std::span<const glm::dvec3> point_normals = {}, std::span<const Vec2> point_uvs = {}) {
        const auto base = std::uint32_t(positions.size());
        for (const Vec2& uv : point_uvs) texcoords.emplace_back(uv[0], uv[1]);
        for (const glm::dvec3& p : points) positions.emplace_back(p);
        for (const glm::uvec3& t : tris) triangles.push_back(t + glm::uvec3(base));
        if (point_normals.empty()) {
            const std::vector<glm::vec3> own =
                area_weighted_normals(std::span<const glm::vec3>(positions).subspan(base), tris);
            normals.insert(normals.end(), own.begin(), own.end());
        } else {
            for (const glm::dvec3& n : point_normals) normals.emplace_back(normalize_or_zero(n));
        }
    }
};

/// Rings of a surface of revolution around `axis` through `centers` with `radii`; a ring of
/// radius 0 is one point. Consecutive rings are joined by quads split in two.
void add_rings(Soup& soup, const glm::dmat4& m, const glm::dvec3& axis,
               std::span<const glm::dvec3> centers, std::span<const double> radii) {
    const glm::dvec3 n = glm::normalize(axis);
    const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 e1 = glm::normalize(glm::cross(n, helper));
    const glm::dvec3 e2 = glm::cross(n, e1);
    std::vector<glm::dvec3> points;
    std::vector<std::uint32_t> ring_start;
    for (std::size_t r = 0; r < centers.size(); ++r) {
        ring_start.push_back(std::uint32_t(points.size()));
        const int count = radii[r] == 0.0 ? 1 : kAffConeSegments;
        for (int i = 0; i < count; ++i) {
            const double a = 2.0 * std::numbers::pi * i / kAffConeSegments;
            const glm::dvec3 p = centers[r] + radii[r] * (std::cos(a) * e1 + std::sin(a) * e2);
            points.push_back(glm::dvec3(m * glm::dvec4(p, 1.0)));
        }
    }
    ring_start.push_back(std::uint32_t(points.size()));
    std::vector<glm::uvec3> tris;
    for (std::size_t r = 0; r + 1 < centers.size(); ++r) {
        const std::uint32_t a0 = ring_start[r], b0 = ring_start[r + 1];
        const bool a_point = ring_start[r + 1] - a0 == 1, b_point = ring_start[r + 2] - b0 == 1;
        for (std::uint32_t i = 0; i < std::uint32_t(kAffConeSegments); ++i) {
            const std::uint32_t j = (i + 1) % kAffConeSegments;
            const std::uint32_t ai = a_point ? a0 : a0 + i, aj = a_point ? a0 : a0 + j;
            const std::uint32_t bi = b_point ? b0 : b0 + i, bj = b_point ? b0 : b0 + j;
            if (!a_point) tris.emplace_back(ai, aj, bj);
            if (!b_point) tris.emplace_back(ai, bj, bi);
        }
    }
    soup.add(points, tris);
}

class Converter {
    /// The triangles of one (anchor, material, texture) triple.
    struct SoupEntry {
        std::int32_t anchor = -1;
        int material = -1;
        /// The texture file, relative to the including file's folder, or empty.
        std::string texture;
        Soup soup;
    };

public:
    Converter(const AffModel& model, const std::string& source) : model_(model) {
        scene_.source = source;
        scene_.materials.push_back(dynrt::Material{"default", glm::vec3(0.8f), glm::vec3(0.2f), 32.0f});
        if (model.animation_params) {
            const AnimationParams& a = *model.animation_params;
            time_offset_ = a.start_time;
            frame_count_ = a.frame_count;
            if (a.frame_count > 1 && a.end_time > a.start_time) {
                fps_ = double(a.frame_count - 1) / (double(a.end_time) - double(a.start_time));
            }
        }
    }

    Scene run() {
        materials();
        nodes();
        shapes();
        camera();
        lights();
        if (!clip_.samplers.empty()) {
            clip_.name = "bart";
            scene_.clips.push_back(std::move(clip_));
        }
        note_ignored();
        return std::move(scene_);
    }

private:
    void materials() {
        for (std::size_t i = 0; i < model_.materials.size(); ++i) {
            const aff::Material& m = model_.materials[i];
            const auto clamp01 = [](const Vec3& c) {
                return glm::clamp(glm::vec3(c[0], c[1], c[2]), glm::vec3(0.0f), glm::vec3(1.0f));
            };
            dynrt::Material material{cat("fm", i), clamp01(m.diffuse), clamp01(m.specular),
                                     std::max(m.shine, 1.0f)};
            // NFF/SPD: Ks weighs the highlight and the reflected ray alike.
            material.reflectance = material.specular;
            material.transmittance = clamp01(Vec3{m.transmittance, m.transmittance, m.transmittance});
            // BART writes 0 for opaque materials; NaN and infinity stay for check_scene to refuse.
            material.ior = m.ior <= 0.0f ? 1.0f : m.ior;
            // BART's ambient term: the `am` light times the material's ambient coefficients
            // (an `f` material's are 0); without `am`, dynrt's own ambient fraction.
            if (model_.ambient) {
                const Vec3& am = *model_.ambient;
                material.ambient = glm::max(glm::vec3(am[0] * m.ambient[0], am[1] * m.ambient[1], am[2] * m.ambient[2]),
                                            glm::vec3(0.0f));
            }
            scene_.materials.push_back(std::move(material));
        }
    }

    // ---- The transform tree: a scene node per `xs` and `x`, and each node's anchor ----
    void nodes() {
        const std::size_t n = model_.nodes.size();
        scene_node_.assign(n, -1);
        anchor_.assign(n, -1);
        to_anchor_.assign(n, glm::dmat4(1.0));
        for (std::size_t i = 1; i < n; ++i) {
            const TransformNode& t = model_.nodes[i];
            const auto parent = std::size_t(t.parent);
            Node node;
            node.parent = scene_node_[parent];
            node.name = t.kind == TransformNode::Kind::animated ? t.animation : cat("xs@", t.where.file, ":", t.where.line);
            glm::dmat4 local(1.0);
            if (t.kind == TransformNode::Kind::fixed) {
                local = static_matrix(t);
                node.matrix = local;
            }
            scene_node_[i] = std::int32_t(scene_.nodes.size());
            scene_.nodes.push_back(std::move(node));
            if (moves(model_, t)) {
                anchor_[i] = std::int32_t(i);
                animate(scene_node_[i], *model_.find_animation(t.animation));
            } else {
                anchor_[i] = anchor_[parent];
                to_anchor_[i] = to_anchor_[parent] * local;
            }
        }
    }

    /// Channels for `animation` on scene node `node`; samplers are shared by every `x` bound to
    /// the same `k` block.
    void animate(std::int32_t node, const Animation& animation) {
        auto [it, added] = samplers_.try_emplace(animation.name, std::array<std::int32_t, 3>{-1, -1, -1});
        if (added) {
            const std::string where = cat(at(animation.where), "k '", animation.name, "' ");
            const auto add = [&](AnimationSampler s) {
                clip_.samplers.push_back(std::move(s));
                return std::int32_t(clip_.samplers.size() - 1);
            };
            if (!animation.translations.empty())
                it->second[0] = add(kochanek_bartels_sampler(animation.translations, time_offset_, where + "transl"));
            if (!animation.rotations.empty())
                it->second[1] = add(bart_rotation_sampler(animation.rotations, time_offset_, where + "rot"));
            if (!animation.scales.empty())
                it->second[2] = add(kochanek_bartels_sampler(animation.scales, time_offset_, where + "scale"));
        }
        const AnimatedProperty properties[3] = {AnimatedProperty::translation, AnimatedProperty::rotation,
                                                AnimatedProperty::scale};
        for (int k = 0; k < 3; ++k) {
            if (it->second[k] >= 0) {
                clip_.channels.push_back(AnimationChannel{std::uint32_t(node), properties[k], std::uint32_t(it->second[k])});
            }
        }
    }

    // ---- Shapes, gathered into one object per (anchor, material) ----
    /// The soup of `p`'s anchor and material, and of `texture` (a path, or empty).
    Soup& soup_for(const Placement& p, const std::string& texture = {}) {
        const auto key = std::make_tuple(anchor_[std::size_t(p.node)], p.material, texture);
        auto [it, added] = soup_index_.try_emplace(key, soups_.size());
        if (added) soups_.push_back({std::get<0>(key), p.material, texture, {}});
        return soups_[it->second].soup;
    }

    /// Where a shape's texture file is: next to the file that names it. Empty when the shape
    /// names none or has no texture coordinates to map it with.
    static std::string texture_path(const Placement& p, const std::string& texture, bool has_uvs) {
        if (texture.empty() || !has_uvs) return {};
        return (std::filesystem::path(p.where.file).parent_path() / texture).lexically_normal().string();
    }

    /// Shape normals through the static transforms between the shape and its anchor (their
    /// cofactor matrix, vertex_normals.h), not yet normalised.
    std::vector<glm::dvec3> placed_normals(const Placement& p, std::span<const Vec3> normals) {
        const glm::dmat3 m = normal_matrix(glm::dmat3(to_anchor_[std::size_t(p.node)]));
        std::vector<glm::dvec3> out;
        out.reserve(normals.size());
        for (const Vec3& n : normals) {
            check_finite(n, p.where, "normal");
            out.push_back(m * to_dvec3(n));
        }
        return out;
    }

    /// Shape points through the static transforms between the shape and its anchor.
    std::vector<glm::dvec3> placed_points(const Placement& p, std::span<const Vec3> points) {
        const glm::dmat4& m = to_anchor_[std::size_t(p.node)];
        std::vector<glm::dvec3> out;
        out.reserve(points.size());
        for (const Vec3& v : points) {
            check_finite(v, p.where, "vertex");
            out.emplace_back(m * glm::dvec4(to_dvec3(v), 1.0));
        }
        return out;
    }

    void shapes() {
        for (const Polygon& poly : model_.polygons) {
            std::vector<glm::uvec3> fan;
            for (std::uint32_t k = 1; k + 1 < poly.vertices.size(); ++k) fan.emplace_back(0, k, k + 1);
            const std::string texture = texture_path(poly, poly.texture, !poly.uvs.empty());
            soup_for(poly, texture)
                .add(placed_points(poly, poly.vertices), fan, placed_normals(poly, poly.normals),
                     texture.empty() ? std::span<const Vec2>() : std::span<const Vec2>(poly.uvs));
        }
        for (const Mesh& mesh : model_.meshes) add_mesh(mesh);
        for (const Cone& c : model_.cones) {
            check_finite(c.base, c.where, "'c' base");
            check_finite(c.apex, c.where, "'c' apex");
            const glm::dvec3 base = to_dvec3(c.base), apex = to_dvec3(c.apex);
            // NFF: negative radii mean "inside visible"; the surface is the same.
            const double radii[2] = {std::abs(double(c.base_radius)), std::abs(double(c.apex_radius))};
            if (glm::length(apex - base) == 0.0 || !std::isfinite(radii[0] + radii[1])) {
                throw SceneError(cat(at(c.where), "'c' needs distinct base and apex and finite radii"));
            }
            const glm::dvec3 centers[2] = {base, apex};
            add_rings(soup_for(c), to_anchor_[std::size_t(c.node)], apex - base, centers, radii);
        }
        for (const Sphere& s : model_.spheres) {
            check_finite(s.center, s.where, "'s' centre");
            const double r = std::abs(double(s.radius));
            if (!std::isfinite(r) || r == 0.0) throw SceneError(cat(at(s.where), "'s' radius must be finite and not 0"));
            std::vector<glm::dvec3> centers;
            std::vector<double> radii;
            const int rings = kAffConeSegments / 2;
            for (int i = 0; i <= rings; ++i) {
                const double polar = std::numbers::pi * i / rings;
                centers.push_back(to_dvec3(s.center) + glm::dvec3(0, 0, r * std::cos(polar)));
                radii.push_back(i == 0 || i == rings ? 0.0 : r * std::sin(polar));
            }
            add_rings(soup_for(s), to_anchor_[std::size_t(s.node)], glm::dvec3(0, 0, 1), centers, radii);
        }
        for (const SoupEntry& e : soups_) add_object(e);
        animated_triangles();
    }

    /// An `m` block. With normals or texture coordinates, its triangles index positions,
    /// normals and texture coordinates separately: each distinct (position, normal, texture
    /// coordinate) triple becomes one vertex.
    void add_mesh(const Mesh& mesh) {
        std::vector<glm::uvec3> tris;
        const bool with_normals = !mesh.normal_indices.empty();
        const std::string texture = texture_path(mesh, mesh.texture, !mesh.uv_indices.empty());
        if (!with_normals && texture.empty()) {
            for (const auto& t : mesh.vertex_indices) tris.emplace_back(t[0], t[1], t[2]);
            soup_for(mesh).add(placed_points(mesh, mesh.vertices), tris);
            return;
        }
        const std::vector<glm::dvec3> points = placed_points(mesh, mesh.vertices);
        const std::vector<glm::dvec3> normals = placed_normals(mesh, mesh.normals);
        std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, std::uint32_t> vertex_of;
        std::vector<glm::dvec3> corner_points, corner_normals;
        std::vector<Vec2> corner_uvs;
        for (std::size_t t = 0; t < mesh.vertex_indices.size(); ++t) {
            glm::uvec3 tri;
            for (int k = 0; k < 3; ++k) {
                const std::size_t c = std::size_t(k);
                const std::tuple<std::uint32_t, std::uint32_t, std::uint32_t> key{
                    mesh.vertex_indices[t][c], with_normals ? mesh.normal_indices[t][c] : 0u,
                    texture.empty() ? 0u : mesh.uv_indices[t][c]};
                const auto [it, added] = vertex_of.try_emplace(key, std::uint32_t(corner_points.size()));
                if (added) {
                    corner_points.push_back(points[std::get<0>(key)]);
                    if (with_normals) corner_normals.push_back(normals[std::get<1>(key)]);
                    if (!texture.empty()) corner_uvs.push_back(mesh.uvs[std::get<2>(key)]);
                }
                tri[k] = it->second;
            }
            tris.push_back(tri);
        }
        soup_for(mesh, texture).add(corner_points, tris, corner_normals, corner_uvs);
    }

    void add_object(const SoupEntry& e) {
        if (e.soup.triangles.empty()) return;
        Object object;
        object.name = cat(anchor_name(e.anchor), "/fm", e.material < 0 ? std::string("-") : cat(e.material));
        object.mesh.positions = e.soup.positions;
        object.mesh.triangles = e.soup.triangles;
        object.mesh.normals = e.soup.normals;
        object.mesh.texcoords = e.soup.texcoords;
        object.material = e.texture.empty() ? std::uint32_t(e.material + 1) : textured_material(e.material, e.texture);
        if (!e.texture.empty()) object.name += cat("/", std::filesystem::path(e.texture).filename().string());
        object.node = e.anchor < 0 ? -1 : scene_node_[std::size_t(e.anchor)];
        object.transform = rest_world(object.node);
        scene_.objects.push_back(std::move(object));
    }

    /// The material `fm` index `material` (-1: the default) with the texture at `path` as its
    /// diffuse map, made once per pair: a copy named "fm<i> <file>".
    std::uint32_t textured_material(int material, const std::string& path) {
        const auto [texture, new_texture] = texture_index_.try_emplace(path, std::uint32_t(scene_.textures.size()));
        if (new_texture) {
            Texture t;
            t.name = path;
            t.path = path;
            scene_.textures.push_back(std::move(t));
        }
        const auto [found, added] =
            textured_material_.try_emplace(std::make_pair(material, path), std::uint32_t(scene_.materials.size()));
        if (added) {
            dynrt::Material m = scene_.materials[std::size_t(material + 1)];
            m.name += cat(" ", std::filesystem::path(path).filename().string());
            m.diffuse_map = TextureMap{texture->second, TextureWrap::repeat, TextureWrap::repeat};
            scene_.materials.push_back(std::move(m));
        }
        return found->second;
    }

    /// Scene node `node`'s world matrix in the rest pose (the identity for -1).
    glm::mat4 rest_world(std::int32_t node) const {
        glm::dmat4 m(1.0);
        for (; node >= 0; node = scene_.nodes[std::size_t(node)].parent) m = scene_.nodes[std::size_t(node)].rest_local() * m;
        return glm::mat4(m);
    }

    std::string anchor_name(std::int32_t anchor) const {
        return anchor < 0 ? std::string("static") : model_.nodes[std::size_t(anchor)].animation;
    }

    // ---- tpa: one deformable object per (anchor, material, key times) ----
    void animated_triangles() {
        std::map<std::tuple<std::int32_t, int, std::vector<float>>, std::vector<const AnimatedTriangle*>> groups;
        std::vector<std::tuple<std::int32_t, int, std::vector<float>>> order;
        for (const AnimatedTriangle& tri : model_.animated_triangles) {
            std::vector<float> times;
            for (const TriangleKey& k : tri.keys) times.push_back(k.time);
            for (std::size_t k = 1; k < times.size(); ++k) {
                if (!(times[k] > times[k - 1])) {
                    throw SceneError(cat(at(tri.where), "'tpa' key times must increase (key ", k, ": ",
                                         times[k], " after ", times[k - 1], ")"));
                }
            }
            auto key = std::make_tuple(anchor_[std::size_t(tri.node)], tri.material, std::move(times));
            auto [it, added] = groups.try_emplace(key);
            if (added) order.push_back(key);
            it->second.push_back(&tri);
        }
        for (const auto& key : order) add_morphing_object(std::get<0>(key), std::get<1>(key), std::get<2>(key), groups[key]);
    }

    void add_morphing_object(std::int32_t anchor, int material, const std::vector<float>& times,
                             const std::vector<const AnimatedTriangle*>& tris) {
        const std::size_t keys = times.size();
        std::vector<std::vector<glm::vec3>> key_positions(keys), key_normals(keys);
        Object object;
        for (const AnimatedTriangle* tri : tris) {
            const auto base = std::uint32_t(object.mesh.triangles.size() * 3);
            object.mesh.triangles.emplace_back(base, base + 1, base + 2);
            for (std::size_t k = 0; k < keys; ++k) {
                const std::vector<glm::dvec3> p = placed_points(*tri, tri->keys[k].positions);
                for (const glm::dvec3& v : p) key_positions[k].emplace_back(v);
                const std::vector<glm::dvec3> n = placed_normals(*tri, tri->keys[k].normals);
                for (const glm::dvec3& v : n) key_normals[k].emplace_back(normalize_or_zero(v));
            }
        }
        object.name = cat(anchor_name(anchor), "/tpa fm", material < 0 ? std::string("-") : cat(material));
        object.material = std::uint32_t(material + 1);
        object.mesh.positions = key_positions[0];
        object.mesh.normals = key_normals[0];
        if (keys == 1) {  // one key: a still triangle set
            object.node = anchor < 0 ? -1 : scene_node_[std::size_t(anchor)];
            object.transform = rest_world(object.node);
            scene_.objects.push_back(std::move(object));
            return;
        }
        // Morph target k - 1 moves key 0's vertices to key k's; the weights are the hat
        // functions of the keys, so linear interpolation of the weights between keys j and j+1
        // is BART's linear interpolation of the vertices between those keys.
        MorphTargets morph;
        morph.base_positions = key_positions[0];
        morph.default_weights.assign(keys - 1, 0.0);
        // The keys' normals morph alike (then renormalised).
        morph.base_normals = key_normals[0];
        for (std::size_t k = 1; k < keys; ++k) {
            std::vector<glm::vec3> delta(key_positions[0].size()), normal_delta(delta.size());
            for (std::size_t v = 0; v < delta.size(); ++v) {
                delta[v] = key_positions[k][v] - key_positions[0][v];
                normal_delta[v] = key_normals[k][v] - key_normals[0][v];
            }
            morph.position_deltas.push_back(std::move(delta));
            morph.normal_deltas.push_back(std::move(normal_delta));
        }
        object.morph = std::move(morph);
        AnimationSampler weights;
        weights.interpolation = Interpolation::linear;
        weights.components = std::uint32_t(keys - 1);
        for (std::size_t k = 0; k < keys; ++k) {
            weights.times.push_back(double(times[k]) - time_offset_);
            for (std::size_t j = 1; j < keys; ++j) weights.values.push_back(j == k ? 1.0 : 0.0);
        }
        Node node;
        node.name = object.name;
        node.parent = anchor < 0 ? -1 : scene_node_[std::size_t(anchor)];
        object.node = std::int32_t(scene_.nodes.size());
        scene_.nodes.push_back(std::move(node));
        object.transform = rest_world(object.node);
        clip_.samplers.push_back(std::move(weights));
        clip_.channels.push_back(AnimationChannel{std::uint32_t(object.node), AnimatedProperty::weights,
                                                  std::uint32_t(clip_.samplers.size() - 1)});
        scene_.objects.push_back(std::move(object));
    }

    // ---- The viewpoint: a node looking down -Z, moved by `k camera` ----
    void camera() {
        if (!model_.view) return;
        const View& v = *model_.view;
        const SourceLocation where{model_.files.empty() ? scene_.source : model_.files.front(), 0};
        check_finite(v.from, where, "'v' from");
        check_finite(v.at, where, "'v' at");
        check_finite(v.up, where, "'v' up");
        const glm::dvec3 from = to_dvec3(v.from);
        const glm::dvec3 forward = to_dvec3(v.at) - from;
        const glm::dvec3 right = glm::cross(forward, to_dvec3(v.up));
        if (glm::length(forward) == 0.0 || glm::length(right) == 0.0) {
            throw SceneError(cat(scene_.source, ": 'v': 'at' equals 'from' or 'up' is parallel to the view direction"));
        }
        // The command line's own limit on image sizes.
        if (v.width > 16384 || v.height > 16384) {
            throw SceneError(cat(scene_.source, ": 'v': resolution ", v.width, "x", v.height, " is larger than 16384 a side"));
        }
        if (!(v.angle_deg > 0.0f && v.angle_deg < 180.0f)) {
            throw SceneError(cat(scene_.source, ": 'v': angle ", v.angle_deg, " must lie in (0, 180) degrees"));
        }
        // Camera basis: x right, y up, z backwards (glTF's camera looks down its -Z).
        const glm::dvec3 z = -glm::normalize(forward);
        const glm::dvec3 x = glm::normalize(right);
        const glm::dvec3 y = glm::cross(z, x);
        const glm::dquat q = glm::quat_cast(glm::dmat3(x, y, z));
        Node node;
        node.name = "camera";
        node.translation = from;
        node.rotation = glm::dvec4(q.x, q.y, q.z, q.w);
        const std::int32_t index = std::int32_t(scene_.nodes.size());
        scene_.nodes.push_back(std::move(node));
        if (const Animation* a = model_.find_animation("camera")) {
            if (!a->scales.empty()) throw SceneError(cat(at(a->where), "'k camera' may not scale the camera"));
            animate(index, *a);
        }
        scene_.cameras.push_back(SceneCamera{"v", std::uint32_t(index), glm::radians(double(v.angle_deg)),
                                             double(v.width) / double(v.height)});
        SceneSetup setup;
        setup.width = v.width;
        setup.height = v.height;
        setup.fps = fps_;
        setup.frame_count = std::max(frame_count_, 1);
        if (model_.background) {
            const Vec3& b = *model_.background;
            setup.background = glm::vec3(b[0], b[1], b[2]);
        }
        scene_.setup = setup;
    }

    // ---- What the model leaves out, for the report (docs/scene-input.md "BART", "Not modelled") ----
    void note_ignored() {
        // Texture coordinates without a texture, or a texture without them, map nothing.
        std::size_t unmapped = 0;
        for (const Polygon& p : model_.polygons) unmapped += p.texture.empty() != p.uvs.empty();
        for (const Mesh& m : model_.meshes) unmapped += m.texture.empty() != m.uv_indices.empty();
        std::vector<std::string>& out = scene_.ignored;
        if (unmapped > 0) {
            out.push_back(cat("texture names or coordinates of ", unmapped,
                              " shapes that lack the other (colour from the material)"));
        }

    }

    // ---- Lights: points placed through their static transforms, or carried by their
    // innermost moving transform (PointLight::node, posed every frame); a grey light's
    // intensity is its grey, a coloured one's colour its colour ----
    void lights() {
        for (const Light& l : model_.lights) {
            if (!l.animation.empty()) {
                throw SceneError(cat(at(l.where), "'la ", l.animation, "': animated lights are not supported"));
            }
            check_finite(l.position, l.where, "light position");
            const Vec3 color = l.color.value_or(Vec3{1, 1, 1});
            check_finite(color, l.where, "light colour");
            const glm::dvec3 p = to_anchor_[std::size_t(l.node)] * glm::dvec4(to_dvec3(l.position), 1.0);
            PointLight light{glm::vec3(p), color[0]};
            if (!(color[0] == color[1] && color[1] == color[2])) {
                light.intensity = 1.0f;
                light.color = glm::vec3(color[0], color[1], color[2]);
            }
            if (const std::int32_t anchor = anchor_[std::size_t(l.node)]; anchor >= 0) light.node = scene_node_[std::size_t(anchor)];
            scene_.lights.push_back(light);
        }
    }

    const AffModel& model_;
    Scene scene_;
    AnimationClip clip_;
    double time_offset_ = 0.0;
    double fps_ = 24.0;
    int frame_count_ = 1;
    /// Per AFF node: its scene node, its innermost moving ancestor-or-self (-1: none) and the
    /// static transform from its own space to that anchor's (to world when there is none).
    std::vector<std::int32_t> scene_node_, anchor_;
    std::vector<glm::dmat4> to_anchor_;
    std::map<std::string, std::array<std::int32_t, 3>> samplers_;
    std::map<std::tuple<std::int32_t, int, std::string>, std::size_t> soup_index_;
    std::map<std::string, std::uint32_t> texture_index_;
    std::map<std::pair<int, std::string>, std::uint32_t> textured_material_;
    std::vector<SoupEntry> soups_;
};

}  // namespace

Scene scene_from_aff(const AffModel& model, const std::string& source) {
    return Converter(model, source).run();
}

}  // namespace dynrt::aff
