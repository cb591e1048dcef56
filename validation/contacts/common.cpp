// The helpers validate_contacts' cases share (contacts.hpp).
#include <algorithm>
#include <cstdio>

#include "../harness.hpp"
#include "contacts.hpp"

namespace contacts {

cbps::Scene builtin(const std::string& name,
                    const std::map<std::string, std::string>& values,
                    const std::string& method) {
  cbps::Scene scene = cbps::make_builtin_scene(name, values);
  scene.solver.method = cbps::method_of(method);
  return scene;
}

long step_count(const cbps::Scene& scene) {
  return std::max(1L, std::lround(scene.duration / scene.world.dt));
}

std::string text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "—";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

double kinetic_energy(const cbps::Simulation& sim) {
  double e = 0.0;
  for (const cbps::Body& body : sim.scene().bodies)
    e += body.is_static ? 0.0 : body.kinetic_energy();
  return e;
}

std::string json_array(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + validation::json_number(v[i]);
  return s + "]";
}

const char* list_end(std::size_t i, std::size_t size) { return i + 1 < size ? ",\n" : "\n"; }

}  // namespace contacts
