#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Install check: installs the already-built build folder into a temporary prefix and builds the
# out-of-tree application tests/install/ against it twice, with find_package(dynblur)
# (CMAKE_PREFIX_PATH) and with pkg-config (PKG_CONFIG_PATH), then runs both programs. Fails if a
# file of the package is missing, if either build or run fails, if the consumers resolve the library
# anywhere but the prefix, or if a private dependency of the library (SUNDIALS, FFTW, ViSP, libmodbus)
# reaches their link line. The prefix and the consumer builds are removed after a pass and kept
# after a failure. Called by run_tests.sh after CTest.
#
#   DYNBLUR_BUILD_DIR  the built folder to install (default build/)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${DYNBLUR_BUILD_DIR:-$here/build}"
work="$build/install-check"
prefix="$work/prefix"

fail() {
  echo "[install] FAIL: $*" >&2
  [ -d "$work" ] && echo "[install] kept for inspection: $work" >&2
  exit 1
}

[ -f "$build/CMakeCache.txt" ] || fail "$build is not a configured build folder (run scripts/setup.sh)"
rm -rf "$work"
mkdir -p "$work"

echo "[install] cmake --install $build --prefix $prefix"
cmake --install "$build" --prefix "$prefix" >"$work/install.log" 2>&1 || { cat "$work/install.log"; fail "cmake --install"; }
for f in include/opencv2/dynblur.hpp include/opencv2/dynblur/deblurrer.hpp lib/libopencv_dynblur.so \
         lib/cmake/dynblur/dynblurConfig.cmake lib/cmake/dynblur/dynblurConfigVersion.cmake \
         lib/cmake/dynblur/dynblurTargets.cmake lib/pkgconfig/dynblur.pc; do
  [ -e "$prefix/$f" ] || fail "the install tree has no $f"
done
echo "[install] installed $(find "$prefix" -type f | wc -l) files; soname $(readelf -d "$prefix/lib/libopencv_dynblur.so" | sed -n 's/.*SONAME.*\[\(.*\)\]/\1/p')"

# A consumer must link the library and OpenCV, nothing that the library keeps private.
private='sundials|fftw|visp|modbus|eigen'
check_consumer() {  # <program>: runs it; its libopencv_dynblur is the prefix's, its NEEDED list clean
  local program="$1" needed resolved
  needed="$(readelf -d "$program" | sed -n 's/.*NEEDED.*\[\(.*\)\]/\1/p')"
  if grep -iqE "$private" <<<"$needed"; then
    fail "$program links private dependencies of the library directly: $(grep -iE "$private" <<<"$needed" | tr '\n' ' ')"
  fi
  resolved="$(ldd "$program" | sed -n 's/.*libopencv_dynblur\.so[^ ]* => \([^ ]*\).*/\1/p')"
  case "$resolved" in
    "$prefix"/*) ;;
    *) fail "$program loads libopencv_dynblur from '$resolved', not from $prefix/lib" ;;
  esac
  "$program" || fail "$program exited with status $?"
}

echo "[install] consumer with find_package(dynblur) (CMAKE_PREFIX_PATH=$prefix)"
{ cmake -S "$here/tests/install" -B "$work/cmake" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_PREFIX_PATH="$prefix" && cmake --build "$work/cmake"; } >"$work/cmake.log" 2>&1 \
  || { cat "$work/cmake.log"; fail "building tests/install with find_package(dynblur)"; }
check_consumer "$work/cmake/dynblur_consumer"

echo "[install] consumer with pkg-config (PKG_CONFIG_PATH=$prefix/lib/pkgconfig)"
flags="$(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs dynblur)" \
  || fail "pkg-config --cflags --libs dynblur"
grep -iqE "$private" <<<"$flags" && fail "dynblur.pc names private dependencies: $flags"
# shellcheck disable=SC2086  # the flags are words
# No -rpath and no LD_LIBRARY_PATH here: dynblur.pc's own rpath must find the library.
"${CXX:-c++}" -O2 "$here/tests/install/main.cpp" -o "$work/dynblur_consumer_pc" $flags \
  2>&1 || fail "compiling tests/install/main.cpp with pkg-config's flags"
check_consumer "$work/dynblur_consumer_pc"

rm -rf "$work"
echo "[install] PASS"
