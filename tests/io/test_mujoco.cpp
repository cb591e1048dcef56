// MuJoCo's constraint problem as cbps exports it (io/mujoco_problem.hpp): MuJoCo's Newton solver
// run to its floor agrees with cbps's direct on the exported problem within a bound made of both
// answers' residuals, on a model of each row kind; A + R agrees with MuJoCo's own efc_AR.
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/mujoco_problem.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/check.hpp"

using namespace cbps;

namespace {

std::string model(const std::string& name) {
  return std::string(CBPS_SOURCE_DIR) + "/tests/data/mujoco/" + name;
}

/// The steps of `run` (MuJoCo's Newton to tolerance 1e-15, as the models set it).
std::vector<MujocoStep> exported(MujocoRun run) {
  std::vector<MujocoStep> steps;
  run_mujoco(run, [&](const MujocoStep& s) { steps.push_back(s); });
  return steps;
}

/// The error bound of a strongly monotone variational inequality (Facchinei & Pang 2003,
/// Proposition 6.3.1 with the natural map): with F(lambda) = A lambda − b, A symmetric positive
/// definite (MuJoCo's R > 0 on every row) of smallest eigenvalue m and largest L,
/// ‖lambda − lambda*‖₂ ≤ (1 + L) / m ‖F_nat(lambda)‖₂. Two answers are then within the sum of
/// their bounds; ‖·‖₂ ≤ √n ‖·‖∞ turns the residuals cbps reports into it.
double agreement_bound(const StoredProblem& p, double residual_1, double residual_2) {
  const Eigen::SelfAdjointEigenSolver<MatX> eigen{MatX(p.A)};
  const double m = eigen.eigenvalues().minCoeff(), L = eigen.eigenvalues().maxCoeff();
  REQUIRE(m > 0.0);
  return (1.0 + L) / m * std::sqrt(double(p.rows())) * (residual_1 + residual_2);
}

/// MuJoCo's forces against direct's answer of each exported step with rows.
void agrees_with_direct(const std::vector<MujocoStep>& steps, long& checked) {
  for (const MujocoStep& s : steps) {
    if (s.problem.rows() == 0) continue;
    CAPTURE(s.step, s.problem.rows());
    // The exported problem is the one MuJoCo solved: A − R = J M⁻¹ Jᵀ (by Eigen's own solve).
    const MatX JMJ = s.J * s.M.ldlt().solve(s.J.transpose());
    MatX A = MatX(s.problem.A);
    A.diagonal() -= s.R;
    CHECK((A - JMJ).cwiseAbs().maxCoeff() <= 1e-12 * std::max(1.0, JMJ.cwiseAbs().maxCoeff()));
    CHECK(s.R.minCoeff() > 0.0);
    SolverOptions o;
    o.method = Method::Direct;
    o.tolerance = 0.0;  // to its rounding floor
    VecX exact = VecX::Zero(s.problem.rows());
    const SolverSummary direct = solve(s.problem.problem(), exact, o);
    REQUIRE(direct.termination != Termination::NotConverged);
    CheckSettings settings;
    settings.exact = false;
    const CheckReport mujoco = check_lambda(s.problem, s.force, settings);
    CHECK(mujoco.solved);
    const double bound = agreement_bound(s.problem, mujoco.natural_map, direct.residual);
    const double gap = (s.force - exact).cwiseAbs().maxCoeff();
    CAPTURE(gap, bound, mujoco.natural_map, direct.residual);
    CHECK(gap <= bound);
    CHECK(bound <= 1e-8 * std::max(1.0, exact.cwiseAbs().maxCoeff()));  // a bound that bites
    ++checked;
  }
}

}  // namespace

TEST_CASE("MuJoCo's problem of a step: Newton at its floor agrees with direct on every row kind",
          "[mujoco]") {
  if (!mujoco_built()) {
    MujocoRun run;
    run.model = model("sliding_box_elliptic.xml");
    CHECK_THROWS_WITH(run_mujoco(run, [](const MujocoStep&) {}), Catch::Contains("libmujoco-dev"));
    return;
  }
  long checked = 0;
  for (const std::string cone : {"elliptic", "pyramidal"}) {
    MujocoRun run;  // landing on an edge at step 10 (two contacts), at rest by step 150 (four)
    run.model = model("sliding_box_" + cone + ".xml");
    run.keyframe = "pushed";
    run.steps = 151;
    run.at = {10, cone == std::string("elliptic") ? 60L : 20L, 150};
    const std::vector<MujocoStep> steps = exported(run);
    REQUIRE(steps.size() == 3);
    REQUIRE(steps[0].problem.rows() > 0);
    CHECK(steps[0].solve.cone == cone);
    if (cone == "elliptic") {
      CHECK(steps[0].problem.cones.contacts() == 2);
      CHECK(steps[0].problem.cones.mu(0) == 0.5);
      CHECK(steps[0].labels[1].rfind("friction floor-box #", 0) == 0);
    } else {
      CHECK(steps[0].problem.rows() == 8);  // two contacts, four edges each, each >= 0
      CHECK(steps[0].problem.cmin.maxCoeff() == 0.0);
    }
    agrees_with_direct(steps, checked);
  }
  MujocoRun soft;  // impratio 10: the friction rows' R changes, the cone is still friction[0]'s
  soft.model = model("sliding_box_elliptic_impratio.xml");
  soft.keyframe = "pushed";
  soft.steps = 91;
  soft.at = {10, 40, 90};  // sliding on two contacts at each
  const std::vector<MujocoStep> impratio = exported(soft);
  REQUIRE(impratio.size() == 3);
  CHECK(impratio[0].problem.cones.mu(0) == 0.5);
  agrees_with_direct(impratio, checked);
  MujocoRun chain;  // joint limits at +-0.3 rad: rows [0, inf)
  chain.model = model("hinge_chain_limits.xml");
  chain.keyframe = "bent";
  chain.steps = 41;
  chain.at = {0, 20, 40};
  const std::vector<MujocoStep> limits = exported(chain);
  CHECK(limits[0].labels[0] == "limit joint j1");
  agrees_with_direct(limits, checked);
  MujocoRun mixed;  // a connect equality (three free rows) and a slider's friction loss (a box)
  mixed.model = model("equality_frictionloss.xml");
  mixed.steps = 21;
  mixed.at = {0, 20};
  const std::vector<MujocoStep> rows = exported(mixed);
  REQUIRE(rows[0].problem.rows() == 4);
  CHECK(rows[0].labels[0] == "equality ab");
  CHECK(std::isinf(rows[0].problem.cmin(0)));
  CHECK(rows[0].labels[3] == "frictionloss joint slide");
  CHECK(rows[0].problem.cmin(3) == -2.0);
  CHECK(rows[0].problem.cmax(3) == 2.0);
  agrees_with_direct(rows, checked);
  CHECK(checked == 14);
}

TEST_CASE("A + R as cbps forms it is MuJoCo's own efc_AR where its PGS forms it", "[mujoco]") {
  if (!mujoco_built()) return;  // the case above holds the message of a build without MuJoCo
  MujocoRun run;
  run.model = model("sliding_box_pyramidal.xml");
  run.keyframe = "pushed";
  run.solver = "pgs";
  run.steps = 21;
  run.at = {20};
  const std::vector<MujocoStep> steps = exported(run);
  REQUIRE(steps.size() == 1);
  const MujocoStep& s = steps[0];
  REQUIRE(s.AR.rows() == s.problem.rows());
  REQUIRE(s.problem.rows() > 0);
  CHECK((MatX(s.problem.A) - s.AR).cwiseAbs().maxCoeff() <= 1e-12 * s.AR.cwiseAbs().maxCoeff());
}

TEST_CASE("cbps mujoco refuses what it cannot map, naming it", "[mujoco]") {
  if (!mujoco_built()) return;
  MujocoRun run;
  run.model = model("no_such_model.xml");
  CHECK_THROWS_AS(run_mujoco(run, [](const MujocoStep&) {}), InputError);
  run.model = model("sliding_box_elliptic.xml");
  run.keyframe = "missing";
  CHECK_THROWS_WITH(run_mujoco(run, [](const MujocoStep&) {}),
                    Catch::Contains("has no keyframe of that name"));
  run.keyframe.clear();
  run.at = {5};
  CHECK_THROWS_WITH(run_mujoco(run, [](const MujocoStep&) {}),
                    Catch::Contains("--step 5: not one of the 1 steps run"));
}
