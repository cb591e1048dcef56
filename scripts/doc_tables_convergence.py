"""The generated parts of docs/convergence.md (scripts/doc_tables.py): the performance profiles
and the convergence studies.
"""
from doc_tables_common import (  # scripts/doc_tables_common.py
    SourceError, dur, generator, need, sci, table, thousands)


# ---------------------------------------------------------------------------------------------
# Performance profiles (`cmake --build build/release --target profile`, reduced by
# update_results.sh into validation/results/profile/summary.json).

PROFILE = "validation/results/profile/summary.json"


def _rho(src, measure, tolerance):
    for p in need(src.json(PROFILE), "profiles", where=PROFILE):
        if p["measure"] == measure and abs(p["tolerance"] - tolerance) <= 1e-3 * tolerance:
            return p["rho"]
    raise SourceError(f"{PROFILE}: no {measure} profile at {tolerance}")


def _pct(x):
    return f"{round(100 * x)} %"


@generator("profile-table", PROFILE)
def _profile_table(src):
    j = src.json(PROFILE)
    n = len(need(j, "problems", where=PROFILE))
    rows = []
    for solver in need(j, "solvers", where=PROFILE):
        name = solver["solver"]
        solved = [round(_rho(src, "time", t)[name]["inf"] * n) for t in (1e-4, 1e-8, 1e-10)]
        t10 = _rho(src, "time", 1e-10)[name]
        cells = [f"`{name}`", " / ".join(str(k) for k in solved), _pct(t10["1"]), _pct(t10["10"])]
        if solver["exact"]:
            cells.append("–")
        else:
            cells.append(_pct(_rho(src, "sweeps", 1e-10)[name]["1"]))
        rows.append(cells)
    return table(["solver", f"solved of {n} (1e-4 / 1e-8 / 1e-10)", "fastest at 1e-10",
                  "within 10× the fastest", "fewest sweeps at 1e-10"], rows, "lrrrr")


@generator("profile-headline", PROFILE)
def _profile_headline(src):
    j = src.json(PROFILE)
    n = len(need(j, "problems", where=PROFILE))
    time10 = _rho(src, "time", 1e-10)
    sweeps10 = _rho(src, "sweeps", 1e-10)
    names = [s["solver"] for s in need(j, "solvers", where=PROFILE)]
    best = max(names, key=lambda name: (time10[name]["1"], time10[name]["inf"]))
    most = max(names, key=lambda name: (time10[name]["inf"], time10[name]["1"]))
    iterative = [s["solver"] for s in j["solvers"] if not s["exact"]]
    fewest = max(iterative, key=lambda name: sweeps10[name]["1"])

    def solved(name):
        return round(time10[name]["inf"] * n)
    text = (f"At a unit-free 1e-10 `{best}` is the fastest on {_pct(time10[best]['1'])} of the "
            f"{n} problems and solves {solved(best)}; `{most}` solves {solved(most)} "
            f"(fastest on {_pct(time10[most]['1'])}, within 10× the fastest on "
            f"{_pct(time10[most]['10'])}); `{fewest}` needs the fewest sweeps on "
            f"{_pct(sweeps10[fewest]['1'])}")
    if "pgs" in names:
        text += (f"; the paper's `pgs` solves {solved('pgs')} and is within 10× the fastest on "
                 f"{_pct(time10['pgs']['10'])}")
    return text


@generator("profile-budget", PROFILE)
def _profile_budget(src):
    j = src.json(PROFILE)
    return (f"{len(need(j, 'problems', where=PROFILE))} problems × "
            f"{len(need(j, 'solvers', where=PROFILE))} solvers, budget "
            f"{thousands(need(j, 'budget_iterations', where=PROFILE))} sweeps and "
            f"{dur(need(j, 'time_limit_s', where=PROFILE))} per problem and solver, "
            f"{dur(need(j, 'wall_time_s', where=PROFILE))} in all")


# ---------------------------------------------------------------------------------------------
# Convergence (`cbps converge --out`: validation/results/convergence/*/summary.json).

CONV = "validation/results/convergence/{}/summary.json"


def _reached(j, target):
    at = j["reached"].get(target)
    if at is None:
        return "-"
    return f"{thousands(at['iterations'])} / {dur(at['time_s'])}"


def _stopped(j, limit_sweeps):
    res = j["residual"]
    if j["stopped"] == "non-finite values" or res is None:
        return f"diverges: non-finite after {thousands(j['iterations'])} sweeps"
    if j["stopped"] == "residual tolerance":
        return f"{sci(res)} N after {thousands(j['iterations'])} sweeps ({dur(j['time_s'])})"
    if j["stopped"] == "time limit":
        return f"{sci(res)} N after {dur(j['time_s'])} ({thousands(j['iterations'])} sweeps)"
    return (f"{sci(res)} N after {thousands(j['iterations'])} sweeps "
            f"({dur(j['time_s'])}; {j['stopped']})")


def _convergence(src, name, with_stop):
    rel = CONV.format(name)
    s = src.json(rel)
    rows = []
    for j in need(s, "solvers", where=rel):
        if j["method"] == "direct":
            t = dur(j["time_s"])
            ok = j["residual"] is not None
            r3 = [t if ok and j["residual"] <= tol else "-" for tol in (1e-3, 1e-6, 1e-10)]
            n = j["iterations"]
            stop = (f"{sci(j['residual'])} N, {j['stopped']}, {n} outer iteration"
                    + ("s" if n != 1 else ""))
            rows.append([j["solver"]] + r3 + ([stop] if with_stop else []))
            continue
        rows.append([j["solver"]] + [_reached(j, t) for t in ("0.001", "1e-06", "1e-10")]
                    + ([_stopped(j, None)] if with_stop else []))
    header = ["solver", "1e-3 N", "1e-6 N", "1e-10 N"] + (["where it stopped"] if with_stop else [])
    return table(header, rows, "lrrr" + ("l" if with_stop else ""))


@generator("convergence-chain", CONV.format("chain"))
def _conv_chain(src):
    return _convergence(src, "chain", True)


@generator("convergence-stack", CONV.format("stack"))
def _conv_stack(src):
    return _convergence(src, "stack", True)


@generator("convergence-pyramid", CONV.format("pyramid"))
def _conv_pyramid(src):
    return _convergence(src, "pyramid", True)


def _by_solver(src, name):
    rel = CONV.format(name)
    return {j["solver"]: j for j in need(src.json(rel), "solvers", where=rel)}


@generator("convergence-findings", CONV.format("chain"), CONV.format("stack"),
           CONV.format("pyramid"))
def _conv_findings(src):
    """The tables' outcome in words: computed, so it cannot contradict them."""
    out = []
    chain = _by_solver(src, "chain")
    d, pgs = chain.get("direct"), chain.get("pgs")
    if d and pgs and pgs["reached"].get("1e-06"):
        out.append(f"On the chain the direct path reaches {sci(d['residual'])} N in "
                   f"{dur(d['time_s'])}; PGS needs {dur(pgs['reached']['1e-06']['time_s'])} for "
                   "1e-6 N.")
    stack = _by_solver(src, "stack")
    finals = [j["residual"] for k, j in stack.items()
              if j["method"] != "direct" and j["residual"] is not None
              and j["stopped"] != "non-finite values"]
    d = stack.get("direct")
    if finals and d:
        out.append(f"On the stack the iterative solvers that stay finite end between "
                   f"{sci(min(finals))} and {sci(max(finals))} N (PGS does not converge on this "
                   f"singular system with friction bounds), while the direct path reaches "
                   f"{sci(d['residual'])} N in {dur(d['time_s'])}.")
    pyr = _by_solver(src, "pyramid")
    d = pyr.get("direct")
    if d:
        out.append(f"The pyramid is the direct path's weak point: one large island, "
                   f"{dur(d['time_s'])} and {d['stopped']} at {sci(d['residual'])} N.")
    mf, pg = pyr.get("matrix-free"), pyr.get("pgs")
    if mf and pg and mf["stopped"] == pg["stopped"] == "time limit":
        out.append(f"In the same 10 s on the pyramid the matrix-free sweep does "
                   f"{thousands(mf['iterations'])} sweeps against the explicit one's "
                   f"{thousands(pg['iterations'])}.")
    return "\n".join(out)
