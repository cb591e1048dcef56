// NSGS on friction cones (cone/nsgs.hpp).
#include "cbps/solvers/cone/nsgs.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <vector>

#include "../sweep.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/paper/pgs.hpp"

namespace cbps {

namespace {

/// What a sweep visits, set up once per solve, in row order: runs of rows no contact owns (each
/// swept by 7.1.1 itself, pgs_sweep) and contacts; and each contact's W_αα and step rho_α.
struct NsgsSetup {
  struct Unit {
    int contact = -1;       ///< a contact's index, or −1 for a run of rows
    std::vector<int> rows;  ///< the run's rows
  };
  std::vector<Unit> units;
  std::vector<Mat3> W;
  std::vector<double> rho;  ///< 1 / λmax(W_αα), 0 when W_αα acts on nothing (r stays)
};

NsgsSetup setup(const BoxedProblem& problem) {
  NsgsSetup s;
  const SpMat& A_rows = detail::rows_of(problem);
  const Eigen::Index c = problem.rows();
  std::vector<int> contact_at(static_cast<std::size_t>(c), -1);
  std::vector<char> in_cone(static_cast<std::size_t>(c), 0);
  if (problem.cones != nullptr) {
    const FrictionContacts& cones = *problem.cones;
    in_cone = cones.rows_in_cones(c);
    for (long i = 0; i < cones.contacts(); ++i) {
      const int n = cones.normal[static_cast<std::size_t>(i)];
      contact_at[static_cast<std::size_t>(n)] = static_cast<int>(i);
      Mat3 W = Mat3::Zero();
      for (int a = 0; a < 3; ++a)
        for (SpMat::InnerIterator it(A_rows, n + a); it; ++it)  // row n + a of A
          if (it.row() >= n && it.row() < n + 3) W(a, it.row() - n) = it.value();
      s.W.push_back(W);
      const double top =
          Eigen::SelfAdjointEigenSolver<Mat3>(0.5 * (W + W.transpose()), Eigen::EigenvaluesOnly)
              .eigenvalues()
              .maxCoeff();
      s.rho.push_back(top > 0.0 ? 1.0 / top : 0.0);
    }
  }
  for (Eigen::Index k = 0; k < c; ++k) {
    const int contact = contact_at[static_cast<std::size_t>(k)];
    if (contact >= 0) {
      s.units.push_back({contact, {}});
    } else if (!in_cone[static_cast<std::size_t>(k)]) {
      if (s.units.empty() || s.units.back().contact >= 0) s.units.push_back({-1, {}});
      s.units.back().rows.push_back(static_cast<int>(k));
    }
  }
  return s;
}

/// w_k = (A lambda)_k − b_k for the three rows of a contact at n, from A's rows.
Vec3 contact_w(const SpMat& A_rows, const VecX& b, const VecX& lambda, int n) {
  Vec3 w;
  for (int a = 0; a < 3; ++a) {
    double sum = -b(n + a);
    for (SpMat::InnerIterator it(A_rows, n + a); it; ++it) sum += it.value() * lambda(it.row());
    w(a) = sum;
  }
  return w;
}

/// Contact i's local steps r ← P_K(r − rho û(W r + p)), at most `local`; returns max |Δr|.
double contact_step(
    const BoxedProblem& problem, const NsgsSetup& s, int i, int local, VecX& lambda) {
  const FrictionContacts& cones = *problem.cones;
  const int n = cones.normal[static_cast<std::size_t>(i)];
  const double rho = s.rho[static_cast<std::size_t>(i)];
  if (rho == 0.0) return 0.0;
  const Mat3& W = s.W[static_cast<std::size_t>(i)];
  const double mu = cones.mu(i);
  const Vec3 start = lambda.segment<3>(n);
  const Vec3 p = contact_w(detail::rows_of(problem), problem.b, lambda, n) - W * start;
  Vec3 r = start;
  for (int step = 0; step < local; ++step) {
    Vec3 next = r - rho * law_velocity(W * r + p, mu, cones.law);
    project_onto_cone(mu, next);
    const double moved = (next - r).lpNorm<Eigen::Infinity>();
    r = next;
    // Stop once a step moves r by round-off of its size (or r is not finite: the sweep's
    // change reports it).
    if (!(moved > 1e-15 * r.lpNorm<Eigen::Infinity>())) break;
  }
  lambda.segment<3>(n) = r;
  return (r - start).lpNorm<Eigen::Infinity>();
}

double nsgs_sweep(const BoxedProblem& problem, const NsgsSetup& s, int local, VecX& lambda) {
  double change = 0.0;
  for (const NsgsSetup::Unit& unit : s.units) {
    max_keep_nan(change,
                 unit.contact >= 0 ? contact_step(problem, s, unit.contact, local, lambda)
                                   : pgs_sweep(problem, lambda, 1.0, unit.rows));  // 7.1.1
  }
  return change;
}

}  // namespace

struct NsgsSweep::Setup {
  NsgsSetup s;
};

NsgsSweep::NsgsSweep(const BoxedProblem& problem)
    : problem_(problem), setup_(std::make_unique<Setup>(Setup{setup(problem)})) {}

NsgsSweep::~NsgsSweep() = default;

double NsgsSweep::operator()(VecX& lambda, int local) const {
  return nsgs_sweep(problem_, setup_->s, local, lambda);
}

SolverSummary solve_nsgs(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  const NsgsSweep sweep(problem);
  const int local = std::max(1, options.methods.nsgs.local);
  return detail::iterate_sweeps(problem, lambda, options, [&](VecX& l) { return sweep(l, local); });
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

/// nsgs's own keys (`--solver NAME:key=value`, /solver/parameters), over its settings
/// (method_settings.hpp).
constexpr MethodKey kNsgsKeys[] = {
    {"local",
     "a whole number >= 1",
     [](const std::string& v, MethodSettings& s) { return key_count(v, s.nsgs.local); },
     [](const MethodSettings& s) -> std::string { return std::to_string(s.nsgs.local); }},
};

extern const MethodEntry kNsgsEntry;
constexpr MethodEntry kNsgsEntry{
    .method = Method::Nsgs,
    .name = "nsgs",
    .laws = kEitherLaw,
    .solve = solve_nsgs,
    .what =
        "non-smooth Gauss-Seidel: 7.1.1 with each contact's rows projected onto its friction "
        "cone (Jean & Moreau 1992); local=; PGS where no row is in a cone",
    .keys = kNsgsKeys,
};

}  // namespace cbps
