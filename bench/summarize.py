#!/usr/bin/env python3
"""Prints the ns-per-nonzero table of a bench_system JSON result as Markdown.

For each benchmark: the median over repetitions of ns_per_nnz (CPU time per iteration / nnz(A))
at each chain length n, and the ratio ns_per_nnz(n = 10^5) / ns_per_nnz(n = 10^3), which linear
scaling in nnz(A) keeps at or below 1.5.

Usage: summarize.py RESULT.json
"""
import json
import sys

LIMIT = 1.5  # allowed growth of the cost per nonzero from 10^3 to 10^5 links


def main(path):
    with open(path, encoding="utf-8") as f:
        result = json.load(f)
    # run_name "build_system/n:1000" → {1000: median ns_per_nnz}; a run without repetitions
    # has no aggregates, so fall back to the single iteration run.
    table, single = {}, {}
    for run in result["benchmarks"]:
        name, _, arg = run["run_name"].rpartition("/n:")
        if "ns_per_nnz" not in run:
            continue
        if run.get("run_type") == "aggregate":
            if run.get("aggregate_name") == "median":
                table.setdefault(name, {})[int(arg)] = run["ns_per_nnz"]
        else:
            single.setdefault(name, {})[int(arg)] = run["ns_per_nnz"]
    for name, by_n in single.items():
        table.setdefault(name, by_n)

    ctx = result["context"]
    print(f"{ctx['date']}, {ctx['host_name']}, {ctx['num_cpus']} CPUs at "
          f"{ctx['mhz_per_cpu']} MHz, load {ctx.get('load_avg', '?')}, "
          f"library build {ctx.get('library_build_type', '?')}")
    print()
    sizes = sorted({n for by_n in table.values() for n in by_n})
    print("| ns per nnz(A) | " + " | ".join(f"n = {n}" for n in sizes) + " | 10⁵/10³ |")
    print("|---" * (len(sizes) + 2) + "|")
    for name, by_n in table.items():
        cells = [f"{by_n[n]:.2f}" if n in by_n else "—" for n in sizes]
        if 1000 in by_n and 100000 in by_n:
            ratio = by_n[100000] / by_n[1000]
            verdict = "ok" if ratio <= LIMIT else f"> {LIMIT}"
            cells.append(f"{ratio:.2f} ({verdict})")
        else:
            cells.append("—")
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
