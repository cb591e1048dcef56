// cbps converge: one system, every solver from the same guess, error against sweeps and time.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.hpp"

using cbps::test::run_cli;
using cbps::test::scratch_dir;
using cbps::test::slurp;

namespace {

/// convergence.csv as solver → rows of (iteration, time_s, residual, lambda_error,
/// velocity_error, objective); empty cells as NaN.
std::map<std::string, std::vector<std::vector<double>>> read_csv(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  REQUIRE(line == "solver,iteration,time_s,residual,lambda_error,velocity_error,objective");
  std::map<std::string, std::vector<std::vector<double>>> rows;
  while (std::getline(in, line)) {
    std::istringstream cells(line);
    std::string solver, cell;
    std::getline(cells, solver, ',');
    std::vector<double> values;
    while (std::getline(cells, cell, ',')) values.push_back(cell.empty() ? NAN : std::stod(cell));
    if (line.back() == ',') values.push_back(NAN);
    REQUIRE(values.size() == 6);
    rows[solver].push_back(values);
  }
  return rows;
}

}  // namespace

TEST_CASE("cbps converge records every sweep of every solver against the direct answer",
          "[cli][converge]") {
  const auto dir = scratch_dir("converge");
  const std::string out = (dir / "c").string();
  const auto r =
      run_cli("converge chain --param n=30 --param mass_ratio=10 --step 20 --quiet --out " + out +
              " --solvers pgs,psor:1.4,sgs,jacobi:0.6,pgs:order=reverse,matrix-free,direct");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto rows = read_csv(slurp(dir / "c" / "convergence.csv"));
  REQUIRE(rows.size() == 7);
  for (const auto& [solver, samples] : rows) {
    CAPTURE(solver);
    if (solver == "direct") {
      REQUIRE(samples.size() == 1);
      CHECK(samples[0][2] < 1e-10);  // residual
      continue;
    }
    CHECK(samples.front()[0] == 0.0);  // the guess
    CHECK(samples.front()[1] == 0.0);
    std::size_t misnumbered = 0, time_backwards = 0, objective_rises = 0;
    for (std::size_t k = 1; k < samples.size(); ++k) {
      if (samples[k][0] != double(k)) ++misnumbered;            // one row per sweep
      if (samples[k][1] < samples[k - 1][1]) ++time_backwards;  // time accumulates
      // The objective ½ λᵀAλ − bᵀλ never rises under Gauss-Seidel (7.1.1 minimises it row by
      // row; the chain has no bounds).
      if (samples[k][5] > samples[k - 1][5] + 1e-9 * std::abs(samples[k - 1][5])) ++objective_rises;
    }
    CHECK(misnumbered == 0);
    CHECK(time_backwards == 0);
    if (solver == "pgs" || solver == "sgs") CHECK(objective_rises == 0);
    // Stopped at the tolerance (1e-10 N), lambda unique (a chain: A definite) and close.
    CHECK(samples.back()[2] <= 1e-10);
    CHECK(samples.back()[3] < 1e-7);
    CHECK(samples.back()[4] < 1e-7);
  }
  // The matrix-free form takes explicit PGS's iterates: the same residual, sweep by sweep.
  const auto& pgs = rows.at("pgs");
  const auto& free = rows.at("matrix-free");
  REQUIRE(free.size() >= 200);
  double worst = 0.0;
  for (std::size_t k = 0; k < 200; ++k)
    worst = std::max(worst, std::abs(free[k][2] - pgs[k][2]) / std::max(1e-12, pgs[k][2]));
  CHECK(worst < 1e-9);
  const auto summary = nlohmann::json::parse(slurp(dir / "c" / "summary.json"));
  CHECK(summary["lambda_unique"] == true);
  CHECK(summary["rows"] == 30);
  CHECK(std::filesystem::file_size(dir / "c" / "convergence.png") > 10000);
  CHECK(std::filesystem::file_size(dir / "c" / "convergence.svg") > 10000);
}

TEST_CASE("cbps converge on a stored problem and on a singular contact system", "[cli][converge]") {
  const auto dir = scratch_dir("converge_problem");
  REQUIRE(run_cli("matrices stack --param n=3 --step 3 --out " + (dir / "m").string()).code == 0);
  const auto r = run_cli("converge " + (dir / "m").string() +
                         " --solvers pgs,block-pgs,matrix-free,direct --iterations 300 --quiet "
                         "--no-plot --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto summary = nlohmann::json::parse(r.out);
  CHECK(summary["lambda_unique"] == false);  // four contacts per face: A singular
  for (const auto& s : summary["solvers"]) {
    CAPTURE(s.dump());
    CHECK(s["lambda_error"].is_null());      // not unique: not compared
    CHECK(s["velocity_error"].is_number());  // v2 is (12.3.1)
  }
}

TEST_CASE("cbps converge refuses bad solver lists and writes nothing", "[cli][converge]") {
  const auto dir = scratch_dir("converge_bad");
  const std::string out = (dir / "c").string();
  struct Bad {
    std::string args, expect;
  };
  const Bad bad = GENERATE(values<Bad>({
      {"chain --solvers pgs,cg", "--solvers 'cg': unknown solver"},
      {"chain --solvers psor:2.5", "must be a number in (0, 2)"},
      {"chain --solvers pgs,,direct", "an empty entry"},
      {"stack --param friction=coulomb", "Coulomb friction"},
  }));
  CAPTURE(bad.args);
  const auto r = run_cli("converge " + bad.args + " --quiet --out " + out);
  CHECK(r.code == 2);
  CHECK(r.err.find(bad.expect) != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(out));
}
