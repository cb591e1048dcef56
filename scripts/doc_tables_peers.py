"""The generated parts of docs/peers.md (scripts/doc_tables.py): Siconos' and Bullet's solvers as
cbps methods, judged by cbps's natural-map residual, on the contact problems of
docs/exact-path.md and over the problem library (scripts/measure_peers.py, target `peers`).
"""
import math
import re

from cbps_files import read_number  # scripts/cbps_files.py
from doc_tables_common import (  # scripts/doc_tables_common.py
    SourceError, cell, dur, generator, need, num, sci, table, thousands)

PEERS = "validation/results/peers/peers.json"
FORMAT = "cbps-peers/1"
TOLERANCES = ("0.0001", "1e-08", "1e-10")  # cbps profile's unit-free tolerances


def _peers(src):
    return src.json(PEERS, FORMAT)


def _rel(x):
    """A relative residual: plain from 1e-3 up, else scientific; '–' for none."""
    x = read_number(x)
    if x is None:
        return "–"
    if not math.isfinite(x):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return num(x) if abs(x) >= 1e-3 else sci(x)


# ---------------------------------------------------------------------------------------------
# The contact problems of docs/exact-path.md, one `cbps lcp` each.


def _exact_cell(r):
    """One solver on one problem: cbps's verdict, the relative residual and the solve's wall
    time; a wrong claim of success in bold; a refusal with the size it exceeds."""
    status = r["status"]
    if status == "refused":
        m = re.search(r"at most (\d+)", r.get("message", ""))
        return f"refused (> {thousands(m.group(1))} rows)" if m else "refused"
    if status == "timeout":
        return f"timeout ({dur(r['job_s'])})"
    if status == "error":
        return f"error (exit {r.get('exit')})"
    rel, time = _rel(r["residual_relative"]), dur(r["wall_time_s"])
    if status == "solved":
        text = f"solved {rel}, {time}"
        if r.get("said_ok") is False:
            text += " (peer said failed)"
        return text
    if r.get("said_ok"):
        return f"**said ok**: {rel}, {time}"
    return f"{status} {rel}, {time}"


@generator("peers-exact-path", PEERS)
def _exact_path(src):
    e = need(_peers(src), "exact_path", where=PEERS)
    problems = need(e, "problems", where=PEERS)
    header = ["solver"] + [f"{cell(p.get('label', p['name']))} ({thousands(p['rows'])} rows)"
                           for p in problems]
    rows = []
    for solver in need(e, "solvers", where=PEERS):
        cells = [f"`{solver}`"]
        for p in problems:
            r = next((x for x in p["runs"] if x["solver"] == solver), None)
            cells.append(cell(_exact_cell(r)) if r else "–")
        rows.append(cells)
    return table(header, rows)


# ---------------------------------------------------------------------------------------------
# The problem library under `cbps profile`.


@generator("peers-profile", PEERS)
def _profile(src):
    p = need(_peers(src), "profile", where=PEERS)
    n = len(need(p, "problems", where=PEERS))
    rows = []
    for s in need(p, "per_solver", where=PEERS):
        solved = " / ".join(str(s["solved"][t]) for t in TOLERANCES)
        t = s["median_time_s"]
        rows.append([f"`{s['solver']}`", solved, dur(t) if t is not None else "–"])
    return table(["solver", f"solved of {n} (unit-free 1e-4 / 1e-8 / 1e-10)",
                  "median time where solved at 1e-10"], rows, "lrr")


@generator("peers-families", PEERS)
def _families(src):
    p = need(_peers(src), "profile", where=PEERS)
    counts = {}
    for q in need(p, "problems", where=PEERS):
        counts[q["family"]] = counts.get(q["family"], 0) + 1
    peers = [s for s in need(p, "solvers", where=PEERS) if ":" in s]
    rows = []
    for f in need(p, "families", where=PEERS):
        first = True
        for s in peers:
            x = next((y for y in p["per_family"] if y["family"] == f and y["solver"] == s), None)
            if x is None:
                raise SourceError(f"{PEERS}: no per_family entry for {f} and {s}")
            failed = str(x["failed"])
            if x.get("aborted"):
                failed += f" ({x['aborted']} aborted)"
            wrong = str(x["wrong_claims"])
            if x["wrong_claims"]:
                wrong += f" (up to {_rel(x['largest_wrong_claim_residual_relative'])})"
            rows.append([f"{f} ({counts[f]})" if first else "", f"`{s}`", x["solved"], failed,
                         wrong, x["refused"], _rel(x["largest_unsolved_residual_relative"])])
            first = False
    return table(["family (problems)", "peer", "solved", "failed", "said ok wrongly", "refused",
                  "largest unsolved residual"], rows, "llrrrrr")


@generator("peers-budget", PEERS)
def _budget(src):
    j = _peers(src)
    p = need(j, "profile", where=PEERS)
    e = need(j, "exact_path", where=PEERS)
    exact_s = sum(r["job_s"] for q in e["problems"] for r in q["runs"])
    return (f"{len(need(p, 'problems', where=PEERS))} problems × {len(p['solvers'])} solvers in "
            f"{dur(need(p, 'wall_time_s', where=PEERS))} (`cbps profile`), and "
            f"{len(e['problems'])} problems × {len(e['solvers'])} solvers in {dur(exact_s)} "
            f"(`cbps lcp`); {dur(need(j, 'wall_time_s', where=PEERS))} in all on "
            f"{j['nproc']} cores, {j['date']}, cbps {j['cbps_commit']}{_rerun(j)}")


def _rerun(j):
    """The entries rerun alone since (scripts/check_results_drift.py found them drifted)."""
    return "".join(f"; {r['entry']} rerun alone on cbps {r['cbps_commit']}, {r['date']}"
                   for r in j.get("regenerated", []))
