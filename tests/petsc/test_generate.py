#!/usr/bin/python3
"""CTest (label petsc): `cbps lcp --generate chain --rows N --solver tao:TYPE` and `cbps lcp
--generate pyramid --rows N --solver direct`, the problem built per rank (docs/distributed.md),
against the serial path's `cbps matrices chain|pyramid --step 0`.

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
  pyramid     pyramids of base 8 (768 rows) at 1, 2 and 3 ranks and of base 46 (25,392 rows; 1,081
              boxes: two generation chunks of 1,024 boxes on 1 rank, one on each of 2) at 1
              and 2 ranks: the generated J, Minv, b, cmin, cmax (--write-system) and the A
              formed from them equal the serial folder's (the same rows in the same order;
              entries to 1e-12 of the largest, the bounds exactly); the exact path under MPI
              solved, `ranks` R, its residual the one numpy forms from the serial folder's A
              (to the rounding floor 64 u (max row sum |A| |lambda|inf + |b|inf)), its objective
              the serial direct path's (to 1e-9 of |f|) and w = A lambda - b the serial path's
              (the same at every solution: to 1e-6 * scale)
  bad-input   bad --rows, --generate, PROBLEM with --generate, a solver not tao:TYPE, too few
              links for the ranks, --write-system too large, an --out holding a user's file:
              exit 2 on both ranks of 2, one message, the folders as they were; a pyramid with a
              solver other than direct, a chain with --solver direct, --write-system on a pyramid of
              more rows than it gathers (--rows 99999 makes 101,568), a pyramid too small for
              rank 0 to hold its bottom row

Exit 0 when every check passes, 77 (skipped) without mpirun. Uses test_tao.py's helpers.
"""
import json
import os
import shutil
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


def compare_factors(written, serial, label):
    """The generated J and Minv in `written` against the serial folder's, as compare_system."""
    for name in ("J", "Minv"):
        mine = t.read_mtx(os.path.join(written, name + ".mtx"))
        theirs = serial[name] if name in serial else t.read_mtx(
            os.path.join(serial["folder"], name + ".mtx"))
        largest = abs(theirs).max()
        d = abs(mine - theirs).max() if mine.shape == theirs.shape else float("inf")
        t.check(d <= 1e-12 * largest, f"{label}: |{name} - {name}_serial|max = {d:.3g}")


def mode_pyramid(cbps, root):
    if not t.mpirun():
        print("petsc SKIPPED: no mpirun (Debian: openmpi-bin; scripts/setup.sh --with-petsc)")
        return 77
    os.makedirs(root, exist_ok=True)
    for base, ranks_list in ((8, (1, 2, 3)), (46, (1, 2))):
        rows = 12 * base * base
        name = f"pyramid{base}"
        folder = os.path.join(root, name)
        r = t.run([cbps, "matrices", "pyramid", "--param", f"base={base}", "--step", "0",
                   "--out", folder, "--quiet"])
        if not t.check(r.returncode == 0, f"cbps matrices: exit {r.returncode} {r.stderr}"):
            continue
        serial = t.load(folder)
        serial["folder"] = folder
        A, b, cmin, cmax = serial["A"], serial["b"], serial["cmin"], serial["cmax"]
        r = t.run([cbps, "lcp", folder, "--solver", "direct", "--json"])
        if not t.check(r.returncode == 0, f"{name}: serial direct path: {r.stderr}"):
            continue
        lam_s = np.asarray(json.loads(r.stdout)["lambda"], dtype=float)
        w_s = A @ lam_s - b
        f_s = 0.5 * lam_s @ (A @ lam_s) - b @ lam_s
        for ranks in ranks_list:
            label = f"generated pyramid of base {base} at {ranks} rank(s)"
            written = os.path.join(root, f"{name}.generated.{ranks}")
            r = t.run([cbps, "lcp", "--generate", "pyramid", "--rows", str(rows), "--solver",
                       "direct", "--json", "--write-system", written], ranks)
            if not t.check(r.returncode == 0, f"{label}: exit {r.returncode}: {r.stderr}"):
                continue
            j = json.loads(r.stdout)
            compare_system(written, serial, label)
            compare_factors(written, serial, label)
            t.check(j["rows"] == rows and j["ranks"] == ranks,
                    f"{label}: rows {j['rows']}, ranks {j['ranks']}")
            t.check(j["status"] == "solved", f"{label}: status {j['status']} ({j['message']})")
            t.check(len(j["rank_memory_mb"]) == ranks, f"{label}: {j['rank_memory_mb']}")
            lam = np.asarray(j["lambda"], dtype=float)
            mine = t.natural_map(A, b, cmin, cmax, lam)
            floor = 64 * 1.11e-16 * (np.max(abs(A).sum(axis=1)) * np.max(np.abs(lam)) +
                                     np.max(np.abs(b)))
            t.check(abs(mine - j["residual"]) <= floor,
                    f"{label}: residual {j['residual']} against {mine} formed from the folder")
            relative = t.unit_free_residual(A, b, cmin, cmax, lam)
            t.check(relative <= t.SOLVED, f"{label}: unit-free residual {relative} > 1e-9")
            f = 0.5 * lam @ (A @ lam) - b @ lam
            t.check(abs(f - f_s) <= 1e-9 * max(1.0, abs(f_s)),
                    f"{label}: objective {f} against the serial path's {f_s}")
            dw = float(np.max(np.abs((A @ lam - b) - w_s)))
            t.check(dw <= 1e-6 * j["scale"], f"{label}: |w - w_serial| = {dw}")
            print(f"{label}: residual {j['residual']:.3g} N, |w - w_serial| {dw:.3g}, "
                  f"{j['direct']}")
    return 0


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
    shutil.rmtree(os.path.join(root, "big"), ignore_errors=True)  # a folder no case may make
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
        (["lcp", "--generate", "stack", "--rows", "10", "--solver", "tao:bqpip"], "unknown"),
        (["lcp", "--generate", "pyramid", "--rows", "1000", "--solver", "tao:bqpip"],
         "--solver direct"),
        (["lcp", "--generate", "chain", "--rows", "10", "--solver", "direct"], "tao:TYPE"),
        (["lcp", "--generate", "pyramid", "--rows", "99999", "--solver", "direct",
          "--write-system", os.path.join(root, "big")], "101568 rows"),
        (["lcp", "--generate", "chain", "--rows", "10", "--solver", "pgs"], "tao:TYPE"),
        (gen + ["--rows", "1"], "1 links on 2 ranks"),
        (["lcp", "some-folder", "--generate", "chain", "--rows", "10", "--solver", "tao:bqpip"],
         "not both"),
        (gen + ["--rows", "1e6", "--write-system", os.path.join(root, "big")], "at most"),
        # Only rank 0 opens --out: its refusal must still end rank 1.
        (gen + ["--rows", "10", "--out", foreign], "mine.txt"),
    ]
    # A base-2 pyramid (3 boxes) on 3 ranks: rank 0 holds 1 box of the bottom row's 2.
    cases.append((["lcp", "--generate", "pyramid", "--rows", "48", "--solver", "direct"],
                  "bottom row", 3))
    for args, words, *ranks in cases:
        label = " ".join(args[1:])
        codes, r = t.rank_exits(cbps, args, *ranks)
        expected = {rank: 2 for rank in range(ranks[0] if ranks else 2)}
        t.check(codes == expected, f"{label}: rank exit codes {codes}, expected 2 on every one")
        t.check(words in r.stderr, f"{label}: stderr does not say '{words}': {r.stderr}")
        t.check(r.stderr.count("cbps: ") == 1, f"{label}: not one message: {r.stderr}")
        print(f"{label}: exit 2 on both ranks; {r.stderr.strip()}")
    t.check(not os.path.exists(os.path.join(root, "big")), "--write-system folder made")
    t.check(sorted(os.listdir(foreign)) == ["mine.txt"], "the refused --out folder changed")
    return 0


def main():
    cbps, mode, root = sys.argv[1], sys.argv[2], sys.argv[3]
    code = {"system": mode_system, "pyramid": mode_pyramid,
            "bad-input": mode_bad_input}[mode](cbps, root)
    if code == 77:
        return 77
    print(f"{len(t.failures)} failed" if t.failures else "all passed")
    return 1 if t.failures else 0


if __name__ == "__main__":
    sys.exit(main())
