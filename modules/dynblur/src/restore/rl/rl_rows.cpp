// SPDX-License-Identifier: Apache-2.0
#include "restore/rl/rl_rows.hpp"

#include "restore/rl/rl_terms.hpp"
#include "restore/row_arithmetic.hpp"
#include "restore/simd_clones.hpp"
#include "restore/kernels/kernel_table.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>

namespace cv {
namespace dynblur {
namespace detail {

/* ratio = b / (A x) over one row, damped as MATLAB's deconvlucy does (White 1994): where the
   Poisson deviance between b and A x is within the damping threshold, the ratio is pulled to 1
   (no update). The deviance is halfPoissonDeviance's log-free form: a log would make this the
   longest loop of the iteration, and DeblurQuality's figures do not tell the two apart.
   Intensities are taken times `scale`
   (1 / the image's level), so the epsilon and the deviance mean the same at any exposure and
   nothing under- or overflows. `invThreshold` is 2 / (damping² · scale). Branch-free, so it
   vectorises. */
DYNBLUR_SIMD_CLONES
void ratioRow(const float* __restrict b, const float* __restrict ab, float* __restrict r, int n, float scale,
              float invThreshold)
{
    if (invThreshold == 0.f)
    {
        for (int x = 0; x < n; x++)
            r[x] = ab[x] > 0.f ? b[x] * scale / (ab[x] * scale + kRatioEpsilon) : 0.f;
        return;
    }
    for (int x = 0; x < n; x++)
    {
        /* Every value is computed and then selected: a conditional division keeps the loop
           scalar. A x ≥ 0, so the quotient and the deviance are finite. */
        const float bs = b[x] * scale, abs = ab[x] * scale;
        const float quotient = bs / (abs + kRatioEpsilon);
        const bool both = (b[x] > 0.f) & (ab[x] > 0.f);
        float g = halfPoissonDeviance(bs, abs) * invThreshold;
        g = std::min(std::max(g, 0.f), 1.f);
        const float g2 = g * g, g4 = g2 * g2, g8 = g4 * g4;
        const float G = g8 * g * (10.f - 9.f * g);  // g^9 (10 − 9 g): 0 within the noise, 1 beyond
        r[x] = both ? 1.f + G * (quotient - 1.f) : ab[x] > 0.f ? quotient : 0.f;
    }
}

// The update of one row: the kernel table's (src/restore/kernels/update_terms.hpp says what it computes).
void updateRow(const float* y, const float* correction, bool correctionExcess, const float* norm, float rowNorm,
               const RowTv* tv, float tvWeight, float upper, int n, float* out, uint16_t* step, float scale,
               UpdateSums& sums)
{
    kernels::kernelTable().updateRow(
        kernels::UpdateRow{y, correction, correctionExcess, norm, rowNorm, tv, tvWeight, upper, n, out, step, scale}, sums);
}

/* The value of a row whose elements are all equal, NaN otherwise. Blocks of 64 columns compared
   whole (that loop vectorises), so a row that varies early is left early. */
DYNBLUR_SIMD_CLONES
float constantValue(const float* p, int n)
{
    constexpr int kBlock = 64;
    const float first = p[0];
    for (int x0 = 0; x0 < n; x0 += kBlock)
    {
        int differs = 0;
        for (int x = x0; x < std::min(x0 + kBlock, n); x++)
            differs |= p[x] != first;
        if (differs)
            return std::numeric_limits<float>::quiet_NaN();
    }
    return first;
}

//! y = max(x + a (x − y), 0) over one row: x_{k−1} in, the extrapolated y_k out (RL needs y ≥ 0).
DYNBLUR_SIMD_CLONES
void extrapolateRow(const float* __restrict x, float a, int n, float* __restrict y)
{
    for (int i = 0; i < n; i++)
        y[i] = std::max(x[i] + a * (x[i] - y[i]), 0.f);
}

//! Σ p[x] (in eight-lane float sums) and max p[x] over a row.
DYNBLUR_SIMD_CLONES
double rowSumAndPeak(const float* p, int n, double& peak)
{
    typedef float v8 __attribute__((vector_size(32), aligned(4)));
    v8 s = {}, m = v8{} - FLT_MAX;
    int x = 0;
    for (; x + 8 <= n; x += 8)
    {
        const v8 v = *(const v8*)(p + x);
        s += v;
        m = v > m ? v : m;
    }
    double total = 0;
    float largest = -FLT_MAX;
    for (int k = 0; k < 8; k++)
    {
        total += s[k];
        largest = std::max(largest, m[k]);
    }
    for (; x < n; x++)
    {
        total += p[x];
        largest = std::max(largest, p[x]);
    }
    peak = largest;
    return total;
}

/* Σ |mask * image| over one row of Immerkær's 3×3 mask, `channels` interleaved: eight float
   lanes, in the form GCC vectorises (a single float sum is a reduction it must keep in order). */
DYNBLUR_SIMD_CLONES
float noiseMaskSumRow(const float* __restrict a, const float* __restrict m, const float* __restrict b, int width,
                      int channels)
{
    const int c = channels, r = 2 * channels;  // centre and right of a pixel, from its left
    auto term = [&](int i) {
        return std::abs(a[i] - 2 * a[i + c] + a[i + r] - 2 * (m[i] - 2 * m[i + c] + m[i + r]) + b[i] - 2 * b[i + c] +
                        b[i + r]);
    };
    float lanes[8] = {};
    int i = 0;
    for (; i + 8 <= width; i += 8)
        for (int k = 0; k < 8; k++)
            lanes[k] += term(i + k);
    for (; i < width; i++)
        lanes[0] += term(i);
    float sum = 0.f;
    for (int k = 0; k < 8; k++)
        sum += lanes[k];
    return sum;
}

//! p[x] = p[x] · factor.
DYNBLUR_SIMD_CLONES
void scaleRow(float* __restrict p, float factor, int n)
{
    for (int x = 0; x < n; x++)
        p[x] *= factor;
}

//! One plane's row takes the luminance's change from `before` to `restored` (luminanceChanged).
DYNBLUR_SIMD_CLONES
void applyLuminanceRow(const float* __restrict restored, const float* __restrict before, float black, float upper,
                       int n, const float* __restrict plane, float* __restrict out)
{
    for (int x = 0; x < n; x++)
    {
        const bool lit = before[x] > black;
        const float gain = restored[x] / (lit ? before[x] : 1.f);  // the divisor made safe
        out[x] = luminanceChanged(plane[x], lit, gain, restored[x], before[x], upper);
    }
}

/* out[x] = the mean of the planes' rows (the sum in plane order, then times 1 / planes): the
   luminance phase's start, and the same value again when the planes take its change. */
void meanRow(const std::vector<Mat>& planes, int y, int x0, int n, float* out)
{
    std::fill(out, out + n, 0.f);
    for (const Mat& p : planes)
        addRow(p.ptr<float>(y) + x0, n, out);
    scaleRow(out, 1.f / float(planes.size()), n);
}

DYNBLUR_SIMD_CLONES
void channelMeanRow(const float* __restrict interleaved, int channels, int n, float* __restrict out)
{
    switch (channels)
    {
    case 3:
        for (int x = 0; x < n; x++)
            out[x] = (interleaved[3 * x] + interleaved[3 * x + 1] + interleaved[3 * x + 2]) * (1.f / 3.f);
        return;
    case 4:
        for (int x = 0; x < n; x++)
            out[x] = (interleaved[4 * x] + interleaved[4 * x + 1] + interleaved[4 * x + 2] + interleaved[4 * x + 3]) *
                     0.25f;
        return;
    default:
        for (int x = 0; x < n; x++)
        {
            float s = 0.f;
            for (int c = 0; c < channels; c++)
                s += interleaved[x * channels + c];
            out[x] = s / float(channels);
        }
    }
}

/* The strides a frame has are spelled out: with a constant stride the compiler loads whole vectors
   and shuffles, where a variable one reads float by float. */
DYNBLUR_SIMD_CLONES
void channelRow(const float* interleaved, int channels, int channel, int n, float* __restrict out)
{
    const float* p = interleaved + channel;
    switch (channels)
    {
    case 1:
        std::memcpy(out, p, sizeof(float) * size_t(n));
        return;
    case 3:
        for (int x = 0; x < n; x++)
            out[x] = p[3 * x];
        return;
    case 4:
        for (int x = 0; x < n; x++)
            out[x] = p[4 * x];
        return;
    default:
        for (int x = 0; x < n; x++)
            out[x] = p[x * channels];
    }
}

DYNBLUR_SIMD_CLONES
void interleaveRow(const float* const* planes, int channels, int n, float* __restrict out)
{
    switch (channels)
    {
    case 1:
        std::memcpy(out, planes[0], sizeof(float) * size_t(n));
        return;
    case 3:
        for (int x = 0; x < n; x++)
        {
            out[3 * x] = planes[0][x];
            out[3 * x + 1] = planes[1][x];
            out[3 * x + 2] = planes[2][x];
        }
        return;
    default:
        for (int x = 0; x < n; x++)
            for (int c = 0; c < channels; c++)
                out[x * channels + c] = planes[c][x];
    }
}

DYNBLUR_SIMD_CLONES
void clampRowToUnit(float* __restrict p, int n)
{
    for (int x = 0; x < n; x++)
        p[x] = std::min(std::max(p[x], 0.f), 1.f);
}

/* Whether a row holds only finite values, and its least and largest: a NaN fails every
   comparison, so v == v catches it, and ±Inf shows in the range. Sixteen lanes of running minima,
   maxima and flags, in vector types (written per lane, GCC left this loop scalar). */
DYNBLUR_SIMD_CLONES
bool finiteRow(const float* p, int n, float& low, float& high)
{
    typedef float v16 __attribute__((vector_size(64), aligned(4)));  // aligned(4): unaligned loads allowed
    typedef int32_t v16i __attribute__((vector_size(64)));
    v16 lo = v16{} + p[0], hi = lo;
    v16i number = v16i{} - 1;  // all ones while every value seen in the lane is a number
    int x = 0;
    for (; x + 16 <= n; x += 16)
    {
        const v16 v = *(const v16*)(p + x);
        number &= v == v;
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
    }
    bool numbers = true;
    low = lo[0];
    high = hi[0];
    for (int k = 0; k < 16; k++)
    {
        numbers &= number[k] != 0;
        low = std::min(low, lo[k]);
        high = std::max(high, hi[k]);
    }
    for (; x < n; x++)
    {
        numbers &= p[x] == p[x];
        low = std::min(low, p[x]);
        high = std::max(high, p[x]);
    }
    return numbers && std::isfinite(low) && std::isfinite(high);
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
