// SPDX-License-Identifier: Apache-2.0
// The terms the gather kernels sum, and how a gather's sums go into its output: plain structs, no
// OpenCV, so the kernels' test builds for any CPU from the headers alone.
#ifndef OPENCV_DYNBLUR_RESTORE_KERNELS_GATHER_TAPS_HPP
#define OPENCV_DYNBLUR_RESTORE_KERNELS_GATHER_TAPS_HPP

#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace cv {
namespace dynblur {
namespace kernels {

//! One term of a gathered row: out[x] += weight · source(row, x + col).
struct Tap
{
    int row;
    int col;
    float weight;
};

//! One term of two gathered rows at once: out_k[x] += weight[k] · source(row, x + col).
struct PairTap
{
    int row;
    int col;
    float weight[2];
};

/** One term of output rows 2k and 2k + 1 from a packed source (packRowPair's layout): out_k[x] +=
the dot product of the two bfloat16 halves of weight[k] (for source rows 2·pair and 2·pair + 1)
with those of packed(pair, x + col). */
struct PackedTap
{
    int pair;
    int col;
    uint32_t weight[2];
};

/** How a gather's sums go into its output rows: added to what the columns below `split` hold,
written from it on, each first times weight[x] (by output column) where `weight` is given. A tile
operator adds its node columns up this way; the default writes. */
struct GatherFold
{
    const float* weight = nullptr;
    int split = INT_MIN;
    bool writes() const { return weight == nullptr && split == INT_MIN; }
};

//! A float's bfloat16, rounded to nearest, ties to even, in the low 16 bits.
inline uint32_t roundToBfloat16(float v)
{
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return (bits + 0x7fffu + ((bits >> 16) & 1u)) >> 16;
}

//! The bfloat16 in the low half of a packed pair, as a float.
inline float lowBfloat16(uint32_t packed)
{
    const uint32_t bits = packed << 16;
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

//! The bfloat16 in the high half of a packed pair, as a float.
inline float highBfloat16(uint32_t packed)
{
    const uint32_t bits = packed & 0xffff0000u;
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

/** The dot product of two bfloat16 pairs in float, as AVX512-BF16's vdpbf16ps sums it: the high
halves' product added first, then the low halves'. Each product of two bfloat16s is exact in float,
so each step is one fused multiply-add. */
inline float packedDot(uint32_t a, uint32_t b, float sum)
{
    sum = std::fma(highBfloat16(a), highBfloat16(b), sum);
    return std::fma(lowBfloat16(a), lowBfloat16(b), sum);
}

//! out[x] from the sum of column x, as `fold` says (an added column: one rounding, weight · sum + out).
inline void foldColumn(float sum, const GatherFold& fold, int x, float* out)
{
    const bool add = x < fold.split;
    if (fold.weight)
        out[x] = add ? std::fma(fold.weight[x], sum, out[x]) : fold.weight[x] * sum;
    else
        out[x] = add ? sum + out[x] : sum;
}

//! out[x] for x in [begin, end) from sums[x], as `fold` says.
inline void foldColumns(const float* sums, const GatherFold& fold, int begin, int end, float* out)
{
    for (int x = begin; x < end; x++)
        foldColumn(sums[x], fold, x, out);
}

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv

#endif
