"""Scenes from Python as the command line has them (`cbps scenes --json`, `--export`), and a
run's trajectory against `cbps run`'s trajectory.csv and against free fall computed by hand."""
import csv
import json

import numpy as np
import pytest

import cbps
from conftest import cli, cli_json


def test_scenes_list_as_cli():
    assert cbps.scenes() == cli_json("scenes", "--json")


def test_scene_json_as_cli_export(tmp_path):
    """scene('chain', n=3, mass_ratio=2.5).to_json() is what `cbps scenes chain --param n=3
    --param mass_ratio=2.5 --export FILE` writes; save() writes the same, load_scene reads it."""
    exported = tmp_path / "cli.json"
    cli("scenes", "chain", "--param", "n=3", "--param", "mass_ratio=2.5", "--export", exported)
    scene = cbps.scene("chain", n=3, mass_ratio=2.5)
    assert scene.to_json() == exported.read_text()
    saved = tmp_path / "py.json"
    scene.save(str(saved))
    assert saved.read_text() == exported.read_text()
    again = cbps.load_scene(str(saved))
    assert again.to_json() == scene.to_json()
    assert cbps.parse_scene(scene.to_json()).to_json() == scene.to_json()
    assert scene.parameters["n"] == "3" and scene.parameters["mass_ratio"] == "2.5"
    assert len(scene.bodies) == 3


def test_settings_as_the_step_options():
    scene = cbps.scene("chain")
    scene.solver = "psor:1.3"
    assert scene.solver == "pgs" and scene.relaxation == 1.3
    scene.dt = 1 / 120
    scene.push = "improved"
    scene.integrator = "midpoint"
    scene.iterations = 7
    scene.gravity = [0, -1.62, 0]
    text = json.loads(scene.to_json())
    assert text["solver"]["iterations"] == 7 and text["world"]["push"] == "improved"
    assert scene.integrator == "midpoint" and text["world"]["integrator"] == "midpoint"
    assert text["world"]["gravity"] == [0, -1.62, 0]
    sim = cbps.Simulation(scene)
    report = sim.step()
    assert report["iterations"] <= 7
    assert sim.time == pytest.approx(1 / 120, rel=1e-15)
    assert sim.stages()[-1].startswith("integrate")


def test_solver_settings_as_the_scene_file():
    """Every /solver setting is a property of its own name, written as a scene file writes it
    and checked as a scene file checks it (relaxation's range by method, contacts_first)."""
    scene = cbps.scene("chain")
    assert (scene.method, scene.order, scene.split_islands, scene.contacts_first) == (
        "pgs", "natural", True, False)
    assert scene.warm_friction == scene.warm == 1.0  # follows warm until given
    assert "warm_friction" not in json.loads(scene.to_json())["solver"]
    scene.relaxation = 1.5
    with pytest.raises(cbps.InputError, match=r"method 'jacobi': takes a relaxation in \(0, 1\]"):
        scene.method = "jacobi"
    scene.order, scene.contacts_first, scene.warm_friction = "random", True, 0.0
    scene.delta_tolerance, scene.seed = 1e-6, 12
    scene.relaxation = 1.0
    with pytest.raises(cbps.InputError, match="method 'direct': takes no contacts_first"):
        scene.method = "direct"
    scene.contacts_first = False
    scene.method = "direct"
    with pytest.raises(cbps.InputError, match="contacts_first True: applies to the methods pgs"):
        scene.contacts_first = True
    scene.method = "pgs"
    scene.contacts_first = True
    with pytest.raises(cbps.InputError, match="split_islands 1: expected True or False"):
        scene.split_islands = 1
    solver = json.loads(scene.to_json())["solver"]
    assert solver["order"] == "random" and solver["contacts_first"] is True
    assert solver["warm_friction"] == 0.0 and solver["delta_tolerance"] == 1e-6
    assert solver["seed"] == 12 and solver["method"] == "pgs"


def test_scheme_substeps_as_the_command_line(tmp_path):
    """scene.scheme and scene.substeps are --scheme and --substeps: the same scene file, and
    a run of 30 steps ends where `cbps run` ends."""
    scene = cbps.scene("stack", n=3)
    assert scene.scheme == "paper" and scene.substeps == 1
    scene.scheme = "soft-step"
    assert scene.substeps == 4  # a substepping scheme named: its default
    scene.substeps = 3
    scene.iterations = 1
    text = json.loads(scene.to_json())
    assert text["world"]["scheme"] == "soft-step" and text["world"]["substeps"] == 3
    exported = tmp_path / "cli.json"
    cli("scenes", "stack", "--param", "n=3", "--export", exported)
    out = tmp_path / "run"
    cli("run", exported, "--scheme", "soft-step", "--substeps", "3", "--iterations", "1",
        "--steps", "30", "--quiet", "--out", out)
    sim = cbps.Simulation(scene)
    for _ in range(30):
        sim.step()
    assert any(stage.startswith("soft-step substep (x3)") for stage in sim.stages())
    rows = read_trajectory(out / "trajectory.csv")
    last = {r["body"]: r for r in rows if float(r["t"]) == pytest.approx(30 * scene.dt)}
    for k, body in enumerate(sim.bodies()):
        got = np.array([float(last[str(k)][c]) for c in "xyz"])
        np.testing.assert_allclose(got, body["x"], rtol=1e-10, atol=1e-12)


def read_trajectory(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return rows


def test_run_trajectory_equals_cbps_run(tmp_path):
    """run(steps=48, record_every=4) against `cbps run chain --steps 48 --record-every 4`:
    positions, orientations and velocities agree to the CSV's 12 significant digits."""
    out = tmp_path / "run"
    cli("run", "chain", "--param", "n=3", "--steps", 48, "--record-every", 4, "--no-timing",
        "--out", out)
    rows = read_trajectory(out / "trajectory.csv")
    sim = cbps.Simulation(cbps.scene("chain", n=3))
    traj = sim.run(steps=48, record_every=4)
    k, n = 13, 3  # t = 0 and after steps 4, 8, ..., 48; three links
    assert traj["t"].shape == (k,) and traj["x"].shape == (k, n, 3) and traj["q"].shape == (k, n, 4)
    assert len(rows) == k * n
    for row in rows:
        i, body = divmod(rows.index(row), n)
        assert int(row["body"]) == body
        assert traj["t"][i] == pytest.approx(float(row["t"]), rel=1e-11, abs=1e-15)
        for key, values in (("x", ("x", "y", "z")), ("q", ("qw", "qx", "qy", "qz")),
                            ("v", ("vx", "vy", "vz")), ("omega", ("wx", "wy", "wz"))):
            expected = [float(row[c]) for c in values]
            np.testing.assert_allclose(traj[key][i, body], expected, rtol=1e-10, atol=1e-12)
    steps = traj["steps"]
    assert steps["t"].shape == (48,) and np.all(steps["rows"] == 3)
    assert steps["energy"][-1] == pytest.approx(sim.energy(), rel=1e-15)
    assert sim.system().step == 47


def test_free_fall_by_hand():
    """One ball and no constraint: semi-implicit Euler (3.2) gives v_k = -g dt k and
    y_k = y_0 - g dt^2 k (k + 1) / 2 after k steps, exactly up to round-off."""
    scene = cbps.parse_scene(json.dumps({
        "name": "fall", "world": {"dt": "1/100"},
        "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "mass": 2.0,
                    "position": [0, 10, 0]}]}))
    sim = cbps.Simulation(scene)
    traj = sim.run(0.5)  # duration 0.5 s: 50 steps
    g, dt = 9.81, 0.01
    k = np.arange(51)
    np.testing.assert_allclose(traj["t"], k * dt, rtol=1e-14)
    np.testing.assert_allclose(traj["v"][:, 0, 1], -g * dt * k, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(traj["x"][:, 0, 1], 10 - g * dt**2 * k * (k + 1) / 2, rtol=1e-12)
    body = sim.bodies()[0]
    assert body["name"] == "ball" and body["mass"] == 2.0
    np.testing.assert_array_equal(body["x"], traj["x"][-1, 0])


def test_run_reports_the_direct_routes_as_cbps_run(tmp_path):
    """The direct path's route per step in sim.run's steps equals `cbps run`'s steps.csv
    direct_route: on the base-8 pyramid the first step has no guess (the interior point) and
    every later one starts from the last step's answer (guess or warm); under PGS it is empty."""
    out = tmp_path / "run"
    cli("run", "pyramid", "--param", "base=8", "--param", "push=original", "--steps", 10,
        "--solver", "direct", "--out", out)
    with open(out / "steps.csv", newline="", encoding="utf-8") as f:
        expected = [row["direct_route"] for row in csv.DictReader(f)]
    scene = cbps.scene("pyramid", base=8, push="original")
    scene.solver = "direct"
    steps = cbps.Simulation(scene).run(steps=10)["steps"]
    assert steps["direct_route"] == expected
    assert expected[0] == "interior" and set(expected[1:]) <= {"guess", "warm"}
    assert steps["solve_time_s"].shape == (10,) and np.all(steps["solve_time_s"] >= 0)
    pgs = cbps.Simulation(cbps.scene("pyramid", base=8)).run(steps=2)["steps"]
    assert pgs["direct_route"] == ["", ""]
