#!/usr/bin/python3
"""The step schemes at equal cost (docs/schemes.md, issue 33): `cbps run` on five scenes under
the paper's step, tgs, the soft step and XPBD, each at 20 sweeps a step, and the pendulum wave's
periods under each scheme and each integrator.

    /usr/bin/python3 validation/schemes_study.py CBPS OUTDIR [--quick]

CBPS is the cbps executable; OUTDIR receives summary.json (format "cbps-schemes-study/2"; /1
had only the end values, named top_drift_m, top_sink_m and max_move_m, and drift_series sampled
every 0.25 s). --quick runs the stack and the card house only (a minute). Every run's command
is recorded.

Cost is sweeps a step: substeps x iterations x systems (2 under soft-step, a push system and a
relax; 2 under the improved push; 1 otherwise). Measured from each run's summary.json,
steps.csv and trajectory.csv. trajectory.csv holds every body at t = 0 and after every step
(the study passes no --record-every but to the pendulum wave, whose swinging balls it does not
measure by displacement; cbps's default is 1), so the largest excursions are taken over every
step's end: the finest the trajectory gives (positions within a step, between substeps, are
not written). "Displacement" is from the body's position at t = 0.
  max_excursion_m    the largest displacement of any body at any recorded time, m (the
                     measure of the step-schemes targets: "at most 0.5 cm" for the stack,
                     "every box within 1 cm" for the pyramid)
  max_excursion_t_s  the time of that largest displacement, s
  top_max_drift_m    the initially highest body's largest horizontal displacement at any
                     recorded time, m; top_max_drift_t_s its time, s
  top_max_sink_m     its largest downward displacement at any recorded time, m (>= 0; 0 if it
                     never went below its start)
  end_top_drift_m    the initially highest body's horizontal displacement at the end, m
  end_top_sink_m     its vertical displacement at the end, m (negative: down)
  end_max_move_m     the largest displacement of any body at the end, m
  max_penetration_m  the deepest contact found at a step's start, m
  max_constraint_error_m  the largest |c| of a distance row after a step, m
  energy_change_J    energy at the end less at the start, J
  exact_velocity_difference  --check: max |v2 - v2_exact| over every substep, m/s, v2_exact
                     from the direct path's answer to the same substep system (where run)
  excursion_series   (stack, pyramid) [t, e]: e the largest displacement of any body at the
                     recorded times in (t - 0.25 s, t], every 0.25 s (t = 0: 0), so no step's
                     excursion falls between the samples
  drift_series       (stack, pyramid) [t, d]: d the top body's largest horizontal displacement
                     in (t - 0.25 s, t], likewise
  period_error       (pendulum wave) max |T - T_design| / T_design over the balls, from
                     validation/pendulum_wave_report.py
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "scripts"))
from cbps_files import write_json  # noqa: E402

# (label, scheme, substeps, iterations, systems, more options): 20 sweeps a step each, and the
# soft step at 8; the soft step also with stiffer contacts (120 Hz, within a quarter of the
# 600 Hz substep rate).
SCHEMES = [
    ("paper 1 x 20", "paper", 1, 20, 1, []),
    ("tgs 4 x 5", "tgs", 4, 5, 1, []),
    ("tgs 20 x 1", "tgs", 20, 1, 1, []),
    ("soft-step 10 x 1", "soft-step", 10, 1, 2, []),
    ("soft-step 10 x 1, 120 Hz", "soft-step", 10, 1, 2, ["--contact-hertz", "120"]),
    ("soft-step 4 x 1", "soft-step", 4, 1, 2, []),
    ("xpbd 20 x 1", "xpbd", 20, 1, 1, []),
]
# (name, cbps scene arguments, solver orders, --check, excursion and drift series)
SCENES = [
    ("stack", ["stack", "--duration", "10", "--push", "original"],
     ["pgs", "pgs:contacts_first=on"], True, True),
    ("card-house", ["card-house", "--duration", "10"],
     ["pgs", "pgs:contacts_first=on"], False, False),
    ("pyramid", ["pyramid", "--param", "base=20", "--duration", "10", "--push", "original"],
     ["pgs:contacts_first=on"], False, True),
    ("chain", ["chain", "--param", "mass_ratio=100", "--duration", "5"], ["pgs"], True, False),
    ("pendulum-wave", ["pendulum-wave", "--record-every", "4"], ["pgs"], False, False),
]
INTEGRATORS = ["paper", "gyroscopic", "midpoint"]


def positions(folder):
    """Each body's position at every recorded time, from trajectory.csv: {body: [(t, x)]}."""
    series = {}
    with open(os.path.join(folder, "trajectory.csv")) as f:
        for row in csv.DictReader(f):
            series.setdefault(row["body"], []).append(
                (float(row["t"]), [float(row[c]) for c in "xyz"]))
    return series


WINDOW = 0.25  # s: the series' interval


def measures(folder, series_wanted):
    """The displacements of the bodies from their start, at the end and over every recorded time."""
    series = positions(folder)
    first = {b: s[0][1] for b, s in series.items()}
    last = {b: s[-1][1] for b, s in series.items()}
    top = max(first, key=lambda b: first[b][1])
    d = [last[top][k] - first[top][k] for k in range(3)]
    out = {"end_top_drift_m": math.hypot(d[0], d[2]), "end_top_sink_m": d[1],
           "end_max_move_m": max(math.dist(first[b], last[b]) for b in first)}
    # The largest of any body at each recorded time (bodies share the recorded times).
    times = [t for t, _ in series[top]]
    excursion = [0.0] * len(times)
    for b, s in series.items():
        if len(s) != len(times):
            sys.exit(f"{folder}/trajectory.csv: body {b} has {len(s)} rows, body {top} "
                     f"{len(times)}")
        for i, (_, x) in enumerate(s):
            excursion[i] = max(excursion[i], math.dist(first[b], x))
    x0 = first[top]
    drift = [math.hypot(x[0] - x0[0], x[2] - x0[2]) for _, x in series[top]]
    sink = [x0[1] - x[1] for _, x in series[top]]
    i = max(range(len(times)), key=lambda i: excursion[i])
    j = max(range(len(times)), key=lambda j: drift[j])
    out.update({"max_excursion_m": excursion[i], "max_excursion_t_s": round(times[i], 6),
                "top_max_drift_m": drift[j], "top_max_drift_t_s": round(times[j], 6),
                "top_max_sink_m": max(0.0, max(sink))})
    if series_wanted:
        out["excursion_series"] = windowed(times, excursion)
        out["drift_series"] = windowed(times, drift)
    return out


def windowed(times, values):
    """[t, the largest value at the recorded times in (t - WINDOW, t]] for t = 0, WINDOW, ..."""
    out = {}
    for t, v in zip(times, values):
        k = max(0, math.ceil(t / WINDOW - 1e-9))
        out[k] = max(out.get(k, 0.0), v)
    return [[round(k * WINDOW, 6), out[k]] for k in sorted(out)]


def period_error(cbps_python, folder):
    subprocess.run([cbps_python, os.path.join(HERE, "pendulum_wave_report.py"), folder],
                   check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(folder, "report.json")) as f:
        report = json.load(f)
    return report["max_abs_period_error"], report["mean_abs_period_error"]


def run(cbps, scene, args, solver, config, check, series_wanted, integrator="paper"):
    label, scheme, substeps, iterations, systems, more = config
    command = ["run", *args, "--scheme", scheme, "--iterations", str(iterations), "--solver",
               solver, "--integrator", integrator, *more]
    if scheme != "paper":
        command += ["--substeps", str(substeps)]
    if check:
        command += ["--check"]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "run")
        # Exit 1: the divergence guard stopped the run; what it recorded is measured.
        done = subprocess.run([cbps, *command, "--quiet", "--out", out],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if done.returncode not in (0, 1):
            sys.exit(f"cbps {' '.join(command)}: exit {done.returncode}: {done.stderr}")
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        result = {"scene": scene, "config": label, "scheme": scheme, "substeps": substeps,
                  "iterations": iterations, "solver": solver, "integrator": integrator,
                  "sweeps_per_step": substeps * iterations * systems,
                  "command": "cbps " + " ".join(command), "status": summary["status"],
                  "steps_done": summary["steps"],
                  "max_penetration_m": summary["max_penetration"],
                  "max_constraint_error_m": summary["max_constraint_error"],
                  "energy_change_J": summary["energy_final"] - summary["energy_initial"],
                  "wall_time_s": summary["wall_time_s"]}
        if check:
            result["exact_velocity_difference"] = \
                summary["cross_check"]["max_velocity_difference"]
        result.update(measures(out, series_wanted))
        if scene == "pendulum-wave":
            result["period_error"], result["mean_period_error"] = period_error(sys.executable, out)
    print(f"{scene:14} {label:17} {solver:22} {integrator:10} max excursion "
          f"{result['max_excursion_m']:.3g} m at {result['max_excursion_t_s']:.3g} s, top max "
          f"drift {result['top_max_drift_m']:.3g} m, end max move "
          f"{result['end_max_move_m']:.3g} m, energy "
          f"{result['energy_change_J']:+.3g} J, {result['wall_time_s']:.1f} s", file=sys.stderr)
    return result


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    cbps, outdir = sys.argv[1], sys.argv[2]
    quick = "--quick" in sys.argv[3:]
    runs = []
    for scene, args, solvers, check, series in SCENES:
        if quick and scene not in ("stack", "card-house"):
            continue
        for solver in solvers:
            for config in SCHEMES:
                runs.append(run(cbps, scene, args, solver, config, check, series))
    if not quick:
        wave = next(s for s in SCENES if s[0] == "pendulum-wave")
        for integrator in INTEGRATORS[1:]:
            runs.append(run(cbps, "pendulum-wave", wave[1], "pgs", SCHEMES[0], False, False,
                            integrator))
    os.makedirs(outdir, exist_ok=True)
    write_json(os.path.join(outdir, "summary.json"),
               {"format": "cbps-schemes-study/2", "quick": quick, "runs": runs})


if __name__ == "__main__":
    main()
