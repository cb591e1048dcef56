#!/usr/bin/python3
"""Measures `cbps lcp --solver tao:TYPE` at 1 and 2 MPI ranks against `--solver direct` on the
problems of the petsc tests (docs/distributed.md, "Measured"), and writes the results as JSON.

    /usr/bin/python3 scripts/measure_tao.py CBPS OUT.json [--work DIR] [--repeat N]

CBPS is a build with PETSc. The problems are written into DIR (default: a temporary folder) by
`cbps matrices` with the arguments of tests/petsc/test_tao.py. Each run is repeated N times
(default 3) and the smallest wall time kept (`wall_time_s` of `cbps lcp --json`: the solve
alone, without starting the program, MPI or reading the problem); iterations and residuals do
not change between repeats. Every command run is recorded in the JSON. As root, Open MPI needs
OMPI_ALLOW_RUN_AS_ROOT=1 and OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, set here.
"""
import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile

from cbps_files import read_number, write_json  # scripts/cbps_files.py
from cbps_problem import PETSC_PROBLEMS as PROBLEMS  # scripts/cbps_problem.py

TYPES = ("bqpip", "gpcg", "tron", "bncg", "bqnls", "blmvm", "bnls", "bntr")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cbps")
    ap.add_argument("out")
    ap.add_argument("--work")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    mpirun = shutil.which("mpirun")
    work = args.work or tempfile.mkdtemp(prefix="cbps_measure_tao_")
    os.makedirs(work, exist_ok=True)
    cbps = os.path.abspath(args.cbps)
    results = {"format": "cbps-tao-measure/1", "machine": platform.node(),
               "cpus": os.cpu_count(), "problems": {}, "runs": []}

    def run(cmd):
        r = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=work)
        if r.returncode not in (0, 1):
            sys.exit(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr}")
        return r

    for name, margs in PROBLEMS.items():
        run([cbps] + margs + ["--out", name])
        results["problems"][name] = {"command": "cbps " + " ".join(margs) + " --out " + name}
        for solver in ["direct"] + ["tao:" + t for t in TYPES]:
            for ranks in ((None,) if solver == "direct" else (1, 2)):
                lcp = ["lcp", name, "--solver", solver, "--json"]
                cmd = [cbps] + lcp if ranks is None else \
                    [mpirun, "-n", str(ranks), "--oversubscribe", cbps] + lcp
                best = None
                for _ in range(args.repeat):
                    j = json.loads(run(cmd).stdout)
                    if best is None or j["wall_time_s"] < best["wall_time_s"]:
                        best = j
                shown = ("cbps " if ranks is None else f"mpirun -n {ranks} cbps ") + " ".join(lcp)
                row = {"problem": name, "solver": solver, "ranks": ranks or 1,
                       "command": shown, "rows": best["rows"], "status": best["status"],
                       "iterations": best["iterations"], "wall_time_s": best["wall_time_s"],
                       "residual": best["residual"], "scale": best["scale"],
                       "unit_free": (best.get("unit_free") or {}).get("relative")}
                if "tao" in best:
                    row["reason"] = best["tao"]["reason"]
                results["runs"].append(row)
                print(f"{name:6} {solver:10} {row['ranks']} {row['status']:7} "
                      f"{row['iterations']:6} {row['wall_time_s']:.3g} s "
                      f"{read_number(row['residual']):.3g} {row.get('reason', '')}", flush=True)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    write_json(args.out, results)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
