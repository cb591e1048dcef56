"""The generated parts of validation/README.md (scripts/doc_tables.py): the pendulum wave's runs,
validate_pendulum's periods in full and its beta study, and validate_contacts' tables.
"""
import math

from doc_tables_common import (  # scripts/doc_tables_common.py
    CONTACTS, PW, PW_CENTER, SourceError, VAL, csv_rows, dur, generator, length, minus,
    need, num, sci, table, thousands, validation_rows)


# ---------------------------------------------------------------------------------------------
# The pendulum wave's runs (validation/pendulum_wave_report.py's report.json).

PW_DT960 = "validation/results/pendulum-wave-dt960/report.json"
PW_THETA2 = "validation/results/pendulum-wave-theta2/report.json"


@generator("pendulum-wave-runs", PW, PW_DT960, PW_THETA2, PW_CENTER)
def _pendulum_runs(src):
    rows = []
    for rel, label in ((PW, "attach=top (default, dt = 1/240, θ0 = 15°)"),
                       (PW_DT960, "attach=top, dt = 1/960"),
                       (PW_THETA2, "attach=top, θ0 = 2°"),
                       (PW_CENTER, "attach=center (dt = 1/240)")):
        r = src.json(rel)
        double = r.get("max_abs_double_error")
        rows.append((label, sci(r["max_abs_period_error"], 3),
                     "—" if double is None else sci(double), f"{num(r['max_abs_phase_deg'])}°"))
    return table(["run", "max \\|T_meas − T_k\\|/T_k", "max \\|T_double − T_k\\|/T_k",
                  "max \\|phase\\| at cycle"], rows, "lrrr")


# ---------------------------------------------------------------------------------------------
# Validation of the pendulum periods (validate_pendulum).


@generator("validation-periods-full", VAL)
def _validation_periods_full(src):
    _, rows = validation_rows(src)
    out = []
    for r in rows:
        def order(key):
            return "" if r.get(key) is None else f"{r[key]:.2f}"
        out.append((r["dt_inv"], f"{r['max_rel_error']:.3e}", f"{r['mean_rel_error']:.3e}",
                    minus(f"{r['mean_signed_rel_error']:+.3e}"), order("order_max"),
                    order("order_mean"), num(r["max_phase_error_deg"], 3),
                    num(r["max_drift_phase_deg"], 3),
                    minus(f"{r['mean_time_offset_over_dt']:.3f}"),
                    minus(f"{r['mean_amplitude_change']:.1e}"),
                    f"{r['max_constraint_error_m']:.1e}"))
    return table(["1/dt (1/s)", "max \\|e\\|", "mean \\|e\\|", "mean e", "p (max)", "p (mean)",
                  "max \\|phase\\| at cycle (°)", "max \\|drift\\| (°)", "offset / dt",
                  "amplitude change", "max \\|c\\| (m)"], out, "rrrrrrrrrrr")


BETA = "validation/results/beta-study/beta-{}-theta-{}.csv"
BETA0 = "validation/results/beta-study/beta-0.json"


@generator("validation-beta", *[BETA.format(b, t) for b in (0.1, 0.2, 0.4, 0.8) for t in (15, 2)])
def _validation_beta(src):
    """Ball 0 at 1/dt = 7680: e/(ω dt)² and ½ c̄/L / (ω dt)² by β and θ0."""
    def ball0(b, theta):
        rel = BETA.format(b, theta)
        for r in csv_rows(src, rel):
            if r["dt_inv"] == "7680" and r["k"] == "0":
                w2dt2 = (2 * math.pi / float(r["period_exact_s"]) * float(r["dt"])) ** 2
                return float(r["rel_error"]) / w2dt2, 0.5 * float(r["mean_stretch"]) / w2dt2
        raise SourceError(f"{rel}: no row for ball 0 at 1/dt = 7680")
    rows = []
    for b in (0.1, 0.2, 0.4, 0.8):
        e15, s15 = ball0(b, 15)
        e2, _ = ball0(b, 2)
        rows.append((b, minus(f"{e15:+.4f}"), f"{s15:.4f}", minus(f"{e2:+.4f}")))
    return table(["β", "θ0 = 15°: e/(ωdt)²", "θ0 = 15°: ½ c̄/L / (ωdt)²", "θ0 = 2°: e/(ωdt)²"],
                 rows, "rrrr")


@generator("validation-beta-zero", BETA0)
def _validation_beta_zero(src):
    runs = sorted(need(src.json(BETA0), "runs", where=BETA0), key=lambda r: float(r["dt_inv"]))
    errors = ", ".join(sci(r["mean_rel_error"]) for r in runs)
    orders = [r["order_mean"] for r in runs if r.get("order_mean") is not None]
    stretch = [r["max_constraint_error_m"] for r in runs]
    return (f"e = {errors} (mean), order {min(orders):.2f} … {max(orders):.2f}: first order, as "
            f"predicted, with the string stretched by up to {length(min(stretch))} … "
            f"{length(max(stretch))}")


# ---------------------------------------------------------------------------------------------
# Contacts (validate_contacts: validation/results/contacts.json).


def _e1(x):
    return f"{x:.1e}"


@generator("contacts-v-corner", CONTACTS)
def _contacts_v_corner(src):
    rows = []
    for r in need(src.json(CONTACTS), "v_corner", where=CONTACTS):
        if r["margin"] <= 0:
            continue
        rows.append((r["angle_left_deg"], r["angle_right_deg"], f"{r['lambda1_ref']:.6f}",
                     f"{r['lambda2_ref']:.6f}", f"{r['lambda1_direct']:.6f}",
                     f"{r['lambda2_direct']:.6f}", _e1(r["error_direct_over_mg"]),
                     f"{r['lambda1_pgs']:.6f}", f"{r['lambda2_pgs']:.6f}",
                     _e1(r["error_pgs_over_mg"]), f"{r['pgs_sweeps_last']}, {r['pgs_sweeps_max']}"))
    return table(["φ_l (°)", "φ_r (°)", "λ₁ ref (N)", "λ₂ ref (N)", "λ₁ direct", "λ₂ direct",
                  "err direct / mg", "λ₁ PGS", "λ₂ PGS", "err PGS / mg",
                  "PGS sweeps (last, max)"], rows, "r" * 11)


@generator("contacts-v-corner-margin0", CONTACTS)
def _contacts_v_corner0(src):
    rows = []
    for r in need(src.json(CONTACTS), "v_corner", where=CONTACTS):
        if r["margin"] != 0:
            continue
        rows.append((r["angle_left_deg"], r["angle_right_deg"], _e1(r["error_direct_over_mg"]),
                     _e1(r["error_pgs_over_mg"]),
                     f"{r['steps_missing_a_contact_direct']}, {r['steps_missing_a_contact_pgs']}",
                     _e1(r["speed_end_direct"]), _e1(r["speed_end_pgs"])))
    return table(["φ_l (°)", "φ_r (°)", "err direct / mg", "err PGS / mg",
                  "steps missing a contact (direct, PGS)", "speed at 2 s, direct (m/s)",
                  "speed at 2 s, PGS (m/s)"], rows, "r" * 7)


@generator("contacts-bounce", CONTACTS)
def _contacts_bounce(src):
    rows = []
    for r in need(src.json(CONTACTS), "bounce", where=CONTACTS):
        rows.append([r["restitution"], r["dt"], f"{r['ratio_ref']:.4f}"]
                    + [f"{h:.4f}" for h in r["apex"]] + [f"{q:.4f}" for q in r["ratio"]]
                    + [f"{r['max_ratio_rel_error']:.2e}",
                       f"{r['max_speed_ratio_error']:.1e} ({r['impacts']})"])
    return table(["ε", "dt (s)", "ε²", "h₁ (m)", "h₂ (m)", "h₃ (m)", "h₁/h₀", "h₂/h₁", "h₃/h₂",
                  "max \\|ratio − ε²\\|/ε²", "max \\|v₊/v₋ − ε\\| (impacts)"], rows, "r" * 11)


@generator("contacts-slide", CONTACTS)
def _contacts_slide(src):
    rows = []
    for r in need(src.json(CONTACTS), "slide", where=CONTACTS):
        mg = r["mu"] * 9.81
        rows.append((r["mu"], r["dt"], r["solver"], f"{r['distance_ref']:.4f}",
                     f"{r['distance_euler']:.4f}", f"{r['distance']:.4f}",
                     f"{(r['distance'] - r['distance_ref']) / r['distance_ref']:.2e}",
                     f"{r['time_ref']:.4f}", f"{r['time']:.4f}",
                     f"{(r['time'] - r['time_ref']) / r['time_ref']:+.2e}"
                     if r["time"] != r["time_ref"] else "< 1e-9",
                     f"{r['deceleration'] / mg:.5f}", f"{r['creep']:.1e}", r["sweeps_max"]))
    return table(["μ", "dt (s)", "solver", "d ref (m)", "d Euler (m)", "d (m)",
                  "(d − d ref)/d ref", "t ref (s)", "t (s)", "(t − t ref)/t ref", "decel / μg",
                  "creep (m)", "iterations max"], rows, "rrlrrrrrrrrrr")


def _g3(x):
    return "%.3g" % x


@generator("contacts-overlap", CONTACTS)
def _contacts_overlap(src):
    rows = []
    for r in need(src.json(CONTACTS), "overlap", where=CONTACTS):
        rows.append((r["push"], r["solver"], f"{r['t_resolved']:.3f}",
                     _g3(r["kinetic_energy_injected"]), _g3(r["kinetic_energy_resolved"]),
                     _g3(r["kinetic_energy_max"]),
                     f"{r['top_start']:.3f}, {r['top_rest']:.3f}, {r['top_max']:.3f}",
                     f"{r['t_top_max']:.3f}", r["sweeps_max"]))
    return table(["push", "solver", "t resolved (s)", "KE injected: max until resolved (J)",
                  "KE then (J)", "max KE over 2 s (J)", "top box: start, rest, max (m)",
                  "t of max (s)", "iterations max"], rows, "llrrrrrrr")


@generator("contacts-column", CONTACTS)
def _contacts_column(src):
    rows = []
    for r in need(src.json(CONTACTS), "column", where=CONTACTS):
        steps = round(r["duration"] / r["dt"])
        slides = max(r["slip_bottom"], r["slip_top"]) >= 1e-3
        rows.append((r["n"], r["friction"], "slides" if r["predicted_slide"] else "holds",
                     f"{r['predicted_slip']:.5f}", f"{r['predicted_slip_euler']:.5f}",
                     "%.5g" % r["slip_bottom"], "%.5g" % r["slip_top"],
                     f"{r['max_tilt_deg']:.1e}", "slides" if slides else "holds",
                     f"{r['steps_short_of_tolerance']} of {steps}", f"{r['wall_time_s']:.2f}"))
    return table(["n", "friction", "predicted", "slip ½at² (m)", "Euler ½at(t+dt) (m)",
                  "slip bottom (m)", "slip top (m)", "max tilt (°)", "outcome",
                  "steps short of tolerance", "wall (s)"], rows, "rllrrrrrlrr")


@generator("contacts-wall", CONTACTS)
def _contacts_wall(src):
    return dur(need(src.json(CONTACTS), "wall_time_s", where=CONTACTS))


@generator("contacts-slide-euler-gap", CONTACTS)
def _contacts_slide_gap(src):
    rows = need(src.json(CONTACTS), "slide", where=CONTACTS)

    def gap(sel):
        return max(abs(r["distance"] - r["distance_euler"]) for r in rows if sel(r))
    return (f"{sci(gap(lambda r: r['solver'] == 'direct' and r['mu'] > 0.3))} m at μ = 0.6, "
            f"direct; ≤ {sci(gap(lambda r: r['solver'] == 'direct' and r['mu'] <= 0.3))} m at "
            f"μ ≤ 0.3; PGS within {sci(gap(lambda r: r['solver'] == 'pgs'))} m")


@generator("contacts-slide-pgs", CONTACTS)
def _contacts_slide_pgs(src):
    rows = [r for r in need(src.json(CONTACTS), "slide", where=CONTACTS) if r["solver"] == "pgs"]
    return (f"at most {max(r['sweeps_max'] for r in rows)} sweeps in a step (of the 100 allowed), "
            f"and the stopped box creeps by at most {sci(max(abs(r['creep']) for r in rows))} m "
            "in the rest of the run")


@generator("contacts-figure-energies", CONTACTS)
def _contacts_figure(src):
    panels = need(src.json(CONTACTS), "push_factor_figure", "panels", where=CONTACTS)
    e = {p["label"]: p["kinetic_energy_injected"] for p in panels}
    return f"{num(e['original'])} J and {sci(e['improved'])} J"


@generator("contacts-column-coulomb-slip", CONTACTS)
def _contacts_column_slip(src):
    rows = need(src.json(CONTACTS), "column", where=CONTACTS)
    return f"{sci(max(max(r['slip_bottom'], r['slip_top']) for r in rows if r['friction'] == 'coulomb'))} m"


@generator("contacts-column-cost", CONTACTS)
def _contacts_column_cost(src):
    rows = {(r["n"], r["friction"]): r for r in need(src.json(CONTACTS), "column", where=CONTACTS)}
    c, p = rows[(5, "coulomb")], rows[(5, "paper")]
    steps = round(c["duration"] / c["dt"])
    return (f"{c['steps_short_of_tolerance']} of {steps} steps end short of tolerance (up to "
            f"{thousands(c['sweeps_max'])} outer iterations in a step) and the run takes "
            f"{dur(c['wall_time_s'])} against {dur(p['wall_time_s'])} with the paper's fixed bounds")
