// SPDX-License-Identifier: Apache-2.0
/* The kernels in AVX-512 (F, CD, VL, BW, DQ: OpenCV's "SKX" level) and FMA, built with those -m
   flags on x86-64 (CMakeLists.txt), for the reason kernels_avx2.cpp gives. */
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && \
    defined(__AVX512CD__) && defined(__FMA__)
#include "restore/kernels/cv_isa_from_compiler.hpp"
#define CV_CPU_DISPATCH_MODE AVX512_SKX
#define DYNBLUR_KERNELS_ISA avx512
// GCC 12 warns inside its own _mm512_slli_epi32 (v_shl), which starts from _mm512_undefined_epi32.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "restore/kernels/gather_simd.hpp"
#else
#include "restore/kernels/kernel_table.hpp"
#endif

namespace cv {
namespace dynblur {
namespace kernels {

const KernelTable* avx512Kernels()
{
#ifdef DYNBLUR_KERNELS_ISA
    static const KernelTable kernels = avx512::table();
    return &kernels;
#else
    return nullptr;
#endif
}

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv
