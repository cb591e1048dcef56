#!/usr/bin/python3
"""One step of a small engine of your own, dumped as a cbps problem folder and judged by
`cbps check` (docs/check-any-engine.md).

The engine: a box (1 kg, half extents 0.2 x 0.05 x 0.1 m) resting on the ground y = 0 on its four
bottom corners, gravity -9.81 m/s^2 along y, step dt = 1/60 s, friction in Coulomb's cone with
mu = 0.5. Its solver is a projected Gauss-Seidel on each contact's three rows, stopped after
--iterations sweeps, as engines stop theirs. Nothing here imports cbps: the folder is written
with scipy and json alone, the way any engine can write it.

    /usr/bin/python3 examples/engine_step.py OUT [--iterations K]
    build/release/cbps check OUT --lambda OUT/lambda_engine.txt

The folder holds A.mtx, b.mtx, cmin.mtx, cmax.mtx (the problem w = A lam - b), J.mtx and
Minv.mtx (A = J Minv J^T), labels.json (a name per row) and cones.json (the contacts' rows and
mu); lambda_engine.txt is the engine's answer, one number a line.
"""
import argparse
import json
import pathlib

import numpy as np
import scipy.io
import scipy.sparse as sp

MASS = 1.0                              # kg
HALF = np.array([0.2, 0.05, 0.1])       # half extents, m
GRAVITY = np.array([0.0, -9.81, 0.0])   # m/s^2
DT = 1.0 / 60.0                         # s
MU = 0.5


def box_rows():
    """The step's J (12 x 6: per corner the normal row, then two tangent rows) and Minv (6 x 6).

    The box's velocity is (v, omega) at its centre, which is at y = HALF[1], so its bottom
    corners are at r = (+-HALF[0], -HALF[1], +-HALF[2]) from the centre. A row's J is (d, r x d) for its direction d: the velocity of the corner along d is
    d . (v + omega x r) = d . v + (r x d) . omega.
    """
    normal, t1, t2 = np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
    rows, labels = [], []
    for k, (sx, sz) in enumerate([(1, 1), (1, -1), (-1, 1), (-1, -1)]):
        r = np.array([sx * HALF[0], -HALF[1], sz * HALF[2]])
        for name, d in (("normal", normal), ("t1", t1), ("t2", t2)):
            rows.append(np.concatenate([d, np.cross(r, d)]))
            labels.append(f"{'contact' if name == 'normal' else 'friction'} ground-box #{k}"
                          + ("" if name == "normal" else f" {name}"))
    J = np.array(rows)
    inertia = MASS / 3.0 * np.array([HALF[1] ** 2 + HALF[2] ** 2, HALF[0] ** 2 + HALF[2] ** 2,
                                     HALF[0] ** 2 + HALF[1] ** 2])  # solid box, kg m^2
    Minv = np.diag(np.concatenate([np.full(3, 1.0 / MASS), 1.0 / inertia]))
    return J, Minv, labels


def engine_solve(A, b, iterations):
    """The engine's own solver: projected Gauss-Seidel over the contacts (normal, then the two
    tangent rows clamped to the disc of radius mu lam_n), from lam = 0."""
    lam = np.zeros(len(b))
    for _ in range(iterations):
        for n in range(0, len(b), 3):
            w = A[n] @ lam - b[n]
            lam[n] = max(0.0, lam[n] - w / A[n, n])
            for t in (n + 1, n + 2):
                lam[t] -= (A[t] @ lam - b[t]) / A[t, t]
            tangential = np.hypot(lam[n + 1], lam[n + 2])
            if tangential > MU * lam[n]:
                lam[n + 1:n + 3] *= MU * lam[n] / tangential
    return lam


def write_vector(path, v, comment):
    scipy.io.mmwrite(str(path), np.asarray(v, dtype=float).reshape(-1, 1), comment=comment,
                     precision=17)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", type=pathlib.Path, help="the folder to write (must not exist)")
    parser.add_argument("--iterations", type=int, default=10,
                        help="the engine's sweeps (default 10)")
    args = parser.parse_args()
    args.out.mkdir(parents=True)

    J, Minv, labels = box_rows()
    v1 = np.zeros(6)                               # at rest before the step, m/s and rad/s
    fext = np.concatenate([MASS * GRAVITY, np.zeros(3)])  # N and N m
    upsilon = np.zeros(len(J))                     # no penetration to push out, m/s
    A = J @ Minv @ J.T                             # 1/kg
    b = upsilon / DT - J @ (v1 / DT + Minv @ fext)  # m/s^2
    lam = engine_solve(A, b, args.iterations)      # N (the impulse is lam dt)

    scipy.io.mmwrite(str(args.out / "A.mtx"), sp.coo_matrix(A), comment="A = J Minv J^T, 1/kg",
                     precision=17)
    scipy.io.mmwrite(str(args.out / "J.mtx"), sp.coo_matrix(J), comment="J, c x 6n",
                     precision=17)
    scipy.io.mmwrite(str(args.out / "Minv.mtx"), sp.coo_matrix(Minv), comment="Minv, 6n x 6n",
                     precision=17)
    write_vector(args.out / "b.mtx", b, "b = upsilon/dt - J (v1/dt + Minv fext), m/s^2")
    contacts = range(0, len(b), 3)
    cmin = np.array([0.0 if k in contacts else -np.inf for k in range(len(b))])
    write_vector(args.out / "cmin.mtx", cmin, "cmin, N (the cone's rows: not used)")
    write_vector(args.out / "cmax.mtx", np.full(len(b), np.inf), "cmax, N")
    (args.out / "labels.json").write_text(json.dumps({"rows": labels}, indent=2) + "\n")
    (args.out / "cones.json").write_text(json.dumps({
        "law": "coulomb",
        "contacts": [{"normal_row": n, "mu": MU} for n in contacts]}, indent=2) + "\n")
    (args.out / "lambda_engine.txt").write_text(
        "# the engine's lambda, N, one row a line\n" + "".join(f"{x!r}\n" for x in lam))
    print(f"wrote {args.out}: {len(b)} rows, the engine's lambda after {args.iterations} sweeps")


if __name__ == "__main__":
    main()
