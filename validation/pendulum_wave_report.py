#!/usr/bin/python3
"""Report on a run of the paper's pendulum wave (section 10, Figure 10).

    cbps run pendulum-wave --out OUTDIR [--param attach=center ...]
    /usr/bin/python3 validation/pendulum_wave_report.py OUTDIR

Reads OUTDIR/summary.json and OUTDIR/trajectory.csv and writes into OUTDIR:
  figure10.png, figure10.svg  snapshots of the wave at t = 0, 10, 20, 30 s (the recorded sample
                              nearest each time; times beyond the run are skipped), seen from
                              above: x against z, balls as circles, the line of pivots;
  report.md                   settings and summary numbers, per ball the length, design period
                              T_k = cycle/(n0+k), measured period and their relative difference,
                              the phase error at the end of the cycle (if the run reached it);
  report.json                 the numbers report.md shows, machine-readable (format
                              "cbps-pendulum-report/1"; scripts/doc_tables.py reads the committed
                              copy in validation/results/pendulum-wave/).
Every file is written to a temporary name and renamed (scripts/cbps_files.py); in report.json
a number that is not finite is the string "nan", "inf" or "-inf", as cbps writes them, and null
means not measured (no phase error before the end of the cycle). If OUTDIR holds a cbps-manifest.json (the
list of files cbps wrote there), the names of these four files are added to its "files" list, so
that a later `cbps run ... --out OUTDIR` may replace them; without a manifest none is written. Exit status 0, 1 if the trajectory gives
no measurable period, 2 if an input file is missing or malformed. Debian's numpy and matplotlib
only (run it with /usr/bin/python3).
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "scripts"))
from cbps_files import json_ready, save_figure, write_json, write_text  # noqa: E402

PROG = "pendulum_wave_report"
HEADER = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz"
OUTPUT_FILES = ("report.md", "report.json", "figure10.png", "figure10.svg")  # what this writes
MANIFEST = "cbps-manifest.json"  # cbps's list of the files it wrote into an output folder
SNAPSHOT_TIMES = (0.0, 10.0, 20.0, 30.0)  # s, as in the paper's Figure 10
G_DEFAULT = 9.81  # m/s², the built-in scene's |gravity| when summary.json does not give it


class InputError(Exception):
    """A missing or malformed input file: exit status 2."""


class MeasureError(Exception):
    """The trajectory gives no measurable period: exit status 1."""


# ---------------------------------------------------------------------------------------------
# Exact pendulum: K(k) by the arithmetic-geometric mean, K = π / (2 AGM(1, sqrt(1 − k²))).


def elliptic_K(k):
    a, b = 1.0, math.sqrt((1.0 - k) * (1.0 + k))
    for _ in range(64):
        if abs(a - b) <= 1e-16 * a:
            break
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return math.pi / (2.0 * a)


def design_length(T, g, theta0):
    """Pivot-to-centre length whose exact period is T: L = g (T / (4 K(sin(θ0/2))))², m."""
    return g * (T / (4.0 * elliptic_K(math.sin(0.5 * theta0)))) ** 2


def double_pendulum_period(l, radius, g, theta0):
    """Slow-mode period of a massless rope of length l ending on the top of a solid ball
    (radius r, moment of inertia I = (2/5) m r² about its centre), s.

    Angles φ (rope) and ψ (rope end to centre); linearised T = ½ m (l φ' + r ψ')² + ½ I ψ'²,
    V = ½ m g (l φ² + r ψ²). With ρ² = I/m, det(K − ω² M) = 0 reads
        l ρ² ω⁴ − g (r² + ρ² + l r) ω² + g² r = 0,
    whose smaller root (rationalised) is ω² = 2 g r / (s + sqrt(s² − 4 l ρ² r)), s = r² + ρ² + l r;
    ρ → 0 gives g / L, the simple pendulum. The amplitude factor 2K(sin(θ0/2))/π of the simple
    pendulum is applied to it: an estimate, not an exact period (the double pendulum is not
    isochronous in the same way, and the release excites the fast mode a little too).
    """
    r = radius
    rho2 = 0.4 * r * r
    s = r * r + rho2 + l * r
    omega2 = 2.0 * g * r / (s + math.sqrt(s * s - 4.0 * l * rho2 * r))
    return 2.0 * math.pi / math.sqrt(omega2) * 2.0 * elliptic_K(math.sin(0.5 * theta0)) / math.pi


# ---------------------------------------------------------------------------------------------
# Input.


def number(text, what):
    """A number such as 0.25 or a fraction such as 1/240."""
    try:
        if isinstance(text, (int, float)) and not isinstance(text, bool):
            value = float(text)
        elif isinstance(text, str) and "/" in text:
            p, q = text.split("/", 1)
            value = float(p) / float(q)
        else:
            value = float(text)
    except (TypeError, ValueError, ZeroDivisionError):
        raise InputError(f"{what}: expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise InputError(f"{what}: not finite ({text!r})")
    return value


def load_summary(path):
    try:
        with open(path, encoding="utf-8") as f:
            summary = json.load(f)
    except FileNotFoundError:
        raise InputError(f"{path}: missing (run `cbps run pendulum-wave --out DIR` first)") \
            from None
    except OSError as e:
        raise InputError(f"{path}: {e.strerror or e}") from None
    except json.JSONDecodeError as e:
        raise InputError(f"{path}: not valid JSON (line {e.lineno}: {e.msg})") from None
    if not isinstance(summary, dict):
        raise InputError(f"{path}: expected a JSON object")
    if summary.get("scene") != "pendulum-wave":
        raise InputError(f"{path}: scene is {summary.get('scene')!r}, expected 'pendulum-wave'")
    params = summary.get("parameters")
    if not isinstance(params, dict):
        raise InputError(f"{path}: no 'parameters' object")
    for name in ("n", "n0", "cycle", "theta0_deg", "attach", "radius", "spacing"):
        if name not in params:
            raise InputError(f"{path}: parameters.{name} missing")
    s = {
        "n": int(number(params["n"], f"{path}: parameters.n")),
        "n0": int(number(params["n0"], f"{path}: parameters.n0")),
        "cycle": number(params["cycle"], f"{path}: parameters.cycle"),
        "theta0": math.radians(number(params["theta0_deg"], f"{path}: parameters.theta0_deg")),
        "attach": str(params["attach"]),
        "radius": number(params["radius"], f"{path}: parameters.radius"),
        "spacing": number(params["spacing"], f"{path}: parameters.spacing"),
        "dt": number(summary.get("dt"), f"{path}: dt"),
        "g": G_DEFAULT,
    }
    if s["attach"] not in ("top", "center"):
        raise InputError(f"{path}: parameters.attach is {s['attach']!r}, expected top or center")
    gravity = summary.get("gravity")
    if isinstance(gravity, list) and len(gravity) == 3:
        s["g"] = math.sqrt(sum(number(c, f"{path}: gravity") ** 2 for c in gravity))
    return summary, s


def load_trajectory(path, n):
    """Times t (m,) and positions x, y, z (m × n) of the n balls."""
    try:
        with open(path, encoding="utf-8") as f:
            header = f.readline().strip()
    except FileNotFoundError:
        raise InputError(f"{path}: missing (run `cbps run pendulum-wave --out DIR` first)") \
            from None
    except OSError as e:
        raise InputError(f"{path}: {e.strerror or e}") from None
    if header != HEADER:
        raise InputError(f"{path}: line 1: expected the header {HEADER!r}, got {header[:80]!r}")
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=1, usecols=range(9), ndmin=2)
    except ValueError as e:
        raise InputError(f"{path}: malformed ({e})") from None
    if data.shape[0] == 0 or data.shape[0] % n != 0:
        raise InputError(f"{path}: {data.shape[0]} rows, not a whole number of samples of "
                         f"{n} bodies")
    if not np.all(np.isfinite(data)):
        row = int(np.flatnonzero(~np.all(np.isfinite(data), axis=1))[0]) + 2
        raise InputError(f"{path}: line {row}: a value is not finite")
    m = data.shape[0] // n
    data = data.reshape(m, n, 9)
    if not np.array_equal(data[:, :, 1], np.broadcast_to(np.arange(n), (m, n))):
        raise InputError(f"{path}: rows must list bodies 0..{n - 1} in order at every time")
    t = data[:, 0, 0]
    if not np.all(data[:, :, 0] == t[:, None]) or (m > 1 and not np.all(np.diff(t) > 0)):
        raise InputError(f"{path}: times must be shared by the bodies of a sample and increase")
    return t, data[:, :, 2], data[:, :, 3], data[:, :, 4], data[0, :, 5:9]


# ---------------------------------------------------------------------------------------------
# Measurements.


def upward_crossings(t, x):
    """Times where x goes from < 0 to ≥ 0: the root of the cubic through the four samples
    around the sign change (Lagrange on the actual times), found by bisection; the chord's root
    at the ends of the record."""
    idx = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    times = t[idx] + (t[idx + 1] - t[idx]) * x[idx] / (x[idx] - x[idx + 1])  # chords
    inner = idx[(idx >= 1) & (idx + 2 < len(x))]
    if inner.size:
        cols = inner[:, None] + np.arange(-1, 3)[None, :]
        nodes, values = t[cols], x[cols]  # (m, 4)

        def p(u):  # the cubics at u (m,)
            total = np.zeros_like(u)
            for j in range(4):
                w = values[:, j].copy()
                for m in range(4):
                    if m != j:
                        w *= (u - nodes[:, m]) / (nodes[:, j] - nodes[:, m])
                total += w
            return total

        lo, hi = t[inner].copy(), t[inner + 1].copy()  # p(lo) < 0 ≤ p(hi)
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            below = p(mid) < 0.0
            lo = np.where(below, mid, lo)
            hi = np.where(below, hi, mid)
        times[np.isin(idx, inner)] = 0.5 * (lo + hi)
    return times


def parabola_vertex(t3, x3):
    """Vertex time of the parabola through three samples (times need not be uniform)."""
    (t0, t1, t2), (x0, x1, x2) = t3, x3
    d1 = (x1 - x0) / (t1 - t0)
    d2 = (x2 - x1) / (t2 - t1)
    c = (d2 - d1) / (t2 - t0)  # second divided difference: x ≈ … + c (t − t0)(t − t1)
    if c >= 0.0:
        return math.nan  # not a maximum
    return 0.5 * (t0 + t1) - d1 / (2.0 * c)


def maximum_near(t, x, t_target, half_window, up, period):
    """Time of the maximum of x nearest t_target (within ±half_window) and how it was found.
    "parabola": the vertex of the parabola through a sampled local maximum and its neighbours.
    "crossings": the maximum is not bracketed by samples (it lies in the last interval or
    beyond the end of the record), so it is placed a quarter period after the last upward zero
    crossing, t_c + T/4 (a pendulum released from rest swings symmetrically about its
    extremes; measured T), shifted by whole periods to the one nearest t_target; used only when
    the window holds no sampled maximum and that time lies after the last-but-one sample.
    Returns (nan, None) when neither finds one."""
    best, method = math.nan, None
    i = np.flatnonzero(np.abs(t - t_target) <= half_window)
    i = i[(i >= 1) & (i <= len(x) - 2)]
    peaks = i[(x[i] >= x[i - 1]) & (x[i] > x[i + 1])]
    for j in peaks:
        t_j = parabola_vertex(t[j - 1:j + 2], x[j - 1:j + 2])
        if math.isnan(best) or abs(t_j - t_target) < abs(best - t_target):
            best, method = t_j, "parabola"
    if method is None and len(up) > 0 and math.isfinite(period):
        t_c = float(up[-1]) + 0.25 * period
        t_c += period * round((t_target - t_c) / period)
        if t_c > t[-2]:
            best, method = t_c, "crossings"
    return best, method


def string_length(centre, q, pivot, r):
    """Distance from the pivot to the ball's top point, the body point (0, r, 0) turned by the
    unit quaternion q = (w, x, y, z): R(q) (0, 1, 0) = (2(xy − wz), 1 − 2(x² + z²), 2(yz + wx))."""
    w, qx, qy, qz = q
    up = np.array([2 * (qx * qy - w * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + w * qx)])
    return float(np.linalg.norm(centre + r * up - pivot))


def measure(s, t, x, y, z, q0):
    """Per ball: length, design and measured periods, phase error at t = cycle."""
    n, cycle, theta0, g = s["n"], s["cycle"], s["theta0"], s["g"]
    reached = t[-1] >= cycle - 1e-9 * cycle
    balls = []
    for k in range(n):
        T_design = cycle / (s["n0"] + k)
        L = design_length(T_design, g, theta0)
        pivot = np.array([0.0, 0.0, k * s["spacing"]])
        L0 = float(np.linalg.norm(np.array([x[0, k], y[0, k], z[0, k]]) - pivot))
        up = upward_crossings(t, x[:, k])
        T_meas = (up[-1] - up[0]) / (len(up) - 1) if len(up) >= 2 else math.nan
        ball = {"k": k, "L": L, "L0": L0, "T_design": T_design, "T_measured": T_meas,
                "crossings": len(up), "rel": (T_meas - T_design) / T_design,
                "phase_deg": math.nan, "phase_method": None}
        if s["attach"] == "top":
            centre = np.array([x[0, k], y[0, k], z[0, k]])
            ball["l"] = string_length(centre, q0[k], pivot, s["radius"])
            ball["T_double"] = double_pendulum_period(ball["l"], s["radius"], g, theta0)
        if reached:
            t_k, ball["phase_method"] = maximum_near(t, x[:, k], cycle, 0.5 * T_design, up,
                                                     T_meas)
            # Modulo whole swings: a phase in [−180°, 180°).
            ball["phase_deg"] = (360.0 * (t_k - cycle) / T_design + 180.0) % 360.0 - 180.0
        balls.append(ball)
    if all(math.isnan(b["T_measured"]) for b in balls):
        raise MeasureError("no ball crosses x = 0 twice: the run is too short to measure a "
                           "period (the longest is %.3g s)" % balls[0]["T_design"])
    return balls, reached


# ---------------------------------------------------------------------------------------------
# Output.


def nanmax_abs(values):
    a = np.abs(np.array(values, dtype=float))
    return float(np.nanmax(a)) if np.any(np.isfinite(a)) else math.nan


def draw_figure(outdir, s, t, x, z):
    times = [tt for tt in SNAPSHOT_TIMES if tt <= t[-1] + 0.5 * (t[1] - t[0] if len(t) > 1 else 0)]
    fig, axes = plt.subplots(len(times), 1, figsize=(10, 0.8 + 1.25 * len(times)), squeeze=False,
                             sharex=True, constrained_layout=True)
    r = s["radius"]
    z_pivot = np.arange(s["n"]) * s["spacing"]
    x_lim = 1.15 * max(float(np.max(np.abs(x))), r) + r
    for ax, target in zip(axes[:, 0], times):
        i = int(np.argmin(np.abs(t - target)))
        ax.plot([z_pivot[0], z_pivot[-1]], [0.0, 0.0], "-", color="0.3", lw=1.0,
                label="pivots")
        ax.plot(z_pivot, np.zeros_like(z_pivot), "|", color="0.3", ms=5)
        for k in range(s["n"]):  # the strings, seen from above
            ax.plot([z_pivot[k], z[i, k]], [0.0, x[i, k]], "-", color="0.75", lw=0.6)
        circles = [Circle((z[i, k], x[i, k]), r) for k in range(s["n"])]
        ax.add_collection(PatchCollection(circles, facecolor="C0", edgecolor="k", lw=0.5))
        ax.set_aspect("equal")
        ax.set_ylim(-x_lim, x_lim)
        ax.set_ylabel("x (m)")
        ax.set_title(f"t = {t[i]:.3f} s", fontsize=9, loc="left")
    axes[-1, 0].set_xlabel("z (m), along the line of pivots")
    axes[-1, 0].set_xlim(z_pivot[0] - 2 * r, z_pivot[-1] + 2 * r)
    fig.suptitle(f"Pendulum wave seen from above (paper Figure 10): {s['n']} balls, "
                 f"attach={s['attach']}, θ0 = {math.degrees(s['theta0']):g}°", fontsize=10)
    save_figure(fig, {os.path.join(outdir, f"figure10.{ext}"): {"dpi": 150}
                      for ext in ("png", "svg")})
    plt.close(fig)
    return [(tt, t[int(np.argmin(np.abs(t - tt)))]) for tt in times]


def fmt(v, spec):
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, spec)


def write_report(outdir, summary, s, balls, reached, snapshot_times, t):
    top = s["attach"] == "top"
    rel = [b["rel"] for b in balls]
    phases = [b["phase_deg"] for b in balls]
    solver = summary.get("solver")
    if isinstance(solver, dict):
        solver = ", ".join(f"{k} {v}" for k, v in solver.items())
    L = []
    L.append("# Pendulum wave (paper section 10, Figure 10)\n")
    L.append(f"Run in `{outdir}`, written by `cbps run pendulum-wave`; this report by "
             "`validation/pendulum_wave_report.py`.\n")
    L.append("## Settings\n")
    L.append("| parameter | value |\n|---|---|")
    for name, value in summary["parameters"].items():
        L.append(f"| {name} | {value} |")
    L.append("")
    L.append("## Summary numbers (summary.json)\n")
    L.append("| quantity | value |\n|---|---|")
    for key, unit in (("steps", ""), ("dt", "s"), ("iterations_total", ""), ("wall_time_s", "s"),
                      ("max_constraint_error", "m"), ("energy_initial", "J"),
                      ("energy_final", "J")):
        if key in summary:
            L.append(f"| {key} | {summary[key]} {unit} |")
    L.append(f"| solver | {solver} |")
    if isinstance(summary.get("stages"), list):
        L.append(f"| stages | {'; '.join(str(x) for x in summary['stages'])} |")
    spacing = fmt(t[1] - t[0] if len(t) > 1 else math.nan, ".6g")
    L.append(f"| recorded samples | {len(t)} (every {spacing} s), t = 0 … {t[-1]:.6g} s |")
    L.append("")

    L.append("## Periods\n")
    L.append("Ball k hangs at pivot-to-centre length L_k = g (T_k / (4 K(sin(θ0/2))))², chosen so "
             "that an exact simple pendulum of that length released from rest at θ0 has the "
             "design period T_k = cycle/(n0+k) (K by the AGM; g = "
             f"{s['g']:g} m/s²). The measured period is the mean time between upward zero "
             "crossings of the ball's x (cubic interpolation between samples).\n")
    L.append(f"Largest |L_k − initial pivot-to-centre distance| in the trajectory: "
             f"{nanmax_abs([b['L'] - b['L0'] for b in balls]):.3g} m.\n")
    if top:
        first, last = balls[0], balls[-1]
        slow_first = (first["T_double"] - first["T_design"]) / first["T_design"]
        slow_last = (last["T_double"] - last["T_design"]) / last["T_design"]
        L.append("**attach=top (as in the paper's picture):** the string ends at the top of the "
                 "ball, so each pendulum is a massless rope of length l holding a rigid ball "
                 "that can turn about its top point: a double pendulum. The scene chooses l so "
                 "that the slow mode has the design period and releases the ball in that mode's "
                 "shape (src/scene/builtin/pendulum_wave.cpp). Checked here independently: l is "
                 "measured from the first sample of the trajectory (pivot to the ball's top "
                 "point), and the linearised double pendulum (rope angle φ, ball angle ψ, "
                 "I = 2/5 m r²) gives the slow mode ω² = 2 g r / (s + sqrt(s² − 4 l ρ² r)), "
                 "s = r² + ρ² + l r, ρ² = 2/5 r², times the simple pendulum's amplitude factor "
                 "2K/π (an estimate for the double pendulum); this is the column T_double. It "
                 f"differs from the design by {slow_first:+.2e} (ball 0) to {slow_last:+.2e} "
                 f"(ball {last['k']}).\n")
    else:
        L.append("**attach=center:** the string ends at the ball's centre, so each ball is an "
                 "exact simple pendulum with period T_k; the differences below are the "
                 "simulation's own error.\n")
    header = "| k | L_k (m) | T_k design (s) | T measured (s) | (T meas − T_k)/T_k |"
    rule = "|---:|---:|---:|---:|---:|"
    if top:
        header += " T_double (s) | (T meas − T_double)/T_double |"
        rule += "---:|---:|"
    if reached:
        header += " phase at cycle (°) |"
        rule += "---:|"
    L.append(header)
    L.append(rule)
    for b in balls:
        row = (f"| {b['k']} | {b['L']:.6f} | {b['T_design']:.6f} | {fmt(b['T_measured'], '.6f')} "
               f"| {fmt(b['rel'], '+.3e')} |")
        if top:
            row += (f" {b['T_double']:.6f} | "
                    f"{fmt((b['T_measured'] - b['T_double']) / b['T_double'], '+.3e')} |")
        if reached:
            mark = " †" if b["phase_method"] == "crossings" else ""
            row += f" {fmt(b['phase_deg'], '+.2f')}{mark} |"
        L.append(row)
    L.append("")
    L.append(f"Max |(T measured − T_k)/T_k| = {nanmax_abs(rel):.3e}, mean "
             f"{float(np.nanmean(np.abs(rel))):.3e} over {len(balls)} balls.\n")
    if top:
        dp = [(b["T_measured"] - b["T_double"]) / b["T_double"] for b in balls]
        L.append(f"Against the double-pendulum estimate T_double: max |difference| "
                 f"{nanmax_abs(dp):.3e}.\n")

    L.append("## Realignment at the end of the cycle\n")
    if reached:
        L.append(f"At t = cycle = {s['cycle']:g} s every ball should be back at its release point "
                 "(maximum of x). Phase error of ball k: 360° (t_k − cycle)/T_k, t_k the maximum "
                 "of x nearest t = cycle, refined by a parabola through three samples"
                 + ("; † where the record ends before that maximum is bracketed by samples, "
                    "t_k = (last upward zero crossing) + T_measured/4 instead"
                    if any(b["phase_method"] == "crossings" for b in balls) else "")
                 + f". Max |phase error| = {nanmax_abs(phases):.3f}°, mean "
                 f"{float(np.nanmean(np.abs(phases))):.3f}°.\n")
        if not top:
            L.append("Semi-implicit Euler started from rest runs half a step ahead "
                     f"(x_n ≈ x_exact((n + ½) dt)); that alone is 360° · dt/2 / T_k = "
                     f"{180 * s['dt'] / balls[0]['T_design']:.3f}° to "
                     f"{180 * s['dt'] / balls[-1]['T_design']:.3f}° (see validation/README.md).\n")
    else:
        L.append(f"The run ended at t = {t[-1]:.6g} s, before the end of the cycle "
                 f"({s['cycle']:g} s): no realignment to measure.\n")

    L.append("## Figure\n")
    skipped = [tt for tt in SNAPSHOT_TIMES if tt not in [target for target, _ in snapshot_times]]
    L.append("Snapshots seen from above (x against z) at t = "
             + ", ".join(f"{actual:.3f}" for _, actual in snapshot_times)
             + " s, the recorded samples nearest "
             + ", ".join(f"{target:g}" for target, _ in snapshot_times) + " s"
             + (f" ({', '.join(f'{tt:g}' for tt in skipped)} s: beyond the run)" if skipped else "")
             + ".\n")
    L.append("![Pendulum wave, Figure 10](figure10.png)\n")
    write_text(os.path.join(outdir, "report.md"), "\n".join(L))
    return nanmax_abs(rel), nanmax_abs(phases) if reached else math.nan


def write_report_json(outdir, summary, s, balls, reached, t, steps_wall_s):
    """report.json: the numbers of report.md, and the run's own timing fields with what each
    one measures."""
    rel = [b["rel"] for b in balls]
    phases = [b["phase_deg"] for b in balls]
    stage = summary.get("stage_times_s")
    timing = {
        "wall_time_s": summary.get("wall_time_s"),
        "wall_time_s_means": "summary.json wall_time_s: the step loop of `cbps run`, i.e. every "
                             "step with its --check cross-check, plus writing each step's rows "
                             "of steps.csv and trajectory.csv; not the start-up, not closing "
                             "the files, not summary.json",
        "steps_wall_time_s": steps_wall_s,
        "steps_wall_time_s_means": "the sum of steps.csv wall_time_s: the steps themselves, with "
                                   "the --check cross-check, without any file writing",
        "stage_times_s": stage,
        "stage_time_sum_s": sum(stage.values()) if isinstance(stage, dict) else None,
        "stage_time_sum_s_means": "the sum of summary.json stage_times_s: the solver's stages "
                                  "(collision, rows, assembly, solve, integrate) only, without "
                                  "the --check cross-check and without file writing",
    }
    report = {
        "format": "cbps-pendulum-report/1",
        "parameters": summary.get("parameters"),
        "dt": s["dt"],
        "steps": summary.get("steps"),
        "bodies": summary.get("bodies"),
        "rows": summary.get("rows"),
        "solver": summary.get("solver"),
        "g": s["g"],
        "attach": s["attach"],
        "samples": len(t),
        "t_end": float(t[-1]),
        "reached_cycle": bool(reached),
        "timing": timing,
        "max_constraint_error": summary.get("max_constraint_error"),
        "max_residual": summary.get("max_residual"),
        "cross_check": summary.get("cross_check"),
        "energy_initial": summary.get("energy_initial"),
        "energy_final": summary.get("energy_final"),
        "max_abs_period_error": nanmax_abs(rel),
        "mean_abs_period_error": float(np.nanmean(np.abs(rel))),
        "max_abs_phase_deg": nanmax_abs(phases) if reached else None,
        "mean_abs_phase_deg": float(np.nanmean(np.abs(phases))) if reached else None,
        "balls": [{key: b.get(key)
                   for key in ("k", "L", "T_design", "T_measured", "rel", "crossings",
                               "phase_deg", "phase_method", "l", "T_double") if key in b}
                  for b in balls],
    }
    if s["attach"] == "top":
        report["max_abs_double_error"] = nanmax_abs(
            [(b["T_double"] - b["T_design"]) / b["T_design"] for b in balls])
    report = json_ready(report)  # non-finite floats as "nan", "inf", "-inf"
    balls_json = report.pop("balls")
    text = json.dumps(report, indent=1, allow_nan=False)  # then the balls, one line each
    text = (text[:-2] + ',\n "balls": [\n  '
            + ",\n  ".join(json.dumps(b, separators=(",", ":"), allow_nan=False)
                            for b in balls_json) + "\n ]\n}\n")
    json.loads(text)  # still valid JSON
    write_text(os.path.join(outdir, "report.json"), text)


def steps_wall_time(path):
    """Sum of the wall_time_s column of steps.csv (s), or None when the run has none
    (--no-timing) or the file is missing."""
    try:
        with open(path, encoding="utf-8") as f:
            header = f.readline().strip().split(",")
            if "wall_time_s" not in header:
                return None
            col = header.index("wall_time_s")
            return float(sum(float(line.split(",")[col]) for line in f if line.strip()))
    except (OSError, ValueError, IndexError):
        return None


def read_manifest(outdir):
    """The folder's cbps-manifest.json as a dict, or None when there is none. A manifest that
    is not {"format": ..., "files": [names]} is an input error: nothing is written then."""
    path = os.path.join(outdir, MANIFEST)
    try:
        with open(path, encoding="utf-8") as f:
            manifest = json.load(f)
    except FileNotFoundError:
        return None
    except OSError as e:
        raise InputError(f"{path}: {e.strerror or e}") from None
    except json.JSONDecodeError as e:
        raise InputError(f"{path}: not valid JSON (line {e.lineno}: {e.msg})") from None
    if not isinstance(manifest, dict) or not isinstance(manifest.get("files"), list) \
            or not all(isinstance(x, str) for x in manifest["files"]):
        raise InputError(f"{path}: expected an object with a \"files\" list of names")
    return manifest


def add_to_manifest(outdir, manifest):
    """Adds OUTPUT_FILES to the manifest's "files" (keeping its order and every other field),
    written to a temporary file in the same folder and renamed over it."""
    for name in OUTPUT_FILES:
        if name not in manifest["files"]:
            manifest["files"].append(name)
    write_json(os.path.join(outdir, MANIFEST), manifest, indent=2)


def main():
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip(), file=sys.stdout if len(sys.argv) == 2 else sys.stderr)
        return 0 if len(sys.argv) == 2 else 2
    outdir = sys.argv[1]
    try:
        if not os.path.isdir(outdir):
            raise InputError(f"{outdir}: no such directory")
        summary, s = load_summary(os.path.join(outdir, "summary.json"))
        t, x, y, z, q0 = load_trajectory(os.path.join(outdir, "trajectory.csv"), s["n"])
        balls, reached = measure(s, t, x, y, z, q0)
        manifest = read_manifest(outdir)  # before anything is written
        snapshots = draw_figure(outdir, s, t, x, z)
        max_rel, max_phase = write_report(outdir, summary, s, balls, reached, snapshots, t)
        write_report_json(outdir, summary, s, balls, reached, t,
                          steps_wall_time(os.path.join(outdir, "steps.csv")))
        if manifest is not None:
            add_to_manifest(outdir, manifest)
    except InputError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 2
    except MeasureError as e:
        print(f"{PROG}: {outdir}: {e}", file=sys.stderr)
        return 1
    print(f"{PROG}: {s['n']} balls, attach={s['attach']}, t = 0 … {t[-1]:.6g} s")
    print(f"  max |T measured − T_k| / T_k = {max_rel:.3e}")
    if s["attach"] == "top":
        worst = max(balls, key=lambda b: abs(b["T_double"] - b["T_design"]))
        print(f"  (attach=top is a double pendulum: the slow mode of the measured string lengths "
              f"is within {abs(worst['T_double'] - worst['T_design']) / worst['T_design']:.1e} "
              f"of T_k)")
    if reached:
        print(f"  max |phase error| at t = cycle = {max_phase:.3f} deg")
    else:
        print(f"  run ended before t = cycle = {s['cycle']:g} s: no phase error")
    print(f"  wrote {os.path.join(outdir, 'report.md')}, report.json, figure10.png, figure10.svg"
          + (f"; listed them in {MANIFEST}" if manifest is not None else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
