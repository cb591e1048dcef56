#!/usr/bin/python3
"""CTest (label petsc): TAO's types in `cbps converge` and `cbps profile`, run in one process
beside the cbps solvers (docs/distributed.md, "TAO beside PGS: converge and profile").

    /usr/bin/python3 tests/petsc/test_tao_studies.py CBPS MODE DIR

MODE is one of
  converge       a 300-row chain (A positive definite, no bounds) with --solvers
                 direct,tao:bqpip,tao:tron in one process: each tao row reaches the direct row's
                 lambda within a bound from the two residuals and numpy's ‖A⁻¹‖∞, its history
                 starts at numpy's residual of lambda = 0, ends at the residual of `cbps lcp
                 --solver tao:TYPE` (another path through solve_tao, same iterations), and is
                 monotone for tron; PETSc is finalised once (-log_view prints one summary); a
                 time limit stops bncg; `mpirun -n 2` is refused with exit 2
  profile        `cbps profile --quick` on the quick library of scripts/make_problem_library.py
                 with tao:bqpip and tao:gpcg: their rows in profile.json/csv, in the sweeps
                 profiles, solved rows with the residual they claim and lambda near the
                 library's exact answer on the definite chains
  without-petsc  a build without PETSc: tao: in converge's and profile's --solvers exits 2 with
                 the message of `cbps lcp --solver tao:`

Exit 0 when every check passes (each failed check is printed).
"""
import csv
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import scipy.io

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_tao import check, failures  # noqa: E402  (one record of failures for the drivers)


def run(args, env=None):
    e = dict(os.environ)
    e.update(env or {})
    return subprocess.run(args, capture_output=True, text=True, timeout=120, env=e)


def fresh(path):
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)


def mode_converge(cbps, root):
    fresh(root)
    chain = os.path.join(root, "chain")
    r = run([cbps, "matrices", "chain", "--param", "n=300", "--step", "10", "--out", chain])
    if not check(r.returncode == 0, f"cbps matrices: {r.stderr}"):
        return
    A = scipy.io.mmread(os.path.join(chain, "A.mtx")).toarray()
    b = scipy.io.mmread(os.path.join(chain, "b.mtx")).ravel()
    # No bounds on a chain's distance rows: the natural-map residual of lambda = 0 is ‖b‖∞ and
    # lambda - lambda* = A⁻¹ (w - w*), so ‖lambda - lambda*‖∞ <= ‖A⁻¹‖∞ (r + r*).
    inv_norm = np.abs(np.linalg.inv(A)).sum(axis=1).max()
    out = os.path.join(root, "converge")
    solvers = ["direct", "tao:bqpip", "tao:tron"]
    r = run([cbps, "converge", chain, "--solvers", ",".join(solvers), "--iterations", "1000",
             "--quiet", "--no-plot", "--out", out])
    if not check(r.returncode == 0, f"converge exited {r.returncode}: {r.stderr}"):
        return
    summary = json.load(open(os.path.join(out, "summary.json")))
    rows = {}
    for row in csv.DictReader(open(os.path.join(out, "convergence.csv"))):
        rows.setdefault(row["solver"], []).append(row)
    by_name = {j["solver"]: j for j in summary["solvers"]}
    check(sorted(by_name) == sorted(solvers), f"summary solvers {sorted(by_name)}")
    direct = by_name["direct"]
    for name in ("tao:bqpip", "tao:tron"):
        j, history = by_name[name], rows.get(name, [])
        check(j["method"] == "tao", f"{name}: method {j['method']}")
        check(j["stopped"] == "residual tolerance", f"{name}: stopped {j['stopped']}")
        bound = inv_norm * (j["residual"] + direct["residual"])
        check(j["lambda_error"] is not None and j["lambda_error"] <= bound,
              f"{name}: |lambda - lambda_direct| {j['lambda_error']} > {bound:.3g}")
        check(j["residual"] <= 1e-10, f"{name}: residual {j['residual']}")
        if not check(len(history) >= 2, f"{name}: {len(history)} rows in convergence.csv"):
            continue
        its = [int(h["iteration"]) for h in history]
        times = [float(h["time_s"]) for h in history]
        res = [float(h["residual"]) for h in history]
        check(its == sorted(set(its)) and its[0] == 0, f"{name}: iterations {its}")
        check(times == sorted(times), f"{name}: time goes back: {times}")
        # (convergence.csv holds 9 significant digits)
        check(abs(res[0] - np.abs(b).max()) <= 1e-8 * np.abs(b).max(),
              f"{name}: residual at lambda = 0 {res[0]}, numpy's |b|inf {np.abs(b).max()}")
        check(abs(res[-1] - j["residual"]) <= 1e-8 * j["residual"] and its[-1] == j["iterations"],
              f"{name}: history ends at {its[-1]}, {res[-1]}; summary {j['iterations']}, "
              f"{j['residual']}")
        # The same solve through `cbps lcp`: same iterations, same residual.
        r = run([cbps, "lcp", chain, "--solver", name, "--iterations", "1000", "--json"])
        if check(r.returncode == 0, f"lcp --solver {name}: {r.stderr}"):
            lcp = json.loads(r.stdout)
            check(lcp["iterations"] == j["iterations"],
                  f"{name}: lcp {lcp['iterations']} iterations, converge {j['iterations']}")
            check(abs(lcp["residual"] - j["residual"]) <= 1e-15 + 1e-9 * lcp["residual"],
                  f"{name}: lcp residual {lcp['residual']}, converge {j['residual']}")
        print(f"{name}: {j['iterations']} iterations, residual {j['residual']:.3g} N, "
              f"|lambda - lambda_direct| {j['lambda_error']:.3g} <= {bound:.3g}, "
              f"history {['%.3g' % x for x in res]}")
    # tron's history on this chain (measured: 2.4, 1.09, 0.47, 0.45, 0.32, 0.042, 6.7e-13 N):
    # every Newton step lowers the residual. A trust-region Newton method on a definite
    # quadratic need not do so step by step, so allow a rise of 10 % over the best so far.
    tron = [float(h["residual"]) for h in rows.get("tao:tron", [])]
    for k in range(1, len(tron)):
        check(tron[k] <= 1.1 * min(tron[:k]), f"tao:tron: residual rises at {k}: {tron}")

    # One PETSc for the whole command: -log_view prints its summary at PetscFinalize.
    r = run([cbps, "converge", chain, "--solvers", "tao:bqpip,tao:gpcg,tao:tron", "--quiet",
             "--no-plot"], env={"PETSC_OPTIONS": "-log_view"})
    check(r.returncode == 0, f"converge with three tao specs: {r.stderr}")
    n = r.stdout.count("PETSc Performance Summary")
    check(n == 1, f"PETSc finalised {n} times for three tao specs (-log_view)")
    # The time limit stops a slow type (bncg needs 10000 iterations here).
    r = run([cbps, "converge", chain, "--solvers", "tao:bncg", "--time-limit", "0.05", "--quiet",
             "--no-plot", "--json"])
    if check(r.returncode == 0, f"converge tao:bncg: {r.stderr}"):
        j = json.loads(r.stdout)["solvers"][0]
        check(j["stopped"] == "time limit" and 0.05 <= j["time_s"] < 1.0,
              f"tao:bncg with --time-limit 0.05: {j['stopped']} after {j['time_s']} s")
    # Not under mpirun with more ranks than one: exit 2 on every rank.
    mpirun = os.environ.get("CBPS_MPIEXEC") or shutil.which("mpirun")
    if mpirun and os.path.exists(mpirun):
        r = run([mpirun, "-n", "2", "--oversubscribe", cbps, "converge", chain, "--solvers",
                 "tao:bqpip", "--quiet", "--no-plot"],
                env={"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"})
        check(r.returncode == 2 and "without mpirun" in r.stderr,
              f"mpirun -n 2 converge: exit {r.returncode}, {r.stderr[-300:]}")


def mode_profile(cbps, root):
    fresh(root)
    lib = os.path.join(root, "lib")
    r = run([sys.executable, os.path.join(ROOT, "scripts", "make_problem_library.py"), cbps, lib,
             "--quick"])
    if not check(r.returncode == 0, f"make_problem_library: {r.stderr}"):
        return
    out = os.path.join(root, "profile")
    solvers = ["pgs", "direct", "tao:bqpip", "tao:gpcg"]
    r = run([cbps, "profile", lib, "--quick", "--solvers", ",".join(solvers), "--time-limit",
             "0.2", "--quiet", "--no-plot", "--out", out])
    if not check(r.returncode == 0, f"profile exited {r.returncode}: {r.stderr}"):
        return
    j = json.load(open(os.path.join(out, "profile.json")))
    index = {p["name"]: p for p in json.load(open(os.path.join(lib, "library.json")))["problems"]}
    methods = {s["solver"]: (s["method"], s["exact"]) for s in j["solvers"]}
    for name in ("tao:bqpip", "tao:gpcg"):
        check(methods.get(name) == ("tao", False), f"{name}: solvers entry {methods.get(name)}")
    for profile in j["profiles"]:
        want = solvers if profile["measure"] == "time" else ["pgs", "tao:bqpip", "tao:gpcg"]
        check(profile["solvers"] == want,
              f"{profile['measure']} profile at {profile['tolerance']}: {profile['solvers']}")
    tao = [m for m in j["measurements"] if m["solver"].startswith("tao:")]
    check(len(tao) == 2 * len(index), f"{len(tao)} tao measurements for {len(index)} problems")
    solved_chains = 0
    for m in tao:
        label = f"{m['solver']} on {m['problem']}"
        p = index[m["problem"]]
        reached = m["reached"]["1e-10"]
        if m["status"] == "solved":
            check(m["residual_relative"] <= 1e-10, f"{label}: solved at {m['residual_relative']}")
            check(reached is not None and reached["iterations"] <= m["iterations"],
                  f"{label}: reached {reached}, {m['iterations']} iterations")
        else:
            check(m["status"] in ("time limit", "iteration budget") or m["status"].startswith(
                "TAO "), f"{label}: status {m['status']}")
            check(m["status"] != "time limit" or m["time_s"] < 0.2 + 0.5,
                  f"{label}: {m['time_s']} s past the 0.2 s limit")
        # A chain's rows have no bounds (measured: bqpip and gpcg solve them in 1 iteration):
        # lambda - lambda* = A⁻¹ (w - w*), so ‖lambda - lambda*‖∞ <= ‖A⁻¹‖∞ (r + r*), with A the
        # matrix solved (A + eps I with the folder's cfm.txt) by numpy.
        if p["source"].get("scene") == "chain":
            solved_chains += m["status"] == "solved"
            folder = os.path.join(lib, p["path"])
            A = scipy.io.mmread(os.path.join(folder, "A.mtx")).toarray()
            cfm_file = os.path.join(folder, "cfm.txt")
            if os.path.exists(cfm_file):
                A += float(open(cfm_file).read().split()[0]) * np.eye(A.shape[0])
            inv_norm = np.abs(np.linalg.inv(A)).sum(axis=1).max()
            bound = inv_norm * (m["residual_relative"] + p["exact_residual_relative"]) * p["scale"]
            check(m["lambda_error"] is not None and m["lambda_error"] <= bound,
                  f"{label}: |lambda - lambda*| {m['lambda_error']} > {bound:.3g}")
            print(f"{label}: |lambda - lambda*| {m['lambda_error']:.3g} <= {bound:.3g}")
        print(f"{label}: {m['status']}, {m['iterations']} iterations, {m['time_s']:.3g} s, "
              f"relative residual {m['residual_relative']}")
    check(solved_chains == 4, f"{solved_chains} of 4 tao runs on the two chains solved")
    rows = list(csv.DictReader(open(os.path.join(out, "profile.csv"))))
    check(sum(r["solver"].startswith("tao:") for r in rows) == len(tao), "profile.csv tao rows")


def mode_without_petsc(cbps, root):
    fresh(root)
    folder = os.path.join(root, "small")
    r = run([cbps, "matrices", "chain", "--param", "n=3", "--out", folder])
    check(r.returncode == 0, f"cbps matrices: {r.stderr}")
    lcp = run([cbps, "lcp", folder, "--solver", "tao:bqpip"])
    check(lcp.returncode == 2, f"lcp: exit {lcp.returncode}, expected 2")
    message = lcp.stderr.split("tao:bqpip", 1)[-1].strip()
    for args in (["converge", folder, "--solvers", "pgs,tao:bqpip", "--no-plot"],
                 ["profile", os.path.join(root, "no-library"), "--solvers", "pgs,tao:bqpip"]):
        r = run([cbps] + args)
        check(r.returncode == 2, f"{args[0]}: exit {r.returncode}, expected 2")
        check("--solvers tao:bqpip" in r.stderr and r.stderr.strip().endswith(message),
              f"{args[0]}: not lcp's message: {r.stderr} (lcp: {lcp.stderr})")
        print(r.stderr.strip())


def main():
    cbps, mode, root = sys.argv[1], sys.argv[2], sys.argv[3]
    modes = {"converge": mode_converge, "profile": mode_profile,
             "without-petsc": mode_without_petsc}
    if mode not in modes:
        print(f"unknown mode {mode}", file=sys.stderr)
        return 2
    modes[mode](cbps, os.path.join(root, mode))
    print(f"{len(failures)} failed" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
