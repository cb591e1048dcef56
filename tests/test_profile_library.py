#!/usr/bin/python3
"""CTest: scripts/make_problem_library.py --quick writes the documented index of eight small
problems whose exact answers solve them, refuses to overwrite a folder that is not a library,
and `cbps profile --quick` runs on what it wrote.

    /usr/bin/python3 tests/test_profile_library.py SOURCE_DIR CBPS

Exit 0 when every check passes; each failed check is printed.
"""
import json
import os
import subprocess
import sys
import tempfile

FIELDS = ("name", "path", "kind", "source", "quick", "exact", "rows", "nonzeros", "rank",
          "definite", "condition", "range_condition", "scale", "exact_residual_relative",
          "guess_residual_relative")


def main():
    source, cbps = sys.argv[1], sys.argv[2]
    script = os.path.join(source, "scripts", "make_problem_library.py")
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)
            print(f"FAILED: {what}", file=sys.stderr)

    with tempfile.TemporaryDirectory(prefix="cbps_profile_library_") as tmp:
        lib = os.path.join(tmp, "lib")
        r = subprocess.run([sys.executable, script, cbps, lib, "--quick"], capture_output=True,
                           text=True)
        check(r.returncode == 0, f"make_problem_library --quick exited {r.returncode}: {r.stderr}")
        if r.returncode != 0:
            return 1
        index = json.load(open(os.path.join(lib, "library.json")))
        check(index["format"] == "cbps-problem-library/1", "format")
        problems = index["problems"]
        check(len(problems) == 8, f"{len(problems)} quick problems, not 8")
        kinds = {p["kind"] for p in problems}
        check(kinds == {"matrices", "siconos"}, f"kinds {kinds}")
        for p in problems:
            name = p.get("name")
            for field in FIELDS:
                check(field in p, f"{name}: no {field}")
            check(p["quick"], f"{name}: not quick")
            check(os.path.exists(os.path.join(lib, p["path"])), f"{name}: no {p['path']}")
            check(os.path.exists(os.path.join(lib, p["exact"])), f"{name}: no {p['exact']}")
            check(0 < p["rank"] <= p["rows"], f"{name}: rank {p['rank']} of {p['rows']} rows")
            check(p["definite"] == (p["rank"] == p["rows"]), f"{name}: definite")
            check((p["condition"] == "inf") == (not p["definite"]), f"{name}: condition")
            check(p["exact_residual_relative"] <= 1e-9, f"{name}: exact answer's residual")
            check(p["guess_residual_relative"] > 1e-3, f"{name}: solved by lambda = 0")
        # A two-box stack has four contacts per face: A is singular (rank below rows).
        stack = [p for p in problems if p["source"].get("scene") == "stack"]
        check(any(p["rank"] < p["rows"] for p in stack), "no stack with a singular A")

        # A folder that is not a library is refused and left as it was.
        other = os.path.join(tmp, "other")
        os.makedirs(other)
        open(os.path.join(other, "keep.txt"), "w").write("mine")
        r = subprocess.run([sys.executable, script, cbps, other, "--quick"], capture_output=True,
                           text=True)
        check(r.returncode != 0, "a folder that is not a library was accepted")
        check(os.listdir(other) == ["keep.txt"], "the refused folder was changed")

        out = os.path.join(tmp, "profile")
        r = subprocess.run([cbps, "profile", lib, "--quick", "--solvers", "pgs,apgd,direct",
                            "--time-limit", "0.5", "--quiet", "--no-plot", "--out", out],
                           capture_output=True, text=True)
        check(r.returncode == 0, f"cbps profile exited {r.returncode}: {r.stderr}")
        if r.returncode == 0:
            profile = json.load(open(os.path.join(out, "profile.json")))
            check(len(profile["problems"]) == 8, "profile.json: not 8 problems")
            check(len(profile["measurements"]) == 24, "profile.json: not 8 x 3 measurements")
            for m in profile["measurements"]:
                if m["solver"] == "direct":
                    check(m["status"] == "solved", f"direct on {m['problem']}: {m['status']}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
