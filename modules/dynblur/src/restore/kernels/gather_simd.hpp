// SPDX-License-Identifier: Apache-2.0
/* The gather kernels in OpenCV's universal intrinsics, written once and compiled once per
   instruction set: a file that includes this header first defines DYNBLUR_KERNELS_ISA, the
   namespace its build goes in (the vector width differs between builds, so their inline functions
   must not meet at link time), and the instruction set's macros (gather_x86.cpp); the baseline
   build (SSE2 on x86-64, NEON on AArch64) needs none. Header-only, no libopencv calls: the
   kernels' test cross-compiles it for AArch64 alone (scripts/arm_check.sh).

   Every kernel sums each output column's taps in tap order, one fused multiply-add each, in a lane
   of its own: a column's sum is the same to the bit at any vector width and in the reference
   (gather_reference.hpp), wherever the instruction set has a fused multiply-add. */
#ifndef DYNBLUR_KERNELS_ISA
#error "define DYNBLUR_KERNELS_ISA, the namespace of this build of the kernels, before including gather_simd.hpp"
#endif

#include "restore/kernels/kernel_table.hpp"
#include "restore/kernels/gather_reference.hpp"
#include "restore/kernels/update_simd.hpp"

#include <opencv2/core/hal/intrin.hpp>

#include <type_traits>

namespace cv {
namespace dynblur {
namespace kernels {
namespace DYNBLUR_KERNELS_ISA {

#if CV_SIMD

constexpr int kLanes = v_float32::nlanes;
/* Vectors per row in a pair's block: two rows' sums, a load and two weights stay within the
   registers (16 on SSE2 and AVX2, 32 on AVX-512 and NEON). The single-row gather keeps 8. */
constexpr int kPairVectors = (CV_SIMD512 || CV_NEON) ? 8 : 4;
constexpr int kRowVectors = 8;

//! The sums of columns [col, col + kLanes) into `out`, as `fold` says (foldColumn's arithmetic, a lane each).
inline void foldVector(const v_float32& sums, const GatherFold& fold, int col, float* out)
{
    if (fold.writes())
    {
        v_store(out + col, sums);
        return;
    }
    if (col + kLanes <= fold.split)
    {
        const v_float32 before = vx_load(out + col);
        v_store(out + col, fold.weight ? v_fma(vx_load(fold.weight + col), sums, before) : sums + before);
    }
    else if (col >= fold.split)
        v_store(out + col, fold.weight ? vx_load(fold.weight + col) * sums : sums);
    else
    {
        float lanes[kLanes];
        v_store(lanes, sums);
        for (int i = 0; i < kLanes; i++)
            foldColumn(lanes[i], fold, col + i, out);
    }
}

//! Columns [col + first, col + kLanes) of `sums` (a vector from col) into `out`, as `fold` says.
inline void foldLastLanes(const v_float32& sums, const GatherFold& fold, int col, int first, float* out)
{
    float lanes[kLanes];
    v_store(lanes, sums);
    for (int i = first; i < kLanes; i++)
        foldColumn(lanes[i], fold, col + i, out);
}

/* A row's columns [begin, end) in blocks of `Vectors` vectors, then of fewer, then the last
   columns through one vector that ends at `end` (it overlaps columns already done, and computes
   them again to the same bits) when the row is a vector wide, else one at a time. block<V>(x)
   does V vectors from column x; last(x, first) does the vector from x, keeping its lanes from
   `first` on; single(x) one column. */
template <int Vectors, typename Block, typename Last, typename Single>
inline void walkColumns(int begin, int end, const Block& block, const Last& last, const Single& single)
{
    int x = begin;
    for (; x + Vectors * kLanes <= end; x += Vectors * kLanes)
        block(std::integral_constant<int, Vectors>(), x);
    if (Vectors >= 8 && x + 4 * kLanes <= end)
        block(std::integral_constant<int, 4>(), x), x += 4 * kLanes;
    if (Vectors >= 4 && x + 2 * kLanes <= end)
        block(std::integral_constant<int, 2>(), x), x += 2 * kLanes;
    if (x + kLanes <= end)
        block(std::integral_constant<int, 1>(), x), x += kLanes;
    if (x == end)
        return;
    if (end - begin >= kLanes)
        last(end - kLanes, x - (end - kLanes));
    else
        for (; x < end; x++)
            single(x);
}

/* walkColumns for a pair of rows: sums(vectors, x, a, b) gives both rows' sums of `vectors`
   vectors from column x, folded here into out0 and out1 as `fold` says; single(x) does column x. */
template <typename Sums, typename Single>
inline void walkPair(const Sums& sums, float* out0, float* out1, int begin, int end, const GatherFold& fold,
                     const Single& single)
{
    walkColumns<kPairVectors>(
        begin, end,
        [&](auto vectors, int x) {
            constexpr int V = decltype(vectors)::value;
            v_float32 a[V], b[V];
            sums(vectors, x, a, b);
#pragma GCC unroll 8
            for (int k = 0; k < V; k++)
            {
                foldVector(a[k], fold, x + k * kLanes, out0);
                foldVector(b[k], fold, x + k * kLanes, out1);
            }
        },
        [&](int x, int first) {
            v_float32 a[1], b[1];
            sums(std::integral_constant<int, 1>(), x, a, b);
            foldLastLanes(a[0], fold, x, first, out0);
            foldLastLanes(b[0], fold, x, first, out1);
        },
        single);
}

//! reference::gatherRow in vectors.
inline void gatherRow(float* out, const float* source, size_t sourceStep, const Tap* taps, int tapCount, int begin,
                      int end)
{
    const auto sums = [&](auto vectors, int x, v_float32* s) {
        constexpr int V = decltype(vectors)::value;
#pragma GCC unroll 8
        for (int k = 0; k < V; k++)
            s[k] = vx_setzero_f32();
        for (int t = 0; t < tapCount; t++)
        {
            const float* p = source + size_t(taps[t].row) * sourceStep + (taps[t].col + x);
            const v_float32 w = vx_setall_f32(taps[t].weight);
#pragma GCC unroll 8
            for (int k = 0; k < V; k++)
                s[k] = v_fma(w, vx_load(p + k * kLanes), s[k]);
        }
    };
    walkColumns<kRowVectors>(
        begin, end,
        [&](auto vectors, int x) {
            constexpr int V = decltype(vectors)::value;
            v_float32 s[V];
            sums(vectors, x, s);
#pragma GCC unroll 8
            for (int k = 0; k < V; k++)
                v_store(out + x + k * kLanes, s[k]);
        },
        [&](int x, int first) {
            v_float32 s[1];
            sums(std::integral_constant<int, 1>(), x, s);
            foldLastLanes(s[0], GatherFold(), x, first, out);
        },
        [&](int x) { reference::gatherRow(out, source, sourceStep, taps, tapCount, x, x + 1); });
}

/* reference::gatherPair in vectors: neighbouring rows read nearly the same source rows, so each
   vector loaded feeds both rows' sums (loads, not multiply-adds, bound the one-row gather). */
inline void gatherPair(float* out0, float* out1, const float* source, size_t sourceStep, const PairTap* taps,
                       int tapCount, int begin, int end, const GatherFold& fold)
{
    const auto sums = [&](auto vectors, int x, v_float32* a, v_float32* b) {
        constexpr int V = decltype(vectors)::value;
#pragma GCC unroll 8
        for (int k = 0; k < V; k++)
            a[k] = b[k] = vx_setzero_f32();
        for (int t = 0; t < tapCount; t++)
        {
            const float* p = source + size_t(taps[t].row) * sourceStep + (taps[t].col + x);
            const v_float32 w = vx_setall_f32(taps[t].weight[0]), u = vx_setall_f32(taps[t].weight[1]);
#pragma GCC unroll 8
            for (int k = 0; k < V; k++)
            {
                const v_float32 l = vx_load(p + k * kLanes);
                a[k] = v_fma(w, l, a[k]);
                b[k] = v_fma(u, l, b[k]);
            }
        }
    };
    walkPair(sums, out0, out1, begin, end, fold,
             [&](int x) { reference::gatherPair(out0, out1, source, sourceStep, taps, tapCount, x, x + 1, fold); });
}

/* reference::gatherPackedPair in vectors: each packed element's bfloat16 halves widened to floats
   (a shift and a mask), the high halves' product added first, as vdpbf16ps does. */
inline void gatherPackedPair(float* out0, float* out1, const uint32_t* source, size_t sourceStep,
                             const PackedTap* taps, int tapCount, int begin, int end, const GatherFold& fold)
{
    const auto sums = [&](auto vectors, int x, v_float32* a, v_float32* b) {
        constexpr int V = decltype(vectors)::value;
        const v_uint32 highMask = vx_setall_u32(0xffff0000u);
#pragma GCC unroll 8
        for (int k = 0; k < V; k++)
            a[k] = b[k] = vx_setzero_f32();
        for (int t = 0; t < tapCount; t++)
        {
            const unsigned* p = source + size_t(taps[t].pair) * sourceStep + (taps[t].col + x);
            const uint32_t w = taps[t].weight[0], u = taps[t].weight[1];
            const v_float32 wLow = vx_setall_f32(lowBfloat16(w)), wHigh = vx_setall_f32(highBfloat16(w));
            const v_float32 uLow = vx_setall_f32(lowBfloat16(u)), uHigh = vx_setall_f32(highBfloat16(u));
#pragma GCC unroll 8
            for (int k = 0; k < V; k++)
            {
                const v_uint32 packed = vx_load(p + k * kLanes);
                const v_float32 low = v_reinterpret_as_f32(v_shl<16>(packed));
                const v_float32 high = v_reinterpret_as_f32(packed & highMask);
                a[k] = v_fma(wLow, low, v_fma(wHigh, high, a[k]));
                b[k] = v_fma(uLow, low, v_fma(uHigh, high, b[k]));
            }
        }
    };
    walkPair(sums, out0, out1, begin, end, fold, [&](int x) {
        reference::gatherPackedPair(out0, out1, source, sourceStep, taps, tapCount, x, x + 1, fold);
    });
}

//! foldColumns in vectors.
inline void foldRow(const float* sums, const GatherFold& fold, int begin, int end, float* out)
{
    int x = begin;
    for (; x + kLanes <= end; x += kLanes)
        foldVector(vx_load(sums + x), fold, x, out);
    foldColumns(sums, fold, x, end, out);
}

#else  // no vector instructions: the reference kernels

using reference::gatherPackedPair;
using reference::gatherPair;
using reference::gatherRow;
inline void foldRow(const float* sums, const GatherFold& fold, int begin, int end, float* out)
{
    foldColumns(sums, fold, begin, end, out);
}

#endif

//! This build's table.
inline KernelTable table()
{
    return KernelTable{gatherRow, gatherPair, gatherPackedPair, foldRow, updateRow};
}

}  // namespace DYNBLUR_KERNELS_ISA
}  // namespace kernels
}  // namespace dynblur
}  // namespace cv
