#!/usr/bin/python3
"""Checks that the committed results the documents' numbers are generated from
(validation/results/**, bench/results/*.json; scripts/doc_tables.py) still match what the
current build computes: for each family of committed results it reruns a cheap sample (one or
a few entries: a small scene, one solver, a short run) the way the committed file was produced,
and compares the deterministic quantities (statuses, counts, residuals, errors, positions; never
wall times or memory) with the committed values, each to a tolerance stated below.

    /usr/bin/python3 scripts/check_results_drift.py BUILD_DIR [--only NAME] [--list]

BUILD_DIR is a build folder (e.g. build/release). --only NAME (repeatable, or NAME,NAME) runs the
samples whose name is NAME or starts with NAME (e.g. --only contacts, --only distributed);
--list lists the samples, the committed file each checks and how that file is produced.

One line per compared entry: the verdict (ok, DRIFT, PENDING), the committed file, the entry,
the committed and the measured value and the tolerance. A family that needs what the build lacks
(Siconos/Bullet peers, PETSc with mpirun, the Python module, the benchmarks) is skipped with the
reason. PENDING marks a drift that is known and not yet regenerated (PENDING below: why, and the
command that regenerates it); it is printed loudly and does not fail the check, but a pending
entry whose measured value moves again is a DRIFT. Exit status 0 when every entry agrees (or is
pending), 1 when one drifted (each listed at the end), 2 on bad usage or a missing build product
(the message names the target that builds it).

The CTest test `results-drift` (tests/CMakeLists.txt) runs it on the build under test;
validation/README.md, "Checking the committed results against the build", says what it reruns.
Needs Debian's /usr/bin/python3 with numpy (the pendulum report, the problem library).
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "validation"))
PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
PROG = "check_results_drift"
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}


# ---------------------------------------------------------------------------------------------
# Tolerances: each is (text, test(committed, measured) -> bool).
#
# EXACT  statuses, routes, and counts of single-process runs (steps, rows, sweeps, pivots,
#        factorizations, steps missing a contact): cbps runs on one thread by default
#        (--threads 1) and its sums have a fixed order, so the same inputs give the same count on
#        the same build; a count that moves means the computation changed.
# MPI_COUNT  iteration counts of PETSc/TAO at 2 ranks: MPI reductions may add the ranks' parts in
#        another order from run to run, which can end an iteration one step sooner or later: ±1.
# SMOOTH relative 1e-6: smooth results of deterministic single-threaded runs (the pendulum's
#        period and phase errors, constraint errors and energies, condition numbers, the box's
#        accelerations). They repeat bit for bit on one build; 1e-6 is far above what another
#        compiler's contractions or libm change in them, and far below the 2-4 digits printed.
# CHAOTIC relative 1e-3: positions, drifts, penetrations and residuals after hundreds of steps of
#        an iterative solver that is not converged (contact stacks, piles, the chain at 20 sweeps).
#        Round-off is amplified there: the code's changes since 2026-11-24, which moved the
#        stored problems by round-off only (their scales agree to 1e-14), moved the 10-box
#        stack's drift by 3e-4 under PGS (30 % under block PGS). The documents print these to
#        2-3 digits.
# ITERATIVE relative 2e-2: residuals and errors where an iterative solver stopped (a tolerance
#        or an iteration limit, not round-off): the documents print them to 2 digits, so a
#        change within 2 % moves the printed value by at most one unit of its last digit.
# ROUNDOFF within a factor 10 (|log10(measured / committed)| <= 1), and equal when both are
#        below a floor: residuals and differences at round-off (the direct path's residual, a
#        speed at rest); their digits depend on the order of every sum, their size does not.
#        The documents print them as a power of ten, e.g. 1.8e-15.
# TILT   absolute 1e-8: a bisection's result (30 halvings of 60°: steps of 1e-9 rad), which may
#        end one halving to either side when round-off flips a decision at the boundary.


def _rel(limit):
    def test(c, m):
        if c == m:
            return True
        if c is None or m is None:
            return False
        return abs(m - c) <= limit * max(abs(c), abs(m))
    return f"rel {limit:g}", test


def _roundoff(floor):
    def test(c, m):
        if c == m:
            return True
        if c is None or m is None:
            return False
        c, m = abs(c), abs(m)
        if c <= floor and m <= floor:
            return True
        if c == 0 or m == 0:
            return False
        return abs(math.log10(m / c)) <= 1.0
    return f"x10 (floor {floor:g})", test


EXACT = ("exact", lambda c, m: c == m)
MPI_COUNT = ("±1", lambda c, m: c == m or (isinstance(c, (int, float)) and
                                          isinstance(m, (int, float)) and abs(c - m) <= 1))
SMOOTH = _rel(1e-6)
CHAOTIC = _rel(1e-3)
ITERATIVE = _rel(2e-2)
TILT = ("abs 1e-8", lambda c, m: c is not None and m is not None and abs(c - m) <= 1e-8)


def ROUNDOFF(floor=1e-13):
    return _roundoff(floor)


# Known drifts not yet regenerated: "sample/entry" -> the value measured when it was found, why
# it is not regenerated, and the command that would. Printed as PENDING on every run.
PENDING = {}


# ---------------------------------------------------------------------------------------------
# The build.


class Missing(Exception):
    """A build product the check needs is missing (exit 2)."""


class SampleError(Exception):
    """A sample's command failed in an unexpected way (a drift of its own)."""


class Build:
    def __init__(self, folder):
        self.folder = os.path.abspath(folder)
        self.cache = {}
        path = os.path.join(self.folder, "CMakeCache.txt")
        if os.path.exists(path):
            with open(path, encoding="utf-8", errors="replace") as f:
                for line in f:
                    if ":" in line and "=" in line and not line.startswith(("//", "#")):
                        key, value = line.rstrip("\n").split("=", 1)
                        self.cache[key.split(":")[0]] = value
        self.cbps = self.product("cbps", "cbps")
        self._features = {}

    def option(self, name):
        return self.cache.get(name, "").upper() in ("ON", "1", "TRUE", "YES")

    def product(self, relative, target):
        path = os.path.join(self.folder, relative)
        if not os.path.exists(path):
            raise Missing(f"{path} is missing: build it with `cmake --build {self.folder} "
                          f"--target {target}`")
        return path

    def python_dir(self):
        """The folder of the Python module, or None (with why) when the build has none."""
        folder = os.path.join(self.folder, "python")
        if os.path.isdir(folder) and any(n.startswith("cbps") and n.endswith(".so")
                                         for n in os.listdir(folder)):
            return folder
        if self.cache and not self.option("CBPS_PYTHON"):
            return None
        raise Missing(f"{folder}/cbps*.so is missing: build it with `cmake --build "
                      f"{self.folder} --target cbps_python`")

    def probe(self, solver):
        """Whether `cbps lcp` takes SOLVER in this build (a peer or tao:TYPE), and if not why."""
        if solver in self._features:
            return self._features[solver]
        problem = os.path.join(ROOT, "tests", "data", "siconos", "lcp", "lcp_deudeu.dat")
        r = subprocess.run([self.cbps, "lcp", problem, "--solver", solver, "--json"],
                           capture_output=True, text=True)
        ok = r.returncode in (0, 1)
        why = None if ok else (r.stderr.strip().splitlines() or ["exit %d" % r.returncode])[-1]
        self._features[solver] = (ok, why)
        return ok, why

    def mpirun(self):
        return os.environ.get("CBPS_MPIEXEC") or self.cache.get("MPIEXEC_EXECUTABLE") or \
            shutil.which("mpirun")


def needs_peers(build):
    for solver in ("siconos:lemke", "bullet:dantzig"):
        ok, why = build.probe(solver)
        if not ok:
            return f"this build has no {solver.split(':')[0]} peer ({why})"
    return None


def needs_petsc(build):
    ok, why = build.probe("tao:bqpip")
    if not ok:
        return f"this build has no PETSc/TAO ({why})"
    exe = build.mpirun()
    if not exe or not (os.path.exists(exe) or shutil.which(exe)):
        return "no mpirun (Debian: openmpi-bin; scripts/setup.sh --with-petsc)"
    return None


def needs_python(build):
    return None if build.python_dir() else "this build has no Python module (CBPS_PYTHON=OFF)"


def needs_validation(build):
    if build.cache and not build.option("CBPS_BUILD_VALIDATION"):
        return "this build has no validation programs (CBPS_BUILD_VALIDATION=OFF)"
    return None


def needs_bench(build):
    if build.cache and not build.option("CBPS_BUILD_BENCH"):
        return "this build has no benchmarks (CBPS_BUILD_BENCH=OFF)"
    return None


# ---------------------------------------------------------------------------------------------
# Running and reading.


class Context:
    """What a sample gets: the build, its own empty folder, and the comparisons it records."""

    def __init__(self, build, work, sample):
        self.build, self.work, self.sample = build, work, sample
        self.rows = []

    def path(self, *names):
        return os.path.join(self.work, *names)

    def run(self, cmd, ok=(0,), env=None):
        full = dict(os.environ, **(env or {}))
        r = subprocess.run(cmd, cwd=self.work, capture_output=True, text=True, env=full)
        if r.returncode not in ok:
            tail = (r.stderr.strip() or r.stdout.strip())[-600:]
            shown = " ".join([os.path.basename(cmd[0])] + list(cmd[1:]))
            raise SampleError(f"{shown}: exit {r.returncode}: {tail}")
        return r

    def cbps(self, args, ok=(0,)):
        return self.run([self.build.cbps] + args, ok)

    def cbps_json(self, args, ok=(0, 1), mpi_ranks=None, env=None):
        cmd = [self.build.cbps] + args
        if mpi_ranks:
            cmd = [self.build.mpirun(), "-n", str(mpi_ranks), "--oversubscribe"] + cmd
            env = dict(MPI_ENV, **(env or {}))
        return json.loads(self.run(cmd, ok, env).stdout)

    def compare(self, committed_file, entry, committed, measured, tolerance):
        try:
            agrees = bool(tolerance[1](committed, measured))
        except TypeError:
            agrees = False
        self.rows.append((committed_file, entry, committed, measured, tolerance, agrees))

    def compare_fields(self, committed_file, prefix, committed, measured, fields):
        """FIELDS: {dotted key: tolerance}; a missing key is compared as None."""
        for key, tolerance in fields.items():
            self.compare(committed_file, f"{prefix}{key}", dig(committed, key),
                         dig(measured, key), tolerance)


def dig(data, dotted):
    for part in dotted.split("."):
        if isinstance(data, dict):
            data = data.get(part)
        elif isinstance(data, list) and part.isdigit() and int(part) < len(data):
            data = data[int(part)]
        else:
            return None
    return data


def committed(relative):
    with open(os.path.join(ROOT, relative), encoding="utf-8") as f:
        return json.load(f)


def committed_csv(relative):
    with open(os.path.join(ROOT, relative), encoding="utf-8", newline="") as f:
        return list(csv.DictReader(f))


def read_json(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def read_csv(path):
    with open(path, encoding="utf-8", newline="") as f:
        return list(csv.DictReader(f))


def top_body_motion(folder):
    """The last body's (a stack's top box's) horizontal displacement at the end, its vertical
    one, and the largest horizontal displacement over the run, from trajectory.csv: what
    validation/validate_stack.cpp and contacts/stack.cpp measure after every step."""
    rows = read_csv(os.path.join(folder, "trajectory.csv"))
    last = max(int(r["body"]) for r in rows)
    path = [[float(r[c]) for c in "xyz"] for r in rows if int(r["body"]) == last]
    x0 = path[0]
    horizontal = [math.hypot(p[0] - x0[0], p[2] - x0[2]) for p in path]
    return horizontal[-1], path[-1][1] - x0[1], max(horizontal)


def number(value):
    """A JSON or CSV number (cbps writes inf/nan as strings) as a float; None stays None."""
    if value is None or isinstance(value, bool):
        return value
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            return value
    return float(value) if isinstance(value, (int, float)) else value


def auto(c, m, floor=1e-9):
    """ROUNDOFF for values at round-off (both below FLOOR), else CHAOTIC."""
    c, m = number(c), number(m)
    small = all(isinstance(v, float) and abs(v) <= floor for v in (c, m))
    return ROUNDOFF(1e-13) if small else CHAOTIC


# ---------------------------------------------------------------------------------------------
# The samples. Each says which committed file it checks and how that file is produced.


def sample_pendulum_wave(ctx):
    """The main job (cmake --workflow --preset main): the README's table."""
    out = ctx.path("pw")
    ctx.cbps(["run", "pendulum-wave", "--record-every", "4", "--check", "--quiet", "--out", out])
    ctx.run([PYTHON, os.path.join(ROOT, "validation", "pendulum_wave_report.py"), out])
    summary = "validation/results/pendulum-wave/summary.json"
    ctx.compare_fields(summary, "", committed(summary), read_json(os.path.join(out,
                                                                              "summary.json")), {
        "steps": EXACT, "iterations_total": EXACT, "status": EXACT,
        "max_constraint_error": SMOOTH, "max_residual": ROUNDOFF(1e-13),
        "energy_final": SMOOTH, "cross_check.steps_checked": EXACT,
        "cross_check.direct_unverified": EXACT,
        "cross_check.max_velocity_difference": ROUNDOFF(1e-13)})
    report = "validation/results/pendulum-wave/report.json"
    ctx.compare_fields(report, "", committed(report), read_json(os.path.join(out, "report.json")),
                       {"max_abs_period_error": SMOOTH, "mean_abs_period_error": SMOOTH,
                        "max_abs_phase_deg": SMOOTH, "max_abs_double_error": ROUNDOFF(1e-11)})


def sample_pendulum_variant(ctx):
    """One of the variants of target validation-pendulum-runs: attach=center."""
    out = ctx.path("center")
    ctx.cbps(["run", "pendulum-wave", "--param", "attach=center", "--record-every", "4",
              "--quiet", "--out", out])
    ctx.run([PYTHON, os.path.join(ROOT, "validation", "pendulum_wave_report.py"), out])
    report = "validation/results/pendulum-wave-center/report.json"
    ctx.compare_fields(report, "", committed(report), read_json(os.path.join(out, "report.json")),
                       {"steps": EXACT, "max_constraint_error": SMOOTH,
                        "max_abs_period_error": SMOOTH, "mean_abs_period_error": SMOOTH,
                        "max_abs_phase_deg": SMOOTH, "energy_final": SMOOTH})


VALIDATION_FIELDS = {"steps": EXACT, "max_rel_error": SMOOTH, "mean_rel_error": SMOOTH,
                     "mean_signed_rel_error": SMOOTH, "max_phase_error_deg": SMOOTH,
                     "max_drift_phase_deg": SMOOTH, "mean_time_offset_over_dt": SMOOTH,
                     "mean_amplitude_change": SMOOTH, "max_mean_stretch": SMOOTH,
                     "max_constraint_error_m": SMOOTH}


def compare_validation_runs(ctx, relative, measured, dts, fields):
    mine = {r["dt_inv"]: r for r in measured["runs"]}
    for r in committed(relative)["runs"]:
        if r["dt_inv"] in dts:
            ctx.compare_fields(relative, f"1/dt={r['dt_inv']}: ", r, mine.get(r["dt_inv"]), fields)


def sample_validation(ctx):
    """validate_pendulum (target validation) at its two coarsest step sizes: each step size's
    row comes from its own run (the orders compare it with the one before)."""
    exe = ctx.build.product("validation/validate_pendulum", "validate_pendulum")
    ctx.run([exe, "--out", ctx.path("v"), "--dts", "60,120"])
    relative = "validation/results/pendulum/validation.json"
    measured = read_json(ctx.path("v", "validation.json"))
    compare_validation_runs(ctx, relative, measured, ("60", "120"),
                            dict(VALIDATION_FIELDS, order_max=SMOOTH, order_mean=SMOOTH))
    ctx.compare(relative, "elliptic_K.max_rel_diff_vs_kcomp",
                committed(relative)["elliptic_K"]["max_rel_diff_vs_kcomp"],
                measured["elliptic_K"]["max_rel_diff_vs_kcomp"], ROUNDOFF(1e-15))


def sample_beta_study(ctx):
    """Target validation-beta-study: beta = 0 (its two coarsest steps; the program reports FAIL
    there, exit 1, after writing its files) and beta = 0.8, theta0 = 2 at 1/dt = 3840 (run
    beside 120 instead of 7680: each step size's rows come from its own run)."""
    exe = ctx.build.product("validation/validate_pendulum", "validate_pendulum")
    ctx.run([exe, "--n", "10", "--dts", "60,120", "--param", "beta=0", "--out", ctx.path("b0")],
            ok=(0, 1))
    compare_validation_runs(ctx, "validation/results/beta-study/beta-0.json",
                            read_json(ctx.path("b0", "validation.json")), ("60", "120"),
                            {"steps": EXACT, "max_rel_error": SMOOTH, "mean_rel_error": SMOOTH,
                             "max_constraint_error_m": SMOOTH})
    ctx.run([exe, "--n", "2", "--dts", "120,3840", "--param", "beta=0.8", "--param",
             "theta0_deg=2", "--out", ctx.path("b8")])
    relative = "validation/results/beta-study/beta-0.8-theta-2.csv"
    mine = {(r["dt_inv"], r["k"]): r for r in read_csv(ctx.path("b8", "period_errors.csv"))}
    for r in committed_csv(relative):
        if r["dt_inv"] != "3840":
            continue
        m = mine.get((r["dt_inv"], r["k"]), {})
        for key in ("rel_error", "mean_stretch", "phase_error_deg"):
            ctx.compare(relative, f"1/dt=3840 ball {r['k']}: {key}", number(r[key]),
                        number(m.get(key)), SMOOTH)


def stack_run(ctx, name, args):
    out = ctx.path(name)
    ctx.cbps(["run", "stack"] + args + ["--quiet", "--out", out])
    drift, vertical, max_drift = top_body_motion(out)
    steps = read_csv(os.path.join(out, "steps.csv"))
    return out, steps, {"top_drift": drift, "top_drift_vertical": vertical,
                        "max_drift": max_drift,
                        "max_penetration": read_json(os.path.join(out, "summary.json"))[
                            "max_penetration"],
                        "residual_last": float(steps[-1]["residual"])}


def sample_contacts(ctx):
    """validate_contacts (target validation-contacts), case 6 and case 1 as `cbps run` of the
    same scenes and settings (validation/contacts/stack.cpp: 10 boxes, dt 1/60, 20 sweeps, 10 s;
    v_corner.cpp: the scene's duration, margin 0), measured as the program measures them."""
    relative = "validation/results/contacts.json"
    data = committed(relative)
    for method in ("pgs", "block-pgs"):
        _, _, m = stack_run(ctx, method, ["--param", "n=10", "--param", "dt=1/60", "--param",
                                          "push=original", "--solver", method,
                                          "--iterations", "20"])
        c = next(r for r in data["stack"] if r["method"] == method and r["push"] == "original")
        for key in ("top_drift", "top_drift_vertical", "max_penetration", "residual_last"):
            ctx.compare(relative, f"stack {method} original: {key}", c[key], m[key], CHAOTIC)
    out = ctx.path("v-corner")
    ctx.cbps(["run", "v-corner", "--param", "angle_left_deg=15", "--param", "angle_right_deg=75",
              "--param", "margin=0", "--solver", "direct", "--quiet", "--out", out])
    c = next(r for r in data["v_corner"] if r["angle_left_deg"] == 15 and r["margin"] == 0)
    missing = sum(1 for r in read_csv(os.path.join(out, "steps.csv")) if int(r["rows"]) < 2)
    last = read_csv(os.path.join(out, "trajectory.csv"))[-1]
    speed = math.sqrt(sum(float(last[k]) ** 2 for k in ("vx", "vy", "vz")))
    ctx.compare(relative, "v-corner 15/75 margin 0: steps_missing_a_contact_direct",
                c["steps_missing_a_contact_direct"], missing, EXACT)
    ctx.compare(relative, "v-corner 15/75 margin 0: speed_end_direct", c["speed_end_direct"],
                speed, ROUNDOFF(1e-12))


def sample_stack_ingredients(ctx):
    """validate_stack (target validation-stack): two of its configurations at 20 sweeps, as
    `cbps run` of the same scene (stack, n = 10, the scene's 10 s; persistence off by
    --param persistence=0), with its measures: the top box's drift after every step, the
    deepest penetration, the share of rows started cold after step 1."""
    relative = "validation/results/stack-ingredients.json"
    runs = committed(relative)["runs"]
    for config, extra in (("the paper's PGS", ["--param", "persistence=0"]),
                          ("+ persistence", [])):
        _, steps, m = stack_run(ctx, config.replace("'", "").replace(" ", "_"),
                                ["--param", "n=10", "--iterations", "20", "--solver", "pgs"] +
                                extra)
        rows = sum(int(s["rows"]) for s in steps[1:])
        m["cold_fraction"] = sum(int(s["rows"]) - int(s["warm_rows"]) for s in steps[1:]) / rows
        c = next(r for r in runs if r["config"] == config and r["sweeps"] == 20)
        for key, tolerance in (("drift", CHAOTIC), ("max_drift", CHAOTIC),
                               ("max_penetration", CHAOTIC), ("cold_fraction", SMOOTH)):
            mine = m["top_drift"] if key == "drift" else m[key]
            ctx.compare(relative, f"{config}, 20 sweeps: {key}", c[key], mine, tolerance)


def compare_converge(ctx, relative, out, solvers, fields):
    mine = {s["solver"]: s for s in read_json(os.path.join(out, "summary.json"))["solvers"]}
    data = committed(relative)
    for s in data["solvers"]:
        if s["solver"] in solvers:
            ctx.compare_fields(relative, f"{s['solver']}: ", s, mine.get(s["solver"]),
                               fields[s["solver"]] if s["solver"] in fields else fields["*"])


REACHED = {f"reached.{t}.iterations": EXACT for t in ("0.001", "1e-06", "1e-10")}


def sample_convergence(ctx):
    """Targets convergence and convergence-pyramid: `cbps converge` with the committed runs'
    problem, options and some of their solvers (the stack's PGS to 40,000 sweeps, not 10^6:
    the sweeps it took to each tolerance do not depend on the limit). Solvers that stopped at
    the 10 s time limit are not compared."""
    base = ["--iterations", "1000000", "--time-limit", "10", "--quiet", "--no-plot"]
    out = ctx.path("chain")
    ctx.cbps(["converge", "chain", "--param", "n=100", "--param", "mass_ratio=100", "--step",
              "100", "--solvers", "pgs,direct"] + base + ["--out", out])
    tolerance_stop = dict(REACHED, iterations=EXACT, stopped=EXACT, residual=ITERATIVE,
                          lambda_error=ITERATIVE, velocity_error=ITERATIVE)
    exact = {"iterations": EXACT, "stopped": EXACT, "residual": ROUNDOFF(1e-12)}
    compare_converge(ctx, "validation/results/convergence/chain/summary.json", out,
                     ("pgs", "direct"), {"pgs": tolerance_stop, "direct": exact})
    out = ctx.path("stack")
    ctx.cbps(["converge", "stack", "--step", "60", "--solvers", "pgs,jacobi:0.7,direct",
              "--iterations", "40000", "--time-limit", "10", "--quiet", "--no-plot", "--out",
              out])
    compare_converge(ctx, "validation/results/convergence/stack/summary.json", out,
                     ("pgs", "jacobi:0.7", "direct"),
                     {"pgs": REACHED, "jacobi:0.7": {"iterations": EXACT, "stopped": EXACT},
                      "direct": exact})
    out = ctx.path("pyramid")
    ctx.cbps(["converge", "pyramid", "--param", "base=20", "--step", "30", "--solvers",
              "direct"] + base + ["--out", out])
    compare_converge(ctx, "validation/results/convergence/pyramid/summary.json", out,
                     ("direct",), {"direct": dict(exact, residual=ROUNDOFF(1e-12))})


def sample_limits(ctx):
    """Target exact-path-limits, its first run (the base-20 pyramid's two runs take minutes)."""
    out = ctx.path("stack-check")
    ctx.cbps(["run", "stack", "--check", "--steps", "60", "--quiet", "--out", out])
    relative = "validation/results/limits/stack-check/summary.json"
    c, m = committed(relative), read_json(os.path.join(out, "summary.json"))
    ctx.compare_fields(relative, "", c, m, {
        "steps": EXACT, "iterations_total": EXACT, "status": EXACT,
        "max_penetration": CHAOTIC, "max_residual": CHAOTIC,
        "cross_check.steps_checked": EXACT, "cross_check.direct_unverified": EXACT,
        "cross_check.direct_stopped_short": EXACT})
    key = "cross_check.max_velocity_difference"
    ctx.compare(relative, key, dig(c, key), dig(m, key), auto(dig(c, key), dig(m, key)))


STRESS_FIELDS = ("max_constraint_error_m", "max_penetration_m", "final_residual_N",
                 "max_residual_N")


def compare_stress(ctx, relative, out):
    mine = {(r["case"], r["solver"]): r for r in read_json(os.path.join(out,
                                                                        "summary.json"))["results"]}
    for c in committed(relative)["results"]:
        m = mine.get((c["case"], c["solver"]))
        if m is None:
            continue
        where = f"{c['case']} {c['solver']}: "
        ctx.compare(relative, where + "status", c["status"], m["status"], EXACT)
        ctx.compare(relative, where + "steps_done", c["steps_done"], m["steps_done"], EXACT)
        for key in STRESS_FIELDS + tuple("measured." + k for k in (c.get("measured") or {})):
            a, b = number(dig(c, key)), number(dig(m, key))
            ctx.compare(relative, where + key, a, b, auto(a, b))


def sample_stress(ctx):
    """Target stress-catalogue: `cbps stress` on a few of its cases (--case, --solver keep the
    catalogue's own runs)."""
    out = ctx.path("stress")
    ctx.cbps(["stress", "--case", "^(mass-ratio-box-1e3|mass-ratio-chain-1e6|stack-20|"
              "near-coincident-anchors|pendulum-dt-1e-1|closed-loop)$", "--solver", "pgs,direct",
              "--quiet", "--out", out])
    compare_stress(ctx, "validation/results/stress/summary.json", out)


def sample_stress_integrators(ctx):
    """Target stress-integrators: the same cases under the gyroscopic and the midpoint turn."""
    for integrator in ("gyroscopic", "midpoint"):
        out = ctx.path(integrator)
        ctx.cbps(["stress", "--integrator", integrator, "--case",
                  "^(dzhanibekov-dt-1/240|mass-ratio-box-1e3|closed-loop)$", "--solver",
                  "pgs,direct", "--quiet", "--out", out], ok=(0, 1))
        compare_stress(ctx, f"validation/results/stress-{integrator}/summary.json", out)


def sample_profile(ctx):
    """Target profile, its library: scripts/make_problem_library.py --quick writes 8 of the 37
    problems, with the same rows, nonzeros, rank and condition (numpy's eigenvalues) as the
    full library's; the profiles themselves come from time-limited runs of every solver on all
    37 (minutes) and are not rerun."""
    lib = ctx.path("library")
    ctx.run([PYTHON, os.path.join(ROOT, "scripts", "make_problem_library.py"), ctx.build.cbps,
             lib, "--quick"])
    relative = "validation/results/profile/summary.json"
    mine = {p["name"]: p for p in read_json(os.path.join(lib, "library.json"))["problems"]}
    for c in committed(relative)["problems"]:
        m = mine.get(c["name"])
        if m is None:
            continue
        m = dict(m, condition=None if m.get("condition") == "inf" else m.get("condition"))
        ctx.compare_fields(relative, f"{c['name']}: ", c, m, {
            "rows": EXACT, "nonzeros": EXACT, "rank": EXACT, "definite": EXACT,
            "condition": SMOOTH})


def sample_schemes(ctx):
    """validation/schemes_study.py (docs/schemes.md): three of its runs through its own run()."""
    import schemes_study as study
    relative = "validation/results/schemes/summary.json"
    runs = committed(relative)["runs"]
    wanted = (("chain", "paper 1 x 20"), ("chain", "soft-step 10 x 1"),
              ("card-house", "soft-step 4 x 1"))
    for scene, label in wanted:
        name, args, solvers, check, series = next(s for s in study.SCENES if s[0] == scene)
        config = next(c for c in study.SCHEMES if c[0] == label)
        mine = study.run(ctx.build.cbps, scene, args, solvers[0], config, check, series)
        c = next(r for r in runs if r["scene"] == scene and r["config"] == label and
                 r["solver"] == solvers[0] and r["integrator"] == "paper")
        where = f"{scene} {label} {solvers[0]}: "
        ctx.compare(relative, where + "status", c["status"], mine["status"], EXACT)
        ctx.compare(relative, where + "steps_done", c["steps_done"], mine["steps_done"], EXACT)
        for key in ("max_penetration_m", "max_constraint_error_m", "energy_change_J",
                    "top_drift_m", "max_move_m", "exact_velocity_difference",
                    "max_excursion_m", "end_top_drift_m", "end_max_move_m"):
            # The study's end values were named top_drift_m and max_move_m before it also kept
            # the largest excursions (end_top_drift_m, end_max_move_m): the same numbers.
            ours = mine.get(key, mine.get("end_" + key))
            if key in c and ours is not None:
                ctx.compare(relative, where + key, c[key], ours, auto(c[key], ours))


BOX_CONE = """
import json, math, sys
import box_vs_cone as b
out = []
for law, deg in (("cone", 30.0), ("paper", 30.0)):
    phi = math.radians(deg)
    start = math.tan(b.critical_tilt(law, phi)) / b.MU
    v = b.simulate(law, math.atan(2.0 * b.MU), phi, 24)[0]
    acc = v / (24 * b.DT)
    out.append({"law": law, "phi_deg": deg, "start_tan_over_mu": start,
                "acceleration": float(math.hypot(acc[0], acc[2])),
                "turn_deg": math.degrees(math.atan2(acc[2], acc[0]) - phi)})
print(json.dumps(out))
"""


def sample_box_cone(ctx):
    """validation/box_vs_cone.py (target box-vs-cone): the cube's rows at phi = 30 degrees under
    the cone and the paper's box, through the script's own critical_tilt and simulate."""
    env = {"PYTHONPATH": os.pathsep.join([ctx.build.python_dir(),
                                          os.path.join(ROOT, "validation")])}
    mine = json.loads(ctx.run([PYTHON, "-c", BOX_CONE], env=env).stdout)
    relative = "validation/results/box-cone/box_vs_cone.json"
    rows = committed(relative)["rows"]
    for m in mine:
        c = next(r for r in rows if r["law"] == m["law"] and r["phi_deg"] == m["phi_deg"])
        where = f"cube {m['law']} phi {m['phi_deg']:g}: "
        ctx.compare(relative, where + "start_tan_over_mu", c["start_tan_over_mu"],
                    m["start_tan_over_mu"], TILT)
        ctx.compare(relative, where + "acceleration", c["acceleration"], m["acceleration"],
                    SMOOTH)
        ctx.compare(relative, where + "turn_deg", c["turn_deg"], m["turn_deg"],
                    ("abs 1e-6", lambda a, b: abs(a - b) <= 1e-6))


def sample_cones_pyramid(ctx):
    """Target cones-pyramid: the whole run (100 steps of the base-20 pyramid in Coulomb's cone
    by the exact path, a few seconds)."""
    out = ctx.path("cones-pyramid")
    ctx.cbps(["run", "pyramid", "--param", "base=20", "--param", "friction=cone", "--param",
              "mu=0.5", "--solver", "direct", "--steps", "100", "--quiet", "--out", out])
    relative = "validation/results/cones-pyramid/summary.json"
    c, m = committed(relative), read_json(os.path.join(out, "summary.json"))
    ctx.compare_fields(relative, "", c, m, {
        "status": EXACT, "steps": EXACT, "rows": EXACT, "iterations_total": EXACT,
        "max_residual": ITERATIVE, "max_penetration": ROUNDOFF(1e-12),
        "energy_final": SMOOTH})


# Siconos' problems the study's direct sample reruns: small ones of each kind (W not symmetric,
# symmetric and singular, the cheap start and the stages after it), a second each.
SICONOS_STUDY_SAMPLE = ("Rover1040.dat", "Rover3865.dat", "FrictionContact3D_RR_1c.dat",
                        "NESpheres_30_1.dat", "OneObject-i100000-316.hdf5.dat",
                        "Confeti-ex13-Fc3D-SBM.dat", "GFC3D_TwoRods1.dat")


def sample_siconos_study(ctx):
    """scripts/measure_siconos_study.py (docs/siconos-study.md): `direct` on a few of the
    problems through `cbps lcp`, as the profile runs it (told 1e-10); the whole study (an hour,
    every Siconos solver to its limit) is not rerun."""
    relative = "validation/results/siconos-fc3d/profile.json"
    runs = {(m["problem"], m["solver"]): m for m in committed(relative)["measurements"]}
    for name in SICONOS_STUDY_SAMPLE:
        c = runs[(name, "direct")]
        m = ctx.cbps_json(["lcp", os.path.join(ROOT, "validation/data/siconos-fc3d", name),
                           "--solver", "direct", "--tolerance", "1e-10", "--json"])
        where = f"{name} direct: "
        ctx.compare(relative, where + "solved to 1e-10", c["reached"]["1e-10"] is not None,
                    m["status"] == "solved" and m["unit_free"]["relative"] <= 1e-10, EXACT)
        ctx.compare(relative, where + "unit-free residual", c["residual_relative"],
                    m["unit_free"]["relative"], auto(c["residual_relative"],
                                                     m["unit_free"]["relative"]))


MU_VARIANT = ("Capsules-i101-404.dat", 0.5)  # one run of mu-variants.json that needs stage 5
MU_VARIANTS = """
import json, os, sys
import cbps, measure_mu_variants as v
name, factor = sys.argv[1], float(sys.argv[2])
p = cbps.read_problem(os.path.join(v.ROOT, v.DATA, name))
print(json.dumps(v.run(cbps, p, factor, "direct")))
"""


def sample_mu_variants(ctx):
    """scripts/measure_mu_variants.py (docs/siconos-study.md, "Problems no simulation wrote"):
    `direct` on one Capsules file with mu halved, through the script's own run (the whole probe,
    with Siconos' PROX, takes minutes and is not rerun)."""
    env = {"PYTHONPATH": os.pathsep.join([ctx.build.python_dir(),
                                          os.path.join(ROOT, "scripts")])}
    name, factor = MU_VARIANT
    m = json.loads(ctx.run([PYTHON, "-c", MU_VARIANTS, name, str(factor)], env=env).stdout)
    relative = "validation/results/siconos-fc3d/mu-variants.json"
    c = next(r for r in committed(relative)["runs"] if r["problem"] == name
             and r["mu_factor"] == factor and r["method"] == "direct")
    where = f"{name} mu x {factor:g} direct: "
    for field in ("termination", "factorizations", "stage5_steps"):
        ctx.compare(relative, where + field, c[field], m[field], EXACT)
    ctx.compare(relative, where + "unit_free", c["unit_free"], m["unit_free"],
                auto(c["unit_free"], m["unit_free"]))


def sample_peers(ctx):
    """scripts/measure_peers.py (target peers), the exact-path problem it runs first: the
    10-box stack at step 30 through `cbps lcp` with every peer, by the script's own functions
    (its library profile takes tens of minutes and is not rerun)."""
    import measure_peers as peers
    peers.BINARY.update(path=ctx.build.cbps, mtime=os.stat(ctx.build.cbps).st_mtime)
    name, _, args = next(p for p in peers.PROBLEMS if p[0] == "stack10")
    ctx.cbps(["matrices"] + args + ["--out", name, "--quiet"])
    relative = "validation/results/peers/peers.json"
    problem = next(p for p in committed(relative)["exact_path"]["problems"] if p["name"] == name)
    for c in problem["runs"]:
        m = peers.exact_path_run(ctx.build.cbps, ctx.work, name, c["solver"])
        where = f"{name} {c['solver']}: "
        ctx.compare(relative, where + "status", c["status"], m["status"], EXACT)
        if c["status"] == "refused":
            continue
        ctx.compare(relative, where + "iterations", c.get("iterations"), m.get("iterations"),
                    EXACT)
        ctx.compare(relative, where + "peer_status", c.get("peer_status"), m.get("peer_status"),
                    EXACT)
        rel = number(c.get("residual_relative"))
        ctx.compare(relative, where + "residual_relative", rel,
                    number(m.get("residual_relative")),
                    ROUNDOFF(1e-11) if rel is not None and rel < 1e-9 else ITERATIVE)


def tao_rows(ctx, problem, solver, ranks):
    data = ctx.cbps_json(["lcp", problem, "--solver", solver, "--json"], mpi_ranks=ranks)
    return {"status": data["status"], "iterations": data["iterations"],
            "residual": number(data["residual"]), "reason": (data.get("tao") or {}).get("reason")}


def sample_tao(ctx):
    """scripts/measure_tao.py (docs/distributed.md, "Measured"): the problems of the petsc tests
    (scripts/cbps_problem.py) and three of its runs (its other runs on the stack take 4 to 80 s
    each)."""
    from cbps_problem import PETSC_PROBLEMS
    for name, args in PETSC_PROBLEMS.items():
        ctx.cbps(args + ["--out", name, "--quiet"])
    relative = "validation/results/distributed/tao.json"
    runs = committed(relative)["runs"]
    for problem, solver, ranks in (("chain", "tao:tron", 1), ("chain", "tao:tron", 2),
                                   ("stack", "tao:blmvm", 1)):
        c = next(r for r in runs if (r["problem"], r["solver"], r["ranks"]) ==
                 (problem, solver, ranks))
        m = tao_rows(ctx, problem, solver, ranks)
        where = f"{problem} {solver} {ranks} rank(s): "
        ctx.compare(relative, where + "status", c["status"], m["status"], EXACT)
        ctx.compare(relative, where + "reason", c.get("reason"), m["reason"], EXACT)
        ctx.compare(relative, where + "iterations", c["iterations"], m["iterations"],
                    EXACT if ranks == 1 else MPI_COUNT)
        ctx.compare(relative, where + "residual", number(c["residual"]), m["residual"],
                    ROUNDOFF(1e-12) if number(c["residual"]) < 1e-9 else ITERATIVE)


def sample_tao_studies(ctx):
    """scripts/measure_tao_studies.py: its `cbps converge` of the chain with three of its
    solvers (those that stop at the tolerance, not at its 2 s time limit)."""
    from cbps_problem import PETSC_PROBLEMS
    ctx.cbps(PETSC_PROBLEMS["chain"] + ["--out", "chain", "--quiet"])
    ctx.cbps(["converge", "chain", "--solvers", "direct,apgd,tao:tron", "--time-limit", "2",
              "--quiet", "--no-plot", "--out", "chain-converge"])
    relative = "validation/results/distributed/tao-studies.json"
    mine = {s["solver"]: s for s in read_json(ctx.path("chain-converge",
                                                       "summary.json"))["solvers"]}
    for c in committed(relative)["converge"]["chain"]["solvers"]:
        if c["solver"] in mine:
            m = mine[c["solver"]]
            where = f"chain {c['solver']}: "
            ctx.compare(relative, where + "stopped", c["stopped"], m["stopped"], EXACT)
            ctx.compare(relative, where + "iterations", c["iterations"], m["iterations"], EXACT)
            ctx.compare(relative, where + "residual", c["residual"], m["residual"],
                        ROUNDOFF(1e-12) if c["residual"] < 1e-11 else ITERATIVE)


def sample_generate(ctx):
    """scripts/measure_generate.py: one of its runs (100,000 generated rows at 2 ranks, TAO's
    bqpip), with PETSc's -log_view message and reduction counts read by the script's own
    log_view."""
    import measure_generate
    log = ctx.path("log.txt")
    data = ctx.cbps_json(["lcp", "--generate", "chain", "--rows", "100000", "--solver",
                          "tao:bqpip", "--json"], mpi_ranks=2,
                         env={"PETSC_OPTIONS": f"-log_view :{log}"})
    view = measure_generate.log_view(log)
    relative = "validation/results/distributed/generate.json"
    c = next(r for r in committed(relative)["runs"] if (r["rows"], r["ranks"], r["type"]) ==
             (100000, 2, "bqpip"))
    where = "100000 rows, 2 ranks, bqpip: "
    ctx.compare(relative, where + "status", c["status"], data["status"], EXACT)
    ctx.compare(relative, where + "iterations", c["iterations"], data["iterations"], MPI_COUNT)
    ctx.compare(relative, where + "reason", c["reason"], data["tao"]["reason"], EXACT)
    ctx.compare(relative, where + "residual", c["residual"], number(data["residual"]),
                ROUNDOFF(1e-12))
    for key in ("messages", "reductions"):
        ctx.compare(relative, where + "log_view." + key, c["log_view"][key], view.get(key), EXACT)


def sample_generate_pyramid(ctx):
    """scripts/measure_generate_pyramid.py: its smallest run (10,000 rows at 1 rank)."""
    relative = "bench/results/generate-pyramid-amd-epyc-2cpu.json"
    run = committed(relative)["runs"][0]
    c = next(r for r in run["mpi"] if r["ranks"] == 1)
    data = ctx.cbps_json(["lcp", "--generate", "pyramid", "--rows", str(run["rows_requested"]),
                          "--solver", "direct", "--json"], mpi_ranks=1)
    where = f"{run['rows_requested']} rows, 1 rank: "
    ctx.compare(relative, where + "rows", c["rows"], data["rows"], EXACT)
    ctx.compare(relative, where + "status", c["status"], data["status"], EXACT)
    ctx.compare(relative, where + "residual_N", c["residual_N"], number(data["residual"]),
                ROUNDOFF(1e-13))
    for key in sorted(c["direct"]):
        ctx.compare(relative, where + "direct." + key, c["direct"][key], data["direct"].get(key),
                    EXACT)


def sample_direct_mpi(ctx):
    """scripts/measure_direct_mpi.py: its first folder (the base-20 pyramid at step 60), the
    serial exact path and the exact path under mpirun -n 1."""
    relative = "bench/results/direct-mpi-amd-epyc-2cpu.json"
    folder = committed(relative)["folders"][0]
    args = folder["matrices"].split()[2:]
    ctx.cbps(["matrices"] + args + ["--out", "problem", "--quiet"])
    serial = ctx.cbps_json(["lcp", "problem", "--solver", "direct", "--json"])
    where = f"{folder['folder']} serial: "
    ctx.compare(relative, where + "status", folder["serial"]["status"], serial["status"], EXACT)
    ctx.compare(relative, where + "message", folder["serial"]["message"].rsplit(", residual")[0],
                serial["message"].rsplit(", residual")[0], EXACT)
    ctx.compare(relative, where + "residual_N", folder["serial"]["residual_N"],
                number(serial["residual"]), ROUNDOFF(1e-12))
    c = next(r for r in folder["mpi"] if r["ranks"] == 1)
    data = ctx.cbps_json(["lcp", "problem", "--solver", "direct", "--json"], mpi_ranks=1)
    where = f"{folder['folder']} mpirun -n 1: "
    ctx.compare(relative, where + "status", c["status"], data["status"], EXACT)
    ctx.compare(relative, where + "residual_N", c["residual_N"], number(data["residual"]),
                ROUNDOFF(1e-12))
    for key in sorted(c["direct"]):
        ctx.compare(relative, where + "direct." + key, c["direct"][key], data["direct"].get(key),
                    EXACT)


def sample_warm(ctx):
    """scripts/measure_warm.py (target bench-warm): its first scene and push (the 10-box stack,
    original push, 600 steps), the direct run and the 10-sweep PGS run, by its own functions."""
    import measure_peers as peers
    import measure_warm as warm
    peers.BINARY.update(path=ctx.build.cbps, mtime=os.stat(ctx.build.cbps).st_mtime)
    relative = "bench/results/warm-amd-epyc-2cpu.json"
    scene = next(s for s in committed(relative)["scenes"]
                 if s["scene"] == "stack 10" and s["push"] == "original")
    label, args, steps = next(s for s in warm.SCENES if s[0] == "stack 10")
    base = args + ["--param", "push=original", "--steps", str(steps)]
    ds, dsteps = warm.cbps_run(ctx.build.cbps, ctx.work, "direct", base + ["--solver", "direct"])
    ps, _ = warm.cbps_run(ctx.build.cbps, ctx.work, "pgs", base + [
        "--solver", "pgs", "--iterations", "10", "--tolerance", "0"])
    direct = warm.direct_facts(ds, dsteps)
    c = scene["runs"][0]
    where = "stack 10 original: "
    for key in ("routes", "steady_routes", "rows"):
        ctx.compare(relative, where + "direct." + key, c["direct"][key], direct[key], EXACT)
    ctx.compare(relative, where + "direct.max_residual_N", c["direct"]["max_residual_N"],
                direct["max_residual_N"], ITERATIVE)
    ctx.compare(relative, where + "pgs_max_residual_N", c["pgs_max_residual_N"],
                ps["max_residual"], CHAOTIC)


def sample_cones_bench(ctx):
    """scripts/measure_cones.py (target bench-cones): its smallest problem (the base-3 pyramid
    at rest on the relaxation's cones) by its own measure(), Siconos' fc3d solvers included
    when the build has the peers."""
    import measure_cones as cones
    import measure_peers as peers
    peers.BINARY.update(path=ctx.build.cbps, mtime=os.stat(ctx.build.cbps).st_mtime)
    relative = "bench/results/cones-amd-epyc-2cpu.json"
    c = next(p for p in committed(relative)["problems"] if p["name"] == "pyramid3")
    with_siconos = needs_peers(ctx.build) is None
    if not with_siconos:
        cones.SICONOS = {}
        print(f"  (Siconos' fc3d runs of {relative} skipped: {needs_peers(ctx.build)})")
    m = cones.measure(ctx.build.cbps, ctx.work, 3, 60, "cone")
    ctx.compare(relative, "pyramid3: contacts", c["contacts"], m["contacts"], EXACT)
    for law, runs in c["laws"].items():
        for run, entry in runs.items():
            mine = m["laws"][law][run]
            where = f"pyramid3 {law} {run}: "
            ctx.compare(relative, where + "status", entry["status"], mine["status"], EXACT)
            ctx.compare(relative, where + "iterations", entry["iterations"], mine["iterations"],
                        EXACT)
            ctx.compare(relative, where + "residual", entry["residual"], mine["residual"],
                        ITERATIVE)
    for s in c["siconos"] if with_siconos else []:
        mine = next(x for x in m["siconos"] if x["solver"] == s["solver"])
        where = f"pyramid3 {s['solver']}: "
        ctx.compare(relative, where + "peer_status", s.get("peer_status"),
                    mine.get("peer_status"), EXACT)
        ctx.compare(relative, where + "iterations", s.get("iterations"), mine.get("iterations"),
                    EXACT)


def sample_bench_counters(ctx):
    """bench_sweeps and bench_system (targets bench-sweeps, bench-results): one benchmark each,
    run briefly; the sizes they count (rows, nonzeros of A and J) are deterministic, their times
    are not compared."""
    for exe, bench, relative in (
            ("bench_sweeps", "pgs_sweep/chain/n:1000", "bench/results/sweeps-amd-epyc-2cpu.json"),
            ("bench_system", "build_system/n:1000", "bench/results/system-amd-epyc-2cpu.json")):
        path = ctx.build.product(f"bench/{exe}", exe)
        out = json.loads(ctx.run([path, f"--benchmark_filter=^{bench}$",
                                  "--benchmark_min_time=0.01", "--benchmark_format=json"]).stdout)
        mine = out["benchmarks"][0] if out["benchmarks"] else {}
        c = next(b for b in committed(relative)["benchmarks"] if b["run_name"] == bench)
        for key in ("rows", "nnz_A", "nnz_J"):
            if key in c:
                ctx.compare(relative, f"{bench}: {key}", c[key], mine.get(key), EXACT)


PYTHON_EXAMPLE = """
import cbps
sim = cbps.Simulation(cbps.scene("chain", n=20, mass_ratio=100))
traj = sim.run(duration=1.0)
s = sim.system()
lam, summary = cbps.solve(s.A, s.b, s.cmin, s.cmax, "psor:1.3", iterations=100000)
print(summary["iterations"], summary["termination"])
"""


def sample_python_example(ctx):
    """docs/python.md's example, whose comment gives the sweeps it prints (written by hand, not
    generated): the example run through the module, its printed line against the comment."""
    relative = "docs/python.md"
    with open(os.path.join(ROOT, relative), encoding="utf-8") as f:
        line = next(x for x in f if x.startswith('print(summary["iterations"]'))
    documented = line.split("#", 1)[1].strip()
    env = {"PYTHONPATH": ctx.build.python_dir()}
    measured = ctx.run([PYTHON, "-c", PYTHON_EXAMPLE], env=env).stdout.strip()
    ctx.compare(relative, "example: iterations and termination", documented, measured, EXACT)


# (name, committed file(s), how it is produced, what the build must have, function)
SAMPLES = [
    ("pendulum-wave", "validation/results/pendulum-wave/", "the main job", None,
     sample_pendulum_wave),
    ("pendulum-wave-center", "validation/results/pendulum-wave-center/",
     "target validation-pendulum-runs", None, sample_pendulum_variant),
    ("validation", "validation/results/pendulum/validation.json", "target validation",
     needs_validation, sample_validation),
    ("beta-study", "validation/results/beta-study/", "target validation-beta-study",
     needs_validation, sample_beta_study),
    ("contacts", "validation/results/contacts.json", "target validation-contacts", None,
     sample_contacts),
    ("stack-ingredients", "validation/results/stack-ingredients.json", "target validation-stack",
     None, sample_stack_ingredients),
    ("convergence", "validation/results/convergence/", "targets convergence, convergence-pyramid",
     None, sample_convergence),
    ("limits", "validation/results/limits/", "target exact-path-limits", None, sample_limits),
    ("stress", "validation/results/stress/summary.json", "target stress-catalogue", None,
     sample_stress),
    ("stress-integrators", "validation/results/stress-{gyroscopic,midpoint}/",
     "target stress-integrators", None, sample_stress_integrators),
    ("profile", "validation/results/profile/summary.json", "target profile", None,
     sample_profile),
    ("schemes", "validation/results/schemes/summary.json", "validation/schemes_study.py", None,
     sample_schemes),
    ("box-cone", "validation/results/box-cone/box_vs_cone.json", "target box-vs-cone",
     needs_python, sample_box_cone),
    ("cones-pyramid", "validation/results/cones-pyramid/summary.json", "target cones-pyramid",
     None, sample_cones_pyramid),
    ("peers", "validation/results/peers/peers.json", "target peers", needs_peers, sample_peers),
    ("siconos-study", "validation/results/siconos-fc3d/profile.json",
     "scripts/measure_siconos_study.py", None, sample_siconos_study),
    ("siconos-mu-variants", "validation/results/siconos-fc3d/mu-variants.json",
     "scripts/measure_mu_variants.py", needs_python, sample_mu_variants),
    ("distributed-tao", "validation/results/distributed/tao.json", "scripts/measure_tao.py",
     needs_petsc, sample_tao),
    ("distributed-tao-studies", "validation/results/distributed/tao-studies.json",
     "scripts/measure_tao_studies.py", needs_petsc, sample_tao_studies),
    ("distributed-generate", "validation/results/distributed/generate.json",
     "scripts/measure_generate.py", needs_petsc, sample_generate),
    ("bench-generate-pyramid", "bench/results/generate-pyramid-*.json",
     "scripts/measure_generate_pyramid.py", needs_petsc, sample_generate_pyramid),
    ("bench-direct-mpi", "bench/results/direct-mpi-*.json", "scripts/measure_direct_mpi.py",
     needs_petsc, sample_direct_mpi),
    ("bench-warm", "bench/results/warm-*.json", "target bench-warm", None, sample_warm),
    ("bench-cones", "bench/results/cones-*.json", "target bench-cones", None,
     sample_cones_bench),
    ("bench-counters", "bench/results/{sweeps,system}-*.json",
     "targets bench-sweeps, bench-results", needs_bench, sample_bench_counters),
    ("python-example", "docs/python.md (its example's comment)", "written by hand",
     needs_python, sample_python_example),
]

# Committed results a document uses that no sample reruns, and why.
NOT_SAMPLED = [
    ("bench/results/direct-*.json", "bench_direct has no smaller run than its whole table "
     "(about 25 s here: the 10^6-row chain and the 1000-box stack)"),
    ("bench/results/exact-*.json", "bench_exact's smallest run (--max-base 10) takes about 20 s "
     "(the 1000-box stacks, the 10^6-row chain)"),
    ("bench/results/contacts-*.json", "bench_contacts always runs the base-40 pyramid (about "
     "30 s); its numbers are times, its sizes the pyramids' contacts"),
    ("validation/results/test-suite/release.json", "the test suite's size and wall time, "
     "measured by scripts/measure_suite.py: nothing the solver computes"),
]


# ---------------------------------------------------------------------------------------------
# The command.


def show(value):
    if isinstance(value, float):
        return f"{value:.10g}"
    text = json.dumps(value, sort_keys=True) if isinstance(value, (dict, list)) else str(value)
    return text if len(text) <= 60 else text[:57] + "..."


def verdict(name, row):
    """ok, DRIFT or PENDING (a known drift whose measured value is still the one recorded, to
    the entry's own tolerance)."""
    file, entry, c, m, tolerance, agrees = row
    if agrees:
        return "ok"
    known = PENDING.get(f"{name}/{entry}")
    if known is not None:
        try:
            if tolerance[1](known["measured"], m):
                return "PENDING"
        except TypeError:
            pass
    return "DRIFT"


def run_sample(build, sample, root):
    name, _, _, needs, function = sample
    reason = needs(build) if needs else None
    if reason:
        print(f"[{name}] SKIPPED: {reason}")
        return [], "skipped"
    work = tempfile.mkdtemp(prefix=f"{name}-", dir=root)
    ctx = Context(build, work, name)
    start = time.monotonic()
    error = None
    try:
        function(ctx)
    except (SampleError, OSError, ValueError, KeyError, StopIteration) as e:
        error = f"{type(e).__name__}: {e}"
    except SystemExit as e:  # a producer's own function stops its script this way
        error = f"stopped: {e}"
    seconds = time.monotonic() - start
    print(f"[{name}] {seconds:.1f} s")
    results = []
    for row in ctx.rows:
        v = verdict(name, row)
        file, entry, c, m, text, _ = row
        print(f"  {v:7} {file} | {entry} | committed {show(c)} | measured {show(m)} | {text[0]}")
        results.append((v, name, row))
    if error:
        print(f"  DRIFT   {sample[1]} | the sample's command failed: {error}")
        results.append(("DRIFT", name, (sample[1], "command", None, error, ("", None), False)))
    return results, seconds


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    ap.add_argument("build", help="the build folder, e.g. build/release")
    ap.add_argument("--only", action="append", default=[], metavar="NAME",
                    help="run only the samples named NAME or starting with it (repeatable)")
    ap.add_argument("--list", action="store_true", help="list the samples and exit")
    args = ap.parse_args(argv)
    if args.list:
        for name, files, producer, _, function in SAMPLES:
            print(f"{name}: {files} ({producer})\n    {function.__doc__.split(chr(10))[0]}")
        for files, why in NOT_SAMPLED:
            print(f"not sampled: {files}: {why}")
        return 0
    only = [n for group in args.only for n in group.split(",") if n]
    chosen = [s for s in SAMPLES if not only or any(s[0].startswith(n) for n in only)]
    if not chosen:
        ap.error(f"--only {','.join(only)}: no such sample (see --list)")
    if not os.path.isdir(args.build):
        print(f"{PROG}: {args.build}: no such build folder", file=sys.stderr)
        return 2
    try:
        build = Build(args.build)
    except Missing as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 2
    start = time.monotonic()
    results = []
    with tempfile.TemporaryDirectory(prefix="cbps-results-drift-") as root:
        try:
            for sample in chosen:
                results += run_sample(build, sample, root)[0]
        except Missing as e:
            print(f"{PROG}: {e}", file=sys.stderr)
            return 2
    if not only:
        for files, why in NOT_SAMPLED:
            print(f"[not sampled] {files}: {why}")
    drifts = [r for r in results if r[0] == "DRIFT"]
    pending = [r for r in results if r[0] == "PENDING"]
    print(f"{PROG}: {len(results)} entries in {time.monotonic() - start:.0f} s: "
          f"{len(results) - len(drifts) - len(pending)} agree, {len(pending)} known pending, "
          f"{len(drifts)} drifted")
    for _, name, (file, entry, c, m, text, _) in pending:
        known = PENDING[f"{name}/{entry}"]
        print(f"KNOWN PENDING DRIFT: {file} | {entry}: committed {show(c)}, measured {show(m)}; "
              f"{known['why']}; regenerate with: {known['command']}")
    for _, name, (file, entry, c, m, text, _) in drifts:
        print(f"DRIFT: [{name}] {file} | {entry}: committed {show(c)}, measured {show(m)} "
              f"({text[0]})")
    return 1 if drifts else 0


if __name__ == "__main__":
    sys.exit(main())
