#!/usr/bin/python3
"""CTest (label petsc): `cbps lcp --generate chain --rows N --solver tao:TYPE`, the problem built
per rank (docs/distributed.md), against the serial path's `cbps matrices chain --step 0`.

    /usr/bin/python3 tests/petsc/test_generate.py CBPS MODE DIR

MODE is one of
  system      a chain of 51 links at 1, 2 and 3 ranks: the generated A, b, cmin, cmax
              (--write-system, gathered onto rank 0) equal the serial folder's to 1e-12 of
              the largest entry (b: of ||b||inf; the bounds exactly), and TAO's lambda on the
              generated problem agrees with the direct path's on the serial folder (w and
              J^T lambda within the bound of test_tao.py, derived from the residuals);
              rank_memory_mb has one entry per rank; --out holds the printed object and lambda;
              and a chain of 9000 links at 1 and 2 ranks (more than one generation chunk of
              4096 joints on a rank): A, b, cmin, cmax as above
  bad-input   bad --rows, --generate, PROBLEM with --generate, a solver not tao:TYPE, too few
              links for the ranks, --write-system too large, an --out holding a user's file:
              exit 2 on both ranks of 2, one message, the folders as they were

Exit 0 when every check passes, 77 (skipped) without mpirun. Uses test_tao.py's helpers.
"""
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import test_tao as t  # noqa: E402

LINKS = 51  # odd: 2 ranks split it unevenly (26 + 25)
LONG_LINKS = 9000
RANKS = (1, 2, 3)


def compare_system(written, serial, label):
    """The generated A, b, cmin, cmax in `written` against the serial folder's (loaded)."""
    A = t.read_mtx(os.path.join(written, "A.mtx"))
    largest = abs(serial["A"]).max()
    dA = abs(A - serial["A"]).max() if A.shape == serial["A"].shape else float("inf")
    t.check(dA <= 1e-12 * largest,
            f"{label}: |A - A_serial|max = {dA:.3g} (largest entry {largest:.3g})")
    b = t.read_mtx(os.path.join(written, "b.mtx"))
    db = float(np.max(np.abs(b - serial["b"]))) if b.shape == serial["b"].shape else float("inf")
    t.check(db <= 1e-12 * float(np.max(np.abs(serial["b"]))),
            f"{label}: |b - b_serial|inf = {db:.3g}")
    for bound in ("cmin", "cmax"):
        mine = t.read_mtx(os.path.join(written, bound + ".mtx"))
        t.check(np.array_equal(mine, serial[bound]), f"{label}: {bound} differs")
    print(f"{label}: |A - A_serial| {dA:.3g}, |b - b_serial| {db:.3g}, bounds equal")


def mode_system(cbps, root):
    if not t.mpirun():
        print("petsc SKIPPED: no mpirun (Debian: openmpi-bin; scripts/setup.sh --with-petsc)")
        return 77
    os.makedirs(root, exist_ok=True)
    # More joints than one generation chunk (4096) on a rank: 1 rank builds 4096 + 4096 + 808,
    # 2 ranks 4096 + 404 each; the system alone (the solve's checks form dense J).
    name = f"chain{LONG_LINKS}"
    folder = os.path.join(root, name)
    r = t.run([cbps, "matrices", "chain", "--param", f"n={LONG_LINKS}", "--step", "0", "--out",
               folder])
    if t.check(r.returncode == 0, f"cbps matrices: exit {r.returncode} {r.stderr}"):
        serial = t.load(folder)
        for ranks in (1, 2):
            label = f"generated chain of {LONG_LINKS} at {ranks} rank(s)"
            written = os.path.join(root, f"{name}.generated.{ranks}")
            r = t.run([cbps, "lcp", "--generate", "chain", "--rows", f"{LONG_LINKS}", "--solver",
                       "tao:bqpip", "--write-system", written], ranks)
            if t.check(r.returncode == 0, f"{label}: exit {r.returncode}: {r.stderr}"):
                compare_system(written, serial, label)

    name = f"chain{LINKS}"
    folder = os.path.join(root, name)
    r = t.run([cbps, "matrices", "chain", "--param", f"n={LINKS}", "--step", "0", "--out",
               folder])
    if not t.check(r.returncode == 0, f"cbps matrices: exit {r.returncode} {r.stderr}"):
        return 1
    r = t.run([cbps, "lcp", folder, "--solver", "direct", "--out", folder + ".direct"])
    if not t.check(r.returncode == 0, f"direct path: exit {r.returncode} {r.stderr}"):
        return 1
    serial = t.load(folder)
    for ranks in RANKS:
        label = f"generated chain of {LINKS} at {ranks} rank(s)"
        written = os.path.join(root, f"{name}.generated.{ranks}")
        out = os.path.join(root, f"{name}.out.{ranks}")
        r = t.run([cbps, "lcp", "--generate", "chain", "--rows", f"{LINKS}", "--solver",
                   "tao:bqpip", "--json", "--write-system", written, "--out", out], ranks)
        if not t.check(r.returncode == 0, f"{label}: exit {r.returncode}: {r.stderr}"):
            continue
        j = json.loads(r.stdout)
        t.check(j["rows"] == LINKS, f"{label}: rows {j['rows']}")
        t.check(len(j["rank_memory_mb"]) == ranks and min(j["rank_memory_mb"]) > 0,
                f"{label}: rank_memory_mb {j['rank_memory_mb']}")
        compare_system(written, serial, label)
        # The solve: compare_with_direct checks the distributed residual against numpy's on
        # the serial folder, w and J^T lambda against the direct path's.
        t.compare_with_direct(root, name, j, ranks, label)
        t.check(j["status"] == "solved", f"{label}: status {j['status']} ({j['message']})")
        # --out by rank 0: result.json is the printed object, lambda.mtx its lambda.
        t.check(json.load(open(os.path.join(out, "result.json"))) == j,
                f"{label}: result.json differs from --json")
        lam = t.read_mtx(os.path.join(out, "lambda.mtx"))
        t.check(np.array_equal(lam, np.array(j["lambda"], dtype=float)),
                f"{label}: lambda.mtx differs from the printed lambda")
    return 0


def mode_bad_input(cbps, root):
    if not t.mpirun():
        print("petsc SKIPPED: no mpirun (Debian: openmpi-bin; scripts/setup.sh --with-petsc)")
        return 77
    os.makedirs(root, exist_ok=True)
    foreign = os.path.join(root, "foreign-out")
    os.makedirs(foreign, exist_ok=True)
    with open(os.path.join(foreign, "mine.txt"), "w") as f:
        f.write("a user's file\n")
    gen = ["lcp", "--generate", "chain", "--solver", "tao:bqpip"]
    cases = [
        (gen + ["--rows", "0"], "--rows 0"),
        (gen + ["--rows", "1.5"], "--rows 1.5"),
        (gen + ["--rows", "1e8"], "--rows 1e8"),
        (gen + ["--rows", "many"], "--rows many"),
        (gen, "--rows N is required"),
        (["lcp", "--generate", "stack", "--rows", "10", "--solver", "tao:bqpip"], "only"),
        (["lcp", "--generate", "chain", "--rows", "10", "--solver", "pgs"], "tao:TYPE"),
        (gen + ["--rows", "1"], "1 links on 2 ranks"),
        (["lcp", "some-folder", "--generate", "chain", "--rows", "10", "--solver", "tao:bqpip"],
         "not both"),
        (gen + ["--rows", "1e6", "--write-system", os.path.join(root, "big")], "at most"),
        # Only rank 0 opens --out: its refusal must still end rank 1.
        (gen + ["--rows", "10", "--out", foreign], "mine.txt"),
    ]
    for args, words in cases:
        label = " ".join(args[1:])
        codes, r = t.rank_exits(cbps, args)
        t.check(codes == {0: 2, 1: 2}, f"{label}: rank exit codes {codes}, expected 2 on both")
        t.check(words in r.stderr, f"{label}: stderr does not say '{words}': {r.stderr}")
        t.check(r.stderr.count("cbps: ") == 1, f"{label}: not one message: {r.stderr}")
        print(f"{label}: exit 2 on both ranks; {r.stderr.strip()}")
    t.check(not os.path.exists(os.path.join(root, "big")), "--write-system folder made")
    t.check(sorted(os.listdir(foreign)) == ["mine.txt"], "the refused --out folder changed")
    return 0


def main():
    cbps, mode, root = sys.argv[1], sys.argv[2], sys.argv[3]
    code = {"system": mode_system, "bad-input": mode_bad_input}[mode](cbps, root)
    if code == 77:
        return 77
    print(f"{len(t.failures)} failed" if t.failures else "all passed")
    return 1 if t.failures else 0


if __name__ == "__main__":
    sys.exit(main())
