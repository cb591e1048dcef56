#!/usr/bin/python3
"""Runs TAO's types beside PGS, APGD and the direct path in `cbps converge` (the 300-row chain and
the 240-row stack of the petsc tests) and in `cbps profile` (the quick problem library), and
keeps what docs/distributed.md ("TAO beside PGS") shows from their summaries, as JSON.

    /usr/bin/python3 scripts/measure_tao_studies.py CBPS OUT.json [--work DIR]

CBPS is a build with PETSc. One run each, in one process (TAO runs in the command's own
process); every command is recorded in the JSON, with the machine's load average after it.
"""
import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time

from cbps_files import write_json  # scripts/cbps_files.py
from cbps_problem import PETSC_PROBLEMS as PROBLEMS  # scripts/cbps_problem.py

CONVERGE = {
    "chain": "direct,pgs,apgd,tao:bqpip,tao:gpcg,tao:tron,tao:bncg",
    "stack": "direct,pgs,apgd,tao:bqpip,tao:gpcg,tao:tron",
}
CONVERGE_TIME_LIMIT = "2"
PROFILE_SOLVERS = "pgs,apgd,direct,tao:bqpip,tao:gpcg,tao:tron"
PROFILE_TIME_LIMIT = "0.5"
KEEP = ("solver", "method", "iterations", "time_s", "residual", "stopped", "reached",
        "lambda_error", "velocity_error")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cbps")
    ap.add_argument("out")
    ap.add_argument("--work")
    args = ap.parse_args()
    env = dict(os.environ)
    env.pop("PETSC_OPTIONS", None)
    work = args.work or tempfile.mkdtemp(prefix="cbps_measure_tao_studies_")
    os.makedirs(work, exist_ok=True)
    cbps = os.path.abspath(args.cbps)
    here = os.path.dirname(os.path.abspath(__file__))
    results = {"format": "cbps-tao-studies/1", "machine": platform.node(),
               "cpus": os.cpu_count(), "converge": {}}

    def run(cmd):
        print("measure_tao_studies: " + " ".join(cmd[1:]), file=sys.stderr, flush=True)
        start = time.monotonic()
        r = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=work)
        if r.returncode != 0:
            sys.exit(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr}")
        return time.monotonic() - start

    for name, solvers in CONVERGE.items():
        problem = os.path.join(work, name)
        shutil.rmtree(problem, ignore_errors=True)
        run([cbps] + PROBLEMS[name] + ["--out", name])
        out = os.path.join(work, name + "-converge")
        shutil.rmtree(out, ignore_errors=True)
        args_ = ["converge", name, "--solvers", solvers, "--time-limit", CONVERGE_TIME_LIMIT,
                 "--quiet", "--out", name + "-converge"]
        run([cbps] + args_)
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        results["converge"][name] = {
            "problem_command": "cbps " + " ".join(PROBLEMS[name]) + " --out " + name,
            "command": "cbps " + " ".join(args_), "rows": s["rows"],
            "lambda_unique": s["lambda_unique"], "load_average": os.getloadavg()[0],
            "solvers": [{k: x.get(k) for k in KEEP} for x in s["solvers"]]}

    library = os.path.join(work, "library")
    shutil.rmtree(library, ignore_errors=True)
    run(["/usr/bin/python3", os.path.join(here, "make_problem_library.py"), cbps, library,
         "--quick"])
    shutil.rmtree(os.path.join(work, "profile"), ignore_errors=True)
    args_ = ["profile", "library", "--quick", "--solvers", PROFILE_SOLVERS, "--time-limit",
             PROFILE_TIME_LIMIT, "--out", "profile"]
    run([cbps] + args_)
    with open(os.path.join(work, "profile", "profile.json")) as f:
        s = json.load(f)
    results["profile"] = {
        "library_command": "scripts/make_problem_library.py CBPS library --quick",
        "command": "cbps " + " ".join(args_), "load_average": os.getloadavg()[0],
        "problems": [{"name": p["name"], "rows": p["rows"]} for p in s["problems"]],
        "solvers": s["solvers"], "profiles": s["profiles"], "wall_time_s": s["wall_time_s"],
        "measurements": [{k: m[k] for k in ("problem", "solver", "status", "iterations",
                                            "residual_relative")} for m in s["measurements"]]}
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    write_json(args.out, results)
    print(f"measure_tao_studies: wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
