"""The generated parts of docs/cones.md (scripts/doc_tables.py): the exact path on friction cones
against 1,000 nsgs sweeps and Siconos' fc3d NSGS and PROX on the cone pyramids
(scripts/measure_cones.py), and the issue's targets checked on those numbers.
"""
from cbps_files import read_number  # scripts/cbps_files.py
from doc_tables_common import SourceError, cell, dur, generator, need, sci, table, thousands

CONES = "bench/results/cones-amd-epyc-2cpu.json"
FORMAT = "cbps-cones/4"
TARGET = 1e-10  # the unit-free residual issue 51 asks of the exact path (docs/cones.md)


def _cones(src):
    return src.json(CONES, FORMAT)


def _rel(x):
    x = read_number(x)
    return "–" if x is None else sci(x)


def _cbps_cell(r):
    """cbps's verdict, unit-free residual and solve time of one `cbps lcp`."""
    if r["status"] in ("timeout", "error"):
        return f"{r['status']} ({dur(r['job_s'])})"
    return f"{r['status']} {_rel(r['unit_free'])}, {dur(r['wall_time_s'])}"


def _ratio(d, n):
    """d's solve time over n's, or – where either has none."""
    if read_number(d.get("wall_time_s")) and read_number(n.get("wall_time_s")):
        return f"{d['wall_time_s'] / n['wall_time_s']:.2g}"
    return "–"


def _siconos_cell(s):
    """A Siconos solver's answer judged by cbps's unit-free residual, with its iterations and
    time."""
    if s["status"] == "timeout":
        return f"no answer in {dur(s['job_s'])}"
    if s["status"] == "error":
        return f"error (exit {s.get('exit')})"
    said = "ok" if s["siconos_info"] == 0 else "failed"
    return (f"{_rel(s['unit_free'])} after {thousands(s['iterations'])} its, "
            f"{dur(s['solve_time_s'])} (said {said})")


@generator("cones-bench", CONES)
def _bench(src):
    rows = []
    for p in need(_cones(src), "problems", where=CONES):
        siconos = {s["solver"]: s for s in p["siconos"]}
        for law in ("ccp", "coulomb"):
            x = need(p["laws"], law, where=CONES)
            d, db, n = x["direct"], x["direct_body"], x["nsgs_1000"]
            first = law == "ccp"
            rows.append([
                f"base {p['base']}: {thousands(p['contacts'])} ({thousands(p['rows'])} rows)"
                if first else "", law, cell(_cbps_cell(d)), cell(_cbps_cell(db)),
                cell(_cbps_cell(n)), f"{_ratio(d, n)} / {_ratio(db, n)}",
                "–" if first else cell(_siconos_cell(siconos["siconos:fc3d-nsgs"])),
                "–" if first else cell(_siconos_cell(siconos["siconos:fc3d-prox"]))])
    return table(["pyramid: contacts", "law", "`direct`, FCLIB file (row space)",
                  "`direct`, folder (body space)", "`nsgs`, 1,000 sweeps",
                  "direct / 1,000 sweeps (time): file / folder", "Siconos fc3d NSGS",
                  "Siconos PROX"], rows, "lllllrll")


def _target_lines(j):
    """Each target of issues 31 and 51 on these numbers (in the unit-free residual): met or not,
    and by what."""
    lines = []
    for p in j["problems"]:
        n = p["laws"]["ccp"]["nsgs_1000"]
        tn = read_number(n.get("wall_time_s"))
        if p["contacts"] < 400:
            continue
        parts = []
        for key, where in (("direct", "file, row space"), ("direct_body", "folder, body space")):
            d = p["laws"]["ccp"][key]
            rel, t = read_number(d.get("unit_free")), read_number(d.get("wall_time_s"))
            met = rel is not None and rel <= TARGET and t is not None and tn and t <= tn
            parts.append(f"{'met' if met else 'not met'} from the {where} (unit-free residual "
                         f"{_rel(rel)} in {dur(t) if t is not None else '–'})")
        lines.append(f"- relaxation, {thousands(p['contacts'])} contacts: {'; '.join(parts)}; "
                     f"1,000 nsgs sweeps {dur(tn) if tn is not None else '–'}")
    for p in j["problems"] + j["box_states"]:
        d = p["laws"]["coulomb"]["direct"]
        rel, t = read_number(d.get("unit_free")), read_number(d.get("wall_time_s"))
        prox = next(s for s in p["siconos"] if s["solver"] == "siconos:fc3d-prox")
        prox_t = prox.get("solve_time_s") if prox["status"] == "answered" else None
        exact = rel is not None and rel <= TARGET and d["status"] == "solved"
        speed = ("PROX gave no answer in " + dur(prox["job_s"]) if prox_t is None else
                 f"{prox_t / t:.3g}× sooner than PROX ({dur(prox_t)})" if t else "–")
        where = ", settling under the box" if p["state"] == "box" else ""
        lines.append(f"- Coulomb's law, {thousands(p['contacts'])} contacts{where}: "
                     f"{'exact' if exact else 'not exact'} (unit-free residual {_rel(rel)}, "
                     f"{d['status']}, {dur(t) if t is not None else '–'}); {speed}")
    return lines


@generator("cones-box-states", CONES)
def _box_states(src):
    rows = []
    for p in need(_cones(src), "box_states", where=CONES):
        siconos = {s["solver"]: s for s in p["siconos"]}
        x = need(p["laws"], "coulomb", where=CONES)
        rows.append([f"base {p['base']}: {thousands(p['contacts'])} ({thousands(p['rows'])} rows)",
                     cell(_cbps_cell(x["direct"])), cell(_cbps_cell(x["direct_body"])),
                     cell(_cbps_cell(x["nsgs_1000"])),
                     cell(_siconos_cell(siconos["siconos:fc3d-nsgs"])),
                     cell(_siconos_cell(siconos["siconos:fc3d-prox"]))])
    return table(["pyramid at step 3 under the box: contacts", "`direct`, FCLIB local file",
                  "`direct`, FCLIB global file (body space)", "`nsgs`, 1,000 sweeps",
                  "Siconos fc3d NSGS", "Siconos PROX"], rows, "llllll")


@generator("cones-targets", CONES)
def _targets(src):
    j = _cones(src)
    return "\n".join(_target_lines(j)) + "\n"


@generator("cones-budget", CONES)
def _budget(src):
    j = _cones(src)
    return (f"{dur(need(j, 'wall_time_s', where=CONES))} on {j['nproc']} cores, {j['date']}, "
            f"cbps {j['cbps_commit']}, Siconos' solvers limited to {dur(j['siconos_timeout_s'])}"
            + "".join(f"; {r['entry']} rerun alone on cbps {r['cbps_commit']}, {r['date']}"
                      for r in j.get("regenerated", [])))


BOX_CONE = "validation/results/box-cone/box_vs_cone.json"


def _deg(x):
    """Degrees to 3 decimals, without a sign on a turn that rounds to zero."""
    text = f"{x:.3f}"
    return ("0.000" if text == "-0.000" else text) + "°"


@generator("cones-box", BOX_CONE)
def _box(src):
    j = src.json(BOX_CONE, "cbps-box-cone/3")
    by = {(r["law"], r["phi_deg"]): r for r in need(j, "rows", where=BOX_CONE)}
    rows = []
    for phi in sorted({r["phi_deg"] for r in j["rows"]}):
        box, coulomb, cone = by[("paper", phi)], by[("coulomb", phi)], by[("cone", phi)]
        worst = max(abs(r[k] - r[k + "_closed"]) / max(1.0, abs(r[k + "_closed"]))
                    for r in (box, coulomb, cone)
                    for k in ("start_tan_over_mu", "acceleration", "turn_deg"))
        rows.append([f"{phi:g}°", f"{box['start_tan_over_mu']:.5f}",
                     f"{coulomb['start_tan_over_mu']:.5f}", f"{cone['start_tan_over_mu']:.5f}",
                     f"{box['acceleration']:.4f}", f"{cone['acceleration']:.4f}",
                     _deg(box["turn_deg"]), _deg(cone["turn_deg"]), sci(worst)])
    return table(["φ", "tan a*/μ paper", "tan a*/μ coulomb", "tan a*/μ cone",
                  "accel. box (m/s²)", "accel. cone (m/s²)", "turn, box", "turn, cone",
                  "largest gap to the closed forms"], rows, "rrrrrrrrr")


def _pile(src, name, closed_paper):
    """A pile's table: where sliding starts, its acceleration, the paper's turn, against the
    closed forms, and how far its boxes' accelerations are apart."""
    j = src.json(BOX_CONE, "cbps-box-cone/3")
    by = {(r["law"], r["phi_deg"]): r for r in need(j, name, where=BOX_CONE)}
    slide = need(j, "piles_slide_tan_over_mu", where=BOX_CONE)
    rows = []
    for phi in sorted({r["phi_deg"] for r in j[name]}):
        laws = [by[(law, phi)] for law in ("paper", "coulomb", "cone")]
        worst = max(abs(r[k] - r[k + "_closed"]) / max(1.0, abs(r[k + "_closed"]))
                    for r in laws for k in ("start_tan_over_mu", "acceleration", "turn_deg"))
        apart = max(r["boxes_apart"] for r in laws)
        rows.append([f"{phi:g}°"] + [f"{r['start_tan_over_mu']:.5f}" for r in laws] +
                    [f"{laws[0]['start_tan_over_mu_closed']:.5f}"] +
                    [f"{r['acceleration']:.4f}" for r in laws] +
                    [_deg(laws[0]["turn_deg"]), sci(worst), sci(apart)])
    return table(["φ", "tan a*/μ paper", "tan a*/μ coulomb", "tan a*/μ cone",
                  f"closed form, paper: {closed_paper}",
                  f"accel. paper (m/s², tan a = {slide:g} μ)", "accel. coulomb", "accel. cone",
                  "turn, paper", "largest gap to the closed forms",
                  "boxes' accelerations apart (m/s²)"], rows, "rrrrrrrrrrr")


@generator("cones-stack", BOX_CONE)
def _stack(src):
    return _pile(src, "stack", "1/(3 max(cos φ, sin φ))")


@generator("cones-pyramid-pile", BOX_CONE)
def _pyramid_pile(src):
    return _pile(src, "pyramid", "1/(2 max(cos φ, sin φ))")


PYRAMID_RUN = "validation/results/cones-pyramid/summary.json"


@generator("cones-pyramid-run", PYRAMID_RUN)
def _pyramid_run(src):
    j = src.json(PYRAMID_RUN)
    contacts = need(j, "contacts", where=PYRAMID_RUN)
    if contacts.get("friction") != "cone":
        raise SourceError(f"{PYRAMID_RUN}: /contacts/friction is not cone")
    return (f"{j['steps']} steps of {thousands(j['rows'])} rows ({thousands(contacts['max_points'])}"
            f" contacts, law {contacts['cone']}), the largest residual of any step "
            f"{sci(j['max_residual'], 3)} N (tolerance 1e-10 N), {dur(j['wall_time_s'])} in all")
