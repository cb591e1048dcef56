#include "cbps/studies/profile.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "cbps/base/error.hpp"
#include "cbps/io/json_numbers.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/solvers/peers/peers.hpp"

namespace cbps {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kLibraryFormat = "cbps-problem-library/1";

std::string text_field(const nlohmann::json& j,
                       const char* key,
                       const std::string& file,
                       const std::string& where) {
  if (!j.contains(key) || !j[key].is_string())
    throw InputError(file + ": " + where + "/" + key + ": missing or not a string");
  return j[key].get<std::string>();
}

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Why a spec cannot run on a problem (empty: it can): what `cbps converge` refuses.
std::string not_applicable(const SolverSpec& spec, const ProfileProblem& p) {
  if (needs_symmetric(spec.method, !p.stored.cones.empty()) && !p.symmetric)
    return "not applicable: A is not symmetric (the method minimises the QP of 6.2)";
  if (needs_jacobian(spec.method) && !p.stored.has_jacobian())
    return "not applicable: no J and Minv (a Siconos file)";
  if (spec.contacts_first && p.stored.kinds.empty())
    return "not applicable: no row kinds (contacts_first needs labels.json)";
  if (!p.stored.cones.empty() && !takes_cone_law(spec.method, p.stored.cones.law))
    return std::string("not applicable: contacts in friction cones under ") +
           std::string(cone_law_name(p.stored.cones.law)) + " (" + kConeMethodNames +
           " solve them)";
  if (const long most = most_rows(spec.method); most > 0 && p.stored.rows() > most)
    return "not applicable: more than " + std::to_string(most) + " rows (a dense copy of A)";
  if (is_peer(spec.method)) {
    const std::string refusal = peer_refusal(spec.method, p.problem());
    if (!refusal.empty()) return "not applicable: " + refusal;
  }
  return "";
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

/// The problems of a folder without library.json: its FCLIB files (.hdf5, .h5), Siconos .dat
/// files and `cbps matrices` folders (a subfolder with A.mtx), in name order; no lambda* known.
std::vector<ProfileEntry> folder_entries(const fs::path& folder, bool quick) {
  if (quick)
    throw InputError(folder.string() +
                     ": --quick: a folder of problem files has no library.json to mark problems "
                     "quick");
  std::vector<fs::path> paths;
  std::error_code listing;
  for (const fs::directory_entry& d : fs::directory_iterator(folder, listing)) {
    const fs::path& f = d.path();
    const std::string extension = f.extension().string();
    std::error_code ec;  // an entry that cannot be read is not listed
    if (d.is_directory(ec) ? fs::is_regular_file(f / "A.mtx", ec)
                           : extension == ".dat" || extension == ".hdf5" || extension == ".h5")
      paths.push_back(f);
  }
  if (listing) throw InputError(folder.string() + ": cannot list the folder: " + listing.message());
  std::sort(paths.begin(), paths.end());
  std::vector<ProfileEntry> entries;
  for (const fs::path& f : paths) {
    ProfileEntry e;
    e.name = f.filename().string();
    e.path = fs::absolute(f).string();
    e.index = {{"name", e.name}, {"path", e.name}, {"exact", nullptr}};
    entries.push_back(std::move(e));
  }
  if (entries.empty())
    throw InputError(folder.string() +
                     ": no library.json and no problem in it (.dat, .hdf5, .h5 files, folders "
                     "with A.mtx)");
  return entries;
}

}  // namespace

/// The index of LIBRARY (a folder holding library.json, or that file; a folder without one: its
/// problem files, folder_entries): its problems, only the quick ones with `quick`. InputError
/// naming the file for anything missing or malformed.
std::vector<ProfileEntry> read_library(const std::string& library, bool quick) {
  std::error_code ec;
  const bool is_folder = fs::is_directory(library, ec);
  if (is_folder && !fs::exists(fs::path(library) / "library.json", ec))
    return folder_entries(library, quick);
  const fs::path file = is_folder ? fs::path(library) / "library.json" : fs::path(library);
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
  std::vector<ProfileEntry> entries;
  for (std::size_t k = 0; k < j["problems"].size(); ++k) {
    const nlohmann::json& p = j["problems"][k];
    const std::string where = "/problems/" + std::to_string(k);
    if (!p.is_object()) throw InputError(file.string() + ": " + where + ": not an object");
    if (quick && !p.value("quick", false)) continue;
    ProfileEntry e;
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

ProfileProblem load_profile_problem(const ProfileEntry& e) {
  ProfileProblem p;
  p.stored = read_problem(e.path);
  p.scale = scale_of(p.problem(), p.stored.cfm);
  p.symmetric = max_asymmetry(p.stored.A) <= symmetry_tolerance(p.stored.A);
  if (e.exact.empty()) return p;  // a folder of problem files: lambda* not known
  p.exact = read_matrix_market_vector(e.exact);
  if (p.exact.size() != p.stored.rows())
    throw InputError(e.exact + ": " + std::to_string(p.exact.size()) + " values for a problem of " +
                     std::to_string(p.stored.rows()) + " rows (" + e.path + ")");
  p.definite = e.index.value("definite", false);
  return p;
}

void finish_measurement(ProfileMeasurement& m, const ProfileProblem& p, const VecX& lambda) {
  m.residual = p.relative(lambda);
  if (p.definite && lambda.size() == p.exact.size())
    m.lambda_error = (lambda - p.exact).lpNorm<Eigen::Infinity>();
}

ProfileMeasurement best_of_runs(const std::function<ProfileMeasurement()>& run) {
  ProfileMeasurement best = run();
  double spent = best.time_s;  // s, the runs' own times so far
  for (int k = 1;
       best.time_s < kRepeatBelow && (k < kRepeats || (k < kMostRepeats && spent < kRepeatSpan));
       ++k) {
    const ProfileMeasurement again = run();
    spent += again.time_s;
    best.time_s = std::min(best.time_s, again.time_s);
    best.convert_time_s = std::min(best.convert_time_s, again.convert_time_s);
    for (std::size_t i = 0; i < kProfileTolerancesCount; ++i)
      if (best.reached[i].iterations >= 0 &&
          again.reached[i].iterations == best.reached[i].iterations)
        best.reached[i].time_s = std::min(best.reached[i].time_s, again.reached[i].time_s);
  }
  return best;
}

ProfileMeasurement profile_iterative(const ProfileProblem& p,
                                     const SolverSpec& spec,
                                     const ProfileLimits& o) {
  ProfileMeasurement m;
  m.status = not_applicable(spec, p);
  if (!m.status.empty()) return m;
  VecX lambda = VecX::Zero(p.stored.rows());
  m.reach(0, 0.0, p.relative(lambda));
  SolverOptions options = study_options(spec, o.budget_iterations, p.stored.cfm);
  const auto start = Clock::now();
  double measuring = 0.0;  // s spent in after_sweep so far, taken off the times
  options.after_sweep = [&](int k, const VecX& l, double) {
    const auto entered = Clock::now();
    const double time_s = std::chrono::duration<double>(entered - start).count() - measuring;
    const double relative = p.relative(l);
    m.reach(k, time_s, relative);
    m.iterations = k;
    m.time_s = time_s;
    if (!std::isfinite(relative)) m.status = "non-finite";
    if (m.reached[kProfileTolerancesCount - 1].iterations >= 0) m.status = "solved";
    if (m.status.empty() && time_s >= o.time_limit) m.status = "time limit";
    measuring += seconds_since(entered);
    return m.status.empty();
  };
  const SolverSummary summary = solve(p.problem(), lambda, options);
  if (m.status.empty())
    m.status = summary.termination == Termination::MaxIterations ? "iteration budget"
                                                                 : to_string(summary.termination);
  finish_measurement(m, p, lambda);
  return m;
}

ProfileMeasurement profile_exact(const ProfileProblem& p,
                                 const SolverSpec& spec,
                                 const ProfileLimits& o) {
  ProfileMeasurement m;
  m.status = not_applicable(spec, p);
  if (!m.status.empty()) return m;
  VecX lambda = VecX::Zero(p.stored.rows());
  SolverOptions options = study_options(spec, 1, p.stored.cfm);
  options.time_limit = o.time_limit;
  // Told the finest tolerance, as `cbps lcp` tells it its default: the direct path reads it in N
  // and as a unit-free residual (system/unit_free.hpp), what the profile measures, and on a
  // Siconos or FCLIB file, in its simulator's units, as a unit-free residual alone.
  options.tolerance = kProfileTolerances[kProfileTolerancesCount - 1];
  options.tolerance_unit_free = !p.stored.folder;
  const auto start = Clock::now();
  const SolverSummary summary = solve(p.problem(), lambda, options);
  m.time_s = seconds_since(start);
  m.iterations = summary.iterations;
  finish_measurement(m, p, lambda);
  for (std::size_t i = 0; i < kProfileTolerancesCount; ++i)
    if (m.residual <= kProfileTolerances[i]) m.reached[i] = {1, m.time_s};
  m.status = m.reached[kProfileTolerancesCount - 1].iterations >= 0
                 ? "solved"
                 : to_string(summary.termination);
  return m;
}

ProfileMeasurement profile_peer(const ProfileProblem& p,
                                const SolverSpec& spec,
                                const ProfileLimits& o) {
  ProfileMeasurement m;
  m.status = not_applicable(spec, p);
  if (!m.status.empty()) return m;
  m.final_point_only = true;
  // A peer reports only its final point. A pivoting peer runs once: its one cost counts at every
  // tolerance its answer meets. An iterative one runs once per tolerance, told that tolerance,
  // from the loosest: what it spends at the finest is not its cost at a looser one.
  const bool iterative = is_iterative(spec.method);
  const std::size_t first = iterative ? 0 : kProfileTolerancesCount - 1;
  SolverSummary summary;
  VecX lambda;
  for (std::size_t t = first; t < kProfileTolerancesCount; ++t) {
    lambda = VecX::Zero(p.stored.rows());
    SolverOptions options = study_options(spec, o.budget_iterations, p.stored.cfm);
    options.tolerance = kProfileTolerances[t];  // the peer's own measure, relative (peers.md)
    options.time_limit = o.time_limit;          // a peer's child is killed at it
    summary = solve(p.problem(), lambda, options);
    const double time_s = summary.convert_time_s + summary.peer_solve_time_s;
    const double relative = p.relative(lambda);
    const long at = iterative ? std::max(1, summary.iterations) : 1;
    for (std::size_t i = 0; i < kProfileTolerancesCount; ++i)
      if (relative <= kProfileTolerances[i] && m.reached[i].iterations < 0)
        m.reached[i] = {at, time_s};
    m.time_s = time_s;
    // Done once the finest tolerance is met (a peer that ignores the tolerance, bullet:pgs, may
    // meet it in its first run), or at the limit (a finer one would not finish): the summary,
    // lambda and status are then this run's.
    if (m.reached[kProfileTolerancesCount - 1].iterations >= 0 ||
        summary.termination == Termination::TimeLimit)
      break;
  }
  m.iterations = summary.iterations;
  m.peer_status = summary.peer_status;
  m.convert_time_s = summary.convert_time_s;
  finish_measurement(m, p, lambda);
  const bool solved = m.reached[kProfileTolerancesCount - 1].iterations >= 0;
  m.status = solved                                          ? "solved"
             : summary.termination == Termination::TimeLimit ? "time limit"
             : summary.peer_said_ok ? "peer said ok; unit-free residual " + number_text(m.residual)
                                    : "peer said failed: " + summary.peer_status;
  return m;
}

ProfileMeasurement profile_spec(const ProfileProblem& p,
                                const SolverSpec& spec,
                                const ProfileLimits& limits,
                                const ProfileTao& tao) {
  if (!spec.tao.empty()) {
    if (!tao) throw std::logic_error("profile_spec: " + spec.text + " given, but no TAO runner");
    return tao(p, spec, limits);
  }
  return is_peer(spec.method)        ? profile_peer(p, spec, limits)
         : is_iterative(spec.method) ? profile_iterative(p, spec, limits)
                                     : profile_exact(p, spec, limits);
}

Profile make_profile(double tolerance,
                     std::size_t t,
                     bool sweeps,
                     const std::vector<SolverSpec>& specs,
                     const std::vector<std::vector<ProfileMeasurement>>& runs) {
  Profile profile;
  profile.tolerance = tolerance;
  profile.measure = sweeps ? "sweeps" : "time";
  for (std::size_t s = 0; s < specs.size(); ++s)
    if (!sweeps || is_iterative(specs[s].method) || !specs[s].tao.empty())
      profile.solvers.push_back(s);
  CostTable cost;
  for (const std::vector<ProfileMeasurement>& problem_runs : runs) {
    std::vector<double> row;
    for (const std::size_t s : profile.solvers) {
      const ProfileReached& at = problem_runs[s].reached[t];
      row.push_back(at.iterations < 0 ? std::numeric_limits<double>::infinity()
                    : sweeps          ? static_cast<double>(at.iterations)
                                      : at.time_s);
    }
    // λ = 0 already meets the tolerance (a sweeping method checks it before its first sweep,
    // at cost 0): every solver started there, so each that reached it is at the best cost. Left
    // alone, the exact paths and the peers, whose one answer comes at the end of a solve, would
    // get r = ∞ (performance_ratios) on a problem they solved (Siconos' GFC3D_TwoRods1 at 1e-4).
    if (!row.empty() && *std::min_element(row.begin(), row.end()) == 0.0)
      for (double& c : row)
        if (std::isfinite(c)) c = 0.0;
    cost.push_back(std::move(row));
  }
  profile.ratios = performance_ratios(cost);
  return profile;
}

/// The summary table: per tolerance, per solver the problems solved and rho_s(tau) at 1, 2, 10
/// for time and sweeps.
std::string profile_summary_text(const std::vector<ProfileEntry>& entries,
                                 const std::vector<SolverSpec>& specs,
                                 const std::vector<Profile>& profiles,
                                 const ProfileLimits& o,
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
  out << "unit-free residual (docs/cones.md); rho(tau): fraction of "
         "problems within tau x the best solver's cost (Dolan & More 2002); exact paths have "
         "no sweeps\n";
  for (std::size_t t = 0; t < kProfileTolerancesCount; ++t) {
    const Profile& time = profiles[2 * t];
    const Profile& sweeps = profiles[2 * t + 1];
    std::snprintf(line,
                  sizeof line,
                  "\nrelative residual <= %g\n%-24s %7s   %-23s   %-23s\n",
                  kProfileTolerances[t],
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
                    performance_fraction(time.ratios, s, kProfileTaus[0]),
                    performance_fraction(time.ratios, s, kProfileTaus[1]),
                    performance_fraction(time.ratios, s, kProfileTaus[2]));
      out << line;
      const auto at = std::find(sweeps.solvers.begin(), sweeps.solvers.end(), s);
      if (at == sweeps.solvers.end()) {
        std::snprintf(line, sizeof line, "   %7s %7s %7s\n", "-", "-", "-");
      } else {
        const auto k = static_cast<std::size_t>(at - sweeps.solvers.begin());
        std::snprintf(line,
                      sizeof line,
                      "   %7.3f %7.3f %7.3f\n",
                      performance_fraction(sweeps.ratios, k, kProfileTaus[0]),
                      performance_fraction(sweeps.ratios, k, kProfileTaus[1]),
                      performance_fraction(sweeps.ratios, k, kProfileTaus[2]));
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
    for (const double x : r) row.push_back(number_json(x));  // a failure: "inf"
    j["ratios"].push_back(row);
  }
  j["rho"] = nlohmann::json::object();
  for (std::size_t k = 0; k < profile.solvers.size(); ++k) {
    nlohmann::json rho = nlohmann::json::object();
    for (const double tau : kProfileTaus)
      rho[tolerance_key(tau)] = performance_fraction(profile.ratios, k, tau);
    rho["inf"] = performance_fraction(profile.ratios, k, std::numeric_limits<double>::infinity());
    j["rho"][specs[profile.solvers[k]].text] = rho;
  }
  return j;
}

ProfileReport profile_report(const std::string& library,
                             bool quick,
                             const ProfileLimits& limits,
                             double wall_time_s,
                             const std::vector<ProfileEntry>& entries,
                             const std::vector<ProfileProblem>& problems,
                             const std::vector<SolverSpec>& specs,
                             const std::vector<std::vector<ProfileMeasurement>>& runs,
                             const std::vector<Profile>& profiles) {
  nlohmann::json j;
  j["format"] = "cbps-profile/1";
  j["library"] = library;
  j["quick"] = quick;
  j["tolerances"] = nlohmann::json::array();
  for (const double t : kProfileTolerances) j["tolerances"].push_back(t);
  j["budget_iterations"] = limits.budget_iterations;
  j["time_limit_s"] = limits.time_limit;
  j["wall_time_s"] = wall_time_s;
  j["problems"] = nlohmann::json::array();
  for (std::size_t p = 0; p < entries.size(); ++p) {
    nlohmann::json e = entries[p].index;
    e["scale"] = problems[p].scale;
    e["rows"] = problems[p].stored.rows();
    e["contacts"] = problems[p].stored.cones.contacts();
    e["symmetric"] = problems[p].symmetric;
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
  for (const double t : kProfileTolerances)
    csv << ",sweeps_to_" << tolerance_key(t) << ",time_to_" << tolerance_key(t);
  csv << '\n';
  for (std::size_t p = 0; p < entries.size(); ++p) {
    for (std::size_t s = 0; s < specs.size(); ++s) {
      const ProfileMeasurement& m = runs[p][s];
      const bool exact = !is_iterative(specs[s].method) && specs[s].tao.empty();
      nlohmann::json mj;
      mj["problem"] = entries[p].name;
      mj["solver"] = specs[s].text;
      mj["status"] = m.status;
      mj["final_point_only"] = m.final_point_only;
      mj["peer_status"] =
          m.peer_status.empty() ? nlohmann::json(nullptr) : nlohmann::json(m.peer_status);
      mj["convert_time_s"] =
          m.final_point_only ? nlohmann::json(m.convert_time_s) : nlohmann::json(nullptr);
      mj["iterations"] = m.iterations;
      mj["time_s"] = m.time_s;
      // null: not measured (the spec did not run; lambda* not unique where A is singular)
      const bool ran = m.status.rfind("not applicable", 0) != 0;
      mj["residual_relative"] = ran ? number_json(m.residual) : nlohmann::json(nullptr);
      mj["lambda_error"] =
          ran && problems[p].definite ? number_json(m.lambda_error) : nlohmann::json(nullptr);
      mj["reached"] = nlohmann::json::object();
      csv << entries[p].name << ',' << specs[s].text << ',' << problems[p].stored.rows() << ','
          << m.status << ',' << m.iterations << ',' << csv_number(m.time_s) << ','
          << csv_number(m.residual) << ',' << csv_number(m.lambda_error);
      for (std::size_t t = 0; t < kProfileTolerancesCount; ++t) {
        const ProfileReached& at = m.reached[t];
        const bool reached = at.iterations >= 0;
        mj["reached"][tolerance_key(kProfileTolerances[t])] =
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
  return {j, csv.str()};
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

}  // namespace cbps
