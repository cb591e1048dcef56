// cbps converge: one system, every solver from the same guess, error against sweeps and time.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "fixture.hpp"

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
              " --record-every 1 --solvers pgs,psor:1.4,sgs,jacobi:0.6,pgs:order=reverse," +
              "matrix-free,direct");
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

TEST_CASE("cbps converge --cfm studies A + eps E, as a folder with cfm.txt does",
          "[cli][converge][cfm]") {
  // The scene's step with --cfm and the same step written by `cbps matrices --cfm` (A = J Minv
  // J^T, eps in cfm.txt) are the same problem: the same summary, sweep for sweep.
  const auto dir = scratch_dir("converge_cfm");
  const std::string folder = (dir / "m").string();
  REQUIRE(run_cli("matrices chain --step 5 --cfm 1e-3 --out " + folder).code == 0);
  // warm=off: the folder has no previous lambda to start from.
  const std::string specs =
      " --solvers pgs:warm=off,direct --iterations 40 --quiet --no-plot --json";
  const auto scene = run_cli("converge chain --step 5 --cfm 1e-3" + specs);
  const auto stored = run_cli("converge " + folder + specs);
  INFO(scene.err << stored.err);
  REQUIRE(scene.code == 0);
  REQUIRE(stored.code == 0);
  const auto a = nlohmann::json::parse(scene.out);
  const auto b = nlohmann::json::parse(stored.out);
  CHECK(a["cfm"] == 1e-3);
  CHECK(b["cfm"] == 1e-3);
  for (std::size_t k = 0; k < 2; ++k) {
    CHECK(a["solvers"][k]["residual"] == b["solvers"][k]["residual"]);
    CHECK(a["solvers"][k]["iterations"] == b["solvers"][k]["iterations"]);
  }
  // The world options shape a scene's step; a stored problem has its own (cfm.txt).
  const auto refused = run_cli("converge " + folder + " --dt 0.01" + specs);
  CHECK(refused.code == 2);
  CHECK(refused.err.find("apply to scenes, not to the problem") != std::string::npos);
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
      // Issue 50, item 11: an empty list fell back to the default, a duplicate drew twice.
      {"chain --solvers ''", "--solvers '': an empty entry"},
      {"chain --solvers pgs,direct,pgs", "'pgs' is given twice"},
      {"stack --param friction=coulomb", "Coulomb friction"},
  }));
  CAPTURE(bad.args);
  const auto r = run_cli("converge " + bad.args + " --quiet --out " + out);
  CHECK(r.code == 2);
  CHECK(r.err.find(bad.expect) != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("cbps converge --record-every K writes every K-th sweep, the guess and the last",
          "[cli][converge]") {
  const auto dir = scratch_dir("converge_every");
  const std::string base =
      "converge chain --param n=30 --param mass_ratio=10 --step 20 --quiet --no-plot "
      "--solvers pgs,jacobi:0.6,direct --out ";
  const auto all = run_cli(base + (dir / "all").string() + " --record-every 1");
  const auto some = run_cli(base + (dir / "some").string() + " --record-every 7");
  const auto logged = run_cli(base + (dir / "log").string());  // the default: log
  INFO(all.err << some.err << logged.err);
  REQUIRE(all.code == 0);
  REQUIRE(some.code == 0);
  REQUIRE(logged.code == 0);
  const auto every = read_csv(slurp(dir / "all" / "convergence.csv"));
  const auto sparse = read_csv(slurp(dir / "some" / "convergence.csv"));
  const auto spaced = read_csv(slurp(dir / "log" / "convergence.csv"));
  for (const std::string solver : {"pgs", "jacobi:0.6"}) {
    CAPTURE(solver);
    const auto& e = every.at(solver);
    const auto& s = sparse.at(solver);
    const double last = e.back()[0];
    REQUIRE(last > 20);
    // Sweeps 0, 7, 14, … and the last one (if it is not a multiple of 7).
    const std::size_t expected =
        static_cast<std::size_t>(last) / 7 + 1 + (static_cast<long>(last) % 7 != 0 ? 1 : 0);
    CHECK(s.size() == expected);
    CHECK(s.size() < e.size());
    CHECK(s.front()[0] == 0.0);
    CHECK(s.back()[0] == last);
    for (std::size_t k = 0; k + 1 < s.size(); ++k) CHECK(s[k][0] == 7.0 * double(k));
    // The recorded sweeps have the values of the full record (same iterates; time apart).
    for (const auto& row : s) {
      const auto& full = e[static_cast<std::size_t>(row[0])];
      CHECK(full[0] == row[0]);
      CHECK(row[2] == Approx(full[2]).epsilon(1e-12));
      CHECK(row[3] == Approx(full[3]).epsilon(1e-12));
    }
    // The default keeps every sweep to 100, then 100 a decade: sweeps 103, 105, 108, ... (the
    // first of each step of 10^0.01), the last, and nothing else; the chain's pgs sweeps
    // thousands of times (issue 50, item 12: 36 MB of convergence.csv for the chain study).
    const auto& g = spaced.at(solver);
    std::vector<double> expected_sweeps;
    for (long k = 0; k <= static_cast<long>(last); ++k) {
      const bool kept = k <= 100 || std::floor(100.0 * std::log10(double(k))) !=
                                        std::floor(100.0 * std::log10(double(k - 1)));
      if (kept || k == static_cast<long>(last)) expected_sweeps.push_back(double(k));
    }
    REQUIRE(g.size() == expected_sweeps.size());
    for (std::size_t k = 0; k < g.size(); ++k) CHECK(g[k][0] == expected_sweeps[k]);
    if (last > 1000) CHECK(g.size() < e.size() / 4);
    for (const auto& row : g)
      CHECK(row[2] == Approx(e[static_cast<std::size_t>(row[0])][2]).epsilon(1e-12));
  }
  CHECK(nlohmann::json::parse(slurp(dir / "log" / "summary.json"))["record_every"] == "log");
  CHECK(run_cli(base + (dir / "bad2").string() + " --record-every often").code == 2);
  CHECK(sparse.at("direct").size() == 1);
  // The summary still finds the milestones sweep by sweep, as the full record does.
  const auto sa = nlohmann::json::parse(slurp(dir / "all" / "summary.json"));
  const auto ss = nlohmann::json::parse(slurp(dir / "some" / "summary.json"));
  CHECK(ss["record_every"] == 7);
  CHECK(sa["record_every"] == 1);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(ss["solvers"][i]["reached"]["1e-06"]["iterations"] ==
          sa["solvers"][i]["reached"]["1e-06"]["iterations"]);
    CHECK(ss["solvers"][i]["iterations"] == sa["solvers"][i]["iterations"]);
    CHECK(ss["solvers"][i]["samples"].get<std::size_t>() ==
          sparse.at(ss["solvers"][i]["solver"].get<std::string>()).size());
  }
  CHECK(run_cli(base + (dir / "bad").string() + " --record-every 0").code == 2);
  CHECK_FALSE(std::filesystem::exists(dir / "bad"));
}

TEST_CASE("cbps converge warns when the step is already solved by the initial guess",
          "[cli][converge]") {
  // Step 0 of a chain released from rest, straight along x under gravity along -y: v1 = 0 and
  // J Minv fext = 0 (the links pull along x, gravity acts along y), so b = 0 and lambda = 0
  // solves it before any sweep.
  const auto r =
      run_cli("converge chain --param n=5 --solvers pgs,jacobi --quiet --no-plot --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto summary = nlohmann::json::parse(r.out);
  CHECK(summary["solved_by_initial_guess"] == true);
  REQUIRE(summary["warnings"].size() == 1);
  CHECK(summary["warnings"][0].get<std::string>().find("already solved by the initial guess") !=
        std::string::npos);
  CHECK(r.err.find("cbps: warning: converge:") != std::string::npos);  // even with --quiet
  for (const auto& s : summary["solvers"]) {
    CHECK(s["reached"]["1e-10"]["iterations"] == 0);  // "converged" before any sweep
    CHECK(s["guess_residual"].get<double>() <= 1e-10);
  }
  // A later step is not: no warning.
  const auto later =
      run_cli("converge chain --param n=5 --step 10 --solvers pgs --quiet --no-plot --json");
  REQUIRE(later.code == 0);
  const auto s10 = nlohmann::json::parse(later.out);
  CHECK(s10["solved_by_initial_guess"] == false);
  CHECK(s10["warnings"].empty());
  CHECK(later.err.find("warning") == std::string::npos);
}

TEST_CASE("cbps converge hands a spec's method keys to the method", "[cli][converge]") {
  // apgd:restart=off and pgs-sm:sweeps=1 are other methods than apgd and pgs-sm: they must not
  // take the same sweeps (before the keys were passed on, both pairs ran the defaults alike).
  const auto r = run_cli(
      "converge chain --param n=10 --param mass_ratio=100 --step 20 --quiet --no-plot --json "
      "--solvers apgd,apgd:restart=off,pgs-sm,pgs-sm:sweeps=1");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto summary = nlohmann::json::parse(r.out);
  std::map<std::string, int> sweeps;
  for (const auto& s : summary["solvers"])
    sweeps[s["solver"].get<std::string>()] = s["iterations"].get<int>();
  CAPTURE(sweeps["apgd"], sweeps["apgd:restart=off"], sweeps["pgs-sm"], sweeps["pgs-sm:sweeps=1"]);
  CHECK(sweeps["apgd"] != sweeps["apgd:restart=off"]);
  CHECK(sweeps["pgs-sm"] != sweeps["pgs-sm:sweeps=1"]);
}

TEST_CASE("cbps converge scales the previous step's lambda by each spec's warm factor once",
          "[cli][converge]") {
  // A double pendulum released from rest along x under gravity along -y: step 0 has b = 0 and
  // lambda = 0, so step 1 starts from 0 whatever the warm factor and both scenes below reach
  // step 2 in the same state with the same previous lambda. A spec's warm=F starts each row from
  // F times that lambda, as `cbps run --solver SPEC` does, whatever the scene's own factor (it
  // was scaled by both: F times the scene's 0.5).
  const auto dir = scratch_dir("converge_warm");
  const auto scene = [&](const std::string& warm) {
    const auto path = dir / ("warm" + warm + ".json");
    cbps::test::write_file(
        path,
        R"({"name": "two-link", "world": {"gravity": [0, -9.81, 0], "dt": "1/240"},
            "solver": {"method": "pgs", "warm": )" +
            warm + R"(},
            "bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 0.05}, "mass": 1,
                        "position": [0.5, 0, 0]},
                       {"name": "b", "shape": {"type": "sphere", "radius": 0.05}, "mass": 1,
                        "position": [1, 0, 0]}],
            "constraints": [{"type": "distance", "a": "world", "b": "a", "anchor_a": [0, 0, 0],
                             "length": 0.5},
                            {"type": "distance", "a": "a", "b": "b", "length": 0.5}]})");
    return path.string();
  };
  std::map<std::string, std::map<std::string, double>> guess;  // scene → spec → residual
  for (const std::string warm : {"1", "0.5"}) {
    const auto r = run_cli("converge " + scene(warm) +
                           " --step 2 --solvers pgs,pgs:warm=0.5 --quiet --no-plot --json");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto summary = nlohmann::json::parse(r.out);
    for (const auto& s : summary.at("solvers"))
      guess[warm][s.at("solver").get<std::string>()] = s.at("guess_residual").get<double>();
  }
  CAPTURE(guess["1"]["pgs"], guess["1"]["pgs:warm=0.5"], guess["0.5"]["pgs"]);
  CHECK(guess["1"]["pgs"] != guess["1"]["pgs:warm=0.5"]);  // the factor matters at this step
  CHECK(guess["0.5"]["pgs"] == guess["1"]["pgs"]);
  CHECK(guess["0.5"]["pgs:warm=0.5"] == guess["1"]["pgs:warm=0.5"]);
}

TEST_CASE("plot_convergence.py draws a CSV with a diverging solver", "[cli][converge][plot]") {
  const auto dir = scratch_dir("converge_plot");
  // pgs converges, jacobi diverges to 1e300 and then inf, direct is one point.
  std::string csv = "solver,iteration,time_s,residual,lambda_error,velocity_error,objective\n";
  const auto num = [](double x) {
    std::ostringstream out;
    out.precision(17);
    out << x;
    return out.str();
  };
  for (int k = 0; k <= 400; ++k) {
    const double r = 10.0 * std::pow(0.9, k);
    csv += "pgs," + std::to_string(k) + "," + num(1e-4 * k) + "," + num(r) + "," + num(0.1 * r) +
           "," + num(0.01 * r) + ",-1\n";
  }
  for (int k = 0; k <= 300; ++k) {
    const std::string r = k < 300 ? "1e" + std::to_string(k) : "inf";
    csv += "jacobi," + std::to_string(k) + "," + num(1e-4 * k) + "," + r + "," + r + "," + r + "," +
           r + "\n";
  }
  csv += "direct,1,0.0005,1e-14,,,-1\n";
  cbps::test::write_file(dir / "c.csv", csv);
  const std::string python =
      std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string cmd = python + " " + CBPS_SOURCE_DIR + "/scripts/plot_convergence.py " +
                          (dir / "c.csv").string() + " " + (dir / "c").string() +
                          " --title diverging 2>" + (dir / "err").string();
  const int status = std::system(cmd.c_str());
  INFO(slurp(dir / "err"));
  CHECK(status == 0);
  REQUIRE(std::filesystem::exists(dir / "c.png"));
  CHECK(std::filesystem::file_size(dir / "c.png") > 10000);
  // The legend says which solver diverged.
  CHECK(slurp(dir / "c.svg").find("diverged") != std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE("cbps converge counts an exact method's iterations as cbps lcp does", "[cli][converge]") {
  // Issue 50, item 11: converge recorded max(1, iterations) for the exact methods, so a problem
  // that Lemke solves with no pivot (q >= 0: lambda = 0) showed 1 in converge and 0 in lcp.
  // A = diag(2, 3), b = (-1, -2), lambda in [0, inf): lambda = 0, w = -b >= 0, by hand.
  const auto dir = scratch_dir("converge_counts");
  const auto folder = dir / "hand";
  std::filesystem::create_directories(folder);
  const std::string vector = "%%MatrixMarket matrix array real general\n2 1\n";
  cbps::test::write_file(folder / "A.mtx",
                         "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 2\n2 2 3\n");
  cbps::test::write_file(folder / "b.mtx", vector + "-1\n-2\n");
  cbps::test::write_file(folder / "cmin.mtx", vector + "0\n0\n");
  cbps::test::write_file(folder / "cmax.mtx", vector + "inf\ninf\n");
  const auto c = run_cli("converge " + folder.string() +
                         " --solvers lemke,direct --quiet --no-plot --out " + (dir / "c").string());
  INFO(c.err);
  REQUIRE(c.code == 0);
  const auto summary = nlohmann::json::parse(slurp(dir / "c" / "summary.json"));
  for (const auto& s : summary["solvers"]) {
    const std::string solver = s["solver"].get<std::string>();
    CAPTURE(solver);
    const auto l = run_cli("lcp " + folder.string() + " --solver " + solver + " --json");
    REQUIRE(l.code == 0);
    const auto j = nlohmann::json::parse(l.out);
    CHECK(j["status"] == "solved");
    CHECK(s["iterations"] == j["iterations"]);
    if (solver == "lemke") CHECK(s["iterations"] == 0);  // q = -b >= 0: no pivot
  }
}
