// cbps.Simulation and cbps.System for Python: stepping a scene (3.2 with 4–8, 12.3), its bodies'
// states, a run's trajectory as numpy arrays, and a step's system (6.1, 6.2.9) with the lambda
// and v2 the step found. Stepping releases the GIL; a Simulation serialises its own calls, so two
// Python threads may share one (each call waits for the other's to end).
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>

#include "cbps/base/error.hpp"
#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/studies/run.hpp"
#include "convert.hpp"

namespace cbps::python {

namespace {

using Clock = std::chrono::steady_clock;

/// The most steps one run() takes (by steps= or by duration=), 1e12: weeks at a microsecond a
/// step.
constexpr long kMaxSteps = 1000000000000L;

/// One step's system as Python sees it: a copy, so later steps (which reuse the simulation's
/// storage) never change it. `lambda` and `v2` are set for a step that ran (Simulation.system),
/// not for a system only built (Simulation.build_system).
struct SystemRecord {
  System sys;
  std::vector<std::string> columns;  ///< "<body>.vx" … "<body>.wz" per movable body (6.1.1)
  long step = 0;                     ///< 0-based index of the step this system is of
  double cfm = 0.0;                  ///< the scene's constraint-force mixing eps, 1/kg
  std::optional<VecX> lambda;        ///< c, N (6.2.1)
  std::optional<VecX> v2;            ///< 6n, m/s and rad/s (12.3.1)
  std::optional<StepReport> report;
  /// The bounds lambda satisfies: the system's, with Coulomb friction rows (5.4) at ∓mu
  /// lambda_n of the step's lambda, as `cbps explain` and `cbps matrices` show them.
  VecX cmin() const { return bounds().first; }
  VecX cmax() const { return bounds().second; }
  std::pair<VecX, VecX> bounds() const {
    if (!lambda || !sys.coulomb().any()) return {sys.cmin, sys.cmax};
    VecX lo, hi;
    coulomb_bounds(sys.problem(), sys.coulomb(), *lambda, lo, hi);
    return {lo, hi};
  }
};

/// A Simulation with the last step's system kept for Python.
class PySimulation {
 public:
  explicit PySimulation(const Scene& scene) : sim_(scene) {
    sim_.set_observer([this](const System& sys, const VecX& lambda, const VecX& v2) {
      if (!keep_) return;  // only the step whose system is asked for is copied
      auto record = std::make_shared<SystemRecord>();
      record->sys = sys;
      record->lambda = lambda;
      record->v2 = v2;
      record->step = sim_.steps_done();
      record->cfm = sim_.scene().solver.cfm;
      record->columns = column_labels(sim_.scene(), sys);
      last_ = std::move(record);
    });
  }
  PySimulation(const PySimulation&) = delete;
  PySimulation& operator=(const PySimulation&) = delete;

  /// f() under this simulation's lock with the GIL released (the lock is taken only without
  /// the GIL, so a thread waiting for it never blocks one that needs the GIL).
  template <class F>
  auto locked(F f) {
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    return f();
  }

  py::dict step() {
    const StepReport report = locked([this] { return step_keeping(true); });
    return step_report_dict(report);
  }

  py::dict run(const py::object& duration_in,
               const py::object& steps_in,
               const py::object& record_every_in);

  std::shared_ptr<SystemRecord> system() {
    const auto last = locked([this] { return last_; });
    if (!last)
      throw InputError("Simulation.system(): no step has been done yet; call step() or run()");
    return last;
  }

  std::shared_ptr<SystemRecord> build_system() {
    return locked([this] {
      auto record = std::make_shared<SystemRecord>();
      record->sys = sim_.build_system();
      record->step = sim_.steps_done();
      record->cfm = sim_.scene().solver.cfm;
      record->columns = column_labels(sim_.scene(), record->sys);
      return record;
    });
  }

  py::list bodies() {
    const std::vector<Body> bodies = locked([this] { return sim_.bodies(); });
    py::list out;
    for (const Body& b : bodies) out.append(body_dict(b));
    return out;
  }

  double time() {
    return locked([this] { return sim_.time(); });
  }
  long steps_done() {
    return locked([this] { return sim_.steps_done(); });
  }
  double energy() {
    return locked([this] { return sim_.energy(); });
  }
  double max_constraint_error() {
    return locked([this] { return sim_.max_constraint_error(); });
  }
  Scene scene() {
    return locked([this] { return sim_.scene(); });
  }
  std::vector<std::string> stages() {
    return locked([this] { return sim_.stages(); });
  }

 private:
  /// One step; `keep` copies its system for system(). Call with the lock held.
  StepReport step_keeping(bool keep) {
    keep_ = keep;
    StepReport report = sim_.step();
    keep_ = false;
    if (keep && last_) last_->report = report;
    return report;
  }

  Simulation sim_;
  std::mutex mutex_;
  bool keep_ = false;
  std::shared_ptr<SystemRecord> last_;
};

/// The steps of run(duration, steps): as `cbps run` counts them (--steps, else --duration,
/// else the scene's duration; the nearest whole number of steps of dt).
long step_count(const Scene& scene,
                const std::optional<double>& duration,
                const std::optional<long>& steps) {
  if (duration && steps) throw InputError("run: give duration or steps, not both");
  if (steps) {
    return *steps;  // 0 to kMaxSteps (run)
  }
  const double t = duration ? *duration : scene.duration;
  const std::string what =
      duration ? "run: duration " + number_text(t) : "run: the scene's duration " + number_text(t);
  if (!(t > 0.0) || !std::isfinite(t))
    throw InputError(what + " s: must be a positive finite time");
  const double count = t / scene.world.dt;
  if (count > static_cast<double>(kMaxSteps))
    throw InputError(what + " s: " + number_text(count) + " steps of dt = " +
                     number_text(scene.world.dt) + " s, more than a run can take (1e+12)");
  const long n = std::lround(count);
  if (n < 1)
    throw InputError(what + " s: shorter than half a step (dt = " + number_text(scene.world.dt) +
                     " s), so no step would run; use steps=1 or a longer duration");
  return n;
}

/// A (samples × bodies × width) array from `width` numbers per body per sample.
py::array_t<double> states(const std::vector<double>& values,
                           long samples,
                           long bodies,
                           long width) {
  py::array_t<double> a({samples, bodies, width});
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

/// What run() returns, gathered step by step without the GIL: the trajectory (t = start and
/// after every record_every-th step, as trajectory.csv) and one entry per step (as steps.csv).
/// Every 0.1 s the GIL is taken for a moment to let Python see its signals (Ctrl-C stops the
/// run).
class RunArrays : public StepObserver {
 public:
  explicit RunArrays(long record_every) : record_every_(record_every) {}

  void start(Simulation& sim) override {
    bodies_ = static_cast<long>(sim.scene().bodies.size());
    sample(sim);
  }

  bool after_step(const Simulation& sim, const StepReport& r, long done) override {
    step_t_.push_back(sim.time());
    rows_.push_back(r.rows);
    warm_rows_.push_back(r.warm_rows);
    contacts_.push_back(r.contacts);
    iterations_.push_back(r.solver.iterations);
    residual_.push_back(r.solver.residual);
    constraint_error_.push_back(r.max_constraint_error);
    energy_.push_back(sim.energy());
    wall_.push_back(r.wall_time_s);
    solve_.push_back(r.times.solve);
    routes_.push_back(r.solver.route);
    if (done % record_every_ == 0) sample(sim);
    if (Clock::now() - checked_ > std::chrono::milliseconds(100)) {
      checked_ = Clock::now();
      const py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) interrupted = true;
    }
    return !interrupted;
  }

  /// {"t", "x", "q", "v", "omega", "steps": {...}} (Simulation.run's documentation).
  py::dict dict() const {
    const long samples = static_cast<long>(t_.size());
    py::dict out;
    out["t"] = py::array_t<double>(static_cast<py::ssize_t>(samples), t_.data());
    out["x"] = states(x_, samples, bodies_, 3);
    out["q"] = states(q_, samples, bodies_, 4);
    out["v"] = states(v_, samples, bodies_, 3);
    out["omega"] = states(omega_, samples, bodies_, 3);
    py::dict per_step;
    const auto count = static_cast<py::ssize_t>(step_t_.size());
    per_step["t"] = py::array_t<double>(count, step_t_.data());
    per_step["rows"] = py::array_t<long>(count, rows_.data());
    per_step["warm_rows"] = py::array_t<long>(count, warm_rows_.data());
    per_step["contacts"] = py::array_t<long>(count, contacts_.data());
    per_step["iterations"] = py::array_t<long>(count, iterations_.data());
    per_step["residual"] = py::array_t<double>(count, residual_.data());
    per_step["max_constraint_error"] = py::array_t<double>(count, constraint_error_.data());
    per_step["energy"] = py::array_t<double>(count, energy_.data());
    per_step["wall_time_s"] = py::array_t<double>(count, wall_.data());
    per_step["solve_time_s"] = py::array_t<double>(count, solve_.data());
    per_step["direct_route"] = py::cast(routes_);  // a list of str, "" for other methods
    out["steps"] = per_step;
    return out;
  }

  bool interrupted = false;

 private:
  void sample(const Simulation& sim) {
    t_.push_back(sim.time());
    for (const Body& b : sim.scene().bodies) {
      const Vec3 vb = b.v(), wb = b.omega();
      x_.insert(x_.end(), {b.x.x(), b.x.y(), b.x.z()});
      q_.insert(q_.end(), {b.q.w(), b.q.x(), b.q.y(), b.q.z()});
      v_.insert(v_.end(), {vb.x(), vb.y(), vb.z()});
      omega_.insert(omega_.end(), {wb.x(), wb.y(), wb.z()});
    }
  }

  long record_every_;
  long bodies_ = 0;
  std::vector<double> t_, x_, q_, v_, omega_;
  std::vector<double> step_t_, residual_, constraint_error_, energy_, wall_, solve_;
  std::vector<std::string> routes_;  ///< SolverSummary::route per step
  std::vector<long> rows_, warm_rows_, contacts_, iterations_;
  Clock::time_point checked_ = Clock::now();
};

py::dict PySimulation::run(const py::object& duration_in,
                           const py::object& steps_in,
                           const py::object& record_every_in) {
  // The numbers, each named with its range (InputError, never pybind11's TypeError).
  const long record_every = static_cast<long>(
      whole_from_python(record_every_in, "run: record_every", 1, std::numeric_limits<long>::max()));
  std::optional<double> duration;
  if (!duration_in.is_none()) duration = real_from_python(duration_in, "run: duration");
  std::optional<long> steps;
  if (!steps_in.is_none())
    steps = static_cast<long>(whole_from_python(steps_in, "run: steps", 0, kMaxSteps));
  const long n = step_count(scene(), duration, steps);
  RunArrays arrays(record_every);
  /// The last step's system is kept for system(), as step() keeps it.
  class KeepLast : public StepObserver {
   public:
    KeepLast(PySimulation& owner, long steps) : owner_(owner), steps_(steps) {}
    void before_step(Simulation&, long index) override { owner_.keep_ = index == steps_ - 1; }
    bool after_step(const Simulation&, const StepReport& report, long) override {
      if (owner_.keep_ && owner_.last_) owner_.last_->report = report;
      owner_.keep_ = false;
      return true;
    }

   private:
    PySimulation& owner_;
    long steps_;
  } keep_last(*this, n);
  locked([&] {
    const RunTotals totals = run_steps(sim_, n, {&keep_last, &arrays});
    keep_ = false;
    if (totals.diverged) throw *totals.diverged;
    return 0;
  });
  if (arrays.interrupted) throw py::error_already_set();  // KeyboardInterrupt; the steps done stay
  return arrays.dict();
}

/// cbps.System's matrices and vectors (6.1, 6.2.9).
void bind_system_matrices(py::class_<SystemRecord, std::shared_ptr<SystemRecord>>& system) {
  system
      .def_property_readonly(
          "J", [](const SystemRecord& r) { return to_csr(r.sys.J); }, "c x 6n (6.1)")
      .def_property_readonly(
          "Minv", [](const SystemRecord& r) { return to_csr(r.sys.Minv); }, "6n x 6n (6.1.2)")
      .def_property_readonly(
          "A", [](const SystemRecord& r) { return to_csr(r.sys.A); }, "c x c, J Minv J^T, 1/kg")
      .def_property_readonly(
          "b",
          [](const SystemRecord& r) { return to_numpy(r.sys.b); },
          "c, upsilon/dt - J (v1/dt + Minv fext), m/s^2 (6.2.9)")
      .def_property_readonly(
          "v1", [](const SystemRecord& r) { return to_numpy(r.sys.v1); }, "6n (6.1.1)")
      .def_property_readonly(
          "fext", [](const SystemRecord& r) { return to_numpy(r.sys.fext); }, "6n (6.1.3)")
      .def_property_readonly(
          "upsilon",
          [](const SystemRecord& r) { return to_numpy(r.sys.upsilon); },
          "c, m/s (6.1.4; with the push terms under the original push, without under the "
          "improved one)")
      .def_property_readonly(
          "upsilon_push",
          [](const SystemRecord& r) { return to_numpy(r.sys.upsilon_push); },
          "c, each row's push term alone, m/s")
      .def_property_readonly(
          "cmin",
          [](const SystemRecord& r) { return to_numpy(r.cmin()); },
          "c, N (5.1); Coulomb friction rows at -mu lambda_n of lam")
      .def_property_readonly(
          "cmax",
          [](const SystemRecord& r) { return to_numpy(r.cmax()); },
          "c, N (5.1); Coulomb friction rows at +mu lambda_n of lam")
      .def_property_readonly(
          "cones",
          [](const SystemRecord& r) {
            return cones_dict(r.sys.cones() != nullptr ? *r.sys.cones() : FrictionContacts{});
          },
          "with friction=cone, the contacts in Coulomb's cone: {'law', 'normal_row', 'mu'} "
          "(their rows' cmin and cmax are not used; docs/cones.md); None otherwise");
}

/// cbps.System's solution, row facts and step.
void bind_system_solution(py::class_<SystemRecord, std::shared_ptr<SystemRecord>>& system) {
  system
      .def_property_readonly(
          "lam",
          [](const SystemRecord& r) -> py::object {
            return r.lambda ? py::object(to_numpy(*r.lambda)) : py::none();
          },
          "c, lambda of the step, N (6.2.1)")
      .def_property_readonly(
          "v2",
          [](const SystemRecord& r) -> py::object {
            return r.v2 ? py::object(to_numpy(*r.v2)) : py::none();
          },
          "6n, v1 + dt Minv (J^T lam + fext) (12.3.1)")
      .def_property_readonly(
          "row_labels", [](const SystemRecord& r) { return r.sys.labels; }, "one per row")
      .def_property_readonly(
          "column_labels",
          [](const SystemRecord& r) { return r.columns; },
          "'<body>.vx' ... '<body>.wz' per movable body (6.1.1)")
      .def_property_readonly(
          "kind",
          [](const SystemRecord& r) {
            std::vector<std::string> kinds;
            for (RowKind k : r.sys.kind) kinds.push_back(to_string(k));
            return kinds;
          },
          "each row's kind: 'distance', 'contact' or 'friction'")
      .def_property_readonly(
          "manifold",
          [](const SystemRecord& r) { return r.sys.manifold; },
          "each row's contact manifold, -1 for none (block PGS: solve(..., blocks=manifold))")
      .def_property_readonly(
          "dt", [](const SystemRecord& r) { return r.sys.dt; }, "s")
      .def_property_readonly(
          "cfm", [](const SystemRecord& r) { return r.cfm; }, "the scene's eps, 1/kg")
      .def_property_readonly(
          "push",
          [](const SystemRecord& r) {
            return r.sys.push == PushMode::Improved ? "improved" : "original";
          },
          "the push form b was made for")
      .def_property_readonly(
          "step", [](const SystemRecord& r) { return r.step; }, "0-based step index")
      .def_property_readonly(
          "report",
          [](const SystemRecord& r) -> py::object {
            return r.report ? py::object(step_report_dict(*r.report)) : py::none();
          },
          "the step's report (as Simulation.step() returns it), or None")
      .def("__repr__", [](const SystemRecord& r) {
        return "<cbps.System of step " + std::to_string(r.step) + ": " +
               count_text(r.sys.rows(), "row") + ", " +
               count_text(r.sys.blocks(), "movable body", "movable bodies") +
               (r.lambda ? ", solved>" : ", not solved>");
      });
}

}  // namespace

void bind_simulation(py::module_& m) {
  py::class_<SystemRecord, std::shared_ptr<SystemRecord>> system(
      m,
      "System",
      "One step's system (6.1, 6.2.9): sparse matrices as scipy.sparse.csr_matrix, vectors as "
      "numpy arrays, all copies. lam and v2 are the step's solution (None for a system from "
      "Simulation.build_system()).");
  bind_system_matrices(system);
  bind_system_solution(system);

  py::class_<PySimulation>(
      m, "Simulation", "A simulation of a scene (a copy of it): step(), run(), system().")
      .def(py::init<const Scene&>(), py::arg("scene"))
      .def("step",
           &PySimulation::step,
           "one step of dt (4, 5, 6.2.9, 7, 12.3.1, 3.2); returns the step's report as a dict "
           "(rows, iterations, residual (N), termination, solver summary, stage times...). "
           "DivergenceError leaves the bodies as they were before the step.")
      .def("run",
           &PySimulation::run,
           py::arg("duration") = py::none(),
           py::kw_only(),
           py::arg("steps") = py::none(),
           py::arg("record_every") = 1,
           "steps for `duration` s (the nearest whole number of steps; default the scene's "
           "duration) or `steps` steps; returns the trajectory: t (k), x (k, bodies, 3) m, q "
           "(k, bodies, 4) w x y z, v (k, bodies, 3) m/s, omega (k, bodies, 3) rad/s at the "
           "start and after every record_every-th step, and 'steps': per-step arrays t, rows, "
           "warm_rows, contacts, iterations, residual, max_constraint_error, energy, "
           "wall_time_s, solve_time_s, and direct_route (a list of str)")
      .def("system",
           &PySimulation::system,
           "the last step's system with its lam and v2 (InputError before the first step)")
      .def("build_system",
           &PySimulation::build_system,
           "the system of the current state, not solved (as `cbps matrices --step K` after K "
           "steps)")
      .def("bodies",
           &PySimulation::bodies,
           "the bodies' states: dicts of name, shape, static, mass, x, q, v, omega")
      .def_property_readonly("time", &PySimulation::time, "simulated time, s")
      .def_property_readonly("steps_done", &PySimulation::steps_done)
      .def_property_readonly("scene",
                             &PySimulation::scene,
                             "a copy of the simulated scene, its bodies in their current state")
      .def("energy",
           &PySimulation::energy,
           "kinetic plus gravitational potential energy -m g.x of the movable bodies, J")
      .def("max_constraint_error",
           &PySimulation::max_constraint_error,
           "max |c| over the distance constraints (5.2.2), m")
      .def("stages", &PySimulation::stages, "the stages the last step ran, in order");
}

}  // namespace cbps::python
