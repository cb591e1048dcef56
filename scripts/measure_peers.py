#!/usr/bin/python3
"""Measures the peers (Siconos' and Bullet's solvers as cbps methods, judged by cbps's natural-map
residual) beside cbps's own: on the contact problems of docs/exact-path.md at the sizes the dense
peers take, and over the problem library with `cbps profile`. Writes what docs/peers.md shows
as JSON (format cbps-peers/1).

    /usr/bin/python3 scripts/measure_peers.py CBPS OUT.json [--work DIR] [--quick]

CBPS is a build with the peers (CBPS_PEERS; scripts/setup.sh installs Siconos and Bullet); the
script stops, writing nothing, at the first peer the build lacks.

"exact_path": `cbps matrices` writes each problem (the 10-box stack at step 30, 120 rows; the
pyramids of base 5, 8 and 10 at step 10, up to 1,200 rows), then `cbps lcp F --solver direct
--json` and `cbps lcp F --solver PEER --iterations 100000 --json` for every peer, each call with
a time limit of 600 s (a call over it is killed with its process group and recorded as
"timeout"). Per problem and solver: cbps's verdict (`status`: solved, failed, no_solution;
"refused" where the peer cannot take the problem, exit 2, with its message; "timeout"; "error"
for any other exit), the residual, the scale and their ratio, the wall time of the solve, and the
peer's own word (the `peer` object of `cbps lcp --json`).

"profile": scripts/make_problem_library.py writes the library (37 problems; --quick the 8 quick
ones), `cbps profile LIB --solvers pgs,direct,PEERS... --quiet --out W/profile` runs every solver
on every problem, and its profile.json is reduced to: per solver the problems solved at a
unit-free 1e-4, 1e-8 and 1e-10 (a measurement's `reached`) and the median time and iterations of
those solved at 1e-10; per problem family (a scene problem's name up to its first '-', "siconos"
for the Siconos files) and solver the problems run, solved, failed (of those the peer's process
ended by Siconos: aborted), claimed solved wrongly ("peer said ok; unit-free residual ..."), refused ("not
applicable: ...") and the largest relative residual of the unsolved; and every measurement's
problem, solver, status, relative residual, time, iterations and the peer's own status.
Iterations are as profile.json gives them: sweeps, pivots, outer iterations, and 0 where a peer
does not report its count (siconos:enum, bullet:dantzig, bullet:lemke).

--quick (a check of the script itself): the stack and the base-5 pyramid, the quick library.
The load average after each command is recorded (other work on the machine slows the times).
Exit 1 without writing OUT as soon as CBPS changes during the run (rebuilt: run it again); exit 1
after writing OUT when a command ended in an unexpected way (an exit status other than 0, 1 and
2; recorded as "error"), with a message; the peers' failures are results, not errors.
"""
import argparse
import datetime
import json
import os
import platform
import shlex
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time

from cbps_files import read_number, write_json  # scripts/cbps_files.py, beside this script

FORMAT = "cbps-peers/1"
PEERS = ["siconos:lemke", "siconos:pgs", "siconos:enum", "siconos:avi", "bullet:dantzig",
         "bullet:lemke", "bullet:pgs"]
PROFILE_SOLVERS = ["pgs", "direct"] + PEERS
PEER_ITERATIONS = "100000"
TIMEOUT_S = 600
# (name, label, the arguments of `cbps matrices` before --out): docs/exact-path.md's contact
# problems.
PROBLEMS = [
    ("stack10", "stack of 10 boxes, step 30", ["stack", "--step", "30"]),
    ("pyramid5", "pyramid, base 5, step 10", ["pyramid", "--param", "base=5", "--step", "10"]),
    ("pyramid8", "pyramid, base 8, step 10", ["pyramid", "--param", "base=8", "--step", "10"]),
    ("pyramid10", "pyramid, base 10, step 10",
     ["pyramid", "--param", "base=10", "--step", "10"]),
]
QUICK = ("stack10", "pyramid5")
TOLERANCES = ("0.0001", "1e-08", "1e-10")  # cbps profile's (include/cbps/studies/profile.hpp)
# How profile.json's status marks a peer's outcome (src/studies/profile.cpp, profile_peer).
WRONG_CLAIM = "peer said ok; unit-free residual"  # profile.cpp profile_peer
PEER_FAILED = "peer said failed"
REFUSED = "not applicable: "
ABORTED = "ended the process"  # the peer_status of a Siconos child that did not reply


def log(text):
    print(f"measure_peers: {text}", file=sys.stderr, flush=True)


BINARY = {}  # the path of CBPS and its modification time when the script started


def check_binary():
    """Stops the script (nothing written) when CBPS was rebuilt since it started."""
    path, built = BINARY["path"], BINARY["mtime"]
    if os.stat(path).st_mtime != built:
        sys.exit(f"measure_peers: {path} was rebuilt during the measurement; run it again "
                 "(nothing written)")


def run(cmd, cwd, timeout=TIMEOUT_S):
    """(exit status or None on a timeout, stdout, stderr, seconds). The command runs in its own
    process group (cbps forks a child for Siconos), which a timeout kills whole."""
    check_binary()
    start = time.monotonic()
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
        return proc.returncode, out, err, time.monotonic() - start
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        return None, out, err, time.monotonic() - start


def write_results(out, results, start, say):
    """Stamps results with the wall time since `start` (time.monotonic()), stops (nothing
    written) when CBPS was rebuilt meanwhile, writes OUT (its folder made) and says so by
    `say`: the end of every measure_*.py that runs CBPS through run()."""
    results["wall_time_s"] = time.monotonic() - start
    check_binary()
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    write_json(out, results)
    say(f"wrote {out} ({results['wall_time_s']:.0f} s)")


def relative(residual, scale):
    r, s = read_number(residual), read_number(scale)
    if r is None or s is None or s == 0:
        return None
    return r / s


def exact_path_run(cbps, work, name, solver):
    """One `cbps lcp` on the folder NAME: its verdict and the peer's word."""
    args = ["lcp", name, "--solver", solver, "--json"]
    if solver != "direct":
        args[4:4] = ["--iterations", PEER_ITERATIONS]
    log(f"cbps {' '.join(args)}")
    code, out, err, elapsed = run([cbps] + args, work)
    entry = {"solver": solver, "command": "cbps " + " ".join(args), "exit": code,
             "job_s": elapsed, "load_average": os.getloadavg()[0]}
    if code is None:
        entry.update(status="timeout", message=f"no answer within {TIMEOUT_S} s (killed)")
        return entry
    if code == 2:
        message = err.strip().removeprefix("cbps: ")
        if "this build has no" in message:  # peers.cpp, peer_refusal: a build without it
            sys.exit(f"measure_peers: {message}")
        entry.update(status="refused", message=message)
        return entry
    try:
        j = json.loads(out) if code in (0, 1) else None
    except json.JSONDecodeError:
        j = None
    if j is None:
        entry.update(status="error", message=f"exit {code}: {err.strip()[-2000:]}")
        return entry
    peer = j.get("peer") or {}
    entry.update({
        "rows": j["rows"], "status": j["status"], "residual": j["residual"],
        "scale": j["scale"], "residual_relative": relative(j["residual"], j["scale"]),
        "wall_time_s": j["wall_time_s"], "iterations": j["iterations"],
        "message": j["message"],
        "peer_status": peer.get("status"), "said_ok": peer.get("said_ok"),
        "peer_iterations": peer.get("iterations"),
        "convert_time_s": peer.get("convert_time_s"), "solve_time_s": peer.get("solve_time_s"),
        "disagrees": peer.get("disagrees")})
    return entry


def exact_path(cbps, work, quick):
    problems = []
    for name, label, args in PROBLEMS:
        if quick and name not in QUICK:
            continue
        shutil.rmtree(os.path.join(work, name), ignore_errors=True)
        matrices = ["matrices"] + args + ["--out", name, "--quiet"]
        log(f"cbps {' '.join(matrices)}")
        code, _, err, _ = run([cbps] + matrices, work)
        if code != 0:
            sys.exit(f"measure_peers: cbps {' '.join(matrices)}: exit {code}: {err}")
        runs = [exact_path_run(cbps, work, name, s) for s in ["direct"] + PEERS]
        rows = next((r["rows"] for r in runs if "rows" in r), None)
        problems.append({"name": name, "label": label, "command": "cbps " + " ".join(matrices),
                         "rows": rows, "runs": runs})
    return {"solvers": ["direct"] + PEERS, "iterations": int(PEER_ITERATIONS),
            "timeout_s": TIMEOUT_S, "problems": problems}


def family(problem):
    return "siconos" if problem["kind"] == "siconos" else problem["name"].split("-", 1)[0]


def median(values):
    return statistics.median(values) if values else None


def reduce_profile(j):
    """profile.json → per solver, per family and solver, and the measurements (module doc)."""
    problems = {p["name"]: p for p in j["problems"]}
    families = list(dict.fromkeys(family(p) for p in j["problems"]))
    solvers = [s["solver"] for s in j["solvers"]]
    measurements = []
    for m in j["measurements"]:
        measurements.append({
            "problem": m["problem"], "family": family(problems[m["problem"]]),
            "rows": problems[m["problem"]]["rows"], "solver": m["solver"],
            "status": m["status"], "residual_relative": m["residual_relative"],
            "time_s": m["time_s"], "iterations": m["iterations"],
            "peer_status": m.get("peer_status"), "convert_time_s": m.get("convert_time_s"),
            "reached": {t: (m["reached"][t] is not None) for t in TOLERANCES}})
    per_solver = []
    for s in solvers:
        mine = [m for m in j["measurements"] if m["solver"] == s]
        done = [m for m in mine if m["reached"]["1e-10"] is not None]
        per_solver.append({
            "solver": s, "problems": len(mine),
            "solved": {t: sum(m["reached"][t] is not None for m in mine) for t in TOLERANCES},
            "median_time_s": median([m["reached"]["1e-10"]["time_s"] for m in done]),
            "median_iterations": median([m["iterations"] for m in done])})
    per_family = []
    for f in families:
        for s in solvers:
            mine = [m for m in measurements if m["family"] == f and m["solver"] == s]
            refused = [m for m in mine if m["status"].startswith(REFUSED)]
            ran = [m for m in mine if not m["status"].startswith(REFUSED)]
            solved = [m for m in ran if m["status"] == "solved"]
            wrong = [m for m in ran if m["status"].startswith(WRONG_CLAIM)]
            failed = [m for m in ran if m["status"] != "solved" and m not in wrong]
            unsolved = [read_number(m["residual_relative"]) for m in ran
                        if m["status"] != "solved"]
            unsolved = [r for r in unsolved if r is not None]
            per_family.append({
                "family": f, "solver": s, "problems": len(mine), "run": len(ran),
                "solved": len(solved), "failed": len(failed),
                "aborted": sum((m["peer_status"] or "").startswith(ABORTED) for m in failed),
                "wrong_claims": len(wrong), "refused": len(refused),
                "largest_unsolved_residual_relative": max(unsolved) if unsolved else None,
                "largest_wrong_claim_residual_relative":
                    max((read_number(m["residual_relative"]) for m in wrong), default=None)})
    return {"families": families, "per_solver": per_solver, "per_family": per_family,
            "measurements": measurements}


def profile(cbps, work, quick):
    here = os.path.dirname(os.path.abspath(__file__))
    library = os.path.join(work, "library")
    shutil.rmtree(library, ignore_errors=True)
    make = ["/usr/bin/python3", os.path.join(here, "make_problem_library.py"), cbps, "library"]
    if quick:
        make.append("--quick")
    log("make_problem_library.py CBPS library" + (" --quick" if quick else ""))
    code, _, err, _ = run(make, work)
    if code != 0:
        sys.exit(f"measure_peers: {' '.join(make)}: exit {code}: {err}")
    shutil.rmtree(os.path.join(work, "profile"), ignore_errors=True)
    args = ["profile", "library", "--solvers", ",".join(PROFILE_SOLVERS), "--quiet",
            "--out", "profile"]
    log(f"cbps {' '.join(args)}")
    code, _, err, elapsed = run([cbps] + args, work, timeout=None)
    if code != 0:
        sys.exit(f"measure_peers: cbps {' '.join(args)}: exit {code}: {err}")
    with open(os.path.join(work, "profile", "profile.json"), encoding="utf-8") as f:
        j = json.load(f)
    out = {"library_command": "scripts/make_problem_library.py CBPS library"
                              + (" --quick" if quick else ""),
           "command": "cbps " + " ".join(args), "job_s": elapsed,
           "load_average": os.getloadavg()[0],
           "budget_iterations": j["budget_iterations"], "time_limit_s": j["time_limit_s"],
           "tolerances": j["tolerances"], "wall_time_s": j["wall_time_s"],
           "solvers": [s["solver"] for s in j["solvers"]],
           "problems": [{"name": p["name"], "family": family(p), "kind": p["kind"],
                         "rows": p["rows"]} for p in j["problems"]],
           # What Siconos printed as the process it ran in ended (an assertion), once each.
           "stderr": list(dict.fromkeys(line for line in err.splitlines() if line.strip()))}
    out.update(reduce_profile(j))
    return out


def git_commit(root):
    try:
        r = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root,
                           capture_output=True, text=True)
    except OSError:
        return None
    return r.stdout.strip() if r.returncode == 0 else None


def begin(args, prefix):
    """The common start of a measure_*.py that runs CBPS through run(): its clock, its work
    folder (--work, else a new temporary one named PREFIX...), CBPS's path and modification time
    (BINARY, checked by run()) and the repository's root, as (start, work, cbps, root)."""
    start = time.monotonic()
    work = os.path.abspath(args.work or tempfile.mkdtemp(prefix=prefix))
    os.makedirs(work, exist_ok=True)
    cbps = os.path.abspath(args.cbps)
    BINARY.update(path=cbps, mtime=os.stat(cbps).st_mtime)
    return start, work, cbps, os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cbps")
    ap.add_argument("out")
    ap.add_argument("--work")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    start = time.monotonic()
    work = os.path.abspath(args.work or tempfile.mkdtemp(prefix="cbps_measure_peers_"))
    os.makedirs(work, exist_ok=True)
    cbps = os.path.abspath(args.cbps)
    BINARY.update(path=cbps, mtime=os.stat(cbps).st_mtime)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    nproc = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    results = {"format": FORMAT,
               "command": shlex.join(["scripts/measure_peers.py"] + sys.argv[1:]),
               "cbps_commit": git_commit(root),
               "date": datetime.date.today().isoformat(), "machine": platform.node(),
               "nproc": nproc, "quick": args.quick}
    results["exact_path"] = exact_path(cbps, work, args.quick)
    results["profile"] = profile(cbps, work, args.quick)
    write_results(args.out, results, start, log)
    errors = [f"{p['name']} {r['solver']}: {r['message']}" for p in
              results["exact_path"]["problems"] for r in p["runs"] if r["status"] == "error"]
    if errors:
        sys.exit("measure_peers: unexpected ends: " + "; ".join(errors))


if __name__ == "__main__":
    main()
