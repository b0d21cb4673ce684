// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "pipeline/frame_rate_preset.hpp"

#include <algorithm>
#include <cmath>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

/* Measured on DeblurQuality's and RotationQuality's frames: 10 iterations lose up to 0.7 dB against
   20 where the most spread kernel covers N ≥ 14.6 px (a 3-axis shake's lines, L = 11 px and more),
   0.2 to 1.4 dB where N ≥ 78 (the saccade's long blurs), and stay within 0.25 dB at N ≤ 9.9 (L = 7 px,
   and the saccade's window III global frame, whose L = 25 px kernels hold most of their light in a
   few taps: N = 3.2), but lose up to 0.77 dB on a 45 px kernel whose N is 10.7 (a zoomed lens's
   window I frame, DeblurQuality.ZoomedLens): 10 only where N ≤ 12 px and L ≤ 32 px. The color at
   half resolution loses 0.6 dB on baboon's fur at L = 7 px whatever its iterations; 6, 8 and 10
   iterations all in color at full resolution lose 0.37, 0.26 and 0.19 dB there at worst (8: the
   margin kept at a fifth less work than 10); 3 color iterations at half
   resolution lost 1.4 dB on fruits' window II frame (91 px), 14 lost 0.3. The automatic stop is a
   safety net: at 2e-3 it stopped none of those frames, at 5e-3 it stopped building's window III
   frame 1.6 dB early. */
constexpr int kShortBlurIterations = 10, kLongBlurIterations = 20, kFullColorIterations = 8;
constexpr double kShortBlurSpread = 12, kShortBlurPx = 32, kFullColorPx = 8;
constexpr int kMinColorIterations = 3, kMaxColorIterations = 14;
constexpr double kPxPerColorIteration = 6.5;
constexpr double kFrameRateTolerance = 2e-3;

}  // namespace

RLParams frameRatePresetParams()
{
    RLParams params;
    params.iterations = kLongBlurIterations;
    params.tolerance = kFrameRateTolerance;
    params.colorIterations = kMinColorIterations;
    params.blurPrecision = RL_BLUR_BFLOAT16;
    return params;
}

double mostSpreadKernelPx(const PsfBank& bank)
{
    double spread = 1;
    for (const Mat& kernel : bank.kernels)
        spread = std::max(spread, 1 / kernel.dot(kernel));
    return spread;
}

RLParams frameRateIterations(const PsfBank& bank, const RLParams& params)
{
    const Size k = bank.maxKernelSize();
    const double longest = std::max(k.width, k.height);
    const double spread = mostSpreadKernelPx(bank);
    RLParams frame = params;
    if (longest <= kFullColorPx)
    {
        frame.iterations = kFullColorIterations;
        frame.colorIterations = -1;
        return frame;
    }
    const bool shortBlur = spread <= kShortBlurSpread && longest <= kShortBlurPx;
    frame.iterations = shortBlur ? kShortBlurIterations : kLongBlurIterations;
    const int byLength = int(std::ceil(longest / kPxPerColorIteration));
    frame.colorIterations =
        std::min(frame.iterations - 1, std::max(kMinColorIterations, std::min(kMaxColorIterations, byLength)));
    return frame;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
