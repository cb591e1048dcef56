#!/usr/bin/python3
"""Draws the push-factor figure (paper 8.1) from the output of validate_contacts.

    /usr/bin/python3 validation/plot_contacts.py RESULTS_JSON OUT_PNG

RESULTS_JSON is the file `validate_contacts --out RESULTS_JSON` wrote (its "push_factor_figure":
the box states of three panels); OUT_PNG the figure, e.g. docs/push-factor.png. Three panels side
by side, a side view (x-y plane) of the `overlap` scene: (a) the begin situation, each box sunk
into the one below and the lowest into the ground; (b) the original push factor (Baumgarte in the
one system) and (c) the improved technique (a separate position system), both at the same time.
Each box is drawn as the outline of its 8 corners, x + R(q) (±h_x, ±h_y, ±h_z), projected onto
the x-y plane (their convex hull), so a box turned about any axis is drawn correctly. Each panel
is titled with the kinetic energy the push injected (the largest kinetic energy up to its time, J).
Uses Debian's matplotlib and numpy only; exits 2 with a message if the input is missing or bad.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "scripts"))
from cbps_files import save_figure  # noqa: E402  scripts/cbps_files.py

PROG = "plot_contacts"


def fail(what, why, code=2):
    print(f"{PROG}: {what}: {why}", file=sys.stderr)
    sys.exit(code)


def number_list(value, length):
    return (isinstance(value, list) and len(value) == length
            and all(isinstance(v, (int, float)) for v in value))


def load(path):
    """The "push_factor_figure" object of the results, checked."""
    try:
        with open(path, encoding="utf-8") as f:
            results = json.load(f)
    except OSError as e:
        fail(path, e.strerror or str(e))
    except json.JSONDecodeError as e:
        fail(path, f"not valid JSON (line {e.lineno}: {e.msg})")
    figure = results.get("push_factor_figure") if isinstance(results, dict) else None
    if not isinstance(figure, dict) or not isinstance(figure.get("panels"), list):
        fail(path, "no 'push_factor_figure' with 'panels'")
    if [p.get("label") for p in figure["panels"]] != ["begin", "original", "improved"]:
        fail(path, "push_factor_figure.panels must be begin, original, improved")
    for i, panel in enumerate(figure["panels"]):
        boxes = panel.get("boxes")
        if not isinstance(boxes, list) or not boxes:
            fail(path, f"panels[{i}].boxes: missing or empty")
        for k, box in enumerate(boxes):
            if not (number_list(box.get("x"), 3) and number_list(box.get("q"), 4)
                    and number_list(box.get("half_extents"), 3)):
                fail(path, f"panels[{i}].boxes[{k}]: needs x[3], q[4] (w, x, y, z), "
                           "half_extents[3]")
    return figure


def rotation(q):
    """R(q) of a unit quaternion q = (w, x, y, z), renormalised."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def convex_hull(points):
    """Counter-clockwise convex hull of 2-D points (Andrew's monotone chain)."""
    pts = sorted(map(tuple, points))

    def half(seq):
        chain = []
        for p in seq:
            while len(chain) >= 2 and ((chain[-1][0] - chain[-2][0]) * (p[1] - chain[-2][1]) -
                                       (chain[-1][1] - chain[-2][1]) * (p[0] - chain[-2][0])) <= 0:
                chain.pop()
            chain.append(p)
        return chain

    lower, upper = half(pts), half(reversed(pts))
    return np.array(lower[:-1] + upper[:-1])


def outline(box):
    """The box's silhouette in the x-y plane: hull of its 8 corners x + R (±h) projected."""
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    corners = np.asarray(box["x"]) + (signs * np.asarray(box["half_extents"])) @ rotation(
        box["q"]).T
    return convex_hull(corners[:, :2])


def main():
    if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        sys.exit(0 if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help") else 2)
    path, out = sys.argv[1], sys.argv[2]
    figure = load(path)
    panels = figure["panels"]

    hulls = [[outline(b) for b in p["boxes"]] for p in panels]
    every = np.vstack([h for panel in hulls for h in panel])
    stack_top = sum(2 * b["half_extents"][1] for b in panels[0]["boxes"])  # boxes just touching
    x_half = max(1.5, np.abs(every[:, 0]).max() + 0.5)
    y_top = max(every[:, 1].max(), stack_top) + 0.4

    fig, axes = plt.subplots(1, 3, figsize=(7.8, 5.4), sharey=True, constrained_layout=True)
    names = {"begin": "(a) begin", "original": "(b) original", "improved": "(c) improved"}
    colors = ["C0", "C1", "C2", "C3", "C4", "C5"]
    for ax, panel, panel_hulls in zip(axes, panels, hulls):
        ax.axhspan(-1.0, 0.0, color="0.85", zorder=0)
        ax.axhline(0.0, color="0.2", lw=1.2, zorder=1)
        ax.axhline(stack_top, color="0.5", lw=0.8, ls=":", zorder=1)
        for k, hull in enumerate(panel_hulls):
            color = colors[k % len(colors)]
            ax.add_patch(Polygon(hull, closed=True, facecolor=color, alpha=0.35, edgecolor=color,
                                 lw=1.5, zorder=2))
        injected = panel.get("kinetic_energy_injected", 0.0)
        energy = "0 J" if injected == 0 else f"{injected:.3g} J"
        ax.set_title(f"{names[panel['label']]}, t = {panel['time']:.2f} s\n"
                     f"kinetic energy injected: {energy}", fontsize=10)
        ax.set_xlim(-x_half, x_half)
        ax.set_ylim(-0.3, y_top)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.grid(True, alpha=0.25)
    axes[0].set_ylabel("y (m)")
    axes[0].annotate("top of the stack at rest", (-x_half + 0.1, stack_top + 0.08), fontsize=7,
                     color="0.4")
    n = len(panels[0]["boxes"])
    fig.suptitle(f"The push factor (8.1): {n} boxes, each sunk {figure.get('initial_overlap', 0):g}"
                 f" m into the one below; dt = 1/{round(1 / figure['dt'])} s, "
                 f"β = {figure.get('beta', '?')}, μ = {figure.get('mu', '?')}, "
                 f"{figure.get('solver', '?')} solver", fontsize=10)

    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    save_figure(fig, {out: {"format": "png", "dpi": 110}})  # a temporary name, renamed
    print(f"{PROG}: wrote {out} ({os.path.getsize(out) // 1024} kB)")
    for panel in panels[1:]:
        print(f"{PROG}: {panel['label']}: kinetic energy injected "
              f"{panel.get('kinetic_energy_injected', float('nan')):.4g} J (max until then), "
              f"{panel.get('kinetic_energy', float('nan')):.4g} J at t = {panel['time']:.3f} s")


if __name__ == "__main__":
    main()
