#include "scene_binding.h"

#include "engine_binding.h"
#include "numpy_args.h"

#include "dynrt/anim/clip_selection.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/engine/sequence.h"
#include "dynrt/scene/scene.h"
#include "dynrt/scene/warnings.h"

#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <span>
#include <string>
#include <vector>

namespace dynrt::python {

namespace {

std::span<const float> flat(std::span<const glm::vec3> v) {
    return {reinterpret_cast<const float*>(v.data()), 3 * v.size()};
}

static_assert(sizeof(glm::uvec3) == 3 * sizeof(std::uint32_t) && sizeof(glm::vec3) == 3 * sizeof(float));

Vec3 vec(const glm::vec3& v) { return Vec3{v.x, v.y, v.z}; }

Transform transform_of(const glm::dmat4& m) {
    Transform t;
    for (int column = 0; column < 4; ++column) {
        for (int row = 0; row < 4; ++row) t.m[std::size_t(column * 4 + row)] = float(m[column][row]);
    }
    return t;
}

Motion motion_of(anim::MotionClass c) {
    switch (c) {
        case anim::MotionClass::static_: return Motion::static_;
        case anim::MotionClass::rigid: return Motion::rigid;
        case anim::MotionClass::deformable: return Motion::deformable;
        case anim::MotionClass::exploding: return Motion::exploding;
    }
    return Motion::exploding;
}

static_assert(sizeof(glm::vec2) == 2 * sizeof(float));

Wrap api_wrap(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::repeat: return Wrap::repeat;
        case TextureWrap::clamp: return Wrap::clamp;
        case TextureWrap::mirror: return Wrap::mirror;
    }
    return Wrap::repeat;
}

View view_of(const Camera& c) { return View{vec(c.eye), vec(c.target), vec(c.up), c.fov_y_deg}; }

const std::string kLoadScene = "dynrt.load_scene";

/// The frame rate asked for (None: the file's, else 24), refused as the CLI's --fps refuses it.
double checked_fps(std::optional<double> fps, const Scene& scene) {
    if (!fps) return scene.setup ? scene.setup->fps : anim::kDefaultFps;
    if (!std::isfinite(*fps) || !(*fps > 0.0)) {
        std::ostringstream value;
        value << *fps;
        throw Error(Error::Code::invalid_argument, kLoadScene + ": fps '" + value.str() + "' is not a positive number");
    }
    return *fps;
}

/// The clips that play, by name or index as the CLI's --clip picks them (None: the CLI's
/// default, anim::default_clips).
std::vector<std::size_t> chosen_clips(const std::optional<std::vector<std::string>>& clips, const Scene& scene) {
    if (!clips) return anim::default_clips(scene);
    std::vector<std::size_t> chosen;
    for (const std::string& clip : *clips) {
        try {
            chosen.push_back(anim::find_clip(scene, clip));
        } catch (const std::invalid_argument& e) {
            throw Error(Error::Code::invalid_argument, kLoadScene + ": " + e.what());
        }
    }
    return chosen;
}

/// A loaded scene, its poser and the engine it plays into.
class SceneAnimation {
public:
    /// `fps` and `clips` as load_scene takes them (docs/python.md "Python"): None for the defaults.
    SceneAnimation(const std::string& source, std::optional<double> fps,
                   const std::optional<std::vector<std::string>>& clips, std::shared_ptr<PyEngine> engine)
        : engine_(std::move(engine)) {
        {
            const py::gil_scoped_release nogil;
            scene_ = std::make_unique<Scene>(load_scene(source));
        }
        anim::PoseSettings settings;
        settings.fps = checked_fps(fps, *scene_);
        settings.clips = chosen_clips(clips, *scene_);
        // Static and rigid objects are added once, from the poser's fixed vertices.
        settings.skip_fixed_positions = true;
        const py::gil_scoped_release nogil;
        poser_ = std::make_unique<anim::ScenePoser>(*scene_, settings);
        poser_->pose(0, posed_);
        // The file's textures, as the CLI's TextureSet opens them: a file path (read at the
        // first render that shows it) or embedded bytes.
        std::vector<TextureId> textures;
        for (const Texture& texture : scene_->textures) {
            if (texture.path.empty() && texture.encoded.empty()) {
                // What TextureSet says of such a texture; the engine refuses one without bytes.
                warn(Warning{.source = scene_->source,
                             .kind = "texture cannot be read",
                             .kinds = "textures cannot be read",
                             .item = "'" + texture.name + "'",
                             .detail = "the file holds no bytes for it",
                             .effect = "the diffuse colour is used alone"});
                textures.emplace_back();
                continue;
            }
            textures.push_back(engine_->engine().add_texture(TextureDesc{
                .name = texture.name, .path = texture.path, .encoded = texture.encoded,
                .mime_type = texture.mime_type, .srgb = texture.srgb}));
        }
        std::vector<glm::vec3> world, world_normals;
        for (std::size_t i = 0; i < scene_->objects.size(); ++i) {
            const Object& object = scene_->objects[i];
            const anim::PosedObject& posed = posed_.objects[i];
            const Material& material = scene_->materials.at(object.material);
            MeshDesc desc;
            desc.name = object.name;
            desc.indices = {reinterpret_cast<const std::uint32_t*>(object.mesh.triangles.data()),
                            3 * object.mesh.triangles.size()};
            desc.motion = motion_of(poser_->motion_class(i));
            desc.surface = Surface{vec(material.diffuse), vec(material.specular), material.shininess,
                                   vec(material.reflectance), vec(material.transmittance), material.ior};
            // An object without texture coordinates shades its colour alone, as in the CLI.
            if (material.diffuse_map && !object.mesh.texcoords.empty() &&
                material.diffuse_map->texture < textures.size()) {
                desc.texcoords = {reinterpret_cast<const float*>(object.mesh.texcoords.data()),
                                  2 * object.mesh.texcoords.size()};
                desc.surface.diffuse_texture = textures[material.diffuse_map->texture];
                desc.surface.wrap_s = api_wrap(material.diffuse_map->wrap_s);
                desc.surface.wrap_t = api_wrap(material.diffuse_map->wrap_t);
            }
            switch (poser_->motion_class(i)) {
                case anim::MotionClass::static_:
                    poser_->fixed_world_positions(i, posed_, world);
                    poser_->fixed_world_normals(i, posed_, world_normals);
                    desc.positions = flat(world);
                    desc.normals = flat(world_normals);
                    break;
                case anim::MotionClass::rigid:
                    desc.positions = flat(poser_->object_space_positions(i));
                    desc.normals = flat(poser_->object_space_normals(i));
                    desc.transform = transform_of(posed.transform);
                    break;
                default:
                    desc.positions = flat(posed.positions);
                    desc.normals = flat(posed.normals);
                    break;
            }
            ids_.push_back(engine_->engine().add_mesh(desc).value);
        }
        frame_ = 0;
    }

    /// Poses `frame`, hands what moved to the engine and updates it. One thread at a time (the
    /// posed frame is this object's state): a second one raises InvalidState. When a call fails
    /// part way (an engine change refused because another thread renders, a non-finite pose),
    /// the engine may hold some of the frame's changes and not others, so the next call hands it
    /// every moving object, not only those the poser saw change.
    /// `frame_number` is any Python int (checked here, so that 2**31 or -1 get the CLI's
    /// wording rather than a conversion error).
    py::object pose(const py::int_& frame_number) {
        int overflow = 0;
        const long long frame = PyLong_AsLongLongAndOverflow(frame_number.ptr(), &overflow);
        if (overflow != 0 || frame < 0 || frame > kFrameMax) {
            const std::string text = py::str(py::handle(frame_number));
            throw Error(Error::Code::invalid_argument,
                        "dynrt.Scene.pose: frame " + text +
                            (overflow < 0 || (overflow == 0 && frame < 0)
                                 ? ": frames are numbered from 0"
                                 : ": frame numbers above " + std::to_string(kFrameMax) + " are not supported"));
        }
        bool idle = false;
        if (!posing_.compare_exchange_strong(idle, true)) {
            throw Error(Error::Code::invalid_state, "dynrt.Scene.pose: another thread is posing this scene");
        }
        struct Done {
            std::atomic<bool>& posing;
            ~Done() { posing = false; }
        } done{posing_};
        FrameStats stats;
        {
            const py::gil_scoped_release nogil;
            Engine& engine = engine_->engine();
            try {
                poser_->pose(int(frame), posed_);
                for (std::size_t i = 0; i < ids_.size(); ++i) {
                    const anim::PosedObject& posed = posed_.objects[i];
                    if (!posed.changed && !resend_all_) continue;
                    const MeshId id{ids_[i]};
                    switch (poser_->motion_class(i)) {
                        case anim::MotionClass::static_: break;
                        case anim::MotionClass::rigid: engine.set_transform(id, transform_of(posed.transform)); break;
                        default: engine.set_positions(id, flat(posed.positions), flat(posed.normals)); break;
                    }
                }
                resend_all_ = false;
                stats = engine.update();
                frame_ = int(frame);
                posed_once_ = true;
            } catch (...) {
                resend_all_ = true;
                throw;
            }
        }
        // The report names the frame posed (FrameStats::frame counts the engine's updates).
        stats.frame = int(frame);
        return report_dict(stats);
    }

    /// The scene's first camera at the posed frame, or None.
    py::object camera() const {
        if (!posed_.camera) return py::none();
        return py::cast(view_of(camera_from_scene(*posed_.camera)));
    }

    View default_view() const { return view_of(default_camera(scene_bounds(*scene_))); }

    std::vector<Light> lights() const {
        std::vector<Light> out;
        // Where they are at the posed frame: a light on a node moves with it.
        for (const PointLight& l : lights_at(effective_lights(*scene_, RenderOptions{}), posed_)) {
            Light light{vec(l.position), l.intensity};
            light.kind = l.kind == PointLight::Kind::spot          ? LightKind::spot
                         : l.kind == PointLight::Kind::directional ? LightKind::directional
                                                                   : LightKind::point;
            light.color = vec(l.color);
            light.direction = vec(l.direction);
            light.inner_cone_deg = l.inner_cone * 57.29577951308232f;
            light.outer_cone_deg = l.outer_cone * 57.29577951308232f;
            light.inverse_square = l.inverse_square;
            light.range = l.range;
            out.push_back(light);
        }
        return out;
    }

    int frame_count() const {
        if (scene_->setup) return scene_->setup->frame_count;
        return int(std::ceil(poser_->end_time() * poser_->settings().fps)) + 1;
    }

    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const Object& o : scene_->objects) out.push_back(o.name);
        return out;
    }

    std::vector<std::string> motions() const {
        std::vector<std::string> out;
        for (std::size_t i = 0; i < ids_.size(); ++i) out.push_back(motion_name(motion_of(poser_->motion_class(i))));
        return out;
    }

    std::shared_ptr<PyEngine> engine_;
    std::unique_ptr<Scene> scene_;
    std::unique_ptr<anim::ScenePoser> poser_;
    anim::PosedScene posed_;
    std::vector<std::uint32_t> ids_;
    int frame_ = 0;
    /// Whether a pose() has succeeded: the engine's meshes are then up to date.
    bool posed_once_ = false;
    std::atomic<bool> posing_{false};
    bool resend_all_ = false;
};

}  // namespace

void bind_scene(py::module_& m) {
    py::class_<SceneAnimation>(m, "SceneAnimation",
                               "A scene file played into an Engine; dynrt.load_scene wraps it as dynrt.Scene.")
        .def(py::init<const std::string&, std::optional<double>, const std::optional<std::vector<std::string>>&,
                      std::shared_ptr<PyEngine>>(),
             py::arg("source"), py::arg("fps"), py::arg("clips"), py::arg("engine"))
        .def_readonly_static("frame_max", &kFrameMax)
        .def("pose", &SceneAnimation::pose, py::arg("frame"))
        .def_property_readonly("engine", [](const SceneAnimation& s) { return s.engine_; })
        .def_property_readonly("mesh_ids", [](const SceneAnimation& s) { return s.ids_; })
        .def_property_readonly("names", &SceneAnimation::names)
        .def_property_readonly("motions", &SceneAnimation::motions)
        .def_property_readonly("frame", [](const SceneAnimation& s) { return s.frame_; })
        .def_property_readonly("posed", [](const SceneAnimation& s) { return s.posed_once_; })
        .def_property_readonly("clips", [](const SceneAnimation& s) {
            std::vector<std::string> out;
            for (const std::size_t c : s.poser_->settings().clips.value_or(std::vector<std::size_t>{})) {
                out.push_back(s.scene_->clips[c].name);
            }
            return out;
        })
        .def_property_readonly("fps", [](const SceneAnimation& s) { return s.poser_->settings().fps; })
        .def_property_readonly("frame_count", &SceneAnimation::frame_count)
        .def_property_readonly("camera", &SceneAnimation::camera)
        .def_property_readonly("default_view", &SceneAnimation::default_view)
        .def_property_readonly("lights", &SceneAnimation::lights)
        .def_property_readonly("background", [](const SceneAnimation& s) {
            return s.scene_->setup ? to_tuple(vec(s.scene_->setup->background)) : to_tuple(RenderSettings{}.background);
        })
        .def_property_readonly("source", [](const SceneAnimation& s) { return s.scene_->source; })
        .def_property_readonly("ignored", [](const SceneAnimation& s) { return s.scene_->ignored; });
}

}  // namespace dynrt::python
