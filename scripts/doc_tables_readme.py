"""The generated parts of README.md (scripts/doc_tables.py): the test suite's time, the main
job's table (the pendulum wave) and the headline of the generated chain under MPI
(docs/distributed.md).
"""
from doc_tables_common import (  # scripts/doc_tables_common.py
    GENERATE, PW, dur, generate_model, generator, need, num, sci, table, thousands)


# ---------------------------------------------------------------------------------------------
# The test suite's time (scripts/measure_suite.py's committed measurement).

SUITE = "validation/results/test-suite/release.json"


@generator("suite-release", SUITE)
def _suite_release(src):
    r = src.json(SUITE)
    labels = need(r, "labels", where=SUITE)
    petsc = labels.get("petsc")
    text = (f"{r['tests']} tests in {dur(r['wall_time_s'])} of wall time with "
            f"`ctest -j{r['jobs']}` on {r['cores']} cores")
    if petsc:  # CTest's label times are summed over the tests, not wall time
        text += f" (the {petsc['tests']} PETSc tests {dur(petsc['seconds'])} of test time)"
    return text + f", {r['date']}" + (f"; {r['note']}" if r.get("note") else "")


# ---------------------------------------------------------------------------------------------
# The main job: the pendulum wave (validation/pendulum_wave_report.py's report.json).


@generator("pendulum-wave", PW)
def _pendulum_wave(src):
    r = src.json(PW)
    t = need(r, "timing", where=PW)
    cc = need(r, "cross_check", where=PW)
    rows = [
        ("simulated", f"{thousands(r['steps'])} steps of dt = 1/{round(1 / r['dt'])} s, "
                      f"{r['bodies']} bodies, {r['rows']} rows, solver {r['solver']['method']}"),
        ("time in the solver's stages (sum of `summary.json` `stage_times_s`: collision, rows, "
         "assembly, solve, integrate)", dur(t["stage_time_sum_s"])),
        ("time in the steps, with the `--check` cross-check (sum of `steps.csv` `wall_time_s`)",
         dur(t["steps_wall_time_s"])),
        ("time of the whole step loop, with writing each step's rows of `steps.csv` and "
         "`trajectory.csv` (`summary.json` `wall_time_s`)", dur(t["wall_time_s"])),
        ("max constraint error \\|c\\| (5.2.2)", f"{sci(r['max_constraint_error'])} m"),
        ("PGS against the direct path on every step (`--check`): max \\|v2 − v2_direct\\|",
         f"{sci(cc['max_velocity_difference'])} m/s over {thousands(cc['steps_checked'])} steps"),
        ("max natural-map residual", f"{sci(r['max_residual'])} N"),
        ("max relative period error of a ball, against its design period",
         sci(r["max_abs_period_error"])),
        ("largest phase error when the wave realigns at t = 60 s",
         f"{num(r['max_abs_phase_deg'])}°"),
    ]
    return table(["quantity", "value"], rows)


# ---------------------------------------------------------------------------------------------
# PETSc/TAO under MPI (the numbers docs/distributed.md details).


@generator("generate-headline", GENERATE)
def _generate_headline(src):
    r = src.json(GENERATE)
    run = next(x for x in need(r, "runs", where=GENERATE)
               if x["ranks"] == 2 and x["type"] == "bqpip" and x["rows"] == 1000000)
    base, per_row, _, _ = generate_model(r)
    return (f"1,000,000 rows at 2 ranks: {run['status']}, residual {sci(run['residual'])} N, "
            f"job {dur(run['job_s'])}, {round(max(run['rank_memory_mb']))} MB on the largest "
            f"rank; measured memory {round(base)} MB a rank plus {round(per_row)} bytes a row")
