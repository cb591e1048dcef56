"""The generated parts of bench/README.md (scripts/doc_tables.py): every benchmark of the system
at every size. Its other table, bench-sweeps, is docs/performance.md's
(scripts/doc_tables_performance.py).
"""
from doc_tables_common import (  # scripts/doc_tables_common.py
    SYSTEM, generator, medians, need, table)


# ---------------------------------------------------------------------------------------------
# Benchmarks (bench/results, Google Benchmark JSON).


@generator("bench-system-all", SYSTEM)
def _bench_system_all(src):
    m = medians(src, SYSTEM)
    sizes = (100, 1000, 10000, 100000)
    names = []
    for run_name in m:
        name = run_name.rpartition("/n:")[0]
        if name not in names:
            names.append(name)
    rows = []
    for name in names:
        v = [need(m, f"{name}/n:{n}", "ns_per_nnz", where=SYSTEM) for n in sizes]
        ratio = v[3] / v[1]
        bold = name in ("build_system", "pgs_sweep")
        verdict = f"{ratio:.2f} ({'ok' if ratio <= 1.5 else '> 1.5'})"
        rows.append([f"**{name}**" if bold else name] + [f"{x:.2f}" for x in v]
                    + [f"**{verdict}**" if bold else verdict])
    return table(["ns per nnz(A)", "n = 100", "n = 1000", "n = 10000", "n = 100000", "10⁵/10³"],
                 rows, "lrrrrr")
