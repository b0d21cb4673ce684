// SPDX-License-Identifier: Apache-2.0
/* The kernels in AVX2 and FMA, built with -mavx2 -mfma on x86-64 (CMakeLists.txt). Outside
   OpenCV's own build its headers take no more than SSE2 from the compiler, so
   cv_isa_from_compiler.hpp sets the instruction set's macros first; CV_CPU_DISPATCH_MODE puts
   OpenCV's 256-bit intrinsics in a namespace of their own, apart from the baseline's. */
#if defined(__AVX2__) && defined(__FMA__)
#include "restore/kernels/cv_isa_from_compiler.hpp"
#define CV_CPU_DISPATCH_MODE AVX2
#define DYNBLUR_KERNELS_ISA avx2
#include "restore/kernels/gather_simd.hpp"
#else
#include "restore/kernels/kernel_table.hpp"
#endif

namespace cv {
namespace dynblur {
namespace kernels {

const KernelTable* avx2Kernels()
{
#ifdef DYNBLUR_KERNELS_ISA
    static const KernelTable kernels = avx2::table();
    return &kernels;
#else
    return nullptr;
#endif
}

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv
