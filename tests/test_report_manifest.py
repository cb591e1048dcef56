#!/usr/bin/python3
"""CTest: validation/pendulum_wave_report.py lists the files it writes in the run folder's
cbps-manifest.json, keeps what was there, writes no manifest where there was none, and touches
nothing when the manifest is malformed.

    /usr/bin/python3 tests/test_report_manifest.py SOURCE_DIR

A tiny fake run: two exact simple pendulums (attach=center) of a 3 s cycle, x(t) = A sin(θ(t))
with θ(t) = θ0 cos(2π t / T_k), sampled every 1/100 s. Exit 0 when every check passes.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

REPORT_FILES = ["report.md", "report.json", "figure10.png", "figure10.svg"]


def fake_run(folder, manifest):
    os.makedirs(folder)
    n, n0, cycle, theta0_deg, dt = 2, 3, 3.0, 10.0, 0.01
    summary = {"scene": "pendulum-wave", "dt": dt, "steps": 300, "bodies": n, "rows": n,
               "gravity": [0, -9.81, 0], "solver": {"method": "pgs"},
               "parameters": {"n": n, "n0": n0, "cycle": cycle, "theta0_deg": theta0_deg,
                              "attach": "center", "radius": 0.05, "spacing": 0.2},
               "wall_time_s": 0.01, "stage_times_s": {"solve": 0.004, "integrate": 0.001},
               "max_constraint_error": 1e-6, "max_residual": 0.0}
    with open(os.path.join(folder, "summary.json"), "w", encoding="utf-8") as f:
        json.dump(summary, f)
    theta0 = math.radians(theta0_deg)
    lines = ["t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz"]
    for i in range(int(round(cycle / dt)) + 1):
        t = i * dt
        for k in range(n):
            T = cycle / (n0 + k)
            L = 9.81 * (T / (2 * math.pi)) ** 2
            th = theta0 * math.cos(2 * math.pi * t / T)
            x, y = L * math.sin(th), -L * math.cos(th)
            lines.append(f"{t:.12g},{k},{x:.12g},{y:.12g},{0.2 * k:.12g},1,0,0,0,0,0,0,0,0,0")
    with open(os.path.join(folder, "trajectory.csv"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(folder, "steps.csv"), "w", encoding="utf-8") as f:
        f.write("t,rows,iterations,residual,max_constraint_error,energy,wall_time_s\n"
                "0.01,2,1,0,0,0,0.5\n0.02,2,1,0,0,0,0.25\n")
    if manifest is not None:
        with open(os.path.join(folder, "cbps-manifest.json"), "w", encoding="utf-8") as f:
            f.write(manifest if isinstance(manifest, str) else json.dumps(manifest))


def report(source, folder):
    return subprocess.run([sys.executable, os.path.join(source, "validation",
                                                        "pendulum_wave_report.py"), folder],
                          capture_output=True, text=True)


def main():
    source = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(
        os.path.dirname(os.path.abspath(__file__)))
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    with tempfile.TemporaryDirectory() as tmp:
        # 1. A manifest: the report's four files are added, the rest kept, the format kept.
        run = os.path.join(tmp, "with")
        before = {"format": "cbps-output/1", "command": "cbps run pendulum-wave --out with",
                  "files": ["summary.json", "trajectory.csv", "steps.csv"]}
        fake_run(run, before)
        r = report(source, run)
        check(r.returncode == 0, f"report with a manifest: exit {r.returncode}: {r.stderr}")
        with open(os.path.join(run, "cbps-manifest.json"), encoding="utf-8") as f:
            after = json.load(f)
        check(after["format"] == before["format"] and after["command"] == before["command"],
              f"manifest's format/command changed: {after}")
        check(after["files"] == before["files"] + REPORT_FILES,
              f"manifest files {after['files']}, expected {before['files'] + REPORT_FILES}")
        for name in after["files"]:
            check(os.path.isfile(os.path.join(run, name)), f"manifest lists {name}, not there")
        leftovers = [f for f in os.listdir(run) if f.endswith(".tmp")]
        check(not leftovers, f"temporary files left: {leftovers}")
        with open(os.path.join(run, "report.json"), encoding="utf-8") as f:
            rj = json.load(f)
        check(rj["format"] == "cbps-pendulum-report/1", "report.json format")
        check(rj["timing"]["steps_wall_time_s"] == 0.75, "report.json: steps.csv wall sum")
        check(rj["max_abs_period_error"] is not None and rj["max_abs_period_error"] < 1e-3,
              f"report.json max period error {rj['max_abs_period_error']}")

        # 2. Again: nothing listed twice.
        r = report(source, run)
        with open(os.path.join(run, "cbps-manifest.json"), encoding="utf-8") as f:
            again = json.load(f)
        check(r.returncode == 0 and again["files"] == after["files"],
              f"second report: {again['files']}")

        # 3. No manifest: none is written, the report is.
        run = os.path.join(tmp, "without")
        fake_run(run, None)
        r = report(source, run)
        check(r.returncode == 0, f"report without a manifest: exit {r.returncode}: {r.stderr}")
        check(not os.path.exists(os.path.join(run, "cbps-manifest.json")),
              "a manifest was written where there was none")
        check(os.path.isfile(os.path.join(run, "report.md")), "no report.md without manifest")

        # 4. A malformed manifest: exit 2, nothing written, the manifest untouched.
        run = os.path.join(tmp, "malformed")
        fake_run(run, '{"files": "summary.json"}')
        r = report(source, run)
        check(r.returncode == 2, f"malformed manifest: exit {r.returncode}, expected 2")
        check(not os.path.exists(os.path.join(run, "report.md")),
              "report.md written despite a malformed manifest")
        with open(os.path.join(run, "cbps-manifest.json"), encoding="utf-8") as f:
            check(f.read() == '{"files": "summary.json"}', "malformed manifest rewritten")

    for what in failures:
        print(f"test_report_manifest: FAILED: {what}", file=sys.stderr)
    if not failures:
        print("test_report_manifest: all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
