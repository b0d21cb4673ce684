/* The kernels in AVX2 and FMA: built with -mavx2 -mfma -mf16c -mpopcnt on x86-64 (CMakeLists.txt).
   Outside OpenCV's own build its headers enable no more than SSE2 (cv_cpu_dispatch.h), so the
   instruction set's macros are set here, before any OpenCV header; CV_CPU_DISPATCH_MODE puts
   OpenCV's 256-bit intrinsics in a namespace of their own, apart from the baseline's. */
#if defined(__AVX2__) && defined(__FMA__) && defined(__F16C__)
#include <immintrin.h>
#define CV_CPU_DISPATCH_MODE AVX2
#define CV_SSE3 1
#define CV_SSSE3 1
#define CV_SSE4_1 1
#define CV_SSE4_2 1
#define CV_POPCNT 1
#define CV_AVX 1
#define CV_FP16 1
#define CV_AVX2 1
#define CV_FMA3 1
#define DYNBLUR_KERNELS_ISA avx2
#include "restore/kernels/gather_simd.hpp"
#else
#include "restore/kernels/gather_kernels.hpp"
#endif

namespace cv {
namespace dynblur {
namespace kernels {

const GatherKernels* avx2GatherKernels()
{
#ifdef DYNBLUR_KERNELS_ISA
    static const GatherKernels kernels = avx2::table("avx2");
    return &kernels;
#else
    return nullptr;
#endif
}

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv
