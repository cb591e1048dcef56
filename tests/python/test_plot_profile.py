"""scripts/plot_profile.py, the picture `cbps profile --out` draws: every solver keeps one look
(colour, line style, marker) in every panel and no two solvers share one, and the legend sits
beside the panels, not over them, however many solvers and however long their specs."""
import importlib.util
import random

import pytest

from conftest import ROOT

spec = importlib.util.spec_from_file_location("plot_profile", ROOT / "scripts" / "plot_profile.py")
plot_profile = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plot_profile)


def profile_json(solvers, problems=6):
    """A profile.json as `cbps profile` writes it (docs/outputs.md): ratios >= 1 or "inf"
    (failed); `direct` has no sweeps, so it is in the time profiles only."""
    rng = random.Random(3)
    tolerances = [1e-4, 1e-8, 1e-10]
    profiles = []
    for measure in ("time", "sweeps"):
        for tol in tolerances:
            names = [s for s in solvers if measure == "time" or s != "direct"]
            ratios = [["inf" if rng.random() < 0.1 else 1.0 + rng.expovariate(0.1) for _ in names]
                      for _ in range(problems)]
            profiles.append({"measure": measure, "tolerance": tol, "solvers": names,
                             "ratios": ratios, "rho": {}})
    return {"format": "cbps-profile/1", "tolerances": tolerances, "profiles": profiles,
            "solvers": [{"solver": s} for s in solvers],
            "problems": [{"name": f"p{k}"} for k in range(problems)],
            "budget_iterations": 100000, "time_limit_s": 1.0}


def test_a_failure_is_inf_and_older_files_null():
    """rho(tau) counts only the solved problems: a failure's ratio is "inf" (null in files
    written before the JSON convention); 2 of 4 solved, at ratios 1 and 2."""
    x, y = plot_profile.curve([[1.0], ["inf"], [2.0], [None]], 0)
    assert x == [0.0, 0.0, 1.0]
    assert y == [0.0, 0.25, 0.5]


# The methods `cbps profile --help` lists, and specs as long as the grammar allows.
MANY = ["pgs", "psor:1.3", "sgs", "jacobi", "block-pgs", "matrix-free", "pgs-nesterov", "apgd",
        "nncg", "pgs-sm", "admm", "rbgs", "shock", "direct", "active-set",
        "pgs:order=reverse:contacts_first=on", "psor:0.7:order=random", "jacobi:0.5",
        "apgd:grow=1.5:shrink=0.8:restart=off", "pgs-nesterov:restart=off", "psor:1.9",
        "sgs:warm=0.5", "pgs:order=random", "admm:warm=off"]


@pytest.mark.parametrize("solvers", [MANY[:14], MANY[10:], MANY],
                         ids=["14-methods", "14-long-specs", "24-specs"])
def test_every_solver_its_own_look_and_the_legend_beside_the_plots(solvers):
    fig = plot_profile.plot(profile_json(solvers))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()

    looks = {}
    for ax in fig.axes:
        for line in ax.get_lines():
            look = (line.get_color(), line.get_linestyle(), line.get_marker())
            assert looks.setdefault(line.get_label(), look) == look, line.get_label()
    assert sorted(looks) == sorted(solvers)
    assert len(set(looks.values())) == len(solvers), "two solvers drawn alike"

    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == solvers  # every solver once, in order
    box = legend.get_window_extent(renderer)
    assert box.x1 <= fig.bbox.x1 + 1 and box.y0 >= -1 and box.y1 <= fig.bbox.y1 + 1
    for ax in fig.axes:  # beside: right of every panel, its tick labels and axis titles too
        assert ax.get_tightbbox(renderer).x1 < box.x0, ax.get_title()
