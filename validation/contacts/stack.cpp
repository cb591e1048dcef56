// 6. The stack (8.1, 7.1.1): 10 unit boxes, dt = 1/60, 20 sweeps per system, 10 s; a
// stack at rest stays at rest, so the top box's drift and the deepest penetration are the
// errors. Row-by-row PGS, block PGS (a manifold's 12 rows solved together) and the direct path,
// each with the original and the improved push. Checked: block PGS and the direct path with the
// improved push hold it under 1 cm (the unit test's bound). With it, the spectrum of the stack's
// A at rest and the Gauss-Seidel iteration on it.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>

#include "../harness.hpp"
#include "contacts.hpp"

namespace contacts {

namespace {

constexpr double kStackBound = 0.01;  ///< m: drift and penetration, as in the unit test

/// The deepest penetration, the last step's residual and the wall time.
class Holding : public cbps::StepObserver {
 public:
  explicit Holding(Stack& r) : r_(r) {}
  bool after_step(const cbps::Simulation&, const cbps::StepReport& report, long) override {
    r_.max_penetration = std::max(r_.max_penetration, report.max_penetration);
    r_.residual_last = report.solver.residual;
    r_.wall_time_s += report.wall_time_s;
    return true;
  }

 private:
  Stack& r_;
};

Stack run_stack(const std::string& method, const std::string& push) {
  Stack r;
  r.method = method;
  r.push = push;
  cbps::Scene scene = builtin("stack", {{"n", "10"}, {"dt", "1/60"}, {"push", push}}, method);
  scene.solver.max_iterations = 20;
  const long steps = step_count(scene);
  cbps::Simulation sim(std::move(scene));
  const Vec3 top0 = sim.bodies().back().x;
  Holding holding(r);
  validation::run_steps(sim, steps, {&holding});
  const Vec3 d = sim.bodies().back().x - top0;
  r.drift = std::hypot(d.x(), d.z());
  r.drift_vertical = d.y();
  return r;
}

/// A's nonzero spectrum (7.1.1) and the spectral radius of G = −(D + L)⁻¹ U on A's range.
StackSpectrum stack_spectrum(double mu) {
  StackSpectrum r;
  r.mu = mu;
  const cbps::Simulation sim(builtin("stack", {{"n", "10"}, {"mu", text(mu)}}, "pgs"));
  const cbps::System sys = sim.build_system();
  const cbps::MatX A(sys.A);
  r.rows = static_cast<int>(A.rows());
  const Eigen::SelfAdjointEigenSolver<cbps::MatX> spectrum(A);
  r.eig_max = spectrum.eigenvalues().maxCoeff();
  r.eig_min = r.eig_max;
  for (const double e : spectrum.eigenvalues())
    if (e > 1e-9 * r.eig_max) r.eig_min = std::min(r.eig_min, e);
  const cbps::MatX lower = A.triangularView<Eigen::Lower>();
  const cbps::MatX upper = A.triangularView<Eigen::StrictlyUpper>();
  const cbps::MatX G = -lower.triangularView<Eigen::Lower>().solve(upper);
  const Eigen::EigenSolver<cbps::MatX> gs(G, false);
  for (const auto& e : gs.eigenvalues())
    if (std::abs(e) < 1.0 - 1e-9) r.rho = std::max(r.rho, std::abs(e));
  r.sweeps_per_decade = std::log(0.1) / std::log(r.rho);
  return r;
}

}  // namespace

Stacks run_stacks() {
  Stacks s;
  for (const char* method : {"pgs", "block-pgs", "direct"})
    for (const char* push : {"original", "improved"}) s.runs.push_back(run_stack(method, push));
  for (double mu : {0.5, 0.0}) s.spectrum.push_back(stack_spectrum(mu));
  return s;
}

void check_stacks(const Stacks& s, Failures& f) {
  for (const Stack& r : s.runs) {
    if (r.push != "improved" || r.method == "pgs") continue;  // reported, not checked
    if (!(r.drift < kStackBound && r.max_penetration < kStackBound))
      f.push_back("stack, " + r.method + ": top drift " + validation::number_text(r.drift) +
                  " m, penetration " + validation::number_text(r.max_penetration) +
                  " m, not < 1 cm");
  }
}

void print_stacks(const Stacks& s) {
  std::printf(
      "\n### 6. A 10-box stack, dt = 1/60 s, 20 sweeps per system, 10 s (8.1, 7.1.1)\n\n"
      "| solver | push | top drift (m) | top vertical (m) | max penetration (m) | "
      "last residual (N) | time (s) |\n|---|---|---:|---:|---:|---:|---:|\n");
  for (const Stack& r : s.runs) {
    std::printf("| %s | %s | %.2g | %.2g | %.2g | %.2g | %.2f |\n",
                r.method.c_str(),
                r.push.c_str(),
                r.drift,
                r.drift_vertical,
                r.max_penetration,
                r.residual_last,
                r.wall_time_s);
  }
  std::printf(
      "\nThe stack's A at rest and Gauss-Seidel on it (7.1.1), on A's range:\n\n"
      "| mu | rows | smallest nonzero eigenvalue | largest | condition | GS spectral radius | "
      "sweeps per decade |\n|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const StackSpectrum& r : s.spectrum) {
    std::printf("| %g | %d | %.3g | %.3g | %.3g | %.6f | %.0f |\n",
                r.mu,
                r.rows,
                r.eig_min,
                r.eig_max,
                r.eig_max / r.eig_min,
                r.rho,
                r.sweeps_per_decade);
  }
}

void write_stacks(std::ostream& j, const Stacks& s) {
  using validation::json_number;
  j << "  \"stack\": [\n";
  for (std::size_t i = 0; i < s.runs.size(); ++i) {
    const Stack& r = s.runs[i];
    j << "    {\"method\": \"" << r.method << "\", \"push\": \"" << r.push
      << "\", \"sweeps\": 20, \"top_drift\": " << json_number(r.drift)
      << ", \"top_drift_vertical\": " << json_number(r.drift_vertical)
      << ", \"max_penetration\": " << json_number(r.max_penetration)
      << ", \"residual_last\": " << json_number(r.residual_last)
      << ", \"wall_time_s\": " << json_number(r.wall_time_s) << "}" << list_end(i, s.runs.size());
  }
  j << "  ],\n  \"stack_spectrum\": [\n";
  for (std::size_t i = 0; i < s.spectrum.size(); ++i) {
    const StackSpectrum& r = s.spectrum[i];
    j << "    {\"mu\": " << json_number(r.mu) << ", \"rows\": " << r.rows
      << ", \"eigenvalue_min_nonzero\": " << json_number(r.eig_min)
      << ", \"eigenvalue_max\": " << json_number(r.eig_max)
      << ", \"gauss_seidel_rho\": " << json_number(r.rho)
      << ", \"sweeps_per_decade\": " << json_number(r.sweeps_per_decade) << "}"
      << list_end(i, s.spectrum.size());
  }
  j << "  ],\n";
}

}  // namespace contacts
