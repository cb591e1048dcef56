#!/usr/bin/python3
"""How long the test suite takes: runs CTest on a build folder (or reads the output of a run
already made) and writes the count, the wall time and the time of each label as JSON, the
committed measurement README.md's test-suite line is generated from (scripts/doc_tables.py).

    /usr/bin/python3 scripts/measure_suite.py BUILD OUT.json [--jobs 2] [--note TEXT]
    /usr/bin/python3 scripts/measure_suite.py --from-log CTEST_OUTPUT OUT.json [--build-name NAME]

BUILD: a configured and built folder (build/release: `cmake --workflow --preset test`;
build/sanitize: `--preset test-sanitize`). OUT.json (format cbps-suite-time/1): `build` (the
folder's name), `tests`, `failed`, `wall_time_s` (CTest's "Total Test time (real)"), `labels`
(per label its tests and summed seconds, "sec*proc"), `cores` (os.cpu_count()), `jobs`, `date`
and `note` (what else ran on the machine). Exit 1 when a test failed (nothing written), 2 on
bad usage or an output without CTest's summary.
"""
import argparse
import datetime
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cbps_files import write_json  # noqa: E402  (scripts/cbps_files.py)

FORMAT = "cbps-suite-time/1"


def parse(text):
    """The summary of CTest's output: tests, failed, wall time, labels; ValueError without it."""
    total = re.search(r"(\d+)% tests passed, (\d+) tests? failed out of (\d+)", text)
    wall = re.search(r"Total Test time \(real\) =\s*([0-9.]+) sec", text)
    if not total or not wall:
        raise ValueError("no CTest summary ('tests passed ... out of N', 'Total Test time')")
    labels = {}
    for m in re.finditer(r"^(\w[\w-]*)\s+=\s+([0-9.]+) sec\*proc \((\d+) tests?\)", text,
                         re.MULTILINE):
        labels[m.group(1)] = {"tests": int(m.group(3)), "seconds": float(m.group(2))}
    return {"tests": int(total.group(3)), "failed": int(total.group(2)),
            "wall_time_s": float(wall.group(1)), "labels": labels}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("build", nargs="?", help="the build folder to run CTest in")
    parser.add_argument("out", help="the JSON file to write")
    parser.add_argument("--from-log", help="read this CTest output instead of running CTest")
    parser.add_argument("--jobs", type=int, default=2, help="ctest -j (default 2)")
    parser.add_argument("--note", default="", help="what else ran on the machine")
    parser.add_argument("--build-name", default="release",
                        help="with --from-log: the build it ran (default release)")
    args = parser.parse_args(argv)
    if bool(args.build) == bool(args.from_log):
        parser.error("give BUILD or --from-log, one of them")
    if args.from_log:
        with open(args.from_log, encoding="utf-8", errors="replace") as f:
            text = f.read()
        build = args.build_name
    else:
        run = subprocess.run(["ctest", "--test-dir", args.build, "-j", str(args.jobs)],
                             capture_output=True, text=True)
        text = run.stdout + run.stderr
        build = os.path.basename(os.path.normpath(args.build))
    try:
        result = parse(text)
    except ValueError as e:
        print(f"measure_suite.py: {args.from_log or args.build}: {e}", file=sys.stderr)
        return 2
    if result["failed"]:
        print(f"measure_suite.py: {result['failed']} of {result['tests']} tests failed; "
              "nothing written", file=sys.stderr)
        return 1
    result.update({"format": FORMAT, "build": build, "cores": os.cpu_count(),
                   "jobs": args.jobs, "date": datetime.date.today().isoformat(),
                   "note": args.note})
    write_json(args.out, result)
    print(f"{build}: {result['tests']} tests, {result['wall_time_s']:.0f} s; wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
