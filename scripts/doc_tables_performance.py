"""The generated parts of docs/performance.md (scripts/doc_tables.py): the benchmarks of assembly
and sweeps (bench/results, Google Benchmark JSON). bench-sweeps is in bench/README.md too.
"""
from doc_tables_common import (  # scripts/doc_tables_common.py
    SYSTEM, cpu_seconds, dur, generator, medians, need, table, thousands)


# ---------------------------------------------------------------------------------------------
# Benchmarks (bench/results, Google Benchmark JSON).

SWEEPS = "bench/results/sweeps-amd-epyc-2cpu.json"


@generator("bench-system", SYSTEM)
def _bench_system(src):
    m = medians(src, SYSTEM)
    sizes = (100, 1000, 10000, 100000)
    rows = []
    for name, label in (("build_system", "assembly of `J`, `Minv`, `A`, `b` (one step's "
                                         "`Simulation::assemble()`)"),
                        ("pgs_sweep", "one PGS sweep (7.1.1)")):
        v = [need(m, f"{name}/n:{n}", "ns_per_nnz", where=SYSTEM) for n in sizes]
        rows.append([label] + [f"{x:.3g}" for x in v] + [f"{v[3] / v[1]:.2f}"])
    return table(["ns per nnz(A)", "n = 10²", "n = 10³", "n = 10⁴", "n = 10⁵", "10⁵/10³"], rows,
                 "lrrrrr")


def _sweep_rows(src):
    m = medians(src, SWEEPS)
    scenes = [("chain", f"n:{n}", f"chain 10{sup}") for n, sup in
              ((100, "²"), (1000, "³"), (10000, "⁴"), (100000, "⁵"))]
    scenes += [("pyramid", f"base:{b}", f"pyramid {b}") for b in (4, 10, 20, 40, 91)]
    return m, scenes


@generator("bench-sweeps", SWEEPS)
def _bench_sweeps(src):
    m, scenes = _sweep_rows(src)
    rows = []
    for kind, arg, label in scenes:
        a = need(m, f"assembly/{kind}/{arg}", where=SWEEPS)
        e = need(m, f"pgs_sweep/{kind}/{arg}", where=SWEEPS)
        f = need(m, f"matrix_free_sweep/{kind}/{arg}", where=SWEEPS)
        d = m.get(f"direct/{kind}/{arg}")
        rows.append((label, thousands(a["rows"]), thousands(a["nnz_A"]),
                     dur(cpu_seconds(a), 3), dur(cpu_seconds(e), 3),
                     f"{e['fraction_of_bound']:.2f}", dur(cpu_seconds(f), 3),
                     f"{f['fraction_of_bound']:.2f}", "—" if d is None else dur(cpu_seconds(d), 3)))
    return table(["scene", "rows", "nnz(A)", "assembly", "explicit sweep", "of bound",
                  "matrix-free sweep", "of bound", "direct"], rows, "lrrrrrrrr")


@generator("bench-sweeps-bandwidth", SWEEPS)
def _bench_sweeps_bandwidth(src):
    m = medians(src, SWEEPS)
    return f"{need(m, 'bandwidth/triad', 'bandwidth_GBps', where=SWEEPS):.1f} GB/s"


@generator("bench-sweeps-pyramid91", SWEEPS)
def _bench_sweeps_pyramid91(src):
    m = medians(src, SWEEPS)
    e = need(m, "pgs_sweep/pyramid/base:91", where=SWEEPS)
    f = need(m, "matrix_free_sweep/pyramid/base:91", where=SWEEPS)
    ec = need(m, "pgs_sweep/chain/n:100000", where=SWEEPS)
    fc = need(m, "matrix_free_sweep/chain/n:100000", where=SWEEPS)
    te, tf = cpu_seconds(e), cpu_seconds(f)
    return (f"an explicit-`A` sweep of the base-91 pyramid ({thousands(e['rows'])} rows, "
            f"{e['bytes_per_sweep'] / 1e6:.0f} MB per sweep) takes {dur(te, 3)}, "
            f"{e['fraction_of_bound']:.2f} of the bound bytes / bandwidth; the matrix-free sweep "
            f"{dur(tf, 3)} ({tf / te:.2f}×); on the 10⁵-link chain {dur(cpu_seconds(ec), 3)} and "
            f"{dur(cpu_seconds(fc), 3)}")
