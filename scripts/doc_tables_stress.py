"""The generated parts of docs/stress.md (scripts/doc_tables.py): the stress catalogue's table and
counts, and its single numbers, <!-- value: stress:CASE:SOLVER:FIELD:FORMAT -->.
"""
from doc_tables_common import (  # scripts/doc_tables_common.py
    SourceError, cell, cg, generator, length, need, num, sci, table)


# ---------------------------------------------------------------------------------------------
# The stress catalogue (`cbps stress --out`: validation/results/stress/summary.json).

STRESS = "validation/results/stress/summary.json"


@generator("stress", STRESS)
def _stress(src):
    """The table `cbps stress` prints (src/cli/stress.cpp), from its summary.json."""
    rows = []
    for r in need(src.json(STRESS), "results", where=STRESS):
        if r["status"] == "skipped":
            rows.append((r["case"], r["solver"], "skipped", "", "", "", "", "", "",
                         cell(r.get("note", ""))))
            continue
        status = {"stable": "yes", "unstable": "NO"}.get(r["status"], r["status"])
        if r["status"] in ("diverged", "budget"):
            status += f" @{r['steps_done']}"
        c = r["condition"]
        cond = cg(c["value"]) + ("" if c["exact"] else "~")
        if c["nullity"] > 0:
            cond += f" (null {c['nullity']})"
        energy = r["energy_change_J"]
        if r["status"] == "diverged":
            note = r.get("note", "")
            head = note.find("): ")
            judged = note if head < 0 else "guard: " + note[head + 3:]
        else:
            judged = r["measure"]
        rows.append((r["case"], r["solver"], status, cg(r["max_constraint_error_m"]),
                     cg(r["max_penetration_m"]), cg(energy), cg(r["final_residual_N"]), cond,
                     cg(r["wall_time_s"]), cell(judged)))
    return table(["case", "solver", "stable", "max \\|c\\| m", "max pen. m", "ΔE J",
                  "residual N", "cond(A)", "wall s", "judged on"], rows, "lllrrrrrrl")


@generator("stress-counts", STRESS)
def _stress_counts(src):
    s = src.json(STRESS)
    c = need(s, "counts", where=STRESS)
    n = len(s["results"])
    return (f"{n} runs: {c['stable']} stable, {c['unstable']} unstable, {c['diverged']} stopped "
            f"by the divergence guard, {c['other']} skipped or out of budget; "
            f"{s['wall_time_s']:.0f} s in all")


def stress_value(name, src, where):
    """stress:CASE:SOLVER:FIELD:FORMAT, one number of validation/results/stress/summary.json."""
    parts = name.split(":")
    if len(parts) != 5:
        raise SourceError(f"{where}: {name}: expected stress:CASE:SOLVER:FIELD:FORMAT")
    _, case, solver, field, form = parts
    for r in need(src.json(STRESS), "results", where=STRESS):
        if r["case"] == case and r["solver"] == solver:
            x = need(r, *field.split("."), where=f"{STRESS} ({case}, {solver})")
            break
    else:
        raise SourceError(f"{where}: {name}: no run {case} / {solver} in {STRESS}")
    if isinstance(x, str):
        return x
    formats = {"len": length, "sci": sci, "num": num, "pct": lambda v: f"{num(100 * v)} %",
               "times": lambda v: f"{num(v)}×"}
    if form not in formats:
        raise SourceError(f"{where}: {name}: unknown format {form!r} ({', '.join(formats)})")
    return formats[form](x)


# ---------------------------------------------------------------------------------------------
# The catalogue under each integrator (target stress-integrators: `cbps stress --integrator`).

STRESS_BY_INTEGRATOR = {"paper": STRESS,
                        "gyroscopic": "validation/results/stress-gyroscopic/summary.json",
                        "midpoint": "validation/results/stress-midpoint/summary.json"}


def _runs(src, path):
    return {(r["case"], r["solver"]): r for r in need(src.json(path), "results", where=path)}


@generator("stress-integrators", *STRESS_BY_INTEGRATOR.values())
def _stress_integrators(src):
    """One row per (case, solver) of the paper's catalogue: stable or not and ΔE under each
    integrator."""
    runs = {name: _runs(src, path) for name, path in STRESS_BY_INTEGRATOR.items()}
    rows = []
    for key, paper in runs["paper"].items():
        if paper["status"] == "skipped":
            continue
        row = [key[0], key[1]]
        for name, path in STRESS_BY_INTEGRATOR.items():
            r = runs[name].get(key)
            if r is None:
                raise SourceError(f"{path}: no run {key[0]} / {key[1]}")
            status = {"stable": "yes", "unstable": "NO"}.get(r["status"], r["status"])
            if r["status"] in ("diverged", "budget"):
                status += f" @{r['steps_done']}"
            row += [status, cg(r["energy_change_J"])]
        rows.append(tuple(row))
    header = ["case", "solver"]
    for name in STRESS_BY_INTEGRATOR:
        header += [f"{name}: stable", f"{name}: ΔE J"]
    return table(header, rows, "ll" + "lr" * len(STRESS_BY_INTEGRATOR))


@generator("stress-integrators-counts", *STRESS_BY_INTEGRATOR.values())
def _stress_integrators_counts(src):
    parts = []
    for name, path in STRESS_BY_INTEGRATOR.items():
        c = need(src.json(path), "counts", where=path)
        parts.append(f"{name} {c['stable']} stable, {c['unstable']} unstable, "
                     f"{c['diverged']} diverged")
    return "; ".join(parts)


@generator("dzhanibekov-integrators", *STRESS_BY_INTEGRATOR.values())
def _dzhanibekov(src):
    """The Dzhanibekov cases under each integrator, with the probe's measures."""
    rows = []
    for name, path in STRESS_BY_INTEGRATOR.items():
        for (case, _), r in _runs(src, path).items():
            if not case.startswith("dzhanibekov"):
                continue
            x = need(r, "measured", where=f"{path} ({case})")
            error = abs(x["flip_interval_s"] - x["reference_flip_interval_s"]) / \
                x["reference_flip_interval_s"]
            rows.append((case, name, num(x["flip_interval_s"]),
                         num(x["reference_flip_interval_s"]), sci(error),
                         sci(x["energy_drift_relative"]),
                         sci(x["angular_momentum_drift_relative"]),
                         {"stable": "yes", "unstable": "NO"}.get(r["status"], r["status"])))
    return table(["case", "integrator", "flip interval s", "GSL's s", "error",
                  "max \\|ΔE\\|/E", "max \\|ΔL\\|/\\|L\\|", "stable"], rows, "llrrrrrl")


@generator("stress-integrators-differ", *STRESS_BY_INTEGRATOR.values())
def _stress_integrators_differ(src):
    """The runs whose status depends on the integrator: case (solvers), in catalogue order."""
    runs = {name: _runs(src, path) for name, path in STRESS_BY_INTEGRATOR.items()}
    differ = {}
    for key in runs["paper"]:
        if len({runs[name][key]["status"] for name in runs}) > 1:
            differ.setdefault(key[0], []).append(key[1])
    return ", ".join(f"`{case}`" + ("" if solvers == ["-"] else f" ({', '.join(solvers)})")
                     for case, solvers in differ.items())
