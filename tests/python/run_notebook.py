#!/usr/bin/python3
"""Runs examples/worked_example.ipynb headless, as a reader would run every cell in order, and
fails if any cell raises (its last cell asserts that every check of worked_example.py passed).

usage: run_notebook.py NOTEBOOK OUT_DIR [--kernel NAME --module-under DIR]

The notebook must be stored without outputs (a clean file in the repository). With --kernel the
cells run in that Jupyter kernel (default python3), and with --module-under a last cell (added
in memory, not to the file) asserts that the kernel imported cbps from under DIR: how
tests/python/run_install.py runs the notebook from a virtual environment registered as a kernel
(docs/python.md, "Jupyter"). Exit 77 (CTest: skipped) with the reason when Debian's
python3-nbclient or python3-ipykernel is missing."""
import os
import pathlib
import sys


def main():
    import argparse
    parser = argparse.ArgumentParser()
    parser.add_argument("notebook")
    parser.add_argument("out")
    parser.add_argument("--kernel", default="python3")
    parser.add_argument("--module-under")
    args = parser.parse_args()
    notebook, out = pathlib.Path(args.notebook).resolve(), pathlib.Path(args.out).resolve()
    try:
        import nbclient
        import nbformat
        import ipykernel  # noqa: F401  (the python3 kernel nbclient starts)
    except ImportError as e:
        print(f"notebook SKIPPED: {e.name} is not installed (Debian: python3-nbclient, "
              "python3-ipykernel; scripts/setup.sh installs them)")
        return 77
    nb = nbformat.read(notebook, as_version=4)
    nbformat.validate(nb)
    stored = [i for i, c in enumerate(nb.cells)
              if c.cell_type == "code" and (c.outputs or c.execution_count is not None)]
    if stored:
        print(f"{notebook}: cells {stored} are stored with outputs; clear them before committing")
        return 1
    out.mkdir(parents=True, exist_ok=True)
    os.environ["CBPS_EXAMPLE_OUT"] = str(out)
    # The kernel runs in the notebook's folder: the module's folder must not be relative.
    os.environ["PYTHONPATH"] = os.pathsep.join(
        str(pathlib.Path(p).resolve()) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep)
        if p)
    os.environ["PYDEVD_DISABLE_FILE_VALIDATION"] = "1"  # ipykernel's debugger: no warnings
    os.environ["MPLBACKEND"] = "module://matplotlib_inline.backend_inline"
    if args.module_under:
        nb.cells.append(nbformat.v4.new_code_cell(
            "import cbps, os\n"
            f"assert os.path.realpath(cbps.__file__).startswith({args.module_under!r}), "
            "cbps.__file__\n"
            "print('cbps imported from', cbps.__file__)"))
    client = nbclient.NotebookClient(nb, timeout=120, kernel_name=args.kernel,
                                     resources={"metadata": {"path": str(notebook.parent)}})
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as e:
        print(f"{notebook}: a cell failed:\n{e}")
        return 1
    text = "".join(o.get("text", "") for c in nb.cells if c.cell_type == "code"
                   for o in c.outputs)
    images = sum("image/png" in o.get("data", {}) for c in nb.cells if c.cell_type == "code"
                 for o in c.outputs)
    for expected in ("every check passed", "lambda ="):
        if expected not in text:
            print(f"{notebook}: its output lacks {expected!r}")
            return 1
    if images < 1 or not (out / "chain-pgs.png").is_file():
        print(f"{notebook}: expected an inline figure and {out / 'chain-pgs.png'}")
        return 1
    print(f"{notebook}: {len(nb.cells)} cells ran, {images} inline figure(s), every check passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
