#!/usr/bin/env bash
# Runs every test: builds the project (installing what it needs), runs the C++ suite through
# CTest, then the Python checks with pytest in the project-local virtual environment .venv, then
# the C++ suite again under ASan + UBSan (scripts/sanitize.sh, build-asan/) and the fuzz targets
# (scripts/fuzz.sh, build-fuzz/: corpus and regressions, then DYNBLUR_FUZZ_SECONDS each).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$here/scripts/setup.sh"
build="${DYNBLUR_BUILD_DIR:-$here/build}"
export DYNBLUR_BUILD_DIR="$build"
export DYNBLUR_TEST_DATA="${DYNBLUR_TEST_DATA:-$here/../shared/data}"

echo "[tests] C++ (CTest, GoogleTest)"
status=0
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" || status=$?

echo "[tests] Python (pytest)"
python="$("$here/scripts/python_env.sh")"
"$python" -m pytest -q "$here/tests/python" || status=$?

echo "[tests] C++ under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)"
"$here/scripts/sanitize.sh" || status=$?

echo "[tests] libFuzzer targets: corpus and regressions, then a bounded run each (build-fuzz/)"
"$here/scripts/fuzz.sh" || status=$?
exit $status
