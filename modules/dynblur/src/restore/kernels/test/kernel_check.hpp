// What the kernel tests in this folder share: the 1e-6 relative comparison against a reference and its
// verdict line. scripts/arm_check.sh builds each *.cpp here into its own program, for aarch64 under
// qemu and natively for each x86 instruction set, and links scripts/arm_check/simd_probe.cpp into
// it, which checks and prints the vector width.
#ifndef DYNBLUR_KERNELS_TEST_KERNEL_CHECK_HPP
#define DYNBLUR_KERNELS_TEST_KERNEL_CHECK_HPP

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace kernel_check {

/* The largest |got - want| / max(|want|, floor) over n values; `floor` keeps values near zero from
   turning a rounding into a large relative error. */
inline double maxRelativeError(const float* got, const float* want, int n, double floor = 1e-30)
{
    double worst = 0;
    for (int i = 0; i < n; i++)
        worst = std::max(worst, std::fabs(double(got[i]) - double(want[i])) / std::max(std::fabs(double(want[i])), floor));
    return worst;
}

//! Prints one comparison's verdict and returns whether it is within `tolerance`.
inline bool report(const char* what, double error, double tolerance = 1e-6)
{
    const bool ok = error <= tolerance && !std::isnan(error);
    std::printf("  %-40s max relative error %.3g (tolerance %.0e): %s\n", what, error, tolerance, ok ? "ok" : "MISMATCH");
    return ok;
}

}  // namespace kernel_check

#endif
