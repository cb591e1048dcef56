"""Stored problems written from Python are read by the command line (and scipy) as written, and
read back bit for bit; verify() is `cbps verify`."""
import pathlib

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

import cbps
from cbps_problem import cone_natural_maps
from conftest import cli_json


@pytest.fixture(scope="module")
def system():
    sim = cbps.Simulation(cbps.scene("v-corner"))
    for _ in range(5):
        sim.step()
    return sim.system()


def test_write_problem_is_what_cbps_lcp_reads(tmp_path, system):
    """A step's system written by write_problem (with J, Minv, v1, fext, dt) is read back bit for
    bit, by read_problem and by scipy, and `cbps lcp` finds the step's lambda in it."""
    s = system
    folder = tmp_path / "p"
    cbps.write_problem(str(folder), s.A, s.b, s.cmin, s.cmax, J=s.J, Minv=s.Minv, v1=s.v1,
                       fext=s.fext, dt=s.dt)
    p = cbps.read_problem(str(folder))
    assert (p.A != s.A).nnz == 0 and (p.J != s.J).nnz == 0 and (p.Minv != s.Minv).nnz == 0
    for name in ("b", "cmin", "cmax", "v1", "fext"):
        assert np.array_equal(getattr(p, name), getattr(s, name)), name
    assert p.dt == s.dt and p.cfm == 0.0
    assert np.array_equal(scipy.io.mmread(str(folder / "b.mtx")).ravel(), s.b)
    result = cli_json("lcp", folder, "--json")
    assert result["status"] == "solved"
    # The step's PGS lambda and the exact one agree to the step's tolerance (1e-10 N residual on
    # a definite 2x2 A: lambda to about 1e-9 N).
    np.testing.assert_allclose(np.array(result["lambda"], dtype=float), s.lam, atol=1e-8)
    cbps.write_problem(str(folder), s.A, s.b, s.cmin, s.cmax, cfm=1e-6, force=True)
    assert cbps.read_problem(str(folder)).cfm == 1e-6


def test_siconos_round_trip_and_cli(tmp_path):
    """An LCP and a relay problem written as Siconos files read back bit for bit (M's lines are
    its columns: a non-symmetric M shows the order), and `cbps lcp` solves them as Python does."""
    M = np.array([[2.0, 1.0, 0.0], [0.5, 3.0, 1.0], [0.0, 1.0, 4.0]])
    b = np.array([1.0, -2.0, 3.0])
    path = tmp_path / "lcp.dat"
    cbps.write_siconos(str(path), M, b)
    p = cbps.read_siconos(str(path))
    np.testing.assert_array_equal(p.A.toarray(), M)
    np.testing.assert_array_equal(p.b, b)
    assert np.all(p.cmin == 0) and np.all(p.cmax == np.inf)
    lam, s = cbps.solve(p.A, p.b, p.cmin, p.cmax, "lemke")
    result = cli_json("lcp", path, "--json")
    assert result["status"] == "solved"
    np.testing.assert_array_equal(lam, np.array(result["lambda"], dtype=float))
    relay = tmp_path / "relay.dat"
    cbps.write_siconos(str(relay), M, b, [-1, -1, -1], [1, 0.5, 1])
    r = cbps.read_siconos(str(relay), kind="relay")
    np.testing.assert_array_equal(r.cmin, [-1, -1, -1])
    np.testing.assert_array_equal(r.cmax, [1, 0.5, 1])
    assert cli_json("lcp", relay, "--json")["status"] == "solved"


def test_matrix_market_round_trip(tmp_path):
    M = sp.random(7, 5, density=0.4, random_state=3, format="csr")
    v = np.array([1.0, -np.inf, np.inf, 1e-300, -0.1])
    cbps.write_matrix_market(str(tmp_path / "M.mtx"), M, "a comment")
    cbps.write_matrix_market(str(tmp_path / "v.mtx"), v)
    back = cbps.read_matrix_market_sparse(str(tmp_path / "M.mtx"))
    assert back.shape == (7, 5) and (back != M).nnz == 0
    assert (scipy.io.mmread(str(tmp_path / "M.mtx")).tocsr() != M).nnz == 0
    np.testing.assert_array_equal(cbps.read_matrix_market_vector(str(tmp_path / "v.mtx")), v)


def test_verify_is_cbps_verify():
    checks = cbps.verify()
    expected = cli_json("verify", "--json")
    assert [c["equation"] for c in checks] == [c["equation"] for c in expected]
    assert [c["what"] for c in checks] == [c["what"] for c in expected]
    assert all(c["pass"] for c in checks)


def test_siconos_frictional_contact_dump_read_and_solved():
    """Siconos' own dump of a rover's two contacts (W not symmetric) reads as `cbps lcp` reads it,
    its contacts in Coulomb's cone, and direct meets the law on the true W (the natural map of
    each contact, computed here from lambda alone)."""
    path = pathlib.Path(__file__).resolve().parents[1] / "data" / "siconos-fc3d" / "Rover4396.dat"
    p = cbps.read_problem(str(path), kind="fc3d")
    A = p.A.toarray()
    assert np.abs(A - A.T).max() > 1e-6
    assert p.cones["law"] == "coulomb"
    assert list(p.cones["normal_row"]) == [0, 3]
    lam, s = cbps.solve(p.A, p.b, p.cmin, p.cmax, "direct", cones=p.cones)
    assert s["termination"] == "direct solve"
    # Coulomb's natural map of each contact, written in numpy (scripts/cbps_problem.py).
    maps = cone_natural_maps(lam, A @ lam - p.b, p.cones["normal_row"], p.cones["mu"], "coulomb")
    assert np.max(maps) <= 1e-9
    # cbps's verdict on it, as `cbps lcp` gives it.
    assert s["solved"] and s["unit_free"]["relative"] <= 1e-9
    assert cli_json("lcp", path, "--json")["status"] == "solved"
