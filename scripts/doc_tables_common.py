"""What every document's tables share (scripts/doc_tables.py and its scripts/doc_tables_*.py):
the registry of generators, reading the committed result files, the number formats, Markdown
tables, the result files more than one document reads, and writing a document back.

A document's module registers each generated part with

    @generator(NAME, SOURCE, ...)
    def _part(src):  # src: Sources; returns the Markdown text of the part
        ...

NAME is what the document's `<!-- table: NAME ... -->` or `<!-- value: NAME -->` marker names,
the SOURCEs the committed files (relative to the repository) it reads. Standard library only.
"""
import json
import math
import os

from cbps_files import read_number, write_text  # scripts/cbps_files.py


# ---------------------------------------------------------------------------------------------
# Errors and the registry of generators.


class SourceError(Exception):
    """A missing or malformed result file, or a document that names an unknown generator."""


GENERATORS = {}  # name → (sources, function(Sources) → text)


def generator(name, *sources):
    def register(fn):
        GENERATORS[name] = (list(sources), fn)
        return fn
    return register


# ---------------------------------------------------------------------------------------------
# Number formats shared by every table. sci, num, dur and length also take a value that is not
# finite as result files write it, the string "inf", "-inf" or "nan" (scripts/cbps_files.py), and
# show it as inf, -inf or nan.


def _float(x):
    return read_number(x) if isinstance(x, str) else x


def _exp(text):
    """'2.9e-05' → '2.9e-5', '1.2e+03' → '1.2e3'."""
    mantissa, _, exponent = text.partition("e")
    if not exponent:
        return text
    return f"{mantissa}e{int(exponent)}"


def sci(x, digits=2):
    """x with `digits` significant digits in scientific form: 2.9e-5; 0 is '0'."""
    x = _float(x)
    if x == 0:
        return "0"
    return _exp(f"{x:.{digits - 1}e}")


def cg(x, digits=2):
    """C's %.{digits}g, as `cbps stress` prints (so its tables match stress.md)."""
    if isinstance(x, str):
        return x  # "inf", "-inf", "nan" as number_json writes them
    return "%.*g" % (digits, x)


def num(x, digits=2):
    """`digits` significant digits, plain between 1e-3 and 1e5, else scientific."""
    x = _float(x)
    if x == 0:
        return "0"
    a = abs(x)
    if 1e-3 <= a < 1e5:
        decimals = max(0, digits - 1 - math.floor(math.log10(a)))
        text = f"{round(x, decimals):.{decimals}f}"
        return text
    return sci(x, digits)


def dur(seconds, digits=2):
    """A duration with two significant digits: 21 µs, 0.15 ms, 16 ms, 0.16 s, 3.5 s."""
    seconds = _float(seconds)
    if seconds < 1e-4:
        return f"{num(seconds * 1e6, digits)} µs"
    if seconds < 0.1:
        return f"{num(seconds * 1e3, digits)} ms"
    return f"{num(seconds, digits)} s"


def length(metres, digits=2):
    """A length in cm or mm when that reads better, else in m (scientific)."""
    metres = _float(metres)
    a = abs(metres)
    if 0.01 <= a < 1:
        return f"{num(metres * 100, digits)} cm"
    if 1e-4 <= a < 0.01:
        return f"{num(metres * 1000, digits)} mm"
    return f"{num(metres, digits)} m"


def minus(text):
    """A leading '-' as the minus sign '−' (the validation tables' typography)."""
    return "−" + text[1:] if text.startswith("-") else text


def thousands(n):
    return f"{int(n):,}"


def table(header, rows, align=None):
    """A Markdown table; align is a string of 'l'/'r' per column (default all left)."""
    align = align or "l" * len(header)
    lines = ["| " + " | ".join(header) + " |",
             "|" + "|".join("---:" if a == "r" else "---" for a in align) + "|"]
    for row in rows:
        lines.append("| " + " | ".join(str(c) for c in row) + " |")
    return "\n".join(lines)


def cell(text):
    """A Markdown table cell: | escaped."""
    return str(text).replace("|", "\\|")


# ---------------------------------------------------------------------------------------------
# Reading result files.


class Sources:
    """The result files of one repository, read once each; remembers what each generator read."""

    def __init__(self, root):
        self.root = root
        self.cache = {}

    def json(self, rel, fmt=None):
        """The committed JSON file rel; with fmt, SourceError unless its "format" is fmt."""
        if rel not in self.cache:
            path = os.path.join(self.root, rel)
            try:
                with open(path, encoding="utf-8") as f:
                    self.cache[rel] = json.load(f)
            except FileNotFoundError:
                raise SourceError(f"{rel}: missing (it is a committed result; see "
                                  "validation/README.md, 'Updating the committed results')") \
                    from None
            except (OSError, json.JSONDecodeError) as e:
                raise SourceError(f"{rel}: cannot read: {e}") from None
        j = self.cache[rel]
        if fmt is not None and (not isinstance(j, dict) or j.get("format") != fmt):
            found = j.get("format") if isinstance(j, dict) else None
            raise SourceError(f"{rel}: format {found!r}, not {fmt}")
        return j


def need(d, *keys, where=""):
    """d[k1][k2]… with a message naming the missing key."""
    for k in keys:
        try:
            d = d[k]
        except (KeyError, IndexError, TypeError):
            raise SourceError(f"{where}: no {'.'.join(str(x) for x in keys)}") from None
    return d


def csv_rows(src, rel):
    """A committed CSV as a list of dicts (cached like the JSON files)."""
    key = ("csv", rel)
    if key not in src.cache:
        import csv
        path = os.path.join(src.root, rel)
        try:
            with open(path, encoding="utf-8", newline="") as f:
                src.cache[key] = list(csv.DictReader(f))
        except FileNotFoundError:
            raise SourceError(f"{rel}: missing (it is a committed result)") from None
    return src.cache[key]


# ---------------------------------------------------------------------------------------------
# The result files more than one document reads, and the readings they share (a file one
# document reads is named in that document's module).

# The pendulum wave (README.md, docs/validation.md, validation/README.md).

PW = "validation/results/pendulum-wave/report.json"
PW_CENTER = "validation/results/pendulum-wave-center/report.json"


# validate_pendulum's periods (docs/validation.md, validation/README.md).

VAL = "validation/results/pendulum/validation.json"


def validation_rows(src):
    v = src.json(VAL)
    rows = need(v, "runs", where=VAL)
    return v, sorted(rows, key=lambda r: float(r["dt_inv"]))


# Google Benchmark JSON (docs/performance.md, bench/README.md).

SYSTEM = "bench/results/system-amd-epyc-2cpu.json"


def medians(src, rel):
    """run_name → the median aggregate of a Google Benchmark JSON file."""
    out = {}
    for run in need(src.json(rel), "benchmarks", where=rel):
        if run.get("run_type") == "aggregate" and run.get("aggregate_name") == "median":
            out[run["run_name"]] = run
    if not out:
        raise SourceError(f"{rel}: no median aggregates (run with --benchmark_repetitions)")
    return out


def cpu_seconds(run):
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[run["time_unit"]]
    return run["cpu_time"] * scale


# validate_contacts (docs/contacts.md, validation/README.md).

CONTACTS = "validation/results/contacts.json"


# The generated chain under MPI and its memory model (docs/distributed.md, README.md).

GENERATE = "validation/results/distributed/generate.json"


def generate_model(r):
    """The model of docs/distributed.md: peak memory per rank = base + per_row × rows / ranks,
    base the 10-row job at 1 rank, per_row the slope between the two largest sizes at 1 rank;
    its prediction for every measured run of at least 1e5 rows."""
    runs = need(r, "runs", where=GENERATE)
    base = next(x for x in runs if x["ranks"] == 1 and x["rows"] <= 10)["rank_memory_mb"][0]
    single = sorted((x for x in runs if x["ranks"] == 1 and x["type"] == "bqpip"
                     and x["rows"] >= 100000), key=lambda x: x["rows"])
    lo, hi = single[-2], single[-1]
    per_row = (hi["rank_memory_mb"][0] - lo["rank_memory_mb"][0]) * 2**20 / \
        (hi["rows"] - lo["rows"])  # bytes a row
    checks = []
    for x in runs:
        if x["rows"] >= 100000 and x["type"] == "bqpip":
            predicted = base + per_row * x["rows"] / x["ranks"] / 2**20
            checks.append((x, predicted, max(x["rank_memory_mb"])))
    return base, per_row, checks, (lo["rows"], hi["rows"])


# ---------------------------------------------------------------------------------------------
# Writing a document back.


def write_document(path, text):
    """A regenerated document, whole or not at all: a temporary file in the same folder renamed
    over it (scripts/cbps_files.py)."""
    write_text(path, text)
