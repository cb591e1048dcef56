"""The peers (siconos:NAME, bullet:NAME, docs/peers.md) through cbps.solve: on a small strictly
convex problem with every kind of row they return its unique solution, found here by enumerating
the bound patterns; the summary carries the peer's own word; a problem a peer cannot take raises
cbps.InputError saying why; and an abort() inside Siconos ends its child process, not Python.

Skipped as a whole in a build without Siconos or Bullet (both optional, CBPS_PEERS)."""
import itertools
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import cbps
from conftest import cli, natural_map_residual


def _missing_peer_library():
    """The InputError of a build without one of the peer libraries, or None."""
    one = np.array([[1.0]])
    for spec in ("bullet:pgs", "siconos:lemke"):
        try:
            cbps.solve(one, np.array([1.0]), np.array([0.0]), np.array([np.inf]), spec)
        except cbps.InputError as e:
            if "this build has no" in str(e):
                return str(e)
            raise
    return None


_missing = _missing_peer_library()
if _missing is not None:
    pytest.skip(_missing, allow_module_level=True)

PEERS = ("siconos:lemke", "siconos:pgs", "siconos:enum", "siconos:avi", "bullet:dantzig",
         "bullet:lemke", "bullet:pgs")


def mixed_problem():
    """6 rows: two [0, inf), two [-1, 1], two free (0 inside every box); A = L L^T + I
    (eigenvalues >= 1), b drawn with a fixed seed (chosen so that the solution has a row of each
    kind at a bound and inside, test_the_mixed_problem_is_a_real_test)."""
    rng = np.random.default_rng(14)
    L = rng.standard_normal((6, 6))
    A = L @ L.T + np.eye(6)
    b = 4.0 * rng.standard_normal(6)
    cmin = np.array([0.0, 0.0, -1.0, -1.0, -np.inf, -np.inf])
    cmax = np.array([np.inf, np.inf, 1.0, 1.0, np.inf, np.inf])
    return A, b, cmin, cmax


def enumerate_solution(A, b, cmin, cmax):
    """The minimiser of 1/2 x^T A x - b^T x on the box, by trying every pattern of active bounds
    (each row free, at cmin or at cmax where finite: at most 3^rows patterns): fix the active
    rows, solve A_FF x_F = b_F - A_FA x_A for the others, keep the patterns whose point is in the
    box and whose w = A x - b has the KKT sign (>= 0 at cmin, <= 0 at cmax). The QP is strictly
    convex (A definite), so its KKT point is unique; every pattern that passes gives it."""
    n = len(b)
    options = [["free"] + (["lo"] if np.isfinite(cmin[k]) else [])
               + (["hi"] if np.isfinite(cmax[k]) else []) for k in range(n)]
    found = []
    for pattern in itertools.product(*options):
        x = np.zeros(n)
        active = [k for k in range(n) if pattern[k] != "free"]
        free = [k for k in range(n) if pattern[k] == "free"]
        for k in active:
            x[k] = cmin[k] if pattern[k] == "lo" else cmax[k]
        if free:
            rhs = b[free] - A[np.ix_(free, active)] @ x[active]
            x[free] = np.linalg.solve(A[np.ix_(free, free)], rhs)
        w = A @ x - b
        slack = 1e-12 * (1 + np.max(np.abs(b)))
        inside = all(cmin[k] - slack <= x[k] <= cmax[k] + slack for k in free)
        signs = all((w[k] >= -slack) if pattern[k] == "lo" else (w[k] <= slack) for k in active)
        if inside and signs and all(abs(w[k]) <= slack for k in free):
            found.append((pattern, x))
    assert found, "no bound pattern satisfies the KKT conditions"
    x = found[0][1]
    for _, y in found[1:]:
        assert np.max(np.abs(y - x)) <= 1e-10, "two different KKT points of a strictly convex QP"
    return x, found[0][0]


def test_the_mixed_problem_is_a_real_test():
    """The problem exercises every kind of row at its solution: a [0, inf) row at 0 and one
    above, a [-1, 1] row at a bound and one inside, strictly complementary (|w| well away from 0
    on the active rows), and lambda = 0 does not solve it."""
    A, b, cmin, cmax = mixed_problem()
    assert np.min(np.linalg.eigvalsh(A)) >= 1.0 - 1e-12
    x, pattern = enumerate_solution(A, b, cmin, cmax)
    assert sorted(pattern[:2]) == ["free", "lo"], pattern
    assert "free" in pattern[2:4] and set(pattern[2:4]) & {"lo", "hi"}, pattern
    w = A @ x - b
    active = [k for k in range(6) if pattern[k] != "free"]
    assert np.min(np.abs(w[active])) > 1e-2, w
    assert natural_map_residual(A, b, cmin, cmax, np.zeros(6)) > 1e-3


@pytest.mark.parametrize("spec,iterations", [("siconos:enum", 10000), ("siconos:lemke", 10000),
                                             ("bullet:dantzig", 10000), ("bullet:pgs", 20000)])
def test_peer_returns_the_unique_solution(spec, iterations):
    A, b, cmin, cmax = mixed_problem()
    expected, _ = enumerate_solution(A, b, cmin, cmax)
    lam, summary = cbps.solve(A, b, cmin, cmax, spec, iterations=iterations)
    assert lam.shape == (6,)
    residual = natural_map_residual(A, b, cmin, cmax, lam)
    assert residual <= 1e-8, (spec, residual, summary["message"])
    assert np.max(np.abs(lam - expected)) <= 1e-6, (spec, lam, expected)
    # cbps's own residual is the one computed here (the same formula on the same numbers, to
    # rounding), and its verdict says solved.
    assert abs(summary["residual"] - residual) <= 1e-12 * (1 + np.max(np.abs(b)))
    assert summary["peer_said_ok"] is True, summary["peer_status"]


@pytest.mark.parametrize("spec", PEERS)
def test_summary_has_the_peer_fields(spec):
    A, b, cmin, cmax = mixed_problem()
    if spec == "siconos:avi":  # it takes no free row: the bounded rows alone
        A, b, cmin, cmax = A[:4, :4], b[:4], cmin[:4], cmax[:4]
    _, summary = cbps.solve(A, b, cmin, cmax, spec, iterations=100)
    assert isinstance(summary["peer_status"], str) and summary["peer_status"]
    assert isinstance(summary["peer_said_ok"], bool)
    it = summary["peer_iterations"]
    assert it is None or (isinstance(it, int) and it >= 0)
    for key in ("convert_time_s", "peer_solve_time_s"):
        assert isinstance(summary[key], float) and summary[key] >= 0.0, (key, summary[key])


def test_summary_peer_fields_are_none_for_cbps_methods():
    A, b, cmin, cmax = mixed_problem()
    _, summary = cbps.solve(A, b, cmin, cmax, "pgs")
    for key in ("peer_status", "peer_said_ok", "peer_iterations", "convert_time_s",
                "peer_solve_time_s"):
        assert key in summary and summary[key] is None, (key, summary.get(key))


def spd(n, seed):
    rng = np.random.default_rng(seed)
    L = rng.standard_normal((n, n))
    return L @ L.T + np.eye(n), rng.standard_normal(n)


@pytest.mark.parametrize("spec,case,reason", [
    ("siconos:enum", "25 rows", "at most 20"),
    ("bullet:dantzig", "cmin 0.5", "cmin <= 0 <= cmax"),
    ("siconos:avi", "a free row", "free"),
])
def test_refused_problem_raises_input_error(spec, case, reason):
    if case == "25 rows":
        A, b = spd(25, 1)
        cmin, cmax = np.zeros(25), np.full(25, np.inf)
    elif case == "cmin 0.5":
        A, b = spd(3, 2)
        cmin, cmax = np.array([0.0, 0.5, -1.0]), np.array([np.inf, 2.0, 1.0])
    else:
        A, b = spd(3, 3)
        cmin, cmax = np.array([0.0, -np.inf, -1.0]), np.array([np.inf, np.inf, 1.0])
    with pytest.raises(cbps.InputError) as e:
        cbps.solve(A, b, cmin, cmax, spec)
    message = str(e.value)
    assert spec in message, message
    assert reason in message, message


def chain_arrays(folder):
    """A (sparse), b, cmin, cmax of a `cbps matrices` folder, read by scipy."""
    import scipy.io
    read = lambda name: scipy.io.mmread(str(folder / name))
    vec = lambda name: np.asarray(read(name), dtype=float).ravel()
    return read("A.mtx").tocsr(), vec("b.mtx"), vec("cmin.mtx"), vec("cmax.mtx")


@pytest.fixture(scope="module")
def chain10(tmp_path_factory):
    """`cbps matrices` of a 10-link chain at step 20: every row free, so Siconos gets an MLCP of
    equalities only, on which its Lemke aborts (an assert() inside NM_gemm)."""
    folder = tmp_path_factory.mktemp("peers") / "chain"
    cli("matrices", "chain", "--param", "n=10", "--step", 20, "--out", folder)
    return folder


CHILD = """
import json, sys
import numpy as np, scipy.io
import cbps
folder = sys.argv[1]
read = lambda name: scipy.io.mmread(folder + "/" + name)
vec = lambda name: np.asarray(read(name), dtype=float).ravel()
A = read("A.mtx").tocsr()
b, cmin, cmax = vec("b.mtx"), vec("cmin.mtx"), vec("cmax.mtx")
lam, s = cbps.solve(A, b, cmin, cmax, "siconos:lemke")
print(json.dumps({"peer_status": s["peer_status"], "peer_said_ok": s["peer_said_ok"]}))
sys.stdout.flush()
after, s2 = cbps.solve(A, b, cmin, cmax, "direct", tolerance=0.0)
print(json.dumps({"after_residual": s2["residual"], "sum": sum(range(10))}))
"""


def test_siconos_abort_does_not_end_a_child_interpreter(chain10):
    """First in a child interpreter, so that an abort reaching Python fails this test with its
    exit status instead of ending pytest: the interpreter prints both lines and exits 0."""
    env = dict(os.environ)
    module_dir = os.path.dirname(os.path.abspath(cbps.__file__))
    env["PYTHONPATH"] = module_dir + os.pathsep + env.get("PYTHONPATH", "")
    r = subprocess.run([sys.executable, "-c", CHILD, str(chain10)], capture_output=True,
                       text=True, env=env, timeout=60)
    assert r.returncode == 0, (r.returncode, r.stdout, r.stderr)
    first, second = [json.loads(line) for line in r.stdout.strip().splitlines()[-2:]]
    assert "ended the process" in first["peer_status"], first
    assert first["peer_said_ok"] is False, first
    assert second["sum"] == 45, second


def test_siconos_abort_does_not_end_python(chain10):
    """The same in this interpreter: cbps.solve returns, peer_status says how Siconos' child
    process ended (signal 6, SIGABRT), cbps's residual says not solved, and Python carries on
    (the direct path then solves the same problem)."""
    A, b, cmin, cmax = chain_arrays(chain10)
    assert np.all(np.isinf(cmin)) and np.all(np.isinf(cmax))
    scale = max(1.0, np.max(np.abs(b)), abs(A).max())
    lam, summary = cbps.solve(A, b, cmin, cmax, "siconos:lemke")
    assert "ended the process" in summary["peer_status"], summary["peer_status"]
    assert "signal 6" in summary["peer_status"], summary["peer_status"]
    assert summary["peer_said_ok"] is False
    assert natural_map_residual(A, b, cmin, cmax, lam) > 1e-9 * scale
    assert summary["residual"] > 1e-9 * scale
    pid = os.getpid()
    lam2, summary2 = cbps.solve(A, b, cmin, cmax, "direct", tolerance=0.0)
    assert os.getpid() == pid
    assert natural_map_residual(A, b, cmin, cmax, lam2) <= 1e-9 * scale
