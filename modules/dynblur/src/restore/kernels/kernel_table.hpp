// SPDX-License-Identifier: Apache-2.0
// The restoration kernels (the gathers of the bank operators and the RL update of a row), one table
// per instruction set, chosen per call from the CPU, cv::useOptimized() and the tests' override.
#ifndef OPENCV_DYNBLUR_RESTORE_KERNELS_KERNEL_TABLE_HPP
#define OPENCV_DYNBLUR_RESTORE_KERNELS_KERNEL_TABLE_HPP

#include "restore/kernels/gather_taps.hpp"
#include "restore/kernels/update_terms.hpp"

#include <opencv2/core/cvdef.h>

#include <vector>

namespace cv {
namespace dynblur {
namespace kernels {

//! One instruction set's kernels (gather_reference.hpp and update_terms.hpp say what each computes).
struct KernelTable
{
    //! out[x] = Σ_t w_t · source(row_t, x + col_t) for x in [begin, end); every read inside.
    void (*row)(float* out, const float* source, size_t sourceStep, const Tap* taps, int tapCount, int begin,
                int end);
    //! Two rows at once, folded into out0 and out1 as `fold` says.
    void (*pair)(float* out0, float* out1, const float* source, size_t sourceStep, const PairTap* taps,
                 int tapCount, int begin, int end, const GatherFold& fold);
    //! Two rows at once from packed bfloat16 row pairs, folded likewise.
    void (*packedPair)(float* out0, float* out1, const uint32_t* source, size_t sourceStep, const PackedTap* taps,
                       int tapCount, int begin, int end, const GatherFold& fold);
    //! out[x] from sums[x] for x in [begin, end), as `fold` says.
    void (*fold)(const float* sums, const GatherFold& fold, int begin, int end, float* out);
    //! Richardson–Lucy's update of one row (update_terms.hpp), its step's sums added to `sums`.
    void (*updateRow)(const UpdateRow& row, UpdateSums& sums);
};

//! The instruction sets the kernels are built for, slowest first.
enum KernelIsa
{
    KERNELS_REFERENCE = 0,  //!< plain C++ (cv::setUseOptimized(false))
    KERNELS_BASELINE,       //!< universal intrinsics at the build's baseline: SSE2 on x86-64, NEON on AArch64
    KERNELS_AVX2,           //!< universal intrinsics, AVX2 and FMA
    KERNELS_AVX512,         //!< universal intrinsics, AVX-512 (F, BW, VL, DQ)
    KERNELS_AVX512_BF16,    //!< KERNELS_AVX512 with the packed gather in AVX512-BF16's vdpbf16ps
    KERNELS_ISA_COUNT
};

/** The kernels to run now: the reference ones when !cv::useOptimized(), else forceKernelIsa's, else
those the environment variable DYNBLUR_KERNELS names (reference, baseline, avx2, avx512 or
avx512bf16; one this build and CPU run, or an error that lists them), else the CPU's best. */
const KernelTable& kernelTable();

//! The kernels built for `isa`, or null when this build or this CPU has none.
const KernelTable* kernelTableFor(KernelIsa isa);

//! Every instruction set this build and this CPU can run, slowest first.
CV_EXPORTS std::vector<KernelIsa> availableKernelIsas();

//! For tests: kernelTable() returns `isa`'s kernels (one of availableKernelIsas()); KERNELS_ISA_COUNT: the CPU's best again.
CV_EXPORTS void forceKernelIsa(KernelIsa isa);

//! The name of an instruction set's kernels, e.g. "avx2".
CV_EXPORTS const char* kernelIsaName(KernelIsa isa);

// Each instruction set's table, defined in its own file (null where the build has none).
const KernelTable* baselineKernels();
const KernelTable* avx2Kernels();
const KernelTable* avx512Kernels();
const KernelTable* avx512Bf16Kernels();

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv

#endif
