// Scenes for Python: cbps.scenes(), cbps.scene(name, **params) (a built-in scene, as `cbps
// scenes` lists them), cbps.load_scene(path) and cbps.parse_scene(text) (JSON scene files,
// docs/scene-format.md), and the Scene class with the world and solver settings the command
// line's step options set (--dt, --beta, --push, --solver, --iterations, --tolerance, --cfm,
// --seed) and to_json() / save(), which writes what load_scene reads back.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <span>

#include "cbps/base/error.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/scene/scene_json.hpp"
#include "cbps/scene/settings.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "convert.hpp"

namespace cbps::python {

namespace {

/// A keyword argument's value as the text a --param NAME=VALUE would give: numbers in Python's
/// shortest round-trip form (repr), words as they are.
std::string parameter_text(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::float_>(value)) return py::repr(value).cast<std::string>();
  return py::str(value).cast<std::string>();
}

/// A finite number > 0 (dt, duration), else InputError naming it and its unit.
double positive(double x, const std::string& what, const char* unit) {
  if (!(x > 0.0) || !std::isfinite(x))
    throw InputError(what + " " + number_text(x) + ": must be a positive finite " + unit);
  return x;
}

py::list parameter_list(const std::vector<SceneParameter>& parameters) {
  py::list out;
  for (const SceneParameter& p : parameters) {
    py::dict d;
    d["name"] = p.name;
    d["default"] = p.default_value;
    d["unit"] = p.unit;
    d["description"] = p.description;
    out.append(d);
  }
  return out;
}

}  // namespace

py::dict body_dict(const Body& b) {
  py::dict d;
  d["name"] = b.name;
  d["shape"] = b.shape.kind == Shape::Kind::Sphere ? "sphere"
               : b.shape.kind == Shape::Kind::Box  ? "box"
                                                   : "plane";
  d["static"] = b.is_static;
  d["mass"] = b.is_static ? py::object(py::none()) : py::object(py::float_(b.m));  // kg
  d["x"] = to_numpy(b.x);                                                          // m
  d["q"] = to_numpy(Eigen::Vector4d(b.q.w(), b.q.x(), b.q.y(), b.q.z()));          // w, x, y, z
  d["v"] = to_numpy(b.v());                                                        // m/s
  d["omega"] = to_numpy(b.omega());                                                // rad/s
  return d;
}

namespace {

/// A scene's name, parameters and its time and push settings (dt, duration, beta, push).
void bind_scene_time(py::class_<Scene>& scene) {
  scene.def_readwrite("name", &Scene::name)
      .def_property_readonly(
          "parameters",
          [](const Scene& s) {
            py::dict d;
            for (const auto& [name, value] : s.parameters) d[py::str(name)] = value;
            return d;
          },
          "a built-in scene's parameters, name -> value text")
      .def_property(
          "duration",
          [](const Scene& s) { return s.duration; },
          [](Scene& s, const py::object& t) {
            s.duration = positive(real_from_python(t, "duration"), "duration", "time in s");
          },
          "default simulated time of Simulation.run(), s");
}

/// A setting as Python gives it: a number, a whole number, one of its words or a bool.
template <typename T>
double setting_from_python(const Setting<T>& s, const py::handle& value) {
  const std::string key(s.key);
  if (s.type == SettingType::Word) {
    if (!py::isinstance<py::str>(value))
      throw InputError(key + " " + py::repr(value).cast<std::string>() + ": expected a string");
    std::string why;
    const std::string text = value.cast<std::string>();
    const std::optional<double> index = setting_value(s, text, why);
    if (!index) throw InputError(key + " '" + text + "': " + why);
    return *index;
  }
  if (s.type == SettingType::Flag) {
    if (!py::isinstance<py::bool_>(value))
      throw InputError(key + " " + py::repr(value).cast<std::string>() +
                       ": expected True or False");
    return value.cast<bool>() ? 1.0 : 0.0;
  }
  if (s.type == SettingType::Whole)
    return static_cast<double>(whole_from_python(
        value, key, static_cast<long long>(s.min), static_cast<long long>(s.max)));
  return real_from_python(value, key);
}

/// Each setting of `settings` (settings.hpp) a property of the scene file's key, held in the
/// part of the scene `part` gives, with the checks of the scene file and the command line.
template <typename T>
void bind_settings(py::class_<Scene>& scene,
                   std::span<const Setting<T>> settings,
                   T& (*part)(Scene&)) {
  for (const Setting<T>& setting : settings) {
    const Setting<T>* s = &setting;
    std::string doc(s->rule);
    if (!s->unit.empty()) doc += ", " + std::string(s->unit);
    if (s->applies != nullptr) doc = std::string(s->applies_text) + ": " + doc;
    scene.def_property(
        std::string(s->key).c_str(),
        [s, part](Scene& sc) -> py::object {
          const T& target = part(sc);
          if (s->type == SettingType::Word) return py::str(setting_text(*s, target));
          if (s->type == SettingType::Flag) return py::bool_(s->get(target) != 0.0);
          if (s->type == SettingType::Whole)
            return py::int_(static_cast<long long>(s->get(target)));
          return py::float_(s->get(target));
        },
        [s, part](Scene& sc, const py::object& value) {
          const double v = setting_from_python(*s, value);
          const std::string why = set_setting(part(sc), *s, v);
          if (why.empty()) return;
          const std::string text = s->type == SettingType::Word
                                       ? "'" + value.cast<std::string>() + "'"
                                       : py::repr(value).cast<std::string>();
          throw InputError(std::string(s->key) + " " + text + ": " + why);
        },
        doc.c_str());
  }
}

/// The world's settings (settings.hpp), each a property of the scene file's key, and gravity.
void bind_scene_world(py::class_<Scene>& scene) {
  bind_settings<World>(scene, world_settings(), [](Scene& sc) -> World& { return sc.world; });
  scene.def_property(
      "gravity",
      [](const Scene& s) { return to_numpy(s.world.gravity); },
      [](Scene& s, const py::object& g) { s.world.gravity = vector_from_python(g, "gravity", 3); },
      "g, m/s^2 (y is up)");
}

/// A scene's solver settings (settings.hpp: method, iterations, tolerance, ..., cfm), each a
/// property of the scene file's key, and `solver`, set as a --solver spec.
void bind_scene_solver(py::class_<Scene>& scene) {
  bind_settings<SolverSettings>(
      scene, solver_settings(), [](Scene& sc) -> SolverSettings& { return sc.solver; });
  scene.def_property(
      "solver",
      [](const Scene& s) { return std::string(to_string(s.solver.method)); },
      [](Scene& s, const std::string& spec) {
        apply_solver_spec(parse_solver_spec(spec, "solver"), s.solver);
      },
      "the method's name; set it with a --solver spec such as 'psor:1.3' or "
      "'apgd:restart=off' (parse_solver_spec)");
}

/// A scene's bodies, its JSON text and file, its repr.
void bind_scene_bodies(py::class_<Scene>& scene) {
  scene
      .def_property_readonly(
          "bodies",
          [](const Scene& s) {
            py::list out;
            for (const Body& b : s.bodies) out.append(body_dict(b));
            return out;
          },
          "the bodies' states (a new scene's initial ones): dicts of name, shape, static, mass "
          "(kg), x (m), q (w, x, y, z), v (m/s), omega (rad/s)")
      .def("to_json", &scene_to_json, "the scene as JSON text, which parse_scene reads back")
      .def(
          "save",
          [](const Scene& s, const std::string& path, bool force) {
            const std::string text = scene_to_json(s);
            write_atomically(path, "save " + path, force, [&](const std::string& temp) {
              std::FILE* f = std::fopen(temp.c_str(), "w");
              if (f == nullptr) throw std::runtime_error("cannot open " + temp);
              const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
              if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + temp);
            });
          },
          py::arg("path"),
          py::arg("force") = false,
          "writes the scene as a JSON scene file (as `cbps scenes NAME --export FILE`); an "
          "existing file is replaced only with force=True")
      .def("__repr__", [](const Scene& s) {
        return "<cbps.Scene '" + s.name + "': " + std::to_string(s.bodies.size()) + " bodies, " +
               std::to_string(s.distances.size()) + " distance constraints, dt " +
               number_text(s.world.dt) + " s>";
      });
}

/// The functions that list, make, read and parse scenes.
void bind_scene_functions(py::module_& m) {
  m.def(
      "scenes",
      [] {
        py::list out;
        for (const BuiltinScene& s : builtin_scenes()) {
          py::dict d;
          d["name"] = s.name;
          d["description"] = s.description;
          d["parameters"] = parameter_list(s.parameters);
          out.append(d);
        }
        return out;
      },
      "the built-in scenes as `cbps scenes --json` lists them: dicts of name, description and "
      "parameters (name, default, unit, description)");
  m.def(
      "scene",
      [](const std::string& name, const py::kwargs& params) {
        std::map<std::string, std::string> values;
        for (const auto& [key, value] : params)
          values[key.cast<std::string>()] = parameter_text(value);
        return make_builtin_scene(name, values);
      },
      py::arg("name"),
      "a built-in scene with its parameters as keywords, e.g. scene('chain', n=5, "
      "mass_ratio=100) (as `--param n=5 --param mass_ratio=100`); InputError for an unknown "
      "scene, parameter or value");
  m.def(
      "load_scene",
      [](const std::string& path) {
        // A folder would be read as empty text and reported as a JSON syntax error at line 1.
        std::error_code ec;
        if (std::filesystem::is_directory(path, ec))
          throw InputError(path +
                           ": a folder, not a scene file; load_scene reads a JSON scene file "
                           "(docs/scene-format.md), and a folder of Matrix Market files from "
                           "`cbps matrices` or write_problem is read by cbps.read_problem");
        return read_scene_file(path);
      },
      py::arg("path"),
      "reads a JSON scene file; InputError '<file>: <json path>: <why>', or naming a folder "
      "given instead of a file");
  m.def("parse_scene",
        &parse_scene,
        py::arg("text"),
        py::arg("source") = "<string>",
        "a scene from JSON text; `source` names it in errors");
}

}  // namespace

void bind_scenes(py::module_& m) {
  py::class_<Scene> scene(
      m,
      "Scene",
      "A scene: bodies, constraints, world and solver settings (scene.hpp). Made by "
      "cbps.scene(), cbps.load_scene() or cbps.parse_scene(); cbps.Simulation "
      "takes a copy.");
  bind_scene_time(scene);
  bind_scene_world(scene);
  bind_scene_solver(scene);
  bind_scene_bodies(scene);
  bind_scene_functions(m);
}

}  // namespace cbps::python
