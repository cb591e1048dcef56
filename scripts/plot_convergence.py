#!/usr/bin/python3
"""Plot solver convergence curves from a `cbps converge` CSV.

Usage: plot_convergence.py CSV OUT_PREFIX [--title TEXT]

CSV header: solver,iteration,time_s,residual,lambda_error,velocity_error,objective
(only solver, iteration, time_s and residual are used; empty cells read as nan).
Writes OUT_PREFIX.png (dpi 150) and OUT_PREFIX.svg atomically: left panel is the
natural-map residual vs iterations, right panel the residual vs wall time.
"""
import argparse
import csv
import math
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")  # non-interactive backend; must precede pyplot import
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

REQUIRED = ("solver", "iteration", "time_s", "residual")
MAX_POINTS = 2000  # per solver and panel before thinning kicks in


class InputError(Exception):
    """Fatal problem with a file; reported as `plot_convergence: <file>: <what>`."""

    def __init__(self, path, what):
        super().__init__(f"{path}: {what}")


def read_csv(path):
    """Return {solver: [(iteration, time_s, residual), ...]} in first-seen order."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            reader = csv.DictReader(f, skipinitialspace=True)
            if not reader.fieldnames:
                raise InputError(path, "empty file (no header)")
            fields = [c.strip() for c in reader.fieldnames]
            missing = [c for c in REQUIRED if c not in fields]
            if missing:
                raise InputError(path, "missing required column(s): " + ", ".join(missing))
            reader.fieldnames = fields
            data = {}
            for row in reader:
                name = (row["solver"] or "").strip()
                if not name:
                    continue  # blank line or row without a solver name
                try:
                    vals = tuple(float(row[c]) if (row[c] or "").strip() else math.nan
                                 for c in REQUIRED[1:])
                except ValueError as e:
                    raise InputError(path, f"line {reader.line_num}: bad number ({e})")
                data.setdefault(name, []).append(vals)
    except OSError as e:
        raise InputError(path, e.strerror or str(e))
    if not data:
        raise InputError(path, "no data rows")
    return data


def thin(x, y):
    """Keep at most ~MAX_POINTS points: first, last and a log-spaced subset."""
    n = len(x)
    if n <= MAX_POINTS:
        return x, y
    logspaced = np.geomspace(1, n - 1, MAX_POINTS).astype(int)
    idx = np.unique(np.concatenate(([0, n - 1], logspaced)))
    return x[idx], y[idx]


def plot(data, title):
    fig, (ax_it, ax_t) = plt.subplots(1, 2, figsize=(12, 5), constrained_layout=True)
    for i, (name, rows) in enumerate(data.items()):
        color = f"C{i % 10}"
        it, t, r = (np.array(col, dtype=float) for col in zip(*rows))
        label = name + (" (reaches 0)" if np.any(r == 0) else "")
        # log axes: drop non-positive and non-finite values, and diverged ones beyond 1e100
        # (matplotlib overflows computing ticks near 1e308)
        ok = np.isfinite(r) & (r > 0) & (r < 1e100)
        if name.startswith("direct"):
            # Direct solve: one row = total iterations and time; draw a star.
            it, t, r, ok = it[-1:], t[-1:], r[-1:], ok[-1:]
            star = dict(marker="*", markersize=14, color=color, markeredgecolor="k",
                        linestyle="none")
            ax_it.plot(it[ok], r[ok], label=label, **star)
            good_t = ok & np.isfinite(t) & (t > 0)
            ax_t.plot(t[good_t], r[good_t], **star)
            continue
        order = np.argsort(it, kind="stable")
        it, t, r, ok = it[order], t[order], r[order], ok[order]
        ax_it.plot(*thin(it[ok], r[ok]), color=color, label=label, linewidth=1.2)
        good_t = ok & np.isfinite(t) & (t > 0)  # time 0 cannot sit on a log axis
        ax_t.plot(*thin(t[good_t], r[good_t]), color=color, linewidth=1.2)

    ax_it.set_yscale("log")
    ax_it.set_xlabel("iterations (sweeps)")
    ax_it.set_ylabel("natural-map residual (N)")
    ax_it.set_title("residual vs iterations")
    ax_t.set_xscale("log")
    ax_t.set_yscale("log")
    ax_t.set_xlabel("wall time (s)")
    ax_t.set_ylabel("natural-map residual (N)")
    ax_t.set_title("residual vs wall time")
    for ax in (ax_it, ax_t):
        ax.grid(True, which="major", alpha=0.5)
        ax.grid(True, which="minor", alpha=0.15)
    ax_it.legend(fontsize="small")
    if title:
        fig.suptitle(title)
    return fig


def save_atomic(fig, prefix):
    """Save PNG and SVG to temp files next to the targets, then rename both."""
    outdir = os.path.dirname(os.path.abspath(prefix))
    base = os.path.basename(prefix)
    umask = os.umask(0)
    os.umask(umask)  # mkstemp creates 0600; give outputs normal permissions
    temps = []
    try:
        for ext, kw in (("png", {"dpi": 150}), ("svg", {})):
            fd, tmp = tempfile.mkstemp(dir=outdir, prefix=f".{base}.", suffix=f".{ext}.tmp")
            temps.append((tmp, f"{prefix}.{ext}"))
            os.chmod(tmp, 0o666 & ~umask)
            with os.fdopen(fd, "wb") as f:
                fig.savefig(f, format=ext, **kw)
        for tmp, final in temps:
            os.replace(tmp, final)
    except OSError as e:
        raise InputError(prefix, e.strerror or str(e))
    finally:
        for tmp, _ in temps:  # clean up anything not yet renamed
            if os.path.exists(tmp):
                os.unlink(tmp)


def main():
    ap = argparse.ArgumentParser(description="Plot cbps convergence CSV.")
    ap.add_argument("csv", help="CSV written by `cbps converge`")
    ap.add_argument("out_prefix", help="writes OUT_PREFIX.png and OUT_PREFIX.svg")
    ap.add_argument("--title", default=None, help="figure title")
    args = ap.parse_args()
    try:
        fig = plot(read_csv(args.csv), args.title)
        save_atomic(fig, args.out_prefix)
    except InputError as e:
        print(f"plot_convergence: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
