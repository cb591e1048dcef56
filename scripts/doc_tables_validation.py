"""The generated parts of docs/validation.md (scripts/doc_tables.py): the pendulum wave with
attach=center, and validate_pendulum's periods.
"""
import math

from doc_tables_common import (  # scripts/doc_tables_common.py
    PW_CENTER, VAL, generator, need, num, sci, table, validation_rows)


# ---------------------------------------------------------------------------------------------
# The pendulum wave with attach=center (validation/pendulum_wave_report.py).


@generator("pendulum-wave-center-error", PW_CENTER)
def _pendulum_center_error(src):
    return sci(need(src.json(PW_CENTER), "max_abs_period_error", where=PW_CENTER))


@generator("pendulum-wave-center-phase", PW_CENTER)
def _pendulum_center_phase(src):
    return f"{num(need(src.json(PW_CENTER), 'max_abs_phase_deg', where=PW_CENTER))}°"


# ---------------------------------------------------------------------------------------------
# Validation of the pendulum periods (validate_pendulum).


@generator("validation-periods", VAL)
def _validation_periods(src):
    _, rows = validation_rows(src)
    out = []
    for r in rows:
        order = r.get("order_max")
        out.append((r["dt_inv"], sci(r["max_rel_error"], 3), sci(r["mean_rel_error"], 3),
                    "–" if order is None else f"{order:.2f}",
                    f"{num(r['max_phase_error_deg'], 3)}°"))
    return table(["1/dt (s⁻¹)", "max error", "mean error", "observed order (max)",
                  "max phase error at t = cycle"], out, "rrrrr")


@generator("validation-asymptotic", VAL)
def _validation_asymptotic(src):
    """The finest step's largest period error over (ω dt)² of the fastest ball."""
    v, rows = validation_rows(src)
    sc = need(v, "scene", where=VAL)
    finest = rows[-1]
    omega = 2 * math.pi * (sc["n0"] + sc["n"] - 1) / sc["cycle_s"]
    ratio = finest["max_rel_error"] / (omega * finest["dt"]) ** 2
    return f"{ratio:.3f} (ω dt)² of the fastest ball at 1/dt = {finest['dt_inv']}"


@generator("validation-elliptic-k", VAL)
def _validation_elliptic(src):
    return sci(need(src.json(VAL), "elliptic_K", "max_rel_diff_vs_kcomp", where=VAL))
