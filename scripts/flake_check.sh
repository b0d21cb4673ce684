#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Flake check (docs/reliability.md): the CTest suite repeated while busy loops load every core, so a
# test that depends on the machine's speed or on timing fails here before it fails in CI.
# Not part of ./run_tests.sh (it takes several times the suite's time).
set -euo pipefail
usage() {
  cat <<'USAGE'
Usage: scripts/flake_check.sh [--repeat N] [--load N] [--regex R] [--exclude R] [--skip-figures] [--build DIR]

Builds the project (scripts/setup.sh), starts N busy loops (default: one per core), and runs
`ctest --repeat until-fail:N` on the build (each test up to N times, stopping at its first failure).
Exits non-zero if any test failed in any repetition.

  --repeat N   repetitions of each test (default 5)
  --load N     busy loops competing with the tests (default: nproc)
  --regex R    only the tests matching R (ctest -R)
  --exclude R  not the tests matching R (ctest -E), e.g. the long figure tests, whose results depend
               on no timing and which take most of the suite's time
  --skip-figures  not the long figure tests (scripts/figure_tests.regex), nor HalfColor.* and
               DeconvMemory.*: their results depend on no timing, and they take most of the suite's time
  --build DIR  build folder (default: build/, or $DYNBLUR_BUILD_DIR)
USAGE
}
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
repeat=5 load="$(nproc)" regex="" exclude="" build="${DYNBLUR_BUILD_DIR:-$here/build}"
while [ $# -gt 0 ]; do
  case "$1" in
    --repeat|--load|--regex|--exclude|--build)
      [ $# -ge 2 ] || { echo "flake_check: $1 needs a value" >&2; exit 2; }
      opt="$1"; val="$2"; shift 2 ;;
    --repeat=*|--load=*|--regex=*|--exclude=*|--build=*) opt="${1%%=*}"; val="${1#*=}"; shift ;;
    --skip-figures) exclude="${exclude:+$exclude|}$(grep -v '^#' "$here/scripts/figure_tests.regex" | paste -sd'|')|HalfColor\.|DeconvMemory\."; shift; continue ;;
    -h|--help) usage; exit 0 ;;
    *) echo "flake_check: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  case "$opt" in
    --repeat) repeat="$val" ;;
    --load) load="$val" ;;
    --regex) regex="$val" ;;
    --exclude) exclude="${exclude:+$exclude|}$val" ;;
    --build) build="$val" ;;
  esac
done
[[ "$repeat" =~ ^[1-9][0-9]*$ ]] || { echo "flake_check: --repeat must be a positive integer, got '$repeat'" >&2; exit 2; }
[[ "$load" =~ ^[0-9]+$ ]] || { echo "flake_check: --load must be a non-negative integer, got '$load'" >&2; exit 2; }

DYNBLUR_BUILD_DIR="$build" "$here/scripts/setup.sh"
export DYNBLUR_TEST_DATA="${DYNBLUR_TEST_DATA:-$here/../shared/data}"
export DYNBLUR_REQUIRE_TEST_DATA=1

pids=()
stop_load() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap stop_load EXIT
for _ in $(seq 1 "$load"); do
  ( while :; do :; done ) &
  pids+=("$!")
done
echo "[flake] $load busy loop(s) running; ctest --repeat until-fail:$repeat${regex:+ -R $regex}${exclude:+ -E $exclude} on $build"
start=$(date +%s)
args=(--test-dir "$build" --output-on-failure -j "$(nproc)" --repeat "until-fail:$repeat")
[ -n "$regex" ] && args+=(-R "$regex")
[ -n "$exclude" ] && args+=(-E "$exclude")
status=0
ctest "${args[@]}" 2>&1 | tee "$build/flake-check.log" || status=$?
echo "[flake] $(( ($(date +%s) - start) / 60 )) min; $( [ $status -eq 0 ] && echo "PASS: no failure in $repeat repetitions" || echo "FAIL (see $build/flake-check.log)")"
exit $status
