// SPDX-License-Identifier: Apache-2.0
// The kernels at the build's baseline: SSE2 on x86-64, NEON on AArch64, plain C++ elsewhere.
#define DYNBLUR_KERNELS_ISA baseline
#include "restore/kernels/gather_simd.hpp"

namespace cv {
namespace dynblur {
namespace kernels {

const KernelTable* baselineKernels()
{
    static const KernelTable kernels = baseline::table();
    return &kernels;
}

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv
