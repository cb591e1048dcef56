"""The generated parts of docs/distributed.md (scripts/doc_tables.py): PETSc/TAO under MPI, the
generated chain and its memory model, and TAO beside the library's solvers. The headline of the
generated chain is README.md's (scripts/doc_tables_readme.py).
"""
from doc_tables_common import (  # scripts/doc_tables_common.py
    GENERATE, SourceError, dur, generate_model, generator, minus, need, num, sci, table,
    thousands)


# ---------------------------------------------------------------------------------------------
# PETSc/TAO under MPI (scripts/measure_tao.py: validation/results/distributed/tao.json).

TAO = "validation/results/distributed/tao.json"


def _unit_free(run):
    """The run's unit-free residual, the verdict's (docs/cones.md), as the JSON gave it."""
    u = run.get("unit_free")
    return "–" if u is None else sci(u)


@generator("tao-measured", TAO)
def _tao_measured(src):
    r = src.json(TAO)
    rows = []
    for run in need(r, "runs", where=TAO):
        res = run["residual"]
        rows.append((run["problem"], f"`{run['solver']}`", str(run["ranks"]), run["status"],
                     thousands(run["iterations"]), dur(run["wall_time_s"]),
                     "–" if res is None else sci(res), _unit_free(run),
                     run.get("reason", "–")))
    return table(("problem", "solver", "ranks", "status", "iterations", "wall time",
                  "residual (N)", "unit-free (solved ≤ 1e-9)", "TAO's reason"), rows,
                 "lllllrrrl")


# ---------------------------------------------------------------------------------------------
# The exact path under MPI (scripts/measure_direct_mpi.py: bench/results/direct-mpi-*.json).

DIRECT_MPI = "bench/results/direct-mpi-amd-epyc-2cpu.json"


def _direct_cells(run):
    d = run.get("direct")
    if d is None:
        counts = run.get("tao", {}).get("reason", "–")
    else:
        counts = (f"{d['interior_iterations']} + {d['crossover_steps']} steps, "
                  f"{d['factorizations']} factorizations, {d['low_rank_rows']} low-rank rows")
    memory = ", ".join(str(round(m)) for m in run.get("rank_memory_mb", [])) or "–"
    return [run["status"], sci(run["residual_N"]), _unit_free(run),
            dur(run["solve_s"]), dur(run["process_s"]), memory, counts]


@generator("direct-mpi", DIRECT_MPI)
def _direct_mpi(src):
    r = src.json(DIRECT_MPI)
    rows = []
    for f in need(r, "folders", where=DIRECT_MPI):
        name = f"{f['folder']} ({thousands(f['rows'])} rows)"
        rows.append([name, "`direct`, one process"] + _direct_cells(f["serial"]))
        for run in f["mpi"]:
            rows.append(["", f"`direct`, `mpirun -n {run['ranks']}`"] + _direct_cells(run))
        for run in f["tao"]:
            rows.append(["", f"`tao:{run['tao']['type']}`, `mpirun -n {run['ranks']}`, "
                             f"{r['tao_iterations']} iterations"] + _direct_cells(run))
    return table(("folder", "solver", "status", "residual (N)", "unit-free", "solve",
                  "process", "memory per rank (MB)", "what it did"), rows, "llllrrrrl")


# ---------------------------------------------------------------------------------------------
# Generated contact problems on the exact path under MPI (scripts/measure_generate_pyramid.py:
# bench/results/generate-pyramid-*.json).

GENERATE_PYRAMID = "bench/results/generate-pyramid-amd-epyc-2cpu.json"


def _assembly(serial):
    """The one-process run's assembly: its time and whether it formed A (a stage named "without
    A" did not; results before it was named formed A)."""
    without = "without A" in serial.get("assembly_stage", "")
    return f"{dur(serial['assembly_s'])} {'assembly without A' if without else 'forming A'}"


def _pyramid_runs(src):
    return need(src.json(GENERATE_PYRAMID), "runs", where=GENERATE_PYRAMID)


@generator("generate-pyramid", GENERATE_PYRAMID)
def _generate_pyramid(src):
    rows = []
    for run in _pyramid_runs(src):
        s = run["serial"]
        name = f"{thousands(s['rows'])} (base {run['base']})"
        rows.append([name, "one process", "solved" if s["exit"] == 0 else f"exit {s['exit']}",
                     sci(s["residual_N"]), "–", "–",
                     f"{dur(s['solve_s'])} (+ {_assembly(s)})",
                     dur(s["process_s"]), str(round(s["peak_memory_mb"])), "–"])
        for m in run["mpi"]:
            d = m["direct"]
            rows.append(["", f"`mpirun -n {m['ranks']}`", m["status"], sci(m["residual_N"]),
                         _unit_free(m), dur(m["build_s"]),
                         dur(m["solve_s"]), dur(m["process_s"]),
                         ", ".join(str(round(x)) for x in m["rank_memory_mb"]),
                         f"{d['interior_iterations']} + {d['crossover_steps']} steps, "
                         f"{d['factorizations']} factorizations"])
    return table(("rows", "path", "status", "residual (N)", "unit-free", "build rows", "solve",
                  "process", "memory per rank (MB)", "what it did"), rows, "lllrrrrrll")


@generator("generate-pyramid-headline", GENERATE_PYRAMID)
def _generate_pyramid_headline(src):
    run = max(_pyramid_runs(src), key=lambda x: x["serial"]["rows"])
    s = run["serial"]
    parts = []
    for m in run["mpi"]:
        parts.append(f"at {m['ranks']} rank{'s' if m['ranks'] > 1 else ''} {m['status']} in "
                     f"{dur(m['solve_s'])} ({sci(m['residual_N'])} N, "
                     f"{', '.join(str(round(x)) for x in m['rank_memory_mb'])} MB)")
    return (f"The {thousands(s['rows'])}-row pyramid (base {run['base']}): "
            + "; ".join(parts) + f"; one process solved it in {dur(s['solve_s'])} "
            f"({sci(s['residual_N'])} N) after {_assembly(s)}, "
            f"{round(s['peak_memory_mb'])} MB")


def _solve3(M, v):
    """x with M x = v (3×3, Gaussian elimination with partial pivoting)."""
    M = [row[:] + [b] for row, b in zip(M, v)]
    for k in range(3):
        p = max(range(k, 3), key=lambda i: abs(M[i][k]))
        M[k], M[p] = M[p], M[k]
        for i in range(k + 1, 3):
            f = M[i][k] / M[k][k]
            M[i] = [a - f * b for a, b in zip(M[i], M[k])]
    x = [0.0, 0.0, 0.0]
    for k in (2, 1, 0):
        x[k] = (M[k][3] - sum(M[k][j] * x[j] for j in range(k + 1, 3))) / M[k][k]
    return x


def pyramid_model(src):
    """Peak memory of the largest rank = base + shared × rows / ranks + every × rows (MB, bytes
    a row), fitted by least squares to every MPI run; (base, shared, every, checks)."""
    runs = [m for run in _pyramid_runs(src) for m in run["mpi"]]
    X = [(1.0, m["rows"] / m["ranks"] / 2**20, m["rows"] / 2**20) for m in runs]
    y = [max(m["rank_memory_mb"]) for m in runs]
    M = [[sum(a[i] * a[j] for a in X) for j in range(3)] for i in range(3)]
    v = [sum(a[i] * t for a, t in zip(X, y)) for i in range(3)]
    base, shared, every = _solve3(M, v)
    checks = [(m, base + shared * a[1] + every * a[2], t) for m, a, t in zip(runs, X, y)]
    return base, shared, every, checks


@generator("generate-pyramid-model", GENERATE_PYRAMID)
def _generate_pyramid_model(src):
    base, shared, every, checks = pyramid_model(src)
    rows = [(thousands(m["rows"]), str(m["ranks"]), str(round(p)), str(round(t)),
             minus(f"{num(100 * (t - p) / p)} %")) for m, p, t in checks]
    return (f"Fitted here: an empty rank {round(base)} MB, {round(shared)} bytes a row shared "
            f"among the ranks and {round(every)} bytes a row on every rank. Against every run:"
            "\n\n" + table(("rows", "ranks", "model (MB)", "measured, largest rank (MB)",
                            "off by"), rows, "rrrrr"))


@generator("generate-pyramid-model-1e8", GENERATE_PYRAMID)
def _generate_pyramid_model_1e8(src):
    base, shared, every, _ = pyramid_model(src)
    parts = []
    for ranks in (16, 64, 256):
        gb = (base + (shared / ranks + every) * 1e8 / 2**20) / 1024
        parts.append(f"{ranks} ranks {num(gb, 2)} GB each")
    return (f"By this model 10⁸ rows (base 2,887, 4.2 million boxes) need {num(every * 1e8 / 2**30, 2)} "
            f"GB on every rank whatever their number, plus their share: " + ", ".join(parts) +
            ". The part every rank holds is what stops it: 10⁸ rows need it gone (an ordering "
            "and symbolic analysis that are themselves distributed) before more ranks help")


@generator("generate-pyramid-messages", GENERATE_PYRAMID)
def _generate_pyramid_messages(src):
    run = max(_pyramid_runs(src), key=lambda x: x["serial"]["rows"])
    m = next(x for x in run["mpi"] if x["ranks"] == 2)
    lv, d = m["log_view"], m["direct"]
    ev = lv["events"]
    its = max(d["interior_iterations"] + d["crossover_steps"], 1)
    products = ev["MatMult"]["calls"] + ev["MatMultTranspose"]["calls"]
    product_messages = ev["MatMult"]["messages"] + ev["MatMultTranspose"]["messages"]
    return (f"{thousands(m['rows'])} rows at 2 ranks, {its} iterations: PETSc sent "
            f"{thousands(lv['messages'])} messages ({num(lv['message_bytes'] / 2**20)} MB) and "
            f"made {thousands(lv['reductions'])} reductions in the whole job; its "
            f"{thousands(products)} products with `J` and `Jᵀ` sent "
            f"{thousands(product_messages)} messages of "
            f"{num(ev['MatMult']['average_bytes'] / 1024)} kB on average "
            f"({num(product_messages / products / m['ranks'])} a rank a product), "
            f"and its {thousands(ev['MatAssemblyBegin']['calls'])} matrix assemblies (`H` at "
            f"each factorization) {thousands(ev['MatAssemblyBegin']['messages'])}; the interior "
            f"point made "
            f"{thousands(d['reductions'])} reductions of its own "
            f"({num(d['reductions'] / its)} an iteration)")


# ---------------------------------------------------------------------------------------------
# The generated chain (scripts/measure_generate.py: validation/results/distributed/generate.json).


def _memory(run):
    return ", ".join(str(round(m)) for m in run["rank_memory_mb"])


@generator("generate-measured", GENERATE)
def _generate_measured(src):
    r = src.json(GENERATE)
    rows = []
    for run in need(r, "runs", where=GENERATE):
        tao = run["log_view"]["events"].get("TaoSolve", {})
        rows.append((thousands(run["rows"]), str(run["ranks"]), run["type"], run["status"],
                     thousands(run["iterations"]), sci(run["residual"]), _unit_free(run),
                     dur(run["generate_s"]), dur(run["solve_s"]), dur(run["job_s"]),
                     _memory(run), thousands(tao.get("messages", 0)),
                     thousands(tao.get("reductions", 0)), num(run["load_average"])))
    return table(("rows", "ranks", "type", "status", "iterations", "residual (N)", "unit-free",
                  "build rows", "solve", "job", "peak memory per rank (MB)",
                  "messages in TaoSolve", "reductions in TaoSolve", "load"), rows,
                 "rrllrrrrrrlrrr")


@generator("generate-model", GENERATE)
def _generate_model(src):
    base, per_row, checks, fit = generate_model(src.json(GENERATE))
    rows = [(thousands(x["rows"]), str(x["ranks"]), str(round(p)), str(round(m)),
             minus(f"{num(100 * (m - p) / p)} %")) for x, p, m in checks]
    return (f"Fitted here: an empty rank {round(base)} MB (the 10-row job); {round(per_row)} "
            f"bytes a row (bqpip; the slope between the {thousands(fit[0])}- and "
            f"{thousands(fit[1])}-row jobs at 1 rank). Against "
            f"every bqpip run of at least 100,000 rows:\n\n"
            + table(("rows", "ranks", "model: base + bytes a row × rows / ranks (MB)",
                     "measured, largest rank (MB)", "off by"), rows, "rrrrr"))


@generator("generate-model-1e8", GENERATE)
def _generate_model_1e8(src):
    base, per_row, _, _ = generate_model(src.json(GENERATE))
    parts = []
    for ranks in (16, 64, 256):
        mb = base + per_row * 1e8 / ranks / 2**20
        parts.append(f"{ranks} ranks {num(mb / 1024, 2)} GB each" if mb >= 1024
                     else f"{ranks} ranks {round(mb)} MB each")
    total = per_row * 1e8 / 2**30
    return (f"10⁸ rows need {num(total, 2)} GB of rows in all ({round(per_row)} bytes a row) "
            f"plus {round(base)} MB a rank: " + ", ".join(parts))


@generator("generate-messages", GENERATE)
def _generate_messages(src):
    r = src.json(GENERATE)
    run = next(x for x in need(r, "runs", where=GENERATE)
               if x["ranks"] == 2 and x["type"] == "bqpip" and x["rows"] == 1000000)
    ev = run["log_view"]["events"]
    tao, mult = ev["TaoSolve"], ev["MatMult"]
    its = max(run["iterations"], 1)
    return (f"1,000,000 rows at 2 ranks, bqpip, {its} iterations: `TaoSolve` sent "
            f"{thousands(tao['messages'])} messages of {num(tao['average_bytes'])} bytes on "
            f"average and made {thousands(tao['reductions'])} reductions "
            f"({num(tao['reductions'] / its)} an iteration); the job's {thousands(mult['calls'])} "
            f"`MatMult`s sent {thousands(mult['messages'])} messages "
            f"({num(mult['messages'] / mult['calls'] / run['ranks'])} a rank a product)")


@generator("read-rows", GENERATE)
def _read_rows(src):
    parts = []
    for x in need(src.json(GENERATE), "read", where=GENERATE):
        parts.append(f"{x['ranks']} rank{'s' if x['ranks'] > 1 else ''}: {x['status']}, read in "
                     f"{dur(x['read_s'])}, solved in {dur(x['solve_s'])}, "
                     f"{', '.join(str(round(m)) for m in x['rank_memory_mb'])} MB")
    return "; ".join(parts)


@generator("generate-exact", GENERATE)
def _generate_exact(src):
    e = need(src.json(GENERATE), "exact", where=GENERATE)
    d, g = e["direct"], e["generated"]
    return (f"{thousands(e['rows'])} rows: the direct path on the serial folder {d['status']} "
            f"with residual {sci(d['residual'])} N, `mpirun -n 2` tao:bqpip on the generated "
            f"problem {g['status']} with {sci(g['residual'])} N (unit-free residuals "
            f"{sci(d['unit_free'])} and {sci(g['unit_free'])}, solved at ≤ 1e-9); their λ "
            f"differ by at most "
            f"{sci(e['lambda_max_difference'])} N (largest |λ| {num(e['lambda_largest'])} N)")


# ---------------------------------------------------------------------------------------------
# TAO beside PGS (scripts/measure_tao_studies.py: validation/results/distributed/tao-studies.json).

TAO_STUDIES = "validation/results/distributed/tao-studies.json"


def _tao_reached(x, tol):
    r = (x.get("reached") or {}).get(tol)
    return "–" if r is None else f"{thousands(r['iterations'])} / {dur(r['time_s'])}"


def _tao_converge(src, name, tolerances):
    c = need(src.json(TAO_STUDIES), "converge", name, where=TAO_STUDIES)
    rows = []
    for x in c["solvers"]:
        stopped = "" if x["stopped"] in ("residual tolerance", None) else f" ({x['stopped']})"
        rows.append((f"`{x['solver']}`", thousands(x["iterations"]), dur(x["time_s"]) + stopped,
                     sci(x["residual"]), sci(x["velocity_error"]))
                    + tuple(_tao_reached(x, t) for t in tolerances))
    return table(("solver", "sweeps", "time", "residual (N)", "v₂ − v₂ of direct (m/s)")
                 + tuple(f"to {t} N (sweeps / time)" for t in tolerances), rows,
                 "lrrrr" + "r" * len(tolerances))


@generator("tao-converge-chain", TAO_STUDIES)
def _tao_converge_chain(src):
    return _tao_converge(src, "chain", ("1e-06", "1e-10"))


@generator("tao-converge-stack", TAO_STUDIES)
def _tao_converge_stack(src):
    return _tao_converge(src, "stack", ("0.001", "1e-06"))


@generator("tao-profile", TAO_STUDIES)
def _tao_profile(src):
    pr = need(src.json(TAO_STUDIES), "profile", where=TAO_STUDIES)
    n = len(pr["problems"])

    def rho(measure):
        for p in pr["profiles"]:
            if p["measure"] == measure and abs(p["tolerance"] - 1e-10) <= 1e-13:
                return p["rho"]
        raise SourceError(f"{TAO_STUDIES}: no {measure} profile at 1e-10")
    time10, sweeps10 = rho("time"), rho("sweeps")
    rows = []
    for solver in pr["solvers"]:
        name = solver["solver"]
        t = time10[name]
        sw = ("–", "–") if solver["exact"] else (num(sweeps10[name]["1"], 3),
                                                 num(sweeps10[name]["10"], 3))
        rows.append((f"`{name}`", f"{round(t['inf'] * n)}/{n}", num(t["1"], 3), num(t["10"], 3))
                    + sw)
    return table(("solver", "solved", "time ρ(1)", "time ρ(10)", "sweeps ρ(1)",
                  "sweeps ρ(10)"), rows, "lrrrrr")


@generator("tao-profile-unsolved", TAO_STUDIES)
def _tao_profile_unsolved(src):
    pr = need(src.json(TAO_STUDIES), "profile", where=TAO_STUDIES)
    parts = []
    for solver in pr["solvers"]:
        if solver["method"] != "tao":
            continue
        missed = [f"{m['problem']} ({sci(m['residual_relative'])})"
                  for m in pr["measurements"]
                  if m["solver"] == solver["solver"] and m["status"] != "solved"]
        parts.append(f"`{solver['solver']}` " + (", ".join(missed) if missed else "none"))
    return "; ".join(parts)


@generator("tao-profile-size", TAO_STUDIES)
def _tao_profile_size(src):
    pr = need(src.json(TAO_STUDIES), "profile", where=TAO_STUDIES)
    rows = [p["rows"] for p in pr["problems"]]
    return (f"{len(rows)} problems, {min(rows)} to {max(rows)} rows; "
            f"{dur(pr['wall_time_s'])} in all")
