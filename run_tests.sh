#!/usr/bin/env bash
# Runs every test: builds the project (installing what it needs), then the C++ suite via CTest.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$here/scripts/setup.sh"
build="${DYNBLUR_BUILD_DIR:-$here/build}"
export DYNBLUR_TEST_DATA="${DYNBLUR_TEST_DATA:-$here/../shared/data}"
echo "[tests] C++ (CTest, GoogleTest)"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"
