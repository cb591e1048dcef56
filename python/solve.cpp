// cbps.solve for Python: the boxed problem of 6.2 (find lambda in [cmin, cmax] with
// w = A lambda − b ≥ 0 at cmin, ≤ 0 at cmax, = 0 between) on any (A, b, cmin, cmax) from Python,
// by every method `cbps converge` knows, named by the --solver grammar (parse_solver_spec:
// the paper's method by its name, "psor:1.3", "apgd:restart=off", "lemke", ...), each through the
// one solve() of the library as `cbps lcp --solver SPEC` solves it.
// The solve runs without the GIL; the history of the iterative methods is the natural-map
// residual after every sweep and the sweeps' time, recorded outside the solver's clock as
// `cbps converge` records it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>

#include "cbps/base/error.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/scene/scene.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/solvers/threads.hpp"
#include "cbps/studies/check.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "cbps/system/unit_free.hpp"
#include "convert.hpp"

namespace cbps::python {

namespace {

using Clock = std::chrono::steady_clock;

/// The default of solve(history_limit=): a million entries, 20 MB (an int and two doubles each).
constexpr long long kHistoryLimit = 1000000;

/// The per-sweep history, at most `limit` (>= 2) entries: sweep 0 (the guess), then every sweep
/// while they fit. When an entry more would not fit, every other entry is dropped and from then
/// on only every 2nd sweep is recorded (then every 4th, 8th, ...), so the entries stay evenly
/// spread over the whole solve in bounded memory; finish() makes the last sweep the last entry.
struct History {
  std::size_t limit = static_cast<std::size_t>(kHistoryLimit);
  long long stride = 1;  ///< only sweeps k with k % stride == 0 are recorded (until the last)
  std::vector<int> iteration;
  std::vector<double> residual;  ///< natural-map residual (6.2), N
  std::vector<double> time_s;    ///< the solver's time so far, s
  bool wants(int k) const { return k % stride == 0; }
  void add(int k, double r, double t) {
    iteration.push_back(k);
    residual.push_back(r);
    time_s.push_back(t);
    if (iteration.size() > limit) thin();
  }
  /// Keeps the entries at multiples of twice the stride: the recorded sweeps 0, s, 2s, ..., K
  /// (K / s + 1 = limit + 1 of them) become 0, 2s, 4s, ..., at most limit / 2 + 1 <= limit.
  void thin() {
    stride *= 2;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < iteration.size(); ++i) {
      if (iteration[i] % stride != 0) continue;
      iteration[kept] = iteration[i];
      residual[kept] = residual[i];
      time_s[kept] = time_s[i];
      ++kept;
    }
    iteration.resize(kept);
    residual.resize(kept);
    time_s.resize(kept);
  }
  /// The last sweep k (residual r, time t) as the last entry, unless it is already; when the
  /// history is full it takes the place of the latest entry before it.
  void finish(int k, double r, double t) {
    if (!iteration.empty() && iteration.back() == k) return;
    if (iteration.size() >= limit) {
      iteration.pop_back();
      residual.pop_back();
      time_s.pop_back();
    }
    iteration.push_back(k);
    residual.push_back(r);
    time_s.push_back(t);
  }
  py::dict dict() const {
    py::dict d;
    const auto n = static_cast<py::ssize_t>(iteration.size());
    d["iteration"] = py::array_t<int>(n, iteration.data());
    d["residual"] = py::array_t<double>(n, residual.data());
    d["time_s"] = py::array_t<double>(n, time_s.data());
    return d;
  }
};

RowKind kind_of(const std::string& name, long k) {
  if (name == "distance") return RowKind::Distance;
  if (name == "contact") return RowKind::Contact;
  if (name == "friction") return RowKind::Friction;
  throw InputError("kinds: entry " + std::to_string(k) + " '" + name +
                   "': expected distance, contact or friction");
}

/// cones= of solve(): {'law', 'normal_row', 'mu'} (System.cones' form), checked against c rows.
FrictionContacts cones_from_python(const py::object& cones, long c) {
  if (!py::isinstance<py::dict>(cones))
    throw InputError("cones: expected a dict {'law', 'normal_row', 'mu'} (System.cones)");
  const py::dict d = cones.cast<py::dict>();
  for (const char* key : {"law", "normal_row", "mu"})
    if (!d.contains(key)) throw InputError(std::string("cones: has no '") + key + "'");
  FrictionContacts out;
  if (!py::isinstance<py::str>(d["law"]) ||
      !cone_law_from_string(d["law"].cast<std::string>(), out.law))
    throw InputError("cones: 'law' must be 'coulomb' or 'ccp'");
  out.mu = vector_from_python(d["mu"], "cones: 'mu'", -1);
  const VecX rows = vector_from_python(d["normal_row"], "cones: 'normal_row'", out.mu.size());
  for (Eigen::Index i = 0; i < rows.size(); ++i) {
    if (!(rows(i) >= 0.0 && rows(i) < double(c) && rows(i) == std::floor(rows(i))))
      throw InputError("cones: 'normal_row' entry " + std::to_string(i) + " " +
                       number_text(rows(i)) + ": not a row (0 to " + std::to_string(c - 1) + ")");
    out.normal.push_back(static_cast<int>(rows(i)));
  }
  const std::string error = cone_contacts_error(out, c);
  if (!error.empty()) throw InputError("cones: " + error);
  return out;
}

/// The inputs of a solve, converted and checked with the GIL held.
struct Inputs {
  StoredProblem p;  ///< A, b, cmin, cmax and, when given, J and Minv
  VecX lambda;      ///< the guess
  std::vector<int> blocks;
  std::vector<RowKind> kinds;
  FrictionContacts cones;  ///< contacts in Coulomb's cone (cones=), none for the boxed problem
  BoxedProblem problem() const {
    BoxedProblem bp = p.J.rows() > 0 ? BoxedProblem{p.A, p.b, p.cmin, p.cmax, &p.J, &p.Minv}
                                     : BoxedProblem{p.A, p.b, p.cmin, p.cmax};
    if (!blocks.empty()) bp.blocks = &blocks;
    if (!kinds.empty()) bp.kinds = &kinds;
    if (!cones.empty()) bp.cones = &cones;
    return bp;
  }
};

Inputs read_inputs(const py::object& A,
                   const py::object& b,
                   const py::object& cmin,
                   const py::object& cmax,
                   const py::object& lam0,
                   const py::object& J,
                   const py::object& Minv,
                   const py::object& blocks,
                   const py::object& kinds,
                   const py::object& cones) {
  Inputs in;
  StoredProblem& p = in.p;
  p.A = sparse_from_python(A, "A");
  const long c = p.A.rows();
  if (p.A.cols() != c)
    throw InputError("A: must be square, got " + std::to_string(c) + " x " +
                     std::to_string(p.A.cols()));
  p.b = vector_from_python(b, "b", c);
  p.cmin = vector_from_python(cmin, "cmin", c, true);
  p.cmax = vector_from_python(cmax, "cmax", c, true);
  for (long k = 0; k < c; ++k) {
    if (p.cmin(k) == kInf || p.cmax(k) == -kInf || p.cmin(k) > p.cmax(k))
      throw InputError("cmin, cmax: row " + std::to_string(k) + ": [" + number_text(p.cmin(k)) +
                       ", " + number_text(p.cmax(k)) + "] is not an interval of lambda");
  }
  in.lambda = lam0.is_none() ? VecX::Zero(c) : vector_from_python(lam0, "lam0", c);
  if (J.is_none() != Minv.is_none())
    throw InputError("J, Minv: give both (A = J Minv J^T) or neither");
  if (!J.is_none()) {
    p.J = SpMatRow(sparse_from_python(J, "J"));
    p.Minv = sparse_from_python(Minv, "Minv");
    if (p.J.rows() != c || p.Minv.rows() != p.J.cols() || p.Minv.cols() != p.J.cols())
      throw InputError("J, Minv: J must be c x 6n and Minv 6n x 6n with c = " + std::to_string(c) +
                       " rows of A; got J " + std::to_string(p.J.rows()) + " x " +
                       std::to_string(p.J.cols()) + ", Minv " + std::to_string(p.Minv.rows()) +
                       " x " + std::to_string(p.Minv.cols()));
  }
  if (!blocks.is_none()) {
    // Whole ids in int's range (block_pgs.hpp: a negative id is a row alone), numpy or a list.
    py::object ids;
    try {
      ids = py::module_::import("numpy").attr("asarray")(blocks, py::arg("dtype") = "object");
    } catch (const py::error_already_set& e) {
      throw InputError("blocks: not a vector of whole numbers (" + std::string(e.what()) + ")");
    }
    if (ids.attr("ndim").cast<int>() != 1)
      throw InputError("blocks: expected a vector of whole numbers, one per row");
    long k = 0;
    for (const py::handle id : ids)
      in.blocks.push_back(static_cast<int>(whole_from_python(id,
                                                             "blocks: entry " + std::to_string(k++),
                                                             std::numeric_limits<int>::min(),
                                                             std::numeric_limits<int>::max())));
    if (static_cast<long>(in.blocks.size()) != c)
      throw InputError("blocks: has " + std::to_string(in.blocks.size()) + " entries, expected " +
                       std::to_string(c));
  }
  if (!kinds.is_none()) {
    const auto names = kinds.cast<std::vector<std::string>>();
    if (static_cast<long>(names.size()) != c)
      throw InputError("kinds: has " + std::to_string(names.size()) + " entries, expected " +
                       std::to_string(c));
    for (std::size_t k = 0; k < names.size(); ++k)
      in.kinds.push_back(kind_of(names[k], static_cast<long>(k)));
  }
  if (!cones.is_none()) in.cones = cones_from_python(cones, c);
  return in;
}

/// What a method needs beyond (A, b, cmin, cmax), as `cbps converge` and `cbps lcp` ask it.
void require_method_inputs(const SolverSpec& spec, const Inputs& in) {
  const std::string what = "method '" + spec.text + "'";
  if (needs_jacobian(spec.method) && in.p.J.rows() == 0)
    throw InputError(what + ": it reads J (matrix-free sweeps on J and Minv; shock takes its " +
                     "levels from J's bodies); pass J= and Minv=");
  if (spec.contacts_first && in.kinds.empty())
    throw InputError(what + ": contacts_first needs each row's kind; pass kinds=");
  if (is_peer(spec.method)) {  // a peer meets the problem as it is, or says why it cannot
    const std::string refusal = peer_refusal(spec.method, in.problem());
    if (!refusal.empty()) throw InputError(what + ": " + refusal);
    return;
  }
  if (!is_iterative(spec.method)) {
    // The exact paths solve the QP of 6.2; direct on cones takes any A (needs_symmetric).
    if (needs_symmetric(spec.method, !in.cones.empty())) require_symmetric(in.p, what);
    return;
  }
  // The sweeps divide by A_kk (7.1.1), as `cbps lcp` checks before PGS and Jacobi.
  for (Eigen::Index k = 0; k < in.p.A.rows(); ++k)
    if (!(in.p.A.coeff(k, k) > 0.0))
      throw InputError(what + ": A[" + std::to_string(k) + "," + std::to_string(k) +
                       "] = " + number_text(in.p.A.coeff(k, k)) +
                       "; the iterative methods need a positive diagonal");
}

/// cbps's verdict on lambda (system/unit_free.hpp), as `cbps lcp` gives it: `unit_free` (a dict
/// of `relative`, `residual` (N) and `scale` (N)) and `solved`.
void add_verdict(py::dict& s, const BoxedProblem& problem, const VecX& lambda, double cfm) {
  const UnitFreeResidual u = unit_free_residual(problem, lambda, cfm);
  py::dict d;
  d["relative"] = u.relative;
  d["residual"] = u.residual;
  d["scale"] = u.scale;
  s["unit_free"] = d;
  s["solved"] = is_solved(u, lambda);
}

/// solve()'s numbers, read and checked.
struct SolveNumbers {
  int iterations = 0;
  std::uint64_t seed = 0;
  long long history_limit = 0;
  double tolerance = 0.0, delta_tolerance = 0.0, cfm = 0.0;
};

/// Each number named with its range (InputError, never pybind11's TypeError).
SolveNumbers read_numbers(const py::object& iterations,
                          const py::object& seed,
                          const py::object& history_limit,
                          const py::object& tolerance,
                          const py::object& delta_tolerance,
                          const py::object& cfm) {
  constexpr long long kMaxInt = std::numeric_limits<int>::max();  // 2**31 - 1
  SolveNumbers n;
  n.iterations = static_cast<int>(whole_from_python(iterations, "iterations", 1, kMaxInt));
  n.seed = unsigned_from_python(seed, "seed", 0, std::numeric_limits<std::uint64_t>::max());
  n.history_limit = whole_from_python(history_limit, "history_limit", 2, kMaxInt);
  for (auto [name, in, value] : {std::tuple{"tolerance", &tolerance, &n.tolerance},
                                 {"delta_tolerance", &delta_tolerance, &n.delta_tolerance},
                                 {"cfm", &cfm, &n.cfm}}) {
    *value = real_from_python(*in, name);
    if (!(*value >= 0.0) || !std::isfinite(*value))
      throw InputError(std::string(name) + " " + number_text(*value) +
                       ": must be a finite number >= 0");
  }
  return n;
}

/// The spec as a scene's solver block takes it (its warm factors only matter between steps),
/// with solve()'s numbers.
SolverOptions options_of(const SolverSpec& spec, const SolveNumbers& n, bool split_islands) {
  SolverSettings settings;
  apply_solver_spec(spec, settings);
  settings.max_iterations = n.iterations;
  settings.tolerance = n.tolerance;
  settings.delta_tolerance = n.delta_tolerance;
  settings.cfm = n.cfm;
  settings.seed = n.seed;
  settings.split_islands = split_islands;
  return settings.options();
}

py::tuple solve_py(const py::object& A,
                   const py::object& b,
                   const py::object& cmin,
                   const py::object& cmax,
                   const std::string& method,
                   const py::object& lam0,
                   const py::object& iterations_in,
                   const py::object& tolerance_in,
                   const py::object& delta_tolerance_in,
                   const py::object& cfm_in,
                   const py::object& seed_in,
                   bool split_islands,
                   const py::object& J,
                   const py::object& Minv,
                   const py::object& blocks,
                   const py::object& kinds,
                   const py::object& cones,
                   bool history,
                   const py::object& history_limit_in,
                   bool unit_free) {
  // The numbers first, then the spec, then the data.
  const SolveNumbers n = read_numbers(
      iterations_in, seed_in, history_limit_in, tolerance_in, delta_tolerance_in, cfm_in);
  const double cfm = n.cfm;
  // The spec first: a bad method is reported before the data are read.
  const SolverSpec spec = parse_solver_spec(method, "method");
  const Inputs in = read_inputs(A, b, cmin, cmax, lam0, J, Minv, blocks, kinds, cones);
  require_method_inputs(spec, in);

  SolverOptions options = options_of(spec, n, split_islands);
  options.tolerance_unit_free = unit_free;
  // The per-sweep history (iterative methods on the whole problem: with split_islands each
  // island sweeps apart, so there is no whole iterate to measure).
  const bool per_sweep =
      history && is_iterative(spec.method) && !is_peer(spec.method) && !split_islands;
  // The residual is that of the problem solved, A + eps E (6.2).
  const BoxedProblem problem = in.problem();
  const auto residual = [&](const VecX& l) { return natural_map_residual(problem, l, cfm); };
  History h;
  h.limit = static_cast<std::size_t>(n.history_limit);
  if (per_sweep) {
    const auto expected = static_cast<std::size_t>(n.iterations) + 2;  // the guess and the sweeps
    const std::size_t capacity = std::min(h.limit + 1, expected);
    h.iteration.reserve(capacity);
    h.residual.reserve(capacity);
    h.time_s.reserve(capacity);
  }
  // Every sweep of the iterative methods comes here (without the GIL): its history entry, and
  // Ctrl-C. Every 0.1 s the GIL is taken for a moment to let Python see its signals, as
  // Simulation.run does; a signal ends the solve (Termination::Stopped, then KeyboardInterrupt).
  bool interrupted = false;
  auto checked = Clock::now();
  int last_k = 0;
  double last_time = 0.0;
  if (is_iterative(spec.method))
    options.after_sweep = [&](int k, const VecX& lambda, double time_s) {
      if (per_sweep) {
        if (h.wants(k)) h.add(k, residual(lambda), time_s);
        last_k = k;
        last_time = time_s;
      }
      if (Clock::now() - checked > std::chrono::milliseconds(100)) {
        checked = Clock::now();
        const py::gil_scoped_acquire acquire;
        interrupted = interrupted || PyErr_CheckSignals() != 0;
      }
      return !interrupted;  // with split_islands: every island after it stops at its first sweep
    };
  VecX lambda = in.lambda;
  SolverSummary summary;
  {
    const py::gil_scoped_release release;
    const double guess = residual(lambda);
    if (per_sweep) h.add(0, guess, 0.0);
    summary = solve(in.problem(), lambda, options);
    if (interrupted) {
      // KeyboardInterrupt (set by PyErr_CheckSignals), raised below with the GIL back
    } else if (per_sweep) {
      if (last_k > 0 && h.iteration.back() != last_k) h.finish(last_k, residual(lambda), last_time);
    } else if (history && !split_islands) {
      h.add(0, guess, 0.0);
      h.add(std::max(1, summary.iterations), residual(lambda), summary.wall_time_s);
    }
  }
  if (interrupted) throw py::error_already_set();
  py::dict s = summary_dict(summary);
  add_verdict(s, problem, lambda, cfm);
  s["method"] = spec.text;
  s["history"] = history && !split_islands ? py::object(h.dict()) : py::none();
  return py::make_tuple(to_numpy(lambda), s);
}

/// The methods' names and the --solver grammar.
void bind_methods(py::module_& m) {
  m.def(
      "methods",
      [] {
        std::vector<std::string> names;
        for (const MethodEntry* e : method_entries()) names.emplace_back(e->name);
        return names;
      },
      "the names of every method solve() and Scene.solver take");
  m.def(
      "parse_solver_spec",
      [](const std::string& text) {
        const SolverSpec spec = parse_solver_spec(text, "spec");
        py::dict d;
        d["text"] = spec.text;
        d["method"] = std::string(to_string(spec.method));
        d["relaxation"] = spec.relaxation;
        d["order"] = to_string(spec.order);
        d["contacts_first"] = spec.contacts_first;
        d["warm"] = spec.warm;
        d["warm_friction"] =
            spec.warm_friction ? py::object(py::float_(*spec.warm_friction)) : py::none();
        py::dict parameters;
        for (const auto& [key, value] : method_parameters(spec.method, spec.methods))
          parameters[py::str(key)] = value;
        d["parameters"] = parameters;
        return d;
      },
      py::arg("text"),
      "a --solver spec parsed as the command line parses it (InputError naming what is wrong)");
  m.def("solver_spec_help",
        &solver_spec_help,
        "every name the --solver grammar accepts, one line each, as `--help` prints it");
}

/// cbps.check: a given lambda judged as `cbps check` judges it (studies/check.hpp).
py::object check_py(const py::object& A,
                    const py::object& b,
                    const py::object& cmin,
                    const py::object& cmax,
                    const py::object& lam,
                    const py::object& cones,
                    const py::object& J,
                    const py::object& Minv,
                    double cfm,
                    int worst,
                    bool exact) {
  if (!std::isfinite(cfm) || cfm < 0.0) throw InputError("cfm: must be finite and >= 0");
  if (worst < 0) throw InputError("worst: must be >= 0");
  Inputs in = read_inputs(A, b, cmin, cmax, py::none(), J, Minv, py::none(), py::none(), cones);
  in.p.cones = in.cones;
  in.p.cfm = cfm;
  const VecX lambda = vector_from_python(lam, "lam", in.p.rows());
  CheckSettings settings;
  settings.worst = worst;
  settings.exact = exact;
  CheckReport report;
  {
    py::gil_scoped_release release;
    report = check_lambda(in.p, lambda, settings);
  }
  return py::module_::import("json").attr("loads")(check_json("python", report).dump());
}

/// The threads of the libraries under the exact path.
void bind_threads(py::module_& m) {
  // The libraries' threads under the exact path (cbps/solvers/threads.hpp): the command line's
  // --threads, which the module leaves to the caller (the BLAS is numpy's too when it is the
  // same library).
  const auto report = [](const ThreadReport& r) {
    py::dict d;
    d["requested"] = r.requested;
    d["blas"] = r.blas;
    d["blas_kind"] = r.blas_kind;
    d["blas_threads"] = r.blas_threads;
    d["openmp_threads"] = r.openmp_threads;
    return d;
  };
  m.def(
      "set_threads",
      [report](int threads) {
        if (threads < 0) throw InputError("threads " + std::to_string(threads) + ": must be >= 0");
        return report(set_threads(threads));
      },
      py::arg("threads"),
      "the threads of the BLAS and OpenMP under the exact path (CHOLMOD), as the command line's "
      "--threads N sets them (1: one thread, CHOLMOD's own parallel loops included; 0: the "
      "libraries' defaults); for the whole process, numpy's BLAS too when it is the same "
      "library. Returns what they run with now, as cbps.threads()");
  m.def(
      "threads",
      [report]() { return report(thread_report()); },
      "what the libraries under the exact path run with: requested, blas (the library's file), "
      "blas_kind, blas_threads, openmp_threads (1 when OpenMP's regions are inactive, 0 without "
      "OpenMP), as summary.json's threads");
}

}  // namespace

void bind_solve(py::module_& m) {
  m.def("check",
        &check_py,
        py::arg("A"),
        py::arg("b"),
        py::arg("cmin"),
        py::arg("cmax"),
        py::arg("lam"),
        py::kw_only(),
        py::arg("cones") = py::none(),
        py::arg("J") = py::none(),
        py::arg("Minv") = py::none(),
        py::arg("cfm") = 0.0,
        py::arg("worst") = 10,
        py::arg("exact") = true,
        "judges lam against the problem w = A lam - b, cmin <= lam <= cmax (cones as for solve; "
        "J and Minv give the distance of J^T lam from the exact answer's) as `cbps check` does, "
        "and returns its JSON report as a dict (docs/outputs.md, cbps check): solved, unit_free "
        "{relative, residual, scale}, natural_map, cone, statuses, worst (the largest terms), "
        "exact (the distance from direct's answer, unless exact=False). InputError for a lam "
        "of the wrong length or not finite");
  m.def(
      "solve",
      &solve_py,
      py::arg("A"),
      py::arg("b"),
      py::arg("cmin"),
      py::arg("cmax"),
      py::arg("method") = std::string(to_string(kPaperMethod)),
      py::kw_only(),
      py::arg("lam0") = py::none(),
      py::arg("iterations") = kProblemIterations,
      py::arg("tolerance") = SolveSettings{}.tolerance,
      py::arg("delta_tolerance") = 0.0,
      py::arg("cfm") = 0.0,
      py::arg("seed") = 0,
      py::arg("split_islands") = false,
      py::arg("J") = py::none(),
      py::arg("Minv") = py::none(),
      py::arg("blocks") = py::none(),
      py::arg("kinds") = py::none(),
      py::arg("cones") = py::none(),
      py::arg("history") = true,
      py::arg("history_limit") = kHistoryLimit,
      py::arg("unit_free") = false,
      "Solves the boxed problem (6.2) w = A lam - b, cmin <= lam <= cmax, by `method` (a --solver "
      "spec: 'pgs', 'psor:1.3', 'jacobi:0.7', 'sgs', 'block-pgs', 'matrix-free', 'direct', "
      "'active-set', 'pgs-nesterov', 'apgd:restart=off', 'nncg', 'pgs-sm', 'admm', 'rbgs', "
      "'shock', 'lemke' (dense), ...) from lam0 (default 0), with the defaults of `cbps lcp` "
      "(iterations 10000, tolerance 1e-10 N; unit_free=True: the iterative methods stop only where"
      " the unit-free residual is within the tolerance too, and direct where it is, as `cbps "
      "lcp` stops on a Siconos or FCLIB file: pass `not problem.folder` for a read_problem's "
      "problem). A: scipy.sparse or "
      "dense; b, cmin, cmax: vectors (bounds may be +-inf). J and Minv (A = J Minv J^T) for "
      "matrix-free and shock; blocks (contact manifold per row, -1 alone) for block-pgs; kinds "
      "('distance', 'contact', 'friction') for contacts_first; cones (a dict {'law': 'coulomb' or "
      "'ccp', 'normal_row': [...], 'mu': [...]}, as System.cones and Problem.cones give it) puts "
      "those contacts' rows in Coulomb's cone, which nsgs and direct solve (also siconos:fc3d-* "
      "under Coulomb's law, apgd, admm and pgs-nesterov under ccp; docs/cones.md). Returns (lam, "
      "summary): summary is a dict of iterations, residual (N), termination, message, wall_time_s,"
      " ... and history {iteration, residual, time_s} after every sweep (sweep 0: the guess), at "
      "most history_limit entries (default 1000000: beyond it every 2nd, 4th, ... sweep, evenly "
      "over the whole solve, and the last); history=False: None. Numbers out of range raise "
      "InputError (iterations and history_limit whole, up to 2**31 - 1; seed whole >= 0; "
      "tolerance, delta_tolerance, cfm finite >= 0). Releases the GIL while solving; Ctrl-C stops "
      "the iterative methods within 0.1 s (KeyboardInterrupt).");
  bind_methods(m);
  bind_threads(m);
}

}  // namespace cbps::python
