// 3. slide (5.4): a box sliding at v0 stops after v0²/(2 μ g) at t = v0/(μ g); semi-implicit
// Euler stops v0 dt/2 short of that.
#include <algorithm>
#include <cstdio>

#include "../harness.hpp"
#include "contacts.hpp"

namespace contacts {

namespace {

/// A body has stopped below this speed, m/s.
constexpr double kStopSpeed = 1e-6;

/// The box's x and v_x after every step.
class Sliding : public cbps::StepObserver {
 public:
  Sliding(Slide& r, std::vector<double>& x, std::vector<double>& v) : r_(r), x_(x), v_(v) {}
  bool after_step(const cbps::Simulation& sim, const cbps::StepReport& report, long) override {
    r_.sweeps_max = std::max(r_.sweeps_max, report.solver.iterations);
    x_.push_back(sim.scene().bodies.back().x.x());
    v_.push_back(sim.scene().bodies.back().v().x());
    return true;
  }

 private:
  Slide& r_;
  std::vector<double>&x_, &v_;
};

Slide run_slide(double mu, const std::string& dt_inv, const std::string& method) {
  Slide r;
  r.mu = mu;
  r.dt_inv = dt_inv;
  r.method = method;
  cbps::Scene scene = builtin("slide", {{"mu", text(mu)}, {"dt", "1/" + dt_inv}}, method);
  const double g = scene.world.gravity.norm(), dt = scene.world.dt;
  r.v0 = scene.bodies.back().v().x();
  r.t_ref = r.v0 / (mu * g);
  r.d_ref = r.v0 * r.v0 / (2.0 * mu * g);
  r.d_euler = r.d_ref - 0.5 * r.v0 * dt;
  scene.duration = 1.25 * r.t_ref + 0.25;
  const long steps = step_count(scene);
  cbps::Simulation sim(std::move(scene));
  const double x0 = sim.bodies().back().x.x();
  std::vector<double> x{x0}, v{r.v0};
  Sliding sliding(r, x, v);
  validation::run_steps(sim, steps, {&sliding});
  // Stop: the first sample with v ≤ kStopSpeed; its time extrapolated from the two samples
  // before it with their own decrement, t = t_{i−1} + dt v_{i−1} / (v_{i−2} − v_{i−1}).
  for (std::size_t i = 2; i < v.size(); ++i) {
    if (v[i] > kStopSpeed) continue;
    const double decrement = v[i - 2] - v[i - 1];
    r.t_stop = (static_cast<double>(i - 1) + (decrement > 0 ? v[i - 1] / decrement : 0.0)) * dt;
    r.d = x.back() - x0;
    r.creep = x.back() - x[i];
    break;
  }
  const auto sample = [&](double t) { return v[static_cast<std::size_t>(std::lround(t / dt))]; };
  r.decel = (sample(0.25 * r.t_ref) - sample(0.75 * r.t_ref)) /
            (dt * static_cast<double>(std::lround(0.75 * r.t_ref / dt) -
                                      std::lround(0.25 * r.t_ref / dt)));
  return r;
}

}  // namespace

std::vector<Slide> run_slides() {
  std::vector<Slide> runs;
  for (double mu : {0.1, 0.3, 0.6})
    for (const char* method : {"pgs", "direct"})
      for (const char* dt_inv : {"240", "960"}) runs.push_back(run_slide(mu, dt_inv, method));
  return runs;
}

void check_slides(const std::vector<Slide>& runs, Failures& f) {
  // The stopping distance's error must shrink from each dt to the next smaller one.
  for (const Slide& a : runs) {
    if (std::isnan(a.d)) {
      f.push_back("slide mu = " + fmt("%g", a.mu) + ", 1/" + a.dt_inv + ", " + a.method +
                  ": the box did not stop");
      continue;
    }
    for (const Slide& b : runs) {
      if (a.mu != b.mu || a.method != b.method || !(std::stod(b.dt_inv) > std::stod(a.dt_inv)))
        continue;
      if (!(std::abs(b.d - b.d_ref) < std::abs(a.d - a.d_ref)))
        f.push_back("slide mu = " + fmt("%g", a.mu) + ", " + a.method +
                    ": stopping distance error does not shrink from 1/" + a.dt_inv + " to 1/" +
                    b.dt_inv);
    }
  }
}

void print_slides(const std::vector<Slide>& runs) {
  std::printf(
      "\n### 3. slide (5.4): v0 = %g m/s, paper friction bound, improved push\n\n"
      "| μ | dt (s) | solver | d ref (m) | d Euler (m) | d (m) | (d − d ref)/d ref | t ref (s) | "
      "t (s) | (t − t ref)/t ref | decel / μg | creep (m) | iterations max |\n"
      "|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
      runs.front().v0);
  for (const Slide& r : runs) {
    const double g = std::abs(cbps::World{}.gravity.y());
    std::printf("| %g | 1/%s | %s | %.4f | %.4f | %s | %s | %.4f | %s | %s | %s | %s | %d |\n",
                r.mu,
                r.dt_inv.c_str(),
                r.method.c_str(),
                r.d_ref,
                r.d_euler,
                fmt("%.4f", r.d).c_str(),
                fmt("%+.2e", (r.d - r.d_ref) / r.d_ref).c_str(),
                r.t_ref,
                fmt("%.4f", r.t_stop).c_str(),
                fmt("%+.2e", (r.t_stop - r.t_ref) / r.t_ref).c_str(),
                fmt("%.5f", r.decel / (r.mu * g)).c_str(),
                fmt("%.1e", r.creep).c_str(),
                r.sweeps_max);
  }
}

void write_slides(std::ostream& j, const std::vector<Slide>& runs) {
  using validation::json_number;
  j << "  \"slide\": [\n";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const Slide& r = runs[i];
    j << "    {\"mu\": " << json_number(r.mu) << ", \"dt\": \"1/" << r.dt_inv
      << "\", \"solver\": \"" << r.method << "\", \"v0\": " << json_number(r.v0)
      << ", \"distance_ref\": " << json_number(r.d_ref)
      << ", \"distance_euler\": " << json_number(r.d_euler)
      << ", \"distance\": " << json_number(r.d) << ", \"time_ref\": " << json_number(r.t_ref)
      << ", \"time\": " << json_number(r.t_stop) << ", \"creep\": " << json_number(r.creep)
      << ", \"deceleration\": " << json_number(r.decel) << ", \"sweeps_max\": " << r.sweeps_max
      << "}" << list_end(i, runs.size());
  }
  j << "  ],\n";
}

}  // namespace contacts
