"""The generated parts of docs/exact-path.md (scripts/doc_tables.py): the benchmarks of the direct
and exact paths, and the direct path's known limits.
"""
import math
import re
import statistics

from doc_tables_common import (  # scripts/doc_tables_common.py
    dur, generator, need, num, sci, table, thousands)


# ---------------------------------------------------------------------------------------------
# Benchmarks (bench/results, the bench programs' own JSON).

DIRECT = "bench/results/direct-amd-epyc-2cpu.json"
EXACT = "bench/results/exact-amd-epyc-2cpu.json"
WARM = "bench/results/warm-amd-epyc-2cpu.json"


def _pgs_cell(p):
    if p["reached"]:
        return dur(p["seconds"])
    return "not in 10 s"


@generator("bench-direct", DIRECT)
def _bench_direct(src):
    d = src.json(DIRECT)
    rows = []
    for c in need(d, "chains", where=DIRECT):
        n = c["links"]
        label = f"10{'⁰¹²³⁴⁵⁶⁷⁸⁹'[round(math.log10(n))]}"
        direct = dur(c["direct_s"])
        sweeps_equiv = c["direct_s"] / c["pgs_sweep_s"]
        direct += f" ({sweeps_equiv:.0f} sweeps)"
        if "pgs" in c:
            pgs = {p["tolerance"]: p for p in c["pgs"]}
            cells = []
            for tol in (1e-3, 1e-6, 1e-10):
                p = pgs[tol]
                cell_text = _pgs_cell(p)
                if not p["reached"] and tol == 1e-3:
                    cell_text += f" ({num(p['final_residual'])} N)"
                cells.append(cell_text)
        else:
            cells = ["not run"] * 3
        rows.append([label if "pgs" in c else f"{label} rows", direct,
                     f"{sci(c['direct_residual'])} N", dur(c["pgs_sweep_s"])] + cells)
    return table(["links", "direct (in sweeps)", "residual", "1 PGS sweep", "PGS to 1e-3 N",
                  "PGS to 1e-6 N", "PGS to 1e-10 N"], rows, "lrrrrrr")


@generator("bench-direct-stack", DIRECT)
def _bench_direct_stack(src):
    s = need(src.json(DIRECT), "stack", where=DIRECT)
    msg = s["direct_message"]
    islands = re.search(r"(\d+) islands", msg)
    facts = re.search(r"(\d+) factorizations", msg)
    pgs = {p["tolerance"]: p for p in s["pgs"]}
    p3, p6, p10 = pgs[1e-3], pgs[1e-6], pgs[1e-10]
    return (f"({thousands(s['rows'])} rows, `A` singular): direct {dur(s['direct_s'])} to "
            f"{sci(s['direct_residual'])} N ({islands.group(1) if islands else '?'} islands, "
            f"{facts.group(1) if facts else '?'} factorizations); PGS from zero needs "
            f"{thousands(p3['sweeps'])} sweeps ({dur(p3['seconds'])}) for 1e-3 N, "
            f"{thousands(p6['sweeps'])} sweeps ({dur(p6['seconds'])}, "
            f"{p6['seconds'] / s['direct_s']:.0f}× the direct path) for 1e-6 N and "
            f"{thousands(p10['sweeps'])} ({dur(p10['seconds'])}) for 1e-10 N")


def _exact_other(r, budget_key):
    """The active-set path's or PGS's cell: its time to the bench's tolerance, or how far it got."""
    if r.get("status") == "skipped":
        return "not run"
    if r.get("status") == "over budget":
        return f"over {r[budget_key]:.0f} s"
    met = r["reached"] if "reached" in r else r["tolerance_met"]
    if met:
        return dur(r["seconds"])
    if "sweeps" in r:
        return f"not in {r[budget_key]:.0f} s ({sci(r['relative_residual'])})"
    return f"{dur(r['seconds'])}, stops at {sci(r['relative_residual'])}"


@generator("bench-exact", EXACT)
def _bench_exact(src):
    d = src.json(EXACT)
    rows = []
    for sy in need(d, "systems", where=EXACT):
        x = need(sy, "direct", where=EXACT)
        work = f"{x['iterations']} + {x['crossover']}" if x["space"] else "one solve"
        facts = thousands(x["factorizations"])
        if x.get("updates", 0) > 0:
            n = x["updates"]
            facts += f" (+ {thousands(n)} row{'' if n == 1 else 's'} updated)"
        residual = sci(x["relative_residual"])
        if not x["tolerance_met"]:
            residual += f" (floor {sci(x['relative_residual_floor'])})"
        rows.append([sy["name"], thousands(sy["rows"]), thousands(sy["nnz_A"]),
                     dur(x["seconds"]), work, facts,
                     thousands(x["factor_nnz"]) if x["factor_nnz"] else "—", residual,
                     _exact_other(sy["active_set"], "budget_s"),
                     _exact_other(sy["pgs"], "budget_s")])
    return table(["system", "rows", "nnz(A)", "direct", "interior + crossover steps",
                  "factorizations", "factor nnz", "relative residual", "active-set path",
                  "PGS"], rows, "lrrrrrrrrr")


# ---------------------------------------------------------------------------------------------
# The direct path's known limits (`cbps run … --out`: validation/results/limits/*/summary.json).

LIMITS_STACK = "validation/results/limits/stack-check/summary.json"
LIMITS_PYRAMID = "validation/results/limits/pyramid-direct/summary.json"
LIMITS_PYRAMID_CHECK = "validation/results/limits/pyramid-check/summary.json"


def _cross_check(path, src):
    c = need(src.json(path), "cross_check", where=path)
    return (f"{c['direct_stopped_short']} of {c['steps_checked']} steps stopped short of the 64 u "
            f"rule, {c['direct_unverified']} unverified, worst direct residual "
            f"{sci(c['max_direct_residual'])} N (PGS's own: {sci(c['max_pgs_residual'])} N), "
            f"max |v2 − v2_direct| {sci(c['max_velocity_difference'])} m/s")


@generator("limits-stack-check", LIMITS_STACK)
def _limits_stack(src):
    return _cross_check(LIMITS_STACK, src)


@generator("limits-pyramid-check", LIMITS_PYRAMID_CHECK)
def _limits_pyramid_check(src):
    s = src.json(LIMITS_PYRAMID_CHECK)
    return (f"{s['steps']} steps in {dur(s['wall_time_s'])}: "
            + _cross_check(LIMITS_PYRAMID_CHECK, src))


@generator("limits-pyramid-direct", LIMITS_PYRAMID)
def _limits_pyramid(src):
    s = src.json(LIMITS_PYRAMID)
    steps = need(s, "steps", where=LIMITS_PYRAMID)
    solve = need(s, "stage_times_s", "solve", where=LIMITS_PYRAMID)
    return (f"{steps} steps in {dur(s['wall_time_s'])}: {dur(solve / steps)} per step in the "
            f"solve stage ({s['rows']:,} rows, {dur(s['wall_time_s'] / steps)} per step in all)")


# ---------------------------------------------------------------------------------------------
# Warm exact steps in running scenes (scripts/measure_warm.py).

_ROUTE_ORDER = ("guess", "warm", "interior", "active-set", "linear")


def _routes(counts):
    return ", ".join(f"{counts[r]} {r}" for r in _ROUTE_ORDER if counts.get(r))


@generator("bench-warm", WARM)
def _bench_warm(src):
    d = src.json(WARM)
    rows = []
    for s in need(d, "scenes", where=WARM):
        runs = s["runs"]
        direct = statistics.median(r["direct"]["solve_per_step_s"] for r in runs)
        sweep = statistics.median(r["pgs_sweep_s"] for r in runs)
        sweeps = s["sweeps_median"]
        rows.append([s["scene"], s["push"], thousands(s["rows"]), dur(direct), dur(sweep),
                     f"**{sweeps:.1f}**" if sweeps <= 10 else f"{sweeps:.1f} (over 10)",
                     f"{s['cold_sweeps']:.0f}", f"{sci(s['max_residual_N'], 3)} N",
                     _routes(runs[0]["direct"]["routes"])])
    return table(["scene", "push", "rows", "direct a step", "1 PGS sweep", "in sweeps",
                  "cold, in sweeps", "largest residual", "routes (all steps, first run)"],
                 rows, "llrrrrrrl")


@generator("bench-warm-assembly", WARM)
def _bench_warm_assembly(src):
    rows = []
    for s in need(src.json(WARM), "scenes", where=WARM):
        runs = s["runs"]
        pgs = statistics.median(r["pgs"]["assembly_per_step_s"] for r in runs)
        direct = statistics.median(r["direct"]["assembly_per_step_s"] for r in runs)
        rows.append([s["scene"], s["push"], thousands(s["rows"]), dur(pgs),
                     f"`{runs[0]['pgs']['assembly_stage']}`", dur(direct),
                     f"`{runs[0]['direct']['assembly_stage']}`", f"{pgs / direct:.1f}×"])
    return table(["scene", "push", "rows", "PGS: assembly a step", "its stage",
                  "direct: assembly a step", "its stage", "PGS / direct"], rows, "llrrlrlr")


@generator("bench-warm-check", WARM)
def _bench_warm_check(src):
    c = need(src.json(WARM), "check", where=WARM)
    runs = c["runs"]
    plain = statistics.median(r["plain_s"] for r in runs)
    checked = statistics.median(r["checked_s"] for r in runs)
    unverified = max(r["direct_unverified"] for r in runs)
    text = (f"{dur(plain)} without `--check`, {dur(checked)} with it: "
            f"{c['ratio_median']:.2f}× (median of {len(runs)}; {unverified} steps unverified)")
    if "direct_s" in runs[0] and "steps" in c:
        direct = statistics.median(r["direct_s"] for r in runs)
        pgs = statistics.median(r["pgs_solve_s"] for r in runs)
        pivots = statistics.median(r["direct_pivots"] for r in runs)
        text += (f"; the direct solves took {dur(direct)} against {dur(pgs)} in PGS's solve stage "
                 f"({direct / pgs:.2f}×), with {pivots / c['steps']:.0f} crossover pivots a step")
    return text
