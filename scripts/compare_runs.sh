#!/usr/bin/env bash
# Runs the same list of `cbps run` cases with a baseline binary and a new one, and checks that
# the outputs are byte-identical: for changes that must not change the physics (moving files,
# renaming, refactoring), whose runs with --no-timing must give the same files before and after.
#
#   scripts/compare_runs.sh [--base COMMIT] [--base-cbps PATH] [NEW_CBPS]
#
# NEW_CBPS: the binary under test (default build/release/cbps, relative to the repository, the
# folder above this script; build it first with `cmake --workflow --preset main` or
# `cmake --build --preset release`).
# The baseline: --base-cbps PATH if given; otherwise the commit --base (default
# 38a6ae0e511cb52961865c51671301530d2668fd, the last commit before the source tree was
# restructured), checked out with `git worktree add --detach` into build/compare-base/src-SHORT
# and built (Release, target cbps only, no tests, benchmarks or validation programs) in
# build/compare-base/build-SHORT. Both are kept, so a second run only checks that the build is up
# to date; the first build takes a few minutes (set CMAKE_BUILD_PARALLEL_LEVEL to limit the jobs,
# CXX to choose the compiler: use the one build/release was configured with, or the last bits of
# the results may differ). Remove them with
#
#   git worktree remove --force build/compare-base/src-SHORT && rm -rf build/compare-base
#
# The scene files the file cases run (scenes/*.json) are taken from commit --base with `git show`
# (also with --base-cbps), so both sides read the same bytes wherever the files now live.
#
# Each case is one `cbps run` argument list (the list is `cases` below: pendulum-wave, the chain
# with every solver, the contact scenes with pgs and direct, one run that diverges, the scene
# files; about 35 s for both sides on 2 cores), run on each side with
# `--no-timing --quiet --out build/compare-runs/{base,new}/CASE` (the case folder is removed
# first; stdout and stderr go to build/compare-runs/{base,new}/CASE.log and are not compared).
# A case is the same when both sides exit with the same code and summary.json, trajectory.csv,
# steps.csv and bodies.json are byte-identical (cmp); cbps-manifest.json is not compared (it
# holds the command line, with the folder's name). Output: the two binaries, then one line per
# case, `same` or `DIFFERS: FILE` with the first differing line of each side (or the two exit
# codes, or the file missing on one side), or `FAILED` when the baseline did not run the case
# (exit 2 or more, or no summary.json: the case list or the binary is wrong); then a count.
#
# Exit status: 0 all cases the same; 1 a case differs or failed; 2 a usage error, a binary that
# is missing or not executable, a commit that git does not know, or a failed baseline build.
set -euo pipefail

default_base=38a6ae0e511cb52961865c51671301530d2668fd
usage="usage: scripts/compare_runs.sh [--base COMMIT] [--base-cbps PATH] [NEW_CBPS]"
die() { echo "compare_runs.sh: $*" >&2; exit 2; }
# abs PATH: PATH made absolute against the folder the script was started from.
abs() { case "$1" in /*) printf '%s\n' "$1" ;; *) printf '%s\n' "$PWD/$1" ;; esac; }

root="$(cd "$(dirname "$0")/.." && pwd)"
base="$default_base"
base_cbps=""
new_cbps=""
while [ $# -gt 0 ]; do
  case "$1" in
    --base) [ $# -ge 2 ] || die "--base needs a COMMIT; $usage"; base="$2"; shift 2 ;;
    --base=*) base="${1#--base=}"; shift ;;
    --base-cbps) [ $# -ge 2 ] || die "--base-cbps needs a PATH; $usage"; base_cbps="$(abs "$2")"; shift 2 ;;
    --base-cbps=*) base_cbps="$(abs "${1#--base-cbps=}")"; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) die "unknown option '$1'; $usage" ;;
    *) [ -z "$new_cbps" ] || die "one NEW_CBPS only; $usage"; new_cbps="$(abs "$1")"; shift ;;
  esac
done
[ -n "$base" ] || die "--base needs a COMMIT; $usage"
new_cbps="${new_cbps:-$root/build/release/cbps}"
if [ ! -f "$new_cbps" ] || [ ! -x "$new_cbps" ]; then
  die "$new_cbps: no such executable (NEW_CBPS)"
fi
if [ -n "$base_cbps" ]; then
  if [ ! -f "$base_cbps" ] || [ ! -x "$base_cbps" ]; then
    die "$base_cbps: no such executable (--base-cbps)"
  fi
fi
cd "$root"
commit="$(git rev-parse --verify --quiet "$base^{commit}")" || die "$base: not a commit of $root"
short="$(git rev-parse --short=7 "$commit")"

# The baseline binary: built from a worktree of the commit unless --base-cbps was given.
if [ -z "$base_cbps" ]; then
  src="$root/build/compare-base/src-$short"
  bld="$root/build/compare-base/build-$short"
  if [ -e "$src" ]; then
    head="$(git -C "$src" rev-parse --verify --quiet HEAD)" || head=""
    [ "$head" = "$commit" ] || die "$src exists but is not a worktree at $short; remove it with: git worktree remove --force $src"
  else
    echo "compare_runs.sh: git worktree add --detach $src $short" >&2
    mkdir -p "$root/build/compare-base"
    # --force: the path may still be registered from a worktree whose folder was deleted.
    git worktree add --force --detach "$src" "$commit" >&2 || die "git worktree add failed"
  fi
  if [ ! -f "$bld/CMakeCache.txt" ]; then
    echo "compare_runs.sh: configuring $bld" >&2
    cmake -S "$src" -B "$bld" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCBPS_BUILD_TESTS=OFF \
      -DCBPS_BUILD_BENCH=OFF -DCBPS_BUILD_VALIDATION=OFF >&2 || die "configuring $bld failed"
  fi
  echo "compare_runs.sh: building target cbps in $bld" >&2
  cmake --build "$bld" --target cbps >&2 || die "building $bld failed"
  base_cbps="$bld/cbps"
  [ -x "$base_cbps" ] || die "the build left no $base_cbps"
fi

runs="$root/build/compare-runs"
mkdir -p "$runs/base" "$runs/new"
# The scene files, from the baseline commit: @SCENES@ in a case stands for this folder.
scenes="$runs/scenes"
rm -rf "$scenes"
mkdir -p "$scenes"
scene_files=()
while IFS= read -r f; do
  case "$f" in
    *.json) git show "$commit:$f" >"$scenes/$(basename "$f")" || die "git show $short:$f failed"
            scene_files+=("$(basename "$f")") ;;
  esac
done < <(git ls-tree --name-only "$commit" scenes/)

# The cases: NAME then the arguments of `cbps run` (no spaces inside an argument).
cases=(
  "pendulum-wave           pendulum-wave --record-every 4"
  "chain-pgs               chain --solver pgs"
  "chain-psor-1.3          chain --solver psor:1.3"
  "chain-sgs               chain --solver sgs"
  "chain-jacobi-0.7        chain --solver jacobi:0.7"
  "chain-block-pgs         chain --solver block-pgs"
  "chain-matrix-free       chain --solver matrix-free"
  "chain-direct            chain --solver direct"
  "chain-pgs-reverse       chain --solver pgs:order=reverse"
  "chain-pgs-random-7      chain --solver pgs:order=random --seed 7"
  "chain-n20-ratio100-pgs  chain --param n=20 --param mass_ratio=100 --solver pgs"
  "chain-n20-ratio100-direct chain --param n=20 --param mass_ratio=100 --solver direct"
  "chain-push-improved     chain --push improved"
  "chain-cfm-1e-6          chain --cfm 1e-6"
  "chain-check             chain --check"
)
for solver in pgs direct; do
  cases+=(
    "stack-$solver                stack --duration 3 --solver $solver"
    "pyramid-6-$solver            pyramid --param base=6 --duration 2 --solver $solver"
    "newtons-cradle-$solver       newtons-cradle --solver $solver"
    "slide-$solver                slide --solver $solver"
    "bounce-$solver               bounce --solver $solver"
    "overlap-$solver              overlap --solver $solver"
    "v-corner-mu0.3-$solver       v-corner --param mu=0.3 --solver $solver"
    "stack-coulomb-$solver        stack --param friction=coulomb --duration 2 --solver $solver"
  )
done
cases+=(
  "stack-block-pgs         stack --duration 3 --solver block-pgs"
  "stack-matrix-free       stack --duration 3 --solver matrix-free"
  "overlap-push-improved   overlap --push improved"
  "bounce-sgs              bounce --solver sgs"
  "stack-jacobi-diverges   stack --duration 1 --solver jacobi:1.0"
)
for f in "${scene_files[@]}"; do cases+=("file-${f%.json}  @SCENES@/$f"); done

# show_line FILE N: line N of FILE, cut to 200 characters.
show_line() { sed -n "${2}{p;q}" "$1" | cut -c1-200; }

echo "base: $base_cbps"
echo "new:  $new_cbps"
total=0
same=0
bad=0
for c in "${cases[@]}"; do
  read -r -a words <<<"$c"
  name="${words[0]}"
  args=("${words[@]:1}")
  args=("${args[@]//@SCENES@/$scenes}")
  declare -A rc=()
  for side in base new; do
    bin="$base_cbps"
    [ "$side" = base ] || bin="$new_cbps"
    out="$runs/$side/$name"
    rm -rf "$out"
    rc[$side]=0
    "$bin" run "${args[@]}" --no-timing --quiet --out "$out" >"$out.log" 2>&1 || rc[$side]=$?
  done
  total=$((total + 1))
  b="$runs/base/$name"
  n="$runs/new/$name"
  report=()
  if [ "${rc[base]}" -ge 2 ] || [ ! -f "$b/summary.json" ]; then
    printf '%-28s FAILED: the baseline exits %s%s (see %s)\n' "$name" "${rc[base]}" \
      "$([ -f "$b/summary.json" ] || echo ' without summary.json')" "$b.log"
    bad=$((bad + 1))
    continue
  fi
  if [ "${rc[base]}" != "${rc[new]}" ]; then
    report+=("DIFFERS: exit code: base ${rc[base]}, new ${rc[new]} (see $n.log)")
  fi
  for f in summary.json trajectory.csv steps.csv bodies.json; do
    if [ ! -f "$b/$f" ] || [ ! -f "$n/$f" ]; then
      report+=("DIFFERS: $f: missing on the $([ -f "$b/$f" ] && echo new || echo base) side")
    elif ! where="$(cmp -- "$b/$f" "$n/$f" 2>&1)"; then
      line=""
      case "$where" in
        *"EOF on"*) ;;  # one file is a prefix of the other
        *) line="$(sed -n 's/.*, line \([0-9][0-9]*\)$/\1/p' <<<"$where")" ;;
      esac
      if [ -n "$line" ]; then
        report+=("DIFFERS: $f: line $line"
                 "    base: $(show_line "$b/$f" "$line")"
                 "    new:  $(show_line "$n/$f" "$line")")
      else
        report+=("DIFFERS: $f: ${where#cmp: }")
        while IFS= read -r l; do report+=("    $l"); done \
          < <(diff "$b/$f" "$n/$f" | head -n 4 | cut -c1-200)
      fi
    fi
  done
  if [ "${#report[@]}" -eq 0 ]; then
    if [ "${rc[base]}" -eq 0 ]; then
      printf '%-28s same\n' "$name"
    else
      printf '%-28s same (both exit %s)\n' "$name" "${rc[base]}"
    fi
    same=$((same + 1))
  else
    printf '%-28s %s\n' "$name" "${report[0]}"
    for l in "${report[@]:1}"; do printf '%-28s %s\n' "" "$l"; done
    bad=$((bad + 1))
  fi
done
echo "compare_runs.sh: $total cases: $same same, $bad differ or failed (${SECONDS} s; outputs in $runs)"
[ "$bad" -eq 0 ]
