#!/usr/bin/python3
"""CTest: scripts/doc_tables.py --check can fail. On a copy of the documents and the committed
results it passes; with one digit of a generated table changed it exits 1, shows a diff and
names the table and the command; a plain run repairs it; an unknown table name exits 2. And
scripts/measure_suite.py, whose measurement README.md's suite line is generated from, reads
CTest's summary: the counts and times of a CTest output written here, refusing one with a
failed test or without a summary.

    /usr/bin/python3 tests/test_doc_tables.py SOURCE_DIR
"""
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile


def copy_tree(source, tmp):
    patterns = ["README.md", "docs/*.md", "bench/README.md", "validation/README.md",
                "bench/results/*.json", "validation/results/**/*.json",
                "validation/results/**/*.md", "validation/results/**/*.csv"]
    for pattern in patterns:
        for path in glob.glob(os.path.join(source, pattern), recursive=True):
            rel = os.path.relpath(path, source)
            os.makedirs(os.path.join(tmp, os.path.dirname(rel)), exist_ok=True)
            shutil.copy(path, os.path.join(tmp, rel))


def run(source, tmp, *args):
    return subprocess.run([sys.executable, os.path.join(source, "scripts", "doc_tables.py"),
                           "--root", tmp, *args], capture_output=True, text=True)


# The tail of a CTest run as CTest prints it (the numbers are this test's own).
CTEST_TAIL = """100% tests passed, 0 tests failed out of 3

Label Time Summary:
petsc     =  12.50 sec*proc (2 tests)
python    =   1.25 sec*proc (1 test)

Total Test time (real) =  10.75 sec
"""


def check_measure_suite(source, check):
    script = os.path.join(source, "scripts", "measure_suite.py")
    with tempfile.TemporaryDirectory() as tmp:
        log, out = os.path.join(tmp, "ctest.log"), os.path.join(tmp, "suite.json")
        with open(log, "w", encoding="utf-8") as f:
            f.write(CTEST_TAIL)
        r = subprocess.run([sys.executable, script, "--from-log", log, out, "--note", "quiet"],
                           capture_output=True, text=True)
        check(r.returncode == 0, f"measure_suite.py on a CTest output: exit {r.returncode}", r)
        if r.returncode == 0:
            with open(out, encoding="utf-8") as f:
                got = json.load(f)
            check(got["tests"] == 3 and got["failed"] == 0 and got["wall_time_s"] == 10.75
                  and got["labels"] == {"petsc": {"tests": 2, "seconds": 12.5},
                                        "python": {"tests": 1, "seconds": 1.25}}
                  and got["note"] == "quiet" and got["format"] == "cbps-suite-time/1",
                  f"measure_suite.py read {got}")
        if os.path.exists(out):
            os.remove(out)
        for text, code in ((CTEST_TAIL.replace("100% tests passed, 0 tests failed out of 3",
                                               "67% tests passed, 1 tests failed out of 3"), 1),
                           ("no summary here\n", 2)):
            with open(log, "w", encoding="utf-8") as f:
                f.write(text)
            r = subprocess.run([sys.executable, script, "--from-log", log, out],
                               capture_output=True, text=True)
            check(r.returncode == code and not os.path.exists(out),
                  f"measure_suite.py on a bad output: exit {r.returncode}, expected {code}", r)


def main():
    source = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(
        os.path.dirname(os.path.abspath(__file__)))
    failures = []

    def check(ok, what, r=None):
        if not ok:
            failures.append(what + (f"\n--- stdout\n{r.stdout}\n--- stderr\n{r.stderr}" if r
                                    else ""))

    with tempfile.TemporaryDirectory() as tmp:
        copy_tree(source, tmp)
        r = run(source, tmp, "--check")
        check(r.returncode == 0, f"--check on the committed files: exit {r.returncode}", r)

        readme = os.path.join(tmp, "README.md")
        with open(readme, encoding="utf-8") as f:
            text = f.read()
        m = re.search(r"<!-- table: ([\w.-]+)[^\n]*-->\n(.*?)<!-- /table -->", text, re.S)
        check(m is not None, "README.md has no generated table")
        if m:
            name = m.group(1)
            body = m.group(2)
            digit = re.search(r"\d", body.split("\n", 2)[2])  # a digit below the header rule
            start = m.start(2) + len("\n".join(body.split("\n", 2)[:2])) + 1 + digit.start()
            changed = text[:start] + ("7" if text[start] != "7" else "3") + text[start + 1:]
            with open(readme, "w", encoding="utf-8") as f:
                f.write(changed)
            r = run(source, tmp, "--check")
            check(r.returncode == 1, f"--check with a changed number: exit {r.returncode}", r)
            check("--- a/README.md" in r.stdout and "+++ b/README.md" in r.stdout,
                  "--check shows no unified diff of README.md", r)
            check(f"README.md: {name} differs" in r.stderr, f"--check does not name {name}", r)
            check("scripts/doc_tables.py" in r.stderr, "--check does not name the command", r)
            with open(readme, encoding="utf-8") as f:
                check(f.read() == changed, "--check changed the file")
            r = run(source, tmp)
            check(r.returncode == 0, f"regenerating: exit {r.returncode}", r)
            with open(readme, encoding="utf-8") as f:
                check(f.read() == text, "regenerating did not restore README.md")
            r = run(source, tmp, "--check")
            check(r.returncode == 0, f"--check after regenerating: exit {r.returncode}", r)

        with open(readme, "a", encoding="utf-8") as f:
            f.write("\n<!-- table: no-such-table -->\n| x |\n<!-- /table -->\n")
        r = run(source, tmp, "--check")
        check(r.returncode == 2 and "no-such-table" in r.stderr,
              f"an unknown table name: exit {r.returncode}, expected 2", r)

    check_measure_suite(source, check)

    for what in failures:
        print(f"test_doc_tables: FAILED: {what}", file=sys.stderr)
    if not failures:
        print("test_doc_tables: all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
