#!/usr/bin/python3
"""CTest (label petsc): `cbps lcp PROBLEM --solver tao:TYPE`, alone and under mpirun, against the
exact path (docs/distributed.md).

    /usr/bin/python3 tests/petsc/test_tao.py CBPS MODE DIR

MODE is one of
  problems                   writes DIR/chain and DIR/stack with `cbps matrices` (300 and 240
                             rows) and the direct path's answers DIR/NAME.direct (the fixture)
  type:TYPE                  TAO's TYPE on both problems at 1 and 2 ranks: exit 0 and solved where
                             measured to solve (SOLVE_CHAIN), else exit 1 and --out not written;
                             the residuals, w = A lambda - b and J^T lambda against the direct
                             path's; --out written by rank 0
  singleton-equals-one-rank  `cbps lcp` without mpirun gives what `mpirun -n 1` gives, bit for bit
  bad-input                  bad input exits 2 on every rank of 2, one message, no hang
  without-petsc              a build without PETSc: --solver tao:bqpip exits 2 saying how to get it

Exit 0 when every check passes (each failed check is printed), 77 (skipped, with the reason)
when a mode needs mpirun and there is none. mpirun is $CBPS_MPIEXEC, else mpirun on PATH; as
root, Open MPI needs OMPI_ALLOW_RUN_AS_ROOT=1 and OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, set here.
"""
import json
import os
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
from cbps_problem import PETSC_PROBLEMS as PROBLEMS  # noqa: E402  (chain and stack)
from cbps_problem import natural_map_residual as natural_map  # noqa: E402
from cbps_problem import read_mtx  # noqa: E402
from cbps_problem import SOLVED, unit_free_residual  # noqa: E402  (the verdict, unit-free)

# Extra arguments per problem: on the stack no TAO type reaches the solved criterion within
# 10000 iterations (docs/distributed.md, measured), so 300 keep its runs short.
ITERATIONS = {"chain": [], "stack": ["--iterations", "300"]}
# The types measured to solve the chain (unit-free residual <= 1e-9 within 10000 iterations:
# all eight; bncg, bqnls and blmvm at the cap, bqnls and blmvm at unit-free 2.3e-10).
SOLVE_CHAIN = {"bqpip", "gpcg", "tron", "bncg", "bnls", "bntr", "bqnls", "blmvm"}
RANKS = (1, 2)
TIMEOUT_S = 60  # a hung rank fails the test instead of stalling the suite
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print(f"FAILED: {what}", file=sys.stderr)
    return ok


def mpirun():
    exe = os.environ.get("CBPS_MPIEXEC") or shutil.which("mpirun")
    return exe if exe and os.path.exists(exe) else None


def mpi_env():
    env = dict(os.environ)
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    return env


def run(args, ranks=None):
    """cbps ARGS, alone (ranks None) or under mpirun -n RANKS; a CompletedProcess."""
    cmd = list(args) if ranks is None else [mpirun(), "-n", str(ranks), "--oversubscribe"] + args
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT_S,
                              env=mpi_env())
    except subprocess.TimeoutExpired:
        check(False, f"hung: no answer within {TIMEOUT_S} s from {' '.join(cmd)}")
        return subprocess.CompletedProcess(cmd, -1, "", "")


def load(folder):
    p = {k: read_mtx(os.path.join(folder, k + ".mtx")) for k in ("A", "b", "cmin", "cmax", "J")}
    cfm_file = os.path.join(folder, "cfm.txt")
    check(not os.path.exists(cfm_file), f"{folder}: no cfm.txt expected")
    return p


_norms = {}


def norms(folder, p):
    """||A||_inf, the smallest eigenvalue of Minv, ||J||_2 and ||J Minv||_2 of a problem."""
    if folder not in _norms:
        J = p["J"].toarray()
        Minv = read_mtx(os.path.join(folder, "Minv.mtx")).toarray()
        _norms[folder] = (float(np.max(np.sum(np.abs(p["A"].toarray()), axis=1))),
                          float(np.linalg.eigvalsh(Minv)[0]), float(np.linalg.norm(J, 2)),
                          float(np.linalg.norm(J @ Minv, 2)))
    return _norms[folder]


def distance_bound(p, folder, lam, r, lam_star_1):
    """A bound on ||J^T (lam - lam*)||_2 for any solution lam* of the boxed problem, given lam's
    natural-map residual r (infinity norm) and ||lam*||_1.

    With y = clamp(lam - w, cmin, cmax) = lam - r_vec, the projection's variational inequality
    (z - y)^T (r_vec - w) <= 0 at z = lam*, and lam*'s optimality (y - lam*)^T w* >= 0, added,
    with w - w* = A (y - lam*) + A r_vec, give
        (y - lam*)^T A (y - lam*) <= (lam* - y)^T (A - I) r_vec
                                  <= (||lam*||_1 + ||y||_1) (||A||_inf + 1) r,
    and (y - lam*)^T A (y - lam*) = ||J^T (y - lam*)||^2 in the Minv norm >= sigma_min(Minv)
    ||J^T (y - lam*)||_2^2; then J^T lam = J^T y + J^T r_vec adds ||J||_2 sqrt(c) r."""
    A_inf, sigma_min, J_2, _ = norms(folder, p)
    y_1 = float(np.sum(np.abs(lam))) + lam.size * r
    inner = (lam_star_1 + y_1) * (A_inf + 1.0) * r / sigma_min
    return np.sqrt(inner) + J_2 * np.sqrt(lam.size) * r


def mode_problems(cbps, root):
    os.makedirs(root, exist_ok=True)
    for name, args in PROBLEMS.items():
        folder = os.path.join(root, name)
        r = run([cbps] + args + ["--out", folder])
        if not check(r.returncode == 0, f"cbps {' '.join(args)}: exit {r.returncode} {r.stderr}"):
            continue
        r = run([cbps, "lcp", folder, "--solver", "direct", "--json", "--out",
                 folder + ".direct"])
        check(r.returncode == 0, f"direct path on {name}: exit {r.returncode} {r.stderr}")
        if r.returncode == 0:
            j = json.loads(r.stdout)
            print(f"{name}: {j['rows']} rows, direct residual {j['residual']:.3g} "
                  f"(scale {j['scale']:.3g})")


def compare_with_direct(root, name, j, ranks, label):
    """j is `cbps lcp --json` of a TAO run on NAME: its residuals, w and J^T lambda."""
    folder = os.path.join(root, name)
    p = load(folder)
    A, b, J = p["A"], p["b"], p["J"]
    lam = np.array([float(x) for x in j["lambda"]])
    exact = read_mtx(os.path.join(folder + ".direct", "lambda.mtx"))
    scale = j["scale"]
    check(j["ranks"] == ranks, f"{label}: ranks {j['ranks']}, expected {ranks}")
    check(j["solver"] == "tao:" + j["tao"]["type"], f"{label}: solver {j['solver']}")
    # The verdict, formed here from the whole problem: the unit-free residual at most 1e-9.
    relative = unit_free_residual(A, b, p["cmin"], p["cmax"], lam)
    check((relative <= SOLVED) == (j["status"] == "solved"),
          f"{label}: status {j['status']} with unit-free residual {relative} formed here")
    reported = j["unit_free"]["relative"] if j.get("unit_free") else None
    check(reported is not None and abs(reported - relative) <= 1e-6 * relative + 1e-15,
          f"{label}: the ranks' unit-free residual {reported} vs {relative} formed here")
    # The distributed residual (PETSc's MatMult, VecPointwiseMax/Min, VecNorm) against numpy's
    # on the whole problem read here: the same formula, summed in another order, so they agree
    # to rounding, a few ulps of the largest term max(|lambda|, |A lambda|, |b|): 1e-13 of that
    # allows some hundred of them.
    terms = max(1.0, np.max(np.abs(lam)), np.max(np.abs(A @ lam)), np.max(np.abs(b)))
    mine = natural_map(A, b, p["cmin"], p["cmax"], lam)
    check(abs(j["residual"] - mine) <= 1e-13 * terms,
          f"{label}: distributed residual {j['residual']:.6g} vs numpy's natural map {mine:.6g}")
    # w and J^T lambda against the direct path's. They are the same at every solution lam*
    # (A = J Minv J^T with Minv positive definite: J^T (l1 - l2) = 0 between two solutions), and
    # each lambda is within distance_bound of a solution in J^T; ||lam*||_1 is taken as twice
    # the direct path's (the exact solution nearest it; for the chain the only one).
    r_exact = natural_map(A, b, p["cmin"], p["cmax"], exact)
    star_1 = 2.0 * float(np.sum(np.abs(exact)))
    bound_J = (distance_bound(p, folder, lam, mine, star_1) +
               distance_bound(p, folder, exact, r_exact, star_1))
    bound_w = norms(folder, p)[3] * bound_J  # w - w* = (J Minv) J^T (lambda - lam*)
    dw = float(np.max(np.abs((A @ lam - b) - (A @ exact - b))))
    dJ = float(np.max(np.abs(J.T @ lam - J.T @ exact)))
    print(f"{label}: {j['iterations']} iterations, residual {j['residual']:.3g}, "
          f"|w - w_direct| {dw:.3g} (bound {bound_w:.3g}), "
          f"|J^T lambda - J^T lambda_direct| {dJ:.3g} (bound {bound_J:.3g})")
    check(dw <= bound_w, f"{label}: |w - w_direct|inf = {dw:.3g} > {bound_w:.3g}")
    check(dJ <= bound_J, f"{label}: |J^T lambda - J^T lambda_direct|inf = {dJ:.3g} > {bound_J:.3g}")


def mode_type(cbps, root, tao_type):
    if not mpirun():
        print("petsc SKIPPED: no mpirun (Debian: openmpi-bin; scripts/setup.sh --with-petsc)")
        return 77
    for name in PROBLEMS:
        for ranks in RANKS:
            label = f"tao:{tao_type} on {name} at {ranks} rank(s)"
            out = os.path.join(root, f"{name}.{tao_type}.{ranks}")
            shutil.rmtree(out, ignore_errors=True)  # a result of an earlier run is not this one
            r = run([cbps, "lcp", os.path.join(root, name), "--solver", "tao:" + tao_type,
                     "--json", "--out", out] + ITERATIONS[name], ranks)
            if not check(r.returncode in (0, 1), f"{label}: exit {r.returncode}: {r.stderr}"):
                continue
            # One JSON object: only rank 0 prints.
            try:
                j = json.loads(r.stdout)
            except json.JSONDecodeError as e:
                check(False, f"{label}: stdout is not one JSON object ({e}): {r.stdout[:300]}")
                continue
            compare_with_direct(root, name, j, ranks, label)
            check(r.returncode == (0 if j["status"] == "solved" else 1),
                  f"{label}: exit {r.returncode} with status {j['status']}")
            if name == "chain" and tao_type in SOLVE_CHAIN:
                check(j["status"] == "solved", f"{label}: status {j['status']} ({j['message']})")
            if j["status"] != "solved":
                check(not os.path.exists(os.path.join(out, "result.json")),
                      f"{label}: --out written though not solved")
                continue
            # --out by rank 0: result.json is the printed object, lambda.mtx its lambda.
            written = json.load(open(os.path.join(out, "result.json")))
            check(written == j, f"{label}: result.json differs from --json")
            lam = read_mtx(os.path.join(out, "lambda.mtx"))
            check(np.array_equal(lam, np.array(j["lambda"], dtype=float)),
                  f"{label}: lambda.mtx differs from the printed lambda")


def mode_singleton(cbps, root):
    if not mpirun():
        print("petsc SKIPPED: no mpirun to compare with (Debian: openmpi-bin)")
        return 77
    for name in PROBLEMS:
        for tao_type in ("bqpip", "tron"):
            args = [cbps, "lcp", os.path.join(root, name), "--solver", "tao:" + tao_type,
                    "--json"] + ITERATIONS[name]
            alone, one = run(args), run(args, 1)
            label = f"tao:{tao_type} on {name}"
            if not check(alone.returncode in (0, 1) and alone.returncode == one.returncode,
                         f"{label}: exits {alone.returncode} alone, {one.returncode} under "
                         f"mpirun -n 1: {alone.stderr} {one.stderr}"):
                continue
            a, o = json.loads(alone.stdout), json.loads(one.stdout)
            for key in ("lambda", "iterations", "residual", "status", "ranks", "tao"):
                check(a[key] == o[key], f"{label}: {key} differs without mpirun: {a[key]} vs "
                                        f"{o[key]}" if key != "lambda" else f"{label}: lambda")
            print(f"{label}: alone and mpirun -n 1 agree ({a['status']}, {a['iterations']} "
                  f"iterations, residual {a['residual']:.3g})")


def rank_exits(cbps, args, ranks=2):
    """Each rank's exit code of cbps ARGS under mpirun (a shell around each rank prints it)."""
    wrapped = ["sh", "-c", '"$0" "$@"; echo "cbps-rank-exit $OMPI_COMM_WORLD_RANK $?"', cbps]
    r = run(wrapped + args, ranks)
    codes = {}
    for line in r.stdout.splitlines():
        if line.startswith("cbps-rank-exit "):
            _, rank, code = line.split()
            codes[int(rank)] = int(code)
    return codes, r


def mode_bad_input(cbps, root):
    if not mpirun():
        print("petsc SKIPPED: no mpirun (Debian: openmpi-bin; scripts/setup.sh --with-petsc)")
        return 77
    chain = os.path.join(root, "chain")
    foreign = os.path.join(root, "foreign-out")
    os.makedirs(foreign, exist_ok=True)
    # A leftover of an earlier run would hide a refused command's write below.
    shutil.rmtree(os.path.join(root, "one-process"), ignore_errors=True)
    with open(os.path.join(foreign, "mine.txt"), "w") as f:
        f.write("a user's file\n")
    nonsym = os.path.join(root, "nonsym.dat")
    with open(nonsym, "w") as f:
        f.write("2\n0\n2 2\n2 2\n2 1\n0 2\n-1 -1\n")  # an LCP with M's columns (2, 1), (0, 2)
    cases = [
        (["lcp", chain, "--solver", "tao:nope"], "unknown TAO type"),
        (["lcp", chain, "--solver", "tao"], "no TAO type"),
        (["lcp", os.path.join(root, "missing"), "--solver", "tao:bqpip"], "missing"),
        (["lcp", nonsym, "--solver", "tao:bqpip"], "symmetric"),
        # Only rank 0 opens --out: its refusal must still end rank 1.
        (["lcp", chain, "--solver", "tao:bqpip", "--out", foreign], "mine.txt"),
        # A command that runs in one process is refused under mpirun -n 2, said once, with
        # nothing written (before, each rank solved, printed and wrote --out at once).
        (["lcp", chain, "--solver", "pgs", "--out", os.path.join(root, "one-process")],
         "without mpirun"),
        (["run", "chain", "--steps", "2", "--out", os.path.join(root, "one-process")],
         "without mpirun"),
    ]
    for args, words in cases:
        label = " ".join(args[2:])
        codes, r = rank_exits(cbps, args)
        check(codes == {0: 2, 1: 2}, f"{label}: rank exit codes {codes}, expected 2 on both")
        check(words in r.stderr, f"{label}: stderr does not say '{words}': {r.stderr}")
        check(r.stderr.count("cbps: ") == 1, f"{label}: not one message: {r.stderr}")
        check(r.stdout.replace("cbps-rank-exit", "").strip().count("\n") <= 1,
              f"{label}: something on stdout: {r.stdout}")
        plain = run([cbps] + args, 2)
        check(plain.returncode == 2, f"{label}: mpirun exited {plain.returncode}, expected 2")
        print(f"{label}: exit 2 on both ranks; {r.stderr.strip()}")
    check(sorted(os.listdir(foreign)) == ["mine.txt"], "the refused --out folder changed")
    check(not os.path.exists(os.path.join(root, "one-process")),
          "a command refused under mpirun wrote its --out folder")


def mode_without_petsc(cbps, root):
    folder = os.path.join(root, "small")
    r = run([cbps, "matrices", "chain", "--param", "n=3", "--out", folder])
    check(r.returncode == 0, f"cbps matrices: {r.stderr}")
    r = run([cbps, "lcp", folder, "--solver", "tao:bqpip"])
    check(r.returncode == 2, f"exit {r.returncode}, expected 2")
    for words in ("built without PETSc", "petsc-dev", "setup.sh --with-petsc"):
        check(words in r.stderr, f"stderr does not say '{words}': {r.stderr}")
    print(r.stderr.strip())


def main():
    cbps, mode, root = sys.argv[1], sys.argv[2], sys.argv[3]
    if mode == "problems":
        code = mode_problems(cbps, root)
    elif mode.startswith("type:"):
        code = mode_type(cbps, root, mode[len("type:"):])
    elif mode == "singleton-equals-one-rank":
        code = mode_singleton(cbps, root)
    elif mode == "bad-input":
        code = mode_bad_input(cbps, root)
    elif mode == "without-petsc":
        code = mode_without_petsc(cbps, root)
    else:
        print(f"unknown mode {mode}", file=sys.stderr)
        return 2
    if code == 77:
        return 77
    print(f"{len(failures)} failed" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
