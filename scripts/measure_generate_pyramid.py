#!/usr/bin/python3
"""Measures the exact path under MPI on contact problems generated per rank (`cbps lcp --generate
pyramid --rows N --solver direct`, docs/distributed.md) against the single-process exact path
on the same problem, and writes what docs/distributed.md's table and model show as JSON (format
cbps-generate-pyramid/1).

    /usr/bin/python3 scripts/measure_generate_pyramid.py CBPS OUT.json [--work DIR] [--quick]

For each N of ROWS (the pyramid of the smallest base with 12 base^2 >= N rows):

- "mpi R" for R = 1, 2 (and 4 at 300,000 rows, oversubscribing the 2 cores: its memory checks
  the model, its time says nothing): `mpirun -n R --oversubscribe cbps lcp --generate pyramid --rows N
  --solver direct --json`: the command's `wall_time_s` (the solve), `generated.wall_time_s`
  (building the rank's rows), the process (mpirun's start included), status, residual, scale,
  the `direct` counts and `rank_memory_mb`; at 2 ranks also PETSc's `-log_view` (through
  PETSC_OPTIONS): the job's MPI messages, their bytes and reductions, and the calls, messages
  and reductions of the events MatMult, MatMultTranspose, MatSolve, MatLUFactor and
  MatAssemblyBegin (SuperLU_dist's own messages inside MatLUFactor and MatSolve, and the
  interior point's MPI_Allreduce calls, `direct.reductions`, are not PETSc's and are not
  counted there);
- "serial": the same system on one process, `cbps run pyramid --param base=B --param
  push=original --steps 1 --solver direct --json` (at step 0 the boxes touch at depth 0, so
  the one system of push=original is the generated one, b included: tests/petsc/
  test_generate.py compares the generated rows with `cbps matrices pyramid --step 0`): its
  solve stage (CHOLMOD, the pivoting crossover), its assembly stage and its name (since
  6cc2f9b "without A": the direct path leaves A = J Minv J^T out; before, A was formed there),
  the process, its max_residual and the process's peak memory (wait4's ru_maxrss).

--quick (a check of the script, the test petsc-measure-generate-pyramid-quick): N = 768 only.
Exit 1 without writing OUT when CBPS changes during the run, and after writing it when a run is
not solved. As root, Open MPI needs OMPI_ALLOW_RUN_AS_ROOT=1 and
OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, set here.
"""
import argparse
import datetime
import json
import os
import platform
import re
import shlex
import subprocess
import sys
import time

import measure_direct_mpi as direct  # mpirun()
import measure_generate  # log_view()
import measure_peers as peers  # run(), begin(), git_commit(), write_results(), check_binary()

FORMAT = "cbps-generate-pyramid/1"
ROWS = (10_000, 100_000, 300_000, 1_000_000)
QUICK = (768,)
RANKS = (1, 2)
MEMORY_RANKS = {300_000: (4,)}  # more ranks than cores: their memory only (the model's check)
TIMEOUT_S = 1800
EVENTS = ("MatMult", "MatMultTranspose", "MatSolve", "MatLUFactor", "MatAssemblyBegin")


def log(text):
    print(f"measure_generate_pyramid: {text}", file=sys.stderr, flush=True)


def printed_json(cmd, code, out, err):
    """The JSON object the command printed; stops the script, saying why, when there is none."""
    try:
        return json.loads(out)
    except json.JSONDecodeError:
        sys.exit(f"measure_generate_pyramid: {shlex.join(cmd)} printed no JSON ({code}): "
                 f"{err[-500:]}")


def base_of(run):
    """The pyramid's base as the generated run describes it ("generated pyramid, base B (...")):
    cbps chooses it from --rows (lcp.cpp's pyramid_base_for), so the serial run takes it from
    there."""
    return int(re.search(r"base (\d+)", run["description"]).group(1))


def generated(cbps, work, rows, ranks):
    args = [cbps, "lcp", "--generate", "pyramid", "--rows", str(rows), "--solver", "direct",
            "--json"]
    cmd = [direct.mpirun(), "-n", str(ranks), "--oversubscribe"] + args
    view = os.path.join(work, f"log_view_{rows}_{ranks}.txt")
    if ranks > 1:
        os.environ["PETSC_OPTIONS"] = f"-log_view :{view}"
    try:
        code, out, err, seconds = peers.run(cmd, work, timeout=TIMEOUT_S)
    finally:
        os.environ.pop("PETSC_OPTIONS", None)
    j = printed_json(cmd, code, out, err)
    log(f"{rows} rows at {ranks} rank(s): {j['status']}, residual {j['residual']:.3g} N, "
        f"{j['wall_time_s']:.2f} s, {j['rank_memory_mb']} MB")
    return {"command": shlex.join(["mpirun", "-n", str(ranks), "cbps"] + args[1:]),
            "exit": code, "ranks": j["ranks"], "rows": j["rows"], "process_s": seconds,
            "solve_s": j["wall_time_s"], "build_s": j["generated"]["wall_time_s"],
            "description": j["generated"]["description"], "status": j["status"],
            "residual_N": j["residual"], "scale": j["scale"], "direct": j["direct"],
            "unit_free": (j.get("unit_free") or {}).get("relative"),
            "rank_memory_mb": j["rank_memory_mb"], "load": os.getloadavg()[0],
            "log_view": measure_generate.log_view(view, EVENTS) if ranks > 1 else None}


def serial(cbps, work, base):
    args = [cbps, "run", "pyramid", "--param", f"base={base}", "--param", "push=original",
            "--steps", "1", "--solver", "direct", "--json", "--quiet"]
    peers.check_binary()
    start = time.monotonic()
    # Reaped here by wait4, whose rusage is this child's own: its peak memory. --quiet keeps
    # stderr short, so reading stdout first cannot block on a full stderr pipe.
    proc = subprocess.Popen(args, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    out = proc.stdout.read()
    err = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    seconds = time.monotonic() - start
    peak_mb = usage.ru_maxrss / 1024.0
    j = printed_json(args, proc.returncode, out, err)
    log(f"{j['rows']} rows on one process: residual {j['max_residual']:.3g} N, solve "
        f"{j['stage_times_s']['solve']:.2f} s")
    return {"command": shlex.join(["cbps"] + args[1:]), "exit": proc.returncode,
            "rows": j["rows"], "process_s": seconds, "solve_s": j["stage_times_s"]["solve"],
            "assembly_s": j["stage_times_s"]["assembly"],
            "assembly_stage": next(n for n in j["stages"] if n.startswith("assembly")),
            "residual_N": j["max_residual"],
            "peak_memory_mb": peak_mb, "load": os.getloadavg()[0]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cbps")
    ap.add_argument("out")
    ap.add_argument("--work")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    start, work, cbps, root = peers.begin(args, "cbps_measure_generate_pyramid_")
    os.environ.pop("PETSC_OPTIONS", None)
    runs = []
    for rows in (QUICK if args.quick else ROWS):
        mpi = [generated(cbps, work, rows, r) for r in RANKS + MEMORY_RANKS.get(rows, ())]
        base = base_of(mpi[0])
        runs.append({"rows_requested": rows, "base": base, "mpi": mpi,
                     "serial": serial(cbps, work, base)})
    results = {"format": FORMAT,
               "command": shlex.join(["scripts/measure_generate_pyramid.py"] + sys.argv[1:]),
               "cbps_commit": peers.git_commit(root),
               "date": datetime.date.today().isoformat(), "machine": platform.node(),
               "nproc": os.cpu_count(), "quick": args.quick, "runs": runs}
    peers.write_results(args.out, results, start, log)
    unsolved = [m["command"] for run in runs for m in run["mpi"] if m["status"] != "solved"]
    unsolved += [run["serial"]["command"] for run in runs if run["serial"]["exit"] != 0]
    if unsolved:
        sys.exit("measure_generate_pyramid: not solved: " + "; ".join(unsolved))


if __name__ == "__main__":
    main()
