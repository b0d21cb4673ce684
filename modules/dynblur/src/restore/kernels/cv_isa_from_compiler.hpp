// SPDX-License-Identifier: Apache-2.0
/* Included before any OpenCV header by the library's per-instruction-set kernel files
   (kernels_avx2.cpp, kernels_avx512.cpp) and force-included (-include) by scripts/arm_check.sh into
   every kernel test it builds. Outside OpenCV's own build (__OPENCV_BUILD undefined), opencv2/core/cv_cpu_dispatch.h
   sets only CV_SSE2 (from __SSE2__), CV_NEON (from __ARM_NEON on AArch64) and CV_FP16 (from
   __F16C__); every other CV_<ISA> macro defaults to 0 whatever -m flags the compiler got. So -mavx2
   alone still gives 128-bit SSE universal intrinsics, v_fma stays a multiply then an add without
   CV_FMA3, and the 256/512-bit paths (intrin_avx.hpp, intrin_avx512.hpp) are never included. This
   maps the compiler's own macros onto OpenCV's, as OpenCV's build does with CV_CPU_COMPILE_*, so that
   a kernel compiled with -mavx2 -mfma gets v_float32 = v_float32x8 with _mm256_fmadd_ps, and one
   compiled with -mavx512f/bw/vl/dq/cd gets v_float32x16. AArch64 needs nothing from here: NEON is
   part of the base ISA, GCC defines __ARM_NEON, and OpenCV's compatibility branch turns that into
   CV_NEON (CV_SIMD128, 4 float lanes). */
#ifndef OPENCV_DYNBLUR_RESTORE_KERNELS_CV_ISA_FROM_COMPILER_HPP
#define OPENCV_DYNBLUR_RESTORE_KERNELS_CV_ISA_FROM_COMPILER_HPP

#if defined(__x86_64__) || defined(__i386__)
#  if defined(__AVX__)
#    include <immintrin.h>  /* cv_cpu_dispatch.h's compatibility branch includes only <emmintrin.h> */
#  elif defined(__SSE4_1__)
#    include <smmintrin.h>
#  elif defined(__SSSE3__)
#    include <tmmintrin.h>
#  endif
#  if defined(__SSE3__)
#    define CV_SSE3 1
#  endif
#  if defined(__SSSE3__)
#    define CV_SSSE3 1
#  endif
#  if defined(__SSE4_1__)
#    define CV_SSE4_1 1
#  endif
#  if defined(__SSE4_2__)
#    define CV_SSE4_2 1
#  endif
#  if defined(__AVX__)
#    define CV_AVX 1
#  endif
#  if defined(__FMA__)
#    define CV_FMA3 1
#  endif
#  if defined(__AVX2__)
#    define CV_AVX2 1
#  endif
#  if defined(__AVX512F__)
#    define CV_AVX_512F 1
#  endif
#  if defined(__AVX512F__) && defined(__AVX512CD__)
#    define CV_AVX512_COMMON 1
#    define CV_AVX_512CD 1
#  endif
/* OpenCV's SKX group (the one intrin_avx512.hpp is written for) is F+CD+BW+DQ+VL. */
#  if defined(__AVX512F__) && defined(__AVX512CD__) && defined(__AVX512BW__) && defined(__AVX512DQ__) \
      && defined(__AVX512VL__) && defined(__AVX2__)
#    define CV_AVX512_SKX 1
#    define CV_AVX_512BW 1
#    define CV_AVX_512DQ 1
#    define CV_AVX_512VL 1
#  endif
#endif

#endif
