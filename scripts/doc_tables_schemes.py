"""The generated parts of docs/schemes.md (scripts/doc_tables.py): the step schemes at equal cost
on five scenes and the pendulum wave's periods, from validation/results/schemes/summary.json
(validation/schemes_study.py).

Every column and sentence that says how far the boxes moved gives the largest displacement over
the whole run (every step's end, the study's max_excursion_m and top_max_drift_m); the values at
the end of the run stand beside them, named "end". The targets are judged on the largest.
"""
from doc_tables_common import SourceError, cell, generator, length, need, num, sci, table

SCHEMES = "validation/results/schemes/summary.json"
WAVE_960 = "validation/results/pendulum-wave-dt960/report.json"
WAVE_CENTER = "validation/results/pendulum-wave-center/report.json"
# The step-schemes issue's targets, on the largest displacement of any box over the 10 s run, at
# no more than MAX_SWEEPS sweeps a step.
STACK_TARGET_M = 0.005
PYRAMID_TARGET_M = 0.01
MAX_SWEEPS = 20


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
    """One scene's runs: the columns named (max_excursion_m, ...) after the scheme's."""
    names = {"max_excursion_m": "max excursion", "top_max_drift_m": "top max drift",
             "top_max_sink_m": "top max sink", "end_top_drift_m": "end top drift",
             "end_top_sink_m": "end top sink", "end_max_move_m": "end max move",
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
    return scene_table(src, "stack", ["max_excursion_m", "top_max_drift_m", "end_top_drift_m",
                                      "end_top_sink_m", "max_penetration_m", "energy_change_J",
                                      "exact_velocity_difference", "wall_time_s"])


@generator("schemes-pyramid", SCHEMES)
def _pyramid(src):
    return scene_table(src, "pyramid", ["max_excursion_m", "top_max_drift_m", "end_max_move_m",
                                        "max_penetration_m", "energy_change_J", "wall_time_s"])


@generator("schemes-card-house", SCHEMES)
def _card_house(src):
    return scene_table(src, "card-house", ["max_excursion_m", "top_max_drift_m",
                                           "end_max_move_m", "max_penetration_m",
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


def candidates(src, scene):
    """The completed runs of the scene at no more than MAX_SWEEPS sweeps a step."""
    chosen = [r for r in runs(src, scene) if r["status"] == "completed" and
              r["sweeps_per_step"] <= MAX_SWEEPS and r["integrator"] == "paper"]
    if not chosen:
        raise SourceError(f"{SCHEMES}: no completed run of {scene}")
    return sorted(chosen, key=lambda r: r["max_excursion_m"])


def verdict(src, scene, target, label):
    """Whether any run meets the target (no box further than it from its start at any step),
    which runs, the one that moved its boxes least, and the least of the others."""
    chosen = candidates(src, scene)
    best = chosen[0]
    meeting = [r for r in chosen if r["max_excursion_m"] <= target]
    least = (f"the least any scheme moved a box is {length(best['max_excursion_m'])} "
             f"({best['config']}, {order(best['solver'])}, {best['sweeps_per_step']} sweeps a "
             f"step; largest at t = {num(best['max_excursion_t_s'])} s, "
             f"{length(best['end_max_move_m'])} at the end; its top box up to "
             f"{length(best['top_max_drift_m'])} sideways): `{cell(best['command'])}`")
    if not meeting:
        return f"**not met**: {least}, over the target's {label}"
    configs = []
    for r in meeting:
        if r["config"] not in configs:
            configs.append(r["config"])
    named = []
    for config in configs:
        orders = [order(r["solver"]) for r in meeting if r["config"] == config]
        every = [r for r in chosen if r["config"] == config]
        both = len(every) > 1 and len(orders) == len(every)
        named.append(f"{config} ({'both row orders' if both else ', '.join(orders)})")
    others = [r for r in chosen if r["max_excursion_m"] > target]
    text = f"**met only by {'; '.join(named)}**: {least}"
    if others:
        o = others[0]
        text += (f". Every other run moves a box more than {label}, the least of them "
                 f"{length(o['max_excursion_m'])} ({o['config']}, {order(o['solver'])})")
    return text


@generator("schemes-stack-target", SCHEMES)
def _stack_target(src):
    soft = find(src, "stack", "soft-step 4 x 1", "pgs:contacts_first=on")
    soft_natural = find(src, "stack", "soft-step 4 x 1", "pgs")
    tgs = min((find(src, "stack", "tgs 4 x 5", s) for s in ("pgs", "pgs:contacts_first=on")),
              key=lambda r: r["max_excursion_m"])
    return (f"{verdict(src, 'stack', STACK_TARGET_M, '0.5 cm')}. The soft step at its default "
            f"30 Hz and 4 substeps of 1 sweep and 1 relax sweep ({soft['sweeps_per_step']} "
            f"sweeps a step) moves a box up to {length(soft['max_excursion_m'])} with the "
            f"contact rows first ({length(soft_natural['max_excursion_m'])} in the natural "
            f"order), mostly down: its top box sinks up to {length(soft['top_max_sink_m'])} "
            f"(the soft contacts' sink) and moves up to {length(soft['top_max_drift_m'])} "
            f"sideways (at t = {num(soft['top_max_drift_t_s'])} s), to end "
            f"{length(soft['end_top_drift_m'])} sideways of where it started: "
            f"`{cell(soft['command'])}`. tgs at 4 substeps of 5 sweeps moves a box up to "
            f"{length(tgs['max_excursion_m'])} in its better row order "
            f"({order(tgs['solver'])})")


@generator("schemes-pyramid-target", SCHEMES)
def _pyramid_target(src):
    return verdict(src, "pyramid", PYRAMID_TARGET_M, "1 cm")


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
