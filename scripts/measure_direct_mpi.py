#!/usr/bin/python3
"""Measures the exact path under MPI (`mpirun -n R cbps lcp FOLDER --solver direct`,
docs/distributed.md) against the single-process exact path and TAO's types on the same contact
folders, and writes what docs/distributed.md's table shows as JSON (format cbps-direct-mpi/1).

    /usr/bin/python3 scripts/measure_direct_mpi.py CBPS OUT.json [--work DIR] [--quick]

The folders, written by `cbps matrices`: the base-20 pyramid after 60 steps (4,800 rows), the
base-40 pyramid after 30 steps (19,200 rows: one island the crossover must finish) and the
100-column stack after 60 steps (12,000 rows in 100 islands). On each:

- "serial": `cbps lcp F --solver direct --json` without mpirun (CHOLMOD, the pivoting
  crossover);
- "mpi R" for R = 1, 2: `mpirun -n R --oversubscribe cbps lcp F --solver direct --json`;
- "tao:TYPE at 2" for bqpip and tron: `mpirun -n 2 ... --solver tao:TYPE --iterations 20`
  (TAO reaches no solved criterion on contact problems in 10000 iterations, docs/distributed.md;
  20 keeps them short and shows where they are: bqpip's 300 iterations on the base-40 pyramid
  took more than 8 minutes here).

Recorded per run: the process's wall time (mpirun's start included), the command's own
`wall_time_s` (the solve), `status`, `residual` (N) and `scale`, the JSON's `direct` counts,
`rank_memory_mb`, and the load average after it. --quick (a check of the script): the base-8
pyramid only. Exit 1 without writing OUT when CBPS changes during the run. As root, Open MPI
needs OMPI_ALLOW_RUN_AS_ROOT=1 and OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, set here.
"""
import argparse
import datetime
import json
import os
import platform
import shlex
import shutil
import sys

import measure_peers as peers  # run(), BINARY, git_commit(), write_results()

FORMAT = "cbps-direct-mpi/1"
FOLDERS = [  # (name, cbps matrices arguments)
    ("pyramid 20", ["pyramid", "--param", "base=20", "--step", "60"]),
    ("pyramid 40", ["pyramid", "--param", "base=40", "--step", "30"]),
    ("stack 100x10", ["stack", "--param", "columns=100", "--step", "60"]),
]
QUICK = [("pyramid 8", ["pyramid", "--param", "base=8", "--step", "30"])]
RANKS = (1, 2)
TAO_TYPES = ("bqpip", "tron")
TAO_ITERATIONS = 20


def log(text):
    print(f"measure_direct_mpi: {text}", file=sys.stderr, flush=True)


def mpirun():
    exe = os.environ.get("CBPS_MPIEXEC") or shutil.which("mpirun")
    if not exe:
        sys.exit("measure_direct_mpi: no mpirun ($CBPS_MPIEXEC or PATH)")
    os.environ.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    return exe


def lcp(cbps, work, folder, solver, ranks, extra=()):
    """One `cbps lcp FOLDER --solver SOLVER --json`, under mpirun -n RANKS (None: without)."""
    args = [cbps, "lcp", folder, "--solver", solver, "--json"] + list(extra)
    cmd = args if ranks is None else [mpirun(), "-n", str(ranks), "--oversubscribe"] + args
    code, out, err, seconds = peers.run(cmd, work)
    try:
        j = json.loads(out)
    except json.JSONDecodeError:
        sys.exit(f"measure_direct_mpi: {shlex.join(cmd)} printed no JSON ({code}): {err[-500:]}")
    record = {"command": shlex.join(["cbps"] + args[1:]) if ranks is None else
              shlex.join(["mpirun", "-n", str(ranks), "cbps"] + args[1:]),
              "exit": code, "process_s": seconds, "solve_s": j["wall_time_s"],
              "status": j["status"], "residual_N": j["residual"], "scale": j["scale"],
              "unit_free": (j.get("unit_free") or {}).get("relative"),
              "message": j["message"], "load": os.getloadavg()[0]}
    for key in ("ranks", "direct", "rank_memory_mb", "tao"):
        if key in j:
            record[key] = j[key]
    log(f"{os.path.basename(folder)} {solver} ranks={ranks}: {j['status']}, residual "
        f"{j['residual']:.3g} N, {j['wall_time_s']:.2f} s")
    return record


def measure(cbps, work, label, args):
    folder = os.path.join(work, label.replace(" ", "_"))
    shutil.rmtree(folder, ignore_errors=True)
    code, _, err, _ = peers.run([cbps, "matrices"] + args + ["--out", folder, "--quiet"], work)
    if code != 0:
        sys.exit(f"measure_direct_mpi: cbps matrices {shlex.join(args)} failed: {err.strip()}")
    with open(os.path.join(folder, "b.mtx"), encoding="utf-8") as f:
        rows = int([line for line in f if not line.startswith("%")][0].split()[0])
    result = {"folder": label, "matrices": "cbps matrices " + shlex.join(args), "rows": rows,
              "serial": lcp(cbps, work, folder, "direct", None),
              "mpi": [lcp(cbps, work, folder, "direct", r) for r in RANKS],
              "tao": [lcp(cbps, work, folder, f"tao:{t}", 2,
                          ["--iterations", str(TAO_ITERATIONS)]) for t in TAO_TYPES]}
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cbps")
    ap.add_argument("out")
    ap.add_argument("--work")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    start, work, cbps, root = peers.begin(args, "cbps_measure_direct_mpi_")
    results = {"format": FORMAT,
               "command": shlex.join(["scripts/measure_direct_mpi.py"] + sys.argv[1:]),
               "cbps_commit": peers.git_commit(root),
               "date": datetime.date.today().isoformat(), "machine": platform.node(),
               "nproc": os.cpu_count(), "quick": args.quick, "tao_iterations": TAO_ITERATIONS,
               "folders": [measure(cbps, work, label, a)
                           for label, a in (QUICK if args.quick else FOLDERS)]}
    peers.write_results(args.out, results, start, log)


if __name__ == "__main__":
    main()
