#!/usr/bin/python3
"""Plots the output of validate_pendulum: period_error.png and period_error.svg in OUTDIR.

    /usr/bin/python3 validation/plot_validation.py OUTDIR

OUTDIR holds validation.json and period_errors.csv written by `validate_pendulum --out OUTDIR`.
Left panel: the relative period error |T_measured - T_exact| / T_exact against the time step,
log-log, every ball faintly, the max and the mean over the balls, and reference slopes dt and
dt^2. Right panel: the phase error at the end of the cycle (max over the balls), as measured and
without the half-step lead that semi-implicit Euler takes from rest (see README.md).
Uses Debian's matplotlib and numpy only; exits 2 with a message if the input is missing or bad.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "scripts"))
from cbps_files import save_figure  # noqa: E402  scripts/cbps_files.py

PROG = "plot_validation"


def fail(what, why, code=2):
    print(f"{PROG}: {what}: {why}", file=sys.stderr)
    sys.exit(code)


def load(outdir):
    """validation.json as a dict and period_errors.csv as a structured array."""
    json_path = os.path.join(outdir, "validation.json")
    csv_path = os.path.join(outdir, "period_errors.csv")
    try:
        with open(json_path, encoding="utf-8") as f:
            summary = json.load(f)
    except OSError as e:
        fail(json_path, e.strerror or str(e))
    except json.JSONDecodeError as e:
        fail(json_path, f"not valid JSON (line {e.lineno}: {e.msg})")
    runs = summary.get("runs") if isinstance(summary, dict) else None
    if not isinstance(runs, list) or len(runs) < 1:
        fail(json_path, "no 'runs' array")
    for i, run in enumerate(runs):
        for key in ("dt", "max_rel_error", "mean_rel_error"):
            if not isinstance(run.get(key), (int, float)):
                fail(json_path, f"runs[{i}].{key}: missing or not a number")
    try:
        table = np.genfromtxt(csv_path, delimiter=",", names=True, dtype=float)
    except OSError as e:
        fail(csv_path, e.strerror or str(e))
    except ValueError as e:
        fail(csv_path, f"malformed ({e})")
    needed = ("dt", "k", "rel_error")
    if table.dtype.names is None or any(n not in table.dtype.names for n in needed):
        fail(csv_path, f"header must name the columns {', '.join(needed)}")
    return summary, np.atleast_1d(table)


def save(fig, outdir, name):
    """Writes name.png and name.svg through temporary names, then renames them
    (scripts/cbps_files.py)."""
    paths = [os.path.join(outdir, f"{name}.{ext}") for ext in ("png", "svg")]
    save_figure(fig, {path: {"dpi": 150} for path in paths})
    return paths


def reference_line(ax, dt, anchor_dt, anchor_err, order, style, label):
    """err = anchor_err (dt / anchor_dt)^order across the plotted range of dt."""
    x = np.array([dt.min(), dt.max()])
    ax.plot(x, anchor_err * (x / anchor_dt) ** order, style, color="0.45", lw=1, label=label)


def main():
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        sys.exit(0 if len(sys.argv) == 2 else 2)
    outdir = sys.argv[1]
    summary, table = load(outdir)
    runs = sorted(summary["runs"], key=lambda r: -r["dt"])
    dt = np.array([r["dt"] for r in runs])
    err_max = np.array([r["max_rel_error"] for r in runs])
    err_mean = np.array([r["mean_rel_error"] for r in runs])
    if not (np.all(np.isfinite(err_max)) and np.all(err_max > 0) and np.all(err_mean > 0)):
        fail(os.path.join(outdir, "validation.json"), "period errors must be finite and > 0", 1)

    scene = summary.get("scene", {})
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.6), constrained_layout=True)

    # Left: relative period error, every ball faintly, max and mean over the balls.
    ok = np.isfinite(table["rel_error"]) & (table["rel_error"] != 0)
    ax.loglog(table["dt"][ok], np.abs(table["rel_error"][ok]), ".", ms=2, color="C0",
              alpha=0.25, label="each ball")
    ax.loglog(dt, err_max, "o-", color="C3", label="max over the balls")
    ax.loglog(dt, err_mean, "s-", color="C0", label="mean over the balls")
    reference_line(ax, dt, dt[-1], err_max[-1], 2, "--", r"$\propto \Delta t^2$")
    reference_line(ax, dt, dt[-1], err_max[-1], 1, ":", r"$\propto \Delta t$")
    ax.set_xlabel(r"time step $\Delta t$ (s)")
    ax.set_ylabel(r"$|T_\mathrm{measured} - T_\mathrm{exact}| \,/\, T_\mathrm{exact}$")
    ax.set_title("period error against the exact period\n"
                 r"$T = 4\sqrt{L/g}\,K(\sin(\theta_0/2))$, K from GSL")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    for r in runs:
        if isinstance(r.get("order_max"), (int, float)):
            ax.annotate(f"p={r['order_max']:.2f}", (r["dt"], r["max_rel_error"]),
                        textcoords="offset points", xytext=(4, 4), fontsize=7, color="C3")

    # Right: phase error at t = cycle, as measured and without the half-step lead.
    phase = np.array([r.get("max_phase_error_deg") for r in runs], dtype=float)
    drift = np.array([r.get("max_drift_phase_deg") for r in runs], dtype=float)
    shown = np.isfinite(phase) & (phase > 0)
    if shown.any():
        bx.loglog(dt[shown], phase[shown], "o-", color="C3",
                  label=r"max $|360°(t_k - \mathrm{cycle})/T_k|$")
        good = np.isfinite(drift) & (drift > 0)
        if good.any():
            bx.loglog(dt[good], drift[good], "s-", color="C2",
                      label=r"the same with $t_k + \Delta t/2$ (drift)")
        last = np.flatnonzero(shown)[-1]
        reference_line(bx, dt, dt[last], phase[last], 1, ":", r"$\propto \Delta t$")
        if good.any():
            lg = np.flatnonzero(good)[-1]
            reference_line(bx, dt, dt[lg], drift[lg], 2, "--", r"$\propto \Delta t^2$")
        bx.legend(fontsize=8)
    else:
        bx.text(0.5, 0.5, "the runs did not reach the end of the cycle", ha="center",
                transform=bx.transAxes)
    bx.set_xlabel(r"time step $\Delta t$ (s)")
    bx.set_ylabel("phase error at t = cycle (degrees)")
    bx.set_title(f"realignment after one cycle ({scene.get('cycle_s', '?')} s)")
    bx.grid(True, which="both", alpha=0.3)

    fig.suptitle(f"pendulum wave, attach=center: n = {scene.get('n', '?')}, "
                 f"n0 = {scene.get('n0', '?')}, θ0 = {scene.get('theta0_deg', '?')}°, "
                 f"β = {scene.get('beta', '?')}", fontsize=10)
    for path in save(fig, outdir, "period_error"):
        print(f"{PROG}: wrote {path}")
    finest = runs[-1]
    print(f"{PROG}: finest dt = {finest['dt']:.6g} s: max period error "
          f"{finest['max_rel_error']:.3g}, mean {finest['mean_rel_error']:.3g}, "
          f"observed order {finest.get('order_max')}")


if __name__ == "__main__":
    main()
