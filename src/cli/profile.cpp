// cbps profile LIBRARY --solvers LIST --out DIR: performance profiles (Dolan & Moré, Math.
// Program. 91, 2002) of solvers over a problem library (scripts/make_problem_library.py).
//
// Every solver runs on every problem from lambda = 0. After each sweep the natural-map residual
// (6.2) is divided by the problem's scale, scale_of(A + eps E, b) = max(1, ‖b‖∞, max |A_ij|), the
// one scale `cbps lcp` and the tests judge residuals by; the first sweep and time at which this
// relative residual falls to 1e-3, 1e-6 and 1e-10 are the solver's costs there (not reached within
// the budget: a failure, ratio ∞). Time is the wall time from the call of solve() to the end of
// that sweep less the time this command spends measuring, so a method's setup (ADMM's
// factorization) counts. The exact paths (direct, active-set) are one solve each: their cost at a
// tolerance is the solve's time if its final residual meets it. They have no sweeps, so they are
// in the time profiles only. tao:TYPE (a build with PETSc, docs/distributed.md) is iterative
// here: its TAO iterations are its "sweeps" (one TAO iteration costs far more than a sweep),
// handed over by solve_tao's monitor; time from the call of solve_tao, distributing A included.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/studies/performance_profile.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "common.hpp"
#include "tao_solvers.hpp"

namespace cbps::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// The relative residuals whose first sweep and time are the costs (of scale_of).
constexpr double kTolerances[] = {1e-3, 1e-6, 1e-10};
constexpr std::size_t kTolerancesCount = std::size(kTolerances);
/// The tau at which the summary reports rho_s(tau).
constexpr double kTaus[] = {1.0, 2.0, 10.0};
constexpr const char* kLibraryFormat = "cbps-problem-library/1";

struct ProfileOptions {
  std::string library;
  std::string solvers = "pgs,psor:1.3,sgs,pgs-nesterov,apgd,nncg,pgs-sm,admm,rbgs,block-pgs,direct";
  std::string out;
  bool quick = false;
  int budget_iterations = 100000;
  double time_limit = 1.0;
  bool json = false;
  bool quiet = false;
  bool plot = true;
};

/// One problem of the library as its index (library.json) describes it.
struct Entry {
  std::string name;
  std::string path;   ///< absolute: a `cbps matrices` folder or a Siconos .dat file
  std::string exact;  ///< absolute: the direct path's lambda (lambda.mtx)
  nlohmann::json index;
};

std::string text_field(const nlohmann::json& j,
                       const char* key,
                       const std::string& file,
                       const std::string& where) {
  if (!j.contains(key) || !j[key].is_string())
    throw InputError(file + ": " + where + "/" + key + ": missing or not a string");
  return j[key].get<std::string>();
}

/// The index of LIBRARY (a folder holding library.json, or that file): its problems, only the
/// quick ones with `quick`. InputError naming the file for anything missing or malformed.
std::vector<Entry> read_library(const std::string& library, bool quick) {
  std::error_code ec;
  const fs::path file =
      fs::is_directory(library, ec) ? fs::path(library) / "library.json" : fs::path(library);
  std::ifstream in(file);
  if (!in)
    throw InputError(file.string() +
                     ": cannot read the problem library's index (write a library with "
                     "scripts/make_problem_library.py CBPS DIR)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string() + ": not JSON: " + e.what());
  }
  if (!j.is_object() || j.value("format", "") != kLibraryFormat)
    throw InputError(file.string() + ": /format: not a problem library (expected \"" +
                     kLibraryFormat + "\")");
  if (!j.contains("problems") || !j["problems"].is_array())
    throw InputError(file.string() + ": /problems: missing or not an array");
  const fs::path folder = file.parent_path();
  std::vector<Entry> entries;
  for (std::size_t k = 0; k < j["problems"].size(); ++k) {
    const nlohmann::json& p = j["problems"][k];
    const std::string where = "/problems/" + std::to_string(k);
    if (!p.is_object()) throw InputError(file.string() + ": " + where + ": not an object");
    if (quick && !p.value("quick", false)) continue;
    Entry e;
    e.name = text_field(p, "name", file.string(), where);
    e.path = (folder / text_field(p, "path", file.string(), where)).string();
    e.exact = (folder / text_field(p, "exact", file.string(), where)).string();
    e.index = p;
    entries.push_back(std::move(e));
  }
  if (entries.empty())
    throw InputError(file.string() + ": no problems" + (quick ? " marked quick" : ""));
  return entries;
}

/// A problem loaded for the solvers, with what is known about its answer.
struct Problem {
  StoredProblem stored;
  SpMat A_solved;         ///< with_cfm(A, cfm): the matrix every solver works on
  VecX exact;             ///< the library's lambda*, N
  bool definite = false;  ///< rank A = rows: lambda* unique, so ‖λ − λ*‖ means something
  double scale = 1.0;     ///< scale_of(A + eps E, b)
  /// With the row kinds and manifolds of the folder's labels.json (read_problem).
  BoxedProblem problem() const { return stored.problem(); }
  BoxedProblem solved() const { return BoxedProblem{A_solved, stored.b, stored.cmin, stored.cmax}; }
};

Problem load(const Entry& e) {
  Problem p;
  p.stored = read_problem(e.path);
  require_symmetric(p.stored, "profile " + e.path);
  p.A_solved = with_cfm(p.stored.A, p.stored.cfm);
  p.scale = scale_of(p.solved());
  p.exact = read_matrix_market_vector(e.exact);
  if (p.exact.size() != p.stored.rows())
    throw InputError(e.exact + ": " + std::to_string(p.exact.size()) + " values for a problem of " +
                     std::to_string(p.stored.rows()) + " rows (" + e.path + ")");
  p.definite = e.index.value("definite", false);
  return p;
}

/// The first sweep and time at which the relative residual reached a tolerance; −1: never.
struct Reached {
  long iterations = -1;
  double time_s = 0.0;
};

/// One solver on one problem.
struct Measurement {
  std::string status;  ///< "solved" (1e-10 reached) or why it stopped short
  long iterations = 0;
  double time_s = 0.0;
  double residual = NAN;      ///< relative, at the end
  double lambda_error = NAN;  ///< ‖λ − λ*‖∞ at the end, N, where lambda* is unique
  Reached reached[kTolerancesCount];
  void reach(long iteration, double time, double relative_residual) {
    for (std::size_t i = 0; i < kTolerancesCount; ++i)
      if (reached[i].iterations < 0 && relative_residual <= kTolerances[i])
        reached[i] = {iteration, time};
  }
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Why a spec cannot run on a problem (empty: it can): what `cbps converge` refuses.
std::string not_applicable(const SolverSpec& spec, const Problem& p) {
  if (needs_jacobian(spec.method) && !p.stored.has_jacobian())
    return "not applicable: no J and Minv (a Siconos file)";
  if (spec.contacts_first && p.stored.kinds.empty())
    return "not applicable: no row kinds (contacts_first needs labels.json)";
  if (spec.method == Method::Lemke && p.stored.rows() > kMaxDenseLemkeRows)
    return "not applicable: more than " + std::to_string(kMaxDenseLemkeRows) +
           " rows (dense Lemke)";
  return "";
}

void finish(Measurement& m, const Problem& p, const VecX& lambda) {
  m.residual = natural_map_residual(p.solved(), lambda) / p.scale;
  if (p.definite && lambda.size() == p.exact.size())
    m.lambda_error = (lambda - p.exact).lpNorm<Eigen::Infinity>();
}

Measurement run_iterative(const Problem& p, const SolverSpec& spec, const ProfileOptions& o) {
  Measurement m;
  m.status = not_applicable(spec, p);
  if (!m.status.empty()) return m;
  VecX lambda = VecX::Zero(p.stored.rows());
  m.reach(0, 0.0, natural_map_residual(p.solved(), lambda) / p.scale);
  SolverOptions options = study_options(spec, o.budget_iterations, p.stored.cfm);
  const auto start = Clock::now();
  double measuring = 0.0;  // s spent in after_sweep so far, taken off the times
  options.after_sweep = [&](int k, const VecX& l, double) {
    const auto entered = Clock::now();
    const double time_s = std::chrono::duration<double>(entered - start).count() - measuring;
    const double relative = natural_map_residual(p.solved(), l) / p.scale;
    m.reach(k, time_s, relative);
    m.iterations = k;
    m.time_s = time_s;
    if (!std::isfinite(relative)) m.status = "non-finite";
    if (m.reached[kTolerancesCount - 1].iterations >= 0) m.status = "solved";
    if (m.status.empty() && time_s >= o.time_limit) m.status = "time limit";
    measuring += seconds_since(entered);
    return m.status.empty();
  };
  const SolverSummary summary = solve(p.problem(), lambda, options);
  if (m.status.empty())
    m.status = summary.termination == Termination::MaxIterations ? "iteration budget"
                                                                 : to_string(summary.termination);
  finish(m, p, lambda);
  return m;
}

/// tao:TYPE from lambda = 0: each TAO iteration as a sweep (the monitor of solve_tao, with the
/// natural-map residual on PETSc's vectors), at most the budget's iterations, stopped by the
/// monitor at the time limit, by solve_tao's test at relative residual 1e-10.
Measurement run_tao(const Problem& p,
                    const SolverSpec& spec,
                    const ProfileOptions& o,
                    const TaoInProcess& tao) {
  Measurement m;
  m.reach(0, 0.0, natural_map_residual(p.solved(), VecX::Zero(p.stored.rows())) / p.scale);
  const distributed::TaoMonitor monitor = [&](const distributed::TaoIterate& at, const VecX&) {
    if (at.iteration == 0) return true;  // TAO's start
    const double relative = at.residual / p.scale;
    m.reach(at.iteration, at.time_s, relative);
    m.iterations = at.iteration;
    m.time_s = at.time_s;
    if (!std::isfinite(relative)) m.status = "non-finite";
    if (m.reached[kTolerancesCount - 1].iterations >= 0) m.status = "solved";
    if (m.status.empty() && at.time_s >= o.time_limit) m.status = "time limit";
    return m.status.empty();
  };
  const TaoRun r = tao.solve(p.solved(),
                             spec.tao,
                             o.budget_iterations,
                             kTolerances[kTolerancesCount - 1] * p.scale,
                             monitor);
  if (m.status.empty())
    m.status = r.reason == "DIVERGED_MAXITS" ? "iteration budget" : "TAO " + r.reason;
  finish(m, p, r.lambda);
  return m;
}

Measurement run_exact(const Problem& p, const SolverSpec& spec) {
  Measurement m;
  m.status = not_applicable(spec, p);
  if (!m.status.empty()) return m;
  VecX lambda = VecX::Zero(p.stored.rows());
  SolverOptions options = study_options(spec, 1, p.stored.cfm);
  const auto start = Clock::now();
  const SolverSummary summary = solve(p.problem(), lambda, options);
  m.time_s = seconds_since(start);
  m.iterations = summary.iterations;
  finish(m, p, lambda);
  for (std::size_t i = 0; i < kTolerancesCount; ++i)
    if (m.residual <= kTolerances[i]) m.reached[i] = {1, m.time_s};
  m.status =
      m.reached[kTolerancesCount - 1].iterations >= 0 ? "solved" : to_string(summary.termination);
  return m;
}

std::string tolerance_key(double tolerance) {
  char text[16];
  std::snprintf(text, sizeof text, "%g", tolerance);
  return text;
}

std::string csv_number(double x) {
  if (!std::isfinite(x)) return "";
  std::ostringstream out;
  out.precision(9);
  out << x;
  return out.str();
}

nlohmann::json json_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

/// One profile: a tolerance, a cost (time or sweeps) and the solvers it compares.
struct Profile {
  double tolerance = 0.0;
  std::string measure;               ///< "time" or "sweeps"
  std::vector<std::size_t> solvers;  ///< indices into the specs
  CostTable ratios;                  ///< [problem][position in solvers]
};

Profile make_profile(double tolerance,
                     std::size_t t,
                     bool sweeps,
                     const std::vector<SolverSpec>& specs,
                     const std::vector<std::vector<Measurement>>& runs) {
  Profile profile;
  profile.tolerance = tolerance;
  profile.measure = sweeps ? "sweeps" : "time";
  for (std::size_t s = 0; s < specs.size(); ++s)
    if (!sweeps || is_iterative(specs[s].method) || !specs[s].tao.empty())
      profile.solvers.push_back(s);
  CostTable cost;
  for (const std::vector<Measurement>& problem_runs : runs) {
    std::vector<double> row;
    for (const std::size_t s : profile.solvers) {
      const Reached& at = problem_runs[s].reached[t];
      row.push_back(at.iterations < 0 ? std::numeric_limits<double>::infinity()
                    : sweeps          ? static_cast<double>(at.iterations)
                                      : at.time_s);
    }
    cost.push_back(std::move(row));
  }
  profile.ratios = performance_ratios(cost);
  return profile;
}

/// The summary table: per tolerance, per solver the problems solved and rho_s(tau) at 1, 2, 10
/// for time and sweeps.
std::string summary_text(const std::vector<Entry>& entries,
                         const std::vector<SolverSpec>& specs,
                         const std::vector<Profile>& profiles,
                         const ProfileOptions& o,
                         double wall_time_s) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line,
                sizeof line,
                "cbps profile: %zu problems x %zu solvers from lambda = 0; budget %d sweeps and "
                "%g s per problem and solver; %.3g s in all\n",
                entries.size(),
                specs.size(),
                o.budget_iterations,
                o.time_limit,
                wall_time_s);
  out << line;
  out << "residual relative to scale_of = max(1, |b|inf, max |A_ij|); rho(tau): fraction of "
         "problems within tau x the best solver's cost (Dolan & More 2002); exact paths have "
         "no sweeps\n";
  for (std::size_t t = 0; t < kTolerancesCount; ++t) {
    const Profile& time = profiles[2 * t];
    const Profile& sweeps = profiles[2 * t + 1];
    std::snprintf(line,
                  sizeof line,
                  "\nrelative residual <= %g\n%-24s %7s   %-23s   %-23s\n",
                  kTolerances[t],
                  "",
                  "",
                  "------- time: rho -----",
                  "------ sweeps: rho ----");
    out << line;
    std::snprintf(line,
                  sizeof line,
                  "%-24s %7s   %7s %7s %7s   %7s %7s %7s\n",
                  "solver",
                  "solved",
                  "tau=1",
                  "2",
                  "10",
                  "tau=1",
                  "2",
                  "10");
    out << line;
    for (std::size_t s = 0; s < specs.size(); ++s) {
      std::size_t solved = 0;
      for (const std::vector<double>& r : time.ratios)
        if (std::isfinite(r[s])) ++solved;
      std::snprintf(line,
                    sizeof line,
                    "%-24s %3zu/%-3zu   %7.3f %7.3f %7.3f",
                    specs[s].text.c_str(),
                    solved,
                    entries.size(),
                    performance_fraction(time.ratios, s, kTaus[0]),
                    performance_fraction(time.ratios, s, kTaus[1]),
                    performance_fraction(time.ratios, s, kTaus[2]));
      out << line;
      const auto at = std::find(sweeps.solvers.begin(), sweeps.solvers.end(), s);
      if (at == sweeps.solvers.end()) {
        std::snprintf(line, sizeof line, "   %7s %7s %7s\n", "-", "-", "-");
      } else {
        const auto k = static_cast<std::size_t>(at - sweeps.solvers.begin());
        std::snprintf(line,
                      sizeof line,
                      "   %7.3f %7.3f %7.3f\n",
                      performance_fraction(sweeps.ratios, k, kTaus[0]),
                      performance_fraction(sweeps.ratios, k, kTaus[1]),
                      performance_fraction(sweeps.ratios, k, kTaus[2]));
      }
      out << line;
    }
  }
  return out.str();
}

nlohmann::json profile_json(const Profile& profile, const std::vector<SolverSpec>& specs) {
  nlohmann::json j;
  j["tolerance"] = profile.tolerance;
  j["measure"] = profile.measure;
  j["solvers"] = nlohmann::json::array();
  for (const std::size_t s : profile.solvers) j["solvers"].push_back(specs[s].text);
  j["ratios"] = nlohmann::json::array();
  for (const std::vector<double>& r : profile.ratios) {
    nlohmann::json row = nlohmann::json::array();
    for (const double x : r) row.push_back(json_or_null(x));
    j["ratios"].push_back(row);
  }
  j["rho"] = nlohmann::json::object();
  for (std::size_t k = 0; k < profile.solvers.size(); ++k) {
    nlohmann::json rho = nlohmann::json::object();
    for (const double tau : kTaus)
      rho[tolerance_key(tau)] = performance_fraction(profile.ratios, k, tau);
    rho["inf"] = performance_fraction(profile.ratios, k, std::numeric_limits<double>::infinity());
    j["rho"][specs[profile.solvers[k]].text] = rho;
  }
  return j;
}

/// What decides a spec's curve here: every solve starts from lambda = 0, so the warm-start
/// factors (warm, warm_friction) never act; the method, omega, row order, contacts_first, the
/// method's own parameters and the TAO type do. Two specs with the same key draw the same curve.
std::string curve_key(const SolverSpec& spec) {
  if (!spec.tao.empty()) return "tao:" + spec.tao;
  std::ostringstream key;
  key.precision(17);
  key << static_cast<int>(spec.method) << ' ' << spec.relaxation << ' '
      << static_cast<int>(spec.order) << ' ' << spec.contacts_first;
  for (const auto& [name, value] : method_parameters(spec.method, spec.methods))
    key << ' ' << name << '=' << value;
  return key.str();
}

/// InputError (exit 2) when two specs of --solvers would draw the same curve: the same text
/// twice (`pgs,pgs`) or two texts for the same solver (`pgs,psor:1`, `pgs,pgs:warm=off`).
void refuse_duplicates(const std::vector<SolverSpec>& specs, const std::string& list) {
  for (std::size_t i = 0; i < specs.size(); ++i)
    for (std::size_t k = 0; k < i; ++k) {
      if (specs[i].text == specs[k].text)
        throw InputError("--solvers '" + list + "': '" + specs[i].text +
                         "' is listed twice; give each solver once");
      if (curve_key(specs[i]) == curve_key(specs[k]))
        throw InputError("--solvers '" + list + "': '" + specs[i].text +
                         "' is the same solver as '" + specs[k].text +
                         "' (same method and settings; every solve starts from lambda = 0, so "
                         "warm factors do not count) and would draw the same curve; give it once");
    }
}

int profile_command(const ProfileOptions& o) {
  const auto started = Clock::now();
  const std::vector<SolverSpec> specs = parse_cli_solver_list(o.solvers, "--solvers");
  refuse_duplicates(specs, o.solvers);
  const TaoInProcess tao(specs, "profile --solvers");  // PETSc once, for every tao spec
  const std::vector<Entry> entries = read_library(o.library, o.quick);
  // Every problem is read before any solver runs, so a bad file is reported at once (exit 2).
  std::vector<Problem> problems;
  for (const Entry& e : entries) problems.push_back(load(e));
  std::unique_ptr<OutputDir> dir;
  if (!o.out.empty()) dir = std::make_unique<OutputDir>(o.out);

  std::vector<std::vector<Measurement>> runs;  // [problem][solver]
  for (std::size_t p = 0; p < problems.size(); ++p) {
    runs.emplace_back();
    for (const SolverSpec& spec : specs) {
      runs.back().push_back(!spec.tao.empty()           ? run_tao(problems[p], spec, o, tao)
                            : is_iterative(spec.method) ? run_iterative(problems[p], spec, o)
                                                        : run_exact(problems[p], spec));
      const Measurement& m = runs.back().back();
      if (!o.quiet)
        std::fprintf(stderr,
                     "profile: problem %zu of %zu, %s (%ld rows): %s: %s, %ld iterations, %.3g s, "
                     "relative residual %.3g\n",
                     p + 1,
                     problems.size(),
                     entries[p].name.c_str(),
                     static_cast<long>(problems[p].stored.rows()),
                     spec.text.c_str(),
                     m.status.c_str(),
                     m.iterations,
                     m.time_s,
                     m.residual);
    }
  }

  std::vector<Profile> profiles;  // per tolerance: time, then sweeps
  for (std::size_t t = 0; t < kTolerancesCount; ++t)
    for (const bool sweeps : {false, true})
      profiles.push_back(make_profile(kTolerances[t], t, sweeps, specs, runs));
  const double wall_time_s = seconds_since(started);

  nlohmann::json j;
  j["format"] = "cbps-profile/1";
  j["library"] = o.library;
  j["quick"] = o.quick;
  j["tolerances"] = nlohmann::json::array();
  for (const double t : kTolerances) j["tolerances"].push_back(t);
  j["budget_iterations"] = o.budget_iterations;
  j["time_limit_s"] = o.time_limit;
  j["wall_time_s"] = wall_time_s;
  j["problems"] = nlohmann::json::array();
  for (std::size_t p = 0; p < entries.size(); ++p) {
    nlohmann::json e = entries[p].index;
    e["scale"] = problems[p].scale;
    j["problems"].push_back(e);
  }
  j["solvers"] = nlohmann::json::array();
  for (const SolverSpec& spec : specs)
    j["solvers"].push_back(
        {{"solver", spec.text},
         {"method", spec.tao.empty() ? std::string(to_string(spec.method)) : "tao"},
         {"exact", !is_iterative(spec.method) && spec.tao.empty()}});
  j["measurements"] = nlohmann::json::array();
  std::ostringstream csv;
  csv << "problem,solver,rows,status,iterations,time_s,residual_relative,lambda_error";
  for (const double t : kTolerances)
    csv << ",sweeps_to_" << tolerance_key(t) << ",time_to_" << tolerance_key(t);
  csv << '\n';
  for (std::size_t p = 0; p < entries.size(); ++p) {
    for (std::size_t s = 0; s < specs.size(); ++s) {
      const Measurement& m = runs[p][s];
      const bool exact = !is_iterative(specs[s].method) && specs[s].tao.empty();
      nlohmann::json mj;
      mj["problem"] = entries[p].name;
      mj["solver"] = specs[s].text;
      mj["status"] = m.status;
      mj["iterations"] = m.iterations;
      mj["time_s"] = m.time_s;
      mj["residual_relative"] = json_or_null(m.residual);
      mj["lambda_error"] = json_or_null(m.lambda_error);
      mj["reached"] = nlohmann::json::object();
      csv << entries[p].name << ',' << specs[s].text << ',' << problems[p].stored.rows() << ','
          << m.status << ',' << m.iterations << ',' << csv_number(m.time_s) << ','
          << csv_number(m.residual) << ',' << csv_number(m.lambda_error);
      for (std::size_t t = 0; t < kTolerancesCount; ++t) {
        const Reached& at = m.reached[t];
        const bool reached = at.iterations >= 0;
        mj["reached"][tolerance_key(kTolerances[t])] =
            !reached
                ? nlohmann::json(nullptr)
                : nlohmann::json({{"iterations",
                                   exact ? nlohmann::json(nullptr) : nlohmann::json(at.iterations)},
                                  {"time_s", at.time_s}});
        csv << ',' << (reached && !exact ? std::to_string(at.iterations) : "") << ','
            << (reached ? csv_number(at.time_s) : "");
      }
      csv << '\n';
      j["measurements"].push_back(mj);
    }
  }
  j["profiles"] = nlohmann::json::array();
  for (const Profile& profile : profiles) j["profiles"].push_back(profile_json(profile, specs));
  const std::string summary = summary_text(entries, specs, profiles, o, wall_time_s);

  if (dir) {
    write_text(dir->file("profile.json"), j.dump(2) + "\n");
    write_text(dir->file("profile.csv"), csv.str());
    write_text(dir->file("summary.txt"), summary);
    if (o.plot && !run_python_script("scripts/plot_profile.py",
                                     {dir->file("profile.json"), dir->file("profile")}))
      throw ComputationError("profile: the plot script failed (" + std::string(CBPS_PLOT_PYTHON) +
                             " scripts/plot_profile.py); nothing written (--no-plot skips the "
                             "plot)");
    dir->commit();
  }
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("%s", summary.c_str());
  if (!o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
  return 0;
}

}  // namespace

void register_profile(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "profile",
      "performance profiles (Dolan & More 2002) of solvers over a problem library: "
      "profile.json, profile.csv, summary.txt, profile.png/.svg");
  auto o = std::make_shared<ProfileOptions>();
  cmd->add_option("LIBRARY",
                  o->library,
                  "a problem library: the folder scripts/make_problem_library.py wrote (or its "
                  "library.json)")
      ->required();
  cmd->add_option(
      "--solvers",
      o->solvers,
      "comma-separated solver specs (the solvers listed below; tao:TYPE only in a build with "
      "PETSc), each solver once: a spec listed twice, or two specs for the same method and "
      "settings (pgs and psor:1; warm factors do not count, every solve starts from lambda = 0), "
      "is refused (default: " +
          o->solvers + ")");
  cmd->footer(solver_spec_help() + tao_spec_help());
  cmd->add_flag("--quick", o->quick, "only the problems the library marks quick");
  cmd->add_option(
         "--budget-iterations",
         o->budget_iterations,
         "max sweeps per problem and solver; TAO's iterations for tao:TYPE (default 100000)")
      ->check(positive());
  cmd->add_option("--time-limit", o->time_limit, "max time per problem and solver, s (default 1)")
      ->check(positive());
  cmd->add_option(
      "--out", o->out, "write profile.json, profile.csv, summary.txt and the plot here");
  cmd->add_flag("--json", o->json, "print profile.json on stdout instead of the table");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->add_flag_callback(
      "--no-plot", [o] { o->plot = false; }, "write no profile.png/.svg");
  cmd->callback([&run, o] { run = [o] { return profile_command(*o); }; });
}

}  // namespace cbps::cli
