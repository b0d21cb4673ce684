// SPDX-License-Identifier: Apache-2.0
// The gather kernels of every instruction set this CPU runs against their plain C++ reference, and
// the dispatch that picks them (cv::setUseOptimized(false) selects the reference).
#include "test_common.hpp"

#include "restore/kernels/kernel_table.hpp"
#include "kernel_check.hpp"

#include <opencv2/core/utility.hpp>

namespace {

using namespace cv::dynblur::kernels;

TEST(KernelTable, EveryInstructionSetAgreesWithTheReference)
{
    const std::vector<KernelIsa> isas = availableKernelIsas();
    ASSERT_GE(isas.size(), 2u) << "at least the reference and the baseline build";
    EXPECT_EQ(isas.front(), KERNELS_REFERENCE);
    for (KernelIsa isa : isas)
    {
        SCOPED_TRACE(kernelIsaName(isa));
        const KernelTable* kernels = kernelTableFor(isa);
        ASSERT_NE(kernels, nullptr);
        EXPECT_TRUE(check::checkKernels(*kernels, kernelIsaName(isa)));
    }
}

TEST(KernelTable, DispatchFollowsUseOptimizedAndTheOverride)
{
    const std::vector<KernelIsa> isas = availableKernelIsas();
    const KernelTable& best = kernelTable();
    EXPECT_EQ(&best, kernelTableFor(isas.back())) << "the CPU's best: " << kernelIsaName(isas.back());
    const bool optimized = cv::useOptimized();
    cv::setUseOptimized(false);
    EXPECT_EQ(&kernelTable(), kernelTableFor(KERNELS_REFERENCE));
    cv::setUseOptimized(optimized);
    for (KernelIsa isa : isas)
    {
        forceKernelIsa(isa);
        EXPECT_EQ(&kernelTable(), kernelTableFor(isa)) << kernelIsaName(isa);
    }
    forceKernelIsa(KERNELS_ISA_COUNT);
    EXPECT_EQ(&kernelTable(), &best);
    // An instruction set this build or CPU lacks is refused, not run.
    for (int isa = KERNELS_REFERENCE; isa < KERNELS_ISA_COUNT; isa++)
    {
        if (!kernelTableFor(KernelIsa(isa)))
        {
            EXPECT_THROW(forceKernelIsa(KernelIsa(isa)), cv::Exception) << kernelIsaName(KernelIsa(isa));
        }
    }
}

}  // namespace
