#!/usr/bin/env bash
# How many files of src/, include/ and python/ spell each method: its enumerator (Method::X) or
# its name in quotes ("pgs"), the tests aside. The measure of issue 52's "a method in one place"
# (its entry and its code): one line per method, then the total and the largest count.
#
#   scripts/count_method_spellings.sh [SOURCE_DIR]     (default: this repository)
#
# The methods and their names are read from the enum of include/cbps/solvers/solver.hpp (each
# enumerator's comment starts with its name in quotes).
set -euo pipefail
cd "${1:-$(dirname "$0")/..}"
header=include/cbps/solvers/solver.hpp
total=0
largest=0
while read -r enumerator name; do
  files=$(grep -rlE "Method::${enumerator}\\b|${name}" src include python | wc -l)
  total=$((total + files))
  ((files > largest)) && largest=$files
  printf '%-18s %-24s %d\n' "$enumerator" "$name" "$files"
done < <(sed -n '/^enum class Method {/,/^};/p' "$header" |
  sed -nE 's/^ +([A-Z][A-Za-z0-9]*),? +\/\/\/< ("[^"]+").*/\1 \2/p')
echo "total $total, largest $largest"
