"""The generated parts of docs/siconos-study.md (scripts/doc_tables.py): cbps's methods and
Siconos' fc3d solvers on the 3-D frictional-contact problems of Siconos' own test suite
(validation/data/siconos-fc3d), one `cbps profile` run (scripts/run_siconos_study.sh), judged by
the unit-free verdict (docs/cones.md).
"""
from cbps_files import read_number  # scripts/cbps_files.py
from doc_tables_common import SourceError, cell, dur, generator, need, num, sci, table

PROFILE = "validation/results/siconos-fc3d/profile.json"
STUDY = "validation/results/siconos-fc3d/study.json"
FORMAT = "cbps-profile/1"
STUDY_FORMAT = "cbps-siconos-study/1"
TOLERANCES = ("0.0001", "1e-08", "1e-10")  # cbps profile's unit-free tolerances
AIM = "1e-10"  # what the issue asks of direct
PEER_BAR = "1e-08"  # where the peers are compared (Acary, Brémond & Huber 2018)
RATIO = 2.0  # direct's time at most this times the fastest Siconos solver's
SOLVED = 1e-9  # the verdict's bound on the unit-free residual (include/cbps/system/unit_free.hpp)


def _profile(src):
    return src.json(PROFILE, FORMAT)


def _by_problem(j):
    """{problem: {solver: measurement}} in the file's order of problems, and the solvers."""
    solvers = [s["solver"] for s in need(j, "solvers", where=PROFILE)]
    by = {p["name"]: {} for p in need(j, "problems", where=PROFILE)}
    for m in need(j, "measurements", where=PROFILE):
        if m["problem"] not in by:
            raise SourceError(f"{PROFILE}: a measurement of unknown problem {m['problem']!r}")
        by[m["problem"]][m["solver"]] = m
    for name, d in by.items():
        missing = [s for s in solvers if s not in d]
        if missing:
            raise SourceError(f"{PROFILE}: {name}: no measurement of {', '.join(missing)}")
    return by, solvers


def _t(m, tol):
    """The time at which m first met tol, or None."""
    r = m["reached"].get(tol)
    return None if r is None else r["time_s"]


def _rel(x):
    """A unit-free residual: plain from 1e-3 up, else scientific; '–' for none."""
    x = read_number(x)
    return "–" if x is None else (num(x) if abs(x) >= 1e-3 else sci(x))


def _name(problem):
    return problem.replace("_", "\\_")


def _wrong(m):
    """A peer that said it succeeded where the verdict (unit-free residual at most 1e-9) says it
    did not."""
    return m["status"].startswith("peer said ok") and read_number(m["residual_relative"]) > SOLVED


def _peers(solvers):
    return [s for s in solvers if s.startswith("siconos:")]


def _fastest_peer(d, solvers, tol=PEER_BAR):
    """(time, solver) of the fastest Siconos solver that met tol on a problem, or None."""
    times = [(_t(d[s], tol), s) for s in _peers(solvers) if _t(d[s], tol) is not None]
    return min(times) if times else None


def _short(name):
    return name.replace("siconos:fc3d-", "Siconos ").replace("nsn-ac", "NSN-AC").replace(
        "nsgs", "NSGS").replace("prox", "PROX").replace("admm", "ADMM")


def _label(s):
    """A solver's column name: cbps's own methods in code, Siconos' by their names."""
    return _short(s) if s.startswith("siconos:") else f"`{s}`"


@generator("siconos-study-run", STUDY, PROFILE)
def _run(src):
    s = src.json(STUDY, STUDY_FORMAT)
    j = _profile(src)
    by, solvers = _by_problem(j)
    return (f"{len(by)} problems × {len(solvers)} solvers, {j['time_limit_s']:g} s and "
            f"{j['budget_iterations']:,} iterations per problem and solver, {dur(j['wall_time_s'])} "
            f"in all, on {s['machine']}, {s['date']}, cbps {s['cbps_commit']}")


@generator("siconos-study-solved", PROFILE)
def _solved(src):
    j = _profile(src)
    by, solvers = _by_problem(j)
    n = len(by)
    rows = []
    for s in solvers:
        ms = [d[s] for d in by.values()]
        counts = [sum(_t(m, t) is not None for m in ms) for t in TOLERANCES]
        rows.append([_label(s)] + [f"{c}/{n}" for c in counts] + [
            str(sum(_wrong(m) for m in ms)),
            str(sum(m["status"] == "time limit" for m in ms)),
            dur(sum(m["time_s"] for m in ms))])
    return table(["solver", "unit-free ≤ 1e-4", "≤ 1e-8", "≤ 1e-10", "wrong \"solved\"",
                  f"killed at {j['time_limit_s']:g} s", "time, all problems"], rows,
                 "lrrrrrr")


def _cell(m):
    """One solver on one problem: its time to 1e-8 (and whether it went on to 1e-10), or where it
    stopped; a wrong claim of success in bold."""
    t8, t10 = _t(m, PEER_BAR), _t(m, AIM)
    res = _rel(m["residual_relative"])
    if t8 is not None:
        return dur(t8) + ("" if t10 is not None else f" (ends {res})")
    if _wrong(m):
        return f"**said ok: {res}**"
    if m["status"] == "time limit":
        return f"✗ {res}, killed"
    if m["status"].startswith("not applicable"):
        return "n/a"
    return f"✗ {res}"


@generator("siconos-study-problems", PROFILE)
def _problems(src):
    j = _profile(src)
    by, solvers = _by_problem(j)
    meta = {p["name"]: p for p in j["problems"]}
    rows = []
    for name, d in by.items():
        p = meta[name]
        shape = f"{p['contacts']} ({p['rows']})" if p.get("contacts") else str(p["rows"])
        direct = d.get("direct")
        best = _fastest_peer(d, solvers)
        ratio = "–"
        if direct is not None and best is not None and _t(direct, AIM) is not None:
            ratio = num(_t(direct, AIM) / best[0])
        rows.append([_name(name), shape, "yes" if p["symmetric"] else "no"] +
                    [cell(_cell(d[s])) for s in solvers] + [ratio])
    return table(["problem", "contacts (rows)", "W symmetric"] + [_label(s) for s in solvers] +
                 ["direct to 1e-10 / fastest Siconos to 1e-8"], rows,
                 "lrl" + "l" * len(solvers) + "r")


@generator("siconos-study-wrong", PROFILE)
def _wrong_claims(src):
    by, solvers = _by_problem(_profile(src))
    rows = []
    for name, d in by.items():
        for s in solvers:
            m = d[s]
            if _wrong(m):
                rows.append([_label(s), _name(name), cell(m["peer_status"]),
                             _rel(m["residual_relative"]),
                             f"{m['iterations']:,}", dur(m["time_s"])])
    if not rows:
        return "No solver said it succeeded where the verdict says it did not."
    return table(["solver", "problem", "its own word", "unit-free residual", "iterations",
                  "time"], rows, "llllrr")


@generator("siconos-study-targets", PROFILE)
def _targets(src):
    j = _profile(src)
    by, solvers = _by_problem(j)
    if "direct" not in solvers:
        raise SourceError(f"{PROFILE}: no direct among the solvers")
    reachable = [n for n, d in by.items() if any(_t(m, PEER_BAR) is not None for m in d.values())]
    missed = [n for n in reachable if _t(by[n]["direct"], AIM) is None]
    lines = [f"- `direct` to unit-free 1e-10 on every problem some solver brings to 1e-8: "
             f"{len(reachable) - len(missed)} of {len(reachable)}" +
             (f"; not on {', '.join(_name(n) for n in missed)}" if missed else "")]
    compared, over = 0, []
    for n in reachable:
        best = _fastest_peer(by[n], solvers)
        t = _t(by[n]["direct"], AIM)
        if best is None or t is None:
            continue
        compared += 1
        if t > RATIO * best[0]:
            over.append(f"{_name(n)} ({dur(t)} against {_short(best[1])}'s {dur(best[0])}: "
                        f"{num(t / best[0])}×)")
    lines.append(f"- `direct`'s time to 1e-10 at most {RATIO:g}× the fastest Siconos solver's "
                 f"to 1e-8, on the {compared} problems a Siconos solver brings to 1e-8: "
                 f"{compared - len(over)} of {compared}" +
                 (f"; over it on {'; '.join(over)}" if over else ""))
    totals = {s: sum(d[s]["time_s"] for d in by.values()) for s in solvers}
    peers = ", ".join(f"{_short(s)} {dur(totals[s])}" for s in _peers(solvers))
    faster = all(totals["direct"] < totals[s] for s in _peers(solvers))
    lines.append(f"- over the set, `direct` {dur(totals['direct'])} in all "
                 f"({'faster than' if faster else 'not faster than'} every Siconos solver: "
                 f"{peers}; each counted to its end, the limit where it was killed)")
    for n, d in by.items():
        if n in reachable:
            continue
        best = min(((read_number(m["residual_relative"]), s) for s, m in d.items()
                    if m["residual_relative"] is not None), default=None)
        dr = d["direct"]
        lines.append(f"- {_name(n)}, which no solver brings to 1e-8: `direct` says "
                     f"\"{dr['status']}\" at unit-free {_rel(dr['residual_relative'])} "
                     f"after {dur(dr['time_s'])}; the closest answer, {_label(best[1])}'s, "
                     f"{_rel(best[0])}")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# Problems no simulation wrote (scripts/measure_mu_variants.py).

VARIANTS = "validation/results/siconos-fc3d/mu-variants.json"
VARIANTS_FORMAT = "cbps-mu-variants/1"


def _variants(src):
    j = src.json(VARIANTS, VARIANTS_FORMAT)
    runs = need(j, "runs", where=VARIANTS)
    direct = {(r["problem"], r["mu_factor"]): r for r in runs if r["method"] == "direct"}
    prox = {r["problem"]: r for r in runs if r["method"] != "direct"}
    problems = list(dict.fromkeys(r["problem"] for r in runs))
    factors = need(j, "factors", where=VARIANTS)
    for p in problems:
        for f in factors:
            if (p, f) not in direct:
                raise SourceError(f"{VARIANTS}: no direct run of {p} with mu x {f:g}")
    return j, direct, prox, problems, factors


def _verdict(r):
    """✓ time where the unit-free residual met the tolerance, else ✗ and the residual."""
    uf = read_number(r["unit_free"])
    if uf is not None and uf <= TOL_VARIANTS:
        return f"✓ {dur(r['time_s'])}"
    return f"✗ {_rel(uf)}"


TOL_VARIANTS = 1e-10


@generator("siconos-mu-variants", VARIANTS)
def _mu_variants(src):
    _, direct, prox, problems, factors = _variants(src)
    header = ["problem"] + [f"mu × {f:g}" for f in factors] + ["Siconos PROX, mu × 0.5"]
    rows = []
    for p in problems:
        row = [_name(p)] + [_verdict(direct[(p, f)]) for f in factors]
        row.append(_verdict(prox[p]) if p in prox else "–")
        rows.append(row)
    return table(header, rows, "l" + "r" * (len(factors) + 1))


@generator("siconos-mu-variants-summary", VARIANTS)
def _mu_variants_summary(src):
    j, direct, _, _, _ = _variants(src)
    solved = [r for r in direct.values() if read_number(r["unit_free"]) <= TOL_VARIANTS]
    stage5 = [r for r in direct.values() if r.get("stage5_steps")]
    return (f"`direct` meets a unit-free 1e-10 on {len(solved)} of the {len(direct)}, "
            f"{len(stage5)} of them through stage 5's proximal points (cbps {j['cbps_commit']}, "
            f"{j['date']})")
