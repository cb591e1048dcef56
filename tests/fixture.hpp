// What several test files share: running the cbps executable (exit code and captured output),
// scratch folders, built-in scenes and their systems after a few steps, boxed problems whose
// solution is known by construction, and the Siconos data folder.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cbps/scene/builtin.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/cone_problem.hpp"
#include "cbps/system/system.hpp"

namespace cbps::test {

// ---------------------------------------------------------------------------------------------
// The command line.

struct CliResult {
  int code = -1;    ///< exit code, -1 if the process did not exit normally
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// The scratch folders this process made; removed when it exits (ctest runs every test case in a
/// process of its own), kept where CBPS_KEEP_TEST_FILES is set, to look at after a failure.
class ScratchFolders {
 public:
  ScratchFolders() = default;
  ScratchFolders(const ScratchFolders&) = delete;
  ScratchFolders& operator=(const ScratchFolders&) = delete;
  ~ScratchFolders() {
    if (std::getenv("CBPS_KEEP_TEST_FILES") != nullptr) return;
    for (const std::filesystem::path& p : made_) {
      std::error_code ec;  // a folder already gone is not an error here
      std::filesystem::remove_all(p, ec);
    }
  }
  void add(const std::filesystem::path& p) {
    if (std::find(made_.begin(), made_.end(), p) == made_.end()) made_.push_back(p);
  }

 private:
  std::vector<std::filesystem::path> made_;
};

inline ScratchFolders& scratch_folders() {
  static ScratchFolders folders;
  return folders;
}

/// An empty folder under the temporary directory, unique to this process and removed when it
/// exits.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                  ("cbps_test_" + name + "_" + std::to_string(::getpid()));
  scratch_folders().add(p);
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

/// Runs `cbps ARGS` (the executable under test, CBPS_EXECUTABLE) with stdout and stderr captured,
/// from the folder `cwd` when one is given.
inline CliResult run_cli(const std::string& args, const std::filesystem::path& cwd = {}) {
  static const std::filesystem::path dir = scratch_dir("io");
  const std::filesystem::path out = dir / "stdout";
  const std::filesystem::path err = dir / "stderr";
  const std::string cd = cwd.empty() ? std::string() : "cd '" + cwd.string() + "' && ";
  const std::string cmd =
      cd + std::string(CBPS_EXECUTABLE) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

// ---------------------------------------------------------------------------------------------
// Built-in scenes.

inline constexpr double kG = 9.81;  // |g| of every built-in scene, m/s²

/// A built-in contact scene with NAME=VALUE overrides and the given solver.
inline Scene contact_scene(const std::string& name,
                           const std::map<std::string, std::string>& values,
                           const std::string& method = "pgs") {
  Scene scene = make_builtin_scene(name, values);
  scene.solver.method = method_of(method);
  return scene;
}

/// Every contact of a step's system in a cone: its normal row and the two friction rows after
/// it, with coefficient mu (the cone tests' problems from the built-in scenes).
inline FrictionContacts cones_of(const System& sys, double mu, FrictionLaw law) {
  FrictionContacts cones;
  cones.law = law;
  for (long k = 0; k + 2 < static_cast<long>(sys.kind.size()); ++k) {
    const auto at = [&](long i) { return sys.kind[static_cast<std::size_t>(i)]; };
    if (at(k) == RowKind::Contact && at(k + 1) == RowKind::Friction &&
        at(k + 2) == RowKind::Friction)
      cones.normal.push_back(static_cast<int>(k));
  }
  cones.mu = VecX::Constant(cones.contacts(), mu);
  return cones;
}

/// A scene file's JSON: a 1 kg, 0.2 m cube resting on a plane under gravity (9.81 m/s²) tilted
/// by `degrees` (a plane inclined by that angle), friction mu = 0.5 of the model `friction`
/// ("paper", "coulomb", "cone"), dt 1/240 s, contacts kept within 1 mm.
inline nlohmann::json incline_scene_json(double degrees, const std::string& friction) {
  const double g = 9.81, a = degrees * kPi / 180.0;
  return {{"name", "incline"},
          {"world",
           {{"gravity", {g * std::sin(a), -g * std::cos(a), 0.0}},
            {"dt", "1/240"},
            {"mu", 0.5},
            {"friction", friction},
            {"contact_margin", 0.001}}},
          {"bodies",
           {{{"name", "ground"}, {"shape", {{"type", "plane"}}}, {"static", true}},
            {{"name", "box"},
             {"shape", {{"type", "box"}, {"half_extents", {0.1, 0.1, 0.1}}}},
             {"mass", 1.0},
             {"position", {0.0, 0.1, 0.0}}}}}};
}

/// The system of a built-in scene after `steps` steps (contacts formed, chains loaded).
inline System system_of(const std::string& name,
                        const std::map<std::string, std::string>& values,
                        int steps) {
  Simulation sim(make_builtin_scene(name, values));
  for (int s = 0; s < steps; ++s) sim.step();
  return sim.build_system();
}

// ---------------------------------------------------------------------------------------------
// Boxed problems (6.2) with known answers.

/// A random SPD matrix B Bᵀ + n I, dense entries, fixed seed.
inline SpMat random_spd(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  MatX B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = n01(rng);
  const MatX A = B * B.transpose() + n * MatX::Identity(n, n);
  return A.sparseView();
}

/// A boxed problem with a solution chosen first: lambda_star, and w_star = A lambda_star − b with
/// the sign each row's place demands (6.2).
struct Constructed {
  SpMat A;
  MatX J;  ///< A = J Jᵀ: rows of J are the constraints, columns the degrees of freedom
  VecX b, lo, hi, lambda_star, w_star;
};

/// k rows over d degrees of freedom, A = J Jᵀ: positive definite if d ≥ k (almost surely),
/// semidefinite with rank d if d < k, as a box on four contacts (12 rows, 6 DOF). Rows are a
/// mix of the paper's kinds: bilateral (free), contact [0, ∞) at rest or pushing, friction
/// [−c, c] sticking or sliding, fixed (cmin = cmax).
inline Constructed construct(int k, int d, std::mt19937& rng) {
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Constructed p;
  p.J = MatX(k, d);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < d; ++j) p.J(i, j) = u(rng) < 0.5 ? n01(rng) : 0.0;
  for (int i = 0; i < k; ++i) p.J(i, i % d) += 1.0;  // no empty row
  const MatX A = p.J * p.J.transpose();
  p.A = A.sparseView();
  p.lo.resize(k);
  p.hi.resize(k);
  p.lambda_star.resize(k);
  p.w_star = VecX::Zero(k);
  for (int i = 0; i < k; ++i) {
    const double c = 0.5 + u(rng);
    switch (static_cast<int>(6 * u(rng))) {
      case 0:  // bilateral row (distance): free, w = 0
        p.lo(i) = -kInf;
        p.hi(i) = kInf;
        p.lambda_star(i) = 2 * u(rng) - 1;
        break;
      case 1:  // contact, separating: lambda = 0, w > 0
        p.lo(i) = 0;
        p.hi(i) = kInf;
        p.lambda_star(i) = 0;
        p.w_star(i) = 0.1 + u(rng);
        break;
      case 2:  // contact, pushing: lambda > 0, w = 0
        p.lo(i) = 0;
        p.hi(i) = kInf;
        p.lambda_star(i) = 0.1 + u(rng);
        break;
      case 3:  // friction at its bound, sliding
        p.lo(i) = -c;
        p.hi(i) = c;
        p.lambda_star(i) = u(rng) < 0.5 ? -c : c;
        p.w_star(i) = p.lambda_star(i) < 0 ? 0.1 + u(rng) : -0.1 - u(rng);
        break;
      case 4:  // fixed row: lambda = cmin = cmax, w anything
        p.lo(i) = p.hi(i) = c;
        p.lambda_star(i) = c;
        p.w_star(i) = 2 * u(rng) - 1;
        break;
      default:  // friction sticking: strictly inside
        p.lo(i) = -c;
        p.hi(i) = c;
        p.lambda_star(i) = c * (1.6 * u(rng) - 0.8);
    }
  }
  // A semidefinite: a nonzero w on a free row must be orthogonal to nothing, but b = A λ* − w*
  // is any vector, so every constructed problem has λ* as a solution.
  p.b = A * p.lambda_star - p.w_star;
  return p;
}

/// max(1, ‖b‖∞, max |A_ij|), the scale residuals are measured against (lcp.hpp).
inline double scale_of(const SpMat& A, const VecX& b) { return lcp_scale(MatX(A), -b); }

/// The constructed problem solved by an exact path (direct or active-set) from lambda = 0.
inline VecX solve_exact(const Constructed& p,
                        SolverSummary* summary = nullptr,
                        Method method = Method::Direct) {
  VecX lambda = VecX::Zero(p.b.size());
  SolverOptions options;
  options.method = method;
  options.tolerance = 0.0;  // to the rounding floor
  const SolverSummary s = solve(BoxedProblem{p.A, p.b, p.lo, p.hi}, lambda, options);
  if (summary != nullptr) *summary = s;
  return lambda;
}

// ---------------------------------------------------------------------------------------------
// Siconos problems.

/// Where the external data lives (tests/data/README.md).
inline const std::filesystem::path kSiconosDir = std::filesystem::path(CBPS_DATA_DIR) / "siconos";
/// Siconos' frictional-contact dumps (tests/data/siconos-fc3d).
inline const std::filesystem::path kFc3dDir = std::filesystem::path(CBPS_DATA_DIR) / "siconos-fc3d";

inline std::vector<std::filesystem::path> dat_files(const std::filesystem::path& dir) {
  INFO("the Siconos data folder is missing: " << dir.string());
  REQUIRE(std::filesystem::is_directory(dir));
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".dat") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace cbps::test
