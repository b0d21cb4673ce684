#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs every test: builds the project (installing what it needs), runs the C++ suite through
# CTest, installs the build into a temporary prefix and builds and runs an application against it
# (scripts/install_check.sh: find_package and pkg-config), then the Python checks with pytest in the
# project-local virtual environment .venv, then the C++ suite again, built with clang, under ASan +
# UBSan (scripts/sanitize.sh, build-asan/), the fuzz targets
# (scripts/fuzz.sh, build-fuzz/: corpus and regressions, then DYNBLUR_FUZZ_SECONDS each), the
# restoration kernels against their references on aarch64 under qemu and on each x86 instruction set
# (scripts/arm_check.sh, $build/kernel-check/) and the short speed check (scripts/benchmark.sh --ci:
# the row-wise restoration against its filter2D peer).
#
# DYNBLUR_REQUIRE_TEST_DATA=1 is set for every step: a test whose data file is missing fails instead
# of skipping, so a run without ../shared/data (or DYNBLUR_TEST_DATA) cannot pass. Whatever is still
# skipped (absent optional hardware or packages) is listed at the end, from the CTest and pytest logs
# kept in $build/test-logs/.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$here/scripts/setup.sh"
build="${DYNBLUR_BUILD_DIR:-$here/build}"
export DYNBLUR_BUILD_DIR="$build"
export DYNBLUR_TEST_DATA="${DYNBLUR_TEST_DATA:-$here/../shared/data}"
export DYNBLUR_REQUIRE_TEST_DATA=1
logs="$build/test-logs"
mkdir -p "$logs"
rm -f "$logs"/*.log

# stage TEXT: announces a stage, after the time the previous one took (the setup's, first).
stage_start=0
stage() {
  echo "[tests] ($((SECONDS - stage_start)) s)"
  stage_start=$SECONDS
  echo "[tests] $1"
}
stage "C++ (CTest, GoogleTest); test data: $DYNBLUR_TEST_DATA (required)"
status=0
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" 2>&1 | tee "$logs/ctest.log" || status=$?

stage "installed package: an application built against it with find_package and pkg-config"
"$here/scripts/install_check.sh" 2>&1 | tee "$logs/install.log" || status=$?

stage "Python (pytest)"
python="$("$here/scripts/python_env.sh")"
"$python" -m pytest -q -rs "$here/tests/python" 2>&1 | tee "$logs/pytest.log" || status=$?

stage "C++ built with clang, under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)"
"$here/scripts/sanitize.sh" 2>&1 | tee "$logs/ctest-asan.log" || status=$?

stage "libFuzzer targets: corpus and regressions, then a bounded run each (build-fuzz/)"
"$here/scripts/fuzz.sh" 2>&1 | tee "$logs/ctest-fuzz.log" || status=$?

stage "kernels on aarch64 under qemu (scripts/arm_check.sh)"
"$here/scripts/arm_check.sh" 2>&1 | tee "$logs/arm.log" || status=$?

stage "speed: a few paired rounds, ratios only (scripts/benchmark.sh --ci)"
"$here/scripts/benchmark.sh" --ci 2>&1 | tee "$logs/benchmark-ci.log" || status=$?

# CTest marks a skipped test "***Skipped" (a GoogleTest GTEST_SKIP, or a CLI test's DYNBLUR-SKIP
# line) and one it could not start "***Not Run"; pytest -rs prints a "SKIPPED [n] file:line: reason"
# summary line per skip.
stage "skipped or not run in this run:"
skipped="$( { grep -H -E '\*\*\*(Skipped|Not Run)|Disabled' "$logs"/ctest*.log \
                | sed -E -e 's|^.*/([a-z-]+)\.log: *[0-9]+/[0-9]+ |\1: |' -e 's/ \.{3,}/ /' || true
              grep -H -E '^SKIPPED' "$logs/pytest.log" | sed -E 's|^.*/([a-z-]+)\.log:|\1: |' || true; } )"
if [ -n "$skipped" ]; then
  echo "$skipped" | sed 's/^/  /'
else
  echo "  none"
fi
echo "[tests] $SECONDS s in all"
if [ "$status" -eq 0 ]; then
  echo "[tests] PASS"
else
  echo "[tests] FAIL (exit $status)"
fi
exit $status
