#!/usr/bin/env bash
# How many files of src/, include/ and python/ spell each method: its enumerator (Method::X) or
# its name in quotes ("pgs"), the tests aside. The measure of issue 52's "a method in one place"
# (its entry and its code): one line per method with two counts, `code` (comments left out: the
# places that run, choose or name the method) and `all` (comments and help texts that quote the
# name too), then each count's total and largest.
#
#   scripts/count_method_spellings.sh [SOURCE_DIR]     (default: this repository)
#
# The methods and their names are read from the enum of include/cbps/solvers/solver.hpp (each
# enumerator's comment starts with its name in quotes). A name can also mean something else in
# code (MuJoCo's own solver "pgs"; a JSON field "direct"): the counter does not tell them apart.
set -euo pipefail
cd "${1:-$(dirname "$0")/..}"
header=include/cbps/solvers/solver.hpp
sed -n '/^enum class Method {/,/^};/p' "$header" |
  sed -nE 's/^ +([A-Z][A-Za-z0-9]*),? +\/\/\/< ("[^"]+").*/\1 \2/p' |
  /usr/bin/python3 -c '
import pathlib, re, sys
def strip_comments(text):
    # Drops // comments and /* */ blocks outside string and character literals.
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if c in "\"\x27":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1]); i = j + 1
        elif text.startswith("//", i):
            j = text.find("\n", i); i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2); i = n if j < 0 else j + 2
        else:
            out.append(c); i += 1
    return "".join(out)
files = sorted(p for d in ("src", "include", "python") for p in pathlib.Path(d).rglob("*") if p.is_file())
texts = {p: p.read_text(errors="replace") for p in files}
code = {p: strip_comments(t) if p.suffix in (".cpp", ".hpp", ".h", ".cc") else t for p, t in texts.items()}
totals = {"code": 0, "all": 0}; largest = {"code": 0, "all": 0}
print("%-18s %-24s %4s %4s" % ("method", "name", "code", "all"))
for line in sys.stdin:
    enumerator, name = line.split()
    pattern = re.compile(r"Method::%s\b|%s" % (enumerator, re.escape(name)))
    counts = {"code": sum(1 for p in files if pattern.search(code[p])),
              "all": sum(1 for p in files if pattern.search(texts[p]))}
    for k in counts:
        totals[k] += counts[k]; largest[k] = max(largest[k], counts[k])
    print("%-18s %-24s %4d %4d" % (enumerator, name, counts["code"], counts["all"]))
print("code: total %d, largest %d; all: total %d, largest %d" %
      (totals["code"], largest["code"], totals["all"], largest["all"]))
'
