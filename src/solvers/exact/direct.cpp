// The exact path for the boxed problem of 6.2: a primal-dual interior-point method (Mehrotra's
// predictor-corrector) with its Newton systems factored in body space, then a crossover to the
// exact active set. The method, its parameters and its sources are described at solve_direct()
// in direct.hpp.
#include "cbps/solvers/exact/direct.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "cbps/solvers/exact/active_set.hpp"
#include "cbps/solvers/islands.hpp"
#include "newton_system.hpp"

namespace cbps {

namespace {

constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon() / 2.0;
/// The fraction of the way to the boundary an interior step goes (Mehrotra's damping).
constexpr double kStepToBoundary = 0.995;
/// Gondzio's multiple centrality correctors (Gondzio, Comput. Optim. Appl. 6 1996): at most
/// this many per iteration, each aiming at a step kCorrectorAspiration times longer, moving
/// the trial products s z, t y into [kCorrectorBand σμ, σμ / kCorrectorBand], and kept when
/// the step grows by kCorrectorGain of what was aimed at (his values: 2, 0.1, 0.1). Three
/// correctors: base-40 pyramid 49 interior iterations instead of 63 (one: 55, two: 51).
constexpr int kCorrectors = 3;
constexpr double kCorrectorAspiration = 2.0;
constexpr double kCorrectorBand = 0.1;
constexpr double kCorrectorGain = 0.1;
/// The crossover's first proximal ε, a fraction of max A_kk: small, because the interior point's
/// partition is close (its proximal steps contract the error by about ε/(σ + ε)).
constexpr double kCrossoverEpsilon = 1e-6;
/// Rows within this fraction of λ's scale (‖b‖∞ / max A_kk) of a bound start the crossover at
/// it: the active set frees wrong-signed rows all at once but blocks rows one at a time, so a
/// partition that errs towards the bound needs far fewer steps (pyramid base 20, measured when
/// every step was a factorization: 301 instead of 1,026).
constexpr double kNearBound = 1e-4;
/// Islands up to this many rows finish apart on CHOLMOD factors of A's free block (row space);
/// larger ones in body space, where one factor is updated from step to step but each step
/// costs a solve of the whole problem (the base-10 pyramid, one island of 1,200 rows: 13 ms in
/// body space against 60 ms on A(F, F); the 100-column stack's 120-row islands the other way).
constexpr Eigen::Index kRowSpaceFinish = 500;
/// A warm start's crossover (warm_finish) takes at most this many proximal steps before the
/// interior point runs from scratch (the cold crossover from the interior point's partition
/// takes 19 to 24 on the 10-box stack and the base-6 pyramid stepped by PGS);
constexpr int kWarmSteps = 30;
/// … and at most this many pivoting rounds in all (each one solve with the free block, about
/// 0.4 ms on the base-20 pyramid's 4,800 rows, where the cold interior point takes about 20 ms).
/// The last step's answer in a scene stepped by the direct path needs 1 to a few
/// (tests/solvers/test_direct_interior.cpp); on states stepped by PGS, settling with its errors,
/// even the last step's exact answer needed 200 to 400 (0.9 λ* likewise), and PGS's λ under
/// `--check` on the base-20 pyramid 233 on one step and 49,473 (9 s, unfinished) on the next:
/// there the interior point is the cheaper way.
constexpr long kWarmRounds = 100;
/// What a message adds when the warm crossover ran out of those.
constexpr const char* kWarmUnfinished =
    "; before it, the warm start's crossover did not finish in 30 proximal steps and 100 "
    "pivoting rounds";
static_assert(kWarmSteps == 30 && kWarmRounds == 100, "kWarmUnfinished names them");

/// Where a row sits in the crossover's partition.
enum class Place : unsigned char { Free, Lower, Upper, Fixed };

/// The whole solve: the interior iterations, then the crossover.
class InteriorSolver {
 public:
  InteriorSolver(const BoxedProblem& problem, const SolverOptions& options, SolverSummary& stats)
      : p_(problem), A_(problem.A), b_(problem.b), options_(options), stats_(stats) {
    const Eigen::Index c = A_.rows();
    lower_.assign(std::size_t(c), 0);
    upper_.assign(std::size_t(c), 0);
    fixed_.assign(std::size_t(c), 0);
    a_ = A_.diagonal();
    for (Eigen::Index k = 0; k < c; ++k) {
      const std::size_t K = std::size_t(k);
      fixed_[K] = problem.cmin(k) == problem.cmax(k);
      lower_[K] = !fixed_[K] && std::isfinite(problem.cmin(k));
      upper_[K] = !fixed_[K] && std::isfinite(problem.cmax(k));
      bounds_ += lower_[K] + upper_[K];
      max_diagonal_ = std::max(max_diagonal_, a_(k));
    }
    if (!(max_diagonal_ > 0.0)) max_diagonal_ = 1.0;
    for (Eigen::Index k = 0; k < c; ++k)
      if (!(a_(k) > 0.0)) a_(k) = max_diagonal_;  // for the crossover's λ − w/A_kk only
    row_sum_ = max_abs_row_sum(A_);
    newton_ = make_newton_system(problem, options.direct.memory.get());
    stats_.space = newton_->space();
  }

  /// The interior iterations, then the crossover; true when lambda reaches the tolerance.
  bool solve(VecX& lambda) {
    interior(lambda);
    const bool small = A_.rows() <= kRowSpaceFinish;
    if (solved_ && !small) {
      stats_.factorizations += newton_->factorizations();
      return true;
    }
    // The crossover starts from the interior point's partition: bound rows at their bounds.
    for (Eigen::Index k = 0; k < lambda.size(); ++k) {
      const Place place = place_[std::size_t(k)];
      if (place == Place::Lower || place == Place::Fixed) lambda(k) = p_.cmin(k);
      if (place == Place::Upper) lambda(k) = p_.cmax(k);
    }
    // Islands of up to kRowSpaceFinish rows finish apart on A(F, F) itself, from ε = 0: where
    // the free block is definite that is exact to round-off, and each factor is the island's
    // own. Larger islands then finish together in body space.
    const std::vector<std::vector<int>> islands =
        small ? std::vector<std::vector<int>>{} : find_islands(A_);
    bool large = false;
    bool all_solved = true;
    if (small) {
      crossover_in_rows_ = true;
      all_solved = finish(p_, lambda, nullptr);
    } else {
      for_each_island(islands, p_, lambda, [&](const BoxedProblem& island, VecX& lambda_I) {
        if (island.rows() > kRowSpaceFinish) {
          large = true;
          return;
        }
        crossover_in_rows_ = true;
        all_solved = finish(island, lambda_I, nullptr) && all_solved;
      });
      if (large) {
        crossover_in_body_ = true;
        all_solved = finish(p_, lambda, newton_.get());
      }
    }
    stats_.factorizations += newton_->factorizations();
    stats_.updates = newton_->updates();
    return all_solved;
  }

  /// The active-set path's finish on `problem` from lambda (newton: body space, else A(F, F)).
  bool finish(const BoxedProblem& problem, VecX& lambda, NewtonSystem* newton) {
    const SolverSummary x = finish_active_set(problem, lambda, options_, newton, kCrossoverEpsilon);
    stats_.crossover += x.iterations;
    stats_.pivots += x.pivots;
    stats_.factorizations += x.factorizations;
    stats_.factor_nnz = std::max(stats_.factor_nnz, x.factor_nnz);
    return x.termination == Termination::Direct;
  }

  /// The rounding floor of the residual at lambda, N.
  double floor(const VecX& lambda) const { return residual_floor(row_sum_, b_, lambda); }

 private:
  bool newton_solve(const VecX& d, const std::vector<char>& dropped, const VecX& r, VecX& x) {
    return newton_->solve(d, dropped, r, x, 0);
  }

  bool factor(const VecX& d, const std::vector<char>& dropped) {
    const bool ok = newton_->factor(d, dropped);
    stats_.factor_nnz = std::max(stats_.factor_nnz, newton_->factor_nonzeros());
    return ok;
  }

  /// The interior point's iterate, slacks s = λ − cmin and t = cmax − λ (N) with their
  /// multipliers z and y (m/s²), and its work vectors: the residual, the Newton systems'
  /// diagonal and right-hand side, the predictor's direction (the _aff ones), the direction,
  /// and a corrector with the corrected direction.
  struct Interior {
    VecX s, t, z, y;
    VecX w, r_d, d, rhs;
    VecX dl_aff, dz_aff, dy_aff, dl, dz, dy;
    VecX dc, cdl, cz, cy;
  };

  /// Mehrotra's predictor-corrector on min ½ λᵀAλ − bᵀλ over the box, from the box's centre.
  void interior(VecX& lambda) {
    const Eigen::Index c = A_.rows();
    const double b_norm = b_.size() > 0 ? b_.lpNorm<Eigen::Infinity>() : 0.0;
    const double lambda_scale = b_norm > 0.0 ? b_norm / max_diagonal_ : 1.0;  // N
    const double w_scale = b_norm > 0.0 ? b_norm : max_diagonal_;             // m/s²
    const double rho = options_.direct.proximal * max_diagonal_;
    Interior v;
    start(lambda, v, lambda_scale, w_scale);
    const std::vector<char> dropped(fixed_.begin(), fixed_.end());
    const double mu_stop = options_.direct.interior_mu * scale_of(p_) * std::max(1.0, lambda_scale);
    // Stationarity only to the square root of that: the proximal term ρ and rounding hold it
    // near 1e-11 · scale on singular A, and the crossover settles the rest.
    const double r_stop = std::sqrt(options_.direct.interior_mu) * scale_of(p_);
    v.r_d.resize(c);
    v.d.resize(c);
    v.rhs.resize(c);
    for (VecX* x : {&v.dz, &v.dy, &v.dz_aff, &v.dy_aff, &v.cdl, &v.cz, &v.cy}) x->resize(c);
    double r_before = std::numeric_limits<double>::infinity();  // the last iteration's residual
    for (int it = 0; it < options_.direct.max_interior; ++it) {
      newton_->times_A(lambda, v.w);
      v.w -= b_;
      double mu = 0.0;
      for (Eigen::Index k = 0; k < c; ++k) {
        v.r_d(k) = fixed_[std::size_t(k)] ? 0.0 : v.w(k) - v.z(k) + v.y(k);
        mu += v.s(k) * v.z(k) + v.t(k) * v.y(k);
      }
      mu /= std::max(bounds_, 1);
      const double r_norm = v.r_d.size() > 0 ? v.r_d.lpNorm<Eigen::Infinity>() : 0.0;
      if (!std::isfinite(mu) || !std::isfinite(r_norm)) break;
      // An interior point that already meets the tolerance needs no crossover.
      const double r_natural = natural_map_residual(v.w, lambda, p_.cmin, p_.cmax);
      if (may_stop(r_natural, r_before, options_.tolerance, floor(lambda))) {
        solved_ = true;
        break;
      }
      r_before = r_natural;
      if (mu <= mu_stop && r_norm <= r_stop) break;
      ++stats_.iterations;
      for (Eigen::Index k = 0; k < c; ++k) {
        v.d(k) = rho;
        if (lower_[std::size_t(k)]) v.d(k) += v.z(k) / v.s(k);
        if (upper_[std::size_t(k)]) v.d(k) += v.y(k) / v.t(k);
      }
      if (!factor(v.d, dropped)) break;
      double sigma = 0.0;
      if (!mehrotra(v, dropped, mu, sigma)) break;
      const double alpha = gondzio(v, dropped, sigma, mu);
      take_step(lambda, v, alpha);
    }
    suggest_partition(v, lambda_scale);
  }

  /// The starting point: λ at the box's centre (or lambda_scale inside a single bound), the
  /// slacks from it, each multiplier w_scale beyond what w at λ asks of it.
  void start(VecX& lambda, Interior& v, double lambda_scale, double w_scale) {
    const Eigen::Index c = A_.rows();
    const VecX& lo = p_.cmin;
    const VecX& hi = p_.cmax;
    v.s = VecX::Zero(c);
    v.t = VecX::Zero(c);
    v.z = VecX::Zero(c);
    v.y = VecX::Zero(c);
    lambda.resize(c);
    for (Eigen::Index k = 0; k < c; ++k) {
      const std::size_t K = std::size_t(k);
      if (fixed_[K]) {
        lambda(k) = lo(k);
      } else if (lower_[K] && upper_[K]) {
        lambda(k) = 0.5 * (lo(k) + hi(k));
      } else if (lower_[K]) {
        lambda(k) = lo(k) + lambda_scale;
      } else if (upper_[K]) {
        lambda(k) = hi(k) - lambda_scale;
      } else {
        lambda(k) = 0.0;
      }
      if (lower_[K]) v.s(k) = lambda(k) - lo(k);
      if (upper_[K]) v.t(k) = hi(k) - lambda(k);
    }
    newton_->times_A(lambda, v.w);
    v.w -= b_;
    for (Eigen::Index k = 0; k < c; ++k) {
      const std::size_t K = std::size_t(k);
      if (lower_[K]) v.z(k) = std::max(v.w(k), 0.0) + w_scale;
      if (upper_[K]) v.y(k) = std::max(-v.w(k), 0.0) + w_scale;
    }
  }

  /// Mehrotra's predictor (σ = 0) and corrector (centring σμ and his second-order term) on the
  /// factored system: the direction (dl, dz, dy) and σ; false when a solve fails.
  bool mehrotra(Interior& v, const std::vector<char>& dropped, double mu, double& sigma) {
    const Eigen::Index c = A_.rows();
    const VecX &s = v.s, &t = v.t, &z = v.z, &y = v.y;
    v.rhs = -v.r_d - z + y;
    if (!newton_solve(v.d, dropped, v.rhs, v.dl_aff)) return false;
    for (Eigen::Index k = 0; k < c; ++k) {
      v.dz_aff(k) = lower_[std::size_t(k)] ? -z(k) - z(k) / s(k) * v.dl_aff(k) : 0.0;
      v.dy_aff(k) = upper_[std::size_t(k)] ? -y(k) + y(k) / t(k) * v.dl_aff(k) : 0.0;
    }
    const double a_aff = step_length(s, t, z, y, v.dl_aff, v.dz_aff, v.dy_aff, 1.0);
    double mu_aff = 0.0;
    for (Eigen::Index k = 0; k < c; ++k) {
      if (lower_[std::size_t(k)])
        mu_aff += (s(k) + a_aff * v.dl_aff(k)) * (z(k) + a_aff * v.dz_aff(k));
      if (upper_[std::size_t(k)])
        mu_aff += (t(k) - a_aff * v.dl_aff(k)) * (y(k) + a_aff * v.dy_aff(k));
    }
    mu_aff /= std::max(bounds_, 1);
    sigma = std::pow(std::clamp(mu_aff / mu, 0.0, 1.0), 3);
    for (Eigen::Index k = 0; k < c; ++k) {
      v.rhs(k) = -v.r_d(k);
      if (lower_[std::size_t(k)]) {
        const double cl = sigma * mu - s(k) * z(k) - v.dl_aff(k) * v.dz_aff(k);
        v.rhs(k) += cl / s(k);
        v.dz(k) = cl;  // completed below
      }
      if (upper_[std::size_t(k)]) {
        const double cu = sigma * mu - t(k) * y(k) + v.dl_aff(k) * v.dy_aff(k);
        v.rhs(k) -= cu / t(k);
        v.dy(k) = cu;
      }
    }
    if (!newton_solve(v.d, dropped, v.rhs, v.dl)) return false;
    for (Eigen::Index k = 0; k < c; ++k) {
      v.dz(k) = lower_[std::size_t(k)] ? (v.dz(k) - z(k) * v.dl(k)) / s(k) : 0.0;
      v.dy(k) = upper_[std::size_t(k)] ? (v.dy(k) + y(k) * v.dl(k)) / t(k) : 0.0;
    }
    return true;
  }

  /// Gondzio's centrality correctors on the direction: the factor is the cost here, a solve is
  /// cheap, so each corrector that lengthens the step saves part of an iteration. The step
  /// length along the (corrected) direction.
  double gondzio(Interior& v, const std::vector<char>& dropped, double sigma, double mu) {
    const Eigen::Index c = A_.rows();
    const VecX &s = v.s, &t = v.t, &z = v.z, &y = v.y;
    double alpha = step_length(s, t, z, y, v.dl, v.dz, v.dy, kStepToBoundary);
    for (int corrector = 0; corrector < kCorrectors && alpha < 1.0; ++corrector) {
      const double reach = std::min(1.0, kCorrectorAspiration * alpha);
      const double low = kCorrectorBand * sigma * mu, high = sigma * mu / kCorrectorBand;
      const auto target = [&](double x) {  // the move of a product x towards [low, high]
        return std::max(std::clamp(x, low, high) - x, -high);
      };
      for (Eigen::Index k = 0; k < c; ++k) {
        const std::size_t K = std::size_t(k);
        v.rhs(k) = 0.0;
        v.cz(k) = lower_[K] ? target((s(k) + reach * v.dl(k)) * (z(k) + reach * v.dz(k))) : 0.0;
        v.cy(k) = upper_[K] ? target((t(k) - reach * v.dl(k)) * (y(k) + reach * v.dy(k))) : 0.0;
        if (lower_[K]) v.rhs(k) += v.cz(k) / s(k);
        if (upper_[K]) v.rhs(k) -= v.cy(k) / t(k);
      }
      if (!newton_solve(v.d, dropped, v.rhs, v.dc)) break;
      for (Eigen::Index k = 0; k < c; ++k) {
        const std::size_t K = std::size_t(k);
        v.cdl(k) = v.dl(k) + v.dc(k);
        v.cz(k) = lower_[K] ? v.dz(k) + (v.cz(k) - z(k) * v.dc(k)) / s(k) : 0.0;
        v.cy(k) = upper_[K] ? v.dy(k) + (v.cy(k) + y(k) * v.dc(k)) / t(k) : 0.0;
      }
      const double corrected = step_length(s, t, z, y, v.cdl, v.cz, v.cy, kStepToBoundary);
      if (!(corrected >= alpha + kCorrectorGain * (reach - alpha))) break;
      alpha = corrected;
      v.dl.swap(v.cdl);
      v.dz.swap(v.cz);
      v.dy.swap(v.cy);
    }
    return alpha;
  }

  /// λ, the slacks and the multipliers a step alpha along the direction.
  void take_step(VecX& lambda, Interior& v, double alpha) const {
    for (Eigen::Index k = 0; k < lambda.size(); ++k) {
      if (fixed_[std::size_t(k)]) continue;
      lambda(k) += alpha * v.dl(k);
      if (lower_[std::size_t(k)]) {
        v.s(k) += alpha * v.dl(k);
        v.z(k) += alpha * v.dz(k);
      }
      if (upper_[std::size_t(k)]) {
        v.t(k) -= alpha * v.dl(k);
        v.y(k) += alpha * v.dy(k);
      }
    }
  }

  /// The partition the interior point suggests: a row is at its bound when its multiplier
  /// outweighs its slack (z > A_kk s, units m/s² against kg⁻¹ N) or its slack is near 0.
  void suggest_partition(const Interior& v, double lambda_scale) {
    const Eigen::Index c = A_.rows();
    const double near = kNearBound * lambda_scale;
    place_.assign(std::size_t(c), Place::Free);
    for (Eigen::Index k = 0; k < c; ++k) {
      const std::size_t K = std::size_t(k);
      if (fixed_[K])
        place_[K] = Place::Fixed;
      else if (lower_[K] && (v.z(k) > a_(k) * v.s(k) || v.s(k) <= near))
        place_[K] = Place::Lower;
      else if (upper_[K] && (v.y(k) > a_(k) * v.t(k) || v.t(k) <= near))
        place_[K] = Place::Upper;
    }
  }

  /// The longest step ≤ 1 (times `fraction` of the way to the boundary) keeping s, t, z, y ≥ 0.
  double step_length(const VecX& s,
                     const VecX& t,
                     const VecX& z,
                     const VecX& y,
                     const VecX& dl,
                     const VecX& dz,
                     const VecX& dy,
                     double fraction) const {
    double alpha = 1.0 / fraction;
    for (Eigen::Index k = 0; k < s.size(); ++k) {
      if (lower_[std::size_t(k)]) {
        if (dl(k) < 0.0) alpha = std::min(alpha, -s(k) / dl(k));
        if (dz(k) < 0.0) alpha = std::min(alpha, -z(k) / dz(k));
      }
      if (upper_[std::size_t(k)]) {
        if (dl(k) > 0.0) alpha = std::min(alpha, t(k) / dl(k));
        if (dy(k) < 0.0) alpha = std::min(alpha, -y(k) / dy(k));
      }
    }
    return std::min(1.0, fraction * alpha);
  }

  const BoxedProblem& p_;
  const SpMat& A_;
  const VecX& b_;
  const SolverOptions& options_;
  SolverSummary& stats_;
  std::vector<char> lower_, upper_, fixed_;
  VecX a_;  ///< A_kk (max A_kk where that is 0)
  int bounds_ = 0;
  double max_diagonal_ = 0.0;
  double row_sum_ = 0.0;  ///< max_i Σ_k |A_ik|, for the rounding floor
  std::shared_ptr<NewtonSystem> newton_;
  std::vector<Place> place_;
  bool solved_ = false;             ///< the interior point met the tolerance
  bool crossover_in_rows_ = false;  ///< the crossover factored A(F, F) (small islands)
  bool crossover_in_body_ = false;  ///< the crossover factored in body space (large islands)

 public:
  /// Where the crossover factored: "on A(F, F)", "in body space" or both.
  std::string crossover_space() const {
    if (crossover_in_rows_ && crossover_in_body_) return "on A(F, F) and in body space";
    return crossover_in_body_ ? "in body space" : "on A(F, F)";
  }
};

}  // namespace

double residual_floor(double row_sum, const VecX& b, const VecX& lambda) {
  const double l = lambda.size() > 0 ? lambda.lpNorm<Eigen::Infinity>() : 0.0;
  const double bn = b.size() > 0 ? b.lpNorm<Eigen::Infinity>() : 0.0;
  return 64.0 * kUnitRoundoff * (row_sum * l + bn);
}

bool may_stop(double r, double r_before, double tolerance, double floor) {
  if (r <= tolerance) return true;
  if (!(r <= floor)) return false;
  return tolerance == 0.0 || !(r < r_before);
}

double residual_floor(const BoxedProblem& problem, const VecX& lambda) {
  return residual_floor(max_abs_row_sum(problem.A), problem.b, lambda);
}

namespace {

/// A warm start (the last step's answer, carried by contact persistence): the crossover from its
/// partition, in body space where the problem has J and Minv, at most kWarmSteps proximal steps
/// and kWarmRounds pivoting rounds.
/// True, with s filled, when that reaches the tolerance; the interior point is then not needed.
bool warm_finish(const BoxedProblem& problem,
                 VecX& lambda,
                 const SolverOptions& options,
                 double row_sum,
                 SolverSummary& s) {
  SolverOptions o = options;
  o.direct.max_outer_iterations = kWarmSteps;
  const std::shared_ptr<NewtonSystem> newton =
      make_newton_system(problem, options.direct.memory.get());
  VecX x = lambda;
  FinishHints hints;
  hints.max_rounds = kWarmRounds;
  hints.row_sum = row_sum;
  const SolverSummary w = finish_active_set(problem, x, o, newton.get(), kCrossoverEpsilon, hints);
  if (w.termination != Termination::Direct) return false;
  lambda = x;
  s.residual = w.residual;
  s.islands = 1;
  s.space = newton->space();
  s.crossover = w.iterations;
  s.pivots = w.pivots;
  s.factorizations = w.factorizations + newton->factorizations();
  s.updates = newton->updates();
  s.factor_nnz = std::max(w.factor_nnz, newton->factor_nonzeros());
  std::ostringstream msg;
  msg << "direct (warm: the crossover from the guess's partition, " << s.space
      << " space): " << s.crossover << " proximal steps and " << s.pivots << " pivots, "
      << s.factorizations << " factorizations";
  s.message = msg.str();
  return true;
}

/// solve_direct on a problem without null rows (solve_around_null_rows).
SolverSummary solve_direct_coupled(const BoxedProblem& problem,
                                   VecX& lambda,
                                   const SolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Index n = problem.A.rows();
  SolverSummary s;
  if (lambda.size() != n) lambda = VecX::Zero(n);
  s.termination = Termination::Direct;
  // `known`: lambda's residual is already in s.residual (one pass over A saved).
  const auto finish = [&](const std::string& what, bool known = false) {
    if (!known) s.residual = natural_map_residual(problem, lambda);
    if (!std::isfinite(s.residual)) s.termination = Termination::NonFinite;
    s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::ostringstream msg;
    msg << what << ", residual " << s.residual << " N";
    s.message = msg.str();
    return s;
  };
  bool bounded = false;
  for (Eigen::Index k = 0; k < n && !bounded; ++k) {
    bounded = problem.cmin(k) != problem.cmax(k) &&
              (std::isfinite(problem.cmin(k)) || std::isfinite(problem.cmax(k)));
  }
  if (!bounded) {
    // No bounded row: one linear solve (the active-set path's all-unbounded case).
    s = solve_active_set(problem, lambda, options);
    s.message = "direct (no bounded rows): " + s.message;
    s.route = "linear";
    s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return s;
  }
  // The guess may already be the answer (a warm start on a resting scene): taken as it is at the
  // rounding floor, since solving again would only move λ by rounding (and a Coulomb fixed
  // point, which solves again from its last answer, would never settle).
  VecX guess = lambda;
  for (Eigen::Index k = 0; k < n; ++k)
    guess(k) = clamp(std::isfinite(guess(k)) ? guess(k) : 0.0, problem.cmin(k), problem.cmax(k));
  const bool warm_tried = !guess.isZero(0.0);
  const double row_sum = warm_tried ? max_abs_row_sum(problem.A) : 0.0;
  if (warm_tried) {
    s.residual = natural_map_residual(problem, guess);
    if (s.residual <= std::max(options.tolerance, residual_floor(row_sum, problem.b, guess))) {
      lambda = guess;
      s.islands = 1;
      s.route = "guess";
      return finish("direct: the guess already solves it", true);
    }
  }
  if (warm_tried && warm_finish(problem, guess, options, row_sum, s)) {
    lambda = guess;
    s.route = "warm";
    return finish(s.message, true);
  }
  if (n < options.direct.interior_from_rows) {
    // Few rows: the active-set path, exact to round-off where the free blocks are definite.
    s = solve_active_set(problem, lambda, options);
    s.message = "direct (few rows, active set): " + s.message;
    if (warm_tried) s.message += kWarmUnfinished;
    s.route = "active-set";
    s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return s;
  }
  SolverSummary inner;
  InteriorSolver solver(problem, options, inner);
  VecX x = lambda;
  const bool solved = solver.solve(x);
  s = inner;
  s.islands = 1;
  s.route = "interior";
  s.termination = solved ? Termination::Direct : Termination::NotConverged;
  lambda = x;
  std::ostringstream what;
  what << "direct (interior point, " << s.space << " space"
       << (s.space == "body" ? " M + Jt D^-1 J" : " A + D") << ", factor nnz " << s.factor_nnz
       << "): " << s.iterations << " interior iterations, crossover (" << solver.crossover_space()
       << ") " << s.crossover << " proximal steps and " << s.pivots << " pivots, "
       << s.factorizations << " factorizations";
  if (s.updates > 0) what << " and " << s.updates << " rows updated in a factor";
  if (warm_tried) what << kWarmUnfinished;
  // The rounding floor grows with ‖λ‖∞, so a λ driven off by inconsistent equality rows would
  // meet it: past 1e8 × λ's natural scale (|b_k| / A_kk, the finite bounds) it is no answer.
  double natural = 1.0;
  const VecX diagonal = problem.A.diagonal();
  for (Eigen::Index k = 0; k < n; ++k) {
    if (diagonal(k) > 0.0) natural = std::max(natural, std::abs(problem.b(k)) / diagonal(k));
    if (std::isfinite(problem.cmin(k))) natural = std::max(natural, std::abs(problem.cmin(k)));
    if (std::isfinite(problem.cmax(k))) natural = std::max(natural, std::abs(problem.cmax(k)));
  }
  if (s.termination == Termination::Direct && lambda.lpNorm<Eigen::Infinity>() > 1e8 * natural) {
    s.termination = Termination::NotConverged;
    what << "; lambda grew past 1e8 times its scale (inconsistent equality rows?)";
  }
  if (s.termination != Termination::Direct) what << "; stopped short of the tolerance";
  return finish(what.str());
}

}  // namespace

SolverSummary solve_direct(const BoxedProblem& problem,
                           VecX& lambda,
                           const SolverOptions& options) {
  SolverSummary s;
  if (!check_input(problem, "direct", s)) return s;
  // A row with no entry in A (j_c = 0) would make the Newton systems singular (CHOLMOD's
  // analysis of a block without entries fails): its lambda follows from b and its bounds.
  return solve_around_null_rows(problem, lambda, [&](const BoxedProblem& rest, VecX& lambda_R) {
    return solve_direct_coupled(rest, lambda_R, options);
  });
}

}  // namespace cbps
