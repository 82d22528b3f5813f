// The flags render and bench share, and what they make of them (frame_args.h).

#include "frame_args.h"

#if DYNRT_HAVE_EMBREE
#include "dynrt/embree/embree_backend.h"
#endif

#include "command_warnings.h"
#include "stage_progress.h"

#include "dynrt/anim/clip_selection.h"
#include "dynrt/anim/motion_class.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/scene_loading.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::cli {

std::vector<float> parse_floats(const std::string& text, const std::string& what) {
    std::vector<float> values;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        float v = 0.0f;
        const char* first = text.data() + start;
        const char* last = text.data() + comma;
        const auto [ptr, ec] = std::from_chars(first, last, v);
        if (ec != std::errc() || ptr != last || !std::isfinite(v)) {
            throw std::invalid_argument(what + " '" + text + "': '" + std::string(first, last) +
                                        "' is not a finite number");
        }
        values.push_back(v);
        if (comma == text.size()) break;
        start = comma + 1;
    }
    return values;
}

void parse_resolution(const std::string& text, int& width, int& height) {
    const std::size_t x = text.find('x');
    int w = 0, h = 0;
    const auto parse = [](const char* first, const char* last, int& v) {
        const auto [ptr, ec] = std::from_chars(first, last, v);
        return ec == std::errc() && ptr == last;
    };
    if (x == std::string::npos || !parse(text.data(), text.data() + x, w) ||
        !parse(text.data() + x + 1, text.data() + text.size(), h) || w < 1 || h < 1 ||
        w > 16384 || h > 16384) {
        throw std::invalid_argument("--res '" + text +
                                    "': expected WIDTHxHEIGHT, each from 1 to 16384");
    }
    width = w;
    height = h;
}

std::size_t parse_memory_budget(const std::string& text) {
    // A number, then an optional K, M, G or T (powers of 1000, as the report's GB) and B.
    const auto bad = [&] {
        return std::invalid_argument("--memory-budget '" + text +
                                     "': expected a size such as 2G, 1500M or 800000000 (bytes), at least 1M");
    };
    double number = 0;
    const char* const end = text.data() + text.size();
    const auto [rest, ec] = std::from_chars(text.data(), end, number);
    if (ec != std::errc() || !std::isfinite(number)) throw bad();
    std::string suffix(rest, end);
    for (char& c : suffix) c = char(std::toupper(static_cast<unsigned char>(c)));
    if (suffix.size() > 1 && suffix.back() == 'B') suffix.pop_back();
    double scale = 1;
    if (suffix == "K") {
        scale = 1e3;
    } else if (suffix == "M") {
        scale = 1e6;
    } else if (suffix == "G") {
        scale = 1e9;
    } else if (suffix == "T") {
        scale = 1e12;
    } else if (!suffix.empty() && suffix != "B") {
        throw bad();
    }
    const double bytes = number * scale;
    // Below a megabyte no layout could matter (the process's libraries alone take more); past
    // 2^60 the count would not fit.
    if (!(bytes >= 1e6 && bytes < 0x1p60)) throw bad();
    return std::size_t(bytes);
}

dynrt::PointLight parse_light(const std::string& text) {
    std::vector<std::string> parts;
    for (std::size_t at = 0;;) {
        const std::size_t colon = text.find(':', at);
        parts.push_back(text.substr(at, colon == std::string::npos ? std::string::npos : colon - at));
        if (colon == std::string::npos) break;
        at = colon + 1;
    }
    const auto bad = [&](const std::string& why) {
        throw std::invalid_argument("--light '" + text + "': " + why);
    };
    const std::vector<float> v = parse_floats(parts[0], "--light");
    if (v.size() != 3 && v.size() != 4) bad("expected x,y,z[,intensity] then :options (dynrt --help)");
    if (v.size() == 4 && !(v[3] >= 0.0f)) bad("the intensity must be >= 0");
    dynrt::PointLight light{glm::vec3(v[0], v[1], v[2]), v.size() == 4 ? v[3] : 1.0f};
    using Kind = dynrt::PointLight::Kind;
    using Shape = dynrt::PointLight::Shape;
    const auto numbers = [&](const std::string& part, std::size_t name_length, std::size_t count,
                             const std::string& expected) {
        const std::vector<float> n = parse_floats(part.substr(name_length), "--light");
        if (n.size() != count) bad(expected);
        return n;
    };
    const auto unit = [&](glm::vec3 d, const std::string& what) {
        const float length = glm::length(d);
        if (!(length > 0.0f) || !std::isfinite(length)) bad(what + " must not be zero");
        return d / length;
    };
    for (std::size_t i = 1; i < parts.size(); ++i) {
        const std::string& part = parts[i];
        if (part.rfind("sphere=", 0) == 0) {
            const std::vector<float> r = numbers(part, 7, 1, "a sphere light's radius is one number > 0");
            if (!(r[0] > 0.0f)) bad("a sphere light's radius must be > 0");
            light.shape = Shape::sphere;
            light.radius = r[0];
        } else if (part.rfind("quad=", 0) == 0) {
            const std::vector<float> e = numbers(part, 5, 6, "a quad light takes its two edges, UX,UY,UZ,VX,VY,VZ");
            light.shape = Shape::quad;
            light.edge_u = glm::vec3(e[0], e[1], e[2]);
            light.edge_v = glm::vec3(e[3], e[4], e[5]);
            const glm::vec3 n = glm::cross(light.edge_u, light.edge_v);
            if (!(glm::dot(n, n) > 0.0f) || !std::isfinite(glm::dot(n, n))) bad("a quad light's edges must not be parallel");
        } else if (part.rfind("spot=", 0) == 0) {
            const std::vector<float> c =
                numbers(part, 5, 5, "a spot takes its axis and cone angles in degrees, DX,DY,DZ,INNER,OUTER");
            light.kind = Kind::spot;
            light.direction = unit(glm::vec3(c[0], c[1], c[2]), "a spot's axis");
            if (!(c[3] >= 0.0f && c[3] < c[4] && c[4] <= 90.0f)) {
                bad("a spot's cone angles must satisfy 0 <= INNER < OUTER <= 90 degrees");
            }
            light.inner_cone = glm::radians(c[3]);
            light.outer_cone = glm::radians(c[4]);
        } else if (part == "directional") {
            // x,y,z is then the direction the light travels.
            light.kind = Kind::directional;
            light.direction = unit(light.position, "a directional light's direction");
            light.position = glm::vec3(0.0f);
        } else if (part.rfind("color=", 0) == 0) {
            const std::vector<float> c = numbers(part, 6, 3, "a colour is R,G,B");
            if (!(std::min({c[0], c[1], c[2]}) >= 0.0f)) bad("a colour's channels must be >= 0");
            light.color = glm::vec3(c[0], c[1], c[2]);
        } else if (part == "falloff") {
            light.inverse_square = true;
        } else if (part.rfind("range=", 0) == 0) {
            const std::vector<float> r = numbers(part, 6, 1, "a range is one number > 0");
            if (!(r[0] > 0.0f)) bad("a range must be > 0");
            light.range = r[0];
        } else {
            bad("unknown option '" + part + "' (sphere=, quad=, spot=, directional, color=, falloff, range=)");
        }
    }
    if (light.kind == Kind::directional && light.shape != Shape::point) bad("a directional light has no area");
    if (light.kind == Kind::directional && (light.inverse_square || light.range > 0.0f)) {
        bad("a directional light has no distance, so no falloff or range");
    }
    return light;
}


/// The factory of the backend `name` names (--backend), or a clear error.
std::function<std::shared_ptr<dynrt::FrameBackend>()> backend_factory(const std::string& name) {
#if DYNRT_HAVE_EMBREE
    dynrt::embree::BuildQuality quality = dynrt::embree::BuildQuality::medium;
    if (name != "embree" && !dynrt::embree::parse_backend_quality(name, quality)) {
        throw std::invalid_argument("--backend '" + name + "': dynrt, embree, embree-low, "
                                    "embree-medium, embree-high or embree-refit");
    }
    return [quality] { return dynrt::embree::make_embree_backend(quality); };
#else
    throw std::runtime_error("--backend " + name + ": this dynrt was built without Embree "
                             "(install libembree-dev and reconfigure)");
#endif
}

dynrt::RenderOptions render_options(const FrameArgs& args) {
    dynrt::RenderOptions options;
    options.width = options.height = 0;
    if (!args.res.empty()) parse_resolution(args.res, options.width, options.height);
    options.build.cost_ratio = args.cost_ratio;
    options.build.leaf_size_max = args.leaf_size;
    options.build.wide = args.bvh == "wide";
    options.compact_static_group = options.compact_moving_objects = args.leaves == "compact";
    options.quantized_static_group = args.nodes == "quantized";
    if (!args.memory_budget.empty()) options.memory_budget = parse_memory_budget(args.memory_budget);
    options.build.method =
        args.builder == "morton" ? dynrt::bvh::BuildMethod::morton : dynrt::bvh::BuildMethod::binned_sah;
    for (const std::string& light : args.lights) options.lights.push_back(parse_light(light));
    options.tracer = args.tracer == "single" ? dynrt::Tracer::single : dynrt::Tracer::packet;
    if (args.backend != "dynrt") options.backend = backend_factory(args.backend);
    options.packet.culling = dynrt::packet::PacketCulling::parse(args.packet_culling);
    options.adaptive_tolerance = args.adaptive;
    options.lod_pixels = args.lod;
    options.smooth_normals = args.normals != "flat";
    options.occluder_cache = args.occluder_cache != "off";
    options.sampling.spp = args.spp;
    options.sampling.filter = dynrt::parse_pixel_filter(args.filter);
    options.sampling.adaptive_contrast = args.aa_contrast;
    dynrt::check_sampling(options.sampling);
    if (!args.background.empty()) options.background = parse_background(args.background);
    if (!args.environment.empty()) {
        try {
            options.environment = dynrt::EnvironmentMap::read(args.environment, args.environment_scale);
        } catch (const std::runtime_error& e) {
            throw std::invalid_argument(std::string("--environment: ") + e.what());
        }
    }
    options.environment_lights = args.environment_lights;
    options.secondary.max_depth = args.depth;
    options.secondary.cutoff = args.cutoff;
    options.secondary.min_packet_rays = args.secondary_packet_min;
    options.reuse = dynrt::parse_reuse(args.reuse);
    options.pose.fps = args.fps;
    options.rebuild_threshold = args.rebuild_threshold;
    options.method = *dynrt::parse_update_method(args.update);  // checked by the flag's parser
    options.exploding_cost_ratio = args.cost_ratio_exploding;
    return options;
}

glm::vec3 parse_background(const std::string& text) {
    const std::vector<float> v = parse_floats(text, "--background");
    if (v.size() != 3 || !std::all_of(v.begin(), v.end(), [](float c) { return c >= 0.0f && std::isfinite(c); })) {
        throw std::invalid_argument("--background '" + text + "': expected r,g,b, three finite numbers >= 0 "
                                    "(linear colour)");
    }
    return glm::vec3(v[0], v[1], v[2]);
}

void apply_scene_setup(const dynrt::Scene& scene, const FrameArgs& args, dynrt::RenderOptions& options) {
    const std::optional<dynrt::SceneSetup>& setup = scene.setup;
    if (options.width == 0) {
        options.width = setup ? setup->width : 1024;
        options.height = setup ? setup->height : 1024;
    }
    if (options.pose.fps == 0.0) options.pose.fps = setup ? setup->fps : dynrt::anim::kDefaultFps;
    if (setup && args.background.empty()) options.background = setup->background;
}

namespace {

/// Refuses --clip choices that animate the same node: played together the first would mask
/// the other there (default_clips keeps only the first of such alternatives for the same
/// reason, and says so).
void refuse_overlapping_clips(const dynrt::Scene& scene, const std::vector<std::size_t>& clips) {
    const std::optional<dynrt::anim::ClipOverlap> overlap = dynrt::anim::find_clip_overlap(scene, clips);
    if (!overlap) return;
    const std::string first = scene.clips[overlap->first].name;
    if (overlap->first == overlap->second) {
        throw std::invalid_argument("--clip '" + first + "' is given twice");
    }
    throw std::invalid_argument(
        "--clip '" + first + "' and --clip '" + scene.clips[overlap->second].name +
        "' both animate node '" + scene.nodes[overlap->node].name + "' (its " +
        dynrt::anim::animated_property_name(overlap->property) + "): they are alternatives, "
        "and played together the first would hide the other; play one at a time (dynrt info "
        "lists the clips)");
}

}  // namespace

dynrt::Scene load_scene_with_progress(const std::string& source) {
    const dynrt::cli::StageProgress progress("loading " + source);
    return dynrt::load_scene(source);
}

dynrt::Scene load_animated_scene(const FrameArgs& args, const std::string& source,
                                 dynrt::RenderOptions& options) {
    dynrt::Scene scene = load_scene_with_progress(source);
    apply_scene_setup(scene, args, options);
    dynrt::anim::add_procedural_motions(scene, args.anims);
    options.pose.class_overrides = dynrt::anim::parse_class_overrides(scene, args.treats);
    std::vector<std::size_t> clips;
    if (!args.clips.empty()) {
        for (const std::string& clip : args.clips) clips.push_back(dynrt::anim::find_clip(scene, clip));
        refuse_overlapping_clips(scene, clips);
    } else {
        clips = dynrt::anim::default_clips(scene);
        if (clips.size() == 1 && scene.clips.size() > 1) {
            std::cout << "clips: playing '" << scene.clips[0].name << "', the first of "
                      << scene.clips.size() << " that animate the same nodes (";
            for (std::size_t i = 0; i < scene.clips.size(); ++i) {
                std::cout << (i ? ", " : "") << "'" << scene.clips[i].name << "'";
            }
            std::cout << "); --clip picks others (dynrt info lists them)\n";
        }
    }
    options.pose.clips = clips;
    options.pose.loop = args.loop;
    // The loader's warnings now, grouped, before any frame is rendered.
    flush_warnings();
    return scene;
}

int animation_end_frame(const dynrt::Scene& scene, const dynrt::anim::PoseSettings& pose) {
    double end = 0.0;
    for (const std::size_t c : pose.clips.value_or(std::vector<std::size_t>{})) {
        end = std::max(end, scene.clips[c].end_time());
    }
    return int(std::min(std::ceil(end * pose.fps), double(dynrt::kFrameMax)));
}

void warn_past_the_end(const dynrt::Scene& scene, const dynrt::anim::PoseSettings& pose,
                       const dynrt::FrameRange& range) {
    // A BART file names its own sequence (`a`): frames beyond it repeat its last state too.
    if (scene.setup && range.last >= scene.setup->frame_count && !pose.loop) {
        dynrt::warn({.kind = "frames " + std::to_string(std::max(range.first, scene.setup->frame_count)) +
                                 "-" + std::to_string(range.last) +
                                 " are past the file's own sequence (frames 0-" +
                                 std::to_string(scene.setup->frame_count - 1) + ")",
                     .effect = "they repeat its last state"});
        flush_warnings();
        return;
    }
    if (pose.loop || !pose.clips || pose.clips->empty()) return;
    const int end = animation_end_frame(scene, pose);
    if (range.last <= end) return;
    std::ostringstream kind;
    kind << "frames " << std::max(range.first, end + 1) << "-" << range.last
         << " are past the end of the animation (frame " << end << " at " << pose.fps << " fps)";
    dynrt::warn({.kind = kind.str(), .effect = "they repeat its last pose; --loop plays it again"});
    flush_warnings();
}

void note_single_frame(std::ostream& out, const std::string& frames) {
    if (frames.empty() || frames.find('-') != std::string::npos) return;
    const dynrt::FrameRange range = dynrt::parse_frame_range(frames);
    if (range.first == 0) return;  // "0" meant nothing before: no script can mean frames 0..-1
    out << "frames: frame " << range.first << " alone (--frames N is one frame; a range is A-B, "
        << "e.g. --frames 0-" << range.first - 1 << " for " << range.first << " frames)\n";
}

std::string scene_source(const FrameArgs& args) {
    return args.scene.empty() ? dynrt::default_scene_path().string() : args.scene;
}

bool uses_scene_camera(const FrameArgs& args, const dynrt::Scene& scene) {
    if (args.camera == "gltf" || args.camera == "scene") {
        if (scene.cameras.empty()) {
            throw std::invalid_argument("--camera " + args.camera + ": " + scene.source + " has no camera");
        }
        return true;
    }
    return args.camera.empty() && scene.setup && !scene.cameras.empty();
}

dynrt::CameraSource camera_source(const dynrt::Scene& scene, const FrameArgs& args,
                                  const dynrt::anim::PoseSettings& pose, dynrt::FrameRange frames) {
    if (args.camera == "still") {
        // The scene's own camera at the first frame, held there (a still view of an animated
        // scene, as exact pixel reuse wants); the default framing when it has none.
        FrameArgs own = args;
        own.camera = scene.cameras.empty() ? "" : "scene";
        return dynrt::CameraSource::fixed(camera_for(scene, own, pose, frames));
    }
    if (uses_scene_camera(args, scene)) return dynrt::CameraSource::scene();
    const dynrt::Camera camera =
        dynrt::default_camera(dynrt::sequence_bounds(scene, pose, frames.first, frames.last));
    return dynrt::CameraSource::fixed(args.camera.empty() ? camera
                                                          : dynrt::parse_camera(args.camera, camera));
}

dynrt::Camera camera_for(const dynrt::Scene& scene, const FrameArgs& args,
                         const dynrt::anim::PoseSettings& pose, dynrt::FrameRange frames) {
    const dynrt::CameraSource view = camera_source(scene, args, pose, frames);
    if (!view.from_scene) return view.camera;
    dynrt::anim::PoseSettings settings;
    settings.fps = pose.fps;
    settings.clips = pose.clips;
    dynrt::anim::PosedScene posed;
    dynrt::anim::pose_scene(scene, settings, frames.first, posed);
    return dynrt::camera_from_scene(*posed.camera);
}

void print_ignored(std::ostream& out, const dynrt::Scene& scene) {
    // Warnings found since loading (unreadable textures, at the first frame) before the table.
    flush_warnings();
    for (const std::string& what : scene.ignored) out << "ignored: " << what << "\n";
}

void print_rebuild_summary(std::ostream& out, const std::vector<dynrt::FrameStats>& frames) {
    std::vector<std::pair<dynrt::RebuildReason, int>> reasons;
    int total = 0;
    std::size_t skipped = 0, refitted = 0;
    for (const dynrt::FrameStats& f : frames) {
        skipped += f.objects_skipped;
        refitted += f.objects_refitted;
        for (const dynrt::TreeRebuild& r : f.rebuilds) {
            ++total;
            auto it = std::find_if(reasons.begin(), reasons.end(),
                                   [&](const auto& p) { return p.first == r.reason; });
            if (it == reasons.end()) reasons.emplace_back(r.reason, 1);
            else ++it->second;
        }
    }
    out << "object updates over " << frames.size() << " frame(s): " << skipped << " skipped, "
        << refitted << " refitted, " << total << " rebuilt";
    for (std::size_t i = 0; i < reasons.size(); ++i) {
        out << (i == 0 ? " (" : ", ") << dynrt::rebuild_reason_name(reasons[i].first) << " "
            << reasons[i].second;
    }
    out << (reasons.empty() ? "\n" : ")\n");
}

void print_update_choices(std::ostream& out, const std::vector<dynrt::FrameStats>& frames) {
    std::size_t refits = 0, fast = 0, sah = 0;
    for (const dynrt::FrameStats& f : frames) {
        for (const dynrt::TreeChoice& c : f.choices) {
            if (c.chosen == "refit") ++refits;
            else if (c.chosen == "rebuild (fast)") ++fast;
            else ++sah;
            if (frames.size() <= 8) {
                out << "frame " << f.frame << ", " << c.name << ": " << c.chosen << " (" << c.why
                    << ")\n";
            }
        }
    }
    if (refits + fast + sah == 0) return;
    out << "update choices over " << frames.size() << " frame(s): " << refits << " refit, "
        << fast << " fast rebuild, " << sah << " sah rebuild (each frame's reasons: --report)\n";
}

void write_text(const std::string& path, const std::string& text) {
    std::ofstream file(path);
    file << text;
    if (!file) throw std::runtime_error(path + ": cannot write");
}

}  // namespace dynrt::cli
