#!/usr/bin/python3
"""The library's folders are layers: a file includes headers of its own folder and of the
layers below it, never of a layer above (README, "The code follows the step"); no script in
scripts/ imports a test; and no function in src/ or python/ (the module's bindings) is longer
than 100 lines, tables aside.

    /usr/bin/python3 tests/test_layers.py SOURCE_DIR

Reads every #include "..." of include/cbps/ and src/ (a cbps/<folder>/... include, or a
relative one such as "../solvers/x.hpp", by the folder it lands in) and every import of
scripts/*.py. Exit 0 when every arrow points down and no file reaches into another folder's
private headers (a relative include out of its folder), 1 listing each that does.
Function lengths are read with Universal Ctags (`ctags`, Debian's universal-ctags, which
scripts/setup.sh installs): from a definition's first line to its closing brace.
"""
import json
import os
import re
import subprocess
import sys

# The longest function src/ and python/ may hold, lines from its first line to its closing brace: a longer
# one does several things the reader should see named.
MAX_FUNCTION_LINES = 100
# Tables: one entry after another, nothing to name apart.
TABLES = {
    ("src/scene/builtin/registry.cpp", "builtin_scenes"),  # the built-in scenes and parameters
}

# Layer of each folder, lowest first; a folder may include its own layer and any lower one.
# io/ reads and writes the boxed problem (system/) beside the solvers; scene/ names the solver
# settings; step/ runs everything below; the studies, the distributed path and the command line
# sit on top.
LAYERS = {
    "base": 0, "body": 1, "collision": 2, "rows": 3, "system": 4, "solvers": 5, "io": 5,
    "scene": 6, "step": 7, "distributed": 8, "studies": 8, "cli": 9, "(top)": 10,
}


def folder_of(path, root):
    rel = os.path.relpath(path, root)
    return rel.split(os.sep)[0] if os.sep in rel else "(top)"


def include_arrows(source_dir):
    """(file, its folder, the included header, its folder) for every cbps include."""
    for root in ("include/cbps", "src"):
        top = os.path.join(source_dir, root)
        for here, _, names in os.walk(top):
            for name in sorted(names):
                if not name.endswith((".hpp", ".cpp")):
                    continue
                path = os.path.join(here, name)
                with open(path, encoding="utf-8") as f:
                    text = f.read()
                for m in re.finditer(r'^\s*#\s*include\s+"([^"]+)"', text, re.MULTILINE):
                    header = m.group(1)
                    if header.startswith("cbps/"):
                        parts = header.split("/")
                        target = parts[1] if len(parts) > 2 else "(top)"
                    else:
                        target = folder_of(os.path.normpath(os.path.join(here, header)), top)
                    yield os.path.relpath(path, source_dir), folder_of(path, top), header, target


def long_functions(source_dir):
    """(path, line, name, lines) of every function of src/ and python/ longer than
    MAX_FUNCTION_LINES."""
    try:
        out = subprocess.run(
            ["ctags", "-R", "--languages=C++", "--kinds-C++=f", "--fields=+ne",
             "--output-format=json", "-o", "-", "src", "python"],
            cwd=source_dir, check=True, capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise SystemExit(f"test_layers: cannot run Universal Ctags ({e}); scripts/setup.sh "
                         "installs it (universal-ctags)")
    found = 0
    for line in out.splitlines():
        tag = json.loads(line)
        if tag.get("_type") != "tag" or "end" not in tag:
            continue
        found += 1
        lines = tag["end"] - tag["line"] + 1
        if lines > MAX_FUNCTION_LINES and (tag["path"], tag["name"]) not in TABLES:
            yield tag["path"], tag["line"], tag["name"], lines
    if found < 500:
        raise SystemExit(f"test_layers: ctags found only {found} functions in src/")


def main():
    source_dir = sys.argv[1]
    failures = []
    seen = 0
    for path, folder, header, target in include_arrows(source_dir):
        seen += 1
        for name in (folder, target):
            if name not in LAYERS:
                failures.append(f"{path}: folder '{name}' has no layer in tests/test_layers.py")
        if not header.startswith("cbps/") and target != folder:
            failures.append(f"{path} includes {header}: a private header of {target}/ (its "
                            f"public call belongs in include/cbps/{target}/)")
        if folder in LAYERS and target in LAYERS and LAYERS[target] > LAYERS[folder]:
            failures.append(f"{path} ({folder}, layer {LAYERS[folder]}) includes {header} "
                            f"({target}, layer {LAYERS[target]}): an arrow up")
    if seen < 100:
        failures.append(f"only {seen} includes found under {source_dir}: wrong folder?")
    scripts = os.path.join(source_dir, "scripts")
    for name in sorted(os.listdir(scripts)):
        if not name.endswith(".py"):
            continue
        with open(os.path.join(scripts, name), encoding="utf-8") as f:
            text = f.read()
        if re.search(r'^\s*(from|import)\s+test_\w*', text, re.MULTILINE) or \
                re.search(r'sys\.path\.\w+\(.*"tests"', text):
            failures.append(f"scripts/{name} imports from tests/: scripts import scripts/ only")
    for path, line, name, lines in long_functions(source_dir):
        failures.append(f"{path}:{line}: {name} is {lines} lines, more than "
                        f"{MAX_FUNCTION_LINES}: split it into named steps")
    for failure in failures:
        print("FAILED:", failure, file=sys.stderr)
    print(f"{seen} includes checked; {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
