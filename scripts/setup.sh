#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
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
"$here/scripts/install_debian_packages.sh" "${packages[@]}"

build="${DYNBLUR_BUILD_DIR:-$here/build}"
echo "[setup] configuring and building in $build"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)"
