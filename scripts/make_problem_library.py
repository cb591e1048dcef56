#!/usr/bin/python3
"""Writes the problem library that `cbps profile` runs every solver on (docs/convergence.md).

    scripts/make_problem_library.py CBPS OUT [--quick]

CBPS is the cbps binary, OUT a folder that must not exist yet (or hold a library this script
wrote: it is then replaced). OUT receives, all or nothing (written beside OUT and renamed):

  - one `cbps matrices` folder per scene problem (a built-in scene, its parameters and a step):
    chains of several lengths and mass ratios, stacks and pyramids (redundant contact rows: four
    per face, so A is singular), the v-corner of 12.2 and a nearly flat one (near-parallel rows),
    scenes with the paper's friction rows and with Coulomb friction (the folder's bounds are the
    fixed point's ±mu lambda_n, docs/outputs.md), Newton's cradle touching;
  - siconos/NAME.dat: each vendored Siconos problem (tests/data/siconos) whose A is symmetric,
    copied, with siconos/NAME.direct/: `cbps lcp --solver direct --tolerance 0 --out` of it;
    the others are listed under "excluded" with cbps's reason (the direct path, which gives the
    exact answer, solves the QP of 6.2 and needs a symmetric A);
  - library.json, the index (format cbps-problem-library/1): per problem its path (relative to
    OUT), source, rows, nonzeros of A, rank, condition, the exact answer (the direct path's
    lambda.mtx, from lambda = 0 to its rounding floor) and that answer's natural-map residual
    relative to the problem's scale, checked here against A, b, cmin, cmax as read by this
    script (so a misread file cannot pass).

Rank and condition are of the matrix the solvers work on, A + eps I with the folder's cfm.txt
(eps = 0 without one), from dense eigenvalues (numpy.linalg.eigvalsh): an eigenvalue at most
n u lambda_max (u the unit round-off) counts as zero, the rule of `estimate_condition`
(include/cbps/studies/conditioning.hpp); condition = lambda_max / lambda_min ("inf" when A is
singular), range_condition = lambda_max / the smallest nonzero eigenvalue (null for A = 0).

--quick writes only the problems marked quick (8 small ones, for tests); every entry of the full
library says whether it is one of them, and `cbps profile --quick` runs only those.
Needs numpy and scipy (Debian's python3-numpy, python3-scipy).
"""

import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy.io

from cbps_files import write_json  # scripts/cbps_files.py
from cbps_problem import natural_map_residual, scale_of  # scripts/cbps_problem.py

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SICONOS = os.path.join(ROOT, "tests", "data", "siconos")

# The scene problems: (scene, parameters, step, quick). Steps are chosen so that lambda = 0
# does not already solve the system (step 0 of a chain released from rest has b = 0).
SCENES = [
    ("chain", {"n": 10, "mass_ratio": 1}, 20, True),
    ("chain", {"n": 10, "mass_ratio": 100}, 20, True),
    ("chain", {"n": 10, "mass_ratio": 10000}, 20, False),
    ("chain", {"n": 50, "mass_ratio": 1}, 20, False),
    ("chain", {"n": 50, "mass_ratio": 100}, 20, False),
    ("chain", {"n": 50, "mass_ratio": 10000}, 20, False),
    ("chain", {"n": 200, "mass_ratio": 100}, 20, False),
    ("stack", {"n": 2}, 10, True),
    ("stack", {"n": 5}, 1, False),
    ("stack", {"n": 5}, 30, False),
    ("stack", {"n": 10}, 1, False),
    ("stack", {"n": 10}, 30, False),
    ("stack", {"n": 20}, 30, False),
    ("stack", {"n": 10, "mu": 0}, 30, False),
    ("stack", {"n": 4, "columns": 4}, 20, False),
    ("stack", {"n": 5, "friction": "coulomb"}, 30, False),
    ("stack", {"n": 3, "friction": "coulomb"}, 10, True),
    ("pyramid", {"base": 3}, 10, True),
    ("pyramid", {"base": 5}, 10, False),
    ("pyramid", {"base": 5}, 60, False),
    ("pyramid", {"base": 8}, 10, False),
    ("pyramid", {"base": 4, "friction": "coulomb"}, 10, False),
    ("v-corner", {}, 10, True),
    ("v-corner", {"angle_left_deg": 3, "angle_right_deg": 3}, 10, False),
    ("v-corner", {"mu": 0.3}, 10, False),
    ("slide", {"friction": "coulomb"}, 10, False),
    ("newtons-cradle", {"gap": 0}, 1, False),
    ("slide", {}, 10, False),
]

# Siconos problems in the quick subset (small, symmetric).
SICONOS_QUICK = {"relay_4x4", "lcp_deudeu"}

ZERO_EIGENVALUE_FACTOR = np.finfo(float).eps / 2  # u, the unit round-off


def problem_name(scene, params, step):
    parts = [scene] + [f"{k}{v}" for k, v in params.items()] + [f"step{step}"]
    return "-".join(str(p).replace(".", "p") for p in parts)


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {r.returncode}: {r.stderr.strip()}")
    return r


def read_siconos(path):
    """A, b, cmin, cmax of a dense Siconos file (storage 0): n, 0, rows and cols twice, M
    column by column, q, and for a relay lb, ub; w = M z + q is A = M, b = -q (tests/data/README.md).
    Returns None for a file that is not dense."""
    words = open(path).read().split()
    n, storage = int(words[0]), int(words[1])
    if storage != 0:
        return None
    pos = 6
    numbers = []
    for w in words[pos:]:
        try:
            numbers.append(float(w))
        except ValueError:
            break  # free text after the numbers
    M = np.array(numbers[: n * n]).reshape(n, n).T  # each line a column
    q = np.array(numbers[n * n : n * n + n])
    rest = numbers[n * n + n :]
    if len(rest) >= 2 * n:
        cmin, cmax = np.array(rest[:n]), np.array(rest[n : 2 * n])
    else:
        cmin, cmax = np.zeros(n), np.full(n, np.inf)
    return M, -q, cmin, cmax


def read_folder(path):
    A = scipy.io.mmread(os.path.join(path, "A.mtx")).toarray()
    vec = lambda name: np.asarray(scipy.io.mmread(os.path.join(path, name))).ravel()
    cfm_file = os.path.join(path, "cfm.txt")
    cfm = float(open(cfm_file).read()) if os.path.exists(cfm_file) else 0.0
    return A + cfm * np.eye(A.shape[0]), vec("b.mtx"), vec("cmin.mtx"), vec("cmax.mtx")


def describe(A, b, cmin, cmax, lam):
    """rows, nonzeros, rank, condition and the exact answer's relative residual."""
    n = A.shape[0]
    eig = np.linalg.eigvalsh((A + A.T) / 2)
    lam_max = float(eig[-1])
    zero = n * ZERO_EIGENVALUE_FACTOR * max(lam_max, 0.0)
    nonzero = eig[eig > zero]
    rank = int(nonzero.size)
    scale = scale_of(A, b)
    guess_residual = natural_map_residual(A, b, cmin, cmax, np.zeros(n))
    return {
        "rows": n,
        "nonzeros": int(np.count_nonzero(A)),
        "rank": rank,
        "definite": rank == n,
        "lambda_max": lam_max,
        "lambda_min": float(eig[0]),
        "condition": lam_max / float(eig[0]) if rank == n else math.inf,  # written "inf"
        "range_condition": lam_max / float(nonzero[0]) if rank > 0 else None,
        "scale": scale,
        "guess_residual_relative": guess_residual / scale,
        "exact_residual_relative": natural_map_residual(A, b, cmin, cmax, lam) / scale,
    }


STARTED = time.monotonic()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("cbps", help="the cbps binary")
    parser.add_argument("out", help="the library folder to write")
    parser.add_argument("--quick", action="store_true", help="only the 8 small problems")
    args = parser.parse_args()
    cbps = os.path.abspath(args.cbps)
    out = os.path.abspath(args.out.rstrip("/") or "/")
    if os.path.exists(out) and not os.path.exists(os.path.join(out, "library.json")):
        sys.exit(f"make_problem_library: {out} exists and is not a problem library; refusing")
    parent = os.path.dirname(out)
    os.makedirs(parent, exist_ok=True)
    work = tempfile.mkdtemp(prefix=".library-", dir=parent)
    try:
        index = build(cbps, work, args.quick)
        write_json(os.path.join(work, "library.json"), index, indent=2)
        if os.path.exists(out):
            shutil.rmtree(out)
        os.rename(work, out)
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    print(f"wrote {len(index['problems'])} problems to {out}")


def admit(entry, files, problems, excluded):
    """Adds the entry to the library, or to the excluded (its files removed) when lambda = 0
    already solves it to 1e-3 of its scale: every solver would reach the loosest tolerance at
    sweep 0, which measures nothing. An exact answer that does not solve the problem as read
    here is an error: 1e-9 of the scale is `cbps lcp`'s "solved" (docs/outputs.md)."""
    if not entry["exact_residual_relative"] <= 1e-9:
        raise RuntimeError(
            f"{entry['path']}: the direct path's lambda has relative residual "
            f"{entry['exact_residual_relative']:.3g} > 1e-9 as read here"
        )
    if entry["guess_residual_relative"] > 1e-3:
        problems.append(entry)
        return
    for f in files:
        shutil.rmtree(f) if os.path.isdir(f) else os.remove(f)
    reason = (
        f"lambda = 0 already solves it to {entry['guess_residual_relative']:.3g} of its scale "
        "(<= 1e-3): every solver would stop at sweep 0"
    )
    excluded.append({"source": entry["source"], "reason": reason})


def progress(what):
    """A line on stderr for every problem made, with the time since the start: the library takes
    seconds, and a silent command looks hung."""
    print(f"make_problem_library: {time.monotonic() - STARTED:5.1f} s: {what}", file=sys.stderr,
          flush=True)


def build(cbps, work, quick):
    problems, excluded = [], []
    for scene, params, step, is_quick in SCENES:
        if quick and not is_quick:
            continue
        name = problem_name(scene, params, step)
        progress(f"{name} (cbps matrices)")
        cmd = [cbps, "matrices", scene, "--step", str(step), "--out", os.path.join(work, name)]
        for k, v in params.items():
            cmd += ["--param", f"{k}={v}"]
        run(cmd)
        folder = os.path.join(work, name)
        lam = np.asarray(scipy.io.mmread(os.path.join(folder, "lambda.mtx"))).ravel()
        entry = {
            "name": name,
            "path": name,
            "kind": "matrices",
            "source": {"scene": scene, "params": params, "step": step},
            "quick": is_quick,
            "exact": f"{name}/lambda.mtx",
        }
        entry.update(describe(*read_folder(folder), lam))
        admit(entry, [folder], problems, excluded)
    os.makedirs(os.path.join(work, "siconos"))
    for group in ("lcp", "relay"):
        for file in sorted(os.listdir(os.path.join(SICONOS, group))):
            if not file.endswith(".dat"):
                continue
            stem = file[: -len(".dat")]
            is_quick = stem in SICONOS_QUICK
            if quick and not is_quick:
                continue
            source = os.path.join(SICONOS, group, file)
            relative = os.path.relpath(source, ROOT)
            progress(f"{group}/{file} (cbps lcp --solver direct)")
            target = os.path.join(work, "siconos", file)
            shutil.copyfile(source, target)
            direct = os.path.join(work, "siconos", stem + ".direct")
            r = subprocess.run(
                [cbps, "lcp", target, "--solver", "direct", "--tolerance", "0", "--out", direct],
                capture_output=True,
                text=True,
            )
            if r.returncode != 0:
                os.remove(target)
                reason = r.stderr.strip().replace(target, relative)
                excluded.append({"source": {"siconos": relative}, "reason": reason})
                continue
            data = read_siconos(target)
            lam = np.asarray(scipy.io.mmread(os.path.join(direct, "lambda.mtx"))).ravel()
            entry = {
                "name": stem,
                "path": f"siconos/{file}",
                "kind": "siconos",
                "source": {"siconos": relative},
                "quick": is_quick,
                "exact": f"siconos/{stem}.direct/lambda.mtx",
            }
            entry.update(describe(*data, lam))
            admit(entry, [target, direct], problems, excluded)
    version = run([cbps, "--version"]).stdout.strip()
    return {
        "format": "cbps-problem-library/1",
        "generator": "scripts/make_problem_library.py" + (" --quick" if quick else ""),
        "cbps": version,
        "problems": problems,
        "excluded": excluded,
    }


if __name__ == "__main__":
    main()
