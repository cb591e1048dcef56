"""A step's system read from Python against the paper's formulas computed here with scipy:
A = J Minv J^T and b = upsilon/dt - J (v1/dt + Minv fext) (6.2.9), v2 = v1 + dt Minv (J^T lam +
fext) (12.3.1), Minv from the bodies' masses (6.1.2), and lam a solution of the boxed problem
(6.2) by its natural-map residual."""
import numpy as np
import pytest
import scipy.sparse as sp

import cbps
from conftest import cli_json, cone_natural_maps, natural_map_residual

# Distance rows (chain, pendulum wave), contacts (v-corner), contacts with friction and the
# improved push (stack), Coulomb friction (stack, friction=coulomb: the bounds move with lam).
CASES = [
    ("chain", {"n": 5}, 10),
    ("pendulum-wave", {"n": 4}, 3),
    ("v-corner", {}, 2),
    ("stack", {"n": 3}, 5),
    ("stack", {"n": 2, "friction": "coulomb"}, 5),
]


def step_system(name, params, steps):
    sim = cbps.Simulation(cbps.scene(name, **params))
    for _ in range(steps):
        sim.step()
    return sim, sim.system()


@pytest.mark.parametrize("name,params,steps", CASES)
def test_A_is_J_Minv_JT_and_b_is_its_formula(name, params, steps):
    """A = J Minv J^T and b = upsilon/dt - J (v1/dt + Minv fext) (6.2.9), computed in Python."""
    _, s = step_system(name, params, steps)
    J, Minv = s.J, s.Minv
    assert sp.isspmatrix_csr(J) and sp.isspmatrix_csr(Minv) and sp.isspmatrix_csr(s.A)
    c, n6 = J.shape
    assert c > 0 and Minv.shape == (n6, n6) and s.A.shape == (c, c)
    for v in (s.b, s.upsilon, s.cmin, s.cmax, s.lam):
        assert v.shape == (c,)
    for v in (s.v1, s.fext, s.v2):
        assert v.shape == (n6,)
    A = (J @ Minv @ J.T).toarray()
    scale = np.max(np.abs(A))
    # Sums of a few products of the same numbers: round-off of a few ulps of the largest entry.
    assert np.max(np.abs(s.A.toarray() - A)) <= 1e-13 * scale
    b = s.upsilon / s.dt - J @ (s.v1 / s.dt + Minv @ s.fext)
    assert np.max(np.abs(s.b - b)) <= 1e-12 * max(1.0, np.max(np.abs(b)))
    # v2 of the step (12.3.1).
    v2 = s.v1 + s.dt * (Minv @ (J.T @ s.lam + s.fext))
    assert np.max(np.abs(s.v2 - v2)) <= 1e-12 * max(1.0, np.max(np.abs(v2)))


@pytest.mark.parametrize("name,params,steps", CASES)
def test_lam_solves_the_boxed_problem(name, params, steps):
    """The step's lam solves (A, b, cmin, cmax) (6.2): the natural-map residual computed here is
    as small as the step's tolerance allows (the scene's PGS: 1e-10 N or its sweep limit)."""
    _, s = step_system(name, params, steps)
    r = natural_map_residual(s.A, s.b, s.cmin, s.cmax, s.lam)
    report = s.report
    assert report is not None and report["rows"] == len(s.b)
    # The step's own residual is the same quantity (up to the last sweep's round-off).
    assert r == pytest.approx(report["residual"], rel=1e-6, abs=1e-12)
    assert np.all(s.lam >= s.cmin - 1e-12) and np.all(s.lam <= s.cmax + 1e-12)


def test_Minv_holds_the_bodies_masses():
    """Minv's linear blocks are 1/m of each movable body (6.1.2), in the order of the labels."""
    scene = cbps.scene("chain", n=4, mass_ratio=100)
    sim = cbps.Simulation(scene)
    sim.step()
    s = sim.system()
    masses = {b["name"]: b["mass"] for b in scene.bodies if not b["static"]}
    diag = s.Minv.diagonal()
    for col, label in enumerate(s.column_labels):
        body, coord = label.rsplit(".", 1)
        if coord in ("vx", "vy", "vz"):
            assert diag[col] == pytest.approx(1.0 / masses[body], rel=1e-15)
    assert len(s.column_labels) == 6 * len(masses) == s.J.shape[1]
    assert s.kind == ["distance"] * 4 and len(s.row_labels) == 4


def test_system_is_a_copy_kept_from_its_step():
    """system() is the last step's, unchanged by later steps; build_system() the next, unsolved."""
    sim, s = step_system("chain", {"n": 3}, 5)
    assert s.step == 4
    b_before = s.b.copy()
    sim.step()
    assert np.array_equal(s.b, b_before)
    later = sim.system()
    assert later.step == 5 and not np.array_equal(later.b, b_before)
    unsolved = sim.build_system()
    assert unsolved.lam is None and unsolved.v2 is None and unsolved.report is None
    assert unsolved.step == 6


def test_coulomb_bounds_are_the_ones_lam_satisfies():
    """With Coulomb friction the friction rows' bounds are -+mu lam_n of the step's lam (5.4), as
    `cbps explain` and `cbps matrices` show them."""
    _, s = step_system("stack", {"n": 2, "friction": "coulomb", "mu": 0.5}, 5)
    friction = [k for k, kind in enumerate(s.kind) if kind == "friction"]
    assert friction
    assert np.all(np.isfinite(s.cmax[friction]))
    assert np.all(s.cmin[friction] == -s.cmax[friction])


def test_v_corner_at_rest_matches_the_appendix():
    """v-corner (12.2): lam_1 = m g sin(phi_r)/sin(phi_l + phi_r), lam_2 = m g sin(phi_l)/
    sin(phi_l + phi_r) once the sphere rests; each row's J is its plane's normal."""
    sim = cbps.Simulation(cbps.scene("v-corner"))
    for _ in range(30):
        sim.step()
    s = sim.system()
    m, g = 1.0, 9.81
    phi_l, phi_r = np.radians(45.0), np.radians(30.0)
    expected = {"left": m * g * np.sin(phi_r) / np.sin(phi_l + phi_r),
                "right": m * g * np.sin(phi_l) / np.sin(phi_l + phi_r)}
    normal = {"left": np.array([np.sin(phi_l), np.cos(phi_l), 0.0]),
              "right": np.array([-np.sin(phi_r), np.cos(phi_r), 0.0])}
    J = s.J.toarray()
    seen = set()
    for k, label in enumerate(s.row_labels):
        plane = "left" if "left" in label else "right"
        seen.add(plane)
        # lam is a force over the step (N); at rest it carries the weight.
        assert s.lam[k] == pytest.approx(expected[plane], rel=1e-6)
        np.testing.assert_allclose(J[k, :3], normal[plane], atol=1e-12)
    assert seen == {"left", "right"}


@pytest.mark.parametrize("name,params,steps", [("chain", {"n": 3}, 10),
                                               ("stack", {"n": 2, "friction": "coulomb"}, 4)])
def test_system_equals_cbps_explain(name, params, steps):
    """After k steps, system() is the system `cbps explain SCENE --step k-1 --json` shows: the
    same J, A, b, bounds, labels and, solved the same way from the same warm start, the same lam
    and v2, bit for bit."""
    _, s = step_system(name, params, steps)
    cli_params = [arg for key, value in params.items() for arg in ("--param", f"{key}={value}")]
    e = cli_json("explain", name, *cli_params, "--step", steps - 1, "--json")
    assert e["row_labels"] == s.row_labels and e["column_labels"] == s.column_labels
    np.testing.assert_array_equal(np.array(e["J"]["value"], dtype=float), s.J.toarray())
    np.testing.assert_array_equal(np.array(e["A"]["value"], dtype=float), s.A.toarray())
    for key, value in (("b", s.b), ("cmin", s.cmin), ("cmax", s.cmax), ("lambda", s.lam),
                       ("v2", s.v2), ("upsilon", s.upsilon)):
        np.testing.assert_array_equal(np.array(e[key]["value"], dtype=float), value, err_msg=key)
    assert e["dt"] == s.dt


def cone_natural_map(lam, w, cones):
    """max over contacts of |r - P_K(r - u^)| (docs/cones.md), in numpy (scripts/cbps_problem.py)."""
    return max(cone_natural_maps(lam, w, cones["normal_row"], cones["mu"], cones["law"]))


@pytest.mark.parametrize("law", ["coulomb", "ccp"])
def test_cone_system_and_solve_with_cones(law):
    """friction=cone: System.cones names each contact's three rows and mu; the step's lam meets
    the cone law (its natural map computed here), and solve(..., cones=) finds it again."""
    scene = cbps.scene("stack", n=2, mu=0.5, friction="cone", cone=law)
    scene.solver = "direct"
    sim = cbps.Simulation(scene)
    for _ in range(4):
        sim.step()
    s = sim.system()
    cones = s.cones
    assert cones["law"] == law and len(cones["normal_row"]) > 0
    assert np.all(cones["mu"] == 0.5)
    for n in cones["normal_row"]:
        assert s.kind[n:n + 3] == ["contact", "friction", "friction"]
    assert cone_natural_map(s.lam, s.A @ s.lam - s.b, cones) <= 1e-9
    for method in ("direct", "nsgs"):
        lam, summary = cbps.solve(s.A, s.b, s.cmin, s.cmax, method, cones=cones,
                                  iterations=100000)
        assert summary["residual"] <= 1e-9
        assert cone_natural_map(lam, s.A @ lam - s.b, cones) <= 1e-9
    # The boxed problem's methods refuse the cones; a malformed cones= is named.
    with pytest.raises(cbps.InputError, match="nsgs and direct"):
        cbps.solve(s.A, s.b, s.cmin, s.cmax, "pgs", cones=cones)
    with pytest.raises(cbps.InputError, match="cones: contact 1: normal row 1 is not after the rows of contact 0"):
        bad = dict(cones, normal_row=[0, 1] + list(cones["normal_row"][2:]))
        cbps.solve(s.A, s.b, s.cmin, s.cmax, "nsgs", cones=bad)
    assert cbps.Simulation(cbps.scene("stack", n=2)).build_system().cones is None


def test_step_reports_the_friction_its_system_solved():
    # A stack of two boxes at mu = 0.25 under the relaxation: every contact point found gets
    # friction rows in the cone, so the step's friction contacts are its contact points.
    sim = cbps.Simulation(cbps.scene("stack", n=2, mu=0.25, friction="cone", cone="ccp"))
    r = sim.step()
    assert r["contacts"] > 0
    assert r["friction_contacts"] == r["contacts"]
    assert r["mu_min"] == r["mu_max"] == 0.25
    assert r["friction_law"] == "cone ccp"
    bare = cbps.Simulation(cbps.scene("stack", n=2, mu=0)).step()
    assert bare["friction_contacts"] == 0 and bare["friction_law"] is None and bare["mu_min"] is None
