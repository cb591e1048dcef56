#!/usr/bin/python3
"""Figures of the step-scheme study (docs/schemes.md) from its summary.json.

    /usr/bin/python3 validation/plot_schemes.py validation/results/schemes/summary.json docs

Writes into the folder given: schemes-drift.png (the stack and the pyramid under each scheme
against time, log scale: above, the largest displacement of any box from its start; below, the
top box's horizontal displacement; each point the largest over the 0.25 s before it, so no
step's excursion falls between the points) and schemes-scenes.png (the resting scenes' largest
displacement of any body at any step of the run, by scheme, with the value at the end marked).
Debian's numpy and matplotlib only.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "scripts"))
from cbps_files import save_figure  # noqa: E402

COLOURS = {"paper": "black", "tgs": "tab:blue", "soft-step": "tab:green", "xpbd": "tab:red"}
STYLES = {1: "-", 4: "--", 5: "--", 10: "-", 20: ":"}


def style(r):
    if "Hz" in r["config"]:
        return dict(color="darkgreen", linestyle="-.")
    return dict(color=COLOURS[r["scheme"]], linestyle=STYLES.get(r["substeps"], "-"))


# (scene, solver, the target on the largest displacement of any box, m)
PANELS = [("stack", "pgs", 0.005), ("stack", "pgs:contacts_first=on", 0.005),
          ("pyramid", "pgs:contacts_first=on", 0.01)]


def drift_figure(runs, folder):
    rows = [("excursion_series", "largest displacement of any box (m)"),
            ("drift_series", "top box's horizontal displacement (m)")]
    fig, axes = plt.subplots(len(rows), len(PANELS), figsize=(15, 8), sharey=True, sharex=True)
    for (key, ylabel), line in zip(rows, axes):
        for ax, (scene, solver, target) in zip(line, PANELS):
            for r in runs:
                if r["scene"] != scene or r["solver"] != solver or key not in r:
                    continue
                t = [p[0] for p in r[key]]
                d = [max(p[1], 1e-7) for p in r[key]]
                ax.semilogy(t, d, label=f"{r['config']} ({r['sweeps_per_step']} sweeps)",
                            **style(r))
            order = "contacts first" if "contacts_first" in solver else "natural order"
            if key == "excursion_series":
                ax.set_title(f"{scene}, {order}; grey: the target, {target * 100:g} cm")
                ax.axhline(target, color="grey", linewidth=0.8)
            else:
                ax.set_xlabel("t (s)")
            ax.set_ylim(1e-6, 1e2)
            ax.grid(True, which="major", alpha=0.3)
        line[0].set_ylabel(ylabel)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=9)
    save_figure(fig, {os.path.join(folder, "schemes-drift.png"): {"dpi": 110}})


def scenes_figure(runs, folder):
    scenes = ["stack", "card-house", "pyramid"]  # the scenes at rest: any motion is error
    configs = []
    for r in runs:
        if r["config"] not in configs:
            configs.append(r["config"])
    fig, ax = plt.subplots(figsize=(12, 4.5))
    width = 0.8 / len(configs)
    for j, config in enumerate(configs):
        xs, ys, ends = [], [], []
        for i, scene in enumerate(scenes):
            chosen = [r for r in runs if r["scene"] == scene and r["config"] == config and
                      r["integrator"] == "paper"]
            if not chosen:
                continue
            best = min(chosen, key=lambda r: r["max_excursion_m"])  # the better row order
            xs.append(i + (j - len(configs) / 2 + 0.5) * width)
            ys.append(max(best["max_excursion_m"], 1e-7))
            ends.append(max(best["end_max_move_m"], 1e-7))
        scheme = config.split()[0]
        ax.bar(xs, ys, width, label=config, color=COLOURS[scheme],
               alpha=0.45 + 0.1 * (j % 5), edgecolor="black", linewidth=0.5)
        ax.plot(xs, ends, "_", color="black", markersize=9,
                label="at the end" if j == 0 else None)
    ax.set_yscale("log")
    ax.set_xticks(range(len(scenes)))
    ax.set_xticklabels([f"{s}" for s in scenes])
    ax.set_ylabel("largest displacement of any body (m)")
    ax.set_title("the resting scenes under each scheme over 10 s (the better row order): at any "
                 "step (bars), at the end (dashes)")
    ax.legend(fontsize=8, ncol=3)
    ax.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    save_figure(fig, {os.path.join(folder, "schemes-scenes.png"): {"dpi": 110}})


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        runs = json.load(f)["runs"]
    drift_figure(runs, sys.argv[2])
    scenes_figure(runs, sys.argv[2])


if __name__ == "__main__":
    main()
