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

The pyramid: the built-in scene's 2-D pyramid of base 3 (rows of 3, 2 and 1 boxes, each on two
below, 1 m boxes 0.1 m apart in a row), its boxes 3 m deep so that it slides before it tips
sideways. The same argument: under the cone and Coulomb's box it starts and slides as one box;
under the paper's box the ground's rows hold the bottom row's 3 boxes of its 6 (each interface
above, bounded by two boxes' mass per contact, holds more), so tan a* = mu / (2 max(cos phi,
sin phi)) and the friction per axis while sliding is half of mu N.

Measured: the tilt a* by bisection on "the cube moves" (speed above 1e-9 m/s after 10 steps of
1/240 s from rest; 30 halvings from [0, 60°]); the acceleration v/t after 24 steps (0.1 s) at
tan a = 2 mu, its size and its direction's turn from phi; for the stack and the pyramid a*
("moves": any box) and each box's acceleration after 24 steps at tan a = 1.5 mu, the bottom
box's size and turn and the largest difference between the boxes'. Writes
OUT_DIR/box_vs_cone.json (format cbps-box-cone/3) and OUT_DIR/box_vs_cone.png.
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
PYRAMID = 3  # boxes in the pyramid's bottom row
DEEP = [0.5, 0.5, 1.5]  # the pyramid's boxes: the built-in scene's 1 m, 3 m deep (no tipping)
PYRAMID_GAP = 0.1  # m between neighbours in a row, the built-in scene's
PILE_SLIDE = 1.5  # the piles' sliding tilt, tan a / mu: below 1 (tan a = 0.75), where they tip


def cube():
    """One cube on the plane: [(half extents, position)]."""
    return [(CUBE, [0.0, CUBE[1], 0.0])]


def stack():
    """STACK flat boxes one on another, bottom first."""
    return [(FLAT, [0.0, FLAT[1] * (2 * i + 1), 0.0]) for i in range(STACK)]


def pyramid():
    """The built-in 2-D pyramid of base PYRAMID (row k: PYRAMID − k boxes, each on two below),
    bottom row first, its boxes DEEP."""
    pitch = 2 * DEEP[0] + PYRAMID_GAP
    return [(DEEP, [(i + 0.5 * row) * pitch, DEEP[1] * (2 * row + 1), 0.0])
            for row in range(PYRAMID) for i in range(PYRAMID - row)]


# Each pile's share of its weight that the paper's box lets the ground hold per axis: the ground
# rows' bound is mu |g·n| times the bottom box's mass, the push the whole pile's.
PILES = {"stack": (stack, 1.0 / STACK),
         "pyramid": (pyramid, PYRAMID / (PYRAMID * (PYRAMID + 1) / 2))}


def simulate(law, a, phi, steps, pile=cube):
    """The velocities (m/s, one row per box, in pile()'s order) after `steps` steps from rest of
    the pile on the plane tilted by a (rad), pushed along phi (rad) from world x."""
    bodies = [{"name": "ground", "shape": {"type": "plane"}, "static": True}]
    for i, (half, position) in enumerate(pile()):
        bodies.append({"name": f"box{i}", "shape": {"type": "box", "half_extents": half},
                       "mass": 1.0, "position": position})
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
    return np.array([by_name[f"box{i}"] for i in range(len(bodies) - 1)])


def critical_tilt(law, phi, pile=cube):
    lo, hi = 0.0, math.radians(60.0)
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        moves = np.linalg.norm(simulate(law, mid, phi, 10, pile), axis=1).max() > 1e-9
        lo, hi = (lo, mid) if moves else (mid, hi)
    return 0.5 * (lo + hi)


def sliding(law, phi, tan_over_mu, share=1.0):
    """(acceleration m/s², turn from phi in degrees) at tan a = tan_over_mu mu: the cone's
    friction mu N against the velocity, a box's `share` of mu N per axis where that component
    slides (a pile under the paper's box: PILES' share)."""
    a = math.atan(tan_over_mu * MU)
    if law == "cone":
        return G * (math.sin(a) - MU * math.cos(a)), 0.0
    ax = max(0.0, G * (math.sin(a) * math.cos(phi) - share * MU * math.cos(a)))
    az = max(0.0, G * (math.sin(a) * math.sin(phi) - share * MU * math.cos(a)))
    return math.hypot(ax, az), math.degrees(math.atan2(az, ax) - phi)


def closed_form(law, phi, share=1.0, tan_over_mu=2.0):
    """(tan a* / mu, acceleration m/s², turn from phi in degrees at tan a = tan_over_mu mu) of
    one box, or of a pile whose ground the paper's box lets hold `share` of its weight."""
    if law == "cone":
        start = 1.0
    else:
        start = (share if law == "paper" else 1.0) / max(math.cos(phi), math.sin(phi))
    return (start,) + sliding(law, phi, tan_over_mu, share if law == "paper" else 1.0)


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


def measure_pile(name):
    """A pile's tilt a* ("moves": any box) and, at tan a = PILE_SLIDE mu, its first (bottom) box's
    acceleration after 24 steps, its turn, and the largest difference between its boxes'."""
    pile, share = PILES[name]
    rows = []
    steps = 24
    for law in LAWS:
        for deg in PHIS:
            phi = math.radians(deg)
            print(f"box_vs_cone: {name}, {law}, phi {deg:g} degrees", file=sys.stderr, flush=True)
            start = math.tan(critical_tilt(law, phi, pile)) / MU
            v = simulate(law, math.atan(PILE_SLIDE * MU), phi, steps, pile)
            acc = v / (steps * DT)
            want = closed_form(law, phi, share, PILE_SLIDE)
            rows.append({"law": law, "phi_deg": deg, "start_tan_over_mu": start,
                         "start_tan_over_mu_closed": want[0],
                         "acceleration": float(np.hypot(acc[0, 0], acc[0, 2])),
                         "acceleration_closed": want[1],
                         "turn_deg": math.degrees(math.atan2(acc[0, 2], acc[0, 0]) - phi),
                         "turn_deg_closed": want[2],
                         "boxes_apart": float(np.abs(acc - acc[0]).max())})
    return rows


def plot(rows, piles, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(3, 3, figsize=(14, 10))
    style = {"paper": ("tab:blue", "o"), "coulomb": ("tab:orange", "s"), "cone": ("tab:green", "^")}
    phis = np.linspace(0.0, 45.0, 91)
    shares = {"cube": 1.0, "stack": PILES["stack"][1], "pyramid": PILES["pyramid"][1]}
    slide = {"cube": 2.0, "stack": PILE_SLIDE, "pyramid": PILE_SLIDE}
    measured = {"cube": rows, "stack": piles["stack"], "pyramid": piles["pyramid"]}
    titles = {"cube": "one cube", "stack": f"stack of {STACK} flat boxes",
              "pyramid": f"2-D pyramid of base {PYRAMID} ({PYRAMID * (PYRAMID + 1) // 2} boxes)"}
    for i, pile in enumerate(("cube", "stack", "pyramid")):
        for law in LAWS:
            color, marker = style[law]
            mine = [r for r in measured[pile] if r["law"] == law]
            curves = [closed_form(law, math.radians(p), shares[pile], slide[pile]) for p in phis]
            for k, key in enumerate(("start_tan_over_mu", "acceleration", "turn_deg")):
                axes[i, k].plot(phis, [c[k] for c in curves], color=color, lw=1)
                axes[i, k].plot([r["phi_deg"] for r in mine], [r[key] for r in mine], marker,
                                color=color, mfc="none", label=law)
        axes[i, 0].set_ylabel(f"{titles[pile]}:\ntan a* / mu (sliding starts)")
        axes[i, 1].set_ylabel(f"acceleration at tan a = {slide[pile]:g} mu, m/s²")
        axes[i, 2].set_ylabel("turn of the sliding direction, degrees")
    for ax in axes.flat:
        ax.set_xlabel("push direction phi from the friction axis, degrees")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(title="lines: closed form")
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    rows = measure()
    piles = {name: measure_pile(name) for name in PILES}
    result = {"format": "cbps-box-cone/3", "mu": MU, "dt": DT, "rows": rows,
              "stack": piles["stack"], "stack_boxes": {"count": STACK, "half_extents": FLAT},
              "pyramid": piles["pyramid"],
              "pyramid_boxes": {"base": PYRAMID, "count": len(pyramid()), "half_extents": DEEP,
                                "gap": PYRAMID_GAP},
              "piles_slide_tan_over_mu": PILE_SLIDE,
              "ground_share_paper": {name: share for name, (_, share) in PILES.items()},
              "command": "validation/box_vs_cone.py " + out}
    tmp = os.path.join(out, "box_vs_cone.json.tmp")
    with open(tmp, "w") as f:
        json.dump(result, f, indent=1)
    os.replace(tmp, os.path.join(out, "box_vs_cone.json"))
    plot(rows, piles, os.path.join(out, "box_vs_cone.png"))
    print(f"box_vs_cone: wrote {out}/box_vs_cone.json and box_vs_cone.png", file=sys.stderr)


if __name__ == "__main__":
    main()
