// SPDX-License-Identifier: Apache-2.0
// The gather kernels of the instruction set this file is compiled for (scripts/arm_check.sh: AArch64
// under qemu, and each x86 flag set) against their reference; exits non-zero on a mismatch.
#define DYNBLUR_KERNELS_ISA checked
#include "restore/kernels/gather_simd.hpp"
#include "kernel_check.hpp"

int main()
{
    const cv::dynblur::kernels::KernelTable kernels = cv::dynblur::kernels::checked::table();
    return cv::dynblur::kernels::check::checkKernels(kernels, "this build") ? 0 : 1;
}
