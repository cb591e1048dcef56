// PGS-SM (Silcowitz, Niebe and Erleben, GRAPP 2010; Morales, Nocedal and Smelyanskiy, Numer.
// Math. 2008): PGS phases that choose the active set, subspace phases that solve the free rows by
// conjugate gradients. The method and its cost are described in pgs_sm.hpp.
#include "cbps/solvers/compared/pgs_sm.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "../sweep.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/paper/pgs.hpp"

namespace cbps {

namespace {

/// The state of one PGS-SM solve between iterations: which phase, how far into it, and the
/// subspace phase's CG vectors (full length c, zero outside F).
class PgsSm {
 public:
  PgsSm(const BoxedProblem& problem, const SolverOptions& options, const PgsSmSettings& settings)
      : p_(problem),
        options_(options),
        settings_(settings),
        x_(VecX::Zero(problem.rows())),
        r_(VecX::Zero(problem.rows())),
        d_(VecX::Zero(problem.rows())),
        q_(VecX::Zero(problem.rows())) {}

  /// One iteration (one PGS sweep or one CG step) on lambda; returns max |Δlambda|, N.
  double iterate(VecX& lambda) {
    if (subspace_ && (!cg_running_ && !start(lambda))) end_subspace();
    if (!subspace_) return pgs_step(lambda);
    return cg_step(lambda);
  }

  int extra_products() const { return extra_products_; }

 private:
  /// One sweep of 7.1.1; the last of a phase hands over to the subspace phase.
  double pgs_step(VecX& lambda) {
    const double delta = pgs_sweep(p_, lambda, options_.relaxation);
    if (++sweeps_ >= settings_.pgs_sweeps) {
      subspace_ = true;
      cg_steps_ = 0;
    }
    return delta;
  }

  void end_subspace() {
    subspace_ = false;
    cg_running_ = false;
    sweeps_ = 0;
  }

  /// Starts CG on the rows strictly inside their bounds: F, x = lambda, r = b_F − (A lambda)_F,
  /// d = r. False when there is nothing to solve (F empty or r_F = 0).
  bool start(const VecX& lambda) {
    free_.clear();
    for (Eigen::Index k = 0; k < p_.rows(); ++k) {
      // A row with A_kk = 0 acts on nothing (7.1.1 leaves it): it is no unknown of A(F,F).
      if (p_.cmin(k) < lambda(k) && lambda(k) < p_.cmax(k) && diagonal(k) > 0.0) free_.push_back(k);
    }
    if (free_.empty()) return false;
    x_ = lambda;
    r_.setZero();
    d_.setZero();
    for (const Eigen::Index k : free_) {
      double Ax = 0.0;  // (A lambda)_k: A is symmetric, column k holds row k
      for (SpMat::InnerIterator it(p_.A, k); it; ++it) Ax += it.value() * x_(it.row());
      r_(k) = p_.b(k) - Ax;  // −w_k (6.2)
    }
    d_ = r_;
    rr_ = r_.squaredNorm();
    rr_start_ = rr_;
    ++extra_products_;
    if (!(rr_ > 0.0)) return false;  // exact already (NaN: the next PGS sweep reports it)
    cg_running_ = true;
    return true;
  }

  /// One CG step on A(F,F) x_F = b_F − A(F,B) lambda_B, then lambda_F = clamp(x_F).
  double cg_step(VecX& lambda) {
    // q = A(F,F) d_F: d is zero outside F, so (A d)_k over the F columns, for k in F.
    double dq = 0.0;
    for (const Eigen::Index k : free_) {
      double Ad = 0.0;
      for (SpMat::InnerIterator it(p_.A, k); it; ++it) Ad += it.value() * d_(it.row());
      q_(k) = Ad;
      dq += d_(k) * Ad;
    }
    // dᵀ A d ≤ 0 relative to round-off: d left range(A(F,F)) (an inconsistent reduced system,
    // see pgs_sm.hpp). The phase ends; its product is counted in extra_products_.
    if (!(dq > kBreakdown * d_.squaredNorm() * max_diagonal())) {
      ++extra_products_;
      end_subspace();
      if (!std::isfinite(dq)) return std::numeric_limits<double>::quiet_NaN();
      return pgs_step(lambda);  // the iteration is a PGS sweep instead
    }
    // The CG step alpha, cut where the first free row meets its bound: x_F stays in the box,
    // and 0.5 λᵀAλ − bᵀλ, a convex parabola along d with its minimum at rr / dq, still falls.
    double alpha = rr_ / dq;
    Eigen::Index blocking = -1;  // the row that meets its bound first, if any
    for (const Eigen::Index k : free_) {
      const double bound = d_(k) > 0.0 ? p_.cmax(k) : p_.cmin(k);
      if (d_(k) == 0.0 || !std::isfinite(bound)) continue;
      const double room = (bound - x_(k)) / d_(k);  // ≥ 0: x_k is inside
      if (room < alpha) {
        alpha = room;
        blocking = k;
      }
    }
    double delta = 0.0;
    for (const Eigen::Index k : free_) {
      x_(k) = clamp(x_(k) + alpha * d_(k), p_.cmin(k), p_.cmax(k));  // clamp: round-off only
      r_(k) -= alpha * q_(k);
      const double change = std::abs(x_(k) - lambda(k));
      max_keep_nan(delta, change);
      lambda(k) = x_(k);
    }
    const bool moved_to_bound = blocking >= 0;
    if (moved_to_bound) {
      lambda(blocking) = x_(blocking) = d_(blocking) > 0.0 ? p_.cmax(blocking) : p_.cmin(blocking);
    }
    ++cg_steps_;
    const double rr_next = r_.squaredNorm();
    if (cg_steps_ >= settings_.cg_iterations ||
        rr_next <= settings_.cg_tolerance * settings_.cg_tolerance * rr_start_) {
      end_subspace();
    } else if (moved_to_bound) {
      cg_running_ = false;  // F shrinks: the next iteration starts CG again from lambda
    } else {
      d_ = r_ + (rr_next / rr_) * d_;  // the next conjugate direction
      rr_ = rr_next;
    }
    return delta;
  }

  double diagonal(Eigen::Index k) const {
    for (SpMat::InnerIterator it(p_.A, k); it; ++it)
      if (it.row() == k) return it.value();
    return 0.0;
  }

  double max_diagonal() {
    if (max_diagonal_ < 0.0) {
      max_diagonal_ = 0.0;
      for (Eigen::Index k = 0; k < p_.rows(); ++k)
        max_diagonal_ = std::max(max_diagonal_, diagonal(k));
    }
    return max_diagonal_;
  }

  /// dᵀAd below this · ‖d‖² · max A_kk counts as zero curvature: a few hundred ε, the rounding
  /// of a product with A relative to its largest entry.
  static constexpr double kBreakdown = 256.0 * std::numeric_limits<double>::epsilon();

  const BoxedProblem& p_;
  const SolverOptions& options_;
  const PgsSmSettings& settings_;
  bool subspace_ = false;    // in the subspace phase (else the PGS phase)
  bool cg_running_ = false;  // CG started on the current F
  int sweeps_ = 0;           // PGS sweeps in this PGS phase
  int cg_steps_ = 0;         // CG steps in this subspace phase
  int extra_products_ = 0;   // products with A not counted as iterations (CG starts, breakdowns)
  std::vector<Eigen::Index> free_;
  VecX x_;  // lambda_F before projection, N
  VecX r_;  // b_F − A(F,F) x_F − A(F,B) lambda_B = −w_F, m/s²
  VecX d_;  // conjugate direction, N
  VecX q_;  // A(F,F) d_F, m/s²
  double rr_ = 0.0;
  double rr_start_ = 0.0;
  double max_diagonal_ = -1.0;
};

}  // namespace

SolverSummary solve_pgs_sm(const BoxedProblem& problem,
                           VecX& lambda,
                           const SolverOptions& options,
                           const PgsSmSettings& settings) {
  if (settings.pgs_sweeps < 1 || settings.cg_iterations < 1) {
    throw std::invalid_argument("pgs-sm: pgs_sweeps and cg_iterations must be at least 1");
  }
  PgsSm method(problem, options, settings);
  SolverSummary s =
      detail::iterate_sweeps(problem, lambda, options, [&](VecX& l) { return method.iterate(l); });
  s.restarts = method.extra_products();
  if (options.describe) {
    std::ostringstream msg;
    msg << s.message << " (PGS sweeps and CG steps), " << s.restarts
        << " products with A besides the iterations (CG starts)";
    s.message = msg.str();
  }
  return s;
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

namespace {

SolverSummary pgs_sm_method(const BoxedProblem& p, VecX& lambda, const SolverOptions& o) {
  return solve_pgs_sm(p, lambda, o, o.methods.pgs_sm);
}

}  // namespace

/// pgs-sm's own keys (`--solver NAME:key=value`, /solver/parameters), over its settings
/// (method_settings.hpp).
constexpr MethodKey kPgsSmKeys[] = {
    {"sweeps",
     "a whole number >= 1",
     [](const std::string& v, MethodSettings& s) { return key_count(v, s.pgs_sm.pgs_sweeps); },
     [](const MethodSettings& s) -> std::string { return std::to_string(s.pgs_sm.pgs_sweeps); }},
    {"cg",
     "a whole number >= 1",
     [](const std::string& v, MethodSettings& s) { return key_count(v, s.pgs_sm.cg_iterations); },
     [](const MethodSettings& s) -> std::string { return std::to_string(s.pgs_sm.cg_iterations); }},
    {"cg_tolerance",
     "a number in (0, 1)",
     [](const std::string& v, MethodSettings& s) {
       return parse_number(v, s.pgs_sm.cg_tolerance) && s.pgs_sm.cg_tolerance > 0.0 &&
              s.pgs_sm.cg_tolerance < 1.0;
     },
     [](const MethodSettings& s) -> std::string { return key_number(s.pgs_sm.cg_tolerance); }},
};

extern const MethodEntry kPgsSmEntry;
constexpr MethodEntry kPgsSmEntry{
    .method = Method::PgsSm,
    .name = "pgs-sm",
    .symmetric = true,
    .symmetric_on_cones = true,
    .solve = pgs_sm_method,
    .what =
        "PGS with subspace minimization by CG (Silcowitz, Niebe & Erleben 2010); sweeps=, "
        "cg=, cg_tolerance=",
    .keys = kPgsSmKeys,
};

}  // namespace cbps
