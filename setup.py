"""The build step of `pip install .` (pyproject.toml; docs/python.md, "Installing with pip").

setuptools builds the wheel; its build_ext is replaced by one that runs the repository's CMake
build of the module's target, cbps_python (python/CMakeLists.txt), with the release preset's
settings (Ninja, Release, warnings as errors) for the interpreter that runs pip, and copies the
extension module it makes into the wheel. The module links the same libraries as the command
line (cbps_core, cbps_studies) built from the same sources.

Where it builds:
- by default in a CMake build folder of its own, build/python-wheel/cmake in this source tree
  (ignored by git, as every build*/ folder): a full build of the libraries the first time, about
  as long as `cmake --build build/release --target cbps_python` from nothing; later installs
  reuse it. Set CMAKE_CXX_COMPILER_LAUNCHER=ccache in the environment to use ccache.
- with CBPS_CMAKE_BUILD_DIR=<folder>, in that existing, configured build folder (such as
  build/release): only the module's target is brought up to date there, and setuptools'
  own files go into <folder>/python-wheel, so nothing is written into the source tree. The
  folder must have been configured for this interpreter's Python version.
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
REUSED = os.environ.get("CBPS_CMAKE_BUILD_DIR", "")
# setuptools' staging folders (build/, *.egg-info): beside the CMake build they go with.
STAGING = (Path(REUSED).resolve() if REUSED else ROOT / "build") / "python-wheel"


def project_version():
    """The version of CMakeLists.txt's project(cbps VERSION x.y.z), the one source of it."""
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    match = re.search(r"project\(\s*cbps\s+VERSION\s+([0-9][0-9.]*)", text)
    if match is None:
        raise SystemExit("setup.py: no 'project(cbps VERSION ...)' in CMakeLists.txt")
    return match.group(1)


def run(command):
    print("setup.py:", " ".join(command), flush=True)
    subprocess.run(command, check=True)


class CMakeBuild(build_ext):
    """build_ext by CMake: configure (unless reusing a build folder), build cbps_python, copy."""

    def build_extension(self, ext):
        if REUSED:
            build_dir = Path(REUSED).resolve()
            if not (build_dir / "CMakeCache.txt").is_file():
                raise SystemExit(f"setup.py: CBPS_CMAKE_BUILD_DIR={REUSED}: not a configured "
                                 "CMake build folder (no CMakeCache.txt); configure it first "
                                 "(cmake --preset release) or unset the variable")
        else:
            build_dir = STAGING / "cmake"
            # The release preset (CMakePresets.json) into a folder of its own, with only what
            # the module needs: no tests, benchmarks, validation programs or PETSc.
            run(["cmake", "--preset", "release", "-S", str(ROOT), "-B", str(build_dir),
                 f"-DCBPS_PYTHON_EXECUTABLE={sys.executable}", "-DCBPS_PYTHON=ON",
                 "-DCBPS_BUILD_TESTS=OFF", "-DCBPS_BUILD_BENCH=OFF",
                 "-DCBPS_BUILD_VALIDATION=OFF", "-DCBPS_PETSC=OFF"])
        run(["cmake", "--build", str(build_dir), "--target", "cbps_python"])
        # The file CMake names for this interpreter (cbps.cpython-311-x86_64-linux-gnu.so).
        built = build_dir / "python" / ("cbps" + sysconfig.get_config_var("EXT_SUFFIX"))
        if not built.is_file():
            found = sorted(p.name for p in (build_dir / "python").glob("cbps*"))
            raise SystemExit(f"setup.py: {built} was not built: the build folder has {found or 'no module'}; "
                             f"it must be configured for {sys.executable} (Python "
                             f"{sys.version_info.major}.{sys.version_info.minor}); CMake's status "
                             "line 'cbps: Python module ...' says which interpreter it found")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


STAGING.mkdir(parents=True, exist_ok=True)
setup(
    version=project_version(),
    # One extension module and no Python packages: nothing for setuptools to look for.
    packages=[],
    py_modules=[],
    ext_modules=[Extension("cbps", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(STAGING / "build")},
             "egg_info": {"egg_base": str(STAGING)}},
)
