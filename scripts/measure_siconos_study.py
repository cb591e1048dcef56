#!/usr/bin/python3
"""The study of docs/siconos-study.md: `cbps profile` of cbps's direct and nsgs and Siconos' four
fc3d solvers on the 3-D frictional-contact problems of Siconos' own test suite
(validation/data/siconos-fc3d), with a time limit per problem and solver.

    /usr/bin/python3 scripts/measure_siconos_study.py --cbps build/release/cbps
    /usr/bin/python3 scripts/doc_tables.py     # then regenerate the page's tables

Writes into --out (default validation/results/siconos-fc3d): profile.json, profile.csv,
summary.txt and profile.png as `cbps profile --out` writes them (docs/outputs.md), and study.json
(format cbps-siconos-study/1: the command, cbps's commit, the date, the machine). The profile runs
in a temporary folder and its files replace the old ones only once it has finished. It takes about
an hour on 2 cores (the solvers that do not converge run to the limit). Needs a build with
Siconos (libsiconos-numerics-dev; scripts/setup.sh installs it). Exit status 0, or 2 with a
message (no such binary, the profile failed).
"""
import argparse
import datetime
import json
import os
import shutil
import subprocess
import sys
import tempfile

from cbps_files import write_json  # scripts/cbps_files.py

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = "validation/data/siconos-fc3d"
SOLVERS = ("direct,nsgs,siconos:fc3d-nsgs,siconos:fc3d-nsn-ac,siconos:fc3d-prox,"
           "siconos:fc3d-admm")
FILES = ("profile.json", "profile.csv", "summary.txt", "profile.png")


def machine():
    """The processor's model and the cores, from /proc/cpuinfo."""
    model, cores = "unknown processor", os.cpu_count()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{model}, {cores} cores"


def commit():
    try:
        return subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], check=True,
                              capture_output=True, text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cbps", default=os.path.join(ROOT, "build/release/cbps"),
                    help="the cbps binary (default: build/release/cbps)")
    ap.add_argument("--out", default=os.path.join(ROOT, "validation/results/siconos-fc3d"),
                    help="where the results go (default: validation/results/siconos-fc3d)")
    ap.add_argument("--time-limit", type=float, default=60.0,
                    help="seconds per problem and solver (default 60)")
    a = ap.parse_args()
    if not os.access(a.cbps, os.X_OK):
        sys.exit(f"measure_siconos_study.py: {a.cbps}: no cbps binary there (build it first)")
    command = ["cbps", "profile", DATA, "--solvers", SOLVERS, "--time-limit", f"{a.time_limit:g}"]
    with tempfile.TemporaryDirectory(prefix="cbps-siconos-study-") as tmp:
        out = os.path.join(tmp, "out")
        run = subprocess.run([a.cbps] + command[1:] + ["--out", out], cwd=ROOT)
        if run.returncode != 0:
            print(f"measure_siconos_study.py: cbps profile exited {run.returncode}",
                  file=sys.stderr)
            sys.exit(2)
        os.makedirs(a.out, exist_ok=True)
        for name in FILES:
            shutil.copyfile(os.path.join(out, name), os.path.join(a.out, name + ".tmp"))
            os.replace(os.path.join(a.out, name + ".tmp"), os.path.join(a.out, name))
    write_json(os.path.join(a.out, "study.json"), {
        "format": "cbps-siconos-study/1", "command": " ".join(command),
        "cbps_commit": commit(), "date": datetime.date.today().isoformat(),
        "machine": machine(), "files": list(FILES)})
    print(f"measure_siconos_study.py: wrote {', '.join(FILES)} and study.json in {a.out}",
          file=sys.stderr)


if __name__ == "__main__":
    main()
