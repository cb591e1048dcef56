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
                                    ("integrator", "verlet", "integrator 'verlet'"),
                                    ("scheme", "verlet", "scheme 'verlet'"),
                                    ("substeps", 4, "substeps 4: needs a scheme that substeps"),
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


INT_MAX = 2**31 - 1
WHOLE = "must be a whole number from"


@pytest.mark.parametrize("kwargs,message", [
    ({"iterations": 2**40}, f"iterations 1099511627776: {WHOLE} 1 to {INT_MAX}"),
    ({"iterations": 10.5}, f"iterations 10.5: {WHOLE} 1 to {INT_MAX}"),
    ({"iterations": 0}, f"iterations 0: {WHOLE} 1 to {INT_MAX}"),
    ({"iterations": float("nan")}, f"iterations nan: {WHOLE} 1 to {INT_MAX}"),
    ({"iterations": "ten"}, f"iterations 'ten': {WHOLE} 1 to {INT_MAX}"),
    ({"iterations": True}, f"iterations True: {WHOLE} 1 to {INT_MAX}"),
    ({"iterations": 10**5000}, f"iterations \\(an integer of 16610 bits\\): {WHOLE} 1 to"),
    ({"seed": -1}, f"seed -1: {WHOLE} 0 to 18446744073709551615"),
    ({"seed": 2**64}, f"seed 18446744073709551616: {WHOLE} 0 to 18446744073709551615"),
    ({"seed": 0.5}, f"seed 0.5: {WHOLE} 0 to"),
    ({"history_limit": 1}, f"history_limit 1: {WHOLE} 2 to {INT_MAX}"),
    ({"history_limit": 2**31}, f"history_limit 2147483648: {WHOLE} 2 to {INT_MAX}"),
    ({"tolerance": -1}, "tolerance -1: must be a finite number >= 0"),
    ({"tolerance": float("inf")}, "tolerance inf: must be a finite number >= 0"),
    ({"tolerance": "tight"}, "tolerance 'tight': not a number"),
    ({"tolerance": 10**400}, "tolerance \\(an integer of 1329 bits\\): too large for a double"),
    ({"delta_tolerance": float("nan")}, "delta_tolerance nan: must be a finite number >= 0"),
    ({"delta_tolerance": None}, "delta_tolerance None: not a number"),
    ({"cfm": -1e-9}, "cfm -1e-09: must be a finite number >= 0"),
    ({"cfm": [0.1]}, r"cfm \[0.1\]: not a number"),
    ({"blocks": [0, 2**40]}, f"blocks: entry 1 1099511627776: {WHOLE} -2147483648 to {INT_MAX}"),
    ({"blocks": [0.5, 0]}, f"blocks: entry 0 0.5: {WHOLE} -2147483648 to {INT_MAX}"),
])
def test_solve_numbers_out_of_range(kwargs, message):
    """Every numeric keyword of solve(): a number out of range or not a number at all is
    InputError naming the argument, its value and the range, never pybind11's TypeError."""
    with pytest.raises(cbps.InputError, match=message):
        cbps.solve(np.eye(2), [1, 1], [0, 0], [1, 1], "block-pgs" if "blocks" in kwargs else "pgs",
                   **kwargs)


def test_solve_takes_whole_numbers_in_any_form():
    """A whole number may come as a float without a fraction (1e3) or a numpy integer; the
    ranges' ends are taken. A = I, b = 1 in [0, 1]: lambda = 1; with cfm 0.5 (A + 0.5 I)
    lambda = 1 / 1.5."""
    args = (np.eye(2), [1, 1], [0, 0], [1, 1])
    for kwargs in ({"iterations": 1e3}, {"iterations": np.int64(7)}, {"iterations": INT_MAX},
                   {"seed": 2**64 - 1}, {"seed": np.uint64(2**64 - 1)}, {"history_limit": 2},
                   {"tolerance": 0}, {"cfm": np.float32(0.5)}):
        lam, s = cbps.solve(*args, **kwargs)
        expected = 1 / 1.5 if "cfm" in kwargs else 1.0
        np.testing.assert_allclose(lam, [expected] * 2, rtol=1e-12, err_msg=str(kwargs))
    lam, s = cbps.solve(*args, "block-pgs", blocks=np.array([-1, 7], dtype=np.int16))
    np.testing.assert_allclose(lam, [1, 1])


@pytest.mark.parametrize("attribute,value,message", [
    ("iterations", 2**40, f"iterations 1099511627776: {WHOLE} 1 to {INT_MAX}"),
    ("iterations", 10.5, f"iterations 10.5: {WHOLE} 1 to {INT_MAX}"),
    ("seed", -1, f"seed -1: {WHOLE} 0 to 9007199254740992"),
    ("seed", 2**64, f"seed 18446744073709551616: {WHOLE} 0 to"),
    ("dt", "1/240", "dt '1/240': not a number"),
    ("dt", -0.01, "dt -0.01: must be > 0"),
    ("duration", float("inf"), "duration inf: must be a positive finite time in s"),
    ("beta", None, "beta None: not a number"),
    ("beta", float("nan"), "beta nan: not a finite number"),
    ("beta", 1.5, r"beta 1.5: must be in \[0, 1\]"),
    ("tolerance", 10**400, "tolerance \\(an integer of 1329 bits\\): too large"),
    ("cfm", "0.1", "cfm '0.1': not a number"),
])
def test_scene_numbers_out_of_range(attribute, value, message):
    scene = cbps.scene("chain")
    with pytest.raises(cbps.InputError, match=message):
        setattr(scene, attribute, value)
    scene.iterations, scene.seed, scene.dt = 5.0, 2**53, 1  # whole floats, the ends, ints
    assert (scene.iterations, scene.seed, scene.dt) == (5, 2**53, 1.0)


@pytest.mark.parametrize("params,message", [
    ({"n": 10.5}, "parameter 'n': expected an integer"),
    ({"n": 2**70}, r"parameter 'n': must be in \[1, 1e\+07\]"),
    ({"n": -1}, r"parameter 'n': must be in \[1, 1e\+07\]"),
    ({"mass_ratio": float("nan")}, "parameter 'mass_ratio': expected a finite number"),
    ({"mass_ratio": float("inf")}, "parameter 'mass_ratio': expected a finite number"),
])
def test_scene_parameters_out_of_range(params, message):
    """cbps.scene()'s keywords are checked by the scene's own parameter ranges, as --param."""
    with pytest.raises(cbps.InputError, match=message):
        cbps.scene("chain", **params)


@pytest.mark.parametrize("kwargs,message", [
    ({"steps": 2**70}, f"run: steps 1180591620717411303424: {WHOLE} 0 to 1000000000000"),
    ({"steps": 1.5}, f"run: steps 1.5: {WHOLE} 0 to 1000000000000"),
    ({"steps": -1}, f"run: steps -1: {WHOLE} 0 to"),
    ({"steps": 1, "record_every": 2**70}, f"run: record_every 1180591620717411303424: {WHOLE} 1"),
    ({"steps": 1, "record_every": 0.5}, f"run: record_every 0.5: {WHOLE} 1 to"),
    ({"duration": "1 s"}, "run: duration '1 s': not a number"),
    ({"duration": 10**400}, "run: duration \\(an integer of 1329 bits\\): too large"),
    ({"duration": float("nan")}, "run: duration nan s: must be a positive finite time"),
])
def test_simulation_numbers_out_of_range(kwargs, message):
    sim = cbps.Simulation(cbps.scene("chain", n=2))
    with pytest.raises(cbps.InputError, match=message):
        sim.run(**kwargs)
    assert sim.steps_done == 0
    sim.run(steps=2.0, record_every=np.int32(2))  # whole numbers in other forms
    assert sim.steps_done == 2


def test_write_problem_numbers(tmp_path):
    args = (np.eye(2), [1, 1], [0, 0], [1, 1])
    with pytest.raises(cbps.InputError, match="cfm 'x': not a number"):
        cbps.write_problem(str(tmp_path / "a"), *args, cfm="x")
    with pytest.raises(cbps.InputError, match="dt '1/240': not a number"):
        cbps.write_problem(str(tmp_path / "b"), *args, J=np.eye(2), Minv=np.eye(2), v1=[0, 0],
                           fext=[0, 0], dt="1/240")


def test_load_scene_names_a_folder(tmp_path):
    """A folder given to load_scene (a `cbps matrices` folder, say) is named as a folder, not
    reported as a JSON syntax error at line 1."""
    with pytest.raises(cbps.InputError) as e:
        cbps.load_scene(str(tmp_path))
    message = str(e.value)
    assert message.startswith(f"{tmp_path}: a folder, not a scene file")
    assert "read_problem" in message and "syntax error" not in message


@pytest.mark.parametrize("writer", ["write_problem", "write_siconos"])
def test_writers_refuse_cmin_above_cmax_as_the_reader_does(tmp_path, writer):
    """cmin[1] = 2 > cmax[1] = 1: no lambda fits (5.1). The writer refuses it with the reader's
    words (read_problem on the same bounds, written file by file) and writes nothing."""
    A, b, cmin, cmax = np.eye(2), [1.0, 1.0], [0.0, 2.0], [1.0, 1.0]
    by_hand = tmp_path / "by_hand"
    by_hand.mkdir()
    for name, value in (("A", sp.csr_matrix(A)), ("b", b), ("cmin", cmin), ("cmax", cmax)):
        cbps.write_matrix_market(str(by_hand / f"{name}.mtx"), np.asarray(value)
                                 if name != "A" else value)
    with pytest.raises(cbps.InputError) as read:
        cbps.read_problem(str(by_hand))
    prefix = f"{by_hand / 'cmin.mtx'}: "
    assert str(read.value).startswith(prefix)
    why = str(read.value)[len(prefix):]
    assert why == "cmin[1] = 2: above cmax, no lambda fits"

    target = tmp_path / ("folder" if writer == "write_problem" else "p.dat")
    with pytest.raises(cbps.InputError) as e:
        getattr(cbps, writer)(str(target), A, b, cmin, cmax)
    assert str(e.value) == f"{writer}: {why}"
    assert not target.exists()
