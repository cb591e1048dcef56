// Cost of one step's system, per nonzero of A, for the built-in chain of n = 10², 10³, 10⁴, 10⁵
// links (one distance row per link, so c = n and A = J Minv Jᵀ is tridiagonal, nnz(A) = 3n − 2):
//
//   build_system  the rows (5.2) and J, Minv, v1, fext, upsilon, cmin, cmax, A, b (6.1, 6.2.9)
//   pgs_sweep     one projected Gauss-Seidel sweep over A (7.1.1), lambda kept across sweeps
//
// and, to locate a cost that grows faster than nnz(A), the stages of build_system on their own:
// build_rows, assemble_J, assemble_Minv, stack_v1_fext (stack_velocities and stack_forces),
// compute_A, compute_b.
//
// Every benchmark reports nnz_A, rows, nnz_J and ns_per_nnz = CPU time per iteration / nnz(A), in
// ns. Linear scaling means ns_per_nnz stays flat in n; the target is ns_per_nnz(10⁵) ≤ 1.5 ×
// ns_per_nnz(10³). bench/summarize.py prints those ratios from the JSON output.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cbps/cbps.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"

namespace {

/// PGS sweeps before the timed ones, so lambda is no longer the zero guess.
constexpr int kWarmUpSweeps = 10;

/// The chain of n links, released along x and stepped a few times so that the links have left
/// the x axis and every row of J has its general pattern; built once per n and shared by all
/// benchmarks.
cbps::Simulation& chain(long n) {
  static std::map<long, std::unique_ptr<cbps::Simulation>> cache;
  std::unique_ptr<cbps::Simulation>& sim = cache[n];
  if (!sim) {
    cbps::Scene scene = cbps::make_builtin_scene("chain", {{"n", std::to_string(n)}});
    scene.solver.max_iterations = 10;
    scene.solver.tolerance = 0.0;
    sim = std::make_unique<cbps::Simulation>(scene);
    for (int s = 0; s < 5; ++s) sim->step();
  }
  return *sim;
}

/// nnz_A, rows, nnz_J, and ns_per_nnz: the rate counter nnz(A)·10⁻⁹ per CPU second, inverted, is
/// the CPU time of one iteration divided by nnz(A), in ns.
void set_counters(benchmark::State& state, const cbps::System& sys) {
  const auto nnz = static_cast<double>(sys.A.nonZeros());
  state.counters["nnz_A"] = nnz;
  state.counters["rows"] = sys.rows();
  state.counters["nnz_J"] = static_cast<double>(sys.J.nonZeros());
  state.counters["ns_per_nnz"] = benchmark::Counter(
      nnz * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// All of one step's assembly (6.1, 6.2.9), as Simulation::step does it: into the simulation's
/// own System, whose storage is reused from step to step.
void bm_build_system(benchmark::State& state) {
  cbps::Simulation& sim = chain(state.range(0));
  for (auto _ : state) {
    const cbps::System& sys = sim.assemble();
    benchmark::DoNotOptimize(sys.A.valuePtr());
    benchmark::DoNotOptimize(sys.b.data());
  }
  set_counters(state, sim.build_system());
}

/// One PGS sweep (7.1.1) over the chain's A; lambda carries over from sweep to sweep.
void bm_pgs_sweep(benchmark::State& state) {
  const cbps::System sys = chain(state.range(0)).build_system();
  cbps::VecX lambda = cbps::VecX::Zero(sys.rows());
  for (int it = 0; it < kWarmUpSweeps; ++it) {
    cbps::pgs_sweep(sys.problem(), lambda);
  }
  if (!lambda.allFinite()) {
    state.SkipWithError("lambda is not finite after the warm-up sweeps");
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(cbps::pgs_sweep(sys.problem(), lambda));
    benchmark::ClobberMemory();
  }
  if (!lambda.allFinite()) {
    state.SkipWithError("lambda is not finite after the timed sweeps");
    return;
  }
  set_counters(state, sys);
}

// The stages of build_system, each on inputs the previous stages made once.

void bm_build_rows(benchmark::State& state) {
  const cbps::Simulation& sim = chain(state.range(0));
  for (auto _ : state) {
    std::vector<cbps::Row> rows = sim.build_rows();
    benchmark::DoNotOptimize(rows.data());
  }
  set_counters(state, sim.build_system());
}

void bm_assemble_J(benchmark::State& state) {
  const cbps::Simulation& sim = chain(state.range(0));
  const std::vector<cbps::Row> rows = sim.build_rows();
  const cbps::System sys = sim.build_system();
  for (auto _ : state) {
    auto J = cbps::assemble_J(rows, sys.block_of_body, sys.blocks());
    benchmark::DoNotOptimize(J.valuePtr());
  }
  set_counters(state, sys);
}

void bm_assemble_Minv(benchmark::State& state) {
  const cbps::Simulation& sim = chain(state.range(0));
  const cbps::System sys = sim.build_system();
  for (auto _ : state) {
    cbps::SpMat Minv = cbps::assemble_Minv(sim.scene().bodies, sys.body_of_block);
    benchmark::DoNotOptimize(Minv.valuePtr());
  }
  set_counters(state, sys);
}

void bm_stack_v1_fext(benchmark::State& state) {
  const cbps::Simulation& sim = chain(state.range(0));
  const cbps::System sys = sim.build_system();
  const cbps::Vec3 gravity = sim.scene().world.gravity;
  for (auto _ : state) {
    cbps::VecX v1 = cbps::stack_velocities(sim.scene().bodies, sys.body_of_block);
    cbps::VecX fext = cbps::stack_forces(sim.scene().bodies, sys.body_of_block, gravity);
    benchmark::DoNotOptimize(v1.data());
    benchmark::DoNotOptimize(fext.data());
  }
  set_counters(state, sys);
}

void bm_compute_A(benchmark::State& state) {
  const cbps::System sys = chain(state.range(0)).build_system();
  for (auto _ : state) {
    cbps::SpMat A = cbps::compute_A(sys.J, sys.Minv);
    benchmark::DoNotOptimize(A.valuePtr());
  }
  set_counters(state, sys);
}

void bm_compute_b(benchmark::State& state) {
  const cbps::System sys = chain(state.range(0)).build_system();
  for (auto _ : state) {
    cbps::VecX b = cbps::compute_b(sys.upsilon, sys.J, sys.v1, sys.Minv, sys.fext, sys.dt);
    benchmark::DoNotOptimize(b.data());
  }
  set_counters(state, sys);
}

/// n = 10², 10³, 10⁴, 10⁵ links.
void chain_sizes(benchmark::internal::Benchmark* b) {
  b->ArgName("n")->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMicrosecond);
}

}  // namespace

BENCHMARK(bm_build_system)->Name("build_system")->Apply(chain_sizes);
BENCHMARK(bm_pgs_sweep)->Name("pgs_sweep")->Apply(chain_sizes);
BENCHMARK(bm_build_rows)->Name("part/build_rows")->Apply(chain_sizes);
BENCHMARK(bm_assemble_J)->Name("part/assemble_J")->Apply(chain_sizes);
BENCHMARK(bm_assemble_Minv)->Name("part/assemble_Minv")->Apply(chain_sizes);
BENCHMARK(bm_stack_v1_fext)->Name("part/stack_v1_fext")->Apply(chain_sizes);
BENCHMARK(bm_compute_A)->Name("part/compute_A")->Apply(chain_sizes);
BENCHMARK(bm_compute_b)->Name("part/compute_b")->Apply(chain_sizes);

BENCHMARK_MAIN();
