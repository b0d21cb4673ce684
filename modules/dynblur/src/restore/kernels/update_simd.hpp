// SPDX-License-Identifier: Apache-2.0
/* updateRow in OpenCV's universal intrinsics, compiled per instruction set like gather_simd.hpp
   (the includer defines DYNBLUR_KERNELS_ISA). Sixteen columns at a time in 16 / lanes vectors, so
   the step's sums fall in the same sixteen lanes at every vector width; the last columns through
   padded copies. Multiply-adds are fused where the reference's are (update_terms.hpp). */
#ifndef DYNBLUR_KERNELS_ISA
#error "define DYNBLUR_KERNELS_ISA before including update_simd.hpp"
#endif

#include "restore/kernels/update_terms.hpp"

#include <opencv2/core/hal/intrin.hpp>

namespace cv {
namespace dynblur {
namespace kernels {
namespace DYNBLUR_KERNELS_ISA {

#if CV_SIMD

namespace update {

constexpr int kLanes = v_float32::nlanes;
constexpr int kVectors = kUpdateSumLanes / kLanes;

/* Columns [x, x + 16) of a row whose pointers (each null when absent) start at x; yRight is y one
   column on, null in the row's last full block (the last column has no gradient across the edge).
   kTv: TV's terms; kOut: the update (else only ny); kStep: the step's sums; kRowNorm: norm null. */
template <bool kTv, bool kOut, bool kStep, bool kRowNorm>
inline void block(const UpdateRow& a, const float* y, const float* yRight, const float* below, const float* nyAbove,
                  float* ny, const float* correction, const float* norm, float* out, uint16_t* step,
                  v_float32& nxLeft, v_float32 (&stepDot)[kVectors], v_float32 (&stepBeforeSq)[kVectors])
{
    const v_float32 zero = vx_setzero_f32();
    for (int v = 0; v < kVectors; v++)
    {
        const int o = v * kLanes;
        const v_float32 yv = vx_load(y + o);
        v_float32 curvature = zero;
        if (kTv)
        {
            v_float32 yr;
            if (yRight || v + 1 < kVectors)
                yr = vx_load(y + o + 1);
            else
            {
                // The row's last column: its right neighbour is itself.
                float lanes[kLanes];
                v_store(lanes, yv);
                for (int k = 0; k + 1 < kLanes; k++)
                    lanes[k] = y[o + k + 1];
                yr = vx_load(lanes);
            }
            const v_float32 tvScale = vx_setall_f32(a.tv->scale);
            const v_float32 gx = (yr - yv) * tvScale;
            const v_float32 gy = below ? (vx_load(below + o) - yv) * tvScale : zero;
            const v_float32 q = v_fma(gx, gx, gy * gy) + vx_setall_f32(a.tv->eps2);
            const v_float32 half = vx_setall_f32(0.5f) * q;
            v_float32 inv = v_reinterpret_as_f32(vx_setall_s32(0x5f375a86) - v_shr<1>(v_reinterpret_as_s32(q)));
            const v_float32 threeHalves = vx_setall_f32(1.5f);
            inv = inv * v_fma(zero - half * inv, inv, threeHalves);
            inv = inv * v_fma(zero - half * inv, inv, threeHalves);
            const v_float32 nx = gx * inv, nyv = gy * inv;
            v_store(ny + o, nyv);
            if (!kOut)
                continue;
            curvature = nx - v_extract<kLanes - 1>(nxLeft, nx) + nyv - vx_load(nyAbove + o);
            nxLeft = nx;
        }
        const v_float32 nv = kRowNorm ? vx_setall_f32(a.rowNorm) : vx_load(norm + o);
        v_float32 cv = vx_load(correction + o);
        if (a.correctionExcess)
            cv = cv + nv;
        v_float32 den = nv;
        if (kTv)
            den = v_fma(vx_setall_f32(-a.tvWeight), curvature, den);
        den = v_max(den, vx_setall_f32(0.1f) * nv);  // keeps a large λ from flipping the sign
        const v_float32 seen = nv > vx_setall_f32(kUpdateUnobserved);
        v_float32 value = yv * cv / den;
        value = v_min(v_max(value, zero), vx_setall_f32(a.upper));
        v_store(out + o, v_select(seen, value, yv));
        if (kStep)
        {
            const v_float32 g = v_select(seen, yv * (cv / nv - vx_setall_f32(1.f)), zero);
            const v_float32 scale = vx_setall_f32(a.scale);
            const v_float32 before = v_reinterpret_as_f32(v_shl<16>(vx_load_expand(step + o))) * scale;
            stepDot[v] = v_fma(g * scale, before, stepDot[v]);
            stepBeforeSq[v] = v_fma(before, before, stepBeforeSq[v]);
            v_pack_store(step + o, v_shr<16>(v_reinterpret_as_u32(g)));
        }
    }
}

template <bool kTv, bool kOut, bool kStep, bool kRowNorm>
inline void row(const UpdateRow& a, UpdateSums& sums)
{
    const int n = a.n;
    v_float32 nxLeft = vx_setzero_f32(), stepDot[kVectors], stepBeforeSq[kVectors];
    for (int v = 0; v < kVectors; v++)
        stepDot[v] = stepBeforeSq[v] = vx_setzero_f32();
    const auto at = [](auto* p, int x) { return p ? p + x : nullptr; };
    int x = 0;
    for (; x + kUpdateSumLanes <= n; x += kUpdateSumLanes)
        block<kTv, kOut, kStep, kRowNorm>(a, a.y + x, x + kUpdateSumLanes < n ? a.y + x + 1 : nullptr,
                                          kTv ? at(a.tv->below, x) : nullptr, kTv ? at(a.tv->nyAbove, x) : nullptr,
                                          kTv ? a.tv->ny + x : nullptr, at(a.correction, x), at(a.norm, x),
                                          at(a.out, x), at(a.step, x), nxLeft, stepDot, stepBeforeSq);
    if (x < n)
    {
        /* The last 1 to 15 columns. Padding: y = 0 and a last step of 0 leave the sums alone, a
           normaliser of 1 the division finite; the last column's right neighbour is itself. */
        const int rest = n - x;
        enum { Y, Below, NyAbove, Ny, Correction, Norm, Out, Rows };
        float padded[Rows][kUpdateSumLanes + 1] = {};
        uint16_t stepTail[kUpdateSumLanes] = {};
        const auto copy = [&](const float* from, int r) {
            if (from)
                std::copy(from + x, from + n, padded[r]);
        };
        std::fill(padded[Norm], padded[Norm] + kUpdateSumLanes, 1.f);
        copy(a.y, Y);
        padded[Y][rest] = a.y[n - 1];  // read as the last column's right neighbour
        copy(a.correction, Correction);
        copy(a.norm, Norm);
        if (kTv)
        {
            copy(a.tv->below, Below);
            copy(a.tv->nyAbove, NyAbove);
        }
        if (kStep)
            std::copy(a.step + x, a.step + n, stepTail);
        block<kTv, kOut, kStep, kRowNorm>(a, padded[Y], padded[Y] + 1, kTv && a.tv->below ? padded[Below] : nullptr,
                                          padded[NyAbove], padded[Ny], padded[Correction], padded[Norm],
                                          padded[Out], stepTail, nxLeft, stepDot, stepBeforeSq);
        if (kTv)
            std::copy(padded[Ny], padded[Ny] + rest, a.tv->ny + x);
        if (kOut)
            std::copy(padded[Out], padded[Out] + rest, a.out + x);
        if (kStep)
            std::copy(stepTail, stepTail + rest, a.step + x);
    }
    for (int v = 0; v < kVectors; v++)
    {
        float dot[kLanes], beforeSq[kLanes];
        v_store(dot, stepDot[v]);
        v_store(beforeSq, stepBeforeSq[v]);
        for (int k = 0; k < kLanes; k++)
        {
            sums.stepDot += dot[k];
            sums.stepBeforeSq += beforeSq[k];
        }
    }
}

}  // namespace update

//! reference::updateRow in vectors, each kind of row (TV or not, ny only, step or not, normaliser plane or value) a loop of its own.
inline void updateRow(const UpdateRow& a, UpdateSums& sums)
{
    const bool tv = a.tv != nullptr, out = a.out != nullptr, step = a.step != nullptr, rowNorm = a.norm == nullptr;
    if (tv && !out)
        return update::row<true, false, false, true>(a, sums);
#define DYNBLUR_UPDATE_ROW(T, S, R) \
    if (tv == T && step == S && rowNorm == R) \
        return update::row<T, true, S, R>(a, sums);
    DYNBLUR_UPDATE_ROW(true, true, true)
    DYNBLUR_UPDATE_ROW(true, true, false)
    DYNBLUR_UPDATE_ROW(true, false, true)
    DYNBLUR_UPDATE_ROW(true, false, false)
    DYNBLUR_UPDATE_ROW(false, true, true)
    DYNBLUR_UPDATE_ROW(false, true, false)
    DYNBLUR_UPDATE_ROW(false, false, true)
    DYNBLUR_UPDATE_ROW(false, false, false)
#undef DYNBLUR_UPDATE_ROW
}

#else

using reference::updateRow;

#endif

}  // namespace DYNBLUR_KERNELS_ISA
}  // namespace kernels
}  // namespace dynblur
}  // namespace cv
