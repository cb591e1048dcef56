"""The generated parts of docs/schemes.md (scripts/doc_tables.py): the step schemes at equal cost
on five scenes and the pendulum wave's periods, from validation/results/schemes/summary.json
(validation/schemes_study.py).
"""
from doc_tables_common import SourceError, cell, generator, length, need, num, sci, table

SCHEMES = "validation/results/schemes/summary.json"
WAVE_960 = "validation/results/pendulum-wave-dt960/report.json"
WAVE_CENTER = "validation/results/pendulum-wave-center/report.json"


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


@generator("schemes-wave-note", SCHEMES, WAVE_960, WAVE_CENTER)
def _wave_note(src):
    paper = find(src, "pendulum-wave", "paper 1 x 20", "pgs")
    tgs = find(src, "pendulum-wave", "tgs 4 x 5", "pgs")
    dt960 = need(src.json(WAVE_960), "max_abs_period_error", where=WAVE_960)
    center = need(src.json(WAVE_CENTER), "max_abs_period_error", where=WAVE_CENTER)
    return (f"The paper's step at dt 1/240 errs by {sci(paper['period_error'])} at most; tgs "
            f"with 4 substeps errs by {sci(tgs['period_error'])}, as the paper's step at dt "
            f"1/960 does ({sci(dt960)}, validation/results/pendulum-wave-dt960): a substep of h "
            f"is the paper's step of h here. Neither tgs nor XPBD errs more than the paper's step at "
            f"its own substep; none reaches the 1/240 step's {sci(paper['period_error'])}, because that "
            f"error is mostly not the step's: with the string at the ball's top each ball is a "
            f"double pendulum, and the same step with the string at the centre (exact simple "
            f"pendulums) errs by {sci(center)} (validation/results/pendulum-wave-center). Between "
            f"1/60 and 1/960 the step's own two errors, the Baumgarte bias's and semi-implicit "
            f"Euler's, have opposite signs ([validation.md](validation.md)), so a smaller step "
            f"need not err less.")
