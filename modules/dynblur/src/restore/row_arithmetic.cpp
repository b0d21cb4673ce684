// SPDX-License-Identifier: Apache-2.0
#include "restore/row_arithmetic.hpp"

#include "restore/simd_clones.hpp"

namespace cv {
namespace dynblur {
namespace detail {

/* Contiguous, restrict-qualified loops the compiler vectorises, cloned for the CPU's widest vectors
   (simd_clones.hpp). */
DYNBLUR_SIMD_CLONES
void accumulateScaled(float* __restrict dst, const float* __restrict src, float w, int begin, int end)
{
    for (int x = begin; x < end; x++)
        dst[x] += w * src[x];
}

DYNBLUR_SIMD_CLONES
void multiplyInto(float* __restrict dst, const float* __restrict a, const float* __restrict b, int n)
{
    for (int x = 0; x < n; x++)
        dst[x] = a[x] * b[x];
}

DYNBLUR_SIMD_CLONES
void addRow(const float* __restrict p, int n, float* __restrict sum)
{
    for (int x = 0; x < n; x++)
        sum[x] += p[x];
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
