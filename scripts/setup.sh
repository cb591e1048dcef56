#!/usr/bin/env bash
# Installs cbps's build and run dependencies from Debian 12's packages (idempotent).
# Runs apt-get only when a package is missing; uses sudo when not root.
#
#   scripts/setup.sh                the packages every build needs
#   scripts/setup.sh --with-petsc   and PETSc with Open MPI, for `cbps lcp --solver tao:TYPE`
#                                   under mpirun (docs/distributed.md); optional, the build uses
#                                   PETSc when it finds it
set -euo pipefail
with_petsc=0
for arg in "$@"; do
  case "$arg" in
    --with-petsc) with_petsc=1 ;;
    -h | --help)
      sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *)
      echo "setup: unknown option $arg (use --with-petsc, or nothing)" >&2
      exit 2
      ;;
  esac
done
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev catch2 libgsl-dev nlohmann-json3-dev libcli11-dev
  libbenchmark-dev python3 python3-matplotlib python3-numpy python3-scipy python3-dev
  pybind11-dev python3-pytest python3-nbclient python3-ipykernel clang-format
  universal-ctags  # function lengths in tests/test_layers.py
  python3-venv python3-pip python3-setuptools python3-wheel  # pip install . (docs/python.md)
  python3-setuptools-whl python3-wheel-whl  # the same with build isolation, offline
  clang libclang-rt-14-dev llvm-14
  chromium  # headless, for the teaching page's tests (tests/test_teaching_page_browser.py)
  # The peers, siconos:NAME and bullet:NAME (docs/peers.md): Siconos numerics' C API and
  # Bullet's MLCP solvers in double precision (libBulletDynamics-float64).
  libsiconos-numerics-dev libbullet-dev
  # FCLIB files (docs/cones.md): HDF5 for cbps's reader and writer; FCLIB's own library for the
  # tests (its reader and merit function check what cbps writes).
  libhdf5-dev libfclib-dev
  # MuJoCo's C API for `cbps mujoco` (docs/mujoco.md), and its sample models for the study.
  libmujoco-dev libmujoco-samples
)
if [ "$with_petsc" -eq 1 ]; then
  # PETSc 3.18 (pkg-config PETSc) with Open MPI's headers and its mpirun; and OpenBLAS's
  # threaded build, which PETSc's packages may bring as the system's libblas.so.3 (they did on a
  # new user's machine): it starts worker threads before main, so the tests run with it
  # (--threads, and Ctrl-C whichever thread receives it, docs/cli-contract.md).
  packages+=(petsc-dev libopenmpi-dev openmpi-bin libopenblas0-pthread)
fi
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ "${#missing[@]}" -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present" >&2
  exit 0
fi
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
echo "setup: installing ${missing[*]}" >&2
"${sudo_cmd[@]}" apt-get update
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
