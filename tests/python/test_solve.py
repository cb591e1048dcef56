"""cbps.solve on (A, b, cmin, cmax) given from Python: the same lambda as the command line on
the same stored problem (`cbps matrices`' lambda.mtx, `cbps lcp --json`), every method of the
--solver grammar reachable by its spec text, and the per-sweep history."""
import os

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

import cbps
from cbps_problem import SOLVED, cone_unit_free_residual, unit_free_residual
from conftest import ROOT, cli, cli_json, cone_natural_maps, natural_map_residual


@pytest.fixture(scope="module")
def chain_folder(tmp_path_factory):
    """`cbps matrices` of a 6-link chain with a heavy last link at step 20."""
    folder = tmp_path_factory.mktemp("m") / "chain"
    cli("matrices", "chain", "--param", "n=6", "--param", "mass_ratio=30", "--step", 20,
        "--out", folder)
    return folder


def mm(folder, name):
    """A stored file read by scipy (an independent reader), vectors flattened."""
    x = scipy.io.mmread(str(folder / name))
    return x.tocsr() if sp.issparse(x) else np.asarray(x, dtype=float).ravel()


def stored(folder):
    return [mm(folder, f) for f in ("A.mtx", "b.mtx", "cmin.mtx", "cmax.mtx")]


def test_direct_equals_matrices_lambda(chain_folder):
    """The direct path from Python on scipy's reading of the folder gives `cbps matrices`'
    lambda.mtx (the same exact path, to its rounding floor)."""
    A, b, cmin, cmax = stored(chain_folder)
    lam, summary = cbps.solve(A, b, cmin, cmax, "direct", tolerance=0.0)
    expected = mm(chain_folder, "lambda.mtx")
    assert summary["method"] == "direct"
    # Both are the exact solution: they agree to round-off of the largest lambda (A is definite
    # for a chain, so lambda is unique).
    assert np.max(np.abs(lam - expected)) <= 1e-9 * np.max(np.abs(expected))
    assert natural_map_residual(A, b, cmin, cmax, lam) <= 1e-9 * max(1.0, np.max(np.abs(b)))


@pytest.mark.parametrize("method", ["pgs", "direct", "active-set"])
def test_solve_equals_cbps_lcp(chain_folder, method):
    """`cbps lcp DIR --solver M --json` and cbps.solve(..., M) with cbps lcp's defaults
    (10000 sweeps, tolerance 1e-10 N, from 0) give the same lambda, bit for bit: the same code on
    the same numbers (scipy's reading of the folder; Matrix Market keeps 17 digits)."""
    result = cli_json("lcp", chain_folder, "--solver", method, "--json")
    A, b, cmin, cmax = stored(chain_folder)
    lam, summary = cbps.solve(A, b, cmin, cmax, method)
    cli_lambda = np.array(result["lambda"], dtype=float)
    if method in ("direct", "active-set"):
        # cbps lcp reads the folder with J and Minv (body space); here only A is given (row
        # space): two factorizations of the same problem, equal to round-off.
        assert np.max(np.abs(lam - cli_lambda)) <= 1e-9 * np.max(np.abs(cli_lambda))
    else:
        assert np.array_equal(lam, cli_lambda)
        assert summary["iterations"] == result["iterations"]


def test_read_problem_gives_the_same_problem_as_scipy(chain_folder):
    p = cbps.read_problem(str(chain_folder))
    A, b, cmin, cmax = stored(chain_folder)
    assert (p.A != A).nnz == 0
    assert np.array_equal(p.b, b) and np.array_equal(p.cmin, cmin) and np.array_equal(p.cmax, cmax)
    assert p.J is not None and p.J.shape == mm(chain_folder, "J.mtx").shape
    assert p.dt == pytest.approx(1 / 240, rel=1e-15)


def test_read_problem_of_an_fclib_global_problem(tmp_path):
    """A cone step written as FCLIB's global problem (`cbps matrices --fclib F --global`) reads
    back as its folder: J and Minv as scipy reads the folder's, A = J Minv J^T and b to
    round-off, the contacts' cones."""
    folder, file = tmp_path / "stack", tmp_path / "stack.hdf5"
    cli("matrices", "stack", "--param", "n=2", "--param", "friction=cone", "--solver", "direct",
        "--step", 5, "--quiet", "--out", folder, "--fclib", file, "--global")
    p = cbps.read_problem(str(file))
    assert (p.J != mm(folder, "J.mtx")).nnz == 0
    Minv = mm(folder, "Minv.mtx")
    assert abs(p.Minv - Minv).max() <= 1e-12 * abs(Minv).max()
    A = mm(folder, "A.mtx")
    assert abs(p.A - A).max() <= 1e-12 * abs(A).max()
    assert np.max(np.abs(p.b - mm(folder, "b.mtx"))) <= 1e-12 * np.max(np.abs(p.b))
    assert p.v1 is None and p.dt is None  # no bodies' state in an FCLIB file
    assert p.cones["law"] == "coulomb" and len(p.cones["normal_row"]) * 3 == len(p.b)


def test_every_method_is_reachable(chain_folder):
    """Every method `cbps converge` knows, by its spec text, on the chain with J and Minv (for
    matrix-free and shock) and blocks (block-pgs): each ends at a residual, computed here, below
    1e-6 N, except Jacobi, which diverges undamped on chains and is run damped (jacobi:0.5)."""
    p = cbps.read_problem(str(chain_folder))
    A, b, cmin, cmax = p.A, p.b, p.cmin, p.cmax
    names = cbps.methods()
    assert {"pgs", "direct", "matrix-free", "apgd", "shock", "admm"} <= set(names)
    for name in names:
        if name.startswith(("siconos:", "bullet:")):
            continue  # the peers are judged, not required to solve: test_peers.py
        spec = "jacobi:0.5" if name == "jacobi" else name
        lam, summary = cbps.solve(A, b, cmin, cmax, spec, iterations=20000, tolerance=1e-9,
                                  J=p.J, Minv=p.Minv, blocks=[-1] * len(b))
        r = natural_map_residual(A, b, cmin, cmax, lam)
        assert r <= 1e-6, (spec, r, summary["message"])
        assert summary["method"] == spec


def test_relaxation_and_keys_reach_the_solver(chain_folder):
    """psor:1.3 is not pgs (other iterates); apgd:restart=off not apgd; a spec's key counts."""
    p = cbps.read_problem(str(chain_folder))
    args = (p.A, p.b, p.cmin, p.cmax)
    pgs, _ = cbps.solve(*args, "pgs", iterations=5, tolerance=0)
    psor, _ = cbps.solve(*args, "psor:1.3", iterations=5, tolerance=0)
    assert not np.array_equal(pgs, psor)
    apgd, s1 = cbps.solve(*args, "apgd", iterations=200, tolerance=0)
    plain, s2 = cbps.solve(*args, "apgd:restart=off", iterations=200, tolerance=0)
    assert not np.array_equal(apgd, plain)
    assert cbps.parse_solver_spec("apgd:restart=off")["parameters"]["restart"] == "off"


def test_history_is_one_entry_per_sweep(chain_folder):
    """history: sweep 0 is the guess, then one entry per sweep; its residuals are the
    natural-map residuals of the iterates (the last one recomputed here), time never falls."""
    p = cbps.read_problem(str(chain_folder))
    lam, s = cbps.solve(p.A, p.b, p.cmin, p.cmax, "pgs", iterations=50, tolerance=0)
    h = s["history"]
    assert s["iterations"] == 50 and s["termination"] == "iteration limit"
    np.testing.assert_array_equal(h["iteration"], np.arange(51))
    assert h["residual"][0] == pytest.approx(natural_map_residual(p.A, p.b, p.cmin, p.cmax,
                                                                  np.zeros(len(p.b))), rel=1e-12)
    assert h["residual"][-1] == pytest.approx(natural_map_residual(p.A, p.b, p.cmin, p.cmax, lam),
                                              rel=1e-9)
    assert np.all(np.diff(h["time_s"]) >= 0)
    assert h["residual"][-1] < h["residual"][0]
    _, s = cbps.solve(p.A, p.b, p.cmin, p.cmax, "pgs", iterations=5, history=False)
    assert s["history"] is None


def test_lemke_on_a_siconos_file_equals_cbps_lcp():
    """Lemke on a Siconos LCP from Python against `cbps lcp FILE --json` (Lemke by default)."""
    path = ROOT / "tests" / "data" / "siconos" / "lcp" / "lcp_CPS_1.dat"
    result = cli_json("lcp", path, "--json")
    assert result["solver"] == "lemke" and result["status"] == "solved"
    p = cbps.read_siconos(str(path))
    lam, s = cbps.solve(p.A, p.b, p.cmin, p.cmax, "lemke")
    # One method, one path: Python's summary is cbps lcp's (the same entry of the method table).
    assert s["solved"] and s["message"] == result["message"]
    assert s["iterations"] == result["iterations"] and s["residual"] == result["residual"]
    np.testing.assert_array_equal(lam, np.array(result["lambda"], dtype=float))


def test_dense_and_list_inputs():
    """A dense array and lists are taken as well as scipy.sparse; a 2x2 problem solved by hand:
    A = [[2, 1], [1, 2]], b = [1, 1], unbounded: lambda = A^-1 b = [1/3, 1/3]."""
    lam, s = cbps.solve(np.array([[2.0, 1.0], [1.0, 2.0]]), [1, 1], [-np.inf] * 2, [np.inf] * 2,
                        "direct")
    np.testing.assert_allclose(lam, [1 / 3, 1 / 3], rtol=1e-14)
    # With cmax = 0.2 on row 0: lambda_0 = 0.2, w_0 <= 0; row 1: 2 lambda_1 = 1 - 0.2.
    lam, s = cbps.solve(sp.csc_matrix([[2.0, 1.0], [1.0, 2.0]]), np.array([[1.0], [1.0]]),
                        [-np.inf, -np.inf], [0.2, np.inf], "pgs")
    np.testing.assert_allclose(lam, [0.2, 0.4], rtol=1e-9)


def tridiagonal(c):
    """A chain's A (2 on the diagonal, -1 beside), b = 1, unbounded: PGS's residual falls by
    about (pi / (c + 1))**2 per sweep, so on c = 200 it is still far above round-off after
    20000 sweeps and every sampled entry is a number worth comparing."""
    A = sp.diags([-np.ones(c - 1), 2 * np.ones(c), -np.ones(c - 1)], [-1, 0, 1], format="csr")
    return A, np.ones(c), np.full(c, -np.inf), np.full(c, np.inf)


def test_history_limit_thins_evenly_and_keeps_the_last_sweep():
    """20000 sweeps with history_limit=100: the entries are sweep 0 and every s-th sweep for the
    smallest power of two s with 20000 // s + 1 <= 100 (s = 256: 0, 256, ..., 19968), then
    the last sweep, 20000; each residual is that of PGS's iterate after so many sweeps,
    recomputed here with numpy from a solve stopped there."""
    A, b, cmin, cmax = tridiagonal(200)
    lam, s = cbps.solve(A, b, cmin, cmax, "pgs", iterations=20000, tolerance=0,
                        history_limit=100)
    h = s["history"]
    assert s["iterations"] == 20000
    expected = np.append(np.arange(0, 20000, 256), 20000)
    np.testing.assert_array_equal(h["iteration"], expected)
    assert len(h["residual"]) == len(h["time_s"]) == len(expected) <= 100
    for k in (256, 5120, 19968):
        lam_k, _ = cbps.solve(A, b, cmin, cmax, "pgs", iterations=k, tolerance=0, history=False)
        r = natural_map_residual(A, b, cmin, cmax, lam_k)
        assert r > 1e-6
        assert h["residual"][np.flatnonzero(h["iteration"] == k)[0]] == pytest.approx(r, rel=1e-9)
    assert h["residual"][-1] == pytest.approx(natural_map_residual(A, b, cmin, cmax, lam),
                                              rel=1e-9)
    assert np.all(np.diff(h["time_s"]) >= 0)


def test_history_is_bounded_by_default():
    """cbps.solve(..., iterations=2**31-1, tolerance=0) grew its history by a sweep at a time
    (5.3 GB in 60 s). The default limit is a million entries: 3e6 sweeps of a 2 x 2 problem
    keep every 4th sweep (the smallest power of two s with 3e6 // s + 1 <= 1e6), 750001
    entries ending at the last sweep; history_limit=2 keeps the guess and the last sweep."""
    A = np.array([[2.0, 1.0], [1.0, 2.0]])
    b, cmin, cmax = [1.0, 1.0], [-np.inf] * 2, [np.inf] * 2
    _, s = cbps.solve(A, b, cmin, cmax, "pgs", iterations=3_000_000, tolerance=0)
    h = s["history"]
    assert len(h["iteration"]) == 750001 <= 1_000_000
    assert h["iteration"][1] == 4 and h["iteration"][-1] == 3_000_000
    _, s = cbps.solve(A, b, cmin, cmax, "pgs", iterations=1000, tolerance=0, history_limit=2)
    np.testing.assert_array_equal(s["history"]["iteration"], [0, 1000])


# Issue 28, item 3: no method returns a silently wrong answer.
UPPER = [[2.0, 1.0], [0.0, 2.0]]  # not symmetric; by hand lambda = [1/4, 1/2], w = 0 (both > 0)


@pytest.mark.parametrize("method", ["pgs", "psor:1.3", "sgs", "jacobi", "rbgs", "block-pgs",
                                    "pgs-nesterov"])
def test_sweeps_solve_a_non_symmetric_a(method):
    """The sweeps of 7.1.1 read A's rows: the issue's example gives A's solution, not Aᵀ's
    ([1/2, 1/4]), as Lemke does."""
    lam, summary = cbps.solve(UPPER, [1, 1], [0, 0], [np.inf, np.inf], method, tolerance=1e-14)
    assert np.allclose(lam, [0.25, 0.5], rtol=0, atol=1e-13), summary["message"]
    lemke, _ = cbps.solve(UPPER, [1, 1], [0, 0], [np.inf, np.inf], "lemke")
    assert np.allclose(lemke, [0.25, 0.5], rtol=0, atol=1e-13)


@pytest.mark.parametrize("method", ["apgd", "nncg", "pgs-sm", "admm", "direct", "active-set"])
def test_qp_methods_refuse_a_non_symmetric_a(method):
    """The methods that minimise ½ λᵀAλ − bᵀλ refuse a non-symmetric A (cbps.InputError)."""
    with pytest.raises(cbps.InputError, match=r"A - A\^T"):
        cbps.solve(UPPER, [1, 1], [0, 0], [np.inf, np.inf], method)


@pytest.mark.parametrize("method", ["direct", "active-set"])
def test_exact_paths_solve_a_zero_row(method):
    """A zero row (j_c = 0) is legitimate: w_2 = −b_2 = −1 < 0 puts lambda_2 at cmax = 5; the
    rest, [[2, 1], [1, 2]] lambda = [1, 1], gives 1/3 each (by hand)."""
    A = [[2, 1, 0], [1, 2, 0], [0, 0, 0]]
    lam, summary = cbps.solve(A, [1, 1, 1], [0] * 3, [np.inf, np.inf, 5], method)
    assert np.allclose(lam, [1 / 3, 1 / 3, 5], rtol=0, atol=1e-14)
    assert summary["residual"] <= 1e-15


def test_set_threads_as_the_command_line_sets_them():
    """cbps.set_threads(1) gives the libraries one thread, as --threads 1 does (OpenMP's regions
    inactive: CHOLMOD's parallel loops name their own team of 4), and the direct path still
    solves; threads() reports the same."""
    r = cbps.set_threads(1)
    assert r["requested"] == 1 and r["blas_threads"] == 1
    assert r["openmp_threads"] in (0, 1)  # 0: no OpenMP runtime loaded
    assert cbps.threads() == r
    n = 400
    A = sp.diags([-np.ones(n - 1), 4.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csr")
    b = np.linspace(-1.0, 1.0, n)
    lam, summary = cbps.solve(A, b, np.full(n, -np.inf), np.full(n, np.inf), method="direct")
    assert np.max(np.abs(A @ lam - b)) <= 1e-12
    with pytest.raises(cbps.InputError, match="threads -1"):
        cbps.set_threads(-1)


def test_summary_carries_cbps_verdict(chain_folder):
    """Every solve's summary has cbps's verdict on its lambda, as `cbps lcp` gives it: the
    unit-free residual (each row's natural map with step 1/A_kk over max(|lambda|, max |b_k|/A_kk),
    written in numpy in scripts/cbps_problem.py) and `solved` exactly when it is at most 1e-9."""
    A, b, cmin, cmax = stored(chain_folder)
    for method, iterations in (("pgs", 3), ("pgs", 100000), ("direct", 1), ("lemke", 1)):
        lam, s = cbps.solve(A, b, cmin, cmax, method, iterations=iterations)
        mine = unit_free_residual(A, b, cmin, cmax, lam)
        assert s["unit_free"]["relative"] == pytest.approx(mine, rel=1e-6, abs=1e-15), method
        assert s["solved"] == (mine <= SOLVED), (method, iterations, mine)
    # Three sweeps of PGS on a chain with a heavy link are far from the answer; the direct path
    # is not.
    assert not cbps.solve(A, b, cmin, cmax, "pgs", iterations=3)[1]["solved"]
    assert cbps.solve(A, b, cmin, cmax, "direct")[1]["solved"]


def test_summary_carries_cbps_verdict_on_cones():
    """The same on friction cones, for a problem of Siconos' own (OneObject-i1028-138: W not
    symmetric, mu per contact) under both laws: cbps's unit-free residual agrees with the one
    written from its definition in numpy (scripts/cbps_problem.py, cone_unit_free_residual: each
    contact's natural map with step 1 / max A_kk of its rows, over max(|lambda|, rho_k |b_k|)), on
    answers far from the law (5 sweeps) and on exact ones."""
    p = cbps.read_problem(os.path.join(ROOT, "validation/data/siconos-fc3d",
                                       "OneObject-i1028-138.hdf5.dat"))
    rows = p.cones["normal_row"]
    for law in ("coulomb", "ccp"):
        cones = dict(p.cones, law=law)
        for method, iterations in (("nsgs", 5), ("direct", 1000)):
            lam, s = cbps.solve(p.A, p.b, p.cmin, p.cmax, method, cones=cones,
                                iterations=iterations, unit_free=True)
            mine = cone_unit_free_residual(p.A, p.b, lam, rows, p.cones["mu"], law)
            assert s["unit_free"]["relative"] == pytest.approx(mine, rel=1e-6, abs=1e-15), (
                law, method)
            assert s["solved"] == (mine <= SOLVED), (law, method, mine)
            assert (mine > 1e-4) if method == "nsgs" else (mine <= 1e-10), (law, method, mine)


def test_check_gives_the_closed_form_residual_of_a_perturbed_answer():
    # w = A lam - b with A = diag(2, 4), b = (2, -4), 0 <= lam: the answer is lam* = (1, 0) (row 0
    # between its bounds with w_0 = 0, row 1 at cmin with w_1 = 4 >= 0). lam = (1 + d, 0) gives
    # w_0 = 2 d and row 0's unit-free term (rho_0 = 1/A_00) |rho_0 w_0| = d; row 1's term is 0.
    A = sp.csr_matrix(np.diag([2.0, 4.0]))
    b = np.array([2.0, -4.0])
    cmin, cmax = np.zeros(2), np.full(2, np.inf)
    d = 1e-3
    r = cbps.check(A, b, cmin, cmax, np.array([1.0 + d, 0.0]))
    assert not r["solved"]
    assert abs(r["unit_free"]["residual"] - d) <= 1e-15
    assert r["unit_free"]["scale"] == 1.0 + d  # max(|lam|inf, max_k rho_k |b_k|) = 1 + d
    assert r["statuses"] == {"between": 1, "at cmin": 1}
    assert r["worst"][0]["row"] == 0 and r["worst"][0]["label"] == "row 0"
    assert abs(r["exact"]["lambda_distance"] - d) <= 1e-15
    assert r["exact"]["force_distance"] is None  # no J given
    solved = cbps.check(A, b, cmin, cmax, np.array([1.0, 0.0]), exact=False)
    assert solved["solved"] and solved["exact"] is None
    with pytest.raises(cbps.InputError, match="lam"):
        cbps.check(A, b, cmin, cmax, np.array([1.0]))
    with pytest.raises(cbps.InputError, match="lam"):
        cbps.check(A, b, cmin, cmax, np.array([1.0, np.nan]))
    # No rows: nothing to violate, solved, and the exact answer is the empty one.
    empty = cbps.check(sp.csr_matrix((0, 0)), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0))
    assert empty["solved"] and empty["worst"] == [] and empty["exact"]["w_distance"] == 0.0


def test_check_judges_a_cone_problem_with_a_non_symmetric_w():
    # Siconos' Capsules (FCLIB, 286 contacts in Coulomb's cone, W not symmetric): nsgs's answer to
    # its floor is solved; the same with one contact's normal pushed by 1e-3 N is not.
    p = cbps.read_problem(str(ROOT / "tests" / "data" / "siconos-fc3d" / "Capsules-i125-1213.hdf5"))
    assert abs(p.A - p.A.T).max() > 0
    lam, _ = cbps.solve(p.A, p.b, p.cmin, p.cmax, "nsgs", cones=p.cones, iterations=100000,
                        tolerance=1e-14, history=False)
    r = cbps.check(p.A, p.b, p.cmin, p.cmax, lam, cones=p.cones)
    assert r["solved"] and r["contacts"] == 286 and r["law"] == "coulomb"
    assert r["exact"]["available"]
    lam[0] += 1e-3
    pushed = cbps.check(p.A, p.b, p.cmin, p.cmax, lam, cones=p.cones, exact=False)
    assert not pushed["solved"] and pushed["exact"] is None


def test_lemke_through_the_library_takes_cfm_and_refuses_cones():
    """'lemke' runs through the library's one solve(): with cfm it solves (A + eps E) lambda = b
    (UPPER + 0.1 I, both rows free: by hand lambda_2 = 1/2.1, lambda_1 = (1 - lambda_2)/2.1), on
    a non-symmetric A; and a problem in friction cones is refused by name, as for every boxed
    method."""
    lam, s = cbps.solve(UPPER, [1, 1], [0, 0], [np.inf, np.inf], "lemke", cfm=0.1)
    l2 = 1 / 2.1
    assert np.allclose(lam, [(1 - l2) / 2.1, l2], rtol=0, atol=1e-13), s["message"]
    assert s["method"] == "lemke"
    cones = {"law": "coulomb", "normal_row": [0], "mu": [0.5]}
    with pytest.raises(cbps.InputError, match="lemke.*friction cones"):
        cbps.solve(np.eye(3) * 2, [1, 1, 1], [0, -np.inf, -np.inf], [np.inf] * 3, "lemke",
                   cones=cones)


@pytest.mark.parametrize("unit_free", [True, False])
def test_unit_free_stops_the_sweeps_where_the_verdict_holds(unit_free):
    """unit_free=True reads the tolerance as `cbps lcp` does on a Siconos or FCLIB file: within
    tau N and within a unit-free tau. Siconos' relay problem in units of force 1e12 times cbps's
    and of velocity 1e-12 times (A as it is; b, cmin, cmax and lambda 1e-12 times): the natural map
    is 1e-12 times smaller, so tau = 1e-10 N is met far from the answer. With the flag PGS stops
    within tau unit-free (the residual of cbps_problem.py, written apart from cbps); without it it
    stops where the unit-free residual is still above 1e-3."""
    p = cbps.read_siconos(str(ROOT / "tests" / "data" / "siconos" / "relay" / "relay_4x4.dat"))
    s = 1e-12
    b, cmin, cmax = p.b * s, p.cmin * s, p.cmax * s
    lam, summary = cbps.solve(p.A, b, cmin, cmax, "pgs", iterations=100000, tolerance=1e-10,
                              unit_free=unit_free)
    assert summary["termination"] == "residual tolerance reached"
    relative = unit_free_residual(p.A, b, cmin, cmax, lam)
    if unit_free:
        assert relative <= 1e-10
        assert summary["solved"]
    else:
        assert relative > 1e-3
        assert not summary["solved"]


@pytest.mark.parametrize("law", ["coulomb", "ccp"])
@pytest.mark.parametrize("unit_free", [True, False])
def test_unit_free_stops_nsgs_on_cones_with_a_non_symmetric_w(law, unit_free):
    """The same on friction cones: Siconos' Rover4396 (W not symmetric) under nsgs, forces 1e12
    times smaller. Judged apart from cbps, in the file's own units: each contact's natural map
    (cbps_problem.cone_natural_maps) at 1e12 lambda. With the flag it is within 1e-9 of the
    forces' size; without it nsgs stops at lambda = 0, where the map is the size of the forces."""
    p = cbps.read_problem(str(ROOT / "tests" / "data" / "siconos-fc3d" / "Rover4396.dat"))
    assert abs(p.A - p.A.T).max() > 1e-7  # the stored W is not symmetric
    cones = dict(p.cones)
    cones["law"] = law
    s = 1e-12
    lam, summary = cbps.solve(p.A, p.b * s, p.cmin * s, p.cmax * s, "nsgs", iterations=100000,
                              tolerance=1e-10, cones=cones, unit_free=unit_free)
    assert summary["termination"] == "residual tolerance reached"
    forces = lam / s
    maps = cone_natural_maps(forces, p.A @ forces - p.b, cones["normal_row"], cones["mu"], law)
    size = float(np.max(np.abs(forces), initial=1.0))
    if unit_free:
        assert maps.max() <= 1e-9 * size
    else:
        assert maps.max() > 1e-2


def test_unit_free_direct_takes_the_same_path_in_any_unit_of_force():
    """direct with unit_free=True (as `cbps lcp` on a file) on friction cones with a non-symmetric
    W: Siconos' Capsules-i125-1213 in units of force 1024 times smaller and larger than its own
    (lambda -> lambda / s, A -> s A, exact in floating point). The answers, brought back to the
    file's units, agree to 1e-12 of the forces, and each keeps Coulomb's law there by the natural
    maps of cbps_problem, written apart: within 1e-9 of the forces' size."""
    p = cbps.read_problem(str(ROOT / "tests" / "data" / "siconos-fc3d" / "Capsules-i125-1213.hdf5"))
    assert abs(p.A - p.A.T).max() > 1e-7  # the simulator's W is not symmetric
    answers = []
    for s in (1.0 / 1024.0, 1024.0):
        lam, summary = cbps.solve(p.A * s, p.b, p.cmin / s, p.cmax / s, "direct", cones=p.cones,
                                  history=False, unit_free=True)
        assert summary["termination"] == "direct solve"
        answers.append(np.asarray(lam) * s)
    size = float(np.max(np.abs(answers[0]), initial=1.0))
    assert np.max(np.abs(answers[0] - answers[1])) <= 1e-12 * size
    for forces in answers:
        maps = cone_natural_maps(forces, p.A @ forces - p.b, p.cones["normal_row"], p.cones["mu"],
                                 p.cones["law"])
        assert maps.max() <= 1e-9 * size
