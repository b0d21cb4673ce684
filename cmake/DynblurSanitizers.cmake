# SPDX-License-Identifier: Apache-2.0
# Sanitizer and fuzzing builds (docs/reliability.md). Included by the top-level CMakeLists.txt after the
# dependencies are found, before any target is defined, so every target of the tree gets the flags.
#
#   DYNBLUR_SANITIZE=ON   AddressSanitizer + UndefinedBehaviorSanitizer for the library, the samples
#                         and the tests (scripts/sanitize.sh, build-asan/). A report aborts the
#                         program (-fno-sanitize-recover=all), so it fails the test that ran it.
#   DYNBLUR_BUILD_FUZZ=ON the libFuzzer targets of fuzz/ (scripts/fuzz.sh, build-fuzz/, clang only):
#                         everything is compiled with ASan + UBSan and libFuzzer's coverage
#                         instrumentation; the fuzz programs link libFuzzer's main.
#
# Debian's OpenCV, ViSP, FFTW, SUNDIALS and libmodbus are not instrumented. ASan still sees every
# heap block they allocate (its allocator replaces malloc) and UBSan checks only our code, so the
# reports are about this project; see sanitizer/lsan.supp for what is suppressed and why.

option(DYNBLUR_SANITIZE "Build with AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)" OFF)
option(DYNBLUR_BUILD_FUZZ "Build the libFuzzer targets in fuzz/ (clang; implies ASan + UBSan)" OFF)

if(NOT DYNBLUR_SANITIZE AND NOT DYNBLUR_BUILD_FUZZ)
  return()
endif()

if(DYNBLUR_BUILD_FUZZ AND NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "DYNBLUR_BUILD_FUZZ needs clang (libFuzzer): configure with "
                      "-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ (scripts/fuzz.sh does)")
endif()

# -g1: line tables, enough for symbolised stack traces at a fraction of -g's build time.
set(DYNBLUR_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all
                            -fno-omit-frame-pointer -g1)
if(DYNBLUR_BUILD_FUZZ)
  # Coverage counters everywhere; only the fuzz programs link libFuzzer itself (fuzz/CMakeLists.txt).
  list(APPEND DYNBLUR_SANITIZER_FLAGS -fsanitize=fuzzer-no-link)
endif()
add_compile_options(${DYNBLUR_SANITIZER_FLAGS})
add_link_options(-fsanitize=address,undefined)

if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  # ViSP's config adds -fopenmp to the global flags; with clang that needs LLVM's libomp, which is
  # not installed. No source of this project uses OpenMP (ViSP's own libraries keep their libgomp).
  string(REPLACE "-fopenmp" "" CMAKE_CXX_FLAGS "${CMAKE_CXX_FLAGS}")
endif()

# Nothing here is for speed: no benchmarks, no Python extension.
set(DYNBLUR_BUILD_PERF OFF CACHE BOOL "" FORCE)
set(DYNBLUR_BUILD_PYTHON OFF CACHE BOOL "" FORCE)
