"""The generated parts of docs/schemes.md (scripts/doc_tables.py): the step schemes at equal cost
on five scenes and the pendulum wave's periods, from validation/results/schemes/summary.json
(validation/schemes_study.py).
"""
from doc_tables_common import SourceError, cell, generator, length, need, num, sci, table

SCHEMES = "validation/results/schemes/summary.json"


def runs(src, scene=None):
    out = [r for r in need(src.json(SCHEMES), "runs", where=SCHEMES)
           if scene is None or r["scene"] == scene]
    if not out:
        raise SourceError(f"{SCHEMES}: no runs of {scene}")
    return out


def find(src, scene, config, solver, integrator="paper"):
    for r in runs(src, scene):
        if r["config"] == config and r["solver"] == solver and r["integrator"] == integrator:
            return r
    raise SourceError(f"{SCHEMES}: no run {scene}, {config}, {solver}, {integrator}")


def status(r):
    if r["status"] == "completed":
        return "completed"
    return f"{r['status']} at step {r['steps_done']}"


def order(solver):
    return "contacts first" if "contacts_first=on" in solver else "natural"


def scene_table(src, scene, columns):
    """One scene's runs: the columns named (top_drift_m, max_move_m, ...) after the scheme's."""
    names = {"top_drift_m": "top drift", "top_sink_m": "top sink", "max_move_m": "max move",
             "max_penetration_m": "max pen.", "max_constraint_error_m": "max \\|c\\|",
             "energy_change_J": "ΔE J", "exact_velocity_difference": "\\|v2 − v2 exact\\| m/s",
             "period_error": "period error", "wall_time_s": "wall s"}
    rows = []
    for r in runs(src, scene):
        if r["integrator"] != "paper":
            continue
        row = [r["config"], order(r["solver"]), r["sweeps_per_step"], status(r)]
        for c in columns:
            x = r.get(c)
            if x is None:
                row.append("")
            elif c.endswith("_m"):
                row.append(length(x))
            elif c == "wall_time_s":
                row.append(num(x))
            else:
                row.append(sci(x))
        rows.append(row)
    return table(["scheme (substeps x iterations)", "row order", "sweeps a step", "run",
                  *[names[c] for c in columns]], rows, "lrrl" + "r" * len(columns))


@generator("schemes-stack", SCHEMES)
def _stack(src):
    return scene_table(src, "stack", ["top_drift_m", "top_sink_m", "max_penetration_m",
                                      "energy_change_J", "exact_velocity_difference",
                                      "wall_time_s"])


@generator("schemes-pyramid", SCHEMES)
def _pyramid(src):
    return scene_table(src, "pyramid", ["max_move_m", "top_drift_m", "max_penetration_m",
                                        "energy_change_J", "wall_time_s"])


@generator("schemes-card-house", SCHEMES)
def _card_house(src):
    return scene_table(src, "card-house", ["max_move_m", "top_drift_m", "max_penetration_m",
                                           "energy_change_J", "wall_time_s"])


@generator("schemes-chain", SCHEMES)
def _chain(src):
    return scene_table(src, "chain", ["max_constraint_error_m", "energy_change_J",
                                      "exact_velocity_difference", "wall_time_s"])


@generator("schemes-wave", SCHEMES)
def _wave(src):
    rows = []
    for r in runs(src, "pendulum-wave"):
        rows.append([r["config"], r["integrator"], r["sweeps_per_step"], status(r),
                     sci(r["period_error"]), sci(r["mean_period_error"]),
                     length(r["max_constraint_error_m"]), sci(r["energy_change_J"]),
                     num(r["wall_time_s"])])
    return table(["scheme", "integrator", "sweeps a step", "run", "max period error",
                  "mean period error", "max \\|c\\|", "ΔE J", "wall s"], rows, "llrlrrrrr")


@generator("schemes-stack-target", SCHEMES)
def _stack_target(src):
    r = find(src, "stack", "soft-step 4 x 1", "pgs:contacts_first=on")
    natural = find(src, "stack", "soft-step 4 x 1", "pgs")
    return (f"the soft step at 4 substeps of 1 sweep and 1 relax sweep ({r['sweeps_per_step']} "
            f"sweeps a step) holds the 10-box stack's top box within {length(r['top_drift_m'])} "
            f"of where it started over 10 s with the contact rows first "
            f"({length(natural['top_drift_m'])} in the natural order), its tower "
            f"{length(-r['top_sink_m'])} lower: `{cell(r['command'])}`")


@generator("schemes-pyramid-target", SCHEMES)
def _pyramid_target(src):
    best = min((r for r in runs(src, "pyramid") if r["status"] == "completed"),
               key=lambda r: r["max_move_m"])
    return (f"the least any scheme moved a box of the base-20 pyramid in 10 s is "
            f"{length(best['max_move_m'])} ({best['config']}, {order(best['solver'])}; top box "
            f"{length(best['top_drift_m'])} sideways)")
