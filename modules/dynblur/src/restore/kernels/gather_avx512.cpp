/* The kernels in AVX-512 (F, CD, VL, BW, DQ: OpenCV's "SKX" level), built with those -m flags on
   x86-64 (CMakeLists.txt); the macros are set here for the reason gather_avx2.cpp gives. */
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && \
    defined(__AVX512CD__) && defined(__FMA__) && defined(__F16C__)
#include <immintrin.h>
#define CV_CPU_DISPATCH_MODE AVX512_SKX
#define CV_SSE3 1
#define CV_SSSE3 1
#define CV_SSE4_1 1
#define CV_SSE4_2 1
#define CV_POPCNT 1
#define CV_AVX 1
#define CV_FP16 1
#define CV_AVX2 1
#define CV_FMA3 1
#define CV_AVX_512F 1
#define CV_AVX512_COMMON 1
#define CV_AVX_512CD 1
#define CV_AVX512_SKX 1
#define CV_AVX_512VL 1
#define CV_AVX_512BW 1
#define CV_AVX_512DQ 1
#define DYNBLUR_KERNELS_ISA avx512
// GCC 12 warns inside its own _mm512_slli_epi32 (v_shl), which starts from _mm512_undefined_epi32.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "restore/kernels/gather_simd.hpp"
#else
#include "restore/kernels/gather_kernels.hpp"
#endif

namespace cv {
namespace dynblur {
namespace kernels {

const GatherKernels* avx512GatherKernels()
{
#ifdef DYNBLUR_KERNELS_ISA
    static const GatherKernels kernels = avx512::table("avx512");
    return &kernels;
#else
    return nullptr;
#endif
}

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv
