#!/usr/bin/python3
"""Draw the performance profiles of a `cbps profile` run (Dolan & More, Math. Program. 91, 2002).

Usage: plot_profile.py PROFILE_JSON OUT_PREFIX

Reads profile.json (docs/outputs.md, `cbps profile`) and writes OUT_PREFIX.png (dpi 150) and
OUT_PREFIX.svg: one column per tolerance of the relative residual, time profiles above and sweep
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

plt.rcParams["svg.fonttype"] = "none"  # SVG text stays text: searchable and editable


def curve(ratios, k):
    """The step function rho(tau) of solver k as (log2 tau, rho) points, from tau = 1."""
    n = len(ratios)
    finite = sorted(r[k] for r in ratios if r[k] is not None)
    x, y = [0.0], [0.0]
    for i, r in enumerate(finite):
        x.append(math.log2(max(r, 1.0)))
        y.append((i + 1) / n)
    return x, y


def plot(data):
    profiles = data["profiles"]
    tolerances = data["tolerances"]
    fig, axes = plt.subplots(2, len(tolerances), figsize=(5 * len(tolerances), 8), squeeze=False)
    solvers = [s["solver"] for s in data["solvers"]]
    # Ten colours, then the same ten dashed: each solver keeps its look in every panel.
    styles = {s: (plt.cm.tab10(i % 10), "-" if i < 10 else "--") for i, s in enumerate(solvers)}
    right = 1.0  # the x range: the largest finite log2 ratio of any profile
    for p in profiles:
        for row in p["ratios"]:
            for r in row:
                if r is not None:
                    right = max(right, math.log2(max(r, 1.0)))
    right *= 1.05
    for p in profiles:
        column = tolerances.index(p["tolerance"])
        ax = axes[0 if p["measure"] == "time" else 1][column]
        for k, solver in enumerate(p["solvers"]):
            x, y = curve(p["ratios"], k)
            x.append(right)
            y.append(y[-1])
            colour, line = styles[solver]
            ax.step(x, y, where="post", color=colour, linestyle=line, label=solver)
        ax.set_xlim(0.0, right)
        ax.set_ylim(0.0, 1.02)
        ax.set_xlabel("log2 tau (cost within tau x the best)")
        ax.set_ylabel("rho(tau): fraction of problems")
        ax.set_title(f"{p['measure']}, relative residual <= {p['tolerance']:g}")
        ax.grid(True, alpha=0.3)
    handles, labels = axes[0][0].get_legend_handles_labels()  # the time panels have them all
    fig.legend(handles, labels, loc="center right", fontsize="small")
    fig.suptitle(
        f"Performance profiles, {len(data['problems'])} problems "
        f"(budget {data['budget_iterations']} sweeps, {data['time_limit_s']:g} s each)"
    )
    fig.tight_layout(rect=(0, 0, 0.88, 1))
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
        fig.savefig(args.out_prefix + ".png", dpi=150)
        fig.savefig(args.out_prefix + ".svg")
    except (OSError, ValueError, KeyError) as e:
        print(f"plot_profile: {args.profile_json}: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
