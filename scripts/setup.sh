#!/usr/bin/env bash
# Installs what the build needs (Debian packages) and configures + builds the project in build/.
# Idempotent: a second run only rebuilds what changed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

packages=(build-essential cmake ninja-build pkg-config git
          libopencv-dev libeigen3-dev libsundials-dev libfftw3-dev libvisp-dev
          libgtest-dev libbenchmark-dev pybind11-dev libmodbus-dev
          python3-venv
          # the fuzz build (scripts/fuzz.sh): clang, its libFuzzer and sanitizer runtimes, and LLVM's
          # OpenMP (only because SUNDIALS' CMake config requires OpenMP, also under clang)
          clang libclang-rt-dev libomp-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "[setup] installing Debian packages: ${missing[*]}"
  sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build="${DYNBLUR_BUILD_DIR:-$here/build}"
echo "[setup] configuring and building in $build"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)"
