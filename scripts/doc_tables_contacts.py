"""The generated parts of docs/contacts.md (scripts/doc_tables.py): the contact pipeline's
benchmark, validate_contacts' stack and validate_stack's ingredients.
"""
from doc_tables_common import (  # scripts/doc_tables_common.py
    CONTACTS, SourceError, dur, generator, length, need, num, sci, table, thousands)


# ---------------------------------------------------------------------------------------------
# The contact pipeline's benchmark (bench/results, the bench program's own JSON).

BENCH_CONTACTS = "bench/results/contacts-amd-epyc-2cpu.json"


@generator("bench-contacts", BENCH_CONTACTS)
def _bench_contacts(src):
    rows = []
    for p in need(src.json(BENCH_CONTACTS), "pyramids", where=BENCH_CONTACTS):
        ms = p["ms_per_step"]

        def t(x):
            return dur(x * 1e-3, 3)
        rows.append((f"{p['base']} ({p['boxes']})", thousands(round(p["rows_mean"])),
                     t(ms["broad_phase"]), t(ms["narrow_phase"]), t(ms["rows"]),
                     t(ms["assembly"]), t(ms["solve"]), t(ms["integrate"]), t(ms["step"])))
    return table(["base (boxes)", "rows (mean)", "broad phase", "narrow phase", "rows",
                  "assembly", "solve", "integrate", "step"], rows, "lrrrrrrrr")


# ---------------------------------------------------------------------------------------------
# Contacts (validate_contacts: validation/results/contacts.json).


@generator("contacts-stack", CONTACTS)
def _contacts_stack(src):
    rows = []
    for r in need(src.json(CONTACTS), "stack", where=CONTACTS):
        method = {"pgs": "`pgs` (7.1.1, row by row)"}.get(r["method"], f"`{r['method']}`")
        rows.append((method, r["push"], length(r["top_drift"], 3), length(r["max_penetration"]),
                     f"{num(r['residual_last'])} N", dur(r["wall_time_s"])))
    return table(["solver", "push", "top box drift", "max penetration", "last residual",
                  "wall time"], rows, "llrrrr")


def _spectrum(src, mu):
    for s in need(src.json(CONTACTS), "stack_spectrum", where=CONTACTS):
        if (s["mu"] > 0) == (mu > 0):
            return s
    raise SourceError(f"{CONTACTS}: no stack_spectrum with mu {'> 0' if mu else '= 0'}")


@generator("contacts-stack-spectrum", CONTACTS)
def _contacts_spectrum(src):
    f, nf = _spectrum(src, 0.5), _spectrum(src, 0)
    return (f"with friction the stack's `A` at rest ({f['rows']} rows) has a smallest nonzero "
            f"eigenvalue {sci(f['eigenvalue_min_nonzero'])} against {num(f['eigenvalue_max'], 3)} "
            f"(condition {sci(f['eigenvalue_max'] / f['eigenvalue_min_nonzero'])}; without "
            f"friction, {nf['rows']} rows: "
            f"{num(nf['eigenvalue_max'] / nf['eigenvalue_min_nonzero'], 3)}), and Gauss-Seidel's "
            f"spectral radius on it is {f['gauss_seidel_rho']:.5f}: "
            f"{thousands(round(f['sweeps_per_decade']))} sweeps per decade of error "
            f"({round(nf['sweeps_per_decade'])} without friction)")


@generator("contacts-block-residual", CONTACTS)
def _contacts_block_residual(src):
    for r in need(src.json(CONTACTS), "stack", where=CONTACTS):
        if r["method"] == "block-pgs" and r["push"] == "improved":
            return f"{sci(r['residual_last'])} N"
    raise SourceError(f"{CONTACTS}: no block-pgs/improved stack run")


@generator("contacts-summary", CONTACTS)
def _contacts_summary(src):
    c = src.json(CONTACTS)
    vc = [r for r in c["v_corner"] if r["margin"] > 0]
    direct = max(r["error_direct_over_mg"] for r in vc)
    pgs = max(r["error_pgs_over_mg"] for r in vc)
    b = [r for r in c["bounce"] if r["restitution"] == 0.8 and r["dt"] == "1/240"][0]
    ov = {(r["push"], r["solver"]): r for r in c["overlap"]}
    return (f"v-corner λ against the force balance to {sci(direct, 1)} m g (direct) and "
            f"{sci(pgs, 1)} m g (PGS) with a contact margin of 1 mm; rebound heights within "
            f"{num(100 * b['max_ratio_rel_error'], 1)} % of ε² at ε = 0.8, dt = 1/240; slide "
            f"stopping distance off by v₀ dt/2 (the integrator); the push-factor figure "
            f"(original injects {num(ov[('original', 'pgs')]['kinetic_energy_injected'])} J, "
            f"improved {sci(ov[('improved', 'pgs')]['kinetic_energy_injected'], 1)} J under PGS)")


# ---------------------------------------------------------------------------------------------
# The stack's ingredients (validate_stack: validation/results/stack-ingredients.json).

STACK = "validation/results/stack-ingredients.json"


def _stack_runs(src, config, sweeps):
    runs = [r for r in need(src.json(STACK), "runs", where=STACK)
            if r["config"] == config and r["sweeps"] == sweeps]
    if not runs:
        raise SourceError(f"{STACK}: no run of {config!r} at {sweeps} sweeps")
    return runs


def _stack_cell(runs):
    d = sorted(r["drift"] for r in runs)
    n = len(d)
    med = d[n // 2] if n % 2 else 0.5 * (d[n // 2 - 1] + d[n // 2])
    if n == 1:
        return length(med)
    return f"{length(med)} (max {length(d[-1])})"


@generator("stack-ingredients", STACK)
def _stack_ingredients(src):
    configs = []
    for r in need(src.json(STACK), "runs", where=STACK):
        if r["config"] not in [c[0] for c in configs]:
            configs.append((r["config"], r["spec"], r["persistence"]))
    rows = []
    for name, spec, persistence in configs:
        cold = _stack_runs(src, name, 20)
        rows.append((name, "on" if persistence else "off", f"`{spec}`",
                     *(_stack_cell(_stack_runs(src, name, s)) for s in (10, 20, 50)),
                     f"{100 * max(r['cold_fraction'] for r in cold):.1f} %"))
    return table(["configuration", "persistence", "solver spec", "10 sweeps", "20 sweeps",
                  "50 sweeps", "rows cold (20 sweeps)"], rows, "lllrrrr")


@generator("stack-ingredients-seeds", STACK)
def _stack_seeds(src):
    j = src.json(STACK)
    return (f"{need(j, 'seeds', where=STACK)} seeds; the whole study takes "
            f"{dur(need(j, 'wall_time_s', where=STACK))}")
