// ViewerSession (viewer_session.h).

#include "viewer_session.h"

#include "dynrt/engine/environment_lights.h"
#include "dynrt/engine/image_output.h"
#include "dynrt/engine/report.h"
#include "dynrt/engine/update_plan.h"

#include "dynrt/anim/posed_scene.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <stdexcept>

namespace dynrt::viewer {

namespace {

constexpr int kDefaultWidth = 640, kDefaultHeight = 480;

/// A whole number, all of `text`.
int parse_int(const std::string& name, const std::string& text) {
    std::size_t used = 0;
    int value = 0;
    try {
        value = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size()) throw std::invalid_argument(name + " '" + text + "': not a whole number");
    return value;
}

/// parse_int, within [lo, hi].
int parse_int_in(const std::string& name, const std::string& text, int lo, int hi) {
    const int value = parse_int(name, text);
    if (value < lo || value > hi) {
        throw std::invalid_argument(name + " '" + text + "': must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return value;
}

float parse_float(const std::string& name, const std::string& text) {
    std::size_t used = 0;
    float value = 0.0f;
    try {
        value = std::stof(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(value)) {
        throw std::invalid_argument(name + " '" + text + "': not a finite number");
    }
    return value;
}

void one_of(const std::string& name, const std::string& value, std::initializer_list<const char*> choices) {
    std::string list;
    for (const char* c : choices) {
        if (value == c) return;
        list += std::string(list.empty() ? "" : ", ") + c;
    }
    throw std::invalid_argument(name + " '" + value + "': one of " + list);
}

/// A setting `set` takes: its name, how it is read into the flags, and how it is shown.
struct Setting {
    const char* name;
    std::function<void(ViewArgs&, const std::string&)> write;
    std::function<std::string(const ViewArgs&)> read;
};

const std::vector<Setting>& setting_table() {
    static const std::vector<Setting> table = {
        {"tracer",
         [](ViewArgs& a, const std::string& v) { one_of("tracer", v, {"packet", "single"}); a.tracer = v; },
         [](const ViewArgs& a) { return a.tracer; }},
        {"backend", [](ViewArgs& a, const std::string& v) { a.backend = v; },
         [](const ViewArgs& a) { return a.backend; }},
        {"update",
         [](ViewArgs& a, const std::string& v) {
             if (!parse_update_method(v)) throw std::invalid_argument("update '" + v + "': not an update method");
             a.update = v;
         },
         [](const ViewArgs& a) { return a.update; }},
        {"cost-ratio",
         [](ViewArgs& a, const std::string& v) {
             const float r = parse_float("cost-ratio", v);
             if (!(r > 0.0f)) throw std::invalid_argument("cost-ratio '" + v + "': must be > 0");
             a.cost_ratio = r;
         },
         [](const ViewArgs& a) { return std::to_string(a.cost_ratio); }},
        {"culling", [](ViewArgs& a, const std::string& v) { a.packet_culling = v; },
         [](const ViewArgs& a) { return a.packet_culling; }},
        {"depth", [](ViewArgs& a, const std::string& v) { a.depth = parse_int_in("depth", v, 0, 64); },
         [](const ViewArgs& a) { return std::to_string(a.depth); }},
        {"reuse", [](ViewArgs& a, const std::string& v) { a.reuse = v; },
         [](const ViewArgs& a) { return a.reuse; }},
        {"spp", [](ViewArgs& a, const std::string& v) { a.spp = parse_int_in("spp", v, 1, 4096); },
         [](const ViewArgs& a) { return std::to_string(a.spp); }},
        {"normals",
         [](ViewArgs& a, const std::string& v) { one_of("normals", v, {"smooth", "flat"}); a.normals = v; },
         [](const ViewArgs& a) { return a.normals; }},
        {"occluder-cache",
         [](ViewArgs& a, const std::string& v) { one_of("occluder-cache", v, {"on", "off"}); a.occluder_cache = v; },
         [](const ViewArgs& a) { return a.occluder_cache; }},
        {"environment-lights",
         [](ViewArgs& a, const std::string& v) {
             a.environment_lights = parse_int_in("environment-lights", v, 0, kEnvironmentLightsMax);
         },
         [](const ViewArgs& a) { return std::to_string(a.environment_lights); }},
        {"view",
         [](ViewArgs& a, const std::string& v) { one_of("view", v, {"image", "nodes", "triangles"}); a.view = v; },
         [](const ViewArgs& a) { return a.view; }},
        {"cost-scale",
         [](ViewArgs& a, const std::string& v) { a.cost_scale = parse_int_in("cost-scale", v, 0, 1 << 24); },
         [](const ViewArgs& a) { return std::to_string(a.cost_scale); }},
    };
    return table;
}

}  // namespace

ViewerSession::ViewerSession(const ViewArgs& args)
    : args_(args), options_(cli::render_options(args_)),
      scene_(cli::load_animated_scene(args_, cli::scene_source(args_), options_)),
      renderer_([&] {
          // The window's size unless the flags or the file give one.
          if (args_.res.empty() && !scene_.setup) {
              options_.width = kDefaultWidth;
              options_.height = kDefaultHeight;
          }
          return options_;
      }()),
      first_camera_(cli::camera_for(scene_, args_, options_.pose)), camera_(first_camera_) {
    display_.exposure = args.exposure;
    display_.curve = parse_tone_curve(args.tone);
    last_frame_ = cli::animation_end_frame(scene_, options_.pose);
    if (scene_.setup) last_frame_ = std::max(last_frame_, scene_.setup->frame_count - 1);
    endless_ = !args_.anims.empty();
}

std::vector<std::string> ViewerSession::camera_names() const {
    std::vector<std::string> names;
    for (const SceneCamera& c : scene_.cameras) names.push_back(c.name);
    return names;
}

void ViewerSession::use_scene_camera(std::size_t index) {
    if (index >= scene_.cameras.size()) {
        throw std::out_of_range("camera " + std::to_string(index) + ": the scene has " +
                                std::to_string(scene_.cameras.size()) + " camera(s)");
    }
    const SceneCamera& source = scene_.cameras[index];
    anim::PosedScene posed;
    anim::pose_scene(scene_, options_.pose, rendered_frame_, posed);
    const glm::dmat4& world = posed.node_world.at(std::size_t(source.node));
    const glm::dvec3 eye(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    const glm::dvec3 forward = glm::normalize(glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0));
    const bvh::Aabb bounds = scene_bounds(scene_);
    const glm::dvec3 centre = 0.5 * (glm::dvec3(bounds.lo) + glm::dvec3(bounds.hi));
    const double radius = 0.5 * glm::length(glm::dvec3(bounds.hi) - glm::dvec3(bounds.lo));
    const double depth = std::max(glm::dot(centre - eye, forward), 0.1 * std::max(radius, 1e-3));
    Camera camera;
    camera.eye = glm::vec3(eye);
    camera.target = glm::vec3(eye + depth * forward);
    camera.fov_y_deg = float(glm::degrees(source.yfov_rad));
    camera_ = OrbitCamera(camera);
}

void ViewerSession::step(int frames) {
    pause();
    seek(frame() + frames);
}

void ViewerSession::seek(int target) {
    pause();
    const int last = endless_ ? std::max(target, 0) : last_frame_;
    time_ = double(std::clamp(target, 0, last)) / fps();
}

void ViewerSession::advance(double seconds) {
    if (!playing_ || !(seconds > 0.0)) return;
    time_ += seconds * speed_;
    if (endless_) return;
    const double end = double(last_frame_ + 1) / fps();
    if (time_ < end) return;
    if (loop_ && last_frame_ > 0) {
        time_ = std::fmod(time_, end);
    } else {
        time_ = double(last_frame_) / fps();
        playing_ = false;
    }
}

int ViewerSession::frame() const {
    const int f = int(std::floor(time_ * fps() + 1e-9));
    return endless_ ? f : std::clamp(f, 0, last_frame_);
}

void ViewerSession::set(const std::string& name, const std::string& value) {
    const auto& table = setting_table();
    const auto found = std::find_if(table.begin(), table.end(), [&](const Setting& s) { return name == s.name; });
    if (found == table.end()) {
        std::string names;
        for (const Setting& s : table) names += std::string(names.empty() ? "" : ", ") + s.name;
        throw std::invalid_argument("unknown setting '" + name + "' (the viewer changes " + names + ")");
    }
    ViewArgs changed = args_;
    found->write(changed, value);
    RenderOptions options = cli::render_options(changed);  // refuses what the flags refuse
    cli::apply_scene_setup(scene_, changed, options);
    options.width = options_.width;
    options.height = options_.height;
    options.pose = options_.pose;
    options.pixel_cost = changed.view != "image";
    renderer_.set_options(options);
    if (changed.backend != args_.backend) renderer_.use_backend(options.backend ? options.backend() : nullptr);
    args_ = std::move(changed);
    options_ = std::move(options);
}

void ViewerSession::resize(int width, int height) {
    if (width < 1 || height < 1 || width > kMaxSize || height > kMaxSize) {
        throw std::invalid_argument("image size " + std::to_string(width) + "x" + std::to_string(height) +
                                    ": must be 1 to " + std::to_string(kMaxSize) + " pixels each way");
    }
    RenderOptions options = options_;
    options.width = width;
    options.height = height;
    renderer_.set_options(options);
    options_ = std::move(options);
}

std::vector<std::pair<std::string, std::string>> ViewerSession::settings() const {
    std::vector<std::pair<std::string, std::string>> out;
    for (const Setting& s : setting_table()) out.emplace_back(s.name, s.read(args_));
    return out;
}

const RenderedFrame& ViewerSession::render(int samples) {
    RenderOptions wanted = options_;
    if (samples > 0) wanted.sampling.spp = samples;
    if (!(wanted.sampling == renderer_.options().sampling)) renderer_.set_options(wanted);
    rendered_frame_ = frame();
    rendered_camera_ = camera_.camera();
    last_samples_ = samples;
    renderer_.render(scene_, rendered_camera_, rendered_frame_, frame_);
    complete_ = !frame_.stats.cancelled;
    if (!complete_) return frame_;
    history_.push_back(frame_.stats);
    if (history_.size() > kHistory) history_.pop_front();
    if (recorder_ != nullptr) recorder_->add(frame_);
    return frame_;
}

CostMeasure ViewerSession::cost_measure() const {
    return args_.view == "triangles" ? CostMeasure::triangles : CostMeasure::nodes;
}

std::uint32_t ViewerSession::heat_scale() const {
    return args_.cost_scale > 0 ? std::uint32_t(args_.cost_scale) : cost_scale(frame_.cost, cost_measure());
}

std::vector<unsigned char> ViewerSession::display_bytes() const {
    // A cost view whose frame has no costs yet (rendered before the switch) shows the image.
    const bool heat = args_.view != "image" && !frame_.cost.empty();
    const std::vector<std::uint8_t> rgb =
        heat ? cost_heat_rgb8(frame_.cost, cost_measure(), heat_scale()) : display_rgb8(frame_, display_);
    return {rgb.begin(), rgb.end()};
}

std::string ViewerSession::legend() const {
    if (args_.view == "image" || frame_.cost.empty()) return {};
    const CostMeasure measure = cost_measure();
    double sum = 0.0;
    std::uint32_t max = 0;
    for (const PixelCost& c : frame_.cost) {
        const std::uint32_t n = cost_of(c, measure);
        sum += n;
        max = std::max(max, n);
    }
    char text[160];
    std::snprintf(text, sizeof text, "%s per pixel: black 0, white %u or more; mean %.1f, max %u",
                  args_.view == "nodes" ? "node visits" : "triangle tests", heat_scale(),
                  sum / double(frame_.cost.size()), max);
    return text;
}

void ViewerSession::screenshot(const std::filesystem::path& path) {
    for (int attempt = 0; !complete_ && attempt < 8; ++attempt) render(last_samples_);
    if (frame_.color.empty() || !complete_) throw std::logic_error("screenshot: no whole frame to write");
    if (args_.view == "image") {
        write_image(path, frame_, display_);
    } else {
        write_image_rgb8(path, frame_.width, frame_.height, display_bytes());
    }
    std::filesystem::path json = path;
    json.replace_extension(".json");
    std::ofstream out(json);
    out << "{\"camera\": \"" << camera_text(rendered_camera_) << "\", \"frame\": " << rendered_frame_
        << ", \"view\": \"" << args_.view << "\", \"legend\": \"" << legend() << "\""
        << ", \"stats\": " << frame_report_json(frame_.stats) << "}\n";
    if (!out) throw std::runtime_error(json.string() + ": cannot be written");
}

}  // namespace dynrt::viewer
