"""scripts/plot_convergence.py, the picture `cbps converge` draws: a method that gives one point
(an exact path, or a peer, which reports only where it ended) is one marker in every panel,
never a line from the guess it never reported passing through (issue 50, item 15: a peer was a
line from λ = 0 in the sweeps panel and missing from the time panel)."""
import importlib.util

import matplotlib.pyplot as plt
import numpy as np

from conftest import ROOT

spec = importlib.util.spec_from_file_location("plot_convergence",
                                              ROOT / "scripts" / "plot_convergence.py")
plot_convergence = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plot_convergence)


def rows(*points):
    """Rows (iteration, time_s, residual, lambda_error, velocity_error) as read_csv gives."""
    return np.array([[k, t, r, np.nan, np.nan] for k, t, r in points], dtype=float)


def drawn(name, lines):
    """The Line2D objects of one solver's colour in a panel."""
    return [line for line in lines if line.get_color() == name]


def test_a_peer_and_the_direct_path_are_one_marker_in_both_panels():
    data = {
        "pgs": rows(*[(k, 1e-4 * k, 10.0 * 0.8 ** k) for k in range(60)]),
        # converge's peer run: the guess at sweep 0, time 0, then the final point only
        "siconos:lemke": rows((0, 0.0, 9.8), (120, 0.02, 2e-7)),
        "direct": rows((12, 0.001, 1e-14)),
    }
    colors = {"pgs": "C0", "siconos:lemke": "C1", "direct": "C2"}
    status = {name: "converging" for name in data}
    for x_column in (0, 1):  # the sweeps panel, the time panel
        fig, ax = plt.subplots()
        if x_column == 1:
            ax.set_xscale("log")
        plot_convergence.draw(ax, data, 2, x_column, colors, status, None)
        for name, marker in (("siconos:lemke", "D"), ("direct", "*")):
            lines = drawn(colors[name], ax.lines)
            assert len(lines) == 1, (name, x_column)
            line = lines[0]
            assert line.get_linestyle() == "None", (name, x_column)
            assert line.get_marker() == marker, (name, x_column)
            x, y = line.get_data()
            assert list(np.asarray(x)) == [data[name][-1, x_column]]
            assert list(np.asarray(y)) == [data[name][-1, 2]]
        # an iterative method stays a line
        assert drawn("C0", ax.lines)[0].get_linestyle() == "-"
        plt.close(fig)
