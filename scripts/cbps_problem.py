"""The boxed problem of 6.2 in numpy, for cbps's scripts and Python tests: one Matrix Market
reader, one natural-map residual, one scale, and the two stored problems the PETSc/TAO
measurements and tests share. Import it with scripts/ on sys.path (the scripts beside it find it
by themselves); nothing here imports a test.
"""
import math
import os

import numpy as np
import scipy.io
import scipy.sparse

# The stored problems of the PETSc/TAO tests (tests/petsc/test_tao.py) and measurements
# (scripts/measure_tao*.py), as `cbps matrices` arguments: a chain of 300 links (300 distance
# rows, A positive definite) and two columns of ten boxes (240 contact and friction rows, A
# singular: lambda is not unique, w and J^T lambda are). Step 30 of the stack has every box
# resting on the one below.
PETSC_PROBLEMS = {
    "chain": ["matrices", "chain", "--param", "n=300", "--step", "10"],
    "stack": ["matrices", "stack", "--param", "n=10", "--param", "columns=2", "--step", "30"],
}


def read_mtx(path):
    """A Matrix Market file: a matrix as scipy CSR, a vector (one column) as a 1-D float array."""
    m = scipy.io.mmread(path)
    return m.tocsr() if scipy.sparse.issparse(m) else np.asarray(m, dtype=float).reshape(-1)


def read_vector(folder, name):
    """FOLDER/NAME.mtx as a 1-D float array."""
    return np.asarray(scipy.io.mmread(os.path.join(folder, name + ".mtx")),
                      dtype=float).reshape(-1)


def natural_map_residual(A, b, cmin, cmax, lam):
    """||lambda - clamp(lambda - w, cmin, cmax)||_inf with w = A lambda - b (6.2), N; 0 for no
    rows. A dense or sparse."""
    w = A @ lam - b
    return float(np.max(np.abs(lam - np.clip(lam - w, cmin, cmax)), initial=0.0))


SOLVED = 1e-9  # kSolvedTolerance (include/cbps/system/unit_free.hpp): the verdict's threshold


def unit_free_residual(A, b, cmin, cmax, lam):
    """The unit-free residual of include/cbps/system/unit_free.hpp for a boxed problem (no
    cones), written here from its definition: each row's natural map with its own step
    rho_k = 1/A_kk (1/max A_kk where A_kk <= 0), |lam_k - clamp(lam_k - rho_k w_k)|, its largest
    over the force scale max(|lam|inf, max rho_k |b_k|). Returns the relative residual (0 when
    both are 0, inf when only the scale is). A dense or sparse."""
    lam = np.asarray(lam, dtype=float)
    if lam.size == 0:
        return 0.0
    diagonal = np.asarray(A.diagonal(), dtype=float)
    top = float(np.max(diagonal))
    fallback = 1.0 / top if top > 0.0 else 1.0
    rho = np.where(diagonal > 0.0, 1.0 / np.where(diagonal > 0.0, diagonal, 1.0), fallback)
    w = A @ lam - b
    residual = float(np.max(np.abs(lam - np.clip(lam - rho * w, cmin, cmax))))
    scale = max(float(np.max(np.abs(lam))), float(np.max(rho * np.abs(b))))
    if residual == 0.0:
        return 0.0
    return residual / scale if scale > 0.0 else math.inf


def scale_of(A, b):
    """max(1, |b|_inf, max |A_ij|), as scale_of in include/cbps/system/boxed_problem.hpp: the
    data's size `cbps lcp` reports beside the residual (the verdict is unit_free_residual's)."""
    a_max = abs(A).max() if scipy.sparse.issparse(A) else np.max(np.abs(A), initial=0.0)
    return max(1.0, float(np.max(np.abs(b), initial=0.0)), float(a_max))


def cone_natural_maps(lam, w, normal_rows, mu, law):
    """Each contact's ‖r − P_K(r − û)‖₂ in Coulomb's cone (docs/cones.md): r = lam[k:k + 3] and
    u = w[k:k + 3] for each normal row k, û = u + mu ‖u_t‖ e_n under law "coulomb", u under
    "ccp", P_K the projection onto ‖r_t‖ ≤ mu r_n. A numpy array, one norm per contact, N."""
    norms = []
    for k, m in zip(normal_rows, mu):
        r, u = lam[k:k + 3], np.array(w[k:k + 3], dtype=float)
        if law == "coulomb":
            u[0] += m * np.hypot(u[1], u[2])
        x = r - u
        t = np.hypot(x[1], x[2])
        if t <= m * x[0]:
            p = x
        elif m * t <= -x[0]:
            p = np.zeros(3)
        else:
            n = (m * t + x[0]) / (m * m + 1.0)
            p = np.array([n, m * n * x[1] / t, m * n * x[2] / t])
        norms.append(np.linalg.norm(r - p))
    return np.array(norms)


def cone_unit_free_residual(A, b, lam, normal_rows, mu, law):
    """The unit-free residual of include/cbps/system/unit_free.hpp for a problem whose rows are all
    contacts (normal, t1, t2 from each of normal_rows), written here from its definition: each
    contact's natural map with its own step rho_a = 1 / max of its rows' A_kk, ‖r_a − P_K(r_a −
    rho_a û_a)‖₂ (û the law's velocity, which scales with u, so the map is cone_natural_maps of
    rho_a w), its largest over the force scale max(‖lam‖∞, max_k rho_k |b_k|). Returns the
    relative residual (0 when both are 0, inf when only the scale is). A dense or sparse."""
    lam = np.asarray(lam, dtype=float)
    if lam.size == 0:
        return 0.0
    diagonal = np.asarray(A.diagonal(), dtype=float)
    top = float(np.max(diagonal))
    rho = np.empty_like(diagonal)
    for k in normal_rows:
        d = float(np.max(diagonal[k:k + 3]))
        rho[k:k + 3] = 1.0 / d if d > 0.0 else (1.0 / top if top > 0.0 else 1.0)
    w = np.asarray(A @ lam - b, dtype=float)
    norms = cone_natural_maps(lam, rho * w, normal_rows, mu, law)
    residual = float(np.max(norms, initial=0.0))
    scale = max(float(np.max(np.abs(lam))), float(np.max(rho * np.abs(b))))
    if residual == 0.0:
        return 0.0
    return residual / scale if scale > 0.0 else math.inf
