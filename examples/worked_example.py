#!/usr/bin/python3
"""A worked example of the Python module cbps (docs/python.md), in three parts:

1. the v-corner (appendix 12.2, Figure 11): J, Minv, A = J Minv J^T and b = upsilon/dt -
   J (v1/dt + Minv fext) (6.2.9) written out by hand for a sphere resting in a V of two planes,
   against the library's, and lambda against the appendix's closed form;
2. projected Gauss-Seidel (7.1.1) on a chain, with equal links and with a heavy last link: the
   natural-map residual after every sweep, for PGS, PSOR and symmetric Gauss-Seidel, plotted
   with matplotlib (Agg backend) to OUT/chain-pgs.png;
3. a stack of boxes: its A is singular (four contact points per face, three degrees of freedom
   of the face), shown by its eigenvalues, with the count of zero eigenvalues predicted by hand.

Run from the repository after building (`cmake --workflow --preset test` runs it as the CTest
test python-worked-example):

    PYTHONPATH=build/release/python /usr/bin/python3 examples/worked_example.py --out out/example

Every number printed is also checked; a check that fails ends the script with exit status 1.
"""
import argparse
import os
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cbps  # noqa: E402

failures = []


def check(what, got, expected, tolerance):
    """Prints a line comparing a library value with the one derived by hand."""
    error = float(np.max(np.abs(np.asarray(got, dtype=float) - np.asarray(expected, dtype=float))))
    ok = error <= tolerance
    print(f"  {'ok  ' if ok else 'FAIL'} {what}: max |library - by hand| = {error:.2e} "
          f"(allowed {tolerance:.0e})")
    if not ok:
        failures.append(what)


def v_corner():
    print("1. v-corner (12.2): a sphere of mass m, radius r in a V of planes tilted phi_l, phi_r")
    m, r, g = 1.0, 0.1, 9.81
    phi_l, phi_r = np.radians(45.0), np.radians(30.0)
    scene = cbps.scene("v-corner", mass=m, radius=r, angle_left_deg=45, angle_right_deg=30)
    sim = cbps.Simulation(scene)
    sim.step()  # step 0: the sphere starts at rest touching both planes
    s = sim.system()
    print(f"  rows {s.row_labels}, columns {s.column_labels}")

    # The contact row (5.3) between a static plane (no columns) and the sphere: j_c = [n^T,
    # (r_b x n)^T] with r_b = -r n from the centre to the contact point, so r_b x n = 0.
    normal = {"left": np.array([np.sin(phi_l), np.cos(phi_l), 0.0]),
              "right": np.array([-np.sin(phi_r), np.cos(phi_r), 0.0])}
    planes = ["left" if "left" in label else "right" for label in s.row_labels]
    J = np.array([np.concatenate([normal[p], np.zeros(3)]) for p in planes])
    # Minv = blockdiag(E3 / m, I^-1) (6.1.2), a solid sphere's I = 2/5 m r^2 E3.
    Minv = np.diag([1 / m] * 3 + [1 / (0.4 * m * r**2)] * 3)
    # A = J Minv J^T = (1/m) [[1, n_l.n_r], [n_l.n_r, 1]], n_l.n_r = cos(phi_l + phi_r).
    A = J @ Minv @ J.T
    check("J", s.J.toarray(), J, 1e-15)
    check("Minv", s.Minv.toarray(), Minv, 1e-12)
    check("A = J Minv J^T", s.A.toarray(), A, 1e-15)
    check("A_12 = cos(phi_l + phi_r) / m", s.A.toarray()[0, 1], np.cos(phi_l + phi_r) / m, 1e-15)
    # b (6.2.9) at rest (v1 = 0) touching (depth 0: no push, upsilon = 0), fext = m g:
    # b = 0/dt - J (0/dt + Minv fext) = -n . g = g cos(phi) per row.
    v1 = np.zeros(6)
    fext = np.array([0.0, -m * g, 0.0, 0.0, 0.0, 0.0])
    upsilon = np.zeros(2)
    b = upsilon / s.dt - J @ (v1 / s.dt + Minv @ fext)
    check("v1 = 0, fext = m g", np.concatenate([s.v1, s.fext]), np.concatenate([v1, fext]), 1e-15)
    check("upsilon = 0 (touching, no push)", s.upsilon, upsilon, 1e-12)
    check("b = g cos(phi)", s.b, [g * np.cos(phi_l if p == "left" else phi_r) for p in planes],
          1e-10)
    check("b by 6.2.9", s.b, b, 1e-10)
    # lambda: both contacts press (w = 0 on both rows), so A lambda = b, and at rest the
    # forces balance the weight: lambda_l = m g sin(phi_r) / sin(phi_l + phi_r), ...
    lam = np.linalg.solve(A, b)
    closed = {"left": m * g * np.sin(phi_r) / np.sin(phi_l + phi_r),
              "right": m * g * np.sin(phi_l) / np.sin(phi_l + phi_r)}
    check("lambda = A^-1 b", s.lam, lam, 1e-8)
    check("lambda, appendix closed form", s.lam, [closed[p] for p in planes], 1e-8)
    print(f"  lambda = {s.lam} N (weight m g = {m * g} N)")


def chain_convergence(out):
    print("2. PGS (7.1.1) on a chain of 20 links at step 100: equal links, and the last link 100")
    print("   times heavier (the mass ratio slows Gauss-Seidel down)")
    plt.figure(figsize=(6.4, 4.0))
    for mass_ratio, methods in ((1, ("pgs",)), (100, ("pgs", "psor:1.5", "sgs"))):
        sim = cbps.Simulation(cbps.scene("chain", n=20, mass_ratio=mass_ratio))
        sim.run(steps=100)
        s = sim.build_system()  # step 100's system, not solved
        # The chain's rows are equalities (cmin = -inf, cmax = +inf) and its A is definite, so
        # the exact lambda is A^-1 b, which PGS tends to.
        exact = np.linalg.solve(s.A.toarray(), s.b)
        for method in methods:
            lam, summary = cbps.solve(s.A, s.b, s.cmin, s.cmax, method, iterations=100000,
                                      tolerance=1e-10)
            h = summary["history"]
            first = int(h["iteration"][np.flatnonzero(h["residual"] <= 1e-6)[0]])
            print(f"  mass ratio {mass_ratio:3d}, {method:9s}: 1e-6 N after {first:5d} sweeps, "
                  f"1e-10 N after {summary['iterations']:5d} ({summary['wall_time_s']:.3f} s)")
            plt.semilogy(h["iteration"], np.maximum(h["residual"], 1e-17),
                         label=f"{method}, mass ratio {mass_ratio}")
            # At a residual of 1e-10 N lambda is within 1e-9 of its largest entry (measured:
            # 1.3e-8 N of 474 N for PGS).
            check(f"{method} (mass ratio {mass_ratio}) against A^-1 b", lam, exact,
                  1e-9 * np.max(np.abs(exact)))
    plt.xlabel("sweep")
    plt.ylabel("natural-map residual (N)")
    plt.title("chain, 20 links, step 100")
    plt.grid(True, which="both", alpha=0.3)
    plt.legend()
    path = out / "chain-pgs.png"
    temporary = out / ".chain-pgs.png.tmp"
    plt.savefig(temporary, format="png", dpi=100)
    plt.close()
    os.replace(temporary, path)  # written whole or not at all
    print(f"  wrote {path}")


def stack_singular():
    print("3. A stack of 3 boxes without friction: A is singular")
    sim = cbps.Simulation(cbps.scene("stack", n=3, mu=0))
    sim.run(steps=2)
    s = sim.system()
    A = s.A.toarray()
    eigenvalues = np.linalg.eigvalsh(A)
    c = len(eigenvalues)
    # Each of the 3 faces (ground-box0, box0-box1, box1-box2) has 4 contact points, 4 normal rows,
    # but a face constrains only 3 relative motions (the normal velocity and the two tilts), so
    # the 4 rows of a face are linearly dependent: rank J = 3 per face, c - rank = 1 per face.
    # Minv is positive definite, so rank A = rank J and A has one zero eigenvalue per face.
    zero = eigenvalues <= 1e-10 * eigenvalues[-1]
    print(f"  {c} rows; eigenvalues of A (1/kg): {np.array2string(eigenvalues, precision=3)}")
    print(f"  {zero.sum()} zero (<= 1e-10 of the largest): predicted by hand 3 (one per face)")
    check("rows: 4 contact points per face, 3 faces", c, 12, 0)
    check("zero eigenvalues", zero.sum(), 3, 0)
    check("A symmetric positive semidefinite", min(eigenvalues[0], 0.0), 0.0, 1e-12 * eigenvalues[-1])
    # lambda is not unique, but w = A lambda - b is: the step still solved its problem.
    r = np.max(np.abs(s.lam - np.clip(s.lam - (A @ s.lam - s.b), s.cmin, s.cmax)))
    print(f"  the step's lambda still solves the boxed problem: residual {r:.1e} N")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="out/worked-example", help="folder for the plot")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    v_corner()
    chain_convergence(out)
    stack_singular()
    if failures:
        print(f"worked example: {len(failures)} checks failed: {', '.join(failures)}")
        return 1
    print("worked example: every check passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
