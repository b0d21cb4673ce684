#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Old and new library, alternating in one process: the frame-rate setting's restoration (the frame
# and settings of the frame-rate benchmark, modules/dynblur/perf/perf_baseline.hpp) timed with two
# revisions of libopencv_dynblur in paired rounds, and their restored images compared bitwise.
# Issue #33's speed check ("within 5 %") is the median new/old ratio this prints. Run by hand, on an
# otherwise idle machine; not part of the test command.
#
#   scripts/compare_revisions.sh [--rounds N] OLD_REV [NEW_REV|worktree]
#
# OLD_REV is built in a git worktree under build-compare/src-<commit>/, NEW_REV likewise, or, by
# default, "worktree": this checkout as it is, uncommitted changes included. Each library is built
# the way scripts/setup.sh configures the project (Ninja, Release), only the library target, in
# build-compare/lib-<commit or worktree>/; builds are kept and reused. Then, in build-compare/run/:
#   - each side's library is copied to libopencv_dynblur_<side>.so and given that soname (patchelf):
#     both revisions build the same soname, libopencv_dynblur.so, and the dynamic linker satisfies a
#     DT_NEEDED from any object already loaded under that soname, so without the rename the second
#     shim would silently run the first side's library, RTLD_LOCAL | RTLD_DEEPBIND or not;
#   - modules/dynblur/perf/compare_revisions/shim.cpp is compiled against that revision's public
#     headers into shim_<side>.so, linked to that copy (RUNPATH to it);
#   - compare_revisions/driver.cpp dlopens both shims RTLD_LOCAL | RTLD_DEEPBIND, prints which library
#     file and load address each side runs (and stops if they are the same), gives both the same
#     frame, and runs N paired rounds (default 20), the order alternating each round.
# It prints the median, min and max of the per-round ratio new/old, each side's median time, and
# whether the restored images are bitwise equal (with their max abs difference).
# Clean up with: rm -rf build-compare && git worktree prune
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

usage() {
  cat <<'EOF'
Usage: scripts/compare_revisions.sh [--rounds N] [--setting frame-rate|default] OLD_REV [NEW_REV|worktree]
Times the frame-rate setting's restoration (--setting default: the DynamicDeblurrer as created,
tile-wise float blurs) with the library built at OLD_REV and at NEW_REV (default:
this working tree, uncommitted changes included), both loaded in one process, in N paired rounds
(default 20) whose order alternates; prints the median, min and max of the per-round ratio new/old
and whether the two restored images are bitwise equal. Builds go to build-compare/ and are reused.
Example: scripts/compare_revisions.sh HEAD~5
EOF
}

rounds=20
setting=frame-rate
revs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds) [ $# -ge 2 ] || { usage >&2; exit 2; }; rounds="$2"; shift 2 ;;
    --rounds=*) rounds="${1#--rounds=}"; shift ;;
    --setting) [ $# -ge 2 ] || { usage >&2; exit 2; }; setting="$2"; shift 2 ;;
    --setting=*) setting="${1#--setting=}"; shift ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "compare_revisions: unknown option $1" >&2; usage >&2; exit 2 ;;
    *) revs+=("$1"); shift ;;
  esac
done
if [ ${#revs[@]} -lt 1 ] || [ ${#revs[@]} -gt 2 ]; then
  usage >&2
  exit 2
fi
[ ${#revs[@]} -eq 1 ] && revs+=(worktree)
case "$setting" in
  frame-rate|default) ;;
  *) echo "compare_revisions: --setting must be frame-rate or default, not '$setting'" >&2; exit 2 ;;
esac

# patchelf gives the library copies their own sonames; the rest comes with scripts/setup.sh.
packages=(patchelf build-essential cmake ninja-build libopencv-dev libbenchmark-dev)
"$here/scripts/install_debian_packages.sh" "${packages[@]}"

work="$here/build-compare"
run="$work/run"
mkdir -p "$run"

# Builds the library of revision $1 (a commit-ish or "worktree"); sets lib_src, lib_file and lib_rev.
build_library() {
  local rev="$1" build
  if [ "$rev" = worktree ]; then
    lib_rev=worktree
    lib_src="$here"
    build="$work/lib-worktree"
  else
    lib_rev="$(git -C "$here" rev-parse --verify --quiet "$rev^{commit}")" \
      || { echo "compare_revisions: $rev is not a commit" >&2; exit 2; }
    lib_src="$work/src-${lib_rev:0:12}"
    build="$work/lib-${lib_rev:0:12}"
    if [ ! -e "$lib_src/.git" ]; then
      git -C "$here" worktree prune
      git -C "$here" worktree add --detach --quiet "$lib_src" "$lib_rev"
    fi
  fi
  echo "[compare] building libopencv_dynblur at $rev ($lib_rev) in ${build#"$here"/}"
  cmake -S "$lib_src" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DDYNBLUR_BUILD_TESTS=OFF \
        -DDYNBLUR_BUILD_PERF=OFF -DDYNBLUR_BUILD_SAMPLES=OFF -DDYNBLUR_BUILD_PYTHON=OFF >"$build.configure.log" 2>&1 \
    || { cat "$build.configure.log" >&2; exit 1; }
  nice -n 10 cmake --build "$build" -j "$(nproc)" --target opencv_dynblur >"$build.build.log" 2>&1 \
    || { tail -40 "$build.build.log" >&2; exit 1; }
  lib_file="$(find "$build" -name 'libopencv_dynblur.so' -print -quit)"
  [ -n "$lib_file" ] || { echo "compare_revisions: no libopencv_dynblur.so in $build" >&2; exit 1; }
}

cxx=(nice -n 10 g++ -std=c++17 -O2 -Wall -Wextra)
opencv_cflags="$(pkg-config --cflags opencv4)"
for side in old new; do
  if [ "$side" = old ]; then build_library "${revs[0]}"; else build_library "${revs[1]}"; fi
  copy="$run/libopencv_dynblur_$side.so"
  cp "$lib_file" "$copy"
  patchelf --set-soname "libopencv_dynblur_$side.so" "$copy"
  # The revision's headers first: perf_baseline.hpp (this tree's) includes <opencv2/dynblur.hpp>.
  # shellcheck disable=SC2086
  "${cxx[@]}" -fPIC -shared -DCOMPARE_REVISION="\"$lib_rev\"" \
    -I"$lib_src/modules/dynblur/include" $opencv_cflags \
    "$here/modules/dynblur/perf/compare_revisions/shim.cpp" -o "$run/shim_$side.so" \
    -L"$run" -l"opencv_dynblur_$side" -Wl,-rpath,"$run" -lopencv_core -lopencv_imgproc
done
"${cxx[@]}" "$here/modules/dynblur/perf/compare_revisions/driver.cpp" -o "$run/compare_revisions_driver" -ldl -lbenchmark

echo "[compare] ${revs[0]} (old) vs ${revs[1]} (new), $rounds rounds"
"$run/compare_revisions_driver" "$run/shim_old.so" "$run/shim_new.so" "$rounds" "$setting"
