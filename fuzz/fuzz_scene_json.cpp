// libFuzzer target for the JSON scene reader, cbps::parse_scene (src/scene/scene_json.cpp).
// The contract: any input either reads as a Scene whose every number is finite, or throws
// cbps::InputError. Any other exception, a crash, a sanitizer report or a non-finite value in
// the Scene is a finding. A scene that reads is also written back (scene_to_json) and must read
// again, as scene_json.hpp promises.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/scene/scene.hpp"
#include "cbps/scene/scene_json.hpp"

namespace {

void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz_scene_json: %s\n", what);
  std::abort();
}

template <class Matrix>
bool finite(const Matrix& m) {
  return m.allFinite();
}

bool finite(double x) { return std::isfinite(x); }

void check_finite(const cbps::Scene& scene) {
  const cbps::World& w = scene.world;
  require(finite(w.gravity) && finite(w.dt) && finite(w.beta) && finite(w.mu) &&
              finite(w.restitution) && finite(w.restitution_threshold) &&
              finite(w.contact_margin) && finite(w.contact_persistence),
          "a world setting is not finite");
  require(finite(scene.duration), "the duration is not finite");
  require(finite(scene.solver.tolerance) && finite(scene.solver.delta_tolerance) &&
              finite(scene.solver.relaxation),
          "a solver setting is not finite");
  for (const cbps::Body& b : scene.bodies) {
    require(finite(b.m) && finite(b.minv()), "a body's mass or 1/mass is not finite");
    require(finite(b.I_body) && finite(b.I_body_inv), "a body's inertia or inverse is not finite");
    require(finite(b.x) && finite(b.q.coeffs()), "a body's position or orientation is not finite");
    require(finite(b.p) && finite(b.l), "a body's momentum is not finite");
    require(finite(b.v()) && finite(b.omega()), "a body's velocity is not finite");
  }
  for (const cbps::DistanceConstraint& d : scene.distances)
    require(finite(d.anchor_a) && finite(d.anchor_b) && finite(d.length),
            "a distance constraint is not finite");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  cbps::Scene scene;
  try {
    scene = cbps::parse_scene(text, "fuzz.json");
  } catch (const cbps::InputError&) {
    return 0;  // the expected answer to bad input
  }
  check_finite(scene);
  const std::string written = cbps::scene_to_json(scene);
  try {
    check_finite(cbps::parse_scene(written, "written.json"));
  } catch (const cbps::InputError& e) {
    std::fprintf(stderr,
                 "fuzz_scene_json: the written scene does not read back: %s\n%s\n",
                 e.what(),
                 written.c_str());
    std::abort();
  }
  return 0;
}
