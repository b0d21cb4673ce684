#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The restoration kernels' test, on aarch64 under qemu and natively on each x86 instruction set.
#
# What: every tests/restore/kernels/*_check.cpp is a self-contained program (its own main(), the
# kernel headers of modules/dynblur/src/restore/kernels/ and their plain C++ references) that exits
# non-zero when a vector kernel and its reference disagree (the folder's test_*.cpp belong to
# dynblur_test's GoogleTest suite instead). This script builds each one
#   - for aarch64 with Debian's g++-aarch64-linux-gnu, -static, and runs it under qemu-aarch64-static
#     (package qemu-user-static), and
#   - for the host, once per x86 flag set: baseline (SSE2), -mavx2 -mfma, and
#     -mavx512f -mavx512bw -mavx512vl -mavx512dq -mavx512cd -mfma, running each set the CPU has,
# and fails if any build or run fails. Packages it lacks are installed first
# (scripts/install_debian_packages.sh, as for scripts/setup.sh). Builds go to $DYNBLUR_BUILD_DIR/kernel-check/<target>/ (default build/kernel-check/) and are
# incremental; a full run takes well under a minute once the packages are installed.
#
# Why it works without libopencv: the kernels are header-only over OpenCV's universal intrinsics
# (opencv2/core/hal/intrin.hpp), so only the OpenCV 4.6 headers of the host (/usr/include/opencv4,
# architecture-independent) are needed; nothing is linked but the C++ runtime. OpenCV's generated
# cvconfig.h / cv_cpu_config.h are not read at all outside OpenCV's own build (__OPENCV_BUILD unset):
# opencv2/core/cv_cpu_dispatch.h then takes its "compatibility" branch, which derives only three
# macros from the compiler: CV_SSE2 from __SSE2__, CV_NEON from __ARM_NEON (on AArch64), CV_FP16 from
# __F16C__.
#   - aarch64: NEON is part of the base ISA; the cross compiler defines __ARM_NEON, so CV_NEON = 1 and
#     intrin_neon.hpp gives CV_SIMD128 (v_float32 = 4 lanes, v_fma = vfmaq_f32) with no define or shim.
#   - x86: every other CV_<ISA> macro defaults to 0 whatever -m flags were given, so -mavx2 -mfma
#     alone still yields 128-bit SSE2 vectors and a v_fma that is a multiply then an add. The
#     CV_CPU_COMPILE_* macros would not help either: only the __OPENCV_BUILD branch reads them. So
#     each build force-includes modules/dynblur/src/restore/kernels/cv_isa_from_compiler.hpp (the library's per-ISA kernel files include it too), which maps __AVX2__, __FMA__,
#     __AVX512*__ ... onto CV_AVX2, CV_FMA3, CV_AVX512_SKX ... (and includes <immintrin.h>), the way
#     OpenCV's build does: then -mavx2 -mfma gives 256-bit and the AVX-512 set 512-bit vectors. (The header and the probe below work
#     the same under clang++, natively and with --target=aarch64-linux-gnu.)
# scripts/arm_check/simd_probe.cpp, linked into every test, proves it each time: its build fails
# unless CV_SIMD_WIDTH is the width the target was built for (16 for NEON and SSE, 32 for AVX2, 64 for
# AVX-512) and not OpenCV's C++ emulation, and at start-up it runs one v_fma and prints the vectors,
# e.g. "[simd] NEON: CV_SIMD_WIDTH 16, v_float32 of 4 lanes, one v_fma checked, CPU reports ASIMD".
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

usage() {
  cat <<'EOF'
Usage: scripts/arm_check.sh [--arm-only | --native-only] [--no-install] [--help]
Builds every tests/restore/kernels/*_check.cpp for aarch64 (static, run under
qemu-aarch64-static) and for the host once per x86 flag set (sse2, avx2, avx512; a set the CPU lacks
is built but not run), runs them and exits non-zero if any build or test fails.
  --arm-only      only the aarch64 build and run
  --native-only   only the host builds and runs (no cross packages needed)
  --no-install    do not install missing Debian packages (fail instead)
Environment: DYNBLUR_BUILD_DIR (default build/): outputs go to its kernel-check/ folder.
EOF
}

arm=1; native=1; install=1
for arg in "$@"; do
  case "$arg" in
    --arm-only) native=0 ;;
    --native-only) arm=0 ;;
    --no-install) install=0 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "arm_check: unknown argument $arg" >&2; usage >&2; exit 2 ;;
  esac
done

src="$here/tests/restore/kernels"
out="${DYNBLUR_BUILD_DIR:-$here/build}/kernel-check"
shopt -s nullglob
tests=("$src"/*_check.cpp)
if [ ${#tests[@]} -eq 0 ]; then
  echo "[arm_check] no kernel tests in $src" >&2
  exit 1
fi

packages=(libopencv-dev make)
[ "$arm" -eq 1 ] && packages+=(g++-aarch64-linux-gnu qemu-user-static)
if [ "$install" -eq 1 ]; then
  "$here/scripts/install_debian_packages.sh" "${packages[@]}"
else
  "$here/scripts/install_debian_packages.sh" --check "${packages[@]}"
fi

# One target per line: name, expected vector width (bytes), compiler, CPU flags it needs to run
# (/proc/cpuinfo names), compile flags, link flags.
# GCC 12 warns "'__Y' may be used uninitialized" inside its own avx512fintrin.h wherever OpenCV's
# AVX-512 code inlines _mm512_undefined_epi32 (a false positive), hence the -Wno- on that target.
avx512="-mavx512f -mavx512bw -mavx512vl -mavx512dq -mavx512cd -mfma -Wno-maybe-uninitialized"
targets=()
[ "$arm" -eq 1 ] && targets+=("aarch64|16|aarch64-linux-gnu-g++||-march=armv8-a|-static")
if [ "$native" -eq 1 ]; then
  targets+=("x86-sse2|16|g++|||"
            "x86-avx2|32|g++|avx2 fma|-mavx2 -mfma|"
            "x86-avx512|64|g++|avx512f avx512bw avx512vl avx512dq avx512cd fma|$avx512|")
fi
cpu_flags=" $(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null | cut -d: -f2) "
jobs="$(nproc)"

status=0
passed=0; failed=0; notrun=0
for target in "${targets[@]}"; do
  IFS='|' read -r name width cxx needs isaflags ldflags <<<"$target"
  dir="$out/$name"
  mkdir -p "$dir"
  # Rewritten only when it changes: kernels.mk rebuilds everything of this target then.
  printf '%s\n' "$cxx $isaflags $ldflags" >"$dir/flags.new"
  cmp -s "$dir/flags.new" "$dir/flags" && rm "$dir/flags.new" || mv "$dir/flags.new" "$dir/flags"
  echo "[arm_check] $name: building ${#tests[@]} test(s) with $cxx $isaflags $ldflags"
  if ! nice -n 10 make -s -j "$jobs" -f "$here/scripts/arm_check/kernels.mk" SRC="$src" OUT="$dir" \
         CXX="$cxx" ISAFLAGS="$isaflags" LDFLAGS_EXTRA="$ldflags" EXPECT="$width"; then
    echo "[arm_check] $name: BUILD FAILED"
    status=1; failed=$((failed + ${#tests[@]}))
    continue
  fi
  runner=()
  [ "$name" = aarch64 ] && runner=(qemu-aarch64-static)
  lacking=""
  for f in $needs; do
    [[ "$cpu_flags" == *" $f "* ]] || lacking+=" $f"
  done
  for t in "${tests[@]}"; do
    bin="$dir/$(basename "$t" .cpp)"
    if [ -n "$lacking" ]; then
      echo "[arm_check] $name: $(basename "$bin") built, not run: this CPU lacks$lacking"
      notrun=$((notrun + 1))
      continue
    fi
    if timeout 300 "${runner[@]}" "$bin" 2>&1 | sed "s/^/  [$name] /"; [ "${PIPESTATUS[0]}" -eq 0 ]; then
      passed=$((passed + 1))
    else
      echo "[arm_check] $name: $(basename "$bin") FAILED"
      status=1; failed=$((failed + 1))
    fi
  done
done

echo "[arm_check] $passed passed, $failed failed, $notrun built but not run (CPU lacks the ISA)"
exit $status
