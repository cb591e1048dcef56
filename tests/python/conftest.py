"""Shared pieces of the Python module's tests (tests/python, run by CTest as python-*).

CTest sets PYTHONPATH to the build's python/ folder and CBPS_EXECUTABLE to the command line
built beside the module; run by hand, the tests look for both in build/release.
"""
import json
import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
from cbps_problem import cone_natural_maps, natural_map_residual  # noqa: E402,F401  (6.2 in numpy)
CLI = os.environ.get("CBPS_EXECUTABLE", str(ROOT / "build" / "release" / "cbps"))


def cli(*args, check=True):
    """Runs the command line; returns the completed process (text output)."""
    result = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"cbps {' '.join(map(str, args))}: exit {result.returncode}\n"
                             f"{result.stderr}")
    return result


def cli_error(*args):
    """The message of a command line that fails with bad input: exit 2, 'cbps: <message>'."""
    result = cli(*args, check=False)
    assert result.returncode == 2, (result.returncode, result.stdout, result.stderr)
    line = result.stderr.strip().splitlines()[0]
    assert line.startswith("cbps: "), line
    return line[len("cbps: "):]


def cli_json(*args):
    return json.loads(cli(*args).stdout)


@pytest.fixture(scope="session")
def cbps_module():
    import cbps
    return cbps
