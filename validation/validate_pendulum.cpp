// validate_pendulum: the pendulum wave of the paper's Figure 10 (section 10) with attach=center,
// where every ball is an exact simple pendulum, against the exact large-amplitude period.
//
// Reference (README.md, "Exact period"): a point mass on a massless rod of length L released
// from rest at angle theta0 swings with period
//     T = 4 sqrt(L/g) K(k),   k = sin(theta0/2),   K(k) = ∫₀^{π/2} dφ / sqrt(1 − k² sin²φ).
// K comes from GSL (gsl_sf_ellint_Kcomp), never from the library under test; L is read from the
// scene's constraint (rest length, pivot to centre), g from the scene's gravity.
//
// Measurements, per ball and per time step dt (README.md, "How it is measured"):
//   period  T_meas = (t_last − t_first) / (m − 1) over the m upward zero crossings of x(t)
//           (x goes from < 0 to ≥ 0), each refined by a cubic through four samples;
//   error   e = (T_meas − T) / T, reported as max and mean of |e| over the balls;
//   order   p = log(e(dt1) / e(dt2)) / log(dt1 / dt2) for consecutive step sizes;
//   phase   360° (t_k − cycle) / T at the end of the cycle, t_k the maximum of x nearest
//           t = cycle, refined by a parabola through three samples;
//   and, to explain those: the first crossing's offset from 3T/4, the phase without the
//   half-step lead (t_k + dt/2), the amplitude change at t = cycle, the mean string stretch.
// It also compares cbps::elliptic_K (AGM) with GSL (Kcomp and Carlson's R_F), and checks that
// the scene's lengths L_k give T_k = cycle / (n0 + k) exactly.
//
// Exit status: 0 all checks pass, 1 a check failed (non-finite numbers, a period error that does
// not decrease as dt decreases, elliptic_K or the scene's lengths off), 2 bad usage.
#include <gsl/gsl_errno.h>
#include <gsl/gsl_mode.h>
#include <gsl/gsl_sf_ellint.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"
#include "harness.hpp"

namespace {

namespace fs = std::filesystem;

/// elliptic_K and GSL are both double precision, each good to a few units of round-off
/// (ε ≈ 2.2e-16). Against Kcomp on [0, 0.999] allow 1e-12 (Kcomp's own 1 − k² cancellation
/// grows like ε/(1 − k²)); against R_F with the exact complement allow 100 ε everywhere. Any real
/// mistake (a modulus/parameter mix-up k vs k², a wrong AGM start) is off by 1e-2 and more.
constexpr double kKcompTolerance = 1e-12;
constexpr double kCarlsonTolerance = 100 * 2.220446049250313e-16;
/// The scene's L_k = g (T_k / 4K)² must reproduce T_k = cycle/(n0+k) to round-off.
constexpr double kDesignTolerance = 1e-12;

struct Options {
  std::string out;
  std::vector<std::string> dt_inv{"60", "120", "240", "480", "960"};  ///< 1/dt, 1/s
  std::string n = "50";
  double duration = -1.0;  ///< s; < 0: one cycle plus the longest period
  std::map<std::string, std::string> params;
};

constexpr const char* kHelp =
    R"(validate_pendulum: the pendulum wave (attach=center) against the exact period
  T = 4 sqrt(L/g) K(sin(theta0/2)), K from GSL, at several time steps

Options:
  --out DIR          write validation.json and period_errors.csv into DIR
  --dts LIST         comma-separated 1/dt values, s^-1 (default 60,120,240,480,960)
  --n N              number of balls (default 50)
  --duration S       simulated time, s (default: one cycle plus the longest period)
  --param NAME=VALUE other pendulum-wave parameters (n0, cycle, theta0_deg, beta, ...)
  --help             this text
Exit status: 0 all checks pass, 1 a check failed, 2 bad usage.
)";

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, sep)) parts.push_back(part);
  return parts;
}

Options parse_options(int argc, char** argv) {
  Options o;
  validation::CommandLine cli("validate_pendulum", kHelp);
  cli.option("--out", [&o](const std::string& value) { o.out = value; });
  cli.option("--dts", [&o, &cli](const std::string& value) {
    o.dt_inv = split(value, ',');
    if (o.dt_inv.size() < 2) cli.fail("--dts: need at least two step sizes");
    std::vector<double> seen;
    for (const std::string& d : o.dt_inv) {
      double number = 0.0;
      if (!cbps::parse_number(d, number) || !(number > 0.0)) {
        cli.fail("--dts: '" + d + "' is not a positive number");
      }
      if (std::find(seen.begin(), seen.end(), number) != seen.end()) {
        cli.fail("--dts: '" + d + "' is given twice");
      }
      seen.push_back(number);
    }
  });
  cli.option("--n", [&o](const std::string& value) { o.n = value; });
  cli.option("--duration", [&o, &cli](const std::string& value) {
    if (!cbps::parse_number(value, o.duration) || !(o.duration > 0.0)) {
      cli.fail("--duration: '" + value + "' is not a positive number");
    }
  });
  cli.option("--param", [&o, &cli](const std::string& value) {
    const auto eq = value.find('=');
    if (eq == std::string::npos) cli.fail("--param: expected NAME=VALUE, got '" + value + "'");
    const std::string name = value.substr(0, eq);
    if (name == "attach" || name == "dt" || name == "n" || name == "duration") {
      cli.fail("--param: '" + name + "' is set by the validation itself");
    }
    o.params[name] = value.substr(eq + 1);
  });
  cli.parse(argc, argv);
  return o;
}

/// K(k) from GSL (modulus k, as cbps::elliptic_K); NaN if GSL reports an error.
double gsl_K(double k) {
  gsl_sf_result result;
  if (gsl_sf_ellint_Kcomp_e(k, GSL_PREC_DOUBLE, &result) != GSL_SUCCESS) return std::nan("");
  return result.val;
}

/// Exact period of a simple pendulum: T = 4 sqrt(L/g) K(sin(theta0/2)), s (K from GSL).
double exact_period(double L, double g, double theta0) {
  return 4.0 * std::sqrt(L / g) * gsl_K(std::sin(0.5 * theta0));
}

/// Times of the upward zero crossings of samples x_i = x(i dt) (x_i < 0 ≤ x_{i+1}). Between
/// samples i and i+1 the root of the cubic through x_{i−1}, x_i, x_{i+1}, x_{i+2} is found by
/// bisection in s = (t − t_i)/dt ∈ [0, 1]; at the ends of the record, the chord's root.
std::vector<double> upward_crossings(const std::vector<double>& x, double dt) {
  std::vector<double> times;
  for (std::size_t i = 0; i + 1 < x.size(); ++i) {
    if (!(x[i] < 0.0 && x[i + 1] >= 0.0)) continue;
    double s = x[i] / (x[i] - x[i + 1]);  // chord
    if (i >= 1 && i + 2 < x.size()) {
      const double xm = x[i - 1], x0 = x[i], x1 = x[i + 1], x2 = x[i + 2];
      // Lagrange cubic on the nodes s = −1, 0, 1, 2.
      const auto p = [&](double u) {
        return -xm * u * (u - 1) * (u - 2) / 6 + x0 * (u + 1) * (u - 1) * (u - 2) / 2 -
               x1 * (u + 1) * u * (u - 2) / 2 + x2 * (u + 1) * u * (u - 1) / 6;
      };
      double lo = 0.0, hi = 1.0;  // p(lo) < 0 ≤ p(hi)
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (p(mid) < 0.0 ? lo : hi) = mid;
      }
      s = 0.5 * (lo + hi);
    }
    times.push_back((static_cast<double>(i) + s) * dt);
  }
  return times;
}

struct Extremum {
  double t = std::nan("");  ///< s
  double x = std::nan("");  ///< m
};

/// The local maximum of x nearest t_target, searched within ±half_window of it; the parabola
/// through the three samples around the sampled maximum gives its vertex
///     s = (x_{i−1} − x_{i+1}) / (2 c),  c = x_{i−1} − 2 x_i + x_{i+1},
///     t = t_i + s dt,  x = x_i − (x_{i−1} − x_{i+1})² / (8 c).
/// NaN if the record has no maximum there.
Extremum extremum_near(const std::vector<double>& x,
                       double dt,
                       double t_target,
                       double half_window) {
  const long last = static_cast<long>(x.size()) - 2;
  const long lo = std::max(1L, static_cast<long>(std::floor((t_target - half_window) / dt)));
  const long hi = std::min(last, static_cast<long>(std::ceil((t_target + half_window) / dt)));
  Extremum best;
  for (long i = lo; i <= hi; ++i) {
    const double xm = x[static_cast<std::size_t>(i - 1)];
    const double x0 = x[static_cast<std::size_t>(i)];
    const double x1 = x[static_cast<std::size_t>(i + 1)];
    if (!(x0 >= xm && x0 > x1)) continue;
    const double c = xm - 2.0 * x0 + x1;  // < 0 at a maximum
    const double t = (static_cast<double>(i) + 0.5 * (xm - x1) / c) * dt;
    if (std::isnan(best.t) || std::abs(t - t_target) < std::abs(best.t - t_target)) {
      best.t = t;
      best.x = x0 - (xm - x1) * (xm - x1) / (8.0 * c);
    }
  }
  return best;
}

std::string parameter(const cbps::Scene& scene, const std::string& name) {
  for (const auto& [key, value] : scene.parameters) {
    if (key == name) return value;
  }
  throw cbps::InputError("scene '" + scene.name + "' has no parameter '" + name + "'");
}

double number_parameter(const cbps::Scene& scene, const std::string& name) {
  double v = 0.0;
  if (!cbps::parse_number(parameter(scene, name), v)) {
    throw cbps::InputError("parameter '" + name + "' is not a number");
  }
  return v;
}

struct Ball {
  int k = 0;
  double L = 0.0;                ///< pivot to centre, m (the constraint's rest length)
  double T_exact = 0.0;          ///< 4 sqrt(L/g) K(sin(theta0/2)) with GSL's K, s
  double T_design = 0.0;         ///< cycle / (n0 + k), s
  double T_measured = 0.0;       ///< mean period between upward zero crossings, s
  double rel_error = 0.0;        ///< (T_measured − T_exact) / T_exact
  int crossings = 0;             ///< upward zero crossings used
  double time_offset = 0.0;      ///< first crossing − 3 T_exact / 4 (its exact time), s
  double t_extremum = 0.0;       ///< max of x nearest t = cycle, s (NaN if not reached)
  double phase_error_deg = 0.0;  ///< 360 (t_extremum − cycle) / T_exact, deg
  /// The same without semi-implicit Euler's half-step lead from rest (README): 360 (t_extremum
  /// + dt/2 − cycle) / T_exact, deg; what the period error accumulates over the cycle.
  double drift_phase_deg = 0.0;
  double amplitude_change = 0.0;  ///< (x at that maximum − x(0)) / x(0)
  double mean_stretch = 0.0;      ///< time average of c / L, c = |x − pivot| − L (5.2.2)
};

struct Run {
  std::string dt_inv_text;
  double dt = 0.0;  ///< s
  long steps = 0;
  std::vector<Ball> balls;
  double max_rel_error = 0.0;          ///< max |e| over the balls
  double mean_rel_error = 0.0;         ///< mean |e|
  double mean_signed_error = 0.0;      ///< mean e (sign: > 0 the simulated balls are slow)
  double max_phase_deg = 0.0;          ///< max |phase error| at t = cycle (NaN if not reached)
  double mean_phase_deg = 0.0;         ///< mean |phase error|
  double max_drift_deg = 0.0;          ///< max |drift_phase_deg|
  double mean_offset_dt = 0.0;         ///< mean time_offset / dt
  double mean_amplitude_change = 0.0;  ///< mean amplitude_change at t = cycle
  double max_mean_stretch = 0.0;       ///< max over the balls of the time-averaged c / L
  double max_constraint_error = 0.0;   ///< m
  /// (E_final − E_initial) / E_swing, E_swing = Σ m g L (1 − cos θ0). Sampled with the step's
  /// v2 and new x, so it also carries symplectic Euler's O(dt) energy oscillation.
  double energy_change = 0.0;
  double design_error = 0.0;  ///< max |T_exact − T_design| / T_design
  double wall_time_s = 0.0;
  double order_max = std::nan("");  ///< against the previous (coarser) run
  double order_mean = std::nan("");
};

struct Settings {
  double cycle = 0.0, theta0 = 0.0, g = 0.0, beta = 0.0, duration = 0.0;
  long n = 0, n0 = 0;
};

/// The pendulum wave at 1/dt = dt_inv with the options' parameters (attach=center), and what
/// the validation reads of it into `settings`.
cbps::Scene pendulum_scene(const Options& o, const std::string& dt_inv, Settings& settings) {
  std::map<std::string, std::string> values = o.params;
  values["attach"] = "center";
  values["n"] = o.n;
  double per_second = 0.0;  // 1/dt, validated by parse_options
  cbps::parse_number(dt_inv, per_second);
  char dt_text[32];
  std::snprintf(dt_text, sizeof dt_text, "%.17g", 1.0 / per_second);  // round-trips exactly
  values["dt"] = dt_text;
  cbps::Scene probe = cbps::make_builtin_scene("pendulum-wave", values);
  settings.cycle = number_parameter(probe, "cycle");
  settings.theta0 = number_parameter(probe, "theta0_deg") * cbps::kPi / 180.0;
  if (!(settings.theta0 > 0.0)) {
    throw cbps::InputError("parameter 'theta0_deg': must be > 0 (the balls must swing)");
  }
  settings.g = -probe.world.gravity.y();
  settings.beta = probe.world.beta;
  settings.n = static_cast<long>(number_parameter(probe, "n"));
  settings.n0 = static_cast<long>(number_parameter(probe, "n0"));
  // Long enough to see the maximum after t = cycle of every ball: one more longest period.
  const double T_longest =
      exact_period(probe.distances.front().length, settings.g, settings.theta0);
  settings.duration = o.duration > 0.0 ? o.duration : settings.cycle + T_longest;
  return probe;
}

/// Every ball's x(i dt), at the start and after each step; the sum over the steps of its
/// string stretch c = |x − pivot| − L (5.2.2); the largest constraint error of the steps.
class Sampling : public cbps::StepObserver {
 public:
  Sampling(Run& run, std::size_t n) : run_(run), x(n), stretch(n, 0.0) {}
  void start(cbps::Simulation& sim) override {
    for (std::size_t k = 0; k < x.size(); ++k) {
      x[k].reserve(static_cast<std::size_t>(run_.steps) + 1);
      x[k].push_back(sim.bodies()[k].x.x());
    }
  }
  bool after_step(const cbps::Simulation& sim, const cbps::StepReport& report, long) override {
    run_.max_constraint_error = std::max(run_.max_constraint_error, report.max_constraint_error);
    for (std::size_t k = 0; k < x.size(); ++k) {
      x[k].push_back(sim.scene().bodies[k].x.x());
      stretch[k] += cbps::distance_violation(sim.scene().distances[k], sim.scene().bodies);
    }
    return true;
  }

 private:
  Run& run_;

 public:
  std::vector<std::vector<double>> x;  ///< per ball, m
  std::vector<double> stretch;         ///< per ball, m
};

/// Ball k's period, its error and the phase at the end of the cycle from its samples x (README,
/// "How periods and phases are measured").
Ball measure_ball(const Run& run,
                  const Settings& settings,
                  std::size_t k,
                  double L,
                  const std::vector<double>& x,
                  double stretch) {
  Ball b;
  b.k = static_cast<int>(k);
  b.L = L;
  b.T_exact = exact_period(b.L, settings.g, settings.theta0);
  b.T_design = settings.cycle / static_cast<double>(settings.n0 + static_cast<long>(k));
  const std::vector<double> up = upward_crossings(x, run.dt);
  b.crossings = static_cast<int>(up.size());
  b.T_measured =
      up.size() >= 2 ? (up.back() - up.front()) / static_cast<double>(up.size() - 1) : std::nan("");
  b.rel_error = (b.T_measured - b.T_exact) / b.T_exact;
  b.time_offset = up.empty() ? std::nan("") : up.front() - 0.75 * b.T_exact;
  const bool reached_cycle = settings.duration >= settings.cycle;
  const Extremum end =
      reached_cycle ? extremum_near(x, run.dt, settings.cycle, 0.5 * b.T_exact) : Extremum{};
  b.t_extremum = end.t;
  b.phase_error_deg = 360.0 * (end.t - settings.cycle) / b.T_exact;
  b.drift_phase_deg = 360.0 * (end.t + 0.5 * run.dt - settings.cycle) / b.T_exact;
  b.amplitude_change = (end.x - x.front()) / x.front();
  b.mean_stretch = stretch / static_cast<double>(run.steps) / b.L;
  return b;
}

/// The run's maxima and means over the balls.
void summarize_balls(Run& run) {
  // max that keeps a NaN (std::max would drop it), so the finiteness check sees it.
  const auto nan_max = [](double a, double b) {
    return std::isnan(a) || std::isnan(b) ? std::nan("") : std::max(a, b);
  };
  const double count = static_cast<double>(run.balls.size());
  for (const Ball& b : run.balls) {
    run.design_error = std::max(run.design_error, std::abs(b.T_exact - b.T_design) / b.T_design);
    run.max_rel_error = nan_max(run.max_rel_error, std::abs(b.rel_error));
    run.mean_rel_error += std::abs(b.rel_error) / count;
    run.mean_signed_error += b.rel_error / count;
    run.max_phase_deg = nan_max(run.max_phase_deg, std::abs(b.phase_error_deg));
    run.mean_phase_deg += std::abs(b.phase_error_deg) / count;
    run.max_drift_deg = nan_max(run.max_drift_deg, std::abs(b.drift_phase_deg));
    run.mean_offset_dt += b.time_offset / run.dt / count;
    run.mean_amplitude_change += b.amplitude_change / count;
    run.max_mean_stretch = nan_max(run.max_mean_stretch, b.mean_stretch);
  }
}

Run simulate(const Options& o, const std::string& dt_inv, Settings& settings) {
  cbps::Scene probe = pendulum_scene(o, dt_inv, settings);
  Run run;
  run.dt_inv_text = dt_inv;
  run.dt = probe.world.dt;
  run.steps = std::max(1L, std::lround(settings.duration / run.dt));
  cbps::Simulation sim(std::move(probe));
  const std::size_t n = sim.bodies().size();
  double E_swing = 0.0;  // J
  for (std::size_t k = 0; k < n; ++k) {
    E_swing += sim.bodies()[k].m * settings.g * sim.scene().distances[k].length *
               (1.0 - std::cos(settings.theta0));
  }
  Sampling sampling(run, n);
  const cbps::RunTotals totals = validation::run_steps(sim, run.steps, {&sampling});
  run.wall_time_s = totals.wall_time_s;
  run.energy_change = (totals.energy_final - totals.energy_initial) / E_swing;
  for (std::size_t k = 0; k < n; ++k) {
    run.balls.push_back(measure_ball(
        run, settings, k, sim.scene().distances[k].length, sampling.x[k], sampling.stretch[k]));
  }
  summarize_balls(run);
  return run;
}

/// cbps::elliptic_K (AGM) against two GSL references, relative differences |K − K_ref| / K_ref:
///   Kcomp:   gsl_sf_ellint_Kcomp(k) for k ∈ [0, 0.999] in steps of 0.001;
///   Carlson: K(k) = R_F(0, 1 − k², 1) with 1 − k² formed as (1 − k)(1 + k), on the same k and
///            on the tail k = 1 − 10⁻ʲ, j = 4 … 12 (release angles up to 180°).
/// Kcomp forms 1 − k² itself, which cancels as k → 1; kcomp_tail_loss shows by how much.
struct EllipticCheck {
  int samples = 0;
  double vs_kcomp = 0.0;  ///< max relative difference to Kcomp on [0, 0.999]
  double worst_k_kcomp = 0.0;
  double vs_carlson = 0.0;  ///< max relative difference to R_F on [0, 1 − 1e-12]
  double worst_k_carlson = 0.0;
  double kcomp_tail_loss = 0.0;  ///< max |Kcomp − R_F| / R_F on the tail (GSL's own cancellation)
};

EllipticCheck check_elliptic_K() {
  EllipticCheck c;
  const auto carlson = [](double k) {
    gsl_sf_result result;
    const int status =
        gsl_sf_ellint_RF_e(0.0, (1.0 - k) * (1.0 + k), 1.0, GSL_PREC_DOUBLE, &result);
    return status == GSL_SUCCESS ? result.val : std::nan("");
  };
  // Keeps the largest difference and its k; a NaN sticks.
  const auto track = [](double diff, double k, double& worst, double& worst_k) {
    if (!(diff <= worst)) {
      worst = diff;
      worst_k = k;
    }
  };
  for (int i = 0; i <= 999; ++i) {
    const double k = i / 1000.0;
    const double K = cbps::elliptic_K(k);
    track(std::abs(K - gsl_K(k)) / gsl_K(k), k, c.vs_kcomp, c.worst_k_kcomp);
    track(std::abs(K - carlson(k)) / carlson(k), k, c.vs_carlson, c.worst_k_carlson);
    ++c.samples;
  }
  double unused = 0.0;
  for (int j = 4; j <= 12; ++j) {
    const double k = 1.0 - std::pow(10.0, -j);
    track(std::abs(cbps::elliptic_K(k) - carlson(k)) / carlson(k),
          k,
          c.vs_carlson,
          c.worst_k_carlson);
    track(std::abs(gsl_K(k) - carlson(k)) / carlson(k), k, c.kcomp_tail_loss, unused);
    ++c.samples;
  }
  return c;
}

std::string period_csv(const std::vector<Run>& runs) {
  std::ostringstream csv;
  csv << "dt_inv,dt,k,length_m,period_exact_s,period_design_s,period_measured_s,rel_error,"
         "crossings,time_offset_s,t_extremum_s,phase_error_deg,drift_phase_deg,"
         "amplitude_change,"
         "mean_stretch\n";
  csv.precision(12);
  for (const Run& r : runs) {
    for (const Ball& b : r.balls) {
      csv << r.dt_inv_text << ',' << r.dt << ',' << b.k << ',' << b.L << ',' << b.T_exact << ','
          << b.T_design << ',' << b.T_measured << ',' << b.rel_error << ',' << b.crossings << ','
          << b.time_offset << ',' << b.t_extremum << ',' << b.phase_error_deg << ','
          << b.drift_phase_deg << ',' << b.amplitude_change << ',' << b.mean_stretch << '\n';
    }
  }
  return csv.str();
}

std::string validation_json(const Settings& s,
                            const std::vector<Run>& runs,
                            const EllipticCheck& ek,
                            const std::vector<std::string>& failures) {
  using validation::json_number_or_null;
  std::ostringstream j;
  j << "{\n  \"case\": \"pendulum-wave attach=center vs 4 sqrt(L/g) K(sin(theta0/2)) (GSL)\",\n"
    << "  \"scene\": {\"n\": " << s.n << ", \"n0\": " << s.n0
    << ", \"cycle_s\": " << json_number_or_null(s.cycle)
    << ", \"theta0_deg\": " << json_number_or_null(s.theta0 * 180.0 / cbps::kPi)
    << ", \"g\": " << json_number_or_null(s.g) << ", \"beta\": " << json_number_or_null(s.beta)
    << ", \"duration_s\": " << json_number_or_null(s.duration) << "},\n  \"runs\": [\n";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const Run& r = runs[i];
    j << "    {\"dt_inv\": \"" << r.dt_inv_text << "\", \"dt\": " << json_number_or_null(r.dt)
      << ", \"steps\": " << r.steps
      << ", \"max_rel_error\": " << json_number_or_null(r.max_rel_error)
      << ", \"mean_rel_error\": " << json_number_or_null(r.mean_rel_error)
      << ", \"mean_signed_rel_error\": " << json_number_or_null(r.mean_signed_error)
      << ", \"order_max\": " << json_number_or_null(r.order_max)
      << ", \"order_mean\": " << json_number_or_null(r.order_mean)
      << ", \"max_phase_error_deg\": " << json_number_or_null(r.max_phase_deg)
      << ", \"mean_phase_error_deg\": " << json_number_or_null(r.mean_phase_deg)
      << ", \"max_drift_phase_deg\": " << json_number_or_null(r.max_drift_deg)
      << ", \"mean_time_offset_over_dt\": " << json_number_or_null(r.mean_offset_dt)
      << ", \"mean_amplitude_change\": " << json_number_or_null(r.mean_amplitude_change)
      << ", \"max_mean_stretch\": " << json_number_or_null(r.max_mean_stretch)
      << ", \"max_constraint_error_m\": " << json_number_or_null(r.max_constraint_error)
      << ", \"energy_change_rel_swing\": " << json_number_or_null(r.energy_change)
      << ", \"design_period_rel_diff\": " << validation::number_text(r.design_error)
      << ", \"wall_time_s\": " << json_number_or_null(r.wall_time_s) << "}"
      << (i + 1 < runs.size() ? ",\n" : "\n");
  }
  j << "  ],\n  \"elliptic_K\": {\"samples\": " << ek.samples
    << ", \"max_rel_diff_vs_kcomp\": " << validation::number_text(ek.vs_kcomp)
    << ", \"worst_k_kcomp\": " << json_number_or_null(ek.worst_k_kcomp)
    << ", \"tolerance_kcomp\": " << json_number_or_null(kKcompTolerance)
    << ", \"max_rel_diff_vs_carlson_rf\": " << validation::number_text(ek.vs_carlson)
    << ", \"worst_k_carlson_rf\": " << json_number_or_null(ek.worst_k_carlson)
    << ", \"tolerance_carlson_rf\": " << json_number_or_null(kCarlsonTolerance)
    << ", \"kcomp_tail_loss\": " << json_number_or_null(ek.kcomp_tail_loss)
    << "},\n  \"passed\": " << (failures.empty() ? "true" : "false")
    << ",\n  \"failures\": " << validation::json_strings(failures) << "\n}\n";
  return j.str();
}

/// check_elliptic_K() printed and checked against its tolerances.
EllipticCheck report_elliptic_K(std::vector<std::string>& failures) {
  const EllipticCheck ek = check_elliptic_K();
  std::printf(
      "elliptic_K (AGM) vs GSL, %d values of k:\n"
      "  vs gsl_sf_ellint_Kcomp, k in [0, 0.999]:         max relative difference %.3g at k = "
      "%.4g (tolerance %.0e)\n"
      "  vs gsl_sf_ellint_RF(0, (1-k)(1+k), 1), k <= 1-1e-12: max relative difference %.3g at "
      "k = %.13g (tolerance %.1e)\n"
      "  (for k = 1-1e-4 ... 1-1e-12 Kcomp itself is off R_F by up to %.3g: it forms 1 - k^2)\n",
      ek.samples,
      ek.vs_kcomp,
      ek.worst_k_kcomp,
      kKcompTolerance,
      ek.vs_carlson,
      ek.worst_k_carlson,
      kCarlsonTolerance,
      ek.kcomp_tail_loss);
  if (!(ek.vs_kcomp <= kKcompTolerance)) {
    failures.push_back("elliptic_K differs from gsl_sf_ellint_Kcomp by " +
                       validation::number_text(ek.vs_kcomp));
  }
  if (!(ek.vs_carlson <= kCarlsonTolerance)) {
    failures.push_back("elliptic_K differs from gsl_sf_ellint_RF by " +
                       validation::number_text(ek.vs_carlson));
  }
  return ek;
}

/// The runs at every step size, coarsest first, each with its observed order against the one
/// before, and their checks.
std::vector<Run> run_all(const Options& o, Settings& settings, std::vector<std::string>& failures) {
  // Coarsest step first, so consecutive runs halve dt (for the default list).
  std::vector<std::string> dts = o.dt_inv;
  std::sort(dts.begin(), dts.end(), [](const std::string& a, const std::string& b) {
    double va = 0.0, vb = 0.0;
    cbps::parse_number(a, va);
    cbps::parse_number(b, vb);
    return va < vb;
  });
  std::vector<Run> runs;
  for (const std::string& d : dts) {
    runs.push_back(simulate(o, d, settings));
    Run& r = runs.back();
    if (runs.size() >= 2) {
      const Run& prev = runs[runs.size() - 2];
      // p = log(e1/e2) / log(dt1/dt2), where both errors are > 0 (dt1 > dt2: no duplicates).
      const double ratio = std::log(prev.dt / r.dt);
      const auto order = [ratio](double e1, double e2) {
        return e1 > 0.0 && e2 > 0.0 ? std::log(e1 / e2) / ratio : std::nan("");
      };
      r.order_max = order(prev.max_rel_error, r.max_rel_error);
      r.order_mean = order(prev.mean_rel_error, r.mean_rel_error);
      if (!(r.max_rel_error < prev.max_rel_error) || !(r.mean_rel_error < prev.mean_rel_error)) {
        failures.push_back("period error does not decrease from dt = 1/" + prev.dt_inv_text +
                           " to 1/" + r.dt_inv_text);
      }
    }
    const bool phase_expected = settings.duration >= settings.cycle;
    if (!std::isfinite(r.max_rel_error) || !std::isfinite(r.mean_rel_error) ||
        (phase_expected && !std::isfinite(r.max_phase_deg))) {
      failures.push_back("non-finite period or phase error at dt = 1/" + r.dt_inv_text);
    }
    if (!(r.design_error <= kDesignTolerance)) {
      failures.push_back("scene lengths L_k miss T_k = cycle/(n0+k) by " +
                         validation::number_text(r.design_error));
    }
    std::fprintf(stderr,
                 "validate_pendulum: dt = 1/%s done (%ld steps, %.1f s)\n",
                 d.c_str(),
                 r.steps,
                 r.wall_time_s);
  }
  return runs;
}

/// The table of the runs on stdout.
void print_runs(const Settings& settings, const std::vector<Run>& runs) {
  std::printf(
      "\npendulum wave, attach=center: n = %ld, n0 = %ld, cycle = %g s, theta0 = %g deg, "
      "beta = %g, %g s simulated\n",
      settings.n,
      settings.n0,
      settings.cycle,
      settings.theta0 * 180.0 / cbps::kPi,
      settings.beta,
      settings.duration);
  std::printf(
      "reference: T = 4 sqrt(L/g) K(sin(theta0/2)), K from GSL; design T_k = cycle/(n0+k) "
      "matches it to %.2g\n\n",
      runs.front().design_error);
  std::printf(
      "    1/dt   steps      max|e|     mean|e|      mean e  p(max) p(mean)  max|phase|  "
      "max|drift|  offset   mean dA/A      max|c|    wall\n"
      "     1/s                                                                     deg  "
      "       deg     /dt                        m       s\n");
  for (const Run& r : runs) {
    std::printf(
        "%8s %7ld %11.3e %11.3e %11.3e %7.3f %7.3f %11.3e %11.3e %7.3f %11.3e %11.3e %7.2f\n",
        r.dt_inv_text.c_str(),
        r.steps,
        r.max_rel_error,
        r.mean_rel_error,
        r.mean_signed_error,
        r.order_max,
        r.order_mean,
        r.max_phase_deg,
        r.max_drift_deg,
        r.mean_offset_dt,
        r.mean_amplitude_change,
        r.max_constraint_error,
        r.wall_time_s);
  }
  std::printf(
      "e = (T_measured - T_exact)/T_exact per ball (> 0: slow); p = log(e(dt1)/e(dt2)) / "
      "log(dt1/dt2);\nphase = 360 (t_max - cycle)/T at t = cycle, drift = the same with t_max + "
      "dt/2; "
      "offset = (first upward crossing "
      "- 3T/4)/dt;\ndA/A = amplitude change at t = cycle; |c| = constraint violation\n");
}

int run_validation(const Options& o) {
  gsl_set_error_handler_off();  // GSL errors come back as NaN, checked below
  std::vector<std::string> failures;
  const EllipticCheck ek = report_elliptic_K(failures);
  Settings settings;
  const std::vector<Run> runs = run_all(o, settings, failures);
  print_runs(settings, runs);
  if (!o.out.empty()) {
    const fs::path out(o.out);
    validation::write_result(out / "period_errors.csv", period_csv(runs));
    validation::write_result(out / "validation.json",
                             validation_json(settings, runs, ek, failures));
    std::printf("wrote %s/validation.json and period_errors.csv\n", o.out.c_str());
  }
  return validation::report_failures(failures);
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse_options(argc, argv);
  return validation::run_main("validate_pendulum", [&o] { return run_validation(o); });
}
