// The cost of the parts of one solve against this machine's memory bandwidth, on the built-in
// chain (n = 10², 10³, 10⁴, 10⁵ links: one distance row per link, A tridiagonal) and pyramid
// (base 4, 10, 20, 40, 91: 12 b² contact and friction rows, 192 … 99,372 rows):
//
//   bandwidth/triad     STREAM's triad a_i = b_i + s c_i over three arrays of 2²⁵ doubles
//                       (768 MB, 24× the 32 MiB L3), one core; bandwidth_GBps is the best of 10
//                       passes, measured once per process before any sweep
//   assembly            assemble_system (6.1, 6.2.9): J, Minv, v1, fext, upsilon, cmin, cmax,
//                       A = J Minv Jᵀ, b from ready rows, into a System whose storage is reused,
//                       as Simulation::step does it (collision detection and rows not included)
//   pgs_sweep           one sweep of 7.1.1 over the explicit A (pgs_sweep)
//   matrix_free_sweep   one sweep of 7.1.1 in the matrix-free form (MatrixFreePgs::sweep, with
//                       W = M⁻¹ Jᵀ and u = W lambda; A is never formed)
//   direct              solve_direct from lambda = 0 (6.2): chains (one CHOLMOD factorization
//                       and solve) and the pyramids of base 4 and 10 only; base 20 (4,800 rows)
//                       took 57 s (1,473 factorizations, 104,765 active-set exchanges)
//
// The chain is stepped 5 times (10 PGS sweeps each) so every row of J has its general pattern;
// the pyramid is the system of its first step (the boxes start touching, so every contact
// exists). Both sweeps start from 10 untimed sweeps from lambda = 0 and keep lambda (and u) from
// one timed sweep to the next.
//
// Every benchmark reports rows, nnz_A and nnz_J; the sweeps also report bytes_per_sweep (see
// explicit_sweep_bytes and matrix_free_sweep_bytes), bandwidth_GBps and
//   fraction_of_bound = (bytes_per_sweep / bandwidth) / CPU time of one sweep,
// 1 when a sweep runs at the speed of streaming its data once from memory. The console prints
// it with a "/s" suffix, as it does every rate counter; the number is a plain fraction.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cbps/cbps.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"

namespace {

// ---------------------------------------------------------------------------------------------
// Streaming bandwidth

constexpr std::size_t kTriadElements = std::size_t{1} << 25;  // 32 Mi doubles = 256 MB per array
constexpr int kTriadPasses = 10;

/// Memory traffic of one triad element: b_i and c_i are read, and a_i is written into a line
/// the core first reads for ownership (write-allocate), then writes back: 4 × 8 bytes. The
/// sweeps' byte counts below are traffic in the same sense (every line they write was read
/// first), so the bound compares like with like. STREAM's convention counts 3 × 8 bytes; its
/// figure is 3/4 of bandwidth_GBps.
constexpr double kTriadBytesPerElement = 4.0 * sizeof(double);

struct TriadArrays {
  std::vector<double> a = std::vector<double>(kTriadElements, 0.0);
  std::vector<double> b = std::vector<double>(kTriadElements, 1.0);
  std::vector<double> c = std::vector<double>(kTriadElements, 2.0);

  void pass(double s) {
    for (std::size_t i = 0; i < kTriadElements; ++i) a[i] = b[i] + s * c[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
};

/// Bytes per second of the triad, the best of kTriadPasses passes; measured on the first call
/// (the triad benchmark runs first; a filtered run measures it before its first sweep).
double bandwidth() {
  static const double best = [] {
    TriadArrays arrays;
    double fastest = 0.0;
    for (int k = 0; k < kTriadPasses; ++k) {
      const auto start = std::chrono::steady_clock::now();
      arrays.pass(3.0);
      const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
      if (k == 0 || took.count() < fastest) fastest = took.count();
    }
    return kTriadBytesPerElement * static_cast<double>(kTriadElements) / fastest;
  }();
  return best;
}

void bm_triad(benchmark::State& state) {
  const double bytes_per_s = bandwidth();
  TriadArrays arrays;
  for (auto _ : state) arrays.pass(3.0);
  state.SetBytesProcessed(state.iterations() *
                          static_cast<std::int64_t>(kTriadBytesPerElement * kTriadElements));
  state.counters["bandwidth_GBps"] = bytes_per_s * 1e-9;
}

// ---------------------------------------------------------------------------------------------
// Systems

enum class SceneKind { Chain, Pyramid };

/// PGS sweeps before the timed ones, so lambda is no longer the zero guess.
constexpr int kWarmUpSweeps = 10;

/// A scene's bodies and rows and the system assembled from them, built once per scene and size
/// and shared by all benchmarks.
struct Problem {
  std::unique_ptr<cbps::Simulation> sim;
  std::vector<cbps::Row> rows;
  cbps::System sys;
};

const Problem& problem(SceneKind kind, long size) {
  static std::map<std::pair<SceneKind, long>, std::unique_ptr<Problem>> cache;
  std::unique_ptr<Problem>& p = cache[{kind, size}];
  if (!p) {
    p = std::make_unique<Problem>();
    if (kind == SceneKind::Chain) {
      cbps::Scene scene = cbps::make_builtin_scene("chain", {{"n", std::to_string(size)}});
      scene.solver.max_iterations = 10;
      scene.solver.tolerance = 0.0;
      p->sim = std::make_unique<cbps::Simulation>(scene);
      for (int s = 0; s < 5; ++s) p->sim->step();
    } else {
      p->sim = std::make_unique<cbps::Simulation>(
          cbps::make_builtin_scene("pyramid", {{"base", std::to_string(size)}}));
    }
    p->rows = p->sim->build_rows();
    const cbps::World& world = p->sim->scene().world;
    p->sys =
        cbps::assemble_system(p->sim->scene().bodies, p->rows, world.gravity, world.dt, world.push);
  }
  return *p;
}

void set_size_counters(benchmark::State& state, const cbps::System& sys) {
  state.counters["rows"] = sys.rows();
  state.counters["nnz_A"] = static_cast<double>(sys.A.nonZeros());
  state.counters["nnz_J"] = static_cast<double>(sys.J.nonZeros());
}

/// bytes_per_sweep, bandwidth_GBps and fraction_of_bound: the rate counter "bound seconds per
/// iteration" is (bytes / bandwidth) · iterations / CPU time, the bound over the measured time.
void set_sweep_counters(benchmark::State& state,
                        const cbps::System& sys,
                        double bytes,
                        double bytes_per_s) {
  set_size_counters(state, sys);
  state.counters["bytes_per_sweep"] = bytes;
  state.counters["bandwidth_GBps"] = bytes_per_s * 1e-9;
  state.counters["fraction_of_bound"] =
      benchmark::Counter(bytes / bytes_per_s, benchmark::Counter::kIsIterationInvariantRate);
}

constexpr double kValue = sizeof(double);
constexpr double kIndex = sizeof(cbps::SpMat::StorageIndex);

/// Bytes one explicit sweep (7.1.1, pgs_sweep) must move, c rows: row j reads column j of the
/// compressed, column-major A (symmetric, so column j is row j) — values and row indices once,
/// the outer index array once — and b_j, cmin_j, cmax_j, and reads and writes lambda_j. A_jj
/// is found in the same column scan (row_target), so the diagonal costs nothing more; the
/// lambda_i of Σ A_ji lambda_i are gathered from lines of lambda the sweep reads anyway.
///   (8 + 4) nnz(A) + 4 (c + 1) + 3 · 8 c + 2 · 8 c.
double explicit_sweep_bytes(const cbps::System& sys) {
  const auto nnz = static_cast<double>(sys.A.nonZeros());
  const double c = sys.rows();
  return (kValue + kIndex) * nnz + kIndex * (c + 1) + 3 * kValue * c + 2 * kValue * c;
}

/// Bytes one matrix-free sweep (MatrixFreePgs::sweep) must move, c rows and n movable bodies:
/// row j reads row j of J (row-major) for j_j u and column j of W = M⁻¹ Jᵀ (column-major, 6n × c)
/// for u += W_j Δlambda_j — values and indices of both once, both outer index arrays — d_j =
/// A_jj, b_j, cmin_j, cmax_j, and reads and writes lambda_j; u (6n doubles, gathered and
/// scattered through the bodies' columns) is counted once read and once written. The W update
/// is skipped for a row whose lambda_j does not change (clamped where it was), so this is an
/// upper bound on what a converged sweep moves.
///   (8 + 4) (nnz(J) + nnz(W)) + 2 · 4 (c + 1) + 8 c + 3 · 8 c + 2 · 8 c + 2 · 8 · 6n.
double matrix_free_sweep_bytes(const cbps::System& sys) {
  // The same product MatrixFreePgs keeps as W (its nonzeros are not exposed).
  const cbps::SpMat W = sys.Minv * cbps::SpMat(sys.J.transpose());
  const auto nnz = static_cast<double>(sys.J.nonZeros() + W.nonZeros());
  const double c = sys.rows();
  const double u = 6.0 * sys.blocks();
  return (kValue + kIndex) * nnz + 2 * kIndex * (c + 1) + kValue * c + 3 * kValue * c +
         2 * kValue * c + 2 * kValue * u;
}

// ---------------------------------------------------------------------------------------------
// Benchmarks

/// assemble_system (6.1, 6.2.9) from the rows, into a System reused across iterations; one
/// untimed assembly first, so the timed ones find their storage allocated, as in step().
void bm_assembly(benchmark::State& state, SceneKind kind) {
  const Problem& p = problem(kind, state.range(0));
  const cbps::Scene& scene = p.sim->scene();
  cbps::System sys;
  cbps::assemble_system(
      scene.bodies, p.rows, scene.world.gravity, scene.world.dt, scene.world.push, sys);
  for (auto _ : state) {
    cbps::assemble_system(
        scene.bodies, p.rows, scene.world.gravity, scene.world.dt, scene.world.push, sys);
    benchmark::DoNotOptimize(sys.A.valuePtr());
    benchmark::DoNotOptimize(sys.b.data());
  }
  set_size_counters(state, p.sys);
}

/// One projected Gauss-Seidel sweep over the explicit A (7.1.1).
void bm_pgs_sweep(benchmark::State& state, SceneKind kind) {
  const double bytes_per_s = bandwidth();
  const cbps::System& sys = problem(kind, state.range(0)).sys;
  cbps::VecX lambda = cbps::VecX::Zero(sys.rows());
  for (int k = 0; k < kWarmUpSweeps; ++k) {
    cbps::pgs_sweep(sys.problem(), lambda);
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(cbps::pgs_sweep(sys.problem(), lambda));
    benchmark::ClobberMemory();
  }
  if (!lambda.allFinite()) {
    state.SkipWithError("lambda is not finite");
    return;
  }
  set_sweep_counters(state, sys, explicit_sweep_bytes(sys), bytes_per_s);
}

/// One sweep of 7.1.1 in the matrix-free form, natural order: W and d are built before timing.
void bm_matrix_free_sweep(benchmark::State& state, SceneKind kind) {
  const double bytes_per_s = bandwidth();
  const cbps::System& sys = problem(kind, state.range(0)).sys;
  const cbps::MatrixFreePgs pgs(sys.J, sys.Minv);
  const std::vector<int> natural_order;
  cbps::VecX lambda = cbps::VecX::Zero(sys.rows());
  cbps::VecX u = pgs.impulse(lambda);
  for (int k = 0; k < kWarmUpSweeps; ++k) {
    pgs.sweep(sys.b, sys.cmin, sys.cmax, lambda, u, 1.0, natural_order);
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(pgs.sweep(sys.b, sys.cmin, sys.cmax, lambda, u, 1.0, natural_order));
    benchmark::ClobberMemory();
  }
  if (!lambda.allFinite() || !u.allFinite()) {
    state.SkipWithError("lambda or u is not finite");
    return;
  }
  set_sweep_counters(state, sys, matrix_free_sweep_bytes(sys), bytes_per_s);
}

/// solve_direct (6.2) from lambda = 0; reports its factorizations and residual (N).
void bm_direct(benchmark::State& state, SceneKind kind) {
  const cbps::System& sys = problem(kind, state.range(0)).sys;
  cbps::SolverSummary summary;
  for (auto _ : state) {
    cbps::VecX lambda = cbps::VecX::Zero(sys.rows());
    summary = cbps::solve_direct(sys.problem(), lambda);
    benchmark::DoNotOptimize(lambda.data());
  }
  if (!summary.ok()) {
    state.SkipWithError(summary.message.c_str());
    return;
  }
  set_size_counters(state, sys);
  state.counters["factorizations"] = summary.factorizations;
  state.counters["residual_N"] = summary.residual;
}

/// n = 10², 10³, 10⁴, 10⁵ links (rows).
void chain_sizes(benchmark::internal::Benchmark* b) {
  b->ArgName("n")->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMicrosecond);
}

/// base 4, 10, 20, 40, 91: 192, 1,200, 4,800, 19,200 and 99,372 rows (12 b²); 91 is the
/// largest base with at most 10⁵ rows.
void pyramid_sizes(benchmark::internal::Benchmark* b) {
  b->ArgName("base")->Arg(4)->Arg(10)->Arg(20)->Arg(40)->Arg(91)->Unit(benchmark::kMicrosecond);
}

/// The direct path on the pyramid: base 4 and 10 only (192 and 1,200 rows), see the top.
void pyramid_direct_sizes(benchmark::internal::Benchmark* b) {
  b->ArgName("base")->Arg(4)->Arg(10)->Unit(benchmark::kMicrosecond);
}

}  // namespace

BENCHMARK(bm_triad)->Name("bandwidth/triad")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_assembly, chain, SceneKind::Chain)->Name("assembly/chain")->Apply(chain_sizes);
BENCHMARK_CAPTURE(bm_assembly, pyramid, SceneKind::Pyramid)
    ->Name("assembly/pyramid")
    ->Apply(pyramid_sizes);
BENCHMARK_CAPTURE(bm_pgs_sweep, chain, SceneKind::Chain)
    ->Name("pgs_sweep/chain")
    ->Apply(chain_sizes);
BENCHMARK_CAPTURE(bm_pgs_sweep, pyramid, SceneKind::Pyramid)
    ->Name("pgs_sweep/pyramid")
    ->Apply(pyramid_sizes);
BENCHMARK_CAPTURE(bm_matrix_free_sweep, chain, SceneKind::Chain)
    ->Name("matrix_free_sweep/chain")
    ->Apply(chain_sizes);
BENCHMARK_CAPTURE(bm_matrix_free_sweep, pyramid, SceneKind::Pyramid)
    ->Name("matrix_free_sweep/pyramid")
    ->Apply(pyramid_sizes);
BENCHMARK_CAPTURE(bm_direct, chain, SceneKind::Chain)->Name("direct/chain")->Apply(chain_sizes);
BENCHMARK_CAPTURE(bm_direct, pyramid, SceneKind::Pyramid)
    ->Name("direct/pyramid")
    ->Apply(pyramid_direct_sizes);

BENCHMARK_MAIN();
