#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# libFuzzer targets (docs/reliability.md): builds fuzz/ with clang in build-fuzz/ (DYNBLUR_BUILD_FUZZ=ON: the
# library, samples/support and samples/simulation compiled with ASan + UBSan + coverage), runs every
# file of fuzz/corpus/<target>/ and fuzz/regressions/<target>/ once (CTest), then fuzzes each target
# for a bounded time. Any crash, sanitizer report, leak, hang (> 10 s per input) or out-of-memory
# fails the run; the input that caused it is kept in build-fuzz/artifacts/<target>/. Called by
# run_tests.sh.
#
#   DYNBLUR_FUZZ_SECONDS    fuzzing time per target (default 20; 0: corpus and regressions only)
#   DYNBLUR_FUZZ_BUILD_DIR  build folder (default build-fuzz/)
# New inputs the fuzzers find are kept in build-fuzz/fuzz-corpus/<target>/ (not in the repository;
# see fuzz/README.md for adding some to the seed corpus).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${DYNBLUR_FUZZ_BUILD_DIR:-$here/build-fuzz}"
seconds="${DYNBLUR_FUZZ_SECONDS:-20}"
targets=(camera_xml plant_file schedule_file response_log recording_logs gyro_log modbus_reply)

echo "[fuzz] configuring and building in $build (clang, libFuzzer, ASan + UBSan)"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang \
      -DCMAKE_CXX_COMPILER=clang++ -DDYNBLUR_BUILD_FUZZ=ON >/dev/null
cmake --build "$build" -j "$(nproc)"

# shellcheck source=scripts/sanitizer_env.sh
source "$here/scripts/sanitizer_env.sh"
echo "[fuzz] corpus and regression inputs, once each (CTest)"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"

[ "$seconds" -gt 0 ] || exit 0
echo "[fuzz] fuzzing each target for $seconds s, $(nproc) at a time"
# fuzz_one TARGET: fuzzes one target for $seconds s into its log, build/fuzz_TARGET.log, and writes
# its exit status to build/fuzz_TARGET.status.
fuzz_one() {
  local t="$1" work="$build/fuzz-corpus/$1" artifacts="$build/artifacts/$1"
  mkdir -p "$work" "$artifacts"
  local inputs=("$work" "$here/fuzz/corpus/$t")
  [ -d "$here/fuzz/regressions/$t" ] && inputs+=("$here/fuzz/regressions/$t")
  local rc=0
  # -close_fd_mask=1: the target's stdout (ViSP prints every camera it finds) is not logged.
  "$build/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -close_fd_mask=1 -artifact_prefix="$artifacts/" "${inputs[@]}" >"$build/fuzz_$t.log" 2>&1 || rc=$?
  echo "$rc" >"$build/fuzz_$t.status"
}
for t in "${targets[@]}"; do
  rm -f "$build/fuzz_$t.status"
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || true; done
  fuzz_one "$t" &
done
wait
status=0
summary=()
for t in "${targets[@]}"; do
  log="$build/fuzz_$t.log" artifacts="$build/artifacts/$t"
  if [ "$(cat "$build/fuzz_$t.status" 2>/dev/null)" = 0 ]; then
    result=ok
  else
    result=FAILED
    status=1
    echo "[fuzz] fuzz_$t FAILED; end of $log:"
    tail -n 40 "$log"
    ls -1 "$artifacts" | sed "s#^#[fuzz]   crasher: $artifacts/#"
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
  summary+=("$(printf '%-14s %-6s %10s runs %7s exec/s  %6s edges' "$t" "$result" "${runs:-?}" "${rate:-?}" "${cov:-?}")")
done
echo "[fuzz] summary ($seconds s per target)"
printf '  %s\n' "${summary[@]}"
exit $status
