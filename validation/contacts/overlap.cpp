// 4. overlap (8.1): three boxes each sunk 25 % into the one below; the kinetic energy the push
// factor injects, original against improved, and the box states of the push-factor figure.
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "../harness.hpp"
#include "cbps/collision/collision.hpp"
#include "contacts.hpp"

namespace contacts {

namespace {

/// Resolved when the deepest contact is below this fraction of the initial overlap.
constexpr double kResolvedFraction = 0.01;
/// The improved push's kinetic energy while resolving, against the original's. The velocity
/// system has no push term, so only the solver's residual can put energy in.
constexpr double kInjectedRatio = 1e-3;

double deepest_contact(const std::vector<cbps::Body>& bodies) {
  double deepest = 0.0;
  for (const cbps::Manifold& m : cbps::detect_contacts(bodies))
    for (const cbps::ContactPoint& p : m.points) deepest = std::max(deepest, p.depth);
  return deepest;
}

/// The boxes and the kinetic energy at the start and after every step, the top box's highest
/// point, and when the overlap is resolved.
class Resolving : public cbps::StepObserver {
 public:
  explicit Resolving(Overlap& r) : r_(r) {}
  void start(cbps::Simulation& sim) override {
    record(sim);
    r_.top_start = r_.top_max = sim.bodies().back().x.y();
  }
  bool after_step(const cbps::Simulation& sim, const cbps::StepReport& report, long) override {
    r_.sweeps_max = std::max(r_.sweeps_max, report.solver.iterations);
    record(sim);
    r_.ke_max = std::max(r_.ke_max, r_.ke.back());
    if (sim.scene().bodies.back().x.y() > r_.top_max) {
      r_.top_max = sim.scene().bodies.back().x.y();
      r_.t_top_max = sim.time();
    }
    if (std::isnan(r_.t_resolved)) {
      r_.ke_injected = std::max(r_.ke_injected, r_.ke.back());
      if (deepest_contact(sim.scene().bodies) <= kResolvedFraction * r_.initial_overlap) {
        r_.t_resolved = sim.time();
        r_.ke_resolved = r_.ke.back();
      }
    }
    return true;
  }

 private:
  void record(const cbps::Simulation& sim) {
    std::vector<BoxState> boxes;
    for (const cbps::Body& b : sim.scene().bodies)
      if (!b.is_static) boxes.push_back({b.x, b.q, b.shape.half_extents});
    r_.states.push_back(boxes);
    r_.ke.push_back(kinetic_energy(sim));
  }

  Overlap& r_;
};

Overlap run_overlap(const std::string& push, const std::string& method) {
  Overlap r;
  r.push = push;
  r.method = method;
  cbps::Scene scene = builtin("overlap", {{"push", push}}, method);
  r.dt = scene.world.dt;
  r.beta = scene.world.beta;
  r.mu = scene.world.mu;
  const long steps = step_count(scene);
  const double edge = 2.0 * scene.bodies.back().shape.half_extents.y();
  r.initial_overlap = deepest_contact(scene.bodies);
  const auto n_boxes = static_cast<double>(scene.bodies.size() - 1);
  r.top_rest = edge * (n_boxes - 0.5);
  cbps::Simulation sim(std::move(scene));
  Resolving resolving(r);
  validation::run_steps(sim, steps, {&resolving});
  return r;
}

/// The largest kinetic energy of a run up to and including step `step`, J.
double injected_until(const Overlap& r, std::size_t step) {
  return *std::max_element(r.ke.begin(), r.ke.begin() + static_cast<long>(step) + 1);
}

std::string json_boxes(const std::vector<BoxState>& boxes) {
  std::ostringstream j;
  j << "[";
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const BoxState& b = boxes[i];
    j << (i ? ", " : "") << "{\"x\": " << json_array({b.x.x(), b.x.y(), b.x.z()})
      << ", \"q\": " << json_array({b.q.w(), b.q.x(), b.q.y(), b.q.z()})
      << ", \"half_extents\": " << json_array({b.h.x(), b.h.y(), b.h.z()}) << "}";
  }
  j << "]";
  return j.str();
}

/// The push-factor figure's three panels: begin, original and improved at the same time.
void write_figure(std::ostream& j, const Overlaps& o) {
  using validation::json_number;
  const Overlap& orig = o.runs[o.figure_original];
  const Overlap& impr = o.runs[o.figure_improved];
  const auto step = static_cast<std::size_t>(o.figure_step);
  j << "  \"push_factor_figure\": {\"time\": " << json_number(o.figure_time) << ", \"solver\": \""
    << orig.method << "\", \"dt\": " << json_number(orig.dt)
    << ", \"beta\": " << json_number(orig.beta) << ", \"mu\": " << json_number(orig.mu)
    << ", \"initial_overlap\": " << json_number(orig.initial_overlap) << ", \"panels\": [\n"
    << "    {\"label\": \"begin\", \"time\": 0, \"kinetic_energy\": "
    << json_number(orig.ke.front())
    << ", \"kinetic_energy_injected\": " << json_number(injected_until(orig, 0))
    << ", \"boxes\": " << json_boxes(orig.states.front()) << "},\n"
    << "    {\"label\": \"original\", \"time\": " << json_number(o.figure_time)
    << ", \"kinetic_energy\": " << json_number(orig.ke[step])
    << ", \"kinetic_energy_injected\": " << json_number(injected_until(orig, step))
    << ", \"boxes\": " << json_boxes(orig.states[step]) << "},\n"
    << "    {\"label\": \"improved\", \"time\": " << json_number(o.figure_time)
    << ", \"kinetic_energy\": " << json_number(impr.ke[step])
    << ", \"kinetic_energy_injected\": " << json_number(injected_until(impr, step))
    << ", \"boxes\": " << json_boxes(impr.states[step]) << "}\n  ]},\n";
}

}  // namespace

Overlaps run_overlaps() {
  Overlaps o;
  for (const char* method : {"pgs", "direct"})
    for (const char* push : {"original", "improved"}) o.runs.push_back(run_overlap(push, method));
  // The figure (scene defaults, PGS): begin, and both pushes when the original's top box peaks.
  o.figure_original = 0;
  o.figure_improved = 1;
  const Overlap& orig = o.runs[o.figure_original];
  o.figure_step = std::lround(orig.t_top_max / orig.dt);
  o.figure_time = static_cast<double>(o.figure_step) * orig.dt;
  return o;
}

void check_overlaps(const Overlaps& overlaps, Failures& f) {
  for (const Overlap& o : overlaps.runs) {
    if (o.push != "improved") continue;
    for (const Overlap& p : overlaps.runs) {
      if (p.push == "original" && p.method == o.method &&
          !(o.ke_injected < kInjectedRatio * p.ke_injected))
        f.push_back("overlap, " + o.method + ": improved push injects " +
                    validation::number_text(o.ke_injected) + " J, not < " +
                    validation::number_text(kInjectedRatio) + " of the original's (" +
                    validation::number_text(p.ke_injected) + " J)");
    }
  }
}

void print_overlaps(const Overlaps& o) {
  const Overlap& first = o.runs.front();
  std::printf(
      "\n### 4. overlap (8.1): 3 boxes of 1 m, each sunk %.2f m, dt = 1/%g s, beta = %g, μ = %g, "
      "margin 0, 2 s; resolved: deepest contact ≤ 1 %% of the overlap\n\n"
      "| push | solver | t resolved (s) | KE injected: max until resolved (J) | KE then (J) | max "
      "KE over 2 s (J) | top box: start, rest, max (m) | t of max (s) | iterations max |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|\n",
      first.initial_overlap,
      std::round(1.0 / first.dt),
      first.beta,
      first.mu);
  for (const Overlap& r : o.runs) {
    std::printf("| %s | %s | %s | %.3g | %s | %.3g | %.3f, %.3f, %.3f | %.3f | %d |\n",
                r.push.c_str(),
                r.method.c_str(),
                fmt("%.3f", r.t_resolved).c_str(),
                r.ke_injected,
                fmt("%.3g", r.ke_resolved).c_str(),
                r.ke_max,
                r.top_start,
                r.top_rest,
                r.top_max,
                r.t_top_max,
                r.sweeps_max);
  }
  std::printf("\nFigure: panels at t = 0 and t = %.3f s (%s solver)\n",
              o.figure_time,
              o.runs[o.figure_original].method.c_str());
}

void write_overlaps(std::ostream& j, const Overlaps& o) {
  using validation::json_number;
  j << "  \"overlap\": [\n";
  for (std::size_t i = 0; i < o.runs.size(); ++i) {
    const Overlap& r = o.runs[i];
    j << "    {\"push\": \"" << r.push << "\", \"solver\": \"" << r.method
      << "\", \"dt\": " << json_number(r.dt)
      << ", \"initial_overlap\": " << json_number(r.initial_overlap)
      << ", \"t_resolved\": " << json_number(r.t_resolved)
      << ", \"kinetic_energy_injected\": " << json_number(r.ke_injected)
      << ", \"kinetic_energy_resolved\": " << json_number(r.ke_resolved)
      << ", \"kinetic_energy_max\": " << json_number(r.ke_max)
      << ", \"top_start\": " << json_number(r.top_start)
      << ", \"top_rest\": " << json_number(r.top_rest)
      << ", \"top_max\": " << json_number(r.top_max)
      << ", \"t_top_max\": " << json_number(r.t_top_max) << ", \"sweeps_max\": " << r.sweeps_max
      << "}" << list_end(i, o.runs.size());
  }
  j << "  ],\n";
  write_figure(j, o);
}

}  // namespace contacts
