"""scripts/strict_feasibility.py: a strictly feasible velocity (u = A z - b strictly inside every
contact's dual cone K* = {mu ||u_t|| <= u_n}) where one exists by hand, none where u_n cannot be
made positive, each witness checked here against K* itself; bad input refused (exit 2)."""
import os
import subprocess
import sys

import numpy as np
import pytest
import scipy.io

import strict_feasibility as sf
from conftest import ROOT

SCRIPT = ROOT / "scripts" / "strict_feasibility.py"
DATA = ROOT / "tests" / "data" / "siconos-fc3d"


def least_margin(A, b, z, normal_rows, mu):
    """min over contacts of u_n - mu ||u_t|| at u = A z - b, written here from K*'s definition."""
    u = np.asarray(A @ z - b, dtype=float).reshape(-1)
    return min(u[k] - m * np.hypot(u[k + 1], u[k + 2]) for k, m in zip(normal_rows, mu))


def test_one_contact_whose_normal_responds_is_strictly_feasible():
    # u = (z_n, 0.5, 0): strictly inside K* (mu 0.5) once z_n > 0.25.
    A = np.diag([1.0, 0.0, 0.0])
    b = np.array([0.0, -0.5, 0.0])
    z, t, margin = sf.certificate(A, b, [0], [0.5])
    assert margin is not None and margin > 0
    assert least_margin(A, b, z, [0], [0.5]) == pytest.approx(margin)
    assert z[0] > 0.25


@pytest.mark.parametrize("A", [np.zeros((3, 3)), np.diag([0.0, 1.0, 1.0])])
def test_no_velocity_opens_a_contact_whose_normal_cannot_move(A):
    # u_n = -b_n = -1 whatever z (A's normal row is zero): no u inside K*; the program's best
    # t is u_n - mu |u_t| with u_t = 0 at best, -1.
    b = np.array([1.0, 0.0, 0.0])
    z, t, margin = sf.certificate(A, b, [0], [0.3])
    assert margin is None
    assert t == pytest.approx(-1.0)


def test_two_contacts_one_of_which_is_held_shut():
    # Contact 0 can open (its normal row responds), contact 1's normal is tied to minus
    # contact 0's (A's normal block [[1, -1], [-1, 1]]: u_n0 + u_n1 = -(b_n0 + b_n1) = -1 < 0):
    # both cannot open at once.
    A = np.zeros((6, 6))
    A[0, 0] = A[3, 3] = 1.0
    A[0, 3] = A[3, 0] = -1.0
    b = np.array([0.5, 0, 0, 0.5, 0, 0])
    z, t, margin = sf.certificate(A, b, [0, 3], [0.5, 0.5])
    assert margin is None and t == pytest.approx(-0.5)
    # With b_n1 = -1.5 the sum is +1: both open, u_n0 = u_n1 = 0.5 at best.
    b[3] = -1.5
    z, t, margin = sf.certificate(A, b, [0, 3], [0.5, 0.5])
    assert margin is not None and least_margin(A, b, z, [0, 3], [0.5, 0.5]) > 0


def test_bad_input_is_refused():
    with pytest.raises(sf.BadInput, match="not symmetric"):
        sf.certificate(np.array([[1.0, 0.1, 0], [0, 1, 0], [0, 0, 1]]), np.zeros(3), [0], [0.5])
    with pytest.raises(sf.BadInput, match="in no friction cone"):
        sf.certificate(np.eye(4), np.zeros(4), [0], [0.5])
    with pytest.raises(sf.BadInput, match="runs past"):
        sf.certificate(np.eye(3), np.zeros(3), [1], [0.5])


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True,
                          text=True, env=os.environ.copy())


def test_a_siconos_file_and_its_witness(tmp_path, cbps_module):
    """FC3D_Example1 (3 contacts, Siconos' test data): shown, and the written z checked here."""
    path = DATA / "FC3D_Example1.dat"
    witness = tmp_path / "z.mtx"
    result = run(path, "--witness", witness)
    assert result.returncode == 0, result.stderr
    assert "strictly feasible" in result.stdout
    p = cbps_module.read_problem(str(path))
    z = np.asarray(scipy.io.mmread(str(witness)), dtype=float).reshape(-1)
    assert least_margin(p.A, p.b, z, p.cones["normal_row"], p.cones["mu"]) > 0
    # The witness is never written over; a non-symmetric W (Siconos' Rover) is refused.
    again = run(path, "--witness", witness, "--json")
    assert again.returncode == 2 and "exists" in again.stderr
    rover = run(DATA / "Rover4396.dat", "--json")
    assert rover.returncode == 2 and "not symmetric" in rover.stderr


def test_an_indefinite_a_is_refused():
    # Symmetric but indefinite (eigenvalues 3 and -1 in the normal rows): no H M^-1 H^T, and
    # u = A z - b could be made anything in those rows; the theorem does not apply.
    A = np.zeros((6, 6))
    A[0, 0] = A[3, 3] = 1.0
    A[0, 3] = A[3, 0] = 2.0
    with pytest.raises(sf.BadInput, match="not positive semi-definite"):
        sf.certificate(A, np.zeros(6), [0, 3], [0.5, 0.5])
