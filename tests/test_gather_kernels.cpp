// The gather kernels of every instruction set this CPU runs against their plain C++ reference, and
// the dispatch that picks them (cv::setUseOptimized(false) selects the reference).
#include "test_common.hpp"

#include "restore/kernels/gather_kernels.hpp"
#include "restore/kernels/test/gather_check.hpp"

#include <opencv2/core/utility.hpp>

namespace {

using namespace cv::dynblur::kernels;

TEST(GatherKernels, EveryInstructionSetAgreesWithTheReference)
{
    const std::vector<KernelIsa> isas = availableKernelIsas();
    ASSERT_GE(isas.size(), 2u) << "at least the reference and the baseline build";
    EXPECT_EQ(isas.front(), KERNELS_REFERENCE);
    for (KernelIsa isa : isas)
    {
        SCOPED_TRACE(kernelIsaName(isa));
        const GatherKernels* kernels = gatherKernelsFor(isa);
        ASSERT_NE(kernels, nullptr);
        EXPECT_TRUE(check::checkGatherKernels(*kernels, kernelIsaName(isa)));
    }
}

TEST(GatherKernels, DispatchFollowsUseOptimizedAndTheOverride)
{
    const std::vector<KernelIsa> isas = availableKernelIsas();
    const GatherKernels& best = gatherKernels();
    EXPECT_EQ(&best, gatherKernelsFor(isas.back())) << "the CPU's best: " << kernelIsaName(isas.back());
    const bool optimized = cv::useOptimized();
    cv::setUseOptimized(false);
    EXPECT_EQ(&gatherKernels(), gatherKernelsFor(KERNELS_REFERENCE));
    cv::setUseOptimized(optimized);
    for (KernelIsa isa : isas)
    {
        forceKernelIsa(isa);
        EXPECT_EQ(&gatherKernels(), gatherKernelsFor(isa)) << kernelIsaName(isa);
    }
    forceKernelIsa(KERNELS_ISA_COUNT);
    EXPECT_EQ(&gatherKernels(), &best);
    // An instruction set this build or CPU lacks is refused, not run.
    for (int isa = KERNELS_REFERENCE; isa < KERNELS_ISA_COUNT; isa++)
    {
        if (!gatherKernelsFor(KernelIsa(isa)))
        {
            EXPECT_THROW(forceKernelIsa(KernelIsa(isa)), cv::Exception) << kernelIsaName(KernelIsa(isa));
        }
    }
}

}  // namespace
