#!/usr/bin/python3
"""CTest (label petsc): the exact path under MPI, `mpirun -n R cbps lcp FOLDER --solver direct`
(docs/distributed.md, "The exact path under MPI"), against the serial exact path.

    /usr/bin/python3 tests/petsc/test_direct_mpi.py CBPS MODE DIR

MODE is one of
  solve      writes contact and chain folders with `cbps matrices` (two pyramids whose one
             island needs the crossover, the base-20 one moving rows on one rank alone, a 5-column stack of many islands, a chain of equality rows only,
             a stack with CFM), solves each by `cbps lcp --solver direct` without mpirun (the
             serial path) and under mpirun at 1 and 2 ranks: exit 0, solved, `ranks` R, the
             residual the command reports equal to the one formed here from the folder's A, its
             unit-free residual at most 1e-9 and the ranks' equal to it; the objective 1/2 l^T A l - b^T l the serial path's (to 1e-9 of
             |f|) and w = A l - b the serial path's (w is the same at every solution of a convex
             QP: to 1e-6 * scale); --out written by rank 0
  bad-input  a folder without J, a Siconos file, a Minv block that is not positive definite:
             exit 2 on every rank of 2, one message naming the file, no hang
  law        what every path that reads a folder must not solve as something else (issue 50):
             a folder on friction cones (`--param friction=cone`) is refused by direct under
             mpirun and by tao:TYPE alone and under mpirun (exit 2, naming the cones and what
             solves them) while the serial direct path solves it; a folder whose A.mtx is
             doubled (not J Minv J^T) or truncated is bad input (exit 2 naming A.mtx) serially,
             under mpirun and for TAO; a missing folder is "no such file or folder" under mpirun;
             --time-limit stops direct under mpirun (status "time limit", exit 1) and is refused
             for tao:TYPE (exit 2)

Exit 0 when every check passes (each failed check is printed), 77 (skipped, with the reason)
when there is no mpirun. As root, Open MPI needs OMPI_ALLOW_RUN_AS_ROOT=1 and
OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, set here.
"""
import json
import os
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cbps_problem import SOLVED, natural_map_residual, read_mtx, scale_of  # noqa: E402
from cbps_problem import unit_free_residual  # noqa: E402
import test_tao as t  # noqa: E402

PROBLEMS = {
    "pyramid": ["matrices", "pyramid", "--param", "base=10", "--step", "30"],
    # 4,800 rows whose crossover moves rows on one rank only: before each rank agreed on whether
    # w was stale, the ranks parted ways in a collective call and hung (issue 50).
    "pyramid20": ["matrices", "pyramid", "--param", "base=20", "--step", "60"],
    "columns": ["matrices", "stack", "--param", "n=10", "--param", "columns=5", "--step", "1"],
    "chain": ["matrices", "chain", "--param", "n=300", "--step", "10"],
    "stack-cfm": ["matrices", "stack", "--param", "n=6", "--step", "20", "--cfm", "1e-5"],
}
RANKS = (1, 2)
TIMEOUT_S = 120  # a hung rank fails the test instead of stalling the suite
check, mpirun, failures = t.check, t.mpirun, t.failures  # tests/petsc/test_tao.py's


def run(args, ranks=None):
    """cbps ARGS, alone (ranks None) or under mpirun -n RANKS; a CompletedProcess."""
    cmd = list(args) if ranks is None else [mpirun(), "-n", str(ranks), "--oversubscribe"] + args
    env = dict(os.environ)
    if ranks is None:  # the serial path: no launcher's variables
        for name in ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE"):
            env.pop(name, None)
    else:
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT_S, env=env)
    except subprocess.TimeoutExpired:
        check(False, f"hung: no answer within {TIMEOUT_S} s from {' '.join(cmd)}")
        return subprocess.CompletedProcess(cmd, -1, "", "")


def problem(folder):
    """A (with cfm.txt's eps on its diagonal, the problem `cbps lcp` solves), b, cmin, cmax."""
    A = read_mtx(os.path.join(folder, "A.mtx"))
    cfm_file = os.path.join(folder, "cfm.txt")
    if os.path.exists(cfm_file):
        with open(cfm_file) as f:
            A = A + float(f.read().split()[0]) * np.eye(A.shape[0])
    return (np.asarray(A.toarray() if hasattr(A, "toarray") else A),
            *(read_mtx(os.path.join(folder, k + ".mtx")) for k in ("b", "cmin", "cmax")))


def solve(cbps, folder, out, ranks=None):
    """cbps lcp FOLDER --solver direct --json [--out OUT]; (CompletedProcess, JSON or None)."""
    args = [cbps, "lcp", folder, "--solver", "direct", "--json"] + (["--out", out] if out else [])
    r = run(args, ranks)
    try:
        return r, json.loads(r.stdout)
    except json.JSONDecodeError:
        return r, None


def mode_solve(cbps, root):
    os.makedirs(root, exist_ok=True)
    for name, args in PROBLEMS.items():
        folder = os.path.join(root, name)
        shutil.rmtree(folder, ignore_errors=True)
        r = run([cbps] + args + ["--out", folder, "--quiet"])
        if not check(r.returncode == 0, f"cbps {' '.join(args)}: exit {r.returncode} {r.stderr}"):
            continue
        A, b, cmin, cmax = problem(folder)
        scale = scale_of(A, b)
        r, serial = solve(cbps, folder, None)
        if not check(r.returncode == 0 and serial and serial["status"] == "solved",
                     f"{name}: serial direct path: exit {r.returncode} {r.stderr}"):
            continue
        lam_s = np.asarray(serial["lambda"], dtype=float)
        w_s = A @ lam_s - b
        f_s = 0.5 * lam_s @ (A @ lam_s) - b @ lam_s
        for ranks in RANKS:
            what = f"{name} at {ranks} rank(s)"
            out = os.path.join(root, f"{name}-out-{ranks}")
            shutil.rmtree(out, ignore_errors=True)
            r, j = solve(cbps, folder, out, ranks)
            if not check(r.returncode == 0 and j is not None,
                         f"{what}: exit {r.returncode} {r.stderr[-2000:]}"):
                continue
            check(j["status"] == "solved", f"{what}: status {j['status']}: {j['message']}")
            check(j["ranks"] == ranks, f"{what}: ranks {j['ranks']}")
            check("SuperLU_dist" in j["message"], f"{what}: not the MPI path: {j['message']}")
            lam = np.asarray(j["lambda"], dtype=float)
            residual = natural_map_residual(A, b, cmin, cmax, lam)
            # Formed here from A, there from J Minv J^T: equal to their rounding, 64 u (the
            # largest row sum of |A| times ||lambda||_inf + ||b||_inf) (direct.hpp's floor).
            floor = 64 * 1.11e-16 * (np.max(np.sum(np.abs(A), axis=1)) * np.max(np.abs(lam))
                                     + np.max(np.abs(b)))
            check(abs(residual - j["residual"]) <= floor,
                  f"{what}: reported residual {j['residual']} against {residual} formed here")
            relative = unit_free_residual(A, b, cmin, cmax, lam)
            check(relative <= SOLVED, f"{what}: unit-free residual {relative} > 1e-9")
            reported = j["unit_free"]["relative"] if j.get("unit_free") else None
            check(reported is not None and abs(reported - relative) <= 1e-6 * relative + 1e-15,
                  f"{what}: the ranks' unit-free residual {reported} vs {relative} formed here")
            f = 0.5 * lam @ (A @ lam) - b @ lam
            check(abs(f - f_s) <= 1e-9 * max(1.0, abs(f_s)),
                  f"{what}: objective {f} against the serial path's {f_s}")
            dw = float(np.max(np.abs((A @ lam - b) - w_s), initial=0.0))
            check(dw <= 1e-6 * scale, f"{what}: |w - w_serial| = {dw}")
            written = os.path.join(out, "lambda.mtx")
            if check(os.path.exists(written), f"{what}: --out {out} has no lambda.mtx"):
                check(np.allclose(read_mtx(written), lam, rtol=0, atol=1e-12 * max(1.0, abs(lam).max())),
                      f"{what}: --out's lambda is not the JSON's")
            print(f"{what}: solved, residual {residual:.3g} N, {j['direct']}")


def mode_bad_input(cbps, root):
    os.makedirs(root, exist_ok=True)
    good = os.path.join(root, "good")
    shutil.rmtree(good, ignore_errors=True)
    r = run([cbps, "matrices", "stack", "--param", "n=3", "--step", "5", "--out", good, "--quiet"])
    if not check(r.returncode == 0, f"cbps matrices: {r.stderr}"):
        return
    no_j = os.path.join(root, "no-J")
    shutil.rmtree(no_j, ignore_errors=True)
    shutil.copytree(good, no_j)
    os.remove(os.path.join(no_j, "J.mtx"))
    bad_minv = os.path.join(root, "bad-Minv")
    shutil.rmtree(bad_minv, ignore_errors=True)
    shutil.copytree(good, bad_minv)
    path = os.path.join(bad_minv, "Minv.mtx")
    with open(path) as f:
        lines = f.read().splitlines()
    head = [k for k, line in enumerate(lines) if not line.startswith("%")][0]
    for k in range(head + 1, len(lines)):  # body 2's first diagonal entry made negative
        i, j, v = lines[k].split()
        if i == j == "7":
            lines[k] = f"{i} {j} {-abs(float(v))}"
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    here = os.path.dirname(os.path.abspath(__file__))
    siconos = os.path.join(here, "..", "data", "siconos", "lcp")
    siconos_file = next((os.path.join(siconos, n) for n in sorted(os.listdir(siconos))
                         if n.endswith(".dat")), None)
    cases = [(no_j, "J.mtx: missing"), (bad_minv, "body 2")]
    if siconos_file:
        cases.append((siconos_file, "not a cbps matrices folder"))
    for folder, said in cases:
        r = run([cbps, "lcp", folder, "--solver", "direct"], 2)
        check(r.returncode == 2, f"{folder}: exit {r.returncode}, not 2: {r.stderr[-1000:]}")
        check(said in r.stderr, f"{folder}: the message does not say '{said}': {r.stderr[-1000:]}")
        check(messages(r.stderr) == 1, f"{folder}: not one message: {r.stderr[-1000:]}")


def messages(stderr):
    """cbps's messages on stderr, less the ranks mpirun terminated once another rank failed
    ("cbps: stopped by SIGTERM": on a loaded machine a rank may still be running when mpirun
    ends the job; which rank reports first is then a race)."""
    return stderr.count("cbps:") - stderr.count("cbps: stopped by SIGTERM")


def expect_refused(args, ranks, said, what):
    """cbps ARGS (alone or under mpirun -n RANKS) exits 2, saying `said`, in one message."""
    r = run(args, ranks)
    where = "alone" if ranks is None else f"at {ranks} rank(s)"
    check(r.returncode == 2, f"{what} {where}: exit {r.returncode}, not 2: {r.stdout[-500:]} "
                             f"{r.stderr[-1000:]}")
    check(said in r.stderr, f"{what} {where}: the message does not say '{said}': "
                            f"{r.stderr[-1000:]}")
    check(messages(r.stderr) == 1, f"{what} {where}: not one message: {r.stderr[-1000:]}")


def edit_A(folder, edit):
    """A.mtx's lines after its header, replaced by edit(lines)."""
    path = os.path.join(folder, "A.mtx")
    with open(path) as f:
        lines = f.read().splitlines()
    head = [k for k, line in enumerate(lines) if not line.startswith("%")][0]
    with open(path, "w") as f:
        f.write("\n".join(lines[:head + 1] + edit(lines[head + 1:])) + "\n")


def mode_law(cbps, root):
    os.makedirs(root, exist_ok=True)
    cone = os.path.join(root, "slide-cone")
    good = os.path.join(root, "stack")
    for folder, args in ((cone, ["slide", "--param", "friction=cone", "--step", "5"]),
                         (good, ["stack", "--param", "n=3", "--step", "5"])):
        shutil.rmtree(folder, ignore_errors=True)
        r = run([cbps, "matrices"] + args + ["--out", folder, "--quiet"])
        if not check(r.returncode == 0, f"cbps matrices {' '.join(args)}: {r.stderr}"):
            return
    # The cones: the serial exact path solves them; the paths on the boxed problem refuse them.
    r, j = solve(cbps, cone, None)
    check(r.returncode == 0 and j and j["status"] == "solved" and j["cone"] is not None,
          f"slide on cones, serial direct: exit {r.returncode} {r.stderr[-500:]}")
    for ranks in RANKS:
        expect_refused([cbps, "lcp", cone, "--solver", "direct"], ranks, "friction cones",
                       "direct on a folder on cones")
    for ranks in (None,) + RANKS:
        expect_refused([cbps, "lcp", cone, "--solver", "tao:bqpip"], ranks, "friction cones",
                       "tao:bqpip on a folder on cones")
    # A that is not J Minv J^T: every path refuses it, naming A.mtx.
    doubled = os.path.join(root, "A-doubled")
    truncated = os.path.join(root, "A-truncated")
    for folder in (doubled, truncated):
        shutil.rmtree(folder, ignore_errors=True)
        shutil.copytree(good, folder)
    edit_A(doubled, lambda rows: [f"{i} {j} {2 * float(v)!r}" for i, j, v in
                                  (line.split() for line in rows)])
    edit_A(truncated, lambda rows: rows[:len(rows) // 2])
    for folder, said in ((doubled, "A is not J Minv J^T"), (truncated, "A.mtx")):
        name = os.path.basename(folder)
        expect_refused([cbps, "lcp", folder, "--solver", "direct"], None, said, name)
        for ranks in RANKS:
            expect_refused([cbps, "lcp", folder, "--solver", "direct"], ranks, said, name)
            expect_refused([cbps, "lcp", folder, "--solver", "tao:bqpip"], ranks, said,
                           name + " by tao:bqpip")
    missing = os.path.join(root, "no-such-folder")
    for ranks in RANKS:
        expect_refused([cbps, "lcp", missing, "--solver", "direct"], ranks,
                       "no such file or folder", "a missing folder")
    # --time-limit (issue 50, item 5): the exact path under MPI stops at it on every rank
    # together (status "time limit", exit 1), where it was ignored; TAO under lcp, whose ranks
    # cannot agree on a time, refuses it.
    for ranks in RANKS:
        r = run([cbps, "lcp", good, "--solver", "direct", "--time-limit", "1e-9", "--json"], ranks)
        try:
            j = json.loads(r.stdout)
        except json.JSONDecodeError:
            j = None
        check(r.returncode == 1 and j is not None and j["status"] == "time limit",
              f"direct --time-limit 1e-9 at {ranks} rank(s): exit {r.returncode}, status "
              f"{j and j['status']}: {r.stderr[-500:]}")
        expect_refused([cbps, "lcp", good, "--solver", "tao:bqpip", "--time-limit", "1"], ranks,
                       "--time-limit", "tao:bqpip with --time-limit")


def main():
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    cbps, mode, root = sys.argv[1:]
    if mpirun() is None:
        print("SKIPPED: no mpirun ($CBPS_MPIEXEC or PATH)")
        return 77
    {"solve": mode_solve, "bad-input": mode_bad_input, "law": mode_law}[mode](cbps, root)
    if failures:
        print(f"{len(failures)} check(s) failed", file=sys.stderr)
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
