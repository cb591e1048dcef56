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
