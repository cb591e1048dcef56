#!/usr/bin/env bash
# Builds the libFuzzer targets (preset "fuzz", build/fuzz; see fuzz/README.md) and runs each of
# fuzz_scene_json, fuzz_matrix_market and fuzz_siconos for SECONDS (default 60) on a scratch
# copy of its seed corpus under build/fuzz/fuzz-run. Prints one line per target; exits non-zero
# if any fuzzer finds a crash, a leak, a timeout (> 10 s) or an out-of-memory (> 2048 MB). The
# input that failed is kept in build/fuzz/fuzz-run/artifacts/<target>/, the log beside it.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "usage: scripts/fuzz.sh [SECONDS]   (run time per target, default 60)" >&2
  exit 2
fi

cmake --workflow --preset fuzz

build=build/fuzz
run="$build/fuzz-run"
rm -rf "$run"
mkdir -p "$run"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"

failed=()
results=()
for name in scene_json matrix_market siconos; do
  exe="$build/fuzz/fuzz_$name"
  corpus="$run/corpus/$name"
  artifacts="$run/artifacts/$name"
  log="$run/$name.log"
  mkdir -p "$corpus" "$artifacts"
  cp -R "$build/fuzz/seeds/$name/." "$corpus/"
  options=(-max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1
           -artifact_prefix="$artifacts/")
  if [ -f "fuzz/$name.dict" ]; then options+=(-dict="fuzz/$name.dict"); fi
  echo "fuzz: fuzz_$name for ${seconds} s ($(ls "$corpus" | wc -l) seeds), log $log" >&2
  rc=0
  "$exe" "${options[@]}" "$corpus" >"$log" 2>&1 || rc=$?
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)"
  coverage="$(grep -Eo 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+/[0-9]+[a-zA-Z]*' "$log" | tail -n 1)"
  if [ "$rc" -eq 0 ]; then
    verdict=ok
  else
    verdict="FAILED (exit $rc)"
    failed+=("fuzz_$name")
  fi
  results+=("fuzz_$name: ${execs:-?} executions, ${coverage:-no coverage line}: $verdict")
  if [ "$rc" -ne 0 ]; then
    echo "---- fuzz_$name: end of $log ----" >&2
    tail -n 60 "$log" >&2
    echo "---- failing inputs in $artifacts:" >&2
    ls -l "$artifacts" >&2
  fi
done

printf '%s\n' "${results[@]}"
if [ "${#failed[@]}" -ne 0 ]; then
  echo "fuzz: findings in ${failed[*]}" >&2
  exit 1
fi
