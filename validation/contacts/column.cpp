// 5. The paper's friction bound ±μ m |g·n| (5.4) against Coulomb's ±μ λ_n on a column of n boxes
// on a plane tilted by θ, tan θ = 0.6 μ: Coulomb holds every column; the paper's bound holds only
// μ m_bottom g cos θ at the bottom, so the column slides when n sin θ > μ cos θ, with
// a = g (sin θ − μ cos θ / n).
#include <algorithm>
#include <cstdio>

#include "../harness.hpp"
#include "contacts.hpp"

namespace contacts {

namespace {

/// A column has held below this slip of its bottom box, m.
constexpr double kHoldSlip = 1e-3;
/// A sliding column's slip against ½ a t (t + dt), relative. The contact points sit within the
/// 1e-3 m margin, not on the plane, which must not change a.
constexpr double kSlipTolerance = 1e-3;

/// The direct path's iterations, the steps short of tolerance, and each box's largest rotation
/// from its start.
class Tilting : public cbps::StepObserver {
 public:
  Tilting(Column& r, const std::vector<cbps::Body>& start) : r_(r), start_(start) {}
  bool after_step(const cbps::Simulation& sim, const cbps::StepReport& report, long) override {
    r_.sweeps_max = std::max(r_.sweeps_max, report.solver.iterations);
    if (report.solver.termination == cbps::Termination::NotConverged ||
        report.position_solver.termination == cbps::Termination::NotConverged)
      ++r_.not_converged;
    r_.wall_time_s += report.wall_time_s;
    for (std::size_t k = 1; k < start_.size(); ++k) {
      r_.tilt_deg = std::max(
          r_.tilt_deg, sim.scene().bodies[k].q.angularDistance(start_[k].q) * 180.0 / cbps::kPi);
    }
    return true;
  }

 private:
  Column& r_;
  const std::vector<cbps::Body>& start_;
};

Column run_column(int n, const std::string& friction, double mu) {
  Column r;
  r.n = n;
  r.friction = friction;
  r.mu = mu;
  r.theta = std::atan(0.6 * mu);
  cbps::Scene scene = builtin("stack",
                              {{"n", std::to_string(n)},
                               {"mu", text(mu)},
                               {"friction", friction},
                               {"margin", "1e-3"},
                               {"dt", "1/240"},
                               {"duration", "2"}},
                              "direct");
  // Tilt the whole stack about z through the origin (a point of the plane): the plane's normal
  // becomes (−sin θ, cos θ, 0) and the boxes stay stacked along it, exactly touching.
  const cbps::Quat tilt(Eigen::AngleAxisd(r.theta, Vec3::UnitZ()));
  for (cbps::Body& b : scene.bodies) {
    b.x = tilt * b.x;
    b.q = tilt * b.q;
  }
  const Vec3 downhill = -(tilt * Vec3::UnitX());
  const double g = scene.world.gravity.norm();
  r.dt = scene.world.dt;
  r.duration = scene.duration;
  const double a = g * (std::sin(r.theta) - mu * std::cos(r.theta) / n);
  r.predicted_slide = friction == "paper" && a > 0.0;
  r.predicted_slip = r.predicted_slide ? 0.5 * a * r.duration * r.duration : 0.0;
  r.predicted_slip_euler =
      r.predicted_slide ? 0.5 * a * r.duration * (r.duration + scene.world.dt) : 0.0;
  const long steps = step_count(scene);
  std::vector<cbps::Body> start = scene.bodies;
  cbps::Simulation sim(std::move(scene));
  Tilting tilting(r, start);
  validation::run_steps(sim, steps, {&tilting});
  r.slip_bottom = (sim.bodies()[1].x - start[1].x).dot(downhill);
  r.slip_top = (sim.bodies().back().x - start.back().x).dot(downhill);
  return r;
}

}  // namespace

std::vector<Column> run_columns() {
  std::vector<Column> runs;
  for (const char* friction : {"paper", "coulomb"})
    for (int n : {1, 2, 5}) runs.push_back(run_column(n, friction, 0.25));
  return runs;
}

void check_columns(const std::vector<Column>& runs, Failures& f) {
  using validation::number_text;
  for (const Column& r : runs) {
    const bool slid = std::abs(r.slip_bottom) >= kHoldSlip;
    if (slid != r.predicted_slide)
      f.push_back("column n = " + std::to_string(r.n) + ", " + r.friction + " friction: " +
                  (slid ? "slides" : "holds") + " (slip " + number_text(r.slip_bottom) +
                  " m), predicted " + (r.predicted_slide ? "to slide" : "to hold"));
    if (r.predicted_slide &&
        !(std::abs(r.slip_bottom - r.predicted_slip_euler) <= kSlipTolerance * r.predicted_slip))
      f.push_back("column n = " + std::to_string(r.n) + ", " + r.friction + " friction: slip " +
                  number_text(r.slip_bottom) + " m against " + number_text(r.predicted_slip_euler) +
                  " m predicted");
  }
}

void print_columns(const std::vector<Column>& runs) {
  const Column& c0 = runs.front();
  std::printf(
      "\n### 5. column of n boxes on a plane tilted by θ = %.3f° (tan θ = 0.6 μ, μ = %g), margin "
      "1e-3 m, direct solver, dt = 1/%g s, %g s\n\n"
      "| n | friction | predicted | slip ½at² (m) | Euler ½at(t+dt) (m) | slip bottom (m) | slip "
      "top (m) | max tilt (°) | outcome | steps short of tolerance | wall (s) |\n"
      "|---:|---|---|---:|---:|---:|---:|---:|---|---:|---:|\n",
      c0.theta * 180.0 / cbps::kPi,
      c0.mu,
      std::round(1.0 / c0.dt),
      c0.duration);
  for (const Column& r : runs) {
    const bool slid = std::abs(r.slip_bottom) >= kHoldSlip;
    std::printf("| %d | %s | %s | %.5f | %.5f | %.5g | %.5g | %.2g | %s | %d of %ld | %.2f |\n",
                r.n,
                r.friction.c_str(),
                r.predicted_slide ? "slides" : "holds",
                r.predicted_slip,
                r.predicted_slip_euler,
                r.slip_bottom,
                r.slip_top,
                r.tilt_deg,
                slid ? "slides" : "holds",
                r.not_converged,
                std::lround(r.duration / r.dt),
                r.wall_time_s);
  }
}

void write_columns(std::ostream& j, const std::vector<Column>& runs) {
  using validation::json_number;
  j << "  \"column\": [\n";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const Column& r = runs[i];
    j << "    {\"n\": " << r.n << ", \"friction\": \"" << r.friction
      << "\", \"mu\": " << json_number(r.mu)
      << ", \"theta_deg\": " << json_number(r.theta * 180.0 / cbps::kPi)
      << ", \"dt\": " << json_number(r.dt) << ", \"duration\": " << json_number(r.duration)
      << ", \"slip_bottom\": " << json_number(r.slip_bottom)
      << ", \"slip_top\": " << json_number(r.slip_top)
      << ", \"max_tilt_deg\": " << json_number(r.tilt_deg)
      << ", \"predicted_slide\": " << (r.predicted_slide ? "true" : "false")
      << ", \"predicted_slip\": " << json_number(r.predicted_slip)
      << ", \"predicted_slip_euler\": " << json_number(r.predicted_slip_euler)
      << ", \"sweeps_max\": " << r.sweeps_max
      << ", \"steps_short_of_tolerance\": " << r.not_converged
      << ", \"wall_time_s\": " << json_number(r.wall_time_s) << "}" << list_end(i, runs.size());
  }
  j << "  ],\n";
}

}  // namespace contacts
