#!/usr/bin/python3
"""Whether Coulomb's law on a stored contact problem has a solution: a strictly feasible velocity.

    PYTHONPATH=build/release/python /usr/bin/python3 scripts/strict_feasibility.py PROBLEM
        [--json] [--witness FILE.mtx]

PROBLEM is anything `cbps lcp` reads with friction cones (an FCLIB file, a Siconos frictional-
contact dump, a `cbps matrices` folder with cones.json) whose every row is in a cone. In cbps's
terms the local problem is w = A lambda - b with each contact's (normal, t1, t2) rows: r = lambda
in K = {||r_t|| <= mu r_n} and, under Coulomb's law, u + mu ||u_t|| e_n in the dual cone
K* = {mu ||u_t|| <= u_n}, orthogonal to r (docs/cones.md).

Acary, Cadoux, Lemarechal & Malick (ZAMM 91(2), 2011) show that this problem has a solution
wherever it is strictly feasible: some velocity of the bodies puts every contact's u strictly
inside K*, every contact opening without sliding (their global form, u = H v + w with M
positive definite). Where A = H M^-1 H^T (a symmetric positive semi-definite A, as every
rigid-body simulation makes) the velocities H v + w are exactly the u = A z - b, z any vector,
so the test needs A and b alone. This script looks for such a z by a linear program: maximise t
subject to u_n - mu (+-u_t1 +-u_t2) >= t at every contact, u = A z - b, t <= max(1, ||b||inf),
the polyhedron inside K* (|x| + |y| >= ||(x, y)||), solved by SciPy's HiGHS. It then checks the
z it found with numpy, in double precision, against K* itself: the least u_n - mu ||u_t|| over
the contacts (the margin, in the problem's units of velocity) must be positive, above the
rounding of u. Where it is, a solution exists (exit 0): a solver that stops short of one has
failed, not the problem. Where the program finds no positive t, nothing is shown (exit 1): the
problem may still be strictly feasible outside the polyhedron, or have a solution without being
strictly feasible. Bad input (not a contact problem; A not symmetric or, up to 5,000 rows where
its eigenvalues are computed, not positive semi-definite: the theorem does not apply) exits 2
with the reason.

--witness FILE.mtx writes z (Matrix Market, one column) where it is shown; --json prints the
result as one JSON object: problem, rows, contacts, strictly_feasible (true, or false where
nothing is shown), margin (the checked least u_n - mu ||u_t||, null where nothing is shown),
lp_t (the program's optimum), witness (the file written, or null), psd_checked (A's
eigenvalues computed: at most 5,000 rows).
"""
import argparse
import json
import math
import os
import sys

import numpy as np
import scipy.io
import scipy.optimize
import scipy.sparse as sp

SIGNS = ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0))
# A is checked positive semi-definite (dense eigenvalues) up to this many rows; above, it is
# taken to be, as a rigid-body simulation makes it ("psd_checked": false in the JSON).
PSD_CHECK_ROWS = 5000


class BadInput(Exception):
    """Input the certificate does not cover: exit 2 with the message."""


def contact_rows(rows, normal_rows):
    """Each contact's three rows, checked to cover all the problem's rows once."""
    covered = np.zeros(rows, dtype=int)
    for k in normal_rows:
        if k < 0 or k + 3 > rows:
            raise BadInput(f"contact with normal row {k}: runs past the {rows} rows")
        covered[k:k + 3] += 1
    if np.any(covered != 1):
        free = int(np.sum(covered == 0))
        raise BadInput(f"{free} of the {rows} rows are in no friction cone: the certificate covers "
                       "contact problems whose every row is in a cone")


def dual_cone_margins(u, normal_rows, mu):
    """u_n - mu ||u_t|| per contact: positive strictly inside K* (in the units of u)."""
    k = np.asarray(normal_rows)
    return u[k] - np.asarray(mu) * np.hypot(u[k + 1], u[k + 2])


def certificate(A, b, normal_rows, mu):
    """(z, t, margin): the program's z and optimum t, and the least u_n - mu ||u_t|| at
    u = A z - b checked against K* itself, or margin None where the z found is not strictly
    inside every K* beyond rounding (nothing shown; z None and t nan where the program did not
    finish). A: scipy.sparse or dense, symmetric."""
    A = sp.csr_matrix(A, dtype=float)
    b = np.asarray(b, dtype=float).reshape(-1)
    rows = A.shape[0]
    if A.shape != (rows, rows) or b.shape != (rows,):
        raise BadInput(f"A is {A.shape[0]}x{A.shape[1]} and b has {b.shape[0]} entries")
    contact_rows(rows, normal_rows)
    asym = abs(A - A.T).max() if rows else 0.0
    if asym > 1e-12 * max(1.0, abs(A).max()):
        raise BadInput(f"A is not symmetric (entries differ by up to {asym:.3g}): the existence "
                       "theorem needs A = H M^-1 H^T, a symmetric A")
    if rows <= PSD_CHECK_ROWS:  # the theorem's A = H M^-1 H^T is positive semi-definite
        least = float(np.linalg.eigvalsh(A.toarray())[0]) if rows else 0.0
        if least < -1e-9 * max(1.0, abs(A).max()):
            raise BadInput(f"A is not positive semi-definite (least eigenvalue {least:.3g}): "
                           "the existence theorem needs A = H M^-1 H^T")
    # Each contact's four rows of -(a . (A z - b)) + t <= 0, a = e_n - mu (s1 e_t1 + s2 e_t2).
    i, j, v = [], [], []
    for c, (k, m) in enumerate(zip(normal_rows, mu)):
        for s, (s1, s2) in enumerate(SIGNS):
            i += [4 * c + s] * 3
            j += [k, k + 1, k + 2]
            v += [1.0, -m * s1, -m * s2]
    n_cons = 4 * len(normal_rows)
    sel = sp.csr_matrix((v, (i, j)), shape=(n_cons, rows))
    lhs = sp.hstack([-(sel @ A), np.ones((n_cons, 1))]).tocsr()
    rhs = -(sel @ b)
    cap = max(1.0, float(np.max(np.abs(b), initial=0.0)))
    cost = np.zeros(rows + 1)
    cost[-1] = -1.0
    bounds = [(None, None)] * rows + [(None, cap)]
    lp = scipy.optimize.linprog(cost, A_ub=lhs, b_ub=rhs, bounds=bounds, method="highs")
    if lp.status != 0:  # nothing shown: no z to check
        return None, math.nan, None
    z, t = lp.x[:rows], -lp.fun
    u = A @ z - b
    # Each row's rounding in u = A z - b: at most (terms + 1) eps (|A| |z| + |b|) (Higham,
    # Accuracy and Stability of Numerical Algorithms, 2002, 3.1), doubled for the norm and the
    # product; a contact counts as shown only with its margin above its rows' bound.
    terms = np.diff(A.indptr) + 1
    bound = 2 * terms * np.finfo(float).eps * (abs(A) @ np.abs(z) + np.abs(b))
    k = np.asarray(normal_rows)
    slack = bound[k] + np.asarray(mu) * (bound[k + 1] + bound[k + 2])
    margins = dual_cone_margins(u, normal_rows, mu)
    shown = bool(np.all(margins > slack))
    return z, t, (float(np.min(margins)) if shown else None)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("problem", help="an FCLIB file, a Siconos frictional-contact dump or a "
                    "cbps matrices folder with cones.json")
    ap.add_argument("--json", action="store_true", help="print the result as one JSON object")
    ap.add_argument("--witness", help="write z (u = A z - b strictly inside every K*) here")
    args = ap.parse_args(argv)
    try:
        import cbps  # the build's module
    except ImportError:
        print("strict_feasibility: the cbps module is not on the path: run with "
              "PYTHONPATH=build/release/python (docs/python.md)", file=sys.stderr)
        return 2
    try:
        p = cbps.read_problem(args.problem)
        if p.cones is None:
            raise BadInput("no friction cones: not a contact problem")
        if args.witness and os.path.exists(args.witness):
            raise BadInput(f"--witness {args.witness}: exists; give a new file")
        z, t, margin = certificate(p.A, p.b, list(p.cones["normal_row"]), list(p.cones["mu"]))
    except (BadInput, cbps.InputError) as e:
        print(f"strict_feasibility: {args.problem}: {e}", file=sys.stderr)
        return 2
    written = None
    if margin is not None and args.witness:
        tmp = args.witness + ".part.mtx"  # written whole, then moved into place
        scipy.io.mmwrite(tmp, z.reshape(-1, 1), comment="z: u = A z - b strictly inside K*")
        os.replace(tmp, args.witness)
        written = args.witness
    result = {"problem": args.problem, "rows": int(p.A.shape[0]),
              "contacts": len(p.cones["normal_row"]), "strictly_feasible": margin is not None,
              "margin": margin, "lp_t": t if math.isfinite(t) else None, "witness": written,
              "psd_checked": int(p.A.shape[0]) <= PSD_CHECK_ROWS}
    if args.json:
        print(json.dumps(result))
    elif margin is not None:
        print(f"{args.problem}: strictly feasible: u = A z - b opens every contact without "
              f"sliding, least u_n - mu |u_t| {margin:.3g}; Coulomb's law has a solution "
              "(Acary, Cadoux, Lemarechal & Malick 2011)")
    else:
        why = (f"the linear program's best t is {t:.3g} (the polyhedron inside K* admits no "
               "strictly feasible velocity)" if math.isfinite(t) else
               "the linear program did not finish")
        print(f"{args.problem}: not shown: {why}; existence is neither shown nor refuted")
    return 0 if margin is not None else 1


if __name__ == "__main__":
    sys.exit(main())
