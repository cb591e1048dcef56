// The derivation checks of verify.hpp.
#include "cbps/studies/verify.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"

namespace cbps {

namespace {

/// Two movable boxes at random poses with random velocities, fixed seed.
std::vector<Body> random_pair(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto vec = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  std::vector<Body> bodies(2);
  for (Body& body : bodies) {
    body.shape.kind = Shape::Kind::Box;
    body.shape.half_extents = Vec3(0.3, 0.2, 0.1) + 0.1 * vec().cwiseAbs();
    set_mass(body, 1.0 + std::abs(u(rng)));
    body.x = vec();
    body.q = Quat(Eigen::AngleAxisd(3.0 * u(rng), vec().normalized()));
    body.set_velocity(vec(), 2.0 * vec());
  }
  bodies[1].x += Vec3(2.0, 0.0, 0.0);
  return bodies;
}

double relative(double error, double scale) { return error / std::max(scale, 1e-300); }

/// Chain scene with a heavier last link, for the system checks.
Scene small_chain(int n) {
  return make_builtin_scene("chain", {{"n", std::to_string(n)}, {"mass_ratio", "10"}});
}

/// The same chain of turned boxes joined off their centres, so that every entry of each j_c
/// block (linear and angular) and of each I⁻¹ block is nonzero.
Scene box_chain(int n) {
  Scene scene = small_chain(n);
  for (Body& body : scene.bodies) {
    body.q = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
    body.shape.kind = Shape::Kind::Box;
    body.shape.half_extents = Vec3(0.05, 0.02, 0.01);
    set_mass(body, body.m);
  }
  for (DistanceConstraint& dc : scene.distances) dc.anchor_b = Vec3(0.01, 0.02, 0.0);
  return scene;
}

/// n samples of the standard normal distribution, fixed seed.
VecX random_vector(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  VecX x(n);
  for (Eigen::Index k = 0; k < n; ++k) x(k) = n01(rng);
  return x;
}

}  // namespace

Check check_distance_jacobian() {
  Check c{
      "5.2.1", "distance row j_c = d/dt (|p_b - p_a| - l), central finite difference", 0.0, 1e-7};
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<Body> bodies = random_pair(rng);
    DistanceConstraint dc;
    dc.a = 0;
    dc.b = 1;
    dc.anchor_a = Vec3(0.3, -0.1, 0.05);
    dc.anchor_b = Vec3(-0.2, 0.15, -0.05);
    dc.length = 1.0;
    const Row row = distance_row(dc, bodies, 0.0, 1.0, 0);
    const double analytic =
        row.j_a.dot(
            (Eigen::Matrix<double, 6, 1>() << bodies[0].v(), bodies[0].omega()).finished()) +
        row.j_b.dot((Eigen::Matrix<double, 6, 1>() << bodies[1].v(), bodies[1].omega()).finished());
    const double h = 1e-5;  // s
    auto moved = [&](double t) {
      std::vector<Body> b = bodies;
      for (Body& body : b) advance_position(body, body.v(), body.omega(), t);
      return distance_violation(dc, b);
    };
    const double numeric = (moved(h) - moved(-h)) / (2.0 * h);
    c.error = std::max(c.error, relative(std::abs(analytic - numeric), std::abs(numeric) + 1.0));
  }
  return c;
}

Check check_transpose_sum() {
  Check c{"12.2.2", "J^T lambda = sum_i J_i^T lambda_i (row by row)", 0.0, 1e-14};
  const System sys = Simulation(box_chain(6)).build_system();
  const VecX lambda = random_vector(sys.rows(), 3);
  const VecX product = sys.J.transpose() * lambda;
  VecX sum = VecX::Zero(sys.J.cols());
  const MatX J = sys.J;
  for (Eigen::Index i = 0; i < J.rows(); ++i) sum += J.row(i).transpose() * lambda(i);
  c.error = relative((product - sum).lpNorm<Eigen::Infinity>(), sum.lpNorm<Eigen::Infinity>());
  return c;
}

Check check_power_identity() {
  Check c{"12.2", "(J^T lambda) . v = lambda . (J v)", 0.0, 1e-13};
  const System sys = Simulation(box_chain(8)).build_system();
  const VecX lambda = random_vector(sys.rows(), 5);
  const VecX v = random_vector(sys.J.cols(), 6);
  const double lhs = (sys.J.transpose() * lambda).dot(v);
  const double rhs = lambda.dot(sys.J * v);
  c.error = relative(std::abs(lhs - rhs), std::abs(lhs));
  return c;
}

Check check_velocity_constraint() {
  Check c{"12.3",
          "J v2 = upsilon after an unbounded solve to convergence (m/s, PGS and direct)",
          0.0,
          1e-10};
  Scene scene = small_chain(10);
  scene.bodies.back().p = Vec3(0.0, 0.3, 0.1);  // something to correct
  Simulation sim(scene);
  const System sys = sim.build_system();
  for (const Method method : {kExactMethod, kPaperMethod}) {
    VecX lambda = VecX::Zero(sys.rows());
    SolverOptions options;
    options.method = method;
    options.max_iterations = 100000;
    options.tolerance = 1e-13;
    solve(sys.problem(), lambda, options);
    const VecX v2 = compute_v2(sys, lambda);
    c.error = std::max(c.error, (sys.J * v2 - sys.upsilon).lpNorm<Eigen::Infinity>());
  }
  return c;
}

Check check_quaternion_derivative() {
  Check c{"12.4.1/12.5.1",
          "d/dt [axis_angle(omega t) q0] at t = 0 equals 1/2 [0, omega] q0",
          0.0,
          1e-8};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 omega = 5.0 * Vec3(u(rng), u(rng), u(rng));
    const Quat q0(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    const double h = 1e-5;
    const Quat qp = axis_angle_quaternion(omega * h) * q0;
    const Quat qm = axis_angle_quaternion(-omega * h) * q0;
    const Eigen::Vector4d numeric = (qp.coeffs() - qm.coeffs()) / (2.0 * h);
    const Quat analytic = Quat(0.0, omega.x(), omega.y(), omega.z()) * q0;
    const Eigen::Vector4d expected = 0.5 * analytic.coeffs();
    c.error = std::max(c.error,
                       relative((numeric - expected).lpNorm<Eigen::Infinity>(),
                                expected.lpNorm<Eigen::Infinity>()));
  }
  return c;
}

Check check_A_symmetric() {
  Check c{"6.2.9",
          "A = J Minv J^T is symmetric: max |A - A^T| / max |A| (round-off)",
          0.0,
          4 * std::numeric_limits<double>::epsilon()};
  const MatX A = Simulation(box_chain(12)).build_system().A;
  c.error = relative((A - A.transpose()).lpNorm<Eigen::Infinity>(), A.lpNorm<Eigen::Infinity>());
  return c;
}

Check check_A_semidefinite() {
  Check c{"6.2.9",
          "A is positive semidefinite (a row given twice makes it singular): -min eig / max eig",
          0.0,
          1e-14};
  Scene scene = box_chain(8);
  scene.distances.push_back(scene.distances[3]);  // the same row twice
  Simulation sim(scene);
  const MatX A = sim.build_system().A;
  Eigen::SelfAdjointEigenSolver<MatX> eig(A);
  const double lo = eig.eigenvalues().minCoeff();
  const double hi = eig.eigenvalues().maxCoeff();
  c.error = std::max(0.0, -lo / hi);
  return c;
}

Check check_bias_reduces_violation() {
  Check c{"5.2.3",
          "a stretched link: c_after / c_before = 1 - beta (beta = 0.3, no gravity, at rest)",
          0.0,
          1e-12};
  Scene scene = make_builtin_scene("pendulum-wave", {{"n", "1"}, {"attach", "center"}});
  scene.world.gravity.setZero();
  scene.world.beta = 0.3;
  scene.distances[0].length *= 0.99;  // the string is now 1 % too short: c > 0
  Simulation sim(scene);
  const double before = distance_violation(scene.distances[0], sim.scene().bodies);
  sim.step();
  const double after = distance_violation(scene.distances[0], sim.scene().bodies);
  // The correction moves the ball along the string, so c shrinks by exactly beta.
  c.error = std::abs(after / before - (1.0 - scene.world.beta));
  if (!(std::abs(after) < std::abs(before))) c.error = kInf;
  return c;
}

Check check_dimensional_analysis() {
  Check c{"9", "m -> cm, kg -> g, s -> 0.5 s: lambda, b, x scale as N, m/s^2, m", 0.0, 1e-10};
  const double L = 100.0;
  const double M = 1000.0;
  const double T = 0.5;
  Scene base = small_chain(5);
  base.solver.tolerance = 0.0;  // a fixed number of sweeps in both units
  base.solver.max_iterations = 30;
  Simulation a(base);
  Simulation b(rescale_units(base, L, M, T));
  // Each quantity is compared relative to its natural size in the base units (the chain's
  // weight in N, g in m/s², the link length in m), so round-off-sized values (λ ≈ 1e-13 N in
  // the first step, when the chain is released at rest) do not count as relative errors.
  double weight = 0.0;
  for (const Body& body : base.bodies) weight += body.m * base.world.gravity.norm();
  const double g = base.world.gravity.norm();
  const double length = base.distances[0].length;
  double worst = 0.0;
  auto compare = [&](const VecX& x, const VecX& y, double unit, double size) {
    const double scale = std::max(x.lpNorm<Eigen::Infinity>(), size) * unit;
    worst = std::max(worst, (x * unit - y).lpNorm<Eigen::Infinity>() / scale);
  };
  VecX lambda_a;
  VecX lambda_b;
  a.set_observer([&](const System&, const VecX& l, const VecX&) { lambda_a = l; });
  b.set_observer([&](const System&, const VecX& l, const VecX&) { lambda_b = l; });
  for (int s = 0; s < 50; ++s) {
    compare(a.build_system().b, b.build_system().b, L / (T * T), g);  // m/s²
    a.step();
    b.step();
    compare(lambda_a, lambda_b, M * L / (T * T), weight);  // N
    for (std::size_t i = 0; i < base.bodies.size(); ++i) {
      compare(a.scene().bodies[i].x, b.scene().bodies[i].x, L, length);  // m
    }
  }
  c.error = worst;
  return c;
}

std::vector<Check> run_derivation_checks() {
  return {check_distance_jacobian(),
          check_quaternion_derivative(),
          check_bias_reduces_violation(),
          check_A_symmetric(),
          check_A_semidefinite(),
          check_transpose_sum(),
          check_power_identity(),
          check_velocity_constraint(),
          check_dimensional_analysis()};
}

std::string checks_text(const std::vector<Check>& checks) {
  char line[512];
  std::snprintf(line,
                sizeof line,
                "%-14s %-10s %-10s %-5s %s\n",
                "equation",
                "error",
                "tolerance",
                "",
                "check");
  std::string t = line;
  for (const Check& c : checks) {
    std::snprintf(line,
                  sizeof line,
                  "%-14s %-10.3g %-10.3g %-5s ",
                  c.equation.c_str(),
                  c.error,
                  c.tolerance,
                  c.pass() ? "pass" : "FAIL");
    t += line + c.what + "\n";
  }
  return t;
}

nlohmann::json checks_json(const std::vector<Check>& checks) {
  nlohmann::json out = nlohmann::json::array();
  for (const Check& c : checks)
    out.push_back({{"equation", c.equation},
                   {"what", c.what},
                   {"error", c.error},
                   {"tolerance", c.tolerance},
                   {"pass", c.pass()}});
  return out;
}

bool all_pass(const std::vector<Check>& checks) {
  return std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.pass(); });
}

}  // namespace cbps
