#!/usr/bin/python3
"""How far MuJoCo's answers are from the exact answer of MuJoCo's own problem (docs/mujoco.md).

    /usr/bin/python3 validation/mujoco_study.py build/release/cbps validation/results/mujoco

For each model (validation/mujoco/*.xml and MuJoCo's own humanoid sample) and each of MuJoCo's
solvers (pgs, cg, newton) at the model's iterations and tolerance (MuJoCo's defaults: 100 and
1e-8), `cbps mujoco` runs the model --steps steps and exports every --every-th step's problem
with MuJoCo's forces and the ladder (each step's state solved again by each MuJoCo solver with
1, 2, 4, ... --ladder iterations, tolerance 0). On every exported step with rows, `cbps check`
judges MuJoCo's forces: the unit-free residual (cbps's verdict, solved at <= 1e-9) and the
distance from direct's exact answer, ‖lambda − lambda*‖∞ over the force scale and
‖w − w*‖ unit-free. The ladder gives the iterations each MuJoCo solver needs to reach 1e-6,
1e-8 and 1e-10 (the first rung there; none within --ladder: null). cbps's own methods are
profiled on the steps of the Newton run (`cbps profile --solvers pgs,apgd,direct`).

Writes OUT/study.json (the numbers docs/mujoco.md's tables are generated from, by
scripts/doc_tables.py) and docs/mujoco-study.png (the residual of MuJoCo's forces per step). Each run's folders go to
a temporary folder that is removed at the end. Standard library, and matplotlib for the figure.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = [
    # name, model file, keyframe, what it is
    ("box-stack", "validation/mujoco/box_stack.xml", "", "five boxes stacked on a plane"),
    ("capsule-pile", "validation/mujoco/capsule_pile.xml", "",
     "24 capsules dropped into a box"),
    ("hinge-chain", "validation/mujoco/hinge_chain_ratio_100.xml", "bent",
     "ten hinged links, mass ratio 100, joint limits"),
    ("humanoid", "/usr/share/mujoco/model/humanoid/humanoid.xml", "",
     "MuJoCo's humanoid sample falling (libmujoco-samples)"),
]
SOLVERS = ["pgs", "cg", "newton"]
TOLERANCES = [1e-6, 1e-8, 1e-10]
CBPS_SOLVERS = "pgs,apgd,direct"


def run(cmd):
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode not in (0, 1):
        sys.exit(f"mujoco_study.py: {' '.join(cmd)}: exit {done.returncode}: {done.stderr}")
    return done


def needed(ladder, solver, tolerance):
    """The fewest iterations of the ladder at which `solver` reaches `tolerance`, or None."""
    for rung in ladder:
        if rung["solver"] == solver and rung["unit_free"] <= tolerance:
            return rung["iterations"]
    return None


def study_run(cbps, model, keyframe, solver, args, folder):
    cmd = [cbps, "mujoco", os.path.join(ROOT, model) if not model.startswith("/") else model,
           "--mujoco-solver", solver, "--steps", str(args.steps), "--every", str(args.every),
           "--ladder", str(args.ladder), "--out", folder, "--quiet"]
    if keyframe:
        cmd += ["--keyframe", keyframe]
    run(cmd)
    steps = []
    for name in sorted(os.listdir(folder), key=lambda n: int(n.split("-")[1])
                       if n.startswith("step-") else -1):
        step_dir = os.path.join(folder, name)
        if not name.startswith("step-"):
            continue
        stats = json.load(open(os.path.join(step_dir, "mujoco.json")))
        if stats["rows"] == 0:
            shutil.rmtree(step_dir)  # nothing to solve: not a problem for the profile
            continue
        check = json.loads(run([cbps, "check", step_dir, "--lambda",
                                os.path.join(step_dir, "lambda_mujoco.mtx"), "--json",
                                "--quiet"]).stdout)
        exact = check["exact"]
        scale = check["unit_free"]["scale"]
        steps.append({
            "step": stats["step"],
            "rows": stats["rows"],
            "contacts": stats["contacts"],
            "iterations": stats["iterations"],
            "unit_free": check["unit_free"]["relative"],
            "solved": check["solved"],
            "exact_status": exact["status"] if exact["available"] else exact["why"],
            "lambda_distance_relative":
                exact["lambda_distance"] / scale if exact["available"] and scale > 0 else None,
            "w_distance_relative": exact["w_distance_relative"] if exact["available"] else None,
            "needed": {s: {f"{t:g}": needed(stats["ladder"], s, t) for t in TOLERANCES}
                       for s in SOLVERS},
        })
    return steps


def profile(cbps, folder, out):
    run([cbps, "profile", folder, "--solvers", CBPS_SOLVERS, "--out", out, "--no-plot",
         "--quiet", "--time-limit", "10"])
    p = json.load(open(os.path.join(out, "profile.json")))
    per = {}
    for m in p["measurements"]:
        per.setdefault(m["solver"], []).append(
            {"problem": m["problem"], "status": m["status"],
             "reached": m["reached"],  # per tolerance: iterations and time_s, or null
             "time_s": m["time_s"]})
    return per


def machine():
    """The processor's make and the cores, as "AMD EPYC, 2 cores"."""
    name = "unknown processor"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    words = line.split(":", 1)[1].split()
                    name = " ".join(words[:2])
                    break
    except OSError:
        pass
    return f"{name}, {os.cpu_count()} cores"


def figure(study, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(study["models"]), figsize=(4 * len(study["models"]), 3.4),
                             sharey=True)
    for ax, model in zip(axes, study["models"]):
        for solver in SOLVERS:
            steps = model["runs"][solver]
            ax.semilogy([s["step"] for s in steps],
                        [max(s["unit_free"], 1e-17) for s in steps], "o-", label=solver)
        ax.axhline(1e-9, color="grey", lw=0.8, ls="--")
        ax.set_title(model["name"])
        ax.set_xlabel("step")
    axes[0].set_ylabel("unit-free residual of MuJoCo's forces")
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cbps")
    parser.add_argument("out")
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--every", type=int, default=50)
    parser.add_argument("--ladder", type=int, default=1024)
    args = parser.parse_args()
    cbps = os.path.abspath(args.cbps)
    start = time.time()
    version = run([cbps, "--version"]).stdout.strip()
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    study = {"format": "cbps-mujoco-study/1", "machine": machine(),
             "command": "/usr/bin/python3 validation/mujoco_study.py build/release/cbps "
                        "validation/results/mujoco",
             "steps": args.steps, "every": args.every, "ladder": args.ladder,
             "tolerances": TOLERANCES, "cbps_solvers": CBPS_SOLVERS, "cbps": version,
             "commit": commit, "date": time.strftime("%Y-%m-%d"), "models": []}
    with tempfile.TemporaryDirectory() as tmp:
        for name, model, keyframe, what in MODELS:
            entry = {"name": name, "model": model, "keyframe": keyframe, "what": what, "runs": {}}
            for solver in SOLVERS:
                print(f"mujoco_study.py: {name}, MuJoCo {solver}", file=sys.stderr)
                folder = os.path.join(tmp, name, solver)
                entry["runs"][solver] = study_run(cbps, model, keyframe, solver, args, folder)
            entry["cbps"] = profile(cbps, os.path.join(tmp, name, "newton"),
                                    os.path.join(tmp, name, "profile"))
            study["models"].append(entry)
    study["wall_time_s"] = round(time.time() - start, 1)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "study.json.tmp"), "w") as f:
        json.dump(study, f, indent=1)
    os.replace(os.path.join(args.out, "study.json.tmp"), os.path.join(args.out, "study.json"))
    figure(study, os.path.join(ROOT, "docs", "mujoco-study.png"))
    print(f"mujoco_study.py: wrote {args.out} ({study['wall_time_s']} s)", file=sys.stderr)


if __name__ == "__main__":
    main()
