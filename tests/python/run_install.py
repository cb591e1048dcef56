"""The two ways of installing the module, each into a scratch folder, then used from there alone
(CTest: python-install, python-pip-install; docs/python.md, "Installing").

  run_install.py cmake BUILD SCRATCH PYTHON_DIR VERSION
      `cmake --install BUILD` into prefixes under SCRATCH: the component python (the module in
      <prefix>/PYTHON_DIR, no program), the component cli (<prefix>/bin/cbps, no module), and
      everything (both). The module is imported from its prefix alone and the program run.
  run_install.py pip SOURCE BUILD SCRATCH VERSION
      A virtual environment with Debian's packages (--system-site-packages), then `pip install
      --no-build-isolation --no-index SOURCE` with CBPS_CMAKE_BUILD_DIR=BUILD (setup.py: the
      module's target is brought up to date in that build folder instead of a build of its own,
      which would take minutes). The installed module is the one BUILD made, it imports from the
      environment and solves a problem, pip's metadata has the version, and nothing was written
      into SOURCE. The environment is made --without-pip and runs Debian's pip (the same pip
      23.0.1 that ensurepip would copy into it, which takes a minute on a busy machine). Then
      the same again with build isolation (a plain `pip install`, its build requirements from
      Debian's wheels of setuptools and wheel in /usr/share/python-wheels, offline).

Run by the interpreter the module is built for. Exit 77 (skipped, with the reason) when that
interpreter lacks venv, pip, setuptools or wheel (Debian: python3-venv, python3-pip,
python3-setuptools, python3-wheel).
"""
import importlib.util
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

# What the installed module must solve (6.2): A = [[2, 1], [1, 2]], b = [1, 1], unbounded, so
# lambda = A^-1 b = [1/3, 1/3].
CHECK = """
import sys, numpy as np, cbps
assert cbps.__file__.startswith(sys.argv[1]), (cbps.__file__, sys.argv[1])
assert cbps.__version__ == sys.argv[2], (cbps.__version__, sys.argv[2])
if len(sys.argv) > 3:  # installed by pip: its metadata (cbps-VERSION.dist-info) says so too
    from importlib.metadata import version
    assert version("cbps") == sys.argv[2], (version("cbps"), sys.argv[2])
lam, s = cbps.solve([[2.0, 1.0], [1.0, 2.0]], [1.0, 1.0], [-np.inf] * 2, [np.inf] * 2, "direct")
assert np.allclose(lam, [1 / 3, 1 / 3], rtol=1e-14, atol=0), lam
print("cbps", cbps.__version__, "from", cbps.__file__, "solves:", lam)
"""


def clean_env(**extra):
    """The environment without CTest's PYTHONPATH to the build folder: the module must come
    from where it was installed."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env.update(extra)
    return env


def run(command, **kwargs):
    print("+", " ".join(map(str, command)), flush=True)
    return subprocess.run(list(map(str, command)), check=True, **kwargs)


def import_from(python, folder, version, cwd, env, *extra):
    run([python, "-c", CHECK, folder, version, *extra], cwd=cwd, env=env)


def cmake_install(build, scratch, python_dir, version):
    cmake = os.environ.get("CMAKE_COMMAND", "cmake")
    built_cli = build / "cbps"
    expected_scenes = json.loads(run([built_cli, "scenes", "--json"], capture_output=True,
                                     text=True).stdout)
    for component in ("python", "cli", None):
        prefix = scratch / (component or "all")
        shutil.rmtree(prefix, ignore_errors=True)
        prefix.mkdir(parents=True)
        run([cmake, "--install", build, "--prefix", prefix]
            + (["--component", component] if component else []))
        module_dir = prefix / python_dir
        program = prefix / "bin" / "cbps"
        has_module = any(module_dir.glob("cbps*.so")) if module_dir.is_dir() else False
        assert has_module == (component != "cli"), (component, module_dir)
        assert program.is_file() == (component != "python"), (component, program)
        if has_module:
            # The working folder is the prefix (python -c puts it first on sys.path), PYTHONPATH
            # the installed folder, not the build's.
            import_from(sys.executable, str(module_dir), version, prefix,
                        clean_env(PYTHONPATH=str(module_dir), PYTHONDONTWRITEBYTECODE="1"))
        if program.is_file():
            assert os.access(program, os.X_OK), program
            out = run([program, "scenes", "--json"], capture_output=True, text=True, cwd=prefix)
            assert json.loads(out.stdout) == expected_scenes
            print("installed program", program, "lists", len(expected_scenes), "scenes")


def top_entries(folder):
    return sorted(p.name for p in folder.iterdir()) if folder.is_dir() else []


def run_notebook_in(python, source, scratch, site):
    """The worked example's notebook run in a Jupyter kernel of the environment, as
    docs/python.md ("Jupyter") tells a reader: the environment registered as a kernel
    (`python -m ipykernel install`, here under SCRATCH/jupyter instead of ~/.local) and chosen
    by name, no PYTHONPATH; the notebook's added last cell asserts that cbps came from `site`.
    Debian's own python3 kernel would not see a module installed into the environment."""
    for module in ("nbclient", "nbformat", "ipykernel"):
        if importlib.util.find_spec(module) is None:
            print(f"the notebook from the environment SKIPPED: no module {module} (Debian: "
                  "python3-nbclient, python3-ipykernel; scripts/setup.sh)")
            return
    prefix = scratch / "jupyter"
    env = clean_env(PYTHONDONTWRITEBYTECODE="1")
    run([python, "-m", "ipykernel", "install", "--prefix", prefix, "--name", "cbps-venv",
         "--display-name", "Python (cbps)"], env=env, capture_output=True)
    env["JUPYTER_PATH"] = str(prefix / "share" / "jupyter")
    run([python, source / "tests" / "python" / "run_notebook.py",
         source / "examples" / "worked_example.ipynb", scratch / "notebook",
         "--kernel", "cbps-venv", "--module-under", os.path.realpath(site)], env=env)


def pip_install(source, build, scratch, version):
    for module in ("venv", "pip", "wheel", "setuptools"):
        if importlib.util.find_spec(module) is None:  # found, not imported (they clash)
            print(f"pip install test SKIPPED: {sys.executable} has no module {module} (Debian: "
                  "python3-venv, python3-pip, python3-wheel, python3-setuptools; "
                  "scripts/setup.sh)")
            return 77
    shutil.rmtree(scratch, ignore_errors=True)
    scratch.mkdir(parents=True)
    venv = scratch / "venv"
    run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", venv])
    python = venv / "bin" / "python"
    # What pip's in-tree build could leave in the source tree: new top-level entries (such as
    # cbps.egg-info), new folders under build/ (setuptools' build/lib..., build/python-wheel).
    before = (top_entries(source), top_entries(source / "build"))
    env = clean_env(CBPS_CMAKE_BUILD_DIR=str(build), PIP_NO_CACHE_DIR="1",
                    PIP_DISABLE_PIP_VERSION_CHECK="1", PYTHONDONTWRITEBYTECODE="1")
    run([python, "-m", "pip", "install", "--no-build-isolation", "--no-index", source],
        cwd=scratch, env=env)
    after = (top_entries(source), top_entries(source / "build"))
    assert after == before, f"pip install left files in the source tree: {before} -> {after}"
    site = run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['platlib'])"],
               capture_output=True, text=True, env=clean_env()).stdout.strip()
    installed = sorted(Path(site).glob("cbps*.so"))
    built = sorted((build / "python").glob("cbps*.so"))
    assert len(installed) == 1 and len(built) == 1, (installed, built)
    assert installed[0].read_bytes() == built[0].read_bytes(), "not the build folder's module"
    import_from(python, site, version, scratch, clean_env(PYTHONDONTWRITEBYTECODE="1"), "pip")
    run_notebook_in(python, source, scratch, site)

    # The plain `pip install .`: with build isolation, pip installs pyproject.toml's
    # [build-system] requires (setuptools, wheel) into an environment of their own first. Offline
    # they come from Debian's wheels of them (python3-setuptools-whl, python3-wheel-whl).
    wheels = Path("/usr/share/python-wheels")
    if not (any(wheels.glob("setuptools-*.whl")) and any(wheels.glob("wheel-*.whl"))):
        print(f"the install with build isolation SKIPPED: no setuptools and wheel wheels in "
              f"{wheels} (Debian: python3-setuptools-whl, python3-wheel-whl)")
        return 0
    installed[0].unlink()
    isolated_env = dict(env)
    isolated_env.pop("PIP_FIND_LINKS", None)
    out = run([python, "-m", "pip", "install", "-v", "--force-reinstall", "--no-deps",
               "--no-index", "--find-links", wheels, source],
              cwd=scratch, env=isolated_env, capture_output=True, text=True).stdout
    assert "Installing build dependencies: finished" in out, out
    assert (top_entries(source), top_entries(source / "build")) == before
    assert installed[0].read_bytes() == built[0].read_bytes(), "not the build folder's module"
    import_from(python, site, version, scratch, clean_env(PYTHONDONTWRITEBYTECODE="1"), "pip")
    return 0


def main(argv):
    mode = argv[1]
    if mode == "cmake":
        build, scratch, python_dir, version = Path(argv[2]), Path(argv[3]), argv[4], argv[5]
        cmake_install(build, scratch, python_dir, version)
        return 0
    if mode == "pip":
        source, build, scratch, version = (Path(argv[2]).resolve(), Path(argv[3]).resolve(),
                                           Path(argv[4]), argv[5])
        return pip_install(source, build, scratch, version)
    raise SystemExit(f"run_install.py: unknown mode {mode!r}: cmake or pip")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
