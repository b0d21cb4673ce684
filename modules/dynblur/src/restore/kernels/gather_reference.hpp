// SPDX-License-Identifier: Apache-2.0
// The gather kernels in plain C++: what every vector kernel is held to (tests), what runs with
// cv::setUseOptimized(false), and the columns a vector kernel leaves over.
#ifndef OPENCV_DYNBLUR_RESTORE_KERNELS_GATHER_REFERENCE_HPP
#define OPENCV_DYNBLUR_RESTORE_KERNELS_GATHER_REFERENCE_HPP

#include "restore/kernels/gather_taps.hpp"

namespace cv {
namespace dynblur {
namespace kernels {
namespace reference {

/** out[x] = Σ_t w_t · source(row_t, x + col_t) for x in [begin, end), the taps summed in order, one
fused multiply-add each. Every read lies inside `source` (sourceStep floats per row). */
inline void gatherRow(float* out, const float* source, size_t sourceStep, const Tap* taps, int tapCount, int begin,
                      int end)
{
    for (int x = begin; x < end; x++)
    {
        float s = 0.f;
        for (int t = 0; t < tapCount; t++)
            s = std::fma(taps[t].weight, source[size_t(taps[t].row) * sourceStep + size_t(taps[t].col + x)], s);
        out[x] = s;
    }
}

//! out0[x], out1[x] = Σ_t w_t[k] · source(row_t, x + col_t), folded into them as `fold` says.
inline void gatherPair(float* out0, float* out1, const float* source, size_t sourceStep, const PairTap* taps,
                       int tapCount, int begin, int end, const GatherFold& fold)
{
    for (int x = begin; x < end; x++)
    {
        float a = 0.f, b = 0.f;
        for (int t = 0; t < tapCount; t++)
        {
            const float l = source[size_t(taps[t].row) * sourceStep + size_t(taps[t].col + x)];
            a = std::fma(taps[t].weight[0], l, a);
            b = std::fma(taps[t].weight[1], l, b);
        }
        foldColumn(a, fold, x, out0);
        foldColumn(b, fold, x, out1);
    }
}

//! The packed form: out_k[x] = Σ_t packedDot(weight_t[k], packed(pair_t, x + col_t)), folded as `fold` says.
inline void gatherPackedPair(float* out0, float* out1, const uint32_t* source, size_t sourceStep,
                             const PackedTap* taps, int tapCount, int begin, int end, const GatherFold& fold)
{
    for (int x = begin; x < end; x++)
    {
        float a = 0.f, b = 0.f;
        for (int t = 0; t < tapCount; t++)
        {
            const uint32_t l = source[size_t(taps[t].pair) * sourceStep + size_t(taps[t].col + x)];
            a = packedDot(taps[t].weight[0], l, a);
            b = packedDot(taps[t].weight[1], l, b);
        }
        foldColumn(a, fold, x, out0);
        foldColumn(b, fold, x, out1);
    }
}

}  // namespace reference
}  // namespace kernels
}  // namespace dynblur
}  // namespace cv

#endif
