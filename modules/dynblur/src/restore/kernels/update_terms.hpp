// SPDX-License-Identifier: Apache-2.0
/* The terms of Richardson–Lucy's update of one row (updateRow): plain structs and the plain C++
   reference, no OpenCV, so the kernels' test builds for any CPU from the headers alone.

   x_{k+1} = y ⊙ correction / (norm − λ curvature) over one row, kept within [0, upper]; with
   `correctionExcess`, `correction` holds correction − norm. With `norm` null the normaliser is
   `rowNorm` all along the row: a row-wise bank's Aᵀ1 usually is, and not streaming it leaves the
   update's loads in the caches. Pixels whose normaliser is ≤ kUpdateUnobserved keep y. `tv` may be
   null (no curvature). `out` may be `y` (each element is read before it is written); with `out`
   null, only tv->ny is computed (the row just above a band). With `step`, the data term's step
   g = y ⊙ (correction / norm − 1) meets the last one, stored there as bfloat16 (a float's upper
   half, truncated: it only feeds the extrapolation's two dot products, whose ratio a 2^-8 relative
   error per element hardly moves, and half the bytes is half that plane's traffic): Σ g·g_old and
   Σ g_old² (times scale², which keeps the products from under- or overflowing) go to `sums`, and g
   replaces g_old. The extrapolation follows the data term's step only: TV's curvature term flips
   sign from one iteration to the next on noise, which would make successive steps look
   uncorrelated and switch acceleration off.

   Multiply-adds are fused where the vector kernels fuse them, so the vector kernels equal this
   reference to the bit wherever the CPU fuses (SSE2 does not). The sums are kept in kUpdateSumLanes
   float lanes (column x in lane x mod 16), added into `sums`
   lane by lane at the row's end, at every vector width alike: the same sums on every CPU. */
#ifndef OPENCV_DYNBLUR_RESTORE_KERNELS_UPDATE_TERMS_HPP
#define OPENCV_DYNBLUR_RESTORE_KERNELS_UPDATE_TERMS_HPP

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace cv {
namespace dynblur {
namespace kernels {

//! Normaliser below which a latent pixel counts as not seen by any frame pixel.
constexpr float kUpdateUnobserved = 1e-3f;
//! The lanes the step's sums are kept in, whatever the vector width.
constexpr int kUpdateSumLanes = 16;

//! Sums an update accumulates over a band of rows, added up afterwards in band order.
struct UpdateSums
{
    double stepDot = 0, stepBeforeSq = 0, changeSq = 0, sizeSq = 0;
};

/* TV's terms for the update of one row of y. The curvature div(∇y/|∇y|) is nx[x] − nx[x−1] +
   ny[x] − nyAbove[x], with the unit gradient n = ∇y/|∇y| by forward differences (zero across the
   last column and below the last row) and the divergence by backward ones (the pair that makes
   −div the adjoint of ∇; nx[−1] and the first row's nyAbove are 0: zero flux across the edges).
   |∇y| is taken on y · scale, so the squares neither under- nor overflow, and regularised by eps2. */
struct RowTv
{
    const float* below;    //!< the next row of y; null on the last row
    const float* nyAbove;  //!< the row above's ny; null when only ny is computed
    float* ny;             //!< where the row's own ny goes, for the row below
    float scale, eps2;
};

//! The arguments of one row's update (see the file's comment).
struct UpdateRow
{
    const float* y;
    const float* correction;
    bool correctionExcess;
    const float* norm;  //!< null: rowNorm everywhere
    float rowNorm;
    const RowTv* tv;
    float tvWeight, upper;
    int n;
    float* out;
    uint16_t* step;
    float scale;
};

/* 1 / sqrt(q) to 5e-6 relative (TV needs no more): the exponent-halving first guess and two
   Newton steps, a few multiplies where a square root and a division each take longer. */
inline float inverseSqrt(float q)
{
    int32_t bits;
    std::memcpy(&bits, &q, sizeof bits);
    bits = 0x5f375a86 - (bits >> 1);
    float inv;
    std::memcpy(&inv, &bits, sizeof inv);
    const float half = 0.5f * q;
    inv *= std::fma(-(half * inv), inv, 1.5f);
    inv *= std::fma(-(half * inv), inv, 1.5f);
    return inv;
}

namespace reference {

//! The update of one row, a column at a time.
inline void updateRow(const UpdateRow& a, UpdateSums& sums)
{
    float stepDot[kUpdateSumLanes] = {}, stepBeforeSq[kUpdateSumLanes] = {};
    float nxLeft = 0.f;
    for (int x = 0; x < a.n; x++)
    {
        const float yv = a.y[x];
        float curvature = 0.f;
        if (a.tv)
        {
            const float yRight = x + 1 < a.n ? a.y[x + 1] : yv;
            const float gx = (yRight - yv) * a.tv->scale;
            const float gy = a.tv->below ? (a.tv->below[x] - yv) * a.tv->scale : 0.f;
            const float q = std::fma(gx, gx, gy * gy) + a.tv->eps2;
            const float inv = inverseSqrt(q);
            const float nx = gx * inv, ny = gy * inv;
            a.tv->ny[x] = ny;
            if (!a.out)
                continue;
            curvature = nx - nxLeft + ny - a.tv->nyAbove[x];
            nxLeft = nx;
        }
        if (!a.out)
            continue;
        const float nv = a.norm ? a.norm[x] : a.rowNorm;
        float cv = a.correction[x];
        if (a.correctionExcess)
            cv += nv;
        float den = nv;
        if (a.tv)
            den = std::fma(-a.tvWeight, curvature, den);
        const float floor = 0.1f * nv;  // keeps a large λ from flipping the sign
        den = den > floor ? den : floor;
        const bool seen = nv > kUpdateUnobserved;
        float value = yv * cv / den;
        value = value > 0.f ? value : 0.f;
        value = value < a.upper ? value : a.upper;
        a.out[x] = seen ? value : yv;
        if (a.step)
        {
            const float g = seen ? yv * (cv / nv - 1.f) : 0.f;
            const uint32_t beforeBits = uint32_t(a.step[x]) << 16;
            float before;
            std::memcpy(&before, &beforeBits, sizeof before);
            before *= a.scale;
            const float now = g * a.scale;
            stepDot[x % kUpdateSumLanes] = std::fma(now, before, stepDot[x % kUpdateSumLanes]);
            stepBeforeSq[x % kUpdateSumLanes] = std::fma(before, before, stepBeforeSq[x % kUpdateSumLanes]);
            uint32_t gBits;
            std::memcpy(&gBits, &g, sizeof gBits);
            a.step[x] = uint16_t(gBits >> 16);
        }
    }
    for (int k = 0; k < kUpdateSumLanes; k++)
    {
        sums.stepDot += stepDot[k];
        sums.stepBeforeSq += stepBeforeSq[k];
    }
}

}  // namespace reference
}  // namespace kernels
}  // namespace dynblur
}  // namespace cv

#endif
