#!/usr/bin/python3
"""Measures the direct path's warm steps in running scenes against PGS sweeps of the same scenes
(issue 32's targets), and writes what docs/exact-path.md's warm table shows as JSON (format
cbps-warm/1).

    /usr/bin/python3 scripts/measure_warm.py CBPS OUT.json [--work DIR] [--repeats R] [--quick]

The scenes: the resting 10-box stack (`stack`, 600 steps = 10 s), the 100-column stack (`stack
--param columns=100`, 1,000 boxes, 120 steps) and the base-20 pyramid (`pyramid --param
base=20`, 210 boxes, 120 steps), each under both pushes (`--param push=original`: the one system
of 5.3; `push=improved`: the velocity and position systems of 8.1). Each is run with

- "direct": `cbps run SCENE --steps N --solver direct --out W/...` (warm start on, the default:
  every step starts from the last step's λ through contact persistence);
- "pgs_10": `--solver pgs --iterations 10 --tolerance 0`, ten sweeps a step on each of the
  step's systems, an engine's budget;
- "direct_cold" (once per scene and push): `--solver direct:warm=off`, every step from scratch.

From each run's `steps.csv` (docs/outputs.md): the solve stage's time per step (`solve_time_s`)
averaged over the steady state, the second half of the steps; the direct path's route per step
(`direct_route`) and its largest residual (N). From each run's summary: the assembly stage's
mean time a step (`stage_times_s`) and its name in `stages`, which says whether A = J Minv Jᵀ
was formed (PGS reads A; the direct path does not, issue 32). One PGS sweep's time is the pgs_10 step's solve
time / 10, so "sweeps" = direct's solve time a step / one sweep's time: the target is ≤ 10. The
two are run one after the other R times (default 3) and the median of the R ratios is reported.
The residual target is 1e-10 relative: the residual in N over max(1, ‖b‖∞, max |A_ij|) ≥ 1, so
an absolute residual ≤ 1e-10 N meets it.

The cross-check (`--check`: every step solved again by the direct path from PGS's λ) on the
pyramid: `cbps run pyramid --param base=20 --steps 120 --solver pgs [--check]`, the scene's own
PGS settings; the ratio of the two runs' `wall_time_s` (target ≤ 2), and how many steps the
direct path left unverified.

--quick (a check of the script itself): 20 steps each, one repetition. The load average after
each run is recorded. Exit 1 without writing OUT when CBPS changes during the run.
"""
import argparse
import csv
import datetime
import json
import os
import platform
import shlex
import statistics
import sys
import tempfile
import time

import measure_peers as peers  # run(), BINARY, git_commit(): the same job control

FORMAT = "cbps-warm/1"
SCENES = [  # (name, cbps run arguments, steps)
    ("stack 10", ["stack"], 600),
    ("stack 100x10", ["stack", "--param", "columns=100"], 120),
    ("pyramid 20", ["pyramid", "--param", "base=20"], 120),
]
PUSHES = ("original", "improved")


def log(text):
    print(f"measure_warm: {text}", file=sys.stderr, flush=True)


def cbps_run(cbps, work, name, args):
    """Runs `cbps run ARGS --out W/name --quiet`; (summary, steps rows) or SystemExit."""
    out = os.path.join(work, name)
    code, _, err, seconds = peers.run([cbps, "run"] + args + ["--out", out, "--quiet"], work)
    if code != 0:
        sys.exit(f"measure_warm: cbps run {shlex.join(args)} failed ({code}): {err.strip()}")
    with open(os.path.join(out, "summary.json"), encoding="utf-8") as f:
        summary = json.load(f)
    with open(os.path.join(out, "steps.csv"), encoding="utf-8", newline="") as f:
        steps = list(csv.DictReader(f))
    log(f"{name}: {seconds:.1f} s")
    return summary, steps


def steady(steps):
    """The second half of the steps: the steady state."""
    return steps[len(steps) // 2:]


def mean_solve(steps):
    window = steady(steps)
    return sum(float(s["solve_time_s"]) for s in window) / len(window)


def assembly(summary, steps):
    """The assembly stage's mean time a step (summary's stage_times_s over all steps) and its
    name in `stages` (whether A was formed)."""
    names = [n for n in summary["stages"] if n.startswith("assembly")]
    return {"assembly_per_step_s": summary["stage_times_s"]["assembly"] / len(steps),
            "assembly_stage": names[0] if names else None}


def direct_facts(summary, steps):
    routes = {}
    for s in steady(steps):
        routes[s["direct_route"]] = routes.get(s["direct_route"], 0) + 1
    return {"solve_per_step_s": mean_solve(steps),
            "max_residual_N": summary["max_residual"],
            "routes": summary.get("direct_routes", {}),
            "routes_position": summary.get("direct_routes_position"),
            "steady_routes": routes,
            "rows": summary["rows"], **assembly(summary, steps)}


def measure_scene(cbps, work, label, args, steps, push, repeats):
    base = args + ["--param", f"push={push}", "--steps", str(steps)]
    tag = label.replace(" ", "_") + "_" + push
    runs = []
    for k in range(repeats):
        ds, dsteps = cbps_run(cbps, work, f"{tag}_direct_{k}", base + ["--solver", "direct"])
        ps, psteps = cbps_run(cbps, work, f"{tag}_pgs_{k}",
                              base + ["--solver", "pgs", "--iterations", "10", "--tolerance",
                                      "0"])
        direct = direct_facts(ds, dsteps)
        sweep = mean_solve(psteps) / 10.0
        runs.append({"direct": direct, "pgs_sweep_s": sweep, "pgs": assembly(ps, psteps),
                     "pgs_max_residual_N": ps["max_residual"],
                     "sweeps": direct["solve_per_step_s"] / sweep,
                     "load": os.getloadavg()[0]})
    cs, csteps = cbps_run(cbps, work, f"{tag}_cold", base + ["--solver", "direct:warm=off"])
    cold = direct_facts(cs, csteps)
    ratios = [r["sweeps"] for r in runs]
    return {"scene": label, "command": "cbps run " + shlex.join(base),
            "push": push, "steps": steps, "rows": runs[0]["direct"]["rows"],
            "runs": runs, "sweeps_median": statistics.median(ratios),
            "max_residual_N": max(r["direct"]["max_residual_N"] for r in runs),
            "cold": cold, "cold_sweeps": cold["solve_per_step_s"] / statistics.median(
                r["pgs_sweep_s"] for r in runs)}


def measure_check(cbps, work, steps, repeats):
    base = ["pyramid", "--param", "base=20", "--steps", str(steps), "--solver", "pgs"]
    runs = []
    for k in range(repeats):
        plain, _ = cbps_run(cbps, work, f"check_plain_{k}", base)
        checked, _ = cbps_run(cbps, work, f"check_checked_{k}", base + ["--check"])
        cross = checked["cross_check"]
        runs.append({"plain_s": plain["wall_time_s"], "checked_s": checked["wall_time_s"],
                     "ratio": checked["wall_time_s"] / plain["wall_time_s"],
                     "direct_unverified": cross["direct_unverified"],
                     "max_direct_residual_N": cross["max_direct_residual"],
                     "max_velocity_difference": cross["max_velocity_difference"],
                     "pgs_solve_s": plain["stage_times_s"]["solve"],
                     "direct_s": cross["direct_time_s"],
                     "direct_pivots": cross["direct_pivots"],
                     "direct_routes": cross["direct_routes"]})
    return {"command": "cbps run " + shlex.join(base) + " [--check]", "steps": steps, "runs": runs,
            "ratio_median": statistics.median(r["ratio"] for r in runs)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cbps")
    ap.add_argument("out")
    ap.add_argument("--work")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    start = time.monotonic()
    work = os.path.abspath(args.work or tempfile.mkdtemp(prefix="cbps_measure_warm_"))
    os.makedirs(work, exist_ok=True)
    cbps = os.path.abspath(args.cbps)
    peers.BINARY.update(path=cbps, mtime=os.stat(cbps).st_mtime)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    repeats = 1 if args.quick else args.repeats
    scenes = [(label, a, 20 if args.quick else n) for label, a, n in SCENES]
    results = {"format": FORMAT,
               "command": shlex.join(["scripts/measure_warm.py"] + sys.argv[1:]),
               "cbps_commit": peers.git_commit(root),
               "date": datetime.date.today().isoformat(), "machine": platform.node(),
               "nproc": os.cpu_count(), "quick": args.quick, "repeats": repeats,
               "scenes": [measure_scene(cbps, work, label, a, n, push, repeats)
                          for label, a, n in scenes for push in PUSHES],
               "check": measure_check(cbps, work, 20 if args.quick else 120, repeats)}
    peers.write_results(args.out, results, start, log)


if __name__ == "__main__":
    main()
