// The exact path's interior point on one process's rows
// (interior_point.hpp). The method and its sources are described at solve_direct() in
// direct.hpp; what spans all rows goes through RowReduction.
#include "cbps/solvers/exact/interior_point.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include "cbps/solvers/exact/direct.hpp"
#include "cbps/system/boxed_problem.hpp"

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
/// Rows within this fraction of λ's scale (‖b‖∞ / max A_kk) of a bound start the crossover at
/// it: the active set frees wrong-signed rows all at once but blocks rows one at a time, so a
/// partition that errs towards the bound needs far fewer steps (pyramid base 20, measured when
/// every step was a factorization: 301 instead of 1,026).
constexpr double kNearBound = 1e-4;
/// The bulk crossover's first proximal ε, a fraction of max A_kk (direct.cpp's
/// kCrossoverEpsilon), and the factor it is reduced by (active_set.cpp's kEpsilonStep); its
/// active-set rounds per proximal step at most, and the refinement passes of each solve.
constexpr double kProximalEpsilon = 1e-6;
constexpr int kInnerRounds = 30;
constexpr int kRefinements = 2;
constexpr double kEpsilonStep = 10.0;
/// bulk_crossover: at most this many proximal steps past the first stop at the rounding floor
/// (a step there that did not lower the residual), while the partition moves or ε may fall.
constexpr int kFloorSteps = 10;
/// Rows whose bound the blocked step reaches within this fraction of their own step block too.
constexpr double kTie = 1e-3;

double max_abs(const VecX& x) { return x.size() > 0 ? x.lpNorm<Eigen::Infinity>() : 0.0; }

/// Whether options.deadline (SolverOptions::time_limit) has passed on any process: one
/// reduction, made only when a deadline is set, so that a solve without one makes the collective
/// calls it always made.
bool past_deadline_anywhere(const SolverOptions& options, const RowReduction& all) {
  if (options.deadline == std::chrono::steady_clock::time_point::max()) return false;
  return !all.all(!past_deadline(options));
}

/// The rows' bounds and the whole problem's sizes, as both methods here need them.
struct Bounds {
  Bounds(const InteriorRows& rows, const RowReduction& all) {
    const Eigen::Index c = rows.b.size();
    lower.assign(std::size_t(c), 0);
    upper.assign(std::size_t(c), 0);
    fixed.assign(std::size_t(c), 0);
    a = rows.diagonal;
    int count = 0;
    double largest = 0.0;
    for (Eigen::Index k = 0; k < c; ++k) {
      const std::size_t K = std::size_t(k);
      fixed[K] = rows.cmin(k) == rows.cmax(k);
      lower[K] = !fixed[K] && std::isfinite(rows.cmin(k));
      upper[K] = !fixed[K] && std::isfinite(rows.cmax(k));
      count += lower[K] + upper[K];
      largest = std::max(largest, a(k));
    }
    bounds = static_cast<int>(all.sum(count));
    max_diagonal = all.max(largest);
    if (!(max_diagonal > 0.0)) max_diagonal = 1.0;
    for (Eigen::Index k = 0; k < c; ++k)
      if (!(a(k) > 0.0)) a(k) = max_diagonal;  // for the crossover's λ − w/A_kk only
    b_norm = all.max(max_abs(rows.b));
  }
  std::vector<char> lower, upper, fixed;
  VecX a;  ///< A_kk (max A_kk where that is 0)
  int bounds = 0;
  double max_diagonal = 0.0;
  double b_norm = 0.0;  ///< ‖b‖∞ of the whole problem
};

/// Mehrotra's predictor-corrector on min ½ λᵀAλ − bᵀλ over the box, from the box's centre.
class InteriorPoint {
 public:
  InteriorPoint(const InteriorRows& rows,
                NewtonSystem& newton,
                const RowReduction& all,
                const SolverOptions& options)
      : rows_(rows), newton_(newton), all_(all), options_(options), k_(rows, all) {}

  InteriorOutcome run(VecX& lambda) {
    interior(lambda);
    return out_;
  }

 private:
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

  bool newton_solve(const VecX& r, VecX& x) {
    newton_.apply(r, x);
    return all_.all(x.allFinite());
  }

  bool factor(const VecX& d, const std::vector<char>& dropped) {
    const bool ok = newton_.factor(d, dropped);
    out_.factor_nnz = std::max(out_.factor_nnz, newton_.factor_nonzeros());
    return ok;
  }

  /// The rounding floor of the residual at lambda, N.
  double floor(const VecX& lambda) const {
    return residual_floor_of(rows_.row_sum, k_.b_norm, all_.max(max_abs(lambda)));
  }

  void interior(VecX& lambda) {
    const Eigen::Index c = rows_.b.size();
    const double lambda_scale = k_.b_norm > 0.0 ? k_.b_norm / k_.max_diagonal : 1.0;  // N
    const double w_scale = k_.b_norm > 0.0 ? k_.b_norm : k_.max_diagonal;             // m/s²
    const double rho = options_.direct.proximal * k_.max_diagonal;
    Interior v;
    start(lambda, v, lambda_scale, w_scale);
    const std::vector<char>& dropped = k_.fixed;
    const double mu_stop = options_.direct.interior_mu * rows_.scale * std::max(1.0, lambda_scale);
    // Stationarity only to the square root of that: the proximal term ρ and rounding hold it
    // near 1e-11 · scale on singular A, and the crossover settles the rest.
    const double r_stop = std::sqrt(options_.direct.interior_mu) * rows_.scale;
    v.r_d.resize(c);
    v.d.resize(c);
    v.rhs.resize(c);
    for (VecX* x : {&v.dz, &v.dy, &v.dz_aff, &v.dy_aff, &v.cdl, &v.cz, &v.cy}) x->resize(c);
    double r_before = std::numeric_limits<double>::infinity();  // the last iteration's residual
    for (int it = 0; it < options_.direct.max_interior; ++it) {
      // Past the deadline (SolverOptions::time_limit) on any process: the crossover from here.
      if (past_deadline_anywhere(options_, all_)) break;
      newton_.times_A(lambda, v.w);
      v.w -= rows_.b;
      double mu = 0.0;
      for (Eigen::Index k = 0; k < c; ++k) {
        v.r_d(k) = k_.fixed[std::size_t(k)] ? 0.0 : v.w(k) - v.z(k) + v.y(k);
        mu += v.s(k) * v.z(k) + v.t(k) * v.y(k);
      }
      mu = all_.sum(mu) / std::max(k_.bounds, 1);
      const double r_norm = all_.max(max_abs(v.r_d));
      if (!std::isfinite(mu) || !std::isfinite(r_norm)) break;
      // An interior point that already meets the tolerance needs no crossover.
      const double r_natural = all_.max(natural_map_residual(v.w, lambda, rows_.cmin, rows_.cmax));
      if (may_stop(r_natural, r_before, options_.tolerance, floor(lambda))) {
        out_.solved = true;
        break;
      }
      r_before = r_natural;
      if (mu <= mu_stop && r_norm <= r_stop) break;
      ++out_.iterations;
      for (Eigen::Index k = 0; k < c; ++k) {
        v.d(k) = rho;
        if (k_.lower[std::size_t(k)]) v.d(k) += v.z(k) / v.s(k);
        if (k_.upper[std::size_t(k)]) v.d(k) += v.y(k) / v.t(k);
      }
      if (!factor(v.d, dropped)) break;
      double sigma = 0.0;
      if (!mehrotra(v, mu, sigma)) break;
      const double alpha = gondzio(v, sigma, mu);
      take_step(lambda, v, alpha);
    }
    suggest_partition(v, lambda_scale);
  }

  /// The starting point: λ at the box's centre (or lambda_scale inside a single bound), the
  /// slacks from it, each multiplier w_scale beyond what w at λ asks of it.
  void start(VecX& lambda, Interior& v, double lambda_scale, double w_scale) {
    const Eigen::Index c = rows_.b.size();
    const VecX& lo = rows_.cmin;
    const VecX& hi = rows_.cmax;
    v.s = VecX::Zero(c);
    v.t = VecX::Zero(c);
    v.z = VecX::Zero(c);
    v.y = VecX::Zero(c);
    lambda.resize(c);
    for (Eigen::Index k = 0; k < c; ++k) {
      const std::size_t K = std::size_t(k);
      if (k_.fixed[K]) {
        lambda(k) = lo(k);
      } else if (k_.lower[K] && k_.upper[K]) {
        lambda(k) = 0.5 * (lo(k) + hi(k));
      } else if (k_.lower[K]) {
        lambda(k) = lo(k) + lambda_scale;
      } else if (k_.upper[K]) {
        lambda(k) = hi(k) - lambda_scale;
      } else {
        lambda(k) = 0.0;
      }
      if (k_.lower[K]) v.s(k) = lambda(k) - lo(k);
      if (k_.upper[K]) v.t(k) = hi(k) - lambda(k);
    }
    newton_.times_A(lambda, v.w);
    v.w -= rows_.b;
    for (Eigen::Index k = 0; k < c; ++k) {
      const std::size_t K = std::size_t(k);
      if (k_.lower[K]) v.z(k) = std::max(v.w(k), 0.0) + w_scale;
      if (k_.upper[K]) v.y(k) = std::max(-v.w(k), 0.0) + w_scale;
    }
  }

  /// Mehrotra's predictor (σ = 0) and corrector (centring σμ and his second-order term) on the
  /// factored system: the direction (dl, dz, dy) and σ; false when a solve fails.
  bool mehrotra(Interior& v, double mu, double& sigma) {
    const Eigen::Index c = rows_.b.size();
    const VecX &s = v.s, &t = v.t, &z = v.z, &y = v.y;
    const std::vector<char>&lower = k_.lower, &upper = k_.upper;
    v.rhs = -v.r_d - z + y;
    if (!newton_solve(v.rhs, v.dl_aff)) return false;
    for (Eigen::Index k = 0; k < c; ++k) {
      v.dz_aff(k) = lower[std::size_t(k)] ? -z(k) - z(k) / s(k) * v.dl_aff(k) : 0.0;
      v.dy_aff(k) = upper[std::size_t(k)] ? -y(k) + y(k) / t(k) * v.dl_aff(k) : 0.0;
    }
    const double a_aff = step_length(s, t, z, y, v.dl_aff, v.dz_aff, v.dy_aff, 1.0);
    double mu_aff = 0.0;
    for (Eigen::Index k = 0; k < c; ++k) {
      if (lower[std::size_t(k)])
        mu_aff += (s(k) + a_aff * v.dl_aff(k)) * (z(k) + a_aff * v.dz_aff(k));
      if (upper[std::size_t(k)])
        mu_aff += (t(k) - a_aff * v.dl_aff(k)) * (y(k) + a_aff * v.dy_aff(k));
    }
    mu_aff = all_.sum(mu_aff) / std::max(k_.bounds, 1);
    sigma = std::pow(std::clamp(mu_aff / mu, 0.0, 1.0), 3);
    for (Eigen::Index k = 0; k < c; ++k) {
      v.rhs(k) = -v.r_d(k);
      if (lower[std::size_t(k)]) {
        const double cl = sigma * mu - s(k) * z(k) - v.dl_aff(k) * v.dz_aff(k);
        v.rhs(k) += cl / s(k);
        v.dz(k) = cl;  // completed below
      }
      if (upper[std::size_t(k)]) {
        const double cu = sigma * mu - t(k) * y(k) + v.dl_aff(k) * v.dy_aff(k);
        v.rhs(k) -= cu / t(k);
        v.dy(k) = cu;
      }
    }
    if (!newton_solve(v.rhs, v.dl)) return false;
    for (Eigen::Index k = 0; k < c; ++k) {
      v.dz(k) = lower[std::size_t(k)] ? (v.dz(k) - z(k) * v.dl(k)) / s(k) : 0.0;
      v.dy(k) = upper[std::size_t(k)] ? (v.dy(k) + y(k) * v.dl(k)) / t(k) : 0.0;
    }
    return true;
  }

  /// Gondzio's centrality correctors on the direction: the factor is the cost here, a solve is
  /// cheap, so each corrector that lengthens the step saves part of an iteration. The step
  /// length along the (corrected) direction.
  double gondzio(Interior& v, double sigma, double mu) {
    const Eigen::Index c = rows_.b.size();
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
        v.cz(k) = k_.lower[K] ? target((s(k) + reach * v.dl(k)) * (z(k) + reach * v.dz(k))) : 0.0;
        v.cy(k) = k_.upper[K] ? target((t(k) - reach * v.dl(k)) * (y(k) + reach * v.dy(k))) : 0.0;
        if (k_.lower[K]) v.rhs(k) += v.cz(k) / s(k);
        if (k_.upper[K]) v.rhs(k) -= v.cy(k) / t(k);
      }
      if (!newton_solve(v.rhs, v.dc)) break;
      for (Eigen::Index k = 0; k < c; ++k) {
        const std::size_t K = std::size_t(k);
        v.cdl(k) = v.dl(k) + v.dc(k);
        v.cz(k) = k_.lower[K] ? v.dz(k) + (v.cz(k) - z(k) * v.dc(k)) / s(k) : 0.0;
        v.cy(k) = k_.upper[K] ? v.dy(k) + (v.cy(k) + y(k) * v.dc(k)) / t(k) : 0.0;
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
      const std::size_t K = std::size_t(k);
      if (k_.fixed[K]) continue;
      lambda(k) += alpha * v.dl(k);
      if (k_.lower[K]) {
        v.s(k) += alpha * v.dl(k);
        v.z(k) += alpha * v.dz(k);
      }
      if (k_.upper[K]) {
        v.t(k) -= alpha * v.dl(k);
        v.y(k) += alpha * v.dy(k);
      }
    }
  }

  /// The partition the interior point suggests: a row is at its bound when its multiplier
  /// outweighs its slack (z > A_kk s, units m/s² against kg⁻¹ N) or its slack is near 0.
  void suggest_partition(const Interior& v, double lambda_scale) {
    const Eigen::Index c = rows_.b.size();
    const double near = kNearBound * lambda_scale;
    std::vector<Place>& place = out_.place;
    place.assign(std::size_t(c), Place::Free);
    for (Eigen::Index k = 0; k < c; ++k) {
      const std::size_t K = std::size_t(k);
      if (k_.fixed[K])
        place[K] = Place::Fixed;
      else if (k_.lower[K] && (v.z(k) > k_.a(k) * v.s(k) || v.s(k) <= near))
        place[K] = Place::Lower;
      else if (k_.upper[K] && (v.y(k) > k_.a(k) * v.t(k) || v.t(k) <= near))
        place[K] = Place::Upper;
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
      if (k_.lower[std::size_t(k)]) {
        if (dl(k) < 0.0) alpha = std::min(alpha, -s(k) / dl(k));
        if (dz(k) < 0.0) alpha = std::min(alpha, -z(k) / dz(k));
      }
      if (k_.upper[std::size_t(k)]) {
        if (dl(k) > 0.0) alpha = std::min(alpha, t(k) / dl(k));
        if (dy(k) < 0.0) alpha = std::min(alpha, -y(k) / dy(k));
      }
    }
    return std::min(1.0, fraction * all_.min(alpha));
  }

  const InteriorRows& rows_;
  NewtonSystem& newton_;
  const RowReduction& all_;
  const SolverOptions& options_;
  const Bounds k_;
  InteriorOutcome out_;
};

}  // namespace

double residual_floor_of(double row_sum, double b_norm, double lambda_norm) {
  return 64.0 * kUnitRoundoff * (row_sum * lambda_norm + b_norm);
}

InteriorOutcome run_interior_point(const InteriorRows& rows,
                                   NewtonSystem& newton,
                                   const RowReduction& all,
                                   const SolverOptions& options,
                                   VecX& lambda) {
  return InteriorPoint(rows, newton, all, options).run(lambda);
}

namespace {

/// bulk_crossover's state and its named steps (interior_point.hpp describes the method).
class BulkCrossover {
 public:
  BulkCrossover(const InteriorRows& rows,
                NewtonSystem& newton,
                const RowReduction& all,
                const SolverOptions& options,
                std::vector<Place> place,
                VecX& lambda)
      : rows_(rows),
        newton_(newton),
        all_(all),
        options_(options),
        k_(rows, all),
        c_(rows.b.size()),
        place_(std::move(place)),
        lambda_(lambda),
        epsilon_(kProximalEpsilon * k_.max_diagonal),
        d_(VecX::Constant(c_, epsilon_)),
        dropped_(std::size_t(c_), 0),
        g_(c_),
        r_(c_),
        trial_(c_) {}

  CrossoverOutcome run() {
    at_place();
    const double epsilon_floor = options_.direct.epsilon_floor * k_.max_diagonal;
    for (;; ++out_.rounds) {
      // w at λ: the proximal step leaves it current unless putting rows at their bounds moved λ.
      if (any_stale()) update_w(lambda_, w_);
      w_stale_ = false;
      out_.residual = all_.max(natural_map_residual(w_, lambda_, rows_.cmin, rows_.cmax));
      const double floor = residual_floor_of(rows_.row_sum, k_.b_norm, all_.max(max_abs(lambda_)));
      if (may_stop(out_.residual, r_before_, options_.tolerance, floor)) {
        // At the floor, a step that did not lower the residual ends the crossover, unless the
        // partition is still moving or ε may still fall (a step contracts the error by about
        // ε/(σ + ε)): then up to kFloorSteps more steps, with a smaller ε once the partition
        // holds, keeping the best answer met at the floor whatever they give.
        if (!(out_.residual < best_residual_)) restore_best();
        const bool more = !(out_.residual <= options_.tolerance) && floor_steps_ < kFloorSteps &&
                          (!settled_ || epsilon_ > epsilon_floor);
        if (!more) return solved();
        ++floor_steps_;
        best_lambda_ = lambda_;
        best_residual_ = out_.residual;
        if (settled_) {
          epsilon_ = std::max(epsilon_ / kEpsilonStep, epsilon_floor);
          d_.setConstant(epsilon_);
          refactor_ = true;
        }
      } else if (out_.rounds >= options_.direct.max_outer_iterations ||
                 !std::isfinite(out_.residual) || past_deadline_anywhere(options_, all_)) {
        return best_residual_ < kInf ? (restore_best(), solved()) : out_;
      }
      // Proximal steps contract the error by about ε/(σ + ε) for an eigenvalue σ of the free
      // block: once the partition holds and a step no longer halves the residual, a smaller ε.
      if (settled_ && out_.residual > 0.5 * r_before_ && epsilon_ > epsilon_floor) {
        epsilon_ = std::max(epsilon_ / kEpsilonStep, epsilon_floor);
        d_.setConstant(epsilon_);
        refactor_ = true;
      }
      r_before_ = out_.residual;
      if (!proximal_step()) return best_residual_ < kInf ? (restore_best(), solved()) : out_;
    }
  }

 private:
  CrossoverOutcome solved() {
    out_.solved = true;
    return out_;
  }

  /// Back to the best answer met at the floor, if it is better than λ.
  void restore_best() {
    if (!(best_residual_ < out_.residual) && std::isfinite(out_.residual)) return;
    lambda_ = best_lambda_;
    out_.residual = best_residual_;
    w_stale_ = true;
  }

  /// Whether any process's λ moved since w was formed: w_stale_ is set by each process for its
  /// own rows (at_place), and update_w's product with A is collective, so every process must
  /// take the same branch. (Without this reduction, one rank formed w while the other went on to
  /// factor: `mpirun -n 2 cbps lcp FOLDER --solver direct` on the base-20 pyramid after 60 steps
  /// hung, each rank waiting in a different collective call.)
  bool any_stale() const { return !all_.all(!w_stale_); }

  /// w = A x − b.
  void update_w(const VecX& x, VecX& w) const {
    newton_.times_A(x, w);
    w -= rows_.b;
  }

  /// Bound rows to their bounds, dropped rows from the places; true when any rank's dropped
  /// rows changed.
  bool at_place() {
    long changed = 0;
    for (Eigen::Index i = 0; i < c_; ++i) {
      const std::size_t K = std::size_t(i);
      const double at = place_[K] == Place::Lower || place_[K] == Place::Fixed ? rows_.cmin(i)
                        : place_[K] == Place::Upper                            ? rows_.cmax(i)
                                                                               : lambda_(i);
      if (at != lambda_(i)) {
        lambda_(i) = at;
        w_stale_ = true;
      }
      const char drop = place_[K] != Place::Free;
      changed += drop != dropped_[K];
      dropped_[K] = drop;
    }
    const bool any = all_.sum(static_cast<double>(changed)) > 0.0;
    refactor_ = refactor_ || any;
    return any;
  }

  /// This process's part of q(x) − q(λ) for the subproblem's q with g its gradient at λ and
  /// w_x = A x − b: gᵀδ + ½ δᵀ(w_x − w) + ε/2 |δ|², δ = x − λ, formed from the gradients
  /// (near the answer q's values differ by less than their rounding).
  double q_change(const VecX& x, const VecX& w_x) const {
    double change = 0.0;
    for (Eigen::Index i = 0; i < c_; ++i) {
      const double delta = x(i) - lambda_(i);
      change += g_(i) * delta + 0.5 * delta * (w_x(i) - w_(i)) + 0.5 * epsilon_ * delta * delta;
    }
    return change;
  }

  /// The proximal subproblem min q(x) = ½ xᵀAx − bᵀx + ε/2 |x − center|² over the box
  /// (strongly convex: its free block A_FF + ε I is definite), by a primal active-set method
  /// from x = center = λ, its gradient g = w + ε (x − center), at most kInnerRounds rounds.
  /// False when a factorization or a solve failed.
  bool proximal_step() {
    center_ = lambda_;
    release_one_ = false;
    settled_ = true;
    for (int inner = 0; inner < kInnerRounds; ++inner) {
      if (any_stale()) update_w(lambda_, w_);
      w_stale_ = false;
      for (Eigen::Index i = 0; i < c_; ++i) {
        g_(i) = w_(i) + epsilon_ * (lambda_(i) - center_(i));
        r_(i) = dropped_[std::size_t(i)] ? 0.0 : -g_(i);
      }
      if (refactor_ && !newton_.factor(d_, dropped_)) return false;
      refactor_ = false;
      const bool finite = newton_.solve(d_, dropped_, r_, dx_, kRefinements);
      if (!all_.all(finite)) return false;  // every rank's answer: the same return everywhere
      ++out_.steps;
      // The Newton step of the free rows, clamped into the box.
      long clamped = 0;
      for (Eigen::Index i = 0; i < c_; ++i) {
        trial_(i) = lambda_(i) + dx_(i);
        if (trial_(i) < rows_.cmin(i) || trial_(i) > rows_.cmax(i)) {
          trial_(i) = clamp(trial_(i), rows_.cmin(i), rows_.cmax(i));
          ++clamped;
        }
      }
      update_w(trial_, w_trial_);
      if (all_.sum(static_cast<double>(clamped)) == 0.0) {
        // A full step: λ minimises the subproblem on this face.
        lambda_.swap(trial_);
        w_.swap(w_trial_);
        if (!free_rows()) break;  // no bound row pulls inwards: the subproblem is solved
        continue;
      }
      block_rows();
    }
    return true;
  }

  /// After a full step: every bound row whose gradient pulls it inwards (g / A_kk > 0, N) is
  /// freed, or after a blocked step of length 0 only the worst (the serial crossover's rule,
  /// active_set.cpp: rows freed together may block each other at once again). False when none.
  bool free_rows() {
    const auto violation = [&](Eigen::Index i) {
      const std::size_t K = std::size_t(i);
      const double gi = w_(i) + epsilon_ * (lambda_(i) - center_(i));
      return place_[K] == Place::Lower   ? -gi / k_.a(i)
             : place_[K] == Place::Upper ? gi / k_.a(i)
                                         : 0.0;
    };
    double worst = 0.0;
    for (Eigen::Index i = 0; i < c_; ++i) worst = std::max(worst, violation(i));
    worst = all_.max(worst);
    if (!(worst > 0.0)) return false;
    long freed = 0;
    for (Eigen::Index i = 0; i < c_; ++i) {
      const double v = violation(i);
      if (v > 0.0 && (!release_one_ || v >= worst)) {
        place_[std::size_t(i)] = Place::Free;
        ++freed;
      }
    }
    out_.moved += static_cast<long>(all_.sum(static_cast<double>(freed)));
    at_place();
    settled_ = false;
    return true;
  }

  /// Rows past a bound. The clamped step (in trial_, w_trial_) is taken, the rows it clamps
  /// going to their bounds all at once, when it lowers q; otherwise the step stops at the first
  /// bound a row reaches (α ≤ 1 along a descent direction on this face: q falls), and the rows
  /// reaching theirs there (within kTie of their own step) block. Either way q falls, so the
  /// partitions never cycle.
  void block_rows() {
    if (all_.sum(q_change(trial_, w_trial_)) < 0.0) {
      lambda_.swap(trial_);
      w_.swap(w_trial_);
    } else {
      double alpha = 1.0;
      for (Eigen::Index i = 0; i < c_; ++i) {
        if (lambda_(i) + dx_(i) < rows_.cmin(i))
          alpha = std::min(alpha, (rows_.cmin(i) - lambda_(i)) / dx_(i));
        if (lambda_(i) + dx_(i) > rows_.cmax(i))
          alpha = std::min(alpha, (rows_.cmax(i) - lambda_(i)) / dx_(i));
      }
      alpha = std::max(all_.min(alpha), 0.0);
      release_one_ = release_one_ || alpha == 0.0;
      for (Eigen::Index i = 0; i < c_; ++i) {
        const double x = lambda_(i) + alpha * dx_(i);
        const double tie = kTie * std::abs(dx_(i));
        lambda_(i) = dx_(i) < 0.0 && x <= rows_.cmin(i) + tie   ? rows_.cmin(i)
                     : dx_(i) > 0.0 && x >= rows_.cmax(i) - tie ? rows_.cmax(i)
                                                                : x;
      }
      update_w(lambda_, w_);
    }
    long blocked = 0;
    for (Eigen::Index i = 0; i < c_; ++i) {
      const std::size_t K = std::size_t(i);
      if (place_[K] != Place::Free) continue;
      // Only rows moving out of the box block: after a step of 0, a row just freed at its
      // bound whose step points inwards stays free.
      if (k_.lower[K] && dx_(i) < 0.0 && lambda_(i) <= rows_.cmin(i))
        place_[K] = Place::Lower;
      else if (k_.upper[K] && dx_(i) > 0.0 && lambda_(i) >= rows_.cmax(i))
        place_[K] = Place::Upper;
      else
        continue;
      ++blocked;
    }
    out_.moved += static_cast<long>(all_.sum(static_cast<double>(blocked)));
    at_place();
    settled_ = false;
  }

  const InteriorRows& rows_;
  NewtonSystem& newton_;
  const RowReduction& all_;
  const SolverOptions& options_;
  const Bounds k_;
  const Eigen::Index c_;
  std::vector<Place> place_;
  VecX& lambda_;
  double epsilon_;  ///< the proximal ε, kg⁻¹
  VecX d_;          ///< ε on every row: the Newton system's diagonal
  std::vector<char> dropped_;
  VecX w_, g_, r_, dx_, center_, trial_, w_trial_;
  bool refactor_ = true;  ///< the partition or ε changed since the last factorization
  /// The best λ met at the rounding floor before ε fell again, and its residual (kInf: none).
  VecX best_lambda_;
  double best_residual_ = kInf;
  int floor_steps_ = 0;       ///< steps taken past a stop at the floor
  bool w_stale_ = true;       ///< λ moved since w_ = A λ − b was formed
  bool settled_ = false;      ///< the last proximal step moved no row
  bool release_one_ = false;  ///< a blocked step made no progress: free one row at a time
  double r_before_ = std::numeric_limits<double>::infinity();
  CrossoverOutcome out_;
};

}  // namespace

CrossoverOutcome bulk_crossover(const InteriorRows& rows,
                                NewtonSystem& newton,
                                const RowReduction& all,
                                const SolverOptions& options,
                                std::vector<Place> place,
                                VecX& lambda) {
  return BulkCrossover(rows, newton, all, options, std::move(place), lambda).run();
}

}  // namespace cbps
