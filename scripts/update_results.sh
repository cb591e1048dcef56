#!/usr/bin/env bash
# Copies measured results from a build folder (and from out/pendulum-wave, the main job's
# folder) into the committed places, then regenerates the documents' tables from them:
#
#   scripts/update_results.sh [BUILD_DIR]        # default build/release
#
# Build targets never write into the source tree; this is the one explicit step that does. It
# copies only the results that exist (run the targets you want first; validation/README.md,
# "Updating the committed results", lists them) and only small files: summaries, never the
# trajectories or convergence.csv. Review `git diff` before committing: wall times change from
# run to run.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
[[ -d "$build" ]] || { echo "update_results.sh: $build: no such build folder" >&2; exit 2; }
build="$(cd "$build" && pwd)"  # absolute: copy() joins relative sources to it
python="/usr/bin/python3"
[[ -x "$python" ]] || python="python3"
copied=0

# copy FROM TO: FROM relative to the build folder (or absolute), TO relative to the repository.
copy() {
  local from="$1" to="$root/$2"
  [[ "$from" = /* ]] || from="$build/$from"
  [[ -f "$from" ]] || return 0
  mkdir -p "$(dirname "$to")"
  if ! cmp -s "$from" "$to"; then
    cp "$from" "$to.tmp" && mv "$to.tmp" "$to"
    echo "update_results.sh: $2 <- $from"
    copied=$((copied + 1))
  fi
}

v=validation
# The main job (cmake --workflow --preset main): out/pendulum-wave.
copy "$root/out/pendulum-wave/summary.json" $v/results/pendulum-wave/summary.json
copy "$root/out/pendulum-wave/report.json" $v/results/pendulum-wave/report.json
copy "$root/out/pendulum-wave/figure10.png" docs/figure10.png
# --target validation-pendulum-runs
for variant in dt960 theta2 center; do
  copy $v/pendulum-wave-$variant/summary.json $v/results/pendulum-wave-$variant/summary.json
  copy $v/pendulum-wave-$variant/report.json $v/results/pendulum-wave-$variant/report.json
done
# --target validation
copy $v/validation.json $v/results/pendulum/validation.json
copy $v/period_error.png docs/period_error.png
# --target validation-beta-study
for b in 0.1 0.2 0.4 0.8; do
  for theta in 15 2; do
    copy $v/beta-study/beta-$b-theta-$theta/period_errors.csv \
      $v/results/beta-study/beta-$b-theta-$theta.csv
  done
done
copy $v/beta-study/beta-0/validation.json $v/results/beta-study/beta-0.json
# --target validation-contacts
copy $v/contacts.json $v/results/contacts.json
copy $v/push-factor.png docs/push-factor.png
# --target validation-stack
copy $v/stack-ingredients.json $v/results/stack-ingredients.json
# --target convergence, convergence-pyramid
for study in chain stack pyramid; do
  copy $v/convergence/$study/summary.json $v/results/convergence/$study/summary.json
done
copy $v/convergence/chain/convergence.png docs/convergence-chain.png
# --target exact-path-limits
for run in stack-check pyramid-direct pyramid-check; do
  copy $v/limits/$run/summary.json $v/results/limits/$run/summary.json
done
# --target box-vs-cone
copy $v/box-cone/box_vs_cone.json $v/results/box-cone/box_vs_cone.json
copy $v/box-cone/box_vs_cone.png docs/box-vs-cone.png
# --target cones-pyramid
copy $v/cones-pyramid/summary.json $v/results/cones-pyramid/summary.json
# --target peers
copy $v/peers/peers.json $v/results/peers/peers.json
# --target stress-catalogue
copy $v/stress/summary.json $v/results/stress/summary.json
copy $v/stress/stress.md $v/results/stress/stress.md
# --target stress-integrators
for integrator in gyroscopic midpoint; do
  copy $v/stress-$integrator/summary.json $v/results/stress-$integrator/summary.json
done
# --target profile: the profiles without the per-problem measurements and ratios (those stay in
# the build folder's profile.json and profile.csv), and the figure
if [[ -f "$build/validation/profile/profile.json" ]]; then
  mkdir -p "$root/$v/results/profile"
  "$python" - "$build/validation/profile/profile.json" "$root/$v/results/profile/summary.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1], encoding="utf-8"))
out = {k: j[k] for k in ("format", "budget_iterations", "time_limit_s", "tolerances", "solvers",
                         "wall_time_s", "quick")}
out["problems"] = [{k: p.get(k) for k in ("name", "kind", "rows", "nonzeros", "rank", "condition",
                                          "definite", "source")} for p in j["problems"]]
for p in out["problems"]:  # a singular A's condition: null, as scripts/check_results_drift.py reads it
    if p["condition"] == "inf":
        p["condition"] = None
out["profiles"] = [{k: p[k] for k in ("measure", "tolerance", "rho")} for p in j["profiles"]]
with open(sys.argv[2] + ".tmp", "w", encoding="utf-8") as f:
    json.dump(out, f, indent=1, sort_keys=True)
    f.write("\n")
PY
  mv "$root/$v/results/profile/summary.json.tmp" "$root/$v/results/profile/summary.json"
  echo "update_results.sh: $v/results/profile/summary.json" >&2
  copied=$((copied + 1))
fi
copy $v/profile/profile.png docs/profile.png
# --target bench-results, bench-direct, bench-contacts, bench-sweeps, bench-exact, bench-cones
for f in "$build"/bench/results/*.json; do
  [[ -f "$f" ]] && copy "$f" "bench/results/$(basename "$f")"
done

echo "update_results.sh: $copied file(s) updated; regenerating the documents' tables" >&2
"$python" "$root/scripts/doc_tables.py"
