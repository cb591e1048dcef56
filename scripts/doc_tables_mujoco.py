"""The generated parts of docs/mujoco.md (scripts/doc_tables.py): MuJoCo's forces judged against
the exact answer of MuJoCo's own problem (validation/mujoco_study.py), in cbps's unit-free
verdict (docs/cones.md).
"""
import statistics

from doc_tables_common import SourceError, generator, need, num, sci, table

STUDY = "validation/results/mujoco/study.json"
FORMAT = "cbps-mujoco-study/1"
SOLVED = 1e-9  # the verdict's bound on the unit-free residual (include/cbps/system/unit_free.hpp)
SOLVERS = ("pgs", "cg", "newton")


def _study(src):
    s = src.json(STUDY, FORMAT)
    for m in need(s, "models", where=STUDY):
        for solver in SOLVERS:
            if not need(m, "runs", solver, where=STUDY):
                raise SourceError(f"{STUDY}: {m['name']}: MuJoCo {solver} exported no step with rows")
    return s


def _count(x):
    """An iteration count (a median may be a half): 1,024 or 1.5."""
    return f"{int(x):,}" if float(x).is_integer() else f"{x:,.1f}"


def _rel(x):
    """A unit-free number: plain from 1e-3 up, else scientific."""
    return num(x) if x >= 1e-3 else sci(x)


@generator("mujoco-study-run", STUDY)
def _run(src):
    s = _study(src)
    return (f"{len(s['models'])} models × 3 MuJoCo solvers, {s['steps']:,} steps each, every "
            f"{s['every']}th step judged, ladders to {s['ladder']:,} iterations; "
            f"{s['wall_time_s']:g} s in all on {s['machine']}, {s['date']}, cbps {s['commit']}")


@generator("mujoco-study-distance", STUDY)
def _distance(src):
    """Per model and MuJoCo solver: its answers' residuals and distances from the exact answer."""
    rows = []
    for m in _study(src)["models"]:
        for solver in SOLVERS:
            steps = m["runs"][solver]
            residuals = [st["unit_free"] for st in steps]
            distances = [st["lambda_distance_relative"] for st in steps
                         if st["lambda_distance_relative"] is not None]
            if len(distances) != len(steps):
                raise SourceError(f"{STUDY}: {m['name']} {solver}: a step without direct's answer")
            rows.append([
                m["name"], solver, len(steps),
                f"{sum(r <= SOLVED for r in residuals)}/{len(steps)}",
                _rel(statistics.median(residuals)), _rel(max(residuals)),
                _rel(statistics.median(distances)), _rel(max(distances)),
                _count(statistics.median(st["iterations"] for st in steps)),
            ])
    return table(["model", "MuJoCo solver", "steps", "solved (≤ 1e-9)", "residual, median",
                  "residual, worst", "‖λ − λ*‖∞ / S, median", "‖λ − λ*‖∞ / S, worst",
                  "iterations used, median"], rows, "llrrrrrrr")


def _needed(steps, solver, tol, ladder):
    """Median and worst iterations `solver` needs to reach tol over steps; '> ladder' where a
    step is not reached within the ladder."""
    counts = [st["needed"][solver][tol] for st in steps]
    reached = [c for c in counts if c is not None]
    missing = len(counts) - len(reached)
    if not reached:
        return f"> {ladder:,} on all {len(counts)}"
    text = f"{_count(statistics.median(reached))} / {max(reached):,}"
    return text + (f"; > {ladder:,} on {missing}" if missing else "")


@generator("mujoco-study-needed", STUDY)
def _ladder(src):
    """Per model and MuJoCo solver, on its own run's states: the iterations it needs."""
    s = _study(src)
    rows = []
    for m in s["models"]:
        for solver in SOLVERS:
            steps = m["runs"][solver]
            rows.append([m["name"], solver] +
                        [_needed(steps, solver, f"{t:g}", s["ladder"]) for t in s["tolerances"]])
    return table(["model", "MuJoCo solver"] + [f"to {t:g}: median / worst" for t in s["tolerances"]],
                 rows, "llrrr")


@generator("mujoco-study-cbps", STUDY)
def _cbps(src):
    """cbps's methods on the states of MuJoCo's Newton run: sweeps to 1e-8 and 1e-10."""
    s = _study(src)
    rows = []
    for m in s["models"]:
        for solver, runs in need(m, "cbps", where=STUDY).items():
            cells = []
            for tol in ("1e-08", "1e-10"):
                met = [r["reached"][tol] for r in runs if r["reached"].get(tol) is not None]
                reached = [r["iterations"] for r in met if r["iterations"] is not None]
                missing = len(runs) - len(met)
                if solver == "direct":
                    cells.append(f"{len(met)}/{len(runs)} solved")
                elif reached:
                    cells.append(f"{_count(statistics.median(reached))} / {max(reached):,}" +
                                 (f"; not on {missing}" if missing else ""))
                else:
                    cells.append(f"not on all {len(runs)}")
            worst = max(r["time_s"] for r in runs)
            rows.append([m["name"], solver] + cells + [sci(worst)])
    return table(["model", "cbps method", "to 1e-8: median / worst", "to 1e-10: median / worst",
                  "time, worst (s)"], rows, "llrrr")


@generator("mujoco-study-summary", STUDY)
def _summary(src):
    """What the distance table says, in one sentence per solver, from the numbers."""
    s = _study(src)
    parts = []
    for solver in SOLVERS:
        steps = [(m["name"], st) for m in s["models"] for st in m["runs"][solver]]
        solved = sum(st["unit_free"] <= SOLVED for _, st in steps)
        name, worst = max(steps, key=lambda p: p[1]["unit_free"])
        parts.append(f"MuJoCo's {solver} was solved on {solved} of {len(steps)} steps, its worst "
                     f"answer {name} step {worst['step']} at a residual of "
                     f"{_rel(worst['unit_free'])} after {worst['iterations']} iteration"
                     f"{'' if worst['iterations'] == 1 else 's'}")
    return "; ".join(parts)
