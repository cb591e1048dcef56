#!/usr/bin/env bash
# Installs cbps's build and run dependencies from Debian 12's packages (idempotent).
# Runs apt-get only when a package is missing; uses sudo when not root.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev catch2 libgsl-dev nlohmann-json3-dev libcli11-dev
  libbenchmark-dev python3 python3-matplotlib python3-numpy python3-scipy python3-dev
  pybind11-dev python3-pytest python3-nbclient python3-ipykernel clang-format
  clang libclang-rt-14-dev llvm-14
  chromium  # headless, for the teaching page's tests (tests/test_teaching_page_browser.py)
)
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
