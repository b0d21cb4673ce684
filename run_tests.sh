#!/usr/bin/env bash
# Runs every test: builds the project (installing what it needs), runs the C++ suite through
# CTest, then the Python checks with pytest in the project-local virtual environment .venv.
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
exit $status
