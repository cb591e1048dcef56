#!/usr/bin/python3
"""The paper's friction box against Coulomb's cone (issue 31, item 5): a 1 kg, 0.2 m cube on a
plane inclined by a, pushed down the slope along a direction phi from its friction axis t2 (world
x; t1 is world z for the plane's normal y, rows/friction.cpp), phi from 0 to 45 degrees, under
friction=paper (±mu m |g·n| per row, 5.4), friction=coulomb (±mu lambda_n per row) and
friction=cone (‖lambda_t‖ ≤ mu lambda_n, De Saxcé's law), mu = 0.5, every step by the exact path.

    cmake --build build/release --target box-vs-cone      # or, with the module built:
    PYTHONPATH=build/release/python /usr/bin/python3 validation/box_vs_cone.py OUT_DIR

Closed forms (N = m g cos a the normal force, F = m g sin a the push down the slope):
- sliding starts when the friction can no longer hold F: under the cone at tan a* = mu whatever
  phi; under a box, whose rows each hold mu N (the paper's and Coulomb's alike at rest: the
  paper's m |g·n| is N), when either component F cos phi, F sin phi exceeds mu N, at
  tan a* = mu / max(cos phi, sin phi): mu √2 along the diagonal.
- once sliding (tan a = 2 mu here), the cone's friction mu N opposes the velocity, so the box
  accelerates along phi at g (sin a − mu cos a); a box's rows each take mu N where their component
  slides, so the acceleration is g (sin a cos phi − mu cos a, sin a sin phi − mu cos a) (a
  component that cannot beat mu N stays 0): slower (up to √2 mu N of friction along the
  diagonal), and turned toward the nearer axis.

The stack (three flat boxes, 1 kg, 0.6 × 0.2 × 0.6 m, one on another: wide enough not to tip
before they slide, tan a < 1): sliding starts at the ground, under the cone at tan a* = mu and
under Coulomb's box at mu / max(cos phi, sin phi) as for one box (every interface carries the
same ratio of push to load, so none slides sooner); under the paper's box, whose bound is
mu |g·n| times the mass of the contact's movable bodies (rows/friction.cpp), the ground's rows
hold only the bottom box's weight while the push is the whole stack's: tan a* = mu / (3 max(cos
phi, sin phi)), a third of Coulomb's (the interfaces above, bounded by two boxes' mass, hold
longer). Sliding at tan a = 1.5 mu (below 1, where the stack would tip), the three boxes
move as one under every law (the forces that would make them so need at most each interface's
bound: the cone's and Coulomb's box's exactly theirs), under the cone and Coulomb's box at one
box's acceleration, under the paper's box with a third of the friction per axis:
g (sin a cos phi − mu cos a / 3, sin a sin phi − mu cos a / 3), a component that cannot beat it
staying 0.

Measured: the tilt a* by bisection on "the cube moves" (speed above 1e-9 m/s after 10 steps of
1/240 s from rest; 30 halvings from [0, 60°]); the acceleration v/t after 24 steps (0.1 s) at
tan a = 2 mu, its size and its direction's turn from phi; for the stack a* ("moves": any box)
and each box's acceleration after 24 steps at tan a = 1.5 mu, the bottom box's size and turn and
the largest difference between the boxes'. Writes OUT_DIR/box_vs_cone.json (format
cbps-box-cone/3) and OUT_DIR/box_vs_cone.png.
"""
import json
import math
import os
import sys

import numpy as np

import cbps

MU = 0.5
G = 9.81
DT = 1.0 / 240.0
LAWS = ["paper", "coulomb", "cone"]
PHIS = [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0]
CUBE = [0.1, 0.1, 0.1]  # half extents, m
STACK = 3  # flat boxes in the stack
FLAT = [0.3, 0.1, 0.3]
STACK_SLIDE = 1.5  # the stack's sliding tilt, tan a / mu: below 1 (tan a = 0.75), where it tips


def simulate(law, a, phi, steps, boxes=1, half=CUBE):
    """The velocities (m/s, one row per box, bottom first) after `steps` steps from rest of
    `boxes` boxes of half extents `half` stacked on the plane tilted by a (rad), pushed along
    phi (rad) from world x."""
    bodies = [{"name": "ground", "shape": {"type": "plane"}, "static": True}]
    for i in range(boxes):
        bodies.append({"name": f"box{i}", "shape": {"type": "box", "half_extents": half},
                       "mass": 1.0, "position": [0.0, half[1] * (2 * i + 1), 0.0]})
    scene = {"name": "box-vs-cone",
             "world": {"gravity": [G * math.sin(a) * math.cos(phi), -G * math.cos(a),
                                   G * math.sin(a) * math.sin(phi)],
                       "dt": "1/240", "mu": MU, "friction": law, "contact_margin": 0.001},
             "solver": {"method": "direct"},
             "bodies": bodies}
    sim = cbps.Simulation(cbps.parse_scene(json.dumps(scene)))
    for _ in range(steps):
        sim.step()
    by_name = {b["name"]: b["v"] for b in sim.bodies()}
    return np.array([by_name[f"box{i}"] for i in range(boxes)])


def critical_tilt(law, phi, boxes=1, half=CUBE):
    lo, hi = 0.0, math.radians(60.0)
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        moves = np.linalg.norm(simulate(law, mid, phi, 10, boxes, half), axis=1).max() > 1e-9
        lo, hi = (lo, mid) if moves else (mid, hi)
    return 0.5 * (lo + hi)


def stack_start(law, phi):
    """tan a* / mu of the stack: the cone's 1, Coulomb's box's 1 / max(cos, sin), the paper's a
    STACK-th of that (its ground rows hold one box's weight)."""
    if law == "cone":
        return 1.0
    box = 1.0 / max(math.cos(phi), math.sin(phi))
    return box / STACK if law == "paper" else box


def sliding(law, phi, tan_over_mu, share=1.0):
    """(acceleration m/s², turn from phi in degrees) at tan a = tan_over_mu mu: the cone's
    friction mu N against the velocity, a box's `share` of mu N per axis where that component
    slides (a share 1 / STACK: the paper's box under the stack)."""
    a = math.atan(tan_over_mu * MU)
    if law == "cone":
        return G * (math.sin(a) - MU * math.cos(a)), 0.0
    ax = max(0.0, G * (math.sin(a) * math.cos(phi) - share * MU * math.cos(a)))
    az = max(0.0, G * (math.sin(a) * math.sin(phi) - share * MU * math.cos(a)))
    return math.hypot(ax, az), math.degrees(math.atan2(az, ax) - phi)


def closed_form(law, phi):
    """(tan a* / mu, acceleration m/s², turn from phi in degrees) at tan a = 2 mu."""
    start = 1.0 if law == "cone" else 1.0 / max(math.cos(phi), math.sin(phi))
    return (start,) + sliding(law, phi, 2.0)


def stack_slide(law, phi):
    """(acceleration m/s², turn in degrees) of the stack at tan a = STACK_SLIDE mu."""
    return sliding(law, phi, STACK_SLIDE, 1.0 / STACK if law == "paper" else 1.0)


def measure():
    rows = []
    steps = 24
    for law in LAWS:
        for deg in PHIS:
            phi = math.radians(deg)
            print(f"box_vs_cone: {law}, phi {deg:g} degrees", file=sys.stderr, flush=True)
            start = math.tan(critical_tilt(law, phi)) / MU
            v = simulate(law, math.atan(2.0 * MU), phi, steps)[0]
            acc = v / (steps * DT)
            turn = math.degrees(math.atan2(acc[2], acc[0]) - phi)
            want = closed_form(law, phi)
            rows.append({"law": law, "phi_deg": deg,
                         "start_tan_over_mu": start, "start_tan_over_mu_closed": want[0],
                         "acceleration": float(np.hypot(acc[0], acc[2])),
                         "acceleration_closed": want[1],
                         "lift_velocity": float(v[1]),
                         "turn_deg": turn, "turn_deg_closed": want[2]})
    return rows


def measure_stack():
    rows = []
    for law in LAWS:
        for deg in PHIS:
            phi = math.radians(deg)
            print(f"box_vs_cone: stack, {law}, phi {deg:g} degrees", file=sys.stderr, flush=True)
            start = math.tan(critical_tilt(law, phi, STACK, FLAT)) / MU
            steps = 24
            v = simulate(law, math.atan(STACK_SLIDE * MU), phi, steps, STACK, FLAT)
            acc = v / (steps * DT)  # one row per box, bottom first
            want = stack_slide(law, phi)
            rows.append({"law": law, "phi_deg": deg, "start_tan_over_mu": start,
                         "start_tan_over_mu_closed": stack_start(law, phi),
                         "acceleration": float(np.hypot(acc[0, 0], acc[0, 2])),
                         "acceleration_closed": want[0],
                         "turn_deg": math.degrees(math.atan2(acc[0, 2], acc[0, 0]) - phi),
                         "turn_deg_closed": want[1],
                         "boxes_apart": float(np.abs(acc - acc[0]).max())})
    return rows


def plot(rows, stack, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 5, figsize=(20, 3.6))
    style = {"paper": ("tab:blue", "o"), "coulomb": ("tab:orange", "s"), "cone": ("tab:green", "^")}
    phis = np.linspace(0.0, 45.0, 91)
    for law in LAWS:
        color, marker = style[law]
        mine = [r for r in rows if r["law"] == law]
        x = [r["phi_deg"] for r in mine]
        curves = [closed_form(law, math.radians(p)) for p in phis]
        for ax, key, k in ((axes[0], "start_tan_over_mu", 0), (axes[1], "acceleration", 1),
                           (axes[2], "turn_deg", 2)):
            ax.plot(phis, [c[k] for c in curves], color=color, lw=1)
            ax.plot(x, [r[key] for r in mine], marker, color=color, mfc="none", label=law)
        axes[3].plot(phis, [stack_start(law, math.radians(p)) for p in phis], color=color, lw=1)
        axes[3].plot([r["phi_deg"] for r in stack if r["law"] == law],
                     [r["start_tan_over_mu"] for r in stack if r["law"] == law], marker,
                     color=color, mfc="none", label=law)
        axes[4].plot(phis, [stack_slide(law, math.radians(p))[0] for p in phis], color=color, lw=1)
        axes[4].plot([r["phi_deg"] for r in stack if r["law"] == law],
                     [r["acceleration"] for r in stack if r["law"] == law], marker,
                     color=color, mfc="none", label=law)
    axes[0].set_ylabel("tan a* / mu (sliding starts)")
    axes[1].set_ylabel("acceleration at tan a = 2 mu, m/s²")
    axes[2].set_ylabel("turn of the sliding direction, degrees")
    axes[3].set_ylabel(f"tan a* / mu, stack of {STACK} flat boxes")
    axes[4].set_ylabel(f"stack's acceleration at tan a = {STACK_SLIDE:g} mu, m/s²")
    for ax in axes:
        ax.set_xlabel("push direction phi from the friction axis, degrees")
        ax.grid(alpha=0.3)
    axes[0].legend(title="lines: closed form")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    rows = measure()
    stack = measure_stack()
    result = {"format": "cbps-box-cone/3", "mu": MU, "dt": DT, "rows": rows,
              "stack": stack, "stack_boxes": {"count": STACK, "half_extents": FLAT},
              "stack_slide_tan_over_mu": STACK_SLIDE,
              "command": "validation/box_vs_cone.py " + out}
    tmp = os.path.join(out, "box_vs_cone.json.tmp")
    with open(tmp, "w") as f:
        json.dump(result, f, indent=1)
    os.replace(tmp, os.path.join(out, "box_vs_cone.json"))
    plot(rows, stack, os.path.join(out, "box_vs_cone.png"))
    print(f"box_vs_cone: wrote {out}/box_vs_cone.json and box_vs_cone.png", file=sys.stderr)


if __name__ == "__main__":
    main()
