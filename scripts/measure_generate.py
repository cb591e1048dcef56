#!/usr/bin/python3
"""Measures `cbps lcp --generate chain --rows N --solver tao:TYPE` at 1, 2 and 4 MPI ranks: time,
each rank's peak memory, TAO's iterations and PETSc's count of MPI messages and reductions, and
checks the largest generated problem against the exact path on the same problem read from a
`cbps matrices` folder (which TAO also reads by rows at 1 and 2 ranks) (docs/distributed.md, "Generated problems"). Writes the results as JSON.

    /usr/bin/python3 scripts/measure_generate.py CBPS OUT.json [--work DIR] [--quick]

CBPS is a build with PETSc. Every run is made once, with PETSc's `-log_view :FILE` (its
summary of events, written to a file, so stdout stays the JSON object): the counts of MPI
messages and reductions are read from it, for the whole job and for the `TaoSolve` and `MatMult`
events. Every command run is recorded in the JSON. --quick (a check of the script itself) runs
the small sizes only. Exit 1 when a run or the direct path is not `solved`, 77 without mpirun
(mpirun is $CBPS_MPIEXEC, else mpirun on PATH). As root, Open MPI needs OMPI_ALLOW_RUN_AS_ROOT=1 and
OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, set here.
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

from cbps_files import write_json  # scripts/cbps_files.py, beside this script
from cbps_problem import read_mtx  # scripts/cbps_problem.py, beside this script

# (rows, ranks, TAO type). 10 rows measure an empty process; 4 ranks oversubscribe the 2 cores
# here, so their times are not scaling, only their memory is.
RUNS = [(10, 1, "bqpip"), (10, 2, "bqpip"),
        (100000, 1, "bqpip"), (100000, 2, "bqpip"),
        (1000000, 1, "bqpip"), (1000000, 2, "bqpip"), (1000000, 4, "bqpip"),
        (1000000, 2, "tron"), (1000000, 2, "gpcg"),
        (3000000, 1, "bqpip"), (3000000, 2, "bqpip")]
QUICK = [(10, 1, "bqpip"), (10, 2, "bqpip"), (1000, 2, "bqpip")]
# The size both paths do here: generated at 2 ranks against `cbps matrices` + `--solver direct`.
EXACT_ROWS = 1000000
EXACT_ROWS_QUICK = 1000


def log_view(path, events=("TaoSolve", "KSPSolve", "MatMult")):
    """PETSc's -log_view summary: the job's message count, bytes and reductions (totals over the
    ranks), and for `events` their calls, messages, average message length and reductions (the
    columns of PETSc 3.18's event table)."""
    out = {"events": {}}
    with open(path) as f:
        for line in f:
            parts = line.split()
            if line.startswith("MPI Msg Count:"):
                out["messages"] = float(parts[-1]) if len(parts) >= 7 else 0.0
            elif line.startswith("MPI Msg Len (bytes):"):
                out["message_bytes"] = float(parts[-1]) if len(parts) >= 8 else 0.0
            elif line.startswith("MPI Reductions:"):
                out["reductions"] = float(parts[2])
            elif parts and parts[0] in events and len(parts) > 10 \
                    and parts[0] not in out["events"]:
                out["events"][parts[0]] = {"calls": int(parts[1]), "messages": float(parts[7]),
                                           "average_bytes": float(parts[8]),
                                           "reductions": float(parts[9])}
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cbps")
    ap.add_argument("out")
    ap.add_argument("--work")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    env.pop("PETSC_OPTIONS", None)
    mpirun = os.environ.get("CBPS_MPIEXEC") or shutil.which("mpirun")
    if mpirun is None:
        print("measure_generate SKIPPED: no mpirun (Debian: openmpi-bin; scripts/setup.sh "
              "--with-petsc)")
        sys.exit(77)
    work = args.work or tempfile.mkdtemp(prefix="cbps_measure_generate_")
    os.makedirs(work, exist_ok=True)
    cbps = os.path.abspath(args.cbps)
    results = {"format": "cbps-generate-measure/1", "machine": platform.node(),
               "cpus": os.cpu_count(), "quick": args.quick, "runs": []}

    def run(cmd, log=None, ok=(0,)):
        run_env = dict(env, PETSC_OPTIONS=f"-log_view :{log}") if log else env
        start = time.monotonic()
        r = subprocess.run(cmd, capture_output=True, text=True, env=run_env, cwd=work)
        elapsed = time.monotonic() - start
        if r.returncode not in ok:
            sys.exit(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr}")
        return r, elapsed

    def generated(rows, ranks, tao, extra=()):
        log = os.path.join(work, f"log-{rows}-{ranks}-{tao}.txt")
        lcp = ["lcp", "--generate", "chain", "--rows", str(rows), "--solver", "tao:" + tao,
               "--json", *extra]
        cmd = [mpirun, "-n", str(ranks), "--oversubscribe", cbps] + lcp
        print(f"measure_generate: {rows} rows, {ranks} ranks, {tao} ...", file=sys.stderr,
              flush=True)
        r, elapsed = run(cmd, log, ok=(0, 1))
        j = json.loads(r.stdout)
        return {"rows": rows, "ranks": ranks, "type": tao, "status": j["status"],
                "iterations": j["iterations"], "residual": j["residual"], "scale": j["scale"],
                "unit_free": (j.get("unit_free") or {}).get("relative"),
                "generate_s": j["generated"]["wall_time_s"], "solve_s": j["wall_time_s"],
                "job_s": elapsed, "rank_memory_mb": j["rank_memory_mb"],
                "reason": j["tao"]["reason"], "load_average": os.getloadavg()[0],
                "log_view": log_view(log),
                "command": "mpirun -n %d --oversubscribe cbps %s" % (ranks, " ".join(lcp))}

    for rows, ranks, tao in (QUICK if args.quick else RUNS):
        results["runs"].append(generated(rows, ranks, tao))

    # The exact path on the same problem, read whole by one process: `cbps matrices` writes the
    # serial chain's step 0, `cbps lcp --solver direct` solves it. λ of both against each other.
    n = EXACT_ROWS_QUICK if args.quick else EXACT_ROWS
    folder = os.path.join(work, "serial")
    if os.path.exists(folder):
        shutil.rmtree(folder)
    matrices = ["matrices", "chain", "--param", f"n={n}", "--step", "0", "--out", "serial"]
    run([cbps] + matrices)
    direct = ["lcp", "serial", "--solver", "direct", "--json", "--out", "direct"]
    shutil.rmtree(os.path.join(work, "direct"), ignore_errors=True)
    r, _ = run([cbps] + direct)
    d = json.loads(r.stdout)
    # The same folder read by rows under TAO (docs/distributed.md, "Reading a folder by rows").
    results["read"] = []
    for ranks in (1, 2):
        lcp = ["lcp", "serial", "--solver", "tao:bqpip", "--json"]
        r, elapsed = run([mpirun, "-n", str(ranks), "--oversubscribe", cbps] + lcp)
        j = json.loads(r.stdout)
        results["read"].append({
            "rows": n, "ranks": ranks, "status": j["status"], "residual": j["residual"],
            "unit_free": (j.get("unit_free") or {}).get("relative"),
            "read_s": j["read_wall_time_s"], "solve_s": j["wall_time_s"], "job_s": elapsed,
            "rank_memory_mb": j["rank_memory_mb"],
            "command": "mpirun -n %d --oversubscribe cbps %s" % (ranks, " ".join(lcp))})
    shutil.rmtree(os.path.join(work, "tao"), ignore_errors=True)
    g = generated(n, 2, "bqpip", ("--out", "tao"))
    lam_direct = read_mtx(os.path.join(work, "direct", "lambda.mtx"))
    lam_tao = read_mtx(os.path.join(work, "tao", "lambda.mtx"))
    if len(lam_direct) != n or len(lam_tao) != n:
        sys.exit(f"measure_generate: lambda of {len(lam_direct)} and {len(lam_tao)} rows, not {n}")
    difference = float(max(abs(lam_direct - lam_tao)))
    results["exact"] = {
        "rows": n,
        "direct": {"status": d["status"], "residual": d["residual"], "scale": d["scale"],
                   "unit_free": (d.get("unit_free") or {}).get("relative"),
                   "solve_s": d["wall_time_s"],
                   "command": "cbps " + " ".join(matrices) + "; cbps " + " ".join(direct)},
        "generated": g,
        "lambda_max_difference": difference,
        "lambda_largest": float(max(abs(lam_direct)))}
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    write_json(args.out, results)
    print(f"measure_generate: wrote {args.out}", file=sys.stderr)
    # The check the docs state: both paths solved the same problem.
    failed = [f"{x['rows']} rows at {x['ranks']} ranks ({x['type']}): {x['status']}"
              for x in results["runs"] + [g] if x["status"] != "solved"]
    failed += [f"{x['rows']} rows read by rows at {x['ranks']} ranks: {x['status']}"
               for x in results["read"] if x["status"] != "solved"]
    if d["status"] != "solved":
        failed.append(f"direct on the serial folder of {n} rows: {d['status']}")
    if failed:
        sys.exit("measure_generate: not solved: " + "; ".join(failed))


if __name__ == "__main__":
    main()
