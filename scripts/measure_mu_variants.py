#!/usr/bin/python3
"""Problems no simulation wrote: Siconos' Capsules files (validation/data/siconos-fc3d, W singular
and not symmetric) with every friction coefficient mu multiplied by a factor, solved by cbps's
`direct` to a unit-free 1e-10 as `cbps lcp` solves a Siconos file (docs/siconos-study.md,
"Problems no simulation wrote").

    PYTHONPATH=build/release/python /usr/bin/python3 scripts/measure_mu_variants.py
    /usr/bin/python3 scripts/doc_tables.py     # then regenerate the page's table

Each run: cbps.read_problem(FILE), the cones' mu times FACTOR, cbps.solve(..., 'direct',
tolerance=1e-10, unit_free=True); the verdict is cbps's (unit-free residual at most 1e-10, or
not), the factorizations and stage 5's proximal steps are read from its message. With
--with-prox, Siconos' PROX (`siconos:fc3d-prox`, 100,000 iterations, no time limit: up to about
four minutes a problem) on the variants with mu halved too, as a second method that shows each of
them has an answer. Writes --out (default
validation/results/siconos-fc3d/mu-variants.json, format cbps-mu-variants/1: the command, cbps's
commit, the date, the machine, and one entry per run) through a temporary file, replaced only
once every run has finished. Takes about a minute (with --with-prox about six). Needs the Python
module (target cbps_python) on PYTHONPATH; Siconos for --with-prox. Exit status 0, or 2 with a
message.
"""
import argparse
import datetime
import glob
import os
import re
import sys
import time

from cbps_files import write_json  # scripts/cbps_files.py
from measure_siconos_study import commit, machine  # scripts/measure_siconos_study.py

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = "validation/data/siconos-fc3d"
PATTERN = "Capsules-*"
FACTORS = (0.25, 0.5, 0.75, 1.5, 2.0, 3.0)
TOLERANCE = 1e-10
PROX = "siconos:fc3d-prox"
PROX_FACTOR = 0.5
PROX_ITERATIONS = 100000


def count(message, pattern):
    """The whole number the pattern's group matches in a message, or None."""
    m = re.search(pattern, message)
    return int(m.group(1)) if m else None


def run(cbps, problem, factor, method, iterations=None):
    """One solve of the problem with mu times factor: a dict for the results file."""
    cones = dict(problem.cones, mu=problem.cones["mu"] * factor)
    options = dict(tolerance=TOLERANCE, cones=cones, unit_free=True, history=False)
    if iterations is not None:
        options["iterations"] = iterations
    start = time.perf_counter()
    _, summary = cbps.solve(problem.A, problem.b, problem.cmin, problem.cmax, method, **options)
    seconds = time.perf_counter() - start
    message = summary["message"]
    return {"method": method, "termination": summary["termination"],
            "unit_free": summary["unit_free"]["relative"], "time_s": seconds,
            "factorizations": count(message, r"(\d+) factorizations"),
            "stage5_steps": count(message, r"\((\d+) of them stage 5's"),
            "message": message}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "validation/results/siconos-fc3d",
                                                  "mu-variants.json"),
                    help="the results file (default: "
                         "validation/results/siconos-fc3d/mu-variants.json)")
    ap.add_argument("--with-prox", action="store_true",
                    help=f"also {PROX} on the variants with mu x {PROX_FACTOR:g}")
    a = ap.parse_args()
    try:
        import cbps  # the Python module: PYTHONPATH=build/release/python
    except ImportError as e:
        sys.exit(f"measure_mu_variants.py: cannot import cbps ({e}); "
                 "set PYTHONPATH=build/release/python after building target cbps_python")
    files = sorted(glob.glob(os.path.join(ROOT, DATA, PATTERN)))
    if not files:
        sys.exit(f"measure_mu_variants.py: no {PATTERN} in {DATA}")
    runs = []
    for path in files:
        problem = cbps.read_problem(path)
        name = os.path.basename(path)
        for factor in FACTORS:
            methods = [("direct", None)]
            if a.with_prox and factor == PROX_FACTOR:
                methods.append((PROX, PROX_ITERATIONS))
            for method, iterations in methods:
                entry = run(cbps, problem, factor, method, iterations)
                entry.update(problem=name, mu_factor=factor)
                runs.append(entry)
                print(f"{name} mu x {factor:g} {method}: {entry['termination']}, unit-free "
                      f"{entry['unit_free']:.2e}, {entry['time_s']:.2f} s", file=sys.stderr,
                      flush=True)
    command = "PYTHONPATH=build/release/python /usr/bin/python3 scripts/measure_mu_variants.py"
    if a.with_prox:
        command += " --with-prox"
    write_json(a.out, {"format": "cbps-mu-variants/1", "command": command,
                       "cbps_commit": commit(), "date": datetime.date.today().isoformat(),
                       "machine": machine(), "tolerance": TOLERANCE,
                       "factors": list(FACTORS), "runs": runs})
    print(f"measure_mu_variants.py: wrote {a.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
