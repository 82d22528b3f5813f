#include "value_types.h"

#include "numpy_args.h"

#include <iomanip>
#include <sstream>

namespace dynrt::python {

namespace {

std::string text(const Vec3& v) {
    std::ostringstream out;
    out << std::setprecision(9) << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return out.str();
}

/// A read-write property holding a Vec3 member as a tuple.
template <typename Class>
void vec3_property(py::class_<Class>& c, const char* name, Vec3 Class::*member) {
    const std::string where = std::string("dynrt.") + py::str(c.attr("__name__")).cast<std::string>();
    c.def_property(
        name, [member](const Class& self) { return to_tuple(self.*member); },
        [member, where, name](Class& self, py::handle value) { self.*member = vec3(value, where, name); });
}

}  // namespace

void bind_value_types(py::module_& m) {
    py::class_<View> view(m, "View", "A pinhole camera: eye, target, up, vertical field of view in degrees.");
    view.def(py::init([](py::handle eye, py::handle target, py::handle up, float fov_y_deg) {
                 return View{vec3(eye, "dynrt.View", "eye"), vec3(target, "dynrt.View", "target"),
                             vec3(up, "dynrt.View", "up"), fov_y_deg};
             }),
             py::arg("eye") = py::make_tuple(0.0, 0.0, 5.0), py::arg("target") = py::make_tuple(0.0, 0.0, 0.0),
             py::arg("up") = py::make_tuple(0.0, 1.0, 0.0), py::arg("fov_y_deg") = 45.0f);
    vec3_property(view, "eye", &View::eye);
    vec3_property(view, "target", &View::target);
    vec3_property(view, "up", &View::up);
    view.def_readwrite("fov_y_deg", &View::fov_y_deg);
    view.def("__repr__", [](const View& v) {
        return "dynrt.View(eye=" + text(v.eye) + ", target=" + text(v.target) + ", up=" + text(v.up) +
               ", fov_y_deg=" + std::to_string(v.fov_y_deg) + ")";
    });

    py::class_<Surface> surface(m, "Surface",
                                "A mesh's material: Phong terms, mirror reflectance, transmittance and "
                                "index of refraction (linear RGB), and optionally a diffuse texture (an id "
                                "from Engine.add_texture) with its wrap modes (\"repeat\", \"clamp\", "
                                "\"mirror\"), emission, and a cut-out's alpha_cutoff and alpha.");
    const Surface d;
    surface.def(py::init([](py::handle diffuse, py::handle specular, float shininess, py::handle reflectance,
                            py::handle transmittance, float ior, py::handle texture, const std::string& wrap_s,
                            const std::string& wrap_t, py::handle emission, float alpha_cutoff, float alpha) {
                    const char* w = "dynrt.Surface";
                    return Surface{vec3(diffuse, w, "diffuse"), vec3(specular, w, "specular"), shininess,
                                   vec3(reflectance, w, "reflectance"), vec3(transmittance, w, "transmittance"),
                                   ior, texture_id(texture, w), wrap(wrap_s, w, "wrap_s"), wrap(wrap_t, w, "wrap_t"),
                                   vec3(emission, w, "emission"), alpha_cutoff, alpha};
                }),
                py::arg("diffuse") = to_tuple(d.diffuse), py::arg("specular") = to_tuple(d.specular),
                py::arg("shininess") = d.shininess, py::arg("reflectance") = to_tuple(d.reflectance),
                py::arg("transmittance") = to_tuple(d.transmittance), py::arg("ior") = d.ior,
                py::arg("texture") = py::none(), py::arg("wrap_s") = wrap_name(d.wrap_s),
                py::arg("wrap_t") = wrap_name(d.wrap_t), py::arg("emission") = to_tuple(d.emission),
                py::arg("alpha_cutoff") = d.alpha_cutoff, py::arg("alpha") = d.alpha);
    vec3_property(surface, "diffuse", &Surface::diffuse);
    vec3_property(surface, "specular", &Surface::specular);
    surface.def_readwrite("shininess", &Surface::shininess);
    vec3_property(surface, "reflectance", &Surface::reflectance);
    vec3_property(surface, "transmittance", &Surface::transmittance);
    surface.def_readwrite("ior", &Surface::ior);
    vec3_property(surface, "emission", &Surface::emission);
    surface.def_readwrite("alpha_cutoff", &Surface::alpha_cutoff);
    surface.def_readwrite("alpha", &Surface::alpha);
    // The diffuse texture as add_texture's id, or None; wrap modes by name.
    surface.def_property(
        "texture",
        [](const Surface& self) -> py::object {
            if (!self.diffuse_texture.valid()) return py::none();
            return py::int_(self.diffuse_texture.value);
        },
        [](Surface& self, py::handle value) { self.diffuse_texture = texture_id(value, "dynrt.Surface"); });
    surface.def_property(
        "wrap_s", [](const Surface& self) { return wrap_name(self.wrap_s); },
        [](Surface& self, const std::string& value) { self.wrap_s = wrap(value, "dynrt.Surface", "wrap_s"); });
    surface.def_property(
        "wrap_t", [](const Surface& self) { return wrap_name(self.wrap_t); },
        [](Surface& self, const std::string& value) { self.wrap_t = wrap(value, "dynrt.Surface", "wrap_t"); });
    surface.def("__repr__", [](const Surface& s) {
        return "dynrt.Surface(diffuse=" + text(s.diffuse) + ", specular=" + text(s.specular) +
               ", shininess=" + std::to_string(s.shininess) + ", reflectance=" + text(s.reflectance) +
               ", transmittance=" + text(s.transmittance) + ", ior=" + std::to_string(s.ior) +
               (s.alpha_cutoff > 0.0f ? ", alpha_cutoff=" + std::to_string(s.alpha_cutoff) +
                                            ", alpha=" + std::to_string(s.alpha)
                                      : std::string()) +
               (s.diffuse_texture.valid() ? ", texture=" + std::to_string(s.diffuse_texture.value) +
                                                ", wrap_s='" + wrap_name(s.wrap_s) + "', wrap_t='" +
                                                wrap_name(s.wrap_t) + "'"
                                          : std::string()) +
               ")";
    });

    py::class_<Light> light(m, "Light",
                            "A light: a point, or with radius a sphere light, or with edge_u and edge_v a "
                            "quad light (area lights: soft shadows, one point per pixel sample); kind='spot' "
                            "(direction, inner_cone, outer_cone in degrees) or 'directional' (direction of "
                            "travel; position unused); color; falloff=True for inverse-square falloff; range "
                            "(docs/rendering.md \"Lights\").");
    light.def(py::init([](py::handle position, float intensity, py::handle radius, py::handle edge_u,
                          py::handle edge_v, const std::string& kind, py::handle color, py::handle direction,
                          float inner_cone, float outer_cone, bool falloff, float range) {
                  const std::string where = "dynrt.Light";
                  Light l{vec3(position, where, "position"), intensity};
                  if (!radius.is_none() && (!edge_u.is_none() || !edge_v.is_none())) {
                      invalid(where, "a light is a sphere (radius) or a quad (edge_u, edge_v), not both");
                  }
                  if (!radius.is_none()) {
                      l.shape = LightShape::sphere;
                      l.radius = radius.cast<float>();
                  } else if (!edge_u.is_none() || !edge_v.is_none()) {
                      if (edge_u.is_none() || edge_v.is_none()) invalid(where, "a quad light takes edge_u and edge_v");
                      l.shape = LightShape::quad;
                      l.edge_u = vec3(edge_u, where, "edge_u");
                      l.edge_v = vec3(edge_v, where, "edge_v");
                  }
                  if (kind == "spot") {
                      l.kind = LightKind::spot;
                  } else if (kind == "directional") {
                      l.kind = LightKind::directional;
                  } else if (kind != "point") {
                      invalid(where, "kind must be 'point', 'spot' or 'directional', not '" + kind + "'");
                  }
                  if (!color.is_none()) l.color = vec3(color, where, "color");
                  if (!direction.is_none()) l.direction = vec3(direction, where, "direction");
                  l.inner_cone_deg = inner_cone;
                  l.outer_cone_deg = outer_cone;
                  l.inverse_square = falloff;
                  l.range = range;
                  return l;
              }),
              py::arg("position"), py::arg("intensity") = 1.0f, py::kw_only(), py::arg("radius") = py::none(),
              py::arg("edge_u") = py::none(), py::arg("edge_v") = py::none(), py::arg("kind") = "point",
              py::arg("color") = py::none(), py::arg("direction") = py::none(), py::arg("inner_cone") = 0.0f,
              py::arg("outer_cone") = 45.0f, py::arg("falloff") = false, py::arg("range") = 0.0f);
    vec3_property(light, "position", &Light::position);
    light.def_readwrite("intensity", &Light::intensity);
    light.def_property_readonly("shape", [](const Light& l) {
        return std::string(l.shape == LightShape::sphere ? "sphere" : l.shape == LightShape::quad ? "quad" : "point");
    }, "'point', 'sphere' or 'quad'");
    light.def_property_readonly("kind", [](const Light& l) {
        return std::string(l.kind == LightKind::spot ? "spot" : l.kind == LightKind::directional ? "directional" : "point");
    }, "'point', 'spot' or 'directional'");
    light.def_readonly("radius", &Light::radius);
    vec3_property(light, "color", &Light::color);
    vec3_property(light, "direction", &Light::direction);
    light.def("__repr__", [](const Light& l) {
        std::string extra;
        if (l.shape == LightShape::sphere) extra = ", radius=" + std::to_string(l.radius);
        if (l.shape == LightShape::quad) extra = ", edge_u=" + text(l.edge_u) + ", edge_v=" + text(l.edge_v);
        if (l.kind == LightKind::spot) {
            extra += ", kind='spot', direction=" + text(l.direction) + ", inner_cone=" + std::to_string(l.inner_cone_deg) +
                     ", outer_cone=" + std::to_string(l.outer_cone_deg);
        }
        if (l.kind == LightKind::directional) extra += ", kind='directional', direction=" + text(l.direction);
        if (l.inverse_square) extra += ", falloff=True";
        if (l.range > 0.0f) extra += ", range=" + std::to_string(l.range);
        return "dynrt.Light(position=" + text(l.position) + ", intensity=" + std::to_string(l.intensity) + extra + ")";
    });
}

}  // namespace dynrt::python
