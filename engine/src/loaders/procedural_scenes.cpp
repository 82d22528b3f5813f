// Procedural spec strings -> scenes. The grammar is in scenes/README.md ("Spec grammar"); this
// parser accepts exactly that language and names the spec and the offending part otherwise.

#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/vertex_normals.h"

#include "message_text.h"
#include "procedural_meshes.h"
#include "scene_copies.h"

#include <glm/common.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace dynrt {

namespace {

enum class MeshKind { sphere, soup, plane };

struct Placement {
    float x = 0.0f, y = 0.0f, z = 0.0f, scale = 1.0f;
};

/// One `kind:N[*K][@x,y,z[,s]][#rrggbb]` part, parsed but not yet built.
struct PartSpec {
    std::string_view text;
    MeshKind kind = MeshKind::sphere;
    std::uint64_t count = 0;
    /// Objects made of the one mesh (`*K`), laid out on a grid; 1 without.
    std::uint64_t copies = 1;
    /// Of the one mesh: copies share it.
    std::uint64_t triangles = 0;
    std::optional<Placement> placement;
    std::optional<glm::vec3> colour;
};

/// Builds the one-line error for `spec`, naming `part` when the problem lies in one.
[[noreturn]] void fail(std::string_view spec, std::string_view part, const std::string& what) {
    if (part.empty()) throw SceneError(cat("procedural spec '", spec, "': ", what));
    throw SceneError(cat("procedural spec '", spec, "': part '", part, "': ", what));
}

std::optional<MeshKind> parse_kind(std::string_view text) {
    if (text == "sphere") return MeshKind::sphere;
    if (text == "soup") return MeshKind::soup;
    if (text == "plane") return MeshKind::plane;
    return std::nullopt;
}

/// Decimal digits only (no sign, no spaces); nullopt on anything else or on overflow.
std::optional<std::uint64_t> parse_count(std::string_view text) {
    if (text.empty()) return std::nullopt;
    for (const char c : text) {
        if (c < '0' || c > '9') return std::nullopt;
    }
    std::uint64_t value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

/// A finite decimal float, the whole of `text`, rounded to the nearest float by from_chars
/// (general format: optional '-', digits with optional '.', optional exponent).
std::optional<float> parse_number(std::string_view text) {
    if (text.empty()) return std::nullopt;
    float value = 0.0f;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
        return std::nullopt;
    }
    return value;
}

std::optional<glm::vec3> parse_colour(std::string_view hex) {
    if (hex.size() != 6) return std::nullopt;
    glm::vec3 rgb;
    for (int channel = 0; channel < 3; ++channel) {
        unsigned value = 0;
        const char* first = hex.data() + 2 * channel;
        const auto [end, ec] = std::from_chars(first, first + 2, value, 16);
        if (ec != std::errc() || end != first + 2) return std::nullopt;
        rgb[channel] = static_cast<float>(value) / 255.0f;
    }
    return rgb;
}

std::vector<std::string_view> split(std::string_view text, char separator) {
    std::vector<std::string_view> pieces;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find(separator, start);
        pieces.push_back(text.substr(start, end == std::string_view::npos ? end : end - start));
        if (end == std::string_view::npos) return pieces;
        start = end + 1;
    }
}

Placement parse_placement(std::string_view spec, std::string_view part, std::string_view text) {
    const std::vector<std::string_view> fields = split(text, ',');
    if (fields.size() != 3 && fields.size() != 4) {
        fail(spec, part, cat("placement '@", text, "' needs 3 or 4 numbers (x,y,z[,scale])"));
    }
    float values[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    for (std::size_t i = 0; i < fields.size(); ++i) {
        const std::optional<float> value = parse_number(fields[i]);
        if (!value) {
            fail(spec, part,
                 cat("'", fields[i], "' in placement '@", text, "' is not a finite decimal number"));
        }
        values[i] = *value;
    }
    if (!(values[3] > 0.0f)) {
        fail(spec, part, cat("scale '", fields[3], "' must be greater than 0"));
    }
    return Placement{values[0], values[1], values[2], values[3]};
}

PartSpec parse_part(std::string_view spec, std::string_view text, std::uint64_t max_triangles) {
    if (text.empty()) fail(spec, "", "empty part (a '+' with nothing on one side)");
    PartSpec part;
    part.text = text;

    const std::size_t colon = text.find(':');
    if (colon == std::string_view::npos) {
        fail(spec, text, "expected kind:N with kind sphere, soup or plane (files must end in .gltf, .glb or .aff)");
    }
    const std::string_view kind = text.substr(0, colon);
    const std::optional<MeshKind> parsed_kind = parse_kind(kind);
    if (!parsed_kind) {
        fail(spec, text, cat("unknown kind '", kind, "' (expected sphere, soup or plane; scene files end in .gltf, .glb or .aff)"));
    }
    part.kind = *parsed_kind;

    // '*K' may follow N; suffixes '@...' and '#...' follow, in either order, each at most once.
    std::string_view rest = text.substr(colon + 1);
    const std::size_t count_end = rest.find_first_of("*@#");
    const std::string_view count_text = rest.substr(0, count_end);
    const std::optional<std::uint64_t> count = parse_count(count_text);
    if (!count || *count == 0) {
        const bool digits_only = !count_text.empty() && count_text.find_first_not_of("0123456789") ==
                                                            std::string_view::npos;
        fail(spec, text,
             cat("count '", count_text, digits_only && !count ? "' is too large" : "' is not a positive integer"));
    }
    part.count = *count;
    rest = count_end == std::string_view::npos ? std::string_view() : rest.substr(count_end);
    if (!rest.empty() && rest.front() == '*') {
        const std::size_t copies_end = rest.find_first_of("@#");
        const std::string_view copies_text = rest.substr(1, copies_end == std::string_view::npos ? copies_end : copies_end - 1);
        const std::optional<std::uint64_t> copies = parse_count(copies_text);
        if (!copies || *copies == 0 || *copies > kMaxCopies) {
            fail(spec, text, cat("copies '*", copies_text, "' must be an integer from 1 to ", kMaxCopies));
        }
        part.copies = *copies;
        rest = copies_end == std::string_view::npos ? std::string_view() : rest.substr(copies_end);
    }

    while (!rest.empty()) {
        const char marker = rest.front();
        const std::size_t end = rest.find_first_of("*@#", 1);
        const std::string_view body = rest.substr(1, end == std::string_view::npos ? end : end - 1);
        if (marker == '*') fail(spec, text, "copies '*K' must follow the count directly");
        if (marker == '@') {
            if (part.placement) fail(spec, text, "placement '@' given twice");
            part.placement = parse_placement(spec, text, body);
        } else {
            if (part.colour) fail(spec, text, "colour '#' given twice");
            part.colour = parse_colour(body);
            if (!part.colour) {
                fail(spec, text, cat("colour '#", body, "' is not #rrggbb (6 hex digits)"));
            }
        }
        rest = end == std::string_view::npos ? std::string_view() : rest.substr(end);
    }

    switch (part.kind) {
        case MeshKind::sphere:
            part.triangles = sphere_triangle_count(part.count);
            break;
        case MeshKind::soup:
            part.triangles = soup_triangle_count(part.count);
            break;
        case MeshKind::plane:
            part.triangles = plane_triangle_count(part.count);
            break;
    }
    if (part.triangles > max_triangles) {
        fail(spec, text, cat("makes ", part.triangles, " triangles, more than the limit of ", max_triangles));
    }
    return part;
}

Mesh build_mesh(const PartSpec& part) {
    switch (part.kind) {
        case MeshKind::sphere:
            return make_sphere_mesh(part.count);
        case MeshKind::soup:
            return make_soup_mesh(part.count);
        case MeshKind::plane:
            return make_plane_mesh(part.count);
    }
    return {};
}

/// translate(x, y, z) * scale(s), written out so the entries are exactly the parsed floats.
glm::mat4 placement_matrix(const Placement& p) {
    glm::mat4 m(p.scale);
    m[3] = glm::vec4(p.x, p.y, p.z, 1.0f);
    return m;
}

}  // namespace

Scene make_procedural_scene(const std::string& spec, std::uint64_t max_triangles) {
    if (spec.empty()) fail(spec, "", "empty spec");

    // Parse everything first so a bad last part fails before any mesh is built.
    std::vector<PartSpec> parts;
    std::uint64_t total_triangles = 0;
    for (const std::string_view text : split(spec, '+')) {
        parts.push_back(parse_part(spec, text, max_triangles));
        total_triangles += parts.back().triangles;
        if (total_triangles > max_triangles) {
            fail(spec, "", cat("makes more than the limit of ", max_triangles, " triangles"));
        }
    }

    Scene scene;
    scene.source = spec;
    scene.materials.push_back(Material{.name = "default"});
    for (const PartSpec& part : parts) {
        Object object;
        object.name = std::string(part.text);
        object.mesh = build_mesh(part);
        if (part.placement) object.transform = placement_matrix(*part.placement);
        if (part.colour) {
            object.material = static_cast<std::uint32_t>(scene.materials.size());
            scene.materials.push_back(Material{.name = object.name, .diffuse = *part.colour});
        }
        if (part.copies == 1) {
            scene.objects.push_back(std::move(object));
            continue;
        }
        // Copies share the one mesh's arrays (normals included, made once): each costs an
        // object's record, not its triangles.
        object.mesh.normals = area_weighted_normals(object.mesh.positions, object.mesh.triangles);
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : object.mesh.positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        const glm::mat4 placement = object.transform;
        scene.objects.reserve(scene.objects.size() + part.copies);
        for (std::uint64_t k = 0; k < part.copies; ++k) {
            Object copy = object;
            copy.name = cat(part.text, "[", k, "]");
            copy.transform = placement * copy_matrix(k, part.copies, lo, hi);
            scene.objects.push_back(std::move(copy));
        }
    }
    // Area-weighted vertex normals: the sphere's shared vertices make it smooth, the plane
    // stays flat and the soup's unshared triangles keep their facets.
    add_missing_normals(scene);
    check_scene(scene);
    return scene;
}

}  // namespace dynrt
