#!/usr/bin/python3
"""Draw the performance profiles of a `cbps profile` run (Dolan & More, Math. Program. 91, 2002).

Usage: plot_profile.py PROFILE_JSON OUT_PREFIX

Reads profile.json (docs/outputs.md, `cbps profile`) and writes OUT_PREFIX.png (dpi 150) and
OUT_PREFIX.svg (each written to a temporary name and renamed): one column per tolerance of the relative residual, time profiles above and sweep
profiles below. Each curve is rho_s(tau), the fraction of problems a solver solved within tau
times the best solver's cost, against log2 tau; it is drawn from the ratios in profile.json,
so the picture and the table say the same. A curve that ends below 1 on the right says on how
many problems the solver failed. `cbps profile --out` calls this script; it needs matplotlib
(Debian's python3-matplotlib).
"""
import argparse
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")  # non-interactive backend; must precede pyplot import
import matplotlib.pyplot as plt  # noqa: E402

from cbps_files import save_figure  # noqa: E402  scripts/cbps_files.py, beside this script

plt.rcParams["svg.fonttype"] = "none"  # SVG text stays text: searchable and editable


def solved(r):
    """A ratio of profile.json that stands for a solved problem: a number (a failure is "inf";
    files written before that convention hold null)."""
    return isinstance(r, (int, float)) and math.isfinite(r)


def curve(ratios, k):
    """The step function rho(tau) of solver k as (log2 tau, rho) points, from tau = 1."""
    n = len(ratios)
    finite = sorted(r[k] for r in ratios if solved(r[k]))
    x, y = [0.0], [0.0]
    for i, r in enumerate(finite):
        x.append(math.log2(max(r, 1.0)))
        y.append((i + 1) / n)
    return x, y


DASHES = ("-", "--", ":", "-.")
MARKERS = (None, "o", "s", "^", "v", "D", "x", "+")


def solver_styles(solvers):
    """Each solver's (colour, line style, marker), the same in every panel and no two alike.

    Solver i takes colour i mod 10 (tab10) and dash i mod 4: the pair repeats only after 20
    solvers (the least common multiple of 10 and 4), so two solvers of one colour never share a
    dash; from the 21st on a marker (i div 20) tells them apart as well.
    """
    if len(solvers) > 20 * len(MARKERS):
        raise ValueError(f"{len(solvers)} solvers: at most {20 * len(MARKERS)} can be told apart")
    return {s: (plt.cm.tab10(i % 10), DASHES[i % 4], MARKERS[i // 20])
            for i, s in enumerate(solvers)}


def plot(data):
    profiles = data["profiles"]
    tolerances = data["tolerances"]
    fig, axes = plt.subplots(2, len(tolerances), figsize=(5 * len(tolerances), 8), squeeze=False)
    solvers = [s["solver"] for s in data["solvers"]]
    styles = solver_styles(solvers)
    right = 1.0  # the x range: the largest finite log2 ratio of any profile
    for p in profiles:
        for row in p["ratios"]:
            for r in row:
                if solved(r):
                    right = max(right, math.log2(max(r, 1.0)))
    right *= 1.05
    for p in profiles:
        column = tolerances.index(p["tolerance"])
        ax = axes[0 if p["measure"] == "time" else 1][column]
        for k, solver in enumerate(p["solvers"]):
            x, y = curve(p["ratios"], k)
            x.append(right)
            y.append(y[-1])
            colour, line, marker = styles[solver]
            ax.step(x, y, where="post", color=colour, linestyle=line, marker=marker,
                    markersize=4, label=solver)
        ax.set_xlim(0.0, right)
        ax.set_ylim(0.0, 1.02)
        ax.set_xlabel("log2 tau (cost within tau x the best)")
        ax.set_ylabel("rho(tau): fraction of problems")
        ax.set_title(f"{p['measure']}, unit-free residual <= {p['tolerance']:g}")
        ax.grid(True, alpha=0.3)
    # One legend for every solver (a solver may be missing from a panel: the exact paths have no
    # sweeps), beside the panels: it is measured once drawn and the panels are laid out in the
    # width left of it, so it never covers a curve however many solvers or however long names.
    handles, labels = [], []
    for ax in axes.flat:
        for h, label in zip(*ax.get_legend_handles_labels()):
            if label not in labels:
                handles.append(h)
                labels.append(label)
    order = sorted(range(len(labels)), key=lambda k: solvers.index(labels[k]))
    columns = 1 + len(labels) // 30  # about 30 entries fit the figure's height
    legend = fig.legend([handles[k] for k in order], [labels[k] for k in order],
                        loc="center right", bbox_to_anchor=(1.0, 0.5), fontsize="small",
                        ncol=columns, handlelength=3.5)
    fig.suptitle(
        f"Performance profiles, {len(data['problems'])} problems "
        f"(budget {data['budget_iterations']} sweeps, {data['time_limit_s']:g} s each)"
    )
    fig.canvas.draw()
    width = legend.get_window_extent().width / fig.bbox.width
    fig.tight_layout(rect=(0, 0, 1.0 - width - 0.01, 1))
    return fig


def main():
    ap = argparse.ArgumentParser(description="Draw the performance profiles of `cbps profile`.")
    ap.add_argument("profile_json", help="profile.json written by `cbps profile`")
    ap.add_argument("out_prefix", help="writes OUT_PREFIX.png and OUT_PREFIX.svg")
    args = ap.parse_args()
    try:
        with open(args.profile_json) as f:
            data = json.load(f)
        fig = plot(data)
        save_figure(fig, {args.out_prefix + ".png": {"dpi": 150}, args.out_prefix + ".svg": {}})
    except (OSError, ValueError, KeyError) as e:
        print(f"plot_profile: {args.profile_json}: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
