#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Contrib check: builds the module inside OpenCV 4.6's own source tree, as opencv_contrib users build
# extra modules, and runs a program linked to the result.
#
#   1. packages  the Debian packages it needs (scripts/install_debian_packages.sh), dpkg-dev included
#   2. source    Debian's `opencv` source package: deb-src is enabled in the apt sources if no entry
#                has it, then `apt-get source opencv` unpacks it into <cache>/source/ (reused when present)
#   3. configure OpenCV with OPENCV_EXTRA_MODULES_PATH=<checkout>/modules and
#                BUILD_LIST=core,imgproc,imgcodecs,calib3d,video,dynblur; no tests, apps, bindings, GUI or
#                video I/O, and nothing that downloads (IPP, ADE, protobuf)
#   4. build     with Ninja, under nice -n 10 (OpenCV's own modules take most of the time)
#   5. program   scripts/contrib_check/: tests/install/main.cpp found through the build tree's
#                OpenCVConfig.cmake (find_package(OpenCV COMPONENTS dynblur)); it plans a move,
#                renders the blurred frame, restores it and exits non-zero unless PSNR improves
# Exits non-zero, naming the stage and its log, if any stage fails. Not part of run_tests.sh: a
# build from scratch takes about a quarter of an hour on 2 cores (docs/reliability.md).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

usage() {
  cat <<'EOF'
Usage: scripts/contrib_check.sh [--cache DIR] [--opencv-source DIR] [--fresh] [--jobs N] [--no-install] [--help]
Builds OpenCV 4.6 (Debian's source package) with modules/dynblur as an extra module
(BUILD_LIST=core,imgproc,imgcodecs,calib3d,video,dynblur) and runs a program linked to its opencv_dynblur.
  --cache DIR          where the source, the build and the program go (default: build-contrib/)
  --opencv-source DIR  an unpacked OpenCV 4.6 source tree to use instead of `apt-get source opencv`
  --fresh              remove the OpenCV build folder first (the unpacked source is kept)
  --jobs N             parallel build jobs (default: the number of cores)
  --no-install         do not install Debian packages or enable deb-src (fail instead)
EOF
}

cache="$here/build-contrib"; source_dir=""; fresh=0; jobs="$(nproc)"; install=1
while [ $# -gt 0 ]; do
  case "$1" in
    --cache) cache="$(realpath -m "${2:?--cache needs a folder}")"; shift ;;
    --opencv-source) source_dir="$(realpath "${2:?--opencv-source needs a folder}")"; shift ;;
    --fresh) fresh=1 ;;
    --jobs) jobs="${2:?--jobs needs a number}"; shift ;;
    --no-install) install=0 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "contrib_check: unknown argument $1" >&2; usage >&2; exit 2 ;;
  esac
  shift
done

fail() {  # <message> [log]: the failure, the end of its log, and where the whole log is
  echo "[contrib] FAIL: $1" >&2
  if [ -n "${2:-}" ] && [ -f "$2" ]; then
    tail -n 30 "$2" >&2
    echo "[contrib] full log: $2" >&2
  fi
  exit 1
}
elapsed() { printf '%d min %02d s' $(($1 / 60)) $(($1 % 60)); }
# The CPU seconds (user + system) of the finished children of this shell, from a file `times` wrote;
# unlike the wall time, it does not grow when other processes share the cores.
children_cpu() { awk 'NR == 2 { split($1, u, /[ms]/); split($2, s, /[ms]/); printf "%d", u[1] * 60 + u[2] + s[1] * 60 + s[2] }' "$1"; }
sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
mkdir -p "$cache"
start_all=$SECONDS

# 1. packages
packages=(dpkg-dev build-essential cmake ninja-build pkg-config
          libeigen3-dev libsundials-dev libfftw3-dev libvisp-dev libmodbus-dev
          libpng-dev libjpeg-dev zlib1g-dev)  # imgcodecs with the system's codecs: the source package has no 3rdparty/
echo "[contrib] 1/5 packages: ${packages[*]}"
if [ "$install" -eq 1 ]; then
  "$here/scripts/install_debian_packages.sh" "${packages[@]}" || fail "installing Debian packages"
else
  "$here/scripts/install_debian_packages.sh" --check "${packages[@]}" || fail "Debian packages missing (--no-install)"
fi

# 2. source
has_deb_src() {
  grep -qsE '^[[:space:]]*Types:.*deb-src' /etc/apt/sources.list.d/*.sources \
    || grep -qsE '^[[:space:]]*deb-src[[:space:]]' /etc/apt/sources.list /etc/apt/sources.list.d/*.list
}
enable_deb_src() {  # Debian 12 keeps its entries in debian.sources (deb822); older ones in sources.list
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    echo "[contrib] enabling deb-src in /etc/apt/sources.list.d/debian.sources"
    $sudo_cmd sed -i -E 's/^([[:space:]]*Types:[[:space:]]*deb)[[:space:]]*$/\1 deb-src/' /etc/apt/sources.list.d/debian.sources
  elif grep -qsE '^[[:space:]]*deb[[:space:]]' /etc/apt/sources.list; then
    echo "[contrib] adding deb-src lines to /etc/apt/sources.list"
    sed -nE 's/^[[:space:]]*deb([[:space:]])/deb-src\1/p' /etc/apt/sources.list | $sudo_cmd tee -a /etc/apt/sources.list >/dev/null
  fi
  has_deb_src || fail "could not enable deb-src: add a deb-src entry to the apt sources by hand"
  $sudo_cmd apt-get update -qq || fail "apt-get update after enabling deb-src"
}
if [ -z "$source_dir" ]; then
  source_dir="$(find "$cache/source" -mindepth 1 -maxdepth 1 -type d -name 'opencv-4.6*' 2>/dev/null | head -n 1 || true)"
  if [ -n "$source_dir" ] && [ -f "$source_dir/CMakeLists.txt" ]; then
    echo "[contrib] 2/5 source: reusing $source_dir"
  else
    echo "[contrib] 2/5 source: apt-get source opencv into $cache/source"
    if ! has_deb_src; then
      [ "$install" -eq 1 ] || fail "no deb-src entry in the apt sources (--no-install)"
      enable_deb_src
    fi
    rm -rf "$cache/source"
    mkdir -p "$cache/source"
    (cd "$cache/source" && apt-get source -qq opencv) >"$cache/source.log" 2>&1 \
      || fail "apt-get source opencv" "$cache/source.log"
    source_dir="$(find "$cache/source" -mindepth 1 -maxdepth 1 -type d -name 'opencv-*' | head -n 1)"
  fi
else
  echo "[contrib] 2/5 source: $source_dir (given)"
fi
version_hpp="$source_dir/modules/core/include/opencv2/core/version.hpp"
[ -f "$version_hpp" ] || fail "$source_dir is not an OpenCV source tree (no $version_hpp)"
version="$(sed -nE 's/^#define CV_VERSION_(MAJOR|MINOR|REVISION)[[:space:]]+([0-9]+).*/\2/p' "$version_hpp" | paste -sd.)"
[[ "$version" == 4.6.* ]] || fail "$source_dir is OpenCV $version, not 4.6"

# 3. configure
build="$cache/opencv-build"
[ "$fresh" -eq 1 ] && rm -rf "$build"
echo "[contrib] 3/5 configure: OpenCV $version in $build, BUILD_LIST=core,imgproc,imgcodecs,calib3d,video,dynblur"
start=$SECONDS
off=(BUILD_TESTS BUILD_PERF_TESTS BUILD_EXAMPLES BUILD_DOCS BUILD_opencv_apps BUILD_JAVA BUILD_opencv_python2
     BUILD_opencv_python3 BUILD_opencv_gapi BUILD_PROTOBUF BUILD_ZLIB BUILD_JPEG BUILD_PNG BUILD_TIFF BUILD_WEBP
     BUILD_OPENJPEG BUILD_JASPER BUILD_OPENEXR BUILD_IPP_IW BUILD_ITT
     WITH_IPP WITH_ADE WITH_PROTOBUF WITH_ITT WITH_OPENCL WITH_CUDA WITH_VA WITH_VA_INTEL WITH_TBB WITH_OPENMP
     WITH_LAPACK WITH_FFMPEG WITH_GSTREAMER WITH_V4L WITH_1394 WITH_GTK WITH_QT WITH_OPENGL WITH_VTK WITH_GDAL
     WITH_GDCM WITH_TIFF WITH_WEBP WITH_OPENJPEG WITH_JASPER WITH_OPENEXR WITH_QUIRC WITH_IMGCODEC_HDR
     WITH_IMGCODEC_SUNRASTER WITH_IMGCODEC_PFM WITH_CAROTENE ENABLE_PRECOMPILED_HEADERS)
args=(-G Ninja -DCMAKE_BUILD_TYPE=Release
      "-DOPENCV_EXTRA_MODULES_PATH=$here/modules" -DBUILD_LIST=core,imgproc,imgcodecs,calib3d,video,dynblur
      -DOPENCV_DOWNLOAD_TRIES_LIST= -DWITH_PNG=ON -DWITH_JPEG=ON -DWITH_EIGEN=ON)
for option in "${off[@]}"; do args+=("-D$option=OFF"); done
cmake -S "$source_dir" -B "$build" "${args[@]}" >"$cache/configure.log" 2>&1 \
  || fail "configuring OpenCV with the module" "$cache/configure.log"
grep -qE 'To be built:.*[[:space:]]dynblur([[:space:]]|$)' "$cache/configure.log" \
  || fail "OpenCV's configuration does not list dynblur among the modules to be built" "$cache/configure.log"
echo "[contrib]   configured in $(elapsed $((SECONDS - start)))"

# 4. build
echo "[contrib] 4/5 build: ninja -j $jobs (nice -n 10); log $cache/build.log"
start=$SECONDS
times >"$cache/times.before"  # in this shell: a subshell's `times` would not see the build
nice -n 10 cmake --build "$build" -j "$jobs" >"$cache/build.log" 2>&1 \
  || fail "building OpenCV with the module" "$cache/build.log"
times >"$cache/times.after"
cpu=$(( $(children_cpu "$cache/times.after") - $(children_cpu "$cache/times.before") ))
library="$(find "$build/lib" -maxdepth 1 -name 'libopencv_dynblur.so.*' -type f 2>/dev/null | head -n 1 || true)"
[ -n "$library" ] || fail "the build made no libopencv_dynblur.so" "$cache/build.log"
echo "[contrib]   built in $(elapsed $((SECONDS - start))), CPU time $(elapsed "$cpu"): $library"

# 5. program
echo "[contrib] 5/5 program: scripts/contrib_check/ with OpenCV_DIR=$build"
program_build="$cache/program"
start=$SECONDS
{ cmake -S "$here/scripts/contrib_check" -B "$program_build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DOpenCV_DIR="$build" && cmake --build "$program_build"; } >"$cache/program.log" 2>&1 \
  || fail "building the program against the OpenCV build tree" "$cache/program.log"
program="$program_build/dynblur_contrib_consumer"
resolved="$(ldd "$program" | sed -n 's/.*libopencv_dynblur\.so[^ ]* => \([^ ]*\).*/\1/p' || true)"
case "$resolved" in
  "$build"/*) ;;
  *) fail "$program loads libopencv_dynblur from '$resolved', not from $build/lib" ;;
esac
"$program" || fail "$program exited with status $?"
echo "[contrib]   program built and run in $(elapsed $((SECONDS - start)))"
echo "[contrib] PASS in $(elapsed $((SECONDS - start_all)))"
