// SPDX-License-Identifier: Apache-2.0
// The one place that chooses the gather kernels.
#include "restore/kernels/kernel_table.hpp"
#include "restore/kernels/gather_reference.hpp"

#include <opencv2/core/utility.hpp>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <string>

namespace cv {
namespace dynblur {
namespace kernels {

namespace {

const KernelTable* referenceKernels()
{
    static const KernelTable kernels{
        reference::gatherRow, reference::gatherPair, reference::gatherPackedPair,
        [](const float* sums, const GatherFold& fold, int begin, int end, float* out) {
            foldColumns(sums, fold, begin, end, out);
        },
        reference::updateRow};
    return &kernels;
}

//! forceKernelIsa's choice; KERNELS_ISA_COUNT: none.
std::atomic<int> forcedIsa{KERNELS_ISA_COUNT};

/* The CPU's support, as OpenCV reads it (instruction and operating-system support: the AVX-512
   registers' state saved on context switches), for the instruction sets the build has kernels for. */
bool cpuRuns(KernelIsa isa)
{
    switch (isa)
    {
    case KERNELS_AVX2: return checkHardwareSupport(CV_CPU_AVX2) && checkHardwareSupport(CV_CPU_FMA3);
    case KERNELS_AVX512:
    case KERNELS_AVX512_BF16: return checkHardwareSupport(CV_CPU_AVX512_SKX);
    default: return true;
    }
}

}  // namespace

const KernelTable* kernelTableFor(KernelIsa isa)
{
    if (!cpuRuns(isa))
        return nullptr;
    switch (isa)
    {
    case KERNELS_REFERENCE: return referenceKernels();
    case KERNELS_BASELINE: return baselineKernels();
    case KERNELS_AVX2: return avx2Kernels();
    case KERNELS_AVX512: return avx512Kernels();
    case KERNELS_AVX512_BF16: return avx512Bf16Kernels();
    default: return nullptr;
    }
}

std::vector<KernelIsa> availableKernelIsas()
{
    std::vector<KernelIsa> isas;
    for (int isa = KERNELS_REFERENCE; isa < KERNELS_ISA_COUNT; isa++)
        if (kernelTableFor(KernelIsa(isa)))
            isas.push_back(KernelIsa(isa));
    return isas;
}

void forceKernelIsa(KernelIsa isa)
{
    CV_Assert(isa == KERNELS_ISA_COUNT || kernelTableFor(isa));
    forcedIsa = isa;
}

const char* kernelIsaName(KernelIsa isa)
{
    static const char* const names[] = {"reference", "baseline", "avx2", "avx512", "avx512bf16"};
    return isa >= KERNELS_REFERENCE && isa < KERNELS_ISA_COUNT ? names[isa] : "none";
}

namespace {

/* The CPU's best kernels, or those the environment variable DYNBLUR_KERNELS names (one of
   kernelIsaName's names): how a whole program, a test run among them, runs on other kernels. */
const KernelTable* defaultKernels()
{
    const std::vector<KernelIsa> isas = availableKernelIsas();
    const char* chosen = std::getenv("DYNBLUR_KERNELS");
    if (!chosen || !*chosen)
        return kernelTableFor(isas.back());
    std::string allowed;
    for (KernelIsa isa : isas)
    {
        if (std::strcmp(chosen, kernelIsaName(isa)) == 0)
            return kernelTableFor(isa);
        allowed += std::string(allowed.empty() ? "" : ", ") + kernelIsaName(isa);
    }
    CV_Error(Error::StsBadArg, format("DYNBLUR_KERNELS='%s': this build and CPU run %s", chosen, allowed.c_str()));
}

}  // namespace

const KernelTable& kernelTable()
{
    static const KernelTable* const best = defaultKernels();
    if (!useOptimized())
        return *referenceKernels();
    const int forced = forcedIsa.load(std::memory_order_relaxed);
    return forced < KERNELS_ISA_COUNT ? *kernelTableFor(KernelIsa(forced)) : *best;
}

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv
