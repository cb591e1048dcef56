#!/usr/bin/python3
"""Plot solver convergence curves from a `cbps converge` CSV.

Usage: plot_convergence.py CSV OUT_PREFIX [--title TEXT] [--sweeps auto|log|linear]

CSV header: solver,iteration,time_s,residual,lambda_error,velocity_error,objective
(solver, iteration, time_s and residual are required; lambda_error and velocity_error are
plotted when present and finite somewhere; empty cells read as nan).
Writes OUT_PREFIX.png (dpi 150) and OUT_PREFIX.svg atomically. Panels: the natural-map
residual vs sweeps and vs wall time; below them, when the CSV has them, the lambda error and
the v2 error vs sweeps.

An exact method (direct, active-set, lemke) is drawn as a star at its one point, a peer
(siconos:NAME, bullet:NAME: it reports only its final point) as a diamond there, in both the
sweeps and the time panels; never as a line from the guess.
A solver diverges when a value turns non-finite or its last residual is more than DIVERGED
times its first: its legend entry says "diverged", its last finite point is marked with an x
(a ^ on the top edge where it leaves the plot), and the y axes span only the converging
curves, so one exploding solver does not flatten the others. The sweep axis is logarithmic
(symlog, so sweep 0 stays) when the sweeps span two decades or more (--sweeps auto).
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")  # non-interactive backend; must precede pyplot import
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from cbps_files import save_figure  # noqa: E402  scripts/cbps_files.py, beside this script

plt.rcParams["svg.fonttype"] = "none"  # SVG text stays text: searchable and editable

REQUIRED = ("solver", "iteration", "time_s", "residual")
OPTIONAL = ("lambda_error", "velocity_error")
MAX_POINTS = 2000  # per solver and panel before thinning kicks in
DIVERGED = 100.0  # last residual above this times the first: diverged
TOO_BIG = 1e100  # beyond this a value is not drawn (matplotlib overflows near 1e308)


class InputError(Exception):
    """Fatal problem with a file; reported as `plot_convergence: <file>: <what>`."""

    def __init__(self, path, what):
        super().__init__(f"{path}: {what}")


def cell(row, name):
    text = (row.get(name) or "").strip()
    return float(text) if text else math.nan


def read_csv(path):
    """Return ({solver: array of rows (iteration, time_s, residual, lambda_error,
    velocity_error)}, the optional columns present) in first-seen order."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            reader = csv.DictReader(f, skipinitialspace=True)
            if not reader.fieldnames:
                raise InputError(path, "empty file (no header)")
            fields = [c.strip() for c in reader.fieldnames]
            missing = [c for c in REQUIRED if c not in fields]
            if missing:
                raise InputError(path, "missing required column(s): " + ", ".join(missing))
            present = [c for c in OPTIONAL if c in fields]
            reader.fieldnames = fields
            data = {}
            for row in reader:
                name = (row["solver"] or "").strip()
                if not name:
                    continue  # blank line or row without a solver name
                try:
                    vals = tuple(cell(row, c) for c in REQUIRED[1:] + OPTIONAL)
                except ValueError as e:
                    raise InputError(path, f"line {reader.line_num}: bad number ({e})")
                data.setdefault(name, []).append(vals)
    except OSError as e:
        raise InputError(path, e.strerror or str(e))
    if not data:
        raise InputError(path, "no data rows")
    out = {}
    for name, rows in data.items():
        a = np.array(rows, dtype=float)
        out[name] = a[np.argsort(a[:, 0], kind="stable")]
    return out, present


def thin(x, y):
    """Keep at most ~MAX_POINTS points: first, last and a log-spaced subset."""
    n = len(x)
    if n <= MAX_POINTS:
        return x, y
    logspaced = np.geomspace(1, n - 1, MAX_POINTS).astype(int)
    idx = np.unique(np.concatenate(([0, n - 1], logspaced)))
    return x[idx], y[idx]


def drawable(y):
    """Values a log axis can show."""
    return np.isfinite(y) & (y > 0) & (y < TOO_BIG)


def diverged(a):
    """True when the residual turned non-finite or grew past DIVERGED times its first."""
    r = a[:, 2]
    if not np.all(np.isfinite(r)):
        return True
    return len(r) > 1 and r[0] > 0 and r[-1] > DIVERGED * r[0]


def y_range(data, column, x_column, converging):
    """(low, high) of the converging curves' drawable values, padded; None if none."""
    vals = []
    for name in converging:
        a = data[name]
        y = a[:, column]
        ok = drawable(y)
        if x_column == 1:
            ok &= np.isfinite(a[:, 1]) & (a[:, 1] > 0)
        vals.append(y[ok])
    vals = np.concatenate(vals) if vals else np.array([])
    if vals.size == 0:
        return None
    lo, hi = vals.min(), vals.max()
    return lo / 3.0, hi * 3.0


def is_peer(name):
    """Siconos' and Bullet's solvers (cbps converge runs them as peers): their final point only."""
    return name.startswith(("siconos:", "bullet:"))


def final_point_only(name):
    """The methods whose run is one point: the exact ones (direct, active-set, lemke) and the
    peers."""
    return is_peer(name) or name.split(":")[0] in ("direct", "active-set", "lemke")


def draw(ax, data, column, x_column, colors, status, ylim):
    """One panel: column (2 residual, 3 lambda error, 4 v2 error) against x_column (0 sweeps,
    1 time). Returns True if anything was drawn."""
    drew = False
    for name, a in data.items():
        color = colors[name]
        x, y = a[:, x_column], a[:, column]
        ok = drawable(y) & np.isfinite(x)
        if x_column == 1:
            ok &= x > 0  # time 0 cannot sit on a log axis
        if final_point_only(name):
            # An exact method (one row: its iterations and time) is a star; a peer, which
            # reports only where it ended, a diamond at that point: never a line from the guess,
            # which it never reported passing through. Both in the time panel too.
            x, y, ok = x[-1:], y[-1:], ok[-1:]
            if np.any(ok):
                ax.plot(x[ok], y[ok], marker="*" if not is_peer(name) else "D",
                        markersize=14 if not is_peer(name) else 8, color=color,
                        markeredgecolor="k", linestyle="none")
                drew = True
            continue
        if not np.any(ok):
            continue
        ax.plot(*thin(x[ok], y[ok]), color=color, linewidth=1.2)
        drew = True
        if status[name] != "diverged":
            continue
        # Mark the last finite point, or where the curve leaves the top of the plot.
        xs, ys = x[ok], y[ok]
        if ylim is not None and np.any(ys > ylim[1]):
            k = int(np.argmax(ys > ylim[1]))
            ax.plot([xs[k]], [ylim[1]], marker="^", markersize=9, color=color,
                    markeredgecolor="k", linestyle="none", clip_on=False)
        else:
            ax.plot([xs[-1]], [ys[-1]], marker="x", markersize=10, markeredgewidth=2,
                    color=color, linestyle="none")
    return drew


def sweep_scale(data, choice):
    if choice != "auto":
        return choice
    top = max((np.nanmax(a[:, 0]) for a in data.values() if a.size), default=0.0)
    return "log" if top >= 100 else "linear"


def plot(data, present, title, sweeps="auto"):
    names = list(data)
    colors = {name: f"C{i % 10}" for i, name in enumerate(names)}
    status = {}
    for name in names:
        a = data[name]
        status[name] = "diverged" if diverged(a) else "converging"
    converging = [n for n in names if status[n] == "converging"]
    extras = [(3, "lambda error, max |lambda - lambda*| (N)", "lambda error vs sweeps"),
              (4, "v2 error, max |v2 - v2*| (m/s, rad/s)", "v2 error vs sweeps")]
    extras = [e for e in extras
              if OPTIONAL[e[0] - 3] in present
              and any(np.any(drawable(data[n][:, e[0]])) for n in names)]
    rows = 2 if extras else 1
    fig, axes = plt.subplots(rows, 2, figsize=(12, 5 * rows), constrained_layout=True,
                             squeeze=False)
    scale = sweep_scale(data, sweeps)
    panels = [(axes[0][0], 2, 0, "natural-map residual (N)", "residual vs sweeps"),
              (axes[0][1], 2, 1, "natural-map residual (N)", "residual vs wall time")]
    for i, (column, ylabel, ptitle) in enumerate(extras):
        panels.append((axes[1][i], column, 0, ylabel, ptitle))
    if len(extras) == 1:
        axes[1][1].set_visible(False)
    for ax, column, x_column, ylabel, ptitle in panels:
        ylim = y_range(data, column, x_column, converging)
        draw(ax, data, column, x_column, colors, status, ylim)
        ax.set_yscale("log")
        if ylim is not None:
            ax.set_ylim(*ylim)
        if x_column == 1:
            ax.set_xscale("log")
            ax.set_xlabel("wall time (s)")
        else:
            if scale == "log":
                ax.set_xscale("symlog", linthresh=1.0)
            ax.set_xlim(left=0.0)
            ax.set_xlabel("sweeps" + (" (log scale)" if scale == "log" else ""))
        ax.set_ylabel(ylabel)
        ax.set_title(ptitle)
        ax.grid(True, which="major", alpha=0.5)
        ax.grid(True, which="minor", alpha=0.15)
    # One legend for all panels, on the first.
    handles = []
    for name in names:
        a = data[name]
        label = name
        if status[name] == "diverged":
            finite = a[np.isfinite(a[:, 2])]
            label += " (diverged"
            if finite.size:
                label += f", last finite residual {finite[-1, 2]:.3g} N at sweep {finite[-1, 0]:.0f}"
            label += ")"
        elif np.any(a[:, 2] == 0):
            label += " (reaches 0)"
        marker = ("D" if is_peer(name) else "*") if final_point_only(name) else None
        handles.append(plt.Line2D([], [], color=colors[name], marker=marker,
                                  linestyle="none" if marker else "-", label=label))
    axes[0][0].legend(handles=handles, fontsize="small")
    if title:
        fig.suptitle(title)
    return fig


def save_atomic(fig, prefix):
    """Save PNG and SVG to temporary files next to the targets, then rename both
    (scripts/cbps_files.py)."""
    try:
        save_figure(fig, {f"{prefix}.png": {"dpi": 150}, f"{prefix}.svg": {}})
    except OSError as e:
        raise InputError(prefix, e.strerror or str(e))


def main():
    ap = argparse.ArgumentParser(description="Plot cbps convergence CSV.")
    ap.add_argument("csv", help="CSV written by `cbps converge`")
    ap.add_argument("out_prefix", help="writes OUT_PREFIX.png and OUT_PREFIX.svg")
    ap.add_argument("--title", default=None, help="figure title")
    ap.add_argument("--sweeps", choices=("auto", "log", "linear"), default="auto",
                    help="sweep axis: log (symlog, sweep 0 kept) or linear; auto: log when the "
                         "sweeps reach 100 or more")
    args = ap.parse_args()
    try:
        data, present = read_csv(args.csv)
        fig = plot(data, present, args.title, args.sweeps)
        save_atomic(fig, args.out_prefix)
    except InputError as e:
        print(f"plot_convergence: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
