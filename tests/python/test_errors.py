"""Bad input from Python raises cbps.InputError (a ValueError) with the message the command line
prints after 'cbps: ' for the same input (exit 2); failed computations raise
cbps.ComputationError, a diverged step cbps.DivergenceError naming step, body and row."""
import json
import shutil

import numpy as np
import pytest
import scipy.sparse as sp

import cbps
from conftest import cli, cli_error

BALL = {
    "name": "ball",
    "world": {"dt": "1/100"},
    "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1.0,
                "position": [0, 1, 0]}],
}


def write_scene(path, scene):
    path.write_text(json.dumps(scene))
    return str(path)


def test_exception_classes():
    assert issubclass(cbps.InputError, ValueError)
    assert issubclass(cbps.ComputationError, RuntimeError)
    assert issubclass(cbps.DivergenceError, cbps.ComputationError)


def test_bad_json_path_same_message_as_cli(tmp_path):
    """A JSON scene file with a bad value: the message names the file and the JSON path."""
    scene = json.loads(json.dumps(BALL))
    scene["bodies"][0]["mass"] = -1
    path = write_scene(tmp_path / "bad.json", scene)
    expected = cli_error("run", path, "--steps", 1)
    assert "/bodies/0/mass" in expected
    with pytest.raises(cbps.InputError) as e:
        cbps.load_scene(path)
    assert str(e.value) == expected


def test_bad_json_syntax_and_missing_file(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text('{"bodies": [}')
    with pytest.raises(cbps.InputError) as e:
        cbps.load_scene(str(path))
    assert str(e.value) == cli_error("run", path, "--steps", 1)
    with pytest.raises(cbps.InputError, match="nowhere.json"):
        cbps.load_scene(str(tmp_path / "nowhere.json"))


@pytest.mark.parametrize("spec", ["psor:3", "nosuch", "apgd:grow=x", "pgs:order=sideways"])
def test_bad_spec_same_message_as_cli(spec):
    """A bad --solver spec: the same words after the option's name (the CLI names --solver,
    Python the argument: method= of solve, Scene.solver)."""
    expected = cli_error("run", "chain", "--steps", 1, "--solver", spec)
    assert expected.startswith(f"--solver '{spec}'")
    tail = expected[len("--solver"):]
    with pytest.raises(cbps.InputError) as e:
        cbps.solve(sp.identity(2, format="csr"), [1, 1], [0, 0], [1, 1], spec)
    assert str(e.value) == "method" + tail
    scene = cbps.scene("chain")
    with pytest.raises(cbps.InputError) as e:
        scene.solver = spec
    assert str(e.value) == "solver" + tail


@pytest.mark.parametrize("name,params,cli_params", [
    ("nosuch", {}, []),
    ("chain", {"bogus": 1}, ["--param", "bogus=1"]),
    ("chain", {"n": -3}, ["--param", "n=-3"]),
    ("chain", {"n": "abc"}, ["--param", "n=abc"]),
    ("stack", {"friction": "sticky"}, ["--param", "friction=sticky"]),
])
def test_bad_scene_or_parameter_same_message_as_cli(name, params, cli_params):
    expected = cli_error("run", name, "--steps", 1, *cli_params)
    with pytest.raises(cbps.InputError) as e:
        cbps.scene(name, **params)
    assert str(e.value) == expected


def test_bad_stored_problem_same_message_as_cli(tmp_path):
    """A missing folder, a corrupt Matrix Market file, a bad Siconos file: as `cbps lcp` says."""
    missing = tmp_path / "missing"
    with pytest.raises(cbps.InputError) as e:
        cbps.read_problem(str(missing))
    assert str(e.value) == cli_error("lcp", missing)

    folder = tmp_path / "m"
    cli("matrices", "chain", "--param", "n=2", "--out", folder)
    (folder / "b.mtx").write_text("%%MatrixMarket matrix array real general\n2 1\n1.0\nx\n")
    with pytest.raises(cbps.InputError) as e:
        cbps.read_problem(str(folder))
    assert str(e.value) == cli_error("lcp", folder) and "b.mtx" in str(e.value)

    dat = tmp_path / "bad.dat"
    dat.write_text("2\n0\n2 2\n2 2\n1 0 0 1\n-1\n")
    with pytest.raises(cbps.InputError) as e:
        cbps.read_problem(str(dat))
    assert str(e.value) == cli_error("lcp", dat)
    with pytest.raises(cbps.InputError) as e:
        cbps.read_problem(str(dat), kind="sideways")
    assert "sideways" in str(e.value)


def test_non_symmetric_A_for_the_direct_path_same_message_as_cli(tmp_path):
    A = sp.csr_matrix(np.array([[2.0, 1.0], [0.0, 2.0]]))
    b, cmin, cmax = np.ones(2), np.zeros(2), np.full(2, np.inf)
    cbps.write_problem(str(tmp_path / "p"), A, b, cmin, cmax)
    expected = cli_error("lcp", tmp_path / "p", "--solver", "direct")
    with pytest.raises(cbps.InputError) as e:
        cbps.solve(A, b, cmin, cmax, "direct")
    # Both name the solver first ('--solver direct' against "method 'direct'"), then the same.
    assert str(e.value).split(": ", 1)[1] == expected.split(": ", 1)[1]


@pytest.mark.parametrize("args,kwargs,match", [
    ((np.ones((2, 3)), [1, 1], [0, 0], [1, 1]), {}, r"A: must be square, got 2 x 3"),
    ((np.eye(2), [1, 1, 1], [0, 0], [1, 1]), {}, r"b: has 3 entries, expected 2"),
    ((np.eye(2), [1, np.nan], [0, 0], [1, 1]), {}, r"b: entry 1 is nan"),
    ((np.eye(2), [1, 1], [0, np.nan], [1, 1]), {}, r"cmin: entry 1 is nan"),
    ((np.eye(2), [1, 1], [0, 2], [1, 1]), {}, r"cmin, cmax: row 1: \[2, 1\]"),
    ((np.eye(2), [1, 1], [0, 0], [1, 1]), {"lam0": [0]}, r"lam0: has 1 entries"),
    ((np.eye(2), [[1, 1], [1, 1]], [0, 0], [1, 1]), {}, r"b: expected a vector"),
    ((np.array([[np.inf, 0], [0, 1]]), [1, 1], [0, 0], [1, 1]), {}, r"A: entry \(0, 0\) is inf"),
    ((np.array([[0.0, 0], [0, 1]]), [1, 1], [0, 0], [1, 1]), {}, r"A\[0,0\] = 0"),
    ((np.eye(2), [1, 1], [0, 0], [1, 1], "matrix-free"), {}, r"pass J= and Minv="),
    ((np.eye(2), [1, 1], [0, 0], [1, 1], "shock"), {}, r"pass J= and Minv="),
    ((np.eye(2), [1, 1], [0, 0], [1, 1], "pgs:contacts_first=on"), {}, r"pass kinds="),
    ((np.eye(2), [1, 1], [0, 0], [1, 1]), {"iterations": 0}, r"iterations 0"),
    ((np.eye(2), [1, 1], [0, 0], [1, 1]), {"tolerance": -1}, r"tolerance -1"),
    ((np.eye(2), [1, 1], [0, 0], [1, 1]), {"J": np.eye(2)}, r"J, Minv: give both"),
    ((np.eye(2), [1, 1], [0, 0], [1, 1]), {"kinds": ["distance", "rope"]}, r"kinds: entry 1"),
    ((np.eye(2), [1, 1], [0, 0], [1, 1]), {"blocks": [0]}, r"blocks: has 1 entries"),
    (("not a matrix", [1], [0], [1]), {}, r"A: not a matrix of numbers"),
])
def test_bad_solve_input(args, kwargs, match):
    with pytest.raises(cbps.InputError, match=match):
        cbps.solve(*args, **kwargs)


def test_bad_simulation_use():
    sim = cbps.Simulation(cbps.scene("chain", n=2))
    with pytest.raises(cbps.InputError, match="no step has been done yet"):
        sim.system()
    with pytest.raises(cbps.InputError, match="duration or steps, not both"):
        sim.run(duration=1.0, steps=3)
    with pytest.raises(cbps.InputError, match="shorter than half a step"):
        sim.run(duration=1e-6)
    with pytest.raises(cbps.InputError, match="record_every 0"):
        sim.run(steps=2, record_every=0)
    scene = cbps.scene("chain")
    for attribute, value, match in [("dt", 0.0, "dt 0"), ("beta", 2.0, "beta 2"),
                                    ("push", "sideways", "push 'sideways'"),
                                    ("iterations", 0, "iterations 0"), ("cfm", -1.0, "cfm -1")]:
        with pytest.raises(cbps.InputError, match=match):
            setattr(scene, attribute, value)


def test_divergence_error_names_step_body_row(tmp_path):
    """A ball falling freely against a divergence speed of 0.5 m/s: v after step k is g dt (k+1)
    (semi-implicit Euler), which exceeds 0.5 m/s at step k = 5 (0.589 m/s, dt = 0.01 s); the
    simulation stays at 5 steps done, and the message is the one `cbps run` prints."""
    scene = json.loads(json.dumps(BALL))
    scene["world"]["divergence_speed"] = 0.5
    path = write_scene(tmp_path / "fast.json", scene)
    sim = cbps.Simulation(cbps.load_scene(path))
    with pytest.raises(cbps.DivergenceError) as e:
        sim.run(steps=100)
    assert e.value.step == 5 and e.value.body == 0 and e.value.row == -1
    assert sim.steps_done == 5
    result = cli("run", path, "--steps", 100, check=False)
    assert result.returncode == 1
    assert str(e.value) in result.stderr


def test_writers_refuse_to_replace_without_force(tmp_path):
    path = tmp_path / "scene.json"
    scene = cbps.scene("chain", n=2)
    scene.save(str(path))
    with pytest.raises(cbps.InputError, match="exists; refusing to overwrite"):
        scene.save(str(path))
    scene.save(str(path), force=True)
    with pytest.raises(cbps.InputError, match="does not exist"):
        scene.save(str(tmp_path / "no" / "scene.json"))
    with pytest.raises(cbps.InputError, match="exists; refusing"):
        cbps.write_matrix_market(str(path), np.ones(2))
    with pytest.raises(cbps.InputError, match="relay problem's bounds must be finite"):
        cbps.write_siconos(str(tmp_path / "r.dat"), np.eye(2), [1, 1], [0, -np.inf], [1, 1])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.json"]  # no temporary left
