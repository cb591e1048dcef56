#!/usr/bin/python3
"""Measures the exact path on friction cones against nsgs and Siconos' fc3d solvers on the cone
pyramids of issue 31, and writes what docs/cones.md's bench tables show as JSON (format
cbps-cones/4).

    /usr/bin/python3 scripts/measure_cones.py CBPS OUT.json [--work DIR] [--quick]
                     [--siconos-timeout S]

The problems: `cbps matrices pyramid --param base=B --param friction=cone --param cone=ccp
--param mu=0.5 --step 50 --solver direct --out W/pyramidB --fclib W/pyramidB.hdf5` for B = 3, 5,
10 and 20 (36, 100, 400 and 1,600 contacts: the pyramid stepped 50 times under the relaxation by
the exact path, then its step's problem written as a folder and an FCLIB file). On each file and
for each law (`--cone ccp`, `--cone coulomb`):

- "direct": `cbps lcp F --cone LAW --solver direct --json` (its status, the unit-free residual
  of cbps's verdict (docs/cones.md, "The verdict"; the issue's targets are read in it), the
  residual in N, the old relative residual residual / scale with scale = max(1, ‖b‖∞,
  max |A_ij|), FCLIB's MERIT_1 and the wall time of the solve);
- "direct_body": the same on the folder, `cbps lcp W/pyramidB --cone LAW --solver direct
  --json`, which has J and Minv, so that the interior point's Newton systems are solved in body
  space (M + Jᵀ Ω J, docs/cones.md; the local file has only W and works in row space on W + B);
- "nsgs_1000": `cbps lcp F --cone LAW --solver nsgs --iterations 1000 --tolerance 0 --json`, the
  time of 1,000 sweeps (the target's yardstick) and the residual they reach.

Under Coulomb's law (FCLIB's, Siconos') also Siconos 4.4's fc3d solvers as cbps's own methods
(`cbps lcp F --solver siconos:fc3d-NAME --iterations 100000 --tolerance 1e-14 --json`, each with
a time limit, --siconos-timeout, default 300 s; a run past it is killed with its Siconos child
and recorded as "timeout"): NSGS and PROX, both asked for 1e-14 in Siconos' own error. Their answers are
judged here as cbps judges its own: the unit-free residual (each contact's natural map with its
own step, over the problem's force scale; computed here from its definition), the natural map
r − P_K(r − û) of Coulomb's law per contact (docs/cones.md), its largest norm (N), over the same
scale, and MERIT_1. The same numbers computed here for cbps's direct answer check this script
against cbps ("residual_here", "unit_free_here").

The states of issue 31's own measurements ("box_states"): `cbps matrices pyramid --param base=B
--param mu=0.5 --step 3 --out W/pyramidB-box --fclib W/pyramidB-box.hdf5 --cone coulomb` for B =
3, 5, 10 and 20: the pyramid stepped 3 times under the paper's box by its default method (pgs)
while it settles, its step's A and b posed on Coulomb's cone; there contacts slide, stick and
open at velocities near 1e-8 m/s. Measured the same way, Coulomb's law only; "direct_body" there
solves the same step written as an FCLIB global file (`... --fclib W/pyramidB-box-global.hdf5
--cone coulomb --global`: M, H, and so J and Minv).

--quick (a check of the script itself): base 3 only, Siconos limited to 20 s. The load average
after each command is recorded. Exit 1 without writing OUT when CBPS changes during the run.
"""
import argparse
import datetime
import json
import os
import platform
import shlex
import sys
import tempfile
import time

import numpy as np
import scipy.io

import measure_peers as peers  # run(), BINARY, git_commit(): the same job control
from cbps_problem import cone_natural_maps, cone_unit_free_residual, scale_of

FORMAT = "cbps-cones/4"
BASES = [3, 5, 10, 20]
# The piles settling under the paper's box: the same bases and base 7, 196 contacts (the averaged
# fixed point of issue 51 left it at a unit-free 8.1e-10 before its differentiated interior point).
BOX_BASES = [3, 5, 7, 10, 20]
LAWS = ["ccp", "coulomb"]
MU = "0.5"
BOX_STEP = 3
# Siconos' fc3d solvers, run as cbps's own methods (`--solver siconos:fc3d-NAME`, docs/peers.md):
# name -> the iterations they are given.
SICONOS = {"nsgs": 100000, "prox": 100000}
SICONOS_TOLERANCE = "1e-14"  # in Siconos' own error, relative to ‖q‖


def log(text):
    print(f"measure_cones: {text}", file=sys.stderr, flush=True)


def coulomb_measures(A, b, mu, r):
    """r judged under Coulomb's law: the unit-free residual of cbps's verdict (computed here from
    its definition, scripts/cbps_problem.py), the unit-step natural map's largest norm over the
    contacts (‖r − P_K(r − û)‖₂, N, with û = u + mu ‖u_t‖ e_n and u = A r − b), that over the old
    scale, and FCLIB's MERIT_1."""
    contacts = range(0, len(b), 3)
    norms = cone_natural_maps(r, A @ r - b, contacts, mu, "coulomb")
    worst = float(np.max(norms, initial=0.0))
    return {"unit_free": cone_unit_free_residual(A, b, r, contacts, mu, "coulomb"),
            "residual": worst, "residual_relative": worst / scale_of(A, b),
            "fclib_merit": float(np.linalg.norm(norms) / (1.0 + np.sqrt(np.linalg.norm(b))))}


def lcp(cbps, work, source, law, solver):
    args = ["lcp", source, "--cone", law, "--solver", solver, "--json"]
    if solver == "nsgs":
        args += ["--iterations", "1000", "--tolerance", "0"]
    log("cbps " + " ".join(args))
    code, out, err, elapsed = peers.run([cbps] + args, work)
    entry = {"command": "cbps " + " ".join(args), "exit": code, "job_s": elapsed,
             "load_average": os.getloadavg()[0]}
    if code not in (0, 1):
        entry.update(status="error" if code is not None else "timeout", message=err.strip())
        return entry, None
    j = json.loads(out)
    entry.update(status=j["status"], unit_free=(j.get("unit_free") or {}).get("relative"),
                 residual=j["residual"], scale=j["scale"],
                 residual_relative=peers.relative(j["residual"], j["scale"]),
                 fclib_merit=j["cone"]["fclib_merit"], wall_time_s=j["wall_time_s"],
                 iterations=j["iterations"], space=j["space"], message=j["message"])
    return entry, np.array(j["lambda"], dtype=float)


def siconos(cbps, work, hdf5, name, timeout, problem):
    """Siconos' fc3d solver NAME on the file through `cbps lcp --solver siconos:fc3d-NAME`, its
    answer judged here by cbps's residual (coulomb_measures), its own word and time from the
    JSON's `peer` object; a run past `timeout` is killed with its Siconos child."""
    iterations = SICONOS[name]
    args = ["lcp", hdf5, "--solver", "siconos:fc3d-" + name, "--iterations", str(iterations),
            "--tolerance", SICONOS_TOLERANCE, "--json"]
    log(f"cbps {' '.join(args)} (limit {timeout} s)")
    code, out, err, elapsed = peers.run([cbps] + args, work, timeout=timeout)
    entry = {"solver": "siconos:fc3d-" + name, "command": "cbps " + " ".join(args),
             "max_iterations": iterations, "exit": code, "job_s": elapsed,
             "load_average": os.getloadavg()[0]}
    if code is None:
        entry.update(status="timeout", message=f"no answer within {timeout} s (killed)")
        return entry
    if code not in (0, 1):
        entry.update(status="error", message=f"exit {code}: {err.strip()[-1000:]}")
        return entry
    j = json.loads(out)
    peer = j["peer"]
    word = peer["status"]
    entry.update(status="answered",
                 siconos_info=int(word.split()[1]) if word.startswith("info ") else None,
                 peer_status=word, iterations=peer["iterations"],
                 solve_time_s=peer["solve_time_s"], cbps_status=j["status"])
    entry.update(coulomb_measures(*problem, np.array(j["lambda"], dtype=float)))
    return entry


def measure(cbps, work, base, siconos_timeout, state):
    """One pyramid: "cone" (stepped under the relaxation, at rest) or "box" (settling under the
    paper's box, posed on the cone)."""
    name = f"pyramid{base}" + ("-box" if state == "box" else "")
    folder, hdf5 = os.path.join(work, name), os.path.join(work, name + ".hdf5")
    if state == "cone":
        args = ["matrices", "pyramid", "--param", f"base={base}", "--param", "friction=cone",
                "--param", "cone=ccp", "--param", f"mu={MU}", "--step", "50", "--solver",
                "direct", "--out", folder, "--fclib", hdf5, "--quiet"]
    else:
        args = ["matrices", "pyramid", "--param", f"base={base}", "--param", f"mu={MU}",
                "--step", str(BOX_STEP), "--out", folder, "--fclib", hdf5, "--cone", "coulomb",
                "--quiet"]
    body = folder  # where J and Minv are: the folder, or the box state's FCLIB global file
    commands = [args]
    if state == "box":
        body = os.path.join(work, name + "-global.hdf5")
        commands.append(args[:args.index("--out")] + ["--out", folder + "-global", "--fclib",
                                                      body, "--cone", "coulomb", "--global",
                                                      "--quiet"])
    for command in commands:
        log("cbps " + " ".join(command))
        code, _, err, _ = peers.run([cbps] + command, work)
        if code != 0:
            sys.exit(f"measure_cones: cbps {' '.join(command)}: exit {code}: {err.strip()}")
    A = scipy.io.mmread(os.path.join(folder, "A.mtx")).toarray()
    b = scipy.io.mmread(os.path.join(folder, "b.mtx")).ravel()
    with open(os.path.join(folder, "labels.json")) as f:  # a contact's rows: normal, t1, t2
        contacts = sum(1 for row in json.load(f)["rows"] if row.startswith("contact "))
    mu = np.full(contacts, float(MU))
    if contacts * 3 != len(b):
        sys.exit(f"measure_cones: {folder}: {len(b)} rows are not {contacts} contacts' rows")
    entry = {"name": name, "base": base, "contacts": len(mu), "rows": len(b), "state": state,
             "command": "; ".join("cbps " + " ".join(c).replace(work + os.sep, "")
                                  for c in commands), "laws": {}}
    for law in (LAWS if state == "cone" else ["coulomb"]):
        direct, lam = lcp(cbps, work, hdf5, law, "direct")
        if law == "coulomb" and lam is not None:
            here = coulomb_measures(A, b, mu, lam)
            direct["residual_here"], direct["unit_free_here"] = here["residual"], here["unit_free"]
        direct_body, _ = lcp(cbps, work, body, law, "direct")
        nsgs, _ = lcp(cbps, work, hdf5, law, "nsgs")
        entry["laws"][law] = {"direct": direct, "direct_body": direct_body, "nsgs_1000": nsgs}
    entry["siconos"] = [siconos(cbps, work, hdf5, s, siconos_timeout, (A, b, mu))
                        for s in SICONOS]
    return entry


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cbps")
    ap.add_argument("out")
    ap.add_argument("--work")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--siconos-timeout", type=float, default=300.0)
    args = ap.parse_args()
    start = time.monotonic()
    work = os.path.abspath(args.work or tempfile.mkdtemp(prefix="cbps_measure_cones_"))
    os.makedirs(work, exist_ok=True)
    cbps = os.path.abspath(args.cbps)
    peers.BINARY.update(path=cbps, mtime=os.stat(cbps).st_mtime)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    timeout = 20.0 if args.quick else args.siconos_timeout
    bases = BASES[:1] if args.quick else BASES
    results = {"format": FORMAT,
               "command": shlex.join(["scripts/measure_cones.py"] + sys.argv[1:]),
               "cbps_commit": peers.git_commit(root),
               "date": datetime.date.today().isoformat(), "machine": platform.node(),
               "nproc": os.cpu_count(), "quick": args.quick, "siconos_timeout_s": timeout,
               "problems": [measure(cbps, work, base, timeout, "cone") for base in bases],
               "box_states": [measure(cbps, work, base, timeout, "box")
                              for base in (BOX_BASES[:1] if args.quick else BOX_BASES)]}
    peers.write_results(args.out, results, start, log)


if __name__ == "__main__":
    main()
