// The exact path on friction cones (cone/cone_direct.hpp): an interior point on second-order
// cones for the convex relaxation, then proximal points around a semismooth Newton method, with
// the fixed point on De Saxcé's term between them for Coulomb's law. The stages, their sources
// and their parameters are described at solve_cone_direct().
#include "cbps/solvers/cone/cone_direct.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseLU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cbps/solvers/cone/nsgs.hpp"
#include "cbps/solvers/exact/cholmod_factor.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/system/cone_problem.hpp"
#include "cbps/system/unit_free.hpp"
#include "interior_system.hpp"

namespace cbps {

namespace {

/// The fraction of the way to the cones' boundary an interior step goes, and the centring
/// weight σ below which the relaxation's interior point is in its fast local phase, where the
/// fraction becomes 1 − gap (τ_k → 1, as in Mehrotra, SIAM J. Optim. 2(4) 1992, and Wright,
/// Primal-Dual Interior-Point Methods, SIAM 1997, ch. 11). A fixed 0.99 caps what one iteration
/// can gain at a factor 100 once σ ≈ 0 (cone pyramids of 400 and 1,600 contacts at rest: 8 and 9
/// iterations, 6 and 7 with 1 − gap). The refreshed interior point (Coulomb) keeps 0.99: its
/// right side moves with x, and on the piles settling under the paper's box 1 − gap lost it.
constexpr double kStepToBoundary = 0.99;
constexpr double kFastPhase = 1e-3;
/// Interior iterations at most (each one CHOLMOD factorization); the base-8 pyramid's 768 rows
/// reach their least residual in about 20.
constexpr int kMaxInterior = 80;
/// The interior point stops once its scaled duality gap and equation residuals are below this
/// (round-off of the scaled problem). Not before: where complementarity is not strict the
/// natural-map residual stays near the square root of the gap and falls only at its end
/// (base-5 pyramid: 1.0e-6 N from gap 1e-8 to 6e-12, 6.1e-8 N at 1.4e-14).
constexpr double kInteriorDone = 1e-14;
/// The proximal weight ε (scaled, max A'_kk = 1): it starts at kProximalWeight · the residual
/// and follows the residual down while each outer step halves it; an outer step that does not
/// multiplies it by 100, up to kLargestWeight. A small ε moves λ far per step but its Newton
/// systems are ill-conditioned near a singular A (base-8 pyramid: stuck at 3.5e-10 N with ε ≤
/// 1e-8); a large one converges linearly but surely (4e-6 took it to 6e-13 N in one step).
constexpr double kProximalWeight = 1e-2;
constexpr double kLargestWeight = 1e-4;
/// Newton steps per proximal subproblem at most, and the subproblem's stop: ‖F‖₂ below this
/// fraction of the outer residual.
constexpr int kMaxNewton = 30;
constexpr double kInnerFraction = 1e-3;
/// Stage 0's proximal points (quick_start) and stage 5's (proximal_points) also end a subproblem
/// after kSubproblemPatience Newton steps in a row that lower ‖F‖₂ by less than kSubproblemRate,
/// and move the proximal centre there: far from the answer the subproblem's steps crawl (Siconos'
/// OneObject-i1028-138, 69 rows, after 20 sweeps: 25 steps from 6e-2 to 3.6e-3 and the budget
/// spent; ended so after 3 steps, the next centres finish in 19 factorizations in all, 1.4 ms,
/// against 51 and 3.7 ms).
constexpr int kSubproblemPatience = 2;
constexpr double kSubproblemRate = 0.9;
/// Outer proximal steps at most per stage, and the count in a row without progress at
/// kLargestWeight that ends it.
constexpr int kMaxOuter = 60;
constexpr int kOuterStall = 5;
/// Factorizations (CHOLMOD and SparseLU) one solve may spend at most: every stage stops there.
/// The relaxation needs far fewer (pyramids of 36 to 1,600 contacts: 8 to 88); Coulomb's law
/// where it does not finish would otherwise go on for minutes (base-8 pyramid: 392 spent for
/// 4.6e-5 N).
constexpr int kMaxFactorizations = 300;
/// Where the stages above stall: rounds of NSGS sweeps then Newton's steps on Alart–Curnier's
/// function (sweeps_then_newton), at most kSweepRounds of kSweepsPerRound sweeps, with a budget
/// of kSweepFactorizations factorizations of their own.
constexpr int kSweepRounds = 10;
/// A start (the best point, zero) ends after this many rounds in a row that do not lower the
/// best residual by a tenth: the sweeps may dwell on a plateau for a round, then fall
/// (Capsules-i125-1213: 3.7e-6 N for 4,000 sweeps, then 1.2e-8 N), but where Coulomb's law has
/// no answer near (the paper's pyramids settling, RockPile) they only wander.
constexpr int kSweepStrikes = 2;
constexpr int kSweepsPerRound = 2000;
/// The sweeps' residual is measured after sweep k, then again after max(1, k / kSweepCheckEvery)
/// more (sweep).
constexpr int kSweepCheckEvery = 4;
constexpr int kSweepFactorizations = 100;
/// Stage 0, a cheap start under Coulomb's law (quick_start), in rounds: each round NSGS sweeps
/// on from the last round's sweeps, then Newton's steps on Alart–Curnier's function from their
/// answer with a budget of factorizations. On small problems (at most `rows`), where a
/// factorization costs a few sweeps, a short round first: a few sweeps suffice there for Newton's
/// steps to finish (Siconos' Rovers, 15 rows: 20 sweeps and 3 steps, 0.06 ms, against 0.18 ms
/// after 200 sweeps). Then a long one (Confeti-ex13: 180 sweeps, 7 ms, where the
/// interior point's stages took 0.56 s; the base-3 cone pyramid at rest). Where sweeps and
/// factorizations are dearer, short rounds that fail cost more than they save (with short rounds
/// at every size the pyramid, 108 rows, took 12 ms instead of 3.3 ms, and KaplasTower, 1,710
/// rows, 0.37 s instead of 0.27 s; best of 5 solves each).
struct QuickRound {
  int sweeps;
  int factorizations;
  Eigen::Index rows;  ///< the round runs on problems of at most this many rows
};
constexpr QuickRound kQuickRounds[] = {{20, 4, 128},
                                       {180, 8, std::numeric_limits<Eigen::Index>::max()}};
/// On problems of at most kQuickProximalRows rows, where a round's Newton steps stop short,
/// proximal points around them (proximal_newton on Alart–Curnier's function, as Siconos' PROX)
/// from the same sweeps, with a budget of kQuickProximal factorizations: where W is of low rank
/// Newton's matrix is singular at most points and Levenberg–Marquardt's steps crawl (Siconos'
/// OneObject, 72 rows, W of rank 6: 20 sweeps, 2 Newton steps and 9 proximal steps, 2 ms, where
/// the interior point's stages took 6 ms). On larger ones they cost more than they save
/// (BoxesStack1, 156 rows: 15 ms instead of 9; Capsules-i101-404, 675 rows, was left unsolved).
constexpr Eigen::Index kQuickProximalRows = 128;
constexpr int kQuickProximal = 25;
/// A solve from λ = 0 of more rows than this starts with the relaxation's interior point, stage
/// 0 only where that is not already the answer: there the sweeps and the row-space LU of
/// Newton's steps cost more than the interior point (body space on a folder) that finishes them
/// at rest (the base-20 cone pyramid at rest, 4,800 rows: 0.72 s with stage 0 first, 57 ms
/// without; the base-10 one 0.17 s, 12 ms; KaplasTower, 1,710 rows: 0.22 s, 25 ms). Below it
/// stage 0 goes first (Confeti-ex13, 321 rows: 6 ms, 0.53 s the other way round).
constexpr Eigen::Index kQuickFirstRows = 500;
/// The interior point with De Saxcé's term differentiated (differentiated_matrix): the
/// smoothing ε = kSmoothing √gap of ‖w_t‖ in its derivative, and the jam that ends it. On the
/// base-7 pile settling under the paper's box (196 contacts) it meets Coulomb's law in 72
/// iterations, 0.26 s, where the averaged fixed point took 17 s (kSmoothing 0.01: 62, 0.81 s;
/// 0.3 to 3 leave the base-10 pile short as 0.1 does).
constexpr double kSmoothing = 0.1;
constexpr double kJammedStep = 0.01;
constexpr int kJammedIterations = 5;
/// A tolerance in N below this many ulps of the force scale is read as a unit-free residual
/// (solve_cone_direct's `meets`).
constexpr double kUlpsOfForces = 1e3;
/// Newton steps on Alart–Curnier's function (Coulomb) at most, and the count in a row that do
/// not lower the law's residual by the fraction kNewtonProgress that ends them. Small: where the
/// answers are not isolated Levenberg–Marquardt's steps converge only linearly (Capsules-i101-404:
/// 2.8e-8 N to 6e-14 N in about 30 steps, some lowering it by a few per cent).
constexpr int kMaxAlartCurnier = 100;
constexpr int kAlartCurnierStall = 5;
constexpr double kNewtonProgress = 1e-3;
/// Where W is not symmetric, Newton's steps from the interior points hand over to proximal
/// points around them (run_stages) after kAlartCurnierStall steps in a row that lower the
/// residual by less than this fraction: there no fixed point on s follows them, and the proximal
/// term makes each subproblem regular where W is singular (Siconos' Capsules-i101-404: 101 steps,
/// 193 factorizations, from 1.7e-6 to 1.4e-8, then NSGS sweeps finished it, 0.21 s; handed over,
/// 0.053 s).
constexpr double kHandOverProgress = 0.1;
/// Stage 5 on a W that is not symmetric (proximal_points), after Siconos' PROX schedule: the
/// first proximal weight ε = kProximalSigma · r (scaled, r the centre's residual); after a
/// subproblem solved to kSubproblemFraction of its centre's residual, ε = max(σ r, ε /
/// kWeightDecrease), after one not solved (kMaxNewton steps, kSubproblemPatience slow ones, or no
/// step descends) 10 ε. PROX sets ε = σ r after every solved one; on Siconos' Capsules with every
/// mu halved that leaves the next subproblem unsolved, and ε swung between σ r and 100 σ r
/// without progress (Capsules-i101-404 stopped at 4.7e-8, unit-free); a quarter of the last ε
/// each time, never below σ r, solves the six of them, and with mu × 1/4, 3/4, 3/2, 2 and 3, for
/// any σ from 5e-4 to 5. PROX's σ = 5 is in W's own units, 5 / max W_kk in ours: 0.7 on the
/// Capsules (W_kk up to 7), 0.04 on OneObject (138). σ = 5 here left OneObject-i1028-138 with mu ×
/// 10 at 1.8e-6 (its first step raised the residual, and ε, tied to it, crawled at 1e-2 for 1,000
/// steps, where Siconos' PROX takes 36 steps from zero); 0.5 and below solve it.
constexpr double kProximalSigma = 0.05;
constexpr double kSubproblemFraction = 1e-2;
constexpr double kWeightDecrease = 4.0;
/// ... ended after kProximalPatience steps in a row that do not lower the best residual by a
/// tenth (the Capsules above: up to 378, Capsules-i122-1617 with mu halved, 2,453 factorizations
/// in all; each step moves the centre, and the residual may hold or rise for hundreds of steps on
/// the way), or at min(kProximalFactorizations, kAveragedWork / rows) factorizations of its own
/// (RockPile_tob1, 1,389 rows: 913 steps, 5,268 factorizations in all, 15 s, from 9.7e-6 to
/// 3.3e-6, unit-free).
constexpr int kProximalPatience = 1000;
constexpr int kProximalFactorizations = 5000;
/// Where A is symmetric and the averaged fixed point (stage 5) stops short, proximal_points
/// follows it from its best point, at most kFallbackWork / rows factorizations of its own (5,000
/// up to 600 rows, 2,500 at 1,200, 625 at 4,800). Its steps move the centre where the averaged
/// rounds hover (the card house of `cbps scenes card-house` at step 30, written by `cbps
/// matrices card-house --step 30 --fclib F --cone coulomb`, 60 contacts, mu per contact drawn in
/// [0.3, 0.8] with numpy's default_rng(1): the rounds ended at a unit-free 3.7e-7, the proximal
/// steps after them at 1.8e-11, 127 steps, 0.6 s, where Siconos' PROX from zero takes 5 s).
constexpr double kFallbackWork = 3e6;
/// Rounds of the fixed point on s = mu ‖u_t‖ (Coulomb) at most.
constexpr int kMaxFixedPoint = 20;
/// Stage 5, the averaged fixed point (averaged_fixed_point): its first weight a, its rounds at
/// most, the factorizations it may spend of its own, and the rounds in a row that do not halve the
/// best Coulomb residual after which it stops. On the base-10 pile settling under the paper's
/// box the plain rounds (a = 1) wander between 7e-5 and 4e-4 N; averaged, with each round's CCP
/// solved from scratch, a = 1/4, 1/2 and 0.7 reached unit-free residuals of 3.4e-8 (round
/// 177), 4.8e-9 and 1.5e-9 (round 200).
constexpr double kAveragedWeight = 0.7;
/// Each round's CCP is solved to this fraction of the best Coulomb residual so far.
constexpr double kAveragedInner = 0.01;
constexpr int kAveragedRounds = 2000;
constexpr int kAveragedFactorizations = 40000;
/// ... and at most this many rows times factorizations (a factorization's cost grows with the
/// rows): 25,000 factorizations at 1,200 rows (the base-10 pile's rounds took 21,700, 97 s),
/// 6,250 at 4,800 (the base-20 pile's: about 4 minutes in row space).
constexpr double kAveragedWork = 3e7;
constexpr int kAveragedStall = 150;
/// Where the rounds cycle, kCycleRounds in a row with a Coulomb residual above kCycleRatio times
/// the rounds' least, the weight halves (down to kSmallestWeight) and the rounds go on from that
/// least one. Measured before stage 3's differentiated interior point, which now finishes that
/// pile first: on the base-7 pile settling under the paper's box (196 contacts) a = 0.7 reached a
/// scaled residual of 8.4e-7 by round 55, then cycled (3 to 9 times that) until the stall rule
/// ended it at round 199 (unit-free 8.1e-10); halved to 0.35 at round 77, the rounds reached
/// 7.8e-11 by round 229 and met the target (Python, every CCP solved to 1e-10: a = 0.4 cycles with
/// period 2, a = 0.2 converges, to a unit-free 9.6e-12 in 386 rounds). The halved weight does not
/// help where the rounds' least point repels them (a pyramid of base 5, mu = 0.8, at step 5: from
/// it the rounds drift away at every weight down to 0.0875); there the stall rule ends them as
/// before.
constexpr double kCycleRatio = 3.0;
constexpr int kCycleRounds = 15;
constexpr double kSmallestWeight = 0.08;
/// Each time the rounds' least residual falls below kNewtonAgain times where Newton's steps on
/// Alart–Curnier's function last started (the best point of stages 1 to 4 at first), those steps
/// run again from the round, with kAveragedNewton factorizations: from the rounds' points they
/// lower the residual 3 to 20 times where they stalled from stages 1 to 4's best (base-7 pile,
/// before stage 3's differentiated interior point:
/// 1.9e-8 to 1.1e-9, then 1.9e-9 to 7.5e-11 scaled, which ends the stage at round 186 instead of
/// 229; base 4: 1.3e-10 to 2.8e-11).
constexpr double kNewtonAgain = 0.1;
constexpr int kAveragedNewton = 20;
/// Armijo's sufficient decrease and the smallest step tried.
constexpr double kArmijo = 1e-4;
constexpr double kSmallestStep = 1e-10;
/// Stage 6 (status_search): Newton runs on the equations of fixed contact statuses, at most
/// kStatusNewton steps each, Levenberg–Marquardt's weight kStatusWeight times GᵀG's largest
/// diagonal entry: the least-squares steps a singular A needs (a card house of 60 contacts, W of
/// rank 90 of 180, from stage 5's best point with contact 5 opened: 1.6e-16 unit-free in 6 steps;
/// with alart_curnier_step's ν = ‖F‖ the steps crept, 1.3e-4 after 100). Then, each in turn,
/// another status for the kStatusCandidates contacts whose equations the first run left
/// furthest from zero; at most min(kStatusFactorizations, kStatusWork / rows) factorizations.
constexpr int kStatusNewton = 20;
constexpr double kStatusWeight = 1e-12;
constexpr int kStatusCandidates = 8;
constexpr int kStatusFactorizations = 400;
constexpr double kStatusWork = 3e5;

using Constraint = ConeConstraint;

/// The scaling of the stages: md = max_k A_kk (kg⁻¹), bn = ‖b‖∞ (m/s²), each 1 where it is 0.
struct Scale {
  double md = 1.0;
  double bn = 1.0;
};
Scale stage_scale(const BoxedProblem& p) {
  double md = 0.0;
  for (Eigen::Index k = 0; k < p.rows(); ++k) md = std::max(md, p.A.coeff(k, k));
  const double bn = p.rows() > 0 ? p.b.lpNorm<Eigen::Infinity>() : 0.0;
  return {md > 0.0 ? md : 1.0, bn > 0.0 ? bn : 1.0};
}

/// The scaled problem and what every stage reads: A' = A / md, b' = b / bn, λ = (bn / md) x.
struct Setup {
  Eigen::Index c = 0;
  double md = 1.0;  ///< max A_kk, kg⁻¹
  double bn = 1.0;  ///< ‖b‖∞, m/s²
  SpMat A;          ///< A', every diagonal entry stored
  /// (A' + A'ᵀ)/2 where A is not symmetric (an FCLIB or Siconos W; empty otherwise): the matrix
  /// of the relaxation's interior point, a QP's, whose answer starts the stages that solve the
  /// law on A' itself (proximal Newton, Alart–Curnier's steps); every residual is A''s.
  SpMat A_sym;
  /// A'ᵀ where the problem carries A's rows apart (A not symmetric, BoxedProblem::A_rows): the
  /// rows the sweeps on the scaled problem read (sweep); empty otherwise.
  SpMat A_rows;
  /// Whether A is symmetric (A_sym empty): only then is the relaxation with De Saxcé's term held
  /// fixed a QP, whose w the fixed points on s (stages 3 and 5) are maps of.
  bool symmetric() const { return A_sym.size() == 0; }
  /// The matrix of the interior point's QP: A', or its symmetric part.
  const SpMat& qp() const { return symmetric() ? A : A_sym; }
  VecX b, cmin, cmax;
  std::vector<char> fixed;  ///< rows held at fixed_value (cmin = cmax, a mu = 0 contact's t1, t2)
  VecX fixed_value;
  FrictionContacts law;         ///< the problem's contacts and law
  FrictionContacts ccp;         ///< the same contacts under the convex relaxation
  std::vector<int> contact_at;  ///< row → contact owning it as its normal, −1 otherwise
  std::vector<char> in_cone;
  std::vector<Constraint> constraints;
  int entries = 0;                  ///< length of s and z
  VecX rho_row;                     ///< the box rows' Newton scaling 1/A'_kk
  std::vector<double> rho;          ///< each contact's 1/λmax(A'_αα)
  std::optional<BodyFactors> body;  ///< what body space reads, where the problem has it
  /// A problem in its simulator's units (SolverOptions::tolerance_unit_free): every residual
  /// the stages read is the unit-free residual's own natural map in x's units (`residual`),
  /// which no change of the units of force or velocity moves.
  bool unit_free = false;
  /// Each row's step of the unit-free residual in x's units, ρ'_k = md ρ_k (unit_free_steps: a
  /// contact's rows 1 / max A'_kk of them, a box row 1 / A'_kk), each at least 1.
  VecX rho_unit_free;

  /// A residual in N expressed in the units of x (the scaled λ): times md / bn.
  double in_x_units(double newtons) const { return newtons * md / bn; }
};

Setup make_setup(const BoxedProblem& p) {
  Setup S;
  S.body = body_factors(p);
  S.c = p.rows();
  const Eigen::Index c = S.c;
  const Scale scale = stage_scale(p);
  S.md = scale.md;
  S.bn = scale.bn;
  const double x_scale = S.md / S.bn;  // x = λ · md / bn
  std::vector<Triplet> t;
  t.reserve(std::size_t(p.A.nonZeros() + c));
  for (int j = 0; j < p.A.outerSize(); ++j)
    for (SpMat::InnerIterator it(p.A, j); it; ++it)
      t.emplace_back(int(it.row()), j, it.value() / S.md);
  for (Eigen::Index k = 0; k < c; ++k) t.emplace_back(int(k), int(k), 0.0);  // the diagonal
  S.A.resize(c, c);
  S.A.setFromTriplets(t.begin(), t.end());
  if (p.A_rows != nullptr) S.A_rows = SpMat(S.A.transpose());
  if (!p.symmetric && max_asymmetry(p.A) > symmetry_tolerance(p.A)) {
    S.A_sym = 0.5 * (S.A + SpMat(S.A.transpose()));
    S.body.reset();  // body space factors J Minv Jᵀ, which is symmetric: not this A
  }
  S.b = p.b / S.bn;
  S.rho_unit_free = unit_free_steps(p) * S.md;
  S.cmin = p.cmin * x_scale;
  S.cmax = p.cmax * x_scale;
  S.law = *p.cones;
  S.ccp = *p.cones;
  S.ccp.law = FrictionLaw::Relaxation;
  S.in_cone = S.law.rows_in_cones(c);
  S.contact_at.assign(std::size_t(c), -1);
  S.fixed.assign(std::size_t(c), 0);
  S.fixed_value = VecX::Zero(c);
  S.rho_row = VecX::Ones(c);
  for (long i = 0; i < S.law.contacts(); ++i) {
    const int n = S.law.normal[std::size_t(i)];
    S.contact_at[std::size_t(n)] = int(i);
    const double mu = S.law.mu(i);
    const Mat3 W = S.A.block(n, n, 3, 3).toDense();
    const double top =
        Eigen::SelfAdjointEigenSolver<Mat3>(0.5 * (W + W.transpose()), Eigen::EigenvaluesOnly)
            .eigenvalues()
            .maxCoeff();
    S.rho.push_back(top > 0.0 ? 1.0 / top : 1.0);
    Constraint k;
    k.row = n;
    k.at = S.entries;
    if (mu > 0.0) {
      k.cone = true;
      k.a = mu;
    } else {  // the ray: the normal's bound, the tangents fixed at 0
      S.fixed[std::size_t(n + 1)] = S.fixed[std::size_t(n + 2)] = 1;
    }
    S.constraints.push_back(k);
    S.entries += k.size();
  }
  for (Eigen::Index k = 0; k < c; ++k) {
    const std::size_t K = std::size_t(k);
    if (S.in_cone[K]) continue;
    const double a_kk = S.A.coeff(k, k);
    S.rho_row(k) = a_kk > 0.0 ? 1.0 / a_kk : 1.0;
    if (S.cmin(k) == S.cmax(k)) {
      S.fixed[K] = 1;
      S.fixed_value(k) = S.cmin(k);
      continue;
    }
    for (const double sign : {1.0, -1.0}) {
      const double bound = sign > 0.0 ? S.cmin(k) : S.cmax(k);
      if (!std::isfinite(bound)) continue;
      S.constraints.push_back({int(k), S.entries, false, sign, bound});
      S.entries += 1;
    }
  }
  return S;
}

/// The law's natural-map residual (cone_problem.hpp) of the problem with right side b at x, all
/// scaled, in units of x: the problem's own residual (N) at λ = (bn / md) x times md / bn. (The
/// natural map of the scaled problem itself would weigh w by md against λ.) On a problem in its
/// simulator's units (S.unit_free), where a newton means nothing, the natural map of the
/// unit-free residual (unit_free.hpp) in x's units: each row's step ρ'_k = md ρ_k, so that it is
/// the unit-free residual's numerator times md / bn and reads the same in any units. (The
/// scaled problem's unit-step map, which 1a294df read here, is smaller by up to md = max A_kk in
/// the file's units than the map in those units, which the stages' proximal weights and stops
/// were measured on: Siconos' OneObject-i100000-499, md 138, lost its short path in stage 0, 173
/// factorizations where 22 do.)
double residual(const Setup& S, const FrictionContacts& cones, const VecX& b, const VecX& x) {
  if (S.unit_free)
    return natural_map_residual(
        VecX(S.rho_unit_free.cwiseProduct(S.A * x - b)), x, S.cmin, S.cmax, cones);
  const double alpha = S.bn / S.md;
  const VecX w = S.bn * (S.A * x - b);
  return natural_map_residual(w, alpha * x, alpha * S.cmin, alpha * S.cmax, cones) / alpha;
}

// The Jordan algebra of the second-order cone (and of R₊ for a bound), on a constraint's
// entries: x ∘ y = (xᵀy, x0 y1 + y0 x1); e = (1, 0, 0).
VecX jordan_product(const Setup& S, const VecX& x, const VecX& y) {
  VecX out(S.entries);
  for (const Constraint& k : S.constraints) {
    const int i = k.at;
    if (!k.cone) {
      out(i) = x(i) * y(i);
      continue;
    }
    out(i) = x.segment<3>(i).dot(y.segment<3>(i));
    out.segment<2>(i + 1) = x(i) * y.segment<2>(i + 1) + y(i) * x.segment<2>(i + 1);
  }
  return out;
}

/// True when v is strictly inside every constraint's cone in floating point (a positive bound, a
/// positive determinant v0² − ‖v1‖² with v0 > 0): where ∘'s inverse and the scaling exist.
bool strictly_inside(const Setup& S, const VecX& v) {
  for (const Constraint& k : S.constraints) {
    const int i = k.at;
    if (!(v(i) > 0.0)) return false;
    if (k.cone && !(v(i) * v(i) - v.segment<2>(i + 1).squaredNorm() > 0.0)) return false;
  }
  return true;
}

/// v with l ∘ v = r (l strictly inside the cones).
VecX jordan_divide(const Setup& S, const VecX& l, const VecX& r) {
  VecX v(S.entries);
  for (const Constraint& k : S.constraints) {
    const int i = k.at;
    if (!k.cone) {
      v(i) = r(i) / l(i);
      continue;
    }
    const double det = l(i) * l(i) - l.segment<2>(i + 1).squaredNorm();
    v(i) = (l(i) * r(i) - l.segment<2>(i + 1).dot(r.segment<2>(i + 1))) / det;
    v.segment<2>(i + 1) = (r.segment<2>(i + 1) - v(i) * l.segment<2>(i + 1)) / l(i);
  }
  return v;
}

/// The largest α ≥ 0 with x + α d in the cones (infinity when every ray stays inside).
double step_to_boundary(const Setup& S, const VecX& x, const VecX& d) {
  double alpha = std::numeric_limits<double>::infinity();
  for (const Constraint& k : S.constraints) {
    const int i = k.at;
    if (!k.cone) {
      if (d(i) < 0.0) alpha = std::min(alpha, -x(i) / d(i));
      continue;
    }
    // x0 + α d0 ≥ ‖x1 + α d1‖: the first positive root of (x + αd)'s determinant, or of x0 + α d0.
    const double qa = d(i) * d(i) - d.segment<2>(i + 1).squaredNorm();
    const double qb = x(i) * d(i) - x.segment<2>(i + 1).dot(d.segment<2>(i + 1));
    const double qc = x(i) * x(i) - x.segment<2>(i + 1).squaredNorm();
    if (d(i) < 0.0) alpha = std::min(alpha, -x(i) / d(i));
    if (std::abs(qa) > 0.0) {
      const double disc = qb * qb - qa * qc;
      if (disc >= 0.0) {
        const double root = std::sqrt(disc);
        for (const double r : {(-qb - root) / qa, (-qb + root) / qa})
          if (r > 0.0) alpha = std::min(alpha, r);
      }
    } else if (qb < 0.0) {
      alpha = std::min(alpha, -qc / (2.0 * qb));
    }
  }
  return alpha;
}

/// What the stages count, for the summary.
struct Counts {
  int interior = 0;
  int outer = 0;
  int factorizations = 0;
  long factor_nnz = 0;
  int rounds = 0;          ///< Coulomb's fixed-point rounds
  int alart_curnier = 0;   ///< Coulomb's Levenberg–Marquardt steps on Alart–Curnier's function
  int desaxce = 0;         ///< interior iterations with De Saxcé's term refreshed (Coulomb)
  int differentiated = 0;  ///< ... refreshed and differentiated
  /// Where the interior point's Newton systems were solved: "body" while all were, "row" once
  /// any was, "" before the first.
  std::string space;
  int body_factorizations = 0;  ///< interior factorizations in body space
  int sweeps = 0;               ///< NSGS sweeps (sweeps_then_newton)
  int averaged = 0;             ///< rounds of the averaged fixed point (Coulomb, stage 5)
  int halved = 0;               ///< times its weight halved
  int proximal_points = 0;      ///< steps of proximal_points (Coulomb, stage 5, W not symmetric)
  int status_runs = 0;          ///< Newton runs with the contacts' statuses fixed (stage 6)
  /// Stage 7's factorizations on W's symmetric part (counted apart: every other count is W's
  /// own), −1 where it did not run; whether it was reached and not run, W's skew part moving
  /// the law at the best point more than that point misses it by.
  int symmetric_part = -1;
  bool skew_too_large = false;
  int budget = kMaxFactorizations;  ///< factorizations the stages may spend
  /// SolverOptions::deadline: the stages stop at it as at their budget.
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  bool spent() const {
    return factorizations >= budget || std::chrono::steady_clock::now() >= deadline;
  }
};

/// E v − h (shift) or E v: each constraint's s of v (a bound's a (v_row − h), a cone's
/// (mu v_n, v_t1, v_t2)).
VecX E_times(const Setup& S, const VecX& v, bool shift) {
  VecX out(S.entries);
  for (const Constraint& k : S.constraints) {
    if (!k.cone) {
      out(k.at) = k.a * (v(k.row) - (shift ? k.h : 0.0));
    } else {
      out(k.at) = k.a * v(k.row);
      out.segment<2>(k.at + 1) = v.segment<2>(k.row + 1);
    }
  }
  return out;
}

/// Eᵀ v, zero on fixed rows.
VecX E_transpose(const Setup& S, const VecX& v) {
  VecX out = VecX::Zero(S.c);
  for (const Constraint& k : S.constraints) {
    out(k.row) += k.a * v(k.at);
    if (k.cone) out.segment<2>(k.row + 1) += v.segment<2>(k.at + 1);
  }
  for (Eigen::Index r = 0; r < S.c; ++r)
    if (S.fixed[std::size_t(r)]) out(r) = 0.0;
  return out;
}

/// The block-diagonal M (a constraint's 3×3 block, or its (0, 0) entry for a bound) times v.
VecX block_times(const Setup& S, const std::vector<Mat3>& M, const VecX& v) {
  VecX out(S.entries);
  for (std::size_t j = 0; j < S.constraints.size(); ++j) {
    const Constraint& k = S.constraints[j];
    if (k.cone)
      out.segment<3>(k.at) = M[j] * v.segment<3>(k.at);
    else
      out(k.at) = M[j](0, 0) * v(k.at);
  }
  return out;
}

/// The Nesterov–Todd scaling W (and W⁻¹) of interior s and z, W z = W⁻¹ s: for a bound
/// sqrt(s / z); for a cone η [w0, w1ᵀ; w1, I + w1 w1ᵀ / (1 + w0)] with w̄ from the normalised
/// s̄ = s / sqrt(det s), z̄ likewise: w̄ = (s̄ + J z̄) / (2γ), γ² = (1 + s̄ᵀz̄) / 2, J = diag(1, −1,
/// −1), η = (det s / det z)^¼ (det x = x0² − ‖x1‖²); W⁻¹ flips the sign of w1. False when s or z
/// has reached a cone's boundary in floating point (a zero bound or determinant): no scaling
/// exists.
bool nt_scaling(
    const Setup& S, const VecX& s, const VecX& z, std::vector<Mat3>& W, std::vector<Mat3>& Winv) {
  if (!strictly_inside(S, s) || !strictly_inside(S, z)) return false;
  for (std::size_t j = 0; j < S.constraints.size(); ++j) {
    const Constraint& k = S.constraints[j];
    const int i = k.at;
    if (!k.cone) {
      W[j] = Mat3::Zero();
      Winv[j] = Mat3::Zero();
      W[j](0, 0) = std::sqrt(s(i) / z(i));
      Winv[j](0, 0) = 1.0 / W[j](0, 0);
      continue;
    }
    const Vec3 sv = s.segment<3>(i), zv = z.segment<3>(i);
    const double sd = std::sqrt(sv(0) * sv(0) - sv.tail<2>().squaredNorm());
    const double zd = std::sqrt(zv(0) * zv(0) - zv.tail<2>().squaredNorm());
    const Vec3 sb = sv / sd, zb = zv / zd;
    const double g = std::sqrt((1.0 + sb.dot(zb)) / 2.0);
    Vec3 wb = sb;
    wb(0) += zb(0);
    wb.tail<2>() -= zb.tail<2>();
    wb /= 2.0 * g;
    const double eta = std::sqrt(sd / zd);
    Mat3 B = Mat3::Zero();
    B(0, 0) = wb(0);
    B.block<2, 2>(1, 1) =
        Eigen::Matrix2d::Identity() + wb.tail<2>() * wb.tail<2>().transpose() / (1.0 + wb(0));
    Mat3 Bi = B;
    B.block<1, 2>(0, 1) = wb.tail<2>().transpose();
    B.block<2, 1>(1, 0) = wb.tail<2>();
    Bi.block<1, 2>(0, 1) = -wb.tail<2>().transpose();
    Bi.block<2, 1>(1, 0) = -wb.tail<2>();
    W[j] = eta * B;
    Winv[j] = Bi / eta;
  }
  return true;
}

/// Stage 1: the interior point on the CCP of right side b (scaled), until its CCP residual meets
/// target(x) or the gap closes; returns the iterate of least CCP residual. The equations:
///   rx = A'x − b − Eᵀz,   rs = s − (E x − h),   λ = W z = W⁻¹ s,
///   (A' + EᵀW⁻²E) Δx = −rx + EᵀW⁻¹(λ \ r_λ + W⁻¹ rs),   Δs = E Δx − rs,
///   Δz = W⁻¹(λ \ r_λ − W⁻¹ Δs),
/// with r_λ = −λ∘λ (predictor) and −λ∘λ + σ gap e − (W⁻¹Δs_a)∘(W Δz_a) (corrector, σ = (gap_a /
/// gap)³). Δs from Δx keeps s − E x + h exact to rounding.
/// b with De Saxcé's term at x moved into it: b_n − mu ‖w_t‖ per contact, w = A'x − b, so
/// that the CCP of this right side has Coulomb's û = w + mu ‖w_t‖ e_n as its w at x.
VecX desaxce_right_side(const Setup& S, const VecX& b, const VecX& x) {
  const VecX w = S.A * x - b;
  VecX shifted = b;
  for (long i = 0; i < S.law.contacts(); ++i) {
    const int n = S.law.normal[std::size_t(i)];
    shifted(n) -= S.law.mu(i) * std::hypot(w(n + 1), w(n + 2));
  }
  return shifted;
}

/// How the interior point treats De Saxcé's term mu ‖w_t‖ (Coulomb's law): not at all (the
/// CCP of b), refreshed into b at every iterate and held fixed within it, or refreshed and
/// differentiated (differentiated_matrix).
enum class DeSaxce { Off, Refreshed, Differentiated };

/// The Newton matrix of the interior point with De Saxcé's term differentiated, at x (scaled):
/// the CCP's row_space_matrix (A' + Eᵀ W⁻² E + ρ I, interior_system.hpp) plus the derivative of
/// its residual's term mu ‖w_t‖_ε in each contact's normal row,
///   ∂/∂x mu ‖w_t‖_ε = mu (w_tᵀ / ‖w_t‖_ε) A'_t,   ‖w_t‖_ε = (‖w_t‖² + ε²)^½,  w = A'x − b,
/// smoothed by ε = kSmoothing √gap, which goes to 0 with the duality gap (the smoothing of
/// Chen & Mangasarian, Comput. Optim. Appl. 5, 1996, for ‖·‖ where a contact's w_t passes 0;
/// Kanzow's interior continuation, SIAM J. Matrix Anal. Appl. 17, 1996). The term makes the
/// matrix not symmetric: SparseLU factors it.
SpMat differentiated_matrix(const Setup& S,
                            const VecX& x,
                            const VecX& b,
                            const std::vector<Mat3>& Winv,
                            double rho,
                            double gap) {
  const auto kept = [&](Eigen::Index k) { return S.fixed[std::size_t(k)] == 0; };
  std::vector<Triplet> t;
  const VecX w = S.A * x - b;
  const double eps = kSmoothing * std::sqrt(std::max(gap, 0.0));
  for (long i = 0; i < S.law.contacts(); ++i) {
    const int n = S.law.normal[std::size_t(i)];
    const double norm = std::sqrt(w(n + 1) * w(n + 1) + w(n + 2) * w(n + 2) + eps * eps);
    if (!kept(n) || !(norm > 0.0)) continue;
    for (int d = 1; d <= 2; ++d) {  // row n + d of A' is its column (A' symmetric)
      const double f = S.law.mu(i) * w(n + d) / norm;
      for (SpMat::InnerIterator a(S.A, n + d); a; ++a)
        if (kept(a.row())) t.emplace_back(n, int(a.row()), f * a.value());
    }
  }
  SpMat G(S.c, S.c);
  G.setFromTriplets(t.begin(), t.end());
  return row_space_matrix(S.A, S.fixed, S.constraints, Winv, rho) + G;
}

/// The interior point's Newton matrix, factored and solved: InteriorSystem's (symmetric,
/// CHOLMOD, in body or row space), or, with De Saxcé's term differentiated, differentiated_matrix
/// (SparseLU). Every factorization goes into the counts, and so into the budget.
class InteriorNewton {
 public:
  InteriorNewton(const Setup& S, bool differentiated, Counts& counts)
      : S_(S),
        differentiated_(differentiated),
        counts_(counts),
        system_(S.qp(), S.md, S.fixed, S.constraints, S.body ? &*S.body : nullptr),
        factorizations_before_(counts.factorizations),
        body_before_(counts.body_factorizations) {}
  /// For the scalings W (Winv = W⁻¹) and ρ; x, b and gap for the term's derivative.
  bool factor(const VecX& x,
              const VecX& b,
              const std::vector<Mat3>& W,
              const std::vector<Mat3>& Winv,
              double rho,
              double gap) {
    bool ok = false;
    if (differentiated_) {
      lu_.compute(differentiated_matrix(S_, x, b, Winv, rho, gap));
      ++lu_factorizations_;
      ok = lu_.info() == Eigen::Success;
    } else {
      ok = system_.factor(W, Winv, rho);
    }
    tally();
    return ok;
  }
  bool solve(const VecX& r, VecX& dx) {
    bool ok = true;
    if (differentiated_) {
      dx = lu_.solve(r);
      ok = dx.allFinite();
    } else {
      ok = system_.solve(r, dx);  // may move to row space and factor there
    }
    tally();
    return ok;
  }

 private:
  void tally() {
    counts_.factorizations = factorizations_before_ + system_.factorizations() + lu_factorizations_;
    counts_.body_factorizations = body_before_ + system_.body_factorizations();
    counts_.factor_nnz = std::max(counts_.factor_nnz, system_.factor_nonzeros());
    if (counts_.space != "row") counts_.space = system_.space();
  }
  const Setup& S_;
  bool differentiated_;
  Counts& counts_;
  InteriorSystem system_;
  Eigen::SparseLU<SpMat> lu_;  // the differentiated matrix, which is not symmetric
  int lu_factorizations_ = 0;
  int factorizations_before_, body_before_;
};

/// With `term` Refreshed (Coulomb's law), the CCP's right side is b with De Saxcé's term moved into
/// it at every iterate, b_n − mu ‖w_t‖ at the current x (so that its w is Coulomb's û), the iterate
/// judged and kept by Coulomb's residual of b: on piles settling under the paper's box, whose
/// answers have contacts opening, sticking and sliding at 1e-9 m/s, this reaches Coulomb's law
/// where the fixed point below, which moves s only between whole CCP solves, stalls
/// (docs/cones.md). With `term` Differentiated the Newton matrix carries the term's derivative
/// too (differentiated_matrix), and the iterations stop once kJammedIterations in a row step
/// less than kJammedStep of the way (the term's derivative can point the direction out of the
/// cones: the base-10 pile jams so at a residual of 3e-3 N).
VecX interior(const Setup& S,
              const VecX& b_in,
              double proximal,
              const std::function<double(const VecX&)>& target,
              Counts& counts,
              DeSaxce term = DeSaxce::Off) {
  const bool desaxce = term != DeSaxce::Off;
  int jammed = 0;  // iterations in a row of a step below kJammedStep
  VecX b = b_in;   // the right side of this iteration's CCP
  const auto refresh = [&](const VecX& at) {
    if (desaxce) b = desaxce_right_side(S, b_in, at);
  };
  const auto judged = [&](const VecX& at) {
    return desaxce ? residual(S, S.law, b_in, at) : residual(S, S.ccp, b, at);
  };
  const Eigen::Index c = S.c;
  const int m = int(S.constraints.size());
  VecX x = VecX::Zero(c);
  for (Eigen::Index k = 0; k < c; ++k)
    if (S.fixed[std::size_t(k)]) x(k) = S.fixed_value(k);
  if (m == 0) return x;
  VecX e = VecX::Zero(S.entries);
  for (const Constraint& k : S.constraints) e(k.at) = 1.0;
  VecX s = e, z = e;  // the cones' axes
  std::vector<Mat3> W(S.constraints.size()), Winv(S.constraints.size());
  InteriorNewton newton(S, term == DeSaxce::Differentiated, counts);
  VecX best = x;
  double best_r = judged(x);
  for (int it = 0; it < kMaxInterior; ++it) {
    refresh(x);
    VecX rx = S.qp() * x - b - E_transpose(S, z);
    for (Eigen::Index k = 0; k < c; ++k)
      if (S.fixed[std::size_t(k)]) rx(k) = 0.0;
    const VecX rs = s - E_times(S, x, true);
    const double gap = s.dot(z) / m;
    if (!std::isfinite(gap) || !rx.allFinite()) break;
    if (gap <= kInteriorDone && rx.lpNorm<Eigen::Infinity>() <= kInteriorDone &&
        rs.lpNorm<Eigen::Infinity>() <= kInteriorDone)
      break;
    if (counts.spent()) break;
    if (!nt_scaling(S, s, z, W, Winv)) break;  // on a boundary: the best iterate stands
    const VecX lam = block_times(S, W, z);
    if (!strictly_inside(S, lam)) break;  // rounding put λ on a boundary: no direction
    bool ok = newton.factor(x, b_in, W, Winv, proximal, gap);
    if (!ok) break;
    ++counts.interior;
    auto direction = [&](const VecX& r_lambda, VecX& dx, VecX& ds, VecX& dz) {
      const VecX tv = jordan_divide(S, lam, r_lambda);
      VecX rhs = -rx + E_transpose(S, block_times(S, Winv, tv + block_times(S, Winv, rs)));
      for (Eigen::Index k = 0; k < c; ++k)
        if (S.fixed[std::size_t(k)]) rhs(k) = 0.0;
      ok = ok && newton.solve(rhs, dx);
      if (!ok) return;
      ds = E_times(S, dx, false) - rs;
      dz = block_times(S, Winv, tv - block_times(S, Winv, ds));
    };
    VecX dx, ds, dz;
    const VecX ll = jordan_product(S, lam, lam);
    direction(-ll, dx, ds, dz);
    if (!ok) break;
    const double a_aff = std::min({1.0, step_to_boundary(S, s, ds), step_to_boundary(S, z, dz)});
    const double gap_aff = (s + a_aff * ds).dot(z + a_aff * dz) / m;
    const double sigma = std::pow(std::max(gap_aff, 0.0) / gap, 3.0);
    const VecX corrector = jordan_product(S, block_times(S, Winv, ds), block_times(S, W, dz));
    direction(-ll + sigma * gap * e - corrector, dx, ds, dz);
    if (!ok) break;
    // The fraction of the way to the boundary: kStepToBoundary, or 1 − gap once the affine step
    // is nearly full on the relaxation (its fast local phase).
    const double tau =
        !desaxce && sigma < kFastPhase ? std::max(kStepToBoundary, 1.0 - gap) : kStepToBoundary;
    const double alpha =
        std::min(1.0, tau * std::min(step_to_boundary(S, s, ds), step_to_boundary(S, z, dz)));
    if (!(alpha > 0.0)) break;
    if (term == DeSaxce::Differentiated) {  // stopped where its steps jam
      jammed = alpha < kJammedStep ? jammed + 1 : 0;
      if (jammed >= kJammedIterations) break;
    }
    x += alpha * dx;
    s += alpha * ds;
    z += alpha * dz;
    const double r = judged(x);
    if (r < best_r) {
      best_r = r;
      best = x;
    }
    if (r <= target(x)) break;
  }
  return best;
}

/// Alart & Curnier's function of one contact under Coulomb's law (Alart & Curnier, Comput.
/// Methods Appl. Mech. Engrg. 92, 1991; the NSN-AC of Siconos), with u = w the contact's rows of
/// A r − b and rho > 0:
///   F_n = r_n − max(0, r_n − rho u_n),   F_t = r_t − P_D(y),   y = r_t − rho u_t,
/// P_D the projection onto the disc of radius R = mu max(0, r_n − rho u_n). F = 0 exactly where
/// De Saxcé's form holds (a closed contact has u_n = 0, so û = u + mu ‖u_t‖ e_n meets the same
/// conditions), but u_t enters linearly: no kink at u_t = 0, where a contact sticks or slides
/// slowly. Dm and Cm: its generalized Jacobian is Dm + Cm A (per contact, 3×3 each).
Vec3 alart_curnier_map(const Vec3& r, const Vec3& u, double mu, double rho, Mat3& Dm, Mat3& Cm) {
  Dm.setZero();
  Cm.setZero();
  const double xn = r(0) - rho * u(0);
  const double a = xn > 0.0 ? 1.0 : 0.0;  // normal closed
  const double radius = mu * std::max(0.0, xn);
  const Eigen::Vector2d y = r.tail<2>() - rho * u.tail<2>();
  const double ny = y.norm();
  Vec3 F;
  F(0) = r(0) - std::max(0.0, xn);
  Dm(0, 0) = 1.0 - a;
  Cm(0, 0) = a * rho;
  if (ny <= radius) {  // sticking: F_t = rho u_t
    F.tail<2>() = r.tail<2>() - y;
    Cm.bottomRightCorner<2, 2>() = rho * Eigen::Matrix2d::Identity();
    return F;
  }
  const Eigen::Vector2d e = y / ny;  // sliding (or open: radius 0)
  F.tail<2>() = r.tail<2>() - radius * e;
  const Eigen::Matrix2d Q = (radius / ny) * (Eigen::Matrix2d::Identity() - e * e.transpose());
  Dm.bottomRightCorner<2, 2>() = Eigen::Matrix2d::Identity() - Q;
  Dm.bottomLeftCorner<2, 1>() = -mu * a * e;
  Cm.bottomRightCorner<2, 2>() = rho * Q;
  Cm.bottomLeftCorner<2, 1>() = mu * a * rho * e;
  return F;
}

/// Problems of at most this many rows take the Newton steps below with dense matrices: there the
/// sparse LU's analysis and the sparse product C A cost more than the arithmetic (a 72×72 matrix
/// with every entry stored, as Siconos' OneObject's W: an LU 28 µs dense, 75 µs by SparseLU).
constexpr Eigen::Index kDenseRows = 128;

/// Newton's matrix G = Dm + Cm A_eps of natural_map_newton (Dm and Cm block-diagonal: a 3×3 block
/// per contact, 1×1 per other row, given as triplets) and its factorizations: Eigen's SparseLU
/// (one analysis: the pattern never changes) and CHOLMOD for Levenberg–Marquardt's GᵀG + ν I,
/// or, on a problem of at most kDenseRows rows, LU with partial pivoting and LLᵀ.
class NewtonMatrix {
 public:
  explicit NewtonMatrix(Eigen::Index c) : c_(c), dense_(c <= kDenseRows) {}

  void assemble(const std::vector<Triplet>& dt,
                const std::vector<Triplet>& ct,
                const SpMat& A_eps) {
    if (!dense_) {
      SpMat Dm(c_, c_), Cm(c_, c_);
      Dm.setFromTriplets(dt.begin(), dt.end());
      Cm.setFromTriplets(ct.begin(), ct.end());
      sparse_ = Dm + SpMat(Cm * A_eps);
      return;
    }
    const MatX A = A_eps;
    dense_G_.setZero(c_, c_);
    for (const Triplet& t : ct)
      if (t.value() != 0.0) dense_G_.row(t.row()) += t.value() * A.row(t.col());
    for (const Triplet& t : dt) dense_G_(t.row(), t.col()) += t.value();
  }

  /// LU of G; false where a pivot is zero (G singular in floating point).
  bool factor() {
    if (dense_) {
      dense_lu_.compute(dense_G_);
      return dense_lu_.matrixLU().diagonal().cwiseAbs().minCoeff() > 0.0;
    }
    if (!analysed_) {
      sparse_lu_.analyzePattern(sparse_);
      analysed_ = true;
    }
    sparse_lu_.factorize(sparse_);
    return sparse_lu_.info() == Eigen::Success;
  }
  /// G⁻¹ r with the last factor().
  VecX solve(const VecX& r) const {
    return dense_ ? VecX(dense_lu_.solve(r)) : VecX(sparse_lu_.solve(r));
  }

  /// Levenberg–Marquardt's step d = −(GᵀG + ν I)⁻¹ Gᵀ F; false where that matrix does not factor.
  bool levenberg_marquardt(const VecX& F, double nu, VecX& d) {
    if (dense_) {
      MatX H = dense_G_.transpose() * dense_G_;
      H.diagonal().array() += nu;
      const Eigen::LLT<MatX> llt(H);
      if (llt.info() != Eigen::Success) return false;
      d = llt.solve(-(dense_G_.transpose() * F));
      return true;
    }
    const SpMat Gt = sparse_.transpose();
    const SpMat H = Gt * sparse_;
    // One analysis while GᵀG keeps its pattern (G stores every contact's 3×3 blocks).
    const bool factored =
        H.nonZeros() == normal_pattern_ ? normal_.refactor(H, nu) : normal_.factor(H, nu);
    normal_pattern_ = H.nonZeros();
    if (factored) normal_.solve(-(Gt * F), d);
    return factored;
  }

  /// max_k ‖G e_k‖², the largest diagonal entry of GᵀG.
  double largest_column_norm2() const {
    if (dense_) return dense_G_.colwise().squaredNorm().maxCoeff();
    double most = 0.0;
    for (int j = 0; j < sparse_.outerSize(); ++j) {
      double sum = 0.0;
      for (SpMat::InnerIterator it(sparse_, j); it; ++it) sum += it.value() * it.value();
      most = std::max(most, sum);
    }
    return most;
  }

 private:
  Eigen::Index c_;
  bool dense_;
  SpMat sparse_;
  Eigen::SparseLU<SpMat, Eigen::COLAMDOrdering<int>> sparse_lu_;
  bool analysed_ = false;
  CholmodFactor normal_;  // GᵀG + ν I
  long normal_pattern_ = -1;
  MatX dense_G_;
  Eigen::PartialPivLU<MatX> dense_lu_;
};

/// A contact's 3×3 blocks of Dm and Cm at rows and columns k to k + 2, as triplets.
void put_blocks(Eigen::Index k,
                const Mat3& Dm,
                const Mat3& Cm,
                std::vector<Triplet>& dt,
                std::vector<Triplet>& ct) {
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) {
      dt.emplace_back(int(k) + r, int(k) + q, Dm(r, q));
      ct.emplace_back(int(k) + r, int(k) + q, Cm(r, q));
    }
}

/// A box row's natural map v_k − clamp(v_k − w_k / A'_kk, cmin_k, cmax_k) (fixed rows at their
/// value), and with `jacobian` its generalized Jacobian's entries into dt and ct: D = 1 at a
/// bound, else C = 1 / A'_kk.
double box_row_map(const Setup& S,
                   Eigen::Index k,
                   double v,
                   double w,
                   bool jacobian,
                   std::vector<Triplet>& dt,
                   std::vector<Triplet>& ct) {
  const std::size_t K = std::size_t(k);
  const double lo = S.fixed[K] ? S.fixed_value(k) : S.cmin(k);
  const double hi = S.fixed[K] ? S.fixed_value(k) : S.cmax(k);
  const double y = v - S.rho_row(k) * w;
  const bool inside = lo < y && y < hi;
  if (jacobian) {
    dt.emplace_back(int(k), int(k), inside ? 0.0 : 1.0);
    ct.emplace_back(int(k), int(k), inside ? S.rho_row(k) : 0.0);
  }
  return v - clamp(y, lo, hi);
}

/// The law's natural map for stage 2's Newton steps, F(v) = v − P_K(v − ρ_α û(w)) per contact
/// and v − clamp(v − w / A'_kk, cmin, cmax) for the other rows, w = A_eps v − b_eps; with
/// `jacobian`, its generalized Jacobian I − D + C A_eps (D = ∂P at v − ρ_α û, C = ρ_α D ∂û/∂w;
/// a box row's D is 1 at a bound, else C = 1/A'_kk), every contact's 3×3 blocks stored so that
/// the pattern never changes. With `alart_curnier` (Coulomb's law only), each contact's rows hold
/// alart_curnier_map instead.
VecX natural_map_newton(const Setup& S,
                        const FrictionContacts& cones,
                        const SpMat& A_eps,
                        const VecX& b_eps,
                        const VecX& v,
                        NewtonMatrix* jacobian,
                        bool alart_curnier = false) {
  const Eigen::Index c = S.c;
  const VecX w = A_eps * v - b_eps;
  VecX F(c);
  std::vector<Triplet> dt, ct;
  if (jacobian != nullptr) {
    dt.reserve(std::size_t(3 * c));
    ct.reserve(std::size_t(3 * c));
  }
  for (Eigen::Index k = 0; k < c; ++k) {
    const std::size_t K = std::size_t(k);
    const int contact = S.contact_at[K];
    if (contact >= 0 && alart_curnier) {
      Mat3 Dm, Cm;
      F.segment<3>(k) = alart_curnier_map(
          v.segment<3>(k), w.segment<3>(k), cones.mu(contact), S.rho[std::size_t(contact)], Dm, Cm);
      if (jacobian != nullptr) put_blocks(k, Dm, Cm, dt, ct);
      continue;
    }
    if (contact >= 0) {
      const double mu = cones.mu(contact);
      const double rho = S.rho[std::size_t(contact)];
      const Vec3 u = w.segment<3>(k);
      const Vec3 y = v.segment<3>(k) - rho * law_velocity(u, mu, cones.law);
      Vec3 P = y;
      project_onto_cone(mu, P);
      F.segment<3>(k) = v.segment<3>(k) - P;
      if (jacobian != nullptr) {
        const Mat3 D = cone_projection_jacobian(mu, y);
        const Mat3 I_D = Mat3::Identity() - D;
        const Mat3 C = rho * D * law_velocity_jacobian(u, mu, cones.law);
        put_blocks(k, I_D, C, dt, ct);
      }
      continue;
    }
    if (S.in_cone[K]) continue;  // a tangent, done with its normal
    F(k) = box_row_map(S, k, v(k), w(k), jacobian != nullptr, dt, ct);
  }
  if (jacobian != nullptr) jacobian->assemble(dt, ct, A_eps);
  return F;
}

/// Stage 2: proximal points around semismooth Newton on `cones`' law with right side b, from x;
/// ends at `target` (scaled), after kMaxOuter steps or kOuterStall without progress, or at a
/// factorization that fails. With `alart_curnier` (Coulomb's law only) each subproblem's Newton
/// steps are on Alart–Curnier's function instead of the natural map; a subproblem also ends
/// after `patience` Newton steps in a row that lower ‖F‖₂ by less than kSubproblemRate. x
/// becomes the best point found.
void proximal_newton(const Setup& S,
                     const FrictionContacts& cones,
                     const VecX& b,
                     double target,
                     int max_outer,
                     VecX& x,
                     Counts& counts,
                     bool alart_curnier = false,
                     int patience = kMaxNewton) {
  const Eigen::Index c = S.c;
  NewtonMatrix jacobian(c);
  VecX best = x;
  double best_r = residual(S, cones, b, x);
  int stall = 0;
  double eps = kProximalWeight * best_r;
  for (int outer = 0;
       outer < max_outer && best_r > target && stall < kOuterStall && !counts.spent();
       ++outer) {
    ++counts.outer;
    SpMat A_eps = S.A;
    for (Eigen::Index k = 0; k < c; ++k) A_eps.coeffRef(k, k) += eps;
    const VecX b_eps = b + eps * x;
    double last_f = std::numeric_limits<double>::infinity();
    for (int it = 0, slow = 0; it < kMaxNewton; ++it) {
      const VecX F = natural_map_newton(S, cones, A_eps, b_eps, x, &jacobian, alart_curnier);
      const double f = F.norm();
      if (!(f > kInnerFraction * best_r) || counts.spent()) break;
      slow = f > kSubproblemRate * last_f ? slow + 1 : 0;
      last_f = f;
      if (slow >= patience) break;
      ++counts.factorizations;
      if (!jacobian.factor()) break;
      const VecX d = jacobian.solve(-F);
      if (!d.allFinite()) break;
      double t = 1.0;
      bool accepted = false;
      for (; t >= kSmallestStep; t *= 0.5) {
        const VecX trial = x + t * d;
        if (natural_map_newton(S, cones, A_eps, b_eps, trial, nullptr, alart_curnier).norm() <=
            (1.0 - kArmijo * t) * f) {
          x = trial;
          accepted = true;
          break;
        }
      }
      if (!accepted) break;
    }
    const double r = residual(S, cones, b, x);
    const double before = best_r;
    if (r < best_r) {
      best_r = r;
      best = x;
    } else {
      x = best;
    }
    if (r <= 0.5 * before) {  // fast: ε follows the residual down
      eps = std::min(eps, kProximalWeight * r);
    } else {  // slow or none: a larger ε, better conditioned
      if (eps >= kLargestWeight) ++stall;
      eps = std::min(eps * 100.0, kLargestWeight);
    }
  }
  x = best;
}

/// One semismooth Newton step on Alart–Curnier's function F of Coulomb's law with matrix A and
/// right side b (alart_curnier_map over all contacts, the box's natural map for the other rows),
/// from x, where F = F(x) and G holds its generalized Jacobian: G d = −F, G not symmetric (nor is
/// A where a file's W is not), factored by Eigen's SparseLU (one analysis), taken where it is
/// whole and lowers ‖F‖² by Armijo's fraction (the NSN-AC of Siconos; Alart & Curnier 1991,
/// Christensen, Klarbring, Pang & Strömberg, Int. J. Numer. Meth. Engng 42, 1998). Where G is
/// singular or that step does not descend, a Levenberg–Marquardt step (GᵀG + ν I) d = −Gᵀ F with
/// ν = ‖F‖ (Fan & Yuan, Computing 74, 2005: fast near a solution even where the solutions are not
/// isolated, as on a singular A), factored by CHOLMOD, with an Armijo search. A damped Newton
/// step on a singular G stalls far from the answer (Capsules: 6e-7 N after 60 steps) where
/// Levenberg–Marquardt's goes on (to 4e-16 N). False where neither step descends.
bool alart_curnier_step(const Setup& S,
                        const SpMat& A,
                        const VecX& b,
                        const VecX& F,
                        NewtonMatrix& G,
                        VecX& x,
                        Counts& counts,
                        double newton_smallest = 1.0) {
  const double f = F.squaredNorm();
  // x + t d for the first t = 1, 1/2, ... down to `smallest` with ‖F‖² decreasing by Armijo's
  // fraction.
  const auto descend = [&](const VecX& d, double smallest) {
    if (!d.allFinite()) return false;
    for (double t = 1.0; t >= smallest; t *= 0.5) {
      const VecX trial = x + t * d;
      if (natural_map_newton(S, S.law, A, b, trial, nullptr, true).squaredNorm() <=
          (1.0 - kArmijo * t) * f) {
        x = trial;
        return true;
      }
    }
    return false;
  };
  ++counts.factorizations;
  if (G.factor() && descend(G.solve(-F), newton_smallest)) return true;
  if (counts.spent()) return false;
  ++counts.factorizations;
  VecX d;
  return G.levenberg_marquardt(F, std::sqrt(f), d) && descend(d, kSmallestStep);
}

/// Coulomb's first try, from the relaxation's answer x: alart_curnier_step's steps on the
/// problem. Ends at `target` (the law's own residual, De Saxcé's natural map), after
/// kMaxAlartCurnier steps or kAlartCurnierStall in a row that do not lower it by the fraction
/// `progress`, or where no step descends. x becomes the point of least residual, which it
/// returns. From the relaxation's answer this finishes Siconos' test problems whose W is not
/// symmetric (Rover, OneObject, Capsules) and those where the relaxation leaves contacts sliding
/// (NESpheres_30_1, Confeti).
double alart_curnier_steps(
    const Setup& S, double target, VecX& x, Counts& counts, double progress = kNewtonProgress) {
  VecX best = x;
  double best_r = residual(S, S.law, S.b, x);
  NewtonMatrix G(S.c);
  int stall = 0;
  for (int it = 0;
       it < kMaxAlartCurnier && best_r > target && stall < kAlartCurnierStall && !counts.spent();
       ++it) {
    const VecX F = natural_map_newton(S, S.law, S.A, S.b, x, &G, true);
    if (!(F.squaredNorm() > 0.0)) break;  // Alart–Curnier's function is zero: the law holds
    ++counts.alart_curnier;
    if (!alart_curnier_step(S, S.A, S.b, F, G, x, counts)) break;
    const double r = residual(S, S.law, S.b, x);
    stall = r < (1.0 - progress) * best_r ? 0 : stall + 1;
    if (r < best_r) {
      best_r = r;
      best = x;
    }
  }
  x = best;
  return best_r;
}

/// Stage 3's fixed point on s = mu ‖u_t‖ for Coulomb's law, from x (the CCP's answer): each
/// round the CCP of b_n − s (De Saxcé's term moved into b) solved by stages 1 and 2, while
/// Coulomb's residual falls by a tenth a round; x becomes the round of least Coulomb residual.
void coulomb_fixed_point(const Setup& S,
                         double proximal,
                         const std::function<double(const VecX&)>& target_of,
                         VecX& x,
                         Counts& counts) {
  double r = residual(S, S.law, S.b, x);
  VecX best = x;
  int worse = 0;
  for (int round = 0; round < kMaxFixedPoint && r > target_of(x) && worse < 2 && !counts.spent();
       ++round) {
    const VecX b_s = desaxce_right_side(S, S.b, x);
    ++counts.rounds;
    x = interior(S, b_s, proximal, target_of, counts);
    proximal_newton(S, S.ccp, b_s, target_of(x), kMaxOuter, x, counts);
    const double next = residual(S, S.law, S.b, x);
    worse = next < 0.9 * r ? 0 : worse + 1;
    if (next < r) {
      r = next;
      best = x;
    }
  }
  x = best;
}

/// NSGS sweeps (nsgs.hpp) from `lambda` (N), told `target_x` (x's units), at most
/// sweeps.max_iterations, each contact's local step taken sweeps.methods.nsgs.local times. On a
/// problem in its simulator's units (options.tolerance_unit_free) they sweep the scaled problem
/// A' x = b' and stop where x's natural map is within the target: where they stop then does not
/// change with the units of force or velocity, as their steps (1/λmax(W_αα) a contact) do not.
/// Elsewhere they sweep the problem itself and stop at the target in N, as on cbps's own problems
/// they always have. The residual, a product with A and a map per contact (as dear as a sweep),
/// is measured after the first sweep, then after max(1, k / kSweepCheckEvery) more where the
/// last was at sweep k: they may run up to 1 / kSweepCheckEvery more sweeps than they need, and far
/// fewer checks (Siconos' NESpheres_30_1: 78 sweeps and 19 checks, 0.25 ms, where a check after
/// every sweep took 67 and 67, 0.33 ms; `cbps profile`, best of 5). Returns the sweeps run.
int sweep(const BoxedProblem& problem,
          const Setup& S,
          const SolverOptions& sweeps,
          double target_x,
          VecX& lambda) {
  const double alpha = S.bn / S.md;  // λ = alpha x
  BoxedProblem scaled{S.A, S.b, S.cmin, S.cmax};
  scaled.cones = &S.law;
  scaled.A_rows = S.A_rows.size() > 0 ? &S.A_rows : nullptr;
  const bool in_x = sweeps.tolerance_unit_free;
  const BoxedProblem& swept = in_x ? scaled : problem;
  const double target = in_x ? target_x : target_x * alpha;  // x's units, or N
  VecX v = in_x ? VecX(lambda / alpha) : lambda;
  const NsgsSweep step(swept);
  const int local = std::max(1, sweeps.methods.nsgs.local);
  int k = 0;
  for (int check = 1; k < sweeps.max_iterations && !past_deadline(sweeps);) {
    if (!std::isfinite(step(v, local))) break;
    if (++k < check && k < sweeps.max_iterations) continue;
    if (target > 0.0 && natural_map_residual(swept, v) <= target) break;
    check = k + std::max(1, k / kSweepCheckEvery);
  }
  lambda = in_x ? VecX(alpha * v) : v;
  return k;
}

/// The last stage, where the others stall: rounds of NSGS sweeps (nsgs.hpp; Jean & Moreau 1992)
/// on the unscaled problem from the best point so far (then from zero), each followed by Newton's
/// steps on Alart–Curnier's function (Coulomb) or proximal Newton on the relaxation from the
/// sweeps' answer, until the law's residual meets the target, the rounds, the factorizations or
/// a start's progress (kSweepStrikes) run out, or the deadline passes. The sweeps converge linearly
/// where Newton's steps stall (a rank-deficient W whose answers are not isolated: Siconos'
/// Capsules), and Newton's steps finish from the sweeps' answer in a few where the sweeps alone
/// would need tens of thousands. x (scaled) becomes the best point.
void sweeps_then_newton(const BoxedProblem& problem,
                        const Setup& S,
                        const SolverOptions& options,
                        const std::function<double(const VecX&)>& target_of,
                        VecX& x,
                        Counts& counts) {
  const double alpha = S.bn / S.md;  // λ = alpha x
  SolverOptions sweeps = options;
  sweeps.max_iterations = kSweepsPerRound;
  counts.budget = counts.factorizations + kSweepFactorizations;
  double best_r = residual(S, S.law, S.b, x);
  // From the best point so far, then from zero: Coulomb's problem is not monotone, and the sweeps
  // that stall near one point may converge from another (Capsules-i125-1213: stalled at 2e-6 N
  // from the relaxation's answer, converged from zero). The sweeps go on from their own iterate
  // round after round (they may dwell on a plateau, then fall once the contacts' states settle);
  // Newton's steps start from a copy of it.
  for (const bool cold : {false, true}) {
    VecX lambda = cold ? VecX::Zero(S.c) : VecX(alpha * x);
    int strikes = 0;  // rounds in a row that did not lower the best residual by a tenth
    for (int round = 0; round < kSweepRounds && strikes < kSweepStrikes && best_r > target_of(x) &&
                        !counts.spent();
         ++round) {
      counts.sweeps += sweep(problem, S, sweeps, target_of(x), lambda);
      VecX y = lambda / alpha;
      if (S.law.law == FrictionLaw::CoulombCone)
        alart_curnier_steps(S, target_of(y), y, counts);
      else
        proximal_newton(S, S.ccp, S.b, target_of(y), kMaxOuter, y, counts);
      const double r = residual(S, S.law, S.b, y);
      strikes = r < 0.9 * best_r ? 0 : strikes + 1;
      if (r < best_r) {
        best_r = r;
        x = y;
      }
    }
    if (best_r <= target_of(x) || counts.spent()) break;
  }
}

/// Stage 5's own factorizations: at most `cap`, and at most `work` / rows (a factorization's
/// cost grows with the rows).
int stage5_budget(const Setup& S, int cap, double work = kAveragedWork) {
  return static_cast<int>(
      std::min<double>(cap, work / static_cast<double>(std::max<Eigen::Index>(S.c, 1))));
}

/// Stage 5 on a W that is not symmetric, where every stage above stops short, and after the
/// averaged fixed point on one that is (kFallbackWork): proximal points (Rockafellar, SIAM J.
/// Control Optim. 14, 1976) in the schedule of Siconos' PROX (fc3d_proximal.c; Acary, Brémond &
/// Huber 2018): from the best point x, each step solves Coulomb's law with A + ε I and b + ε x_k
/// around the centre x_k by alart_curnier_step's steps (at x_k the subproblem's F is the law's
/// own), Newton's direction shortened by halving down to kSmallestStep before Levenberg–Marquardt's
/// is tried (taken whole or not at all, it left Siconos' RockPile_tob1 at a unit-free 3.3e-6 after
/// 29 s; shortened, 8.9e-8 after 16 s), to kSubproblemFraction of the centre's residual,
/// and its answer is the next centre whether or not the residual fell: the steps converge in
/// the distance to the answers, not in the residual (on Siconos' Capsules-i103-990 with mu halved
/// and ε held at 5e-5, a trial, the centres moved 1.6e-4 a step, scaled, for 130 steps while the
/// residual held near 2e-8, then it fell to 2e-13 in two). The weight ε follows kProximalSigma,
/// kWeightDecrease. No QP is assumed, so it stands where the fixed point on s (stage 5 on a
/// symmetric A) is no map of s. x becomes the point of least residual.
void proximal_points(const Setup& S,
                     const std::function<double(const VecX&)>& target_of,
                     VecX& x,
                     Counts& counts,
                     double work = kAveragedWork) {
  counts.budget = counts.factorizations + stage5_budget(S, kProximalFactorizations, work);
  NewtonMatrix G(S.c);
  double r = residual(S, S.law, S.b, x);
  VecX best = x;
  double best_r = r;
  double mark = r;  // best_r when the patience count last started
  double eps = kProximalSigma * r;
  for (int stalled = 0;
       best_r > target_of(best) && stalled < kProximalPatience && !counts.spent();) {
    ++counts.outer;
    ++counts.proximal_points;
    SpMat A_eps = S.A;
    for (Eigen::Index k = 0; k < S.c; ++k) A_eps.coeffRef(k, k) += eps;
    const VecX b_eps = S.b + eps * x;
    bool solved = false;
    double last_f = std::numeric_limits<double>::infinity();
    for (int it = 0, slow = 0; it < kMaxNewton && !counts.spent(); ++it) {
      const VecX F = natural_map_newton(S, S.law, A_eps, b_eps, x, &G, true);
      const double f = F.norm();
      solved = !(f > kSubproblemFraction * r);
      slow = f > kSubproblemRate * last_f ? slow + 1 : 0;
      last_f = f;
      if (solved || slow >= kSubproblemPatience ||
          !alart_curnier_step(S, A_eps, b_eps, F, G, x, counts, kSmallestStep))
        break;
    }
    r = residual(S, S.law, S.b, x);
    if (r < best_r) {
      best_r = r;
      best = x;
    }
    if (best_r < 0.9 * mark) {
      mark = best_r;
      stalled = 0;
    } else {
      ++stalled;
    }
    eps = solved ? std::max(kProximalSigma * r, eps / kWeightDecrease) : 10.0 * eps;
  }
  x = best;
}

/// Stage 5, under Coulomb's law where every stage above stops short: the fixed point on De
/// Saxcé's term averaged (Krasnosel'skii, Uspekhi Mat. Nauk 10, 1955; Mann, Proc. AMS 4, 1953),
///   s ← (1 − a) s + a mu ‖u_t(s)‖,  a = kAveragedWeight, halved where the rounds cycle,
/// with u(s) the w of the CCP of b_n − s (the convex relaxation with De Saxcé's term held fixed,
/// Cadoux's fixed point: Acary, Cadoux, Lemaréchal & Malick, ZAMM 91, 2011). That CCP is a convex
/// QP's optimality condition, so its w is unique even where A is singular and its λ is not, and
/// s is a function of s alone; a fixed point is a solution of Coulomb's law. Each round solves
/// the CCP of the new right side by stages 1 and 2 to kAveragedInner times the best Coulomb
/// residual so far (proximal Newton from the last round's answer first, the interior point only
/// where it stops short, took the base-10 pile's rounds 231 s instead of 97 s). Where the plain
/// rounds cycle (the contacts of a settling pile trading sticking, sliding and opening at 1e-9
/// m/s), the averaged ones converge, slowly: the base-10 pile (400 contacts) to a unit-free
/// residual of 3.9e-11 in about 440 rounds. Newton's steps on Alart–Curnier's function start
/// again from the rounds as they get closer (kNewtonAgain). x becomes the point of least Coulomb
/// residual.
/// Only where A is symmetric: on a W that is not, the CCP is no QP and its w need not be unique
/// (on Siconos' RockPile_tob1 the rounds ran 167 times in 54 s without going below the best
/// point of stages 1 to 4).
void averaged_fixed_point(const Setup& S,
                          double proximal,
                          const std::function<double(const VecX&)>& target_of,
                          VecX& x,
                          Counts& counts) {
  double best_r = residual(S, S.law, S.b, x);
  counts.budget = counts.factorizations + stage5_budget(S, kAveragedFactorizations);
  // Round 0 from s = 0: the relaxation, to the target. The rounds start far from the stages'
  // best point, so their progress is measured against their own best residual (own), and each
  // round's CCP is solved to a fraction of it, not to the final target: the rounds' error is
  // the fixed point's until the last ones.
  VecX b_s = S.b;
  VecX y = interior(S, b_s, proximal, target_of, counts);
  proximal_newton(S, S.ccp, b_s, target_of(y), kMaxOuter, y, counts);
  double own = std::numeric_limits<double>::infinity();
  double mark = own;  // own when the stall count last started
  int stalled = 0;
  double a = kAveragedWeight;
  double tried = best_r;          // own when Newton's steps last started from the rounds
  int above = 0;                  // rounds in a row of residual above kCycleRatio times own
  VecX own_b_s = b_s, own_y = y;  // the round of residual own, where a smaller weight restarts
  const std::function<double(const VecX&)> inner = [&](const VecX& v) {
    return std::max(target_of(v), kAveragedInner * own);
  };
  for (int round = 0; round < kAveragedRounds; ++round) {
    ++counts.averaged;
    const double r = residual(S, S.law, S.b, y);
    if (r < best_r) {
      best_r = r;
      x = y;
    }
    if (r < own) {
      own = r;
      own_b_s = b_s;
      own_y = y;
    }
    if (own < kNewtonAgain * tried) {  // Newton's steps on Alart–Curnier's function from it
      tried = own;
      VecX z = y;
      const int budget = counts.budget;
      counts.budget = std::min(budget, counts.factorizations + kAveragedNewton);
      const double rz = alart_curnier_steps(S, target_of(z), z, counts);
      counts.budget = budget;
      if (rz < best_r) {
        best_r = rz;
        x = z;
      }
    }
    stalled = own < 0.5 * mark ? 0 : stalled + 1;
    if (stalled == 0) mark = own;
    if (best_r <= target_of(x) || counts.spent()) break;
    above = r > kCycleRatio * own ? above + 1 : 0;
    if (stalled >= kAveragedStall) break;
    if (above >= kCycleRounds && a * 0.5 >= kSmallestWeight) {  // a cycle: half the weight,
      a *= 0.5;                                                 // from the rounds' best
      ++counts.halved;
      b_s = own_b_s;
      y = own_y;
      above = 0;
    }
    // s ← (1 − a) s + a mu ‖u_t(s)‖, as b_n − s: the right side averaged the same way.
    b_s = (1.0 - a) * b_s + a * desaxce_right_side(S, S.b, y);
    y = interior(S, b_s, proximal, inner, counts);
    proximal_newton(S, S.ccp, b_s, inner(y), kMaxOuter, y, counts);
  }
  // Where the rounds stop short: Newton's steps on Alart–Curnier's function from their best.
  if (best_r > target_of(x)) {
    const int budget = counts.budget;
    counts.budget = counts.factorizations + kSweepFactorizations;
    alart_curnier_steps(S, target_of(x), x, counts);
    counts.budget = budget;
  }
}

/// A contact's status in stage 6: its force 0 (open), anywhere in the cone at zero velocity
/// (sticking), or on the cone's boundary along its tangential velocity (sliding; under mu = 0,
/// closed at zero normal velocity).
enum class Status : char { Open, Stick, Slide };

/// Each contact's status at x, where the natural map sends it: z = r − ρ_α û (De Saxcé's
/// û = u + mu ‖u_t‖ e_n) sticks where z is in the cone, is open where −z is in its dual, and
/// slides otherwise.
std::vector<Status> statuses_at(const Setup& S, const VecX& x) {
  const VecX w = S.A * x - S.b;
  std::vector<Status> status;
  for (long i = 0; i < S.law.contacts(); ++i) {
    const int n = S.law.normal[std::size_t(i)];
    const double mu = S.law.mu(i);
    const Vec3 z =
        x.segment<3>(n) - S.rho[std::size_t(i)] * law_velocity(w.segment<3>(n), mu, S.law.law);
    const double zt = z.tail<2>().norm();
    if (mu == 0.0)
      status.push_back(z(0) > 0.0 ? Status::Slide : Status::Open);
    else if (zt <= mu * z(0))
      status.push_back(Status::Stick);
    else if (mu * zt <= -z(0))
      status.push_back(Status::Open);
    else
      status.push_back(Status::Slide);
  }
  return status;
}

/// The equations of Coulomb's law with each contact's status fixed, in x's units (r = x_α, u =
/// ρ_α w_α, w = A' x − b'): open r = 0; sticking u = 0; sliding u_n = 0, ‖r_t‖ = mu r_n and
/// r_t1 u_t2 − r_t2 u_t1 = 0 (r_t along u_t; under mu = 0, r_t = 0). Smooth where the law's
/// natural map is not: at a contact that slides at 1e-9 m/s, where the natural map's Jacobian
/// holds mu r_n / ‖u_t‖. A box row keeps its natural map. With G, their Jacobian Dm + Cm A'.
VecX status_equations(const Setup& S,
                      const std::vector<Status>& status,
                      const VecX& v,
                      NewtonMatrix* G) {
  const Eigen::Index c = S.c;
  const VecX w = S.A * v - S.b;
  VecX F(c);
  std::vector<Triplet> dt, ct;
  for (Eigen::Index k = 0; k < c; ++k) {
    const std::size_t K = std::size_t(k);
    const int contact = S.contact_at[K];
    if (contact >= 0) {
      const double mu = S.law.mu(contact);
      const double rho = S.rho[std::size_t(contact)];
      const Vec3 r = v.segment<3>(k);
      const Vec3 u = rho * w.segment<3>(k);
      Vec3 f = Vec3::Zero();
      Mat3 Dm = Mat3::Zero(), Cm = Mat3::Zero();
      switch (status[std::size_t(contact)]) {
        case Status::Open:
          f = r;
          Dm.setIdentity();
          break;
        case Status::Stick:
          f = u;
          Cm = rho * Mat3::Identity();
          break;
        case Status::Slide:
          f(0) = u(0);
          Cm(0, 0) = rho;
          if (mu == 0.0) {
            f.tail<2>() = r.tail<2>();
            Dm(1, 1) = Dm(2, 2) = 1.0;
            break;
          }
          const double rt = r.tail<2>().norm();
          f(1) = rt - mu * r(0);
          Dm(1, 0) = -mu;
          if (rt > 0.0) Dm.block<1, 2>(1, 1) = r.tail<2>().transpose() / rt;
          f(2) = r(1) * u(2) - r(2) * u(1);
          Dm(2, 1) = u(2);
          Dm(2, 2) = -u(1);
          Cm(2, 1) = -rho * r(2);
          Cm(2, 2) = rho * r(1);
          break;
      }
      F.segment<3>(k) = f;
      if (G != nullptr) put_blocks(k, Dm, Cm, dt, ct);
      continue;
    }
    if (S.in_cone[K]) continue;  // a tangent, done with its normal
    F(k) = box_row_map(S, k, v(k), w(k), G != nullptr, dt, ct);
  }
  if (G != nullptr) G->assemble(dt, ct, S.A);
  return F;
}

/// One run of stage 6: Levenberg–Marquardt's steps on status_equations from v (kStatusNewton,
/// kStatusWeight), each shortened by halving to Armijo's decrease; F becomes the equations at
/// the run's end. Returns the law's residual there.
double status_run(const Setup& S,
                  const std::vector<Status>& status,
                  VecX& v,
                  VecX& F,
                  NewtonMatrix& G,
                  Counts& counts) {
  ++counts.status_runs;
  F = status_equations(S, status, v, &G);
  for (int it = 0; it < kStatusNewton && !counts.spent(); ++it) {
    const double f = F.norm();
    if (f == 0.0) break;
    ++counts.factorizations;
    VecX d;
    if (!G.levenberg_marquardt(F, kStatusWeight * G.largest_column_norm2(), d) || !d.allFinite())
      break;
    bool accepted = false;
    for (double t = 1.0; t >= kSmallestStep && !accepted; t *= 0.5) {
      const VecX trial = v + t * d;
      if (status_equations(S, status, trial, nullptr).norm() <= (1.0 - kArmijo * t) * f) {
        v = trial;
        accepted = true;
      }
    }
    if (!accepted) break;
    F = status_equations(S, status, v, &G);
  }
  return residual(S, S.law, S.b, v);
}

/// Stage 6, under Coulomb's law where every stage above stops short: a search over the contacts'
/// statuses. The stages above stall where contacts slide at 1e-9 m/s or sit on the border of two
/// statuses (a card house of 60 contacts whose W has rank 90 of 180: 1.3e-10 unit-free, where
/// Siconos' PROX reaches 2e-16; its answer differs in one contact, open there and sliding at the
/// best point). From the best point x: Newton's steps on the equations of the statuses the
/// natural map gives there (status_equations; an active-set step, as the polishing of Stellato
/// et al., "OSQP", Math. Prog. Comp. 12, 2020, on a QP), then, where they stop short, the same
/// from x with one contact's status changed, for each of the kStatusCandidates contacts whose
/// equations the first run left furthest from zero (where the statuses admit no solution, the
/// least-squares residual sits at the contacts that must change), until one meets the target.
/// Every answer is judged by the law's own residual, so a wrong status costs time, never a
/// wrong verdict. x becomes the point of least residual.
void status_search(const Setup& S,
                   const std::function<double(const VecX&)>& target_of,
                   VecX& x,
                   Counts& counts) {
  counts.budget = counts.factorizations + stage5_budget(S, kStatusFactorizations, kStatusWork);
  NewtonMatrix G(S.c);
  const std::vector<Status> natural = statuses_at(S, x);
  VecX best = x;
  double best_r = residual(S, S.law, S.b, x);
  VecX y = x, F;
  const double r = status_run(S, natural, y, F, G, counts);
  if (r < best_r) {
    best_r = r;
    best = y;
  }
  const long m = S.law.contacts();
  std::vector<long> order(static_cast<std::size_t>(m));
  std::iota(order.begin(), order.end(), 0L);
  const auto off = [&](long i) { return F.segment<3>(S.law.normal[std::size_t(i)]).norm(); };
  const long candidates = std::min<long>(kStatusCandidates, m);
  std::partial_sort(order.begin(), order.begin() + candidates, order.end(), [&](long a, long b) {
    return off(a) > off(b);
  });
  for (long j = 0; j < candidates; ++j) {
    const std::size_t i = std::size_t(order[std::size_t(j)]);
    for (const Status other : {Status::Open, Status::Stick, Status::Slide}) {
      if (other == natural[i] || best_r <= target_of(best) || counts.spent()) continue;
      if (other == Status::Stick && S.law.mu(long(i)) == 0.0) continue;
      std::vector<Status> changed = natural;
      changed[i] = other;
      VecX z = x, Fz;
      const double rz = status_run(S, changed, z, Fz, G, counts);
      if (rz < best_r) {
        best_r = rz;
        best = z;
      }
    }
  }
  x = best;
}

VecX run_stages(const Setup& S,
                double proximal,
                const std::function<double(const VecX&)>& target_of,
                Counts& counts,
                const std::optional<VecX>& relaxed = std::nullopt);
void last_stages(const Setup& S,
                 double proximal,
                 const std::function<double(const VecX&)>& target_of,
                 const std::function<bool(const VecX&)>& met,
                 VecX& x,
                 Counts& counts);

/// Stage 7, under Coulomb's law on a W that is not symmetric, where stages 1 to 6 stop short on
/// it: the same law on W's symmetric part (W + Wᵀ)/2 first, by every stage a symmetric W has
/// (the fixed points on De Saxcé's term, stage 3's differentiated interior point, the status
/// search), then W's own from that answer: Alart–Curnier's steps, and where they stop short the
/// proximal points and the status search. A continuation in the skew part (W_sym + t W_skew, t
/// from 0 to 1 in one step): where W's asymmetry is the round-off of a stored file or of a
/// simulator's assembly, the symmetric part's answer is within it of W's. On the card house of
/// `cbps matrices card-house --param friction=cone --step 5` (60 contacts, W of rank 90 of 180)
/// with a skew part of 1e-12 of each entry added, stages 1 to 6 stopped at a unit-free 3.0e-10
/// where Siconos' PROX reached 3e-15 (in 180 s); the symmetric part's answer meets the law on W
/// at 2.6e-13. Only where the skew part's w at the best point x, read as the law's residual
/// reads w, is at most x's residual: where it is more, the symmetric part's answers are further
/// from W's than x is (Siconos' RockPile_tob1, max |W − Wᵀ| 7e-2: 3.5e-3 against 5.3e-7, and the
/// symmetric part's answer left W's law at 3e-4 after 14 s; the card house above: 2.6e-11
/// against 1.9e-8). Each part with a budget of kMaxFactorizations for the stages that have none
/// of their own. x becomes the point of least residual on W.
void symmetric_part_first(const Setup& S,
                          double proximal,
                          const std::function<double(const VecX&)>& target_of,
                          VecX& x,
                          Counts& counts) {
  // The skew part's w at x, in the units of `residual`: how far the symmetric part's law is from
  // W's there.
  const VecX skew = (S.A - S.A_sym) * x;
  const double moved = S.unit_free ? S.rho_unit_free.cwiseProduct(skew).lpNorm<Eigen::Infinity>()
                                   : S.md * skew.lpNorm<Eigen::Infinity>();
  if (moved > residual(S, S.law, S.b, x)) {
    counts.skew_too_large = true;
    return;
  }
  Setup T = S;  // the same scaling, contacts and rows; A' its symmetric part
  T.A = S.A_sym;
  T.A_sym.resize(0, 0);
  T.A_rows.resize(0, 0);
  const auto met_T = [&](const VecX& v) { return residual(T, T.law, T.b, v) <= target_of(v); };
  Counts part;  // the symmetric part's stages, counted apart
  part.deadline = counts.deadline;
  VecX y = run_stages(T, proximal, target_of, part);
  if (!met_T(y)) last_stages(T, proximal, target_of, met_T, y, part);
  counts.symmetric_part = part.factorizations;
  counts.factorizations += part.factorizations;
  counts.budget = counts.factorizations + kMaxFactorizations;
  if (alart_curnier_steps(S, target_of(y), y, counts, kHandOverProgress) > target_of(y)) {
    proximal_points(S, target_of, y, counts);
    if (residual(S, S.law, S.b, y) > target_of(y)) status_search(S, target_of, y, counts);
  }
  if (residual(S, S.law, S.b, y) < residual(S, S.law, S.b, x)) x = y;
}

/// Stages 5 and 6 in their order, under Coulomb's law where stages 1 to 4 stop short: on a W
/// that is not symmetric the proximal points, on one that is the averaged fixed point and the
/// proximal points after it; then the search over statuses; then, on a W that is not symmetric,
/// stage 7 (symmetric_part_first).
void last_stages(const Setup& S,
                 double proximal,
                 const std::function<double(const VecX&)>& target_of,
                 const std::function<bool(const VecX&)>& met,
                 VecX& x,
                 Counts& counts) {
  if (!S.symmetric()) {
    proximal_points(S, target_of, x, counts);
  } else {
    averaged_fixed_point(S, proximal, target_of, x, counts);
    if (!met(x)) proximal_points(S, target_of, x, counts, kFallbackWork);
  }
  if (!met(x)) status_search(S, target_of, x, counts);
  if (!met(x) && !S.symmetric()) symmetric_part_first(S, proximal, target_of, x, counts);
}

/// Stage 0 (kQuickRounds), under Coulomb's law: rounds of NSGS sweeps (nsgs.hpp) on the
/// unscaled problem from `lambda`, each followed by Newton's steps on Alart–Curnier's function
/// from the sweeps' answer (on small problems, proximal points around them where they stop
/// short: kQuickProximalRows), until `met`; x (scaled) becomes the best point (under the
/// relaxation: `lambda` itself).
void quick_start(const BoxedProblem& problem,
                 const Setup& S,
                 const SolverOptions& options,
                 const std::function<double(const VecX&)>& target_of,
                 const std::function<bool(const VecX&)>& met,
                 const VecX& lambda,
                 VecX& x,
                 Counts& counts) {
  const double alpha = S.bn / S.md;  // λ = alpha x
  x = lambda / alpha;
  // The relaxation's interior point is cheap and exact; Coulomb's stages are the costly ones.
  if (S.law.law != FrictionLaw::CoulombCone) return;
  SolverOptions sweeps = options;
  VecX swept = lambda;
  double best_r = std::numeric_limits<double>::infinity();
  const int budget = counts.budget;
  for (const QuickRound& round : kQuickRounds) {
    if (S.c > round.rows) continue;
    sweeps.max_iterations = round.sweeps;
    counts.sweeps += sweep(problem, S, sweeps, target_of(swept / alpha), swept);
    VecX y = swept / alpha;
    double r = residual(S, S.law, S.b, y);
    if (!met(y)) {
      counts.budget = counts.factorizations + round.factorizations;
      r = alart_curnier_steps(S, target_of(y), y, counts);
      if (r > target_of(y) && S.c <= kQuickProximalRows) {
        VecX z = y;  // the least residual so far
        counts.budget = counts.factorizations + kQuickProximal;
        proximal_newton(
            S, S.law, S.b, target_of(z), kMaxOuter, z, counts, true, kSubproblemPatience);
        const double rz = residual(S, S.law, S.b, z);
        if (rz < r) {
          r = rz;
          y = z;
        }
      }
      counts.budget = budget;
    }
    if (r < best_r) {
      best_r = r;
      x = y;
    }
    if (met(x) || counts.spent()) break;
  }
}

/// The stages in their order (cone_direct.hpp) on the scaled problem: the answer in units of x.
/// The relaxation's interior point first. Under Coulomb's law its answer stands where it keeps
/// Coulomb's law too (a pile at rest: no contact slides, so De Saxcé's term is zero); else the
/// interior point with De Saxcé's term refreshed at every iterate, and where that does not
/// finish the other stages from the relaxation's answer, the better answer kept.
VecX run_stages(const Setup& S,
                double proximal,
                const std::function<double(const VecX&)>& target_of,
                Counts& counts,
                const std::optional<VecX>& relaxed) {
  VecX x = relaxed ? *relaxed : interior(S, S.b, proximal, target_of, counts);
  VecX refreshed;
  bool finished =
      S.law.law == FrictionLaw::CoulombCone && residual(S, S.law, S.b, x) <= target_of(x);
  double refreshed_r = std::numeric_limits<double>::infinity();
  if (S.law.law == FrictionLaw::CoulombCone && !finished) {
    const int before = counts.interior;
    refreshed = interior(S, S.b, proximal, target_of, counts, DeSaxce::Refreshed);
    refreshed_r = residual(S, S.law, S.b, refreshed);
    counts.desaxce = counts.interior - before;
    finished = refreshed_r <= target_of(refreshed);
    if (!finished && S.symmetric()) {  // the term differentiated too (A symmetric: its
                                       // rows are its columns); the better one stands
      const int held = counts.interior;
      VecX other = interior(S, S.b, proximal, target_of, counts, DeSaxce::Differentiated);
      counts.differentiated = counts.interior - held;
      const double other_r = residual(S, S.law, S.b, other);
      if (other_r < refreshed_r) {
        refreshed = std::move(other);
        refreshed_r = other_r;
        finished = refreshed_r <= target_of(refreshed);
      }
    }
    if (finished) x = refreshed;
  }
  if (finished) {
    // Coulomb's law met by the relaxation's or the refreshed interior point: nothing more to do
  } else if (S.law.law == FrictionLaw::Relaxation) {
    proximal_newton(S, S.ccp, S.b, target_of(x), kMaxOuter, x, counts);
  } else if (!S.symmetric()) {
    // W not symmetric: the relaxation of De Saxcé's term held fixed is no QP, so the fixed point
    // on s below is no map of s (averaged_fixed_point); on Siconos' Capsules its rounds ended
    // far from the law (0.2 to 5e-3 scaled, 70 to 80 ms, where Newton's steps had reached 3e-6
    // to 8e-9), and Newton's steps from the relaxation's answer, far from the law (residual near
    // 1), did not come near the refreshed one's (40 to 60 ms). Newton's steps from the better
    // interior point, then proximal points around them from their best point (Capsules-i125-1213,
    // 858 rows: 0.10 s instead of 0.46 s).
    const double x_r = residual(S, S.law, S.b, x);
    VecX y = refreshed_r < x_r ? refreshed : x;
    if (alart_curnier_steps(S, target_of(y), y, counts, kHandOverProgress) > target_of(y))
      proximal_newton(S, S.law, S.b, target_of(y), kMaxOuter, y, counts, true);
    if (residual(S, S.law, S.b, y) < x_r) x = y;
  } else {  // Alart–Curnier's steps, and where they do not finish the fixed point on s
    const double x_r = residual(S, S.law, S.b, x);
    const bool from_refreshed = refreshed_r < x_r;
    VecX y = from_refreshed ? refreshed : x;  // the better start first, then the other
    double tried = alart_curnier_steps(S, target_of(y), y, counts);
    if (tried > target_of(y) && refreshed.size() > 0) {
      VecX z = from_refreshed ? x : refreshed;
      const double other = alart_curnier_steps(S, target_of(z), z, counts);
      if (other < tried) {
        tried = other;
        y = z;
      }
    }
    if (tried > target_of(y)) {
      coulomb_fixed_point(S, proximal, target_of, x, counts);
      proximal_newton(S, S.law, S.b, target_of(x), kMaxOuter, x, counts, true);
      if (residual(S, S.law, S.b, x) < tried) {  // Newton's steps again, from the best point
        VecX z = x;
        const double again = alart_curnier_steps(S, target_of(z), z, counts);
        if (again < tried) {
          tried = again;
          y = z;
        }
      }
    }
    if (tried < residual(S, S.law, S.b, x)) x = y;
    if (refreshed_r < residual(S, S.law, S.b, x)) x = refreshed;
  }
  return x;
}

/// The tolerance τ as solve_cone_direct reads it (docs/cones.md, "The verdict"). On cbps's own
/// problems, in SI units: both ways, the natural map (unit step, N) within
/// min(τ, newtons(τ, λ)) (UnitFreeTarget::both), or the rounding floor where that is higher. On a
/// problem in its simulator's units (SolverOptions::tolerance_unit_free: a Siconos or FCLIB file),
/// where a newton means nothing, through unit-free quantities alone: met where the unit-free
/// residual is within τ, and the stages aim in x's units, where they read the scaled problem's
/// own natural map (`residual`, Setup::unit_free), so that a change of the unit of force or of
/// velocity changes neither their path nor the verdict.
class Aim {
 public:
  Aim(const BoxedProblem& problem, const SolverOptions& options)
      : problem_(problem),
        tolerance_(options.tolerance),
        unit_free_only_(options.tolerance_unit_free),
        target_(unit_free_target(problem)),
        scale_(stage_scale(problem)),
        steps_(unit_free_steps(problem)) {}

  bool unit_free_only() const { return unit_free_only_; }

  /// The residual (N) to reach at λ on cbps's own problems (what the message shows there).
  double newtons(const VecX& l) const {
    return std::max(target_.both(tolerance_, l), residual_floor(problem_, l));
  }

  /// Met, at λ of natural-map residual r (N): on a problem in its simulator's units the
  /// unit-free residual within τ; on cbps's own, r within τ N and the unit-free residual within
  /// τ, both computed (r within newtons(λ) implies the second, but not in floating point: where
  /// A_kk is far below the forces' compliances, the unit-step map loses w_k under the rounding
  /// of λ_k, and a λ_k off by 1e-5 of itself had a map of 0 N); or, either way, every row and
  /// contact within its own rounding floor in the unit-free map (within_rounding), or, where τ N
  /// is below kUlpsOfForces ulps of the force scale (out of reach: forces of 1e8 N leave 1e-9 N
  /// of round-off, Siconos' Confeti-ex13), the unit-free residual within τ. (The floor was
  /// the largest row's, shared: a contact of compliance 1e-8 kg⁻¹ beside one of 1e6 passed 50%
  /// off.)
  bool meets(const VecX& l, double r) const {
    const UnitFreeResidual u = unit_free_residual(problem_, l);
    if (u.relative <= tolerance_ && (unit_free_only_ || r <= tolerance_)) return true;
    if (within_rounding(problem_, l, steps_, 0.0)) return true;
    return !unit_free_only_ &&
           tolerance_ < kUlpsOfForces * std::numeric_limits<double>::epsilon() * u.scale &&
           u.relative <= tolerance_;
  }

  /// The residual the stages reach for at λ, in x's units (x = λ md / bn). On cbps's own problems
  /// newtons(λ) in x's units. On a problem in its simulator's units the unit-free target itself:
  /// the stages' residual there is the unit-free residual's numerator in x's units (`residual`),
  /// so τ S' with S' = max(‖x‖∞, max_k ρ'_k |b'_k|) = S md / bn, or its rounding floor: each
  /// row's rounding_floors times its own step ρ_k, the largest (within_rounding's, in x's
  /// units); neither moves with the units. (The bound in N,
  /// newtons(τ, λ), does: its max(1, ρ_max) does, and in units where it made ρ_max > 1 the
  /// stages ran to another target on another path: Siconos' Capsules-i125-1213 in units of
  /// force 1000 times smaller than its own was not verified. The floor was the largest row's
  /// times the largest step, two rows' maxima: on contacts of compliances 1e6 and 1e-8 kg⁻¹ it
  /// was 0.47 N, and the relaxation stopped with the second's force a third off.)
  double in_x(const VecX& l) const {
    const double x_per_newton = scale_.md / scale_.bn;
    if (!unit_free_only_) return newtons(l) * x_per_newton;
    const double scale_x = std::max(l.lpNorm<Eigen::Infinity>(), target_.rho_b) * x_per_newton;
    const double floor = steps_.cwiseProduct(rounding_floors(problem_, l)).maxCoeff();  // N
    return std::max(tolerance_ * scale_x, floor * x_per_newton);
  }

 private:
  const BoxedProblem& problem_;
  double tolerance_;
  bool unit_free_only_;
  UnitFreeTarget target_;
  Scale scale_;
  VecX steps_;  ///< unit_free_steps: each row's ρ_k, kg
};

/// The summary's message: what each stage did, the residual against its target, and why it
/// stopped short where it did.
std::string cone_direct_message(const Setup& S,
                                const Counts& counts,
                                bool reached,
                                double residual,
                                double target,
                                double floor,
                                double tolerance,
                                double unit_free) {
  std::ostringstream msg;
  msg << (reached ? "direct on cones" : "not verified: direct on cones stopped") << " ("
      << cone_law_name(S.law.law) << ", " << S.law.contacts() << " contacts): " << counts.interior
      << " interior iterations";
  if (S.law.law == FrictionLaw::CoulombCone)
    msg << " (" << counts.desaxce << " with De Saxce's term refreshed, " << counts.differentiated
        << " with it differentiated), " << counts.alart_curnier << " Alart-Curnier steps, "
        << counts.rounds << " fixed-point rounds";
  if (counts.sweeps > 0) msg << ", " << counts.sweeps << " NSGS sweeps";
  if (counts.averaged > 0) {
    msg << ", " << counts.averaged << " averaged fixed-point rounds";
    if (counts.halved > 0)
      msg << " (weight " << kAveragedWeight << " halved " << counts.halved << "x)";
  }
  msg << ", ";
  msg << counts.outer << " proximal steps";
  if (counts.proximal_points > 0)
    msg << " (" << counts.proximal_points << " of them stage 5's, in PROX's schedule)";
  if (counts.status_runs > 0)
    msg << ", " << counts.status_runs << " Newton runs with the contacts' statuses fixed";
  if (counts.symmetric_part >= 0)
    msg << ", stage 7: the law on W's symmetric part first (" << counts.symmetric_part
        << " factorizations), then on W from its answer";
  if (counts.skew_too_large)
    msg << ", stage 7 not run: W's skew part moves the law at the best point more than that "
           "point misses it by";
  msg << ", " << counts.factorizations << " factorizations";
  if (counts.body_factorizations > 0) {
    msg << " (" << counts.body_factorizations << " interior ones in body space, M + Jt Omega J";
    if (counts.space == "row")
      msg << ", the rest in row space once a body-space solve's backward error exceeded "
          << kBodyAccuracy;
    msg << ")";
  }
  if (S.unit_free)
    msg << "; residual " << residual << " in the problem's units, unit-free " << unit_free
        << " (target " << tolerance
        << ", the tolerance read as a unit-free residual alone: the problem's units are its "
           "simulator's; or the rounding floor)";
  else
    msg << "; residual " << residual << " N, unit-free " << unit_free << " (target " << target
        << " N, from the tolerance in N and as a unit-free residual, or each row's own rounding "
           "floor, the largest row's "
        << floor << " N; or, where that is below 1000 ulps of the forces, a unit-free residual "
        << "at most the tolerance)";
  if (!S.unit_free && !reached && residual <= target)
    msg << "; under that target but not verified: some row is above its own rounding floor "
           "(a row of far smaller compliance than the largest row's: docs/cones.md, \"The "
           "verdict\")";
  if (!reached && counts.factorizations >= counts.budget)
    msg << "; stopped at its budget of " << counts.budget << " factorizations";
  if (!reached && S.law.law == FrictionLaw::CoulombCone)
    msg << "; Coulomb's law is not the optimality condition of a convex problem: the interior "
           "point with De Saxce's term refreshed, "
        << (!S.symmetric() ? "the semismooth Newton steps on Coulomb's own map, the "
                             "proximal points around them and NSGS sweeps"
                           : "the fixed point on s = mu |u_t|, the semismooth Newton "
                             "steps on Coulomb's own map and the proximal points after them")
        << (counts.symmetric_part >= 0 ? ", and the same from the answer on W's symmetric part,"
                                       : "")
        << " each stopped short of it; a solution "
           "exists wherever some velocity opens every contact at once, which "
           "scripts/strict_feasibility.py PROBLEM shows for a symmetric A (Acary, Cadoux, "
           "Lemarechal & Malick 2011), and may not otherwise (docs/cones.md)";
  return msg.str();
}

}  // namespace

SolverSummary solve_cone_direct(const BoxedProblem& problem,
                                VecX& lambda,
                                const SolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  SolverSummary summary;
  const Eigen::Index c = problem.rows();
  if (lambda.size() != c) lambda = VecX::Zero(c);
  auto finish = [&](Termination termination, const std::string& message) {
    summary.termination = termination;
    summary.message = message;
    summary.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  };
  bool finite = problem.b.allFinite();
  for (int j = 0; j < problem.A.outerSize() && finite; ++j)
    for (SpMat::InnerIterator it(problem.A, j); it; ++it)
      finite = finite && std::isfinite(it.value());
  if (!finite) {
    summary.residual = std::numeric_limits<double>::quiet_NaN();
    return finish(Termination::NonFinite, "non-finite A or b");
  }
  const Aim aim(problem, options);
  // A guess that already meets the tolerance is kept as it is.
  const double guess_r = natural_map_residual(problem, lambda);
  if (aim.meets(lambda, guess_r)) {
    summary.residual = guess_r;
    std::ostringstream msg;
    msg << "the guess already meets the tolerance (residual " << guess_r << " N)";
    return finish(Termination::Direct, msg.str());
  }

  Setup setup = make_setup(problem);
  setup.unit_free = aim.unit_free_only();
  const Setup& S = setup;
  Counts counts;
  counts.deadline = options.deadline;
  const double proximal = options.direct.proximal;
  // The residual to reach at x, in units of x.
  const std::function<double(const VecX&)> target_of = [&](const VecX& v) {
    return aim.in_x(v * (S.bn / S.md));
  };
  const auto unscaled = [&](const VecX& v) {
    VecX l = v * (S.bn / S.md);
    for (Eigen::Index k = 0; k < c; ++k)  // fixed rows exactly at their value
      if (S.fixed[std::size_t(k)] && !S.in_cone[std::size_t(k)]) l(k) = problem.cmin(k);
    return l;
  };
  const auto met = [&](const VecX& v) {
    const VecX l = unscaled(v);
    return aim.meets(l, natural_map_residual(problem, l));
  };
  // A cold solve of a large problem takes the relaxation's interior point first (stage 1; at
  // rest it is the answer under either law), a small or warm one the cheap start (stage 0).
  std::optional<VecX> relaxed;
  const bool cold = (lambda.array() == 0.0).all();
  if (cold && c > kQuickFirstRows) relaxed = interior(S, S.b, proximal, target_of, counts);
  VecX x;
  if (relaxed && (met(*relaxed) || S.law.law != FrictionLaw::CoulombCone)) {
    x = *relaxed;
  } else {
    quick_start(problem, S, options, target_of, met, lambda, x, counts);
  }
  if (!met(x)) {
    const VecX quick = x;
    x = run_stages(S, proximal, target_of, counts, relaxed);
    if (residual(S, S.law, S.b, quick) < residual(S, S.law, S.b, x)) x = quick;
    if (!met(x)) sweeps_then_newton(problem, S, options, target_of, x, counts);
    if (!met(x) && S.law.law == FrictionLaw::CoulombCone)
      last_stages(S, proximal, target_of, met, x, counts);
  }
  VecX answer = unscaled(x);
  const double r = natural_map_residual(problem, answer);
  // Keep the guess when it was better (the stages never saw it).
  if (guess_r < r) answer = lambda;
  lambda = answer;
  summary.residual = std::min(r, guess_r);
  summary.iterations = counts.interior;
  summary.crossover = counts.outer;
  summary.factorizations = counts.factorizations;
  summary.factor_nnz = counts.factor_nnz;
  summary.space = counts.space;
  const double floor = residual_floor(problem, lambda);
  const bool reached = aim.meets(lambda, summary.residual);
  const std::string message = cone_direct_message(S,
                                                  counts,
                                                  reached,
                                                  summary.residual,
                                                  aim.newtons(lambda),
                                                  floor,
                                                  options.tolerance,
                                                  unit_free_residual(problem, lambda).relative);
  return finish(reached ? Termination::Direct : Termination::NotConverged, message);
}

}  // namespace cbps
