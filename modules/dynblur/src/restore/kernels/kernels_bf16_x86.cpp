// SPDX-License-Identifier: Apache-2.0
/* The one kernel universal intrinsics cannot express: the packed gather in AVX512-BF16's
   vdpbf16ps, which takes both bfloat16 halves of a packed pair in one instruction (twice the
   multiply-adds of a float FMA per instruction, from half the bytes). Raw intrinsics, behind
   function target attributes, so the file builds for any x86-64 and runs only where the CPU has
   the instructions (avx512Bf16Kernels). Its sums equal the universal packed gather's to the
   bit: vdpbf16ps adds the high halves' exact product, then the low halves'. */
#include "restore/kernels/kernel_table.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#include <immintrin.h>

#include <algorithm>

#define DYNBLUR_BF16_TARGET __attribute__((target("avx512bf16,avx512vl,avx512bw,avx512f,avx2,fma")))

namespace cv {
namespace dynblur {
namespace kernels {

namespace {

//! The lanes of the last of `Vectors` 16-column vectors from x before `end` (end − x > 16 · (Vectors − 1)).
template <int Vectors>
inline __mmask16 lastVectorMask(int x, int end)
{
    return __mmask16(0xffffu >> (16 - (end - x - 16 * (Vectors - 1))));
}

/* The sums of a block of both output rows into them as `fold` says: the added lanes as
   weight · sum + out in one rounding (foldColumn's arithmetic), the written ones as weight · sum;
   the last vector masked. */
template <int Vectors>
DYNBLUR_BF16_TARGET __attribute__((always_inline)) inline void
foldBlock(float* __restrict out0, float* __restrict out1, int x, __mmask16 last, const __m512 (&a)[Vectors],
          const __m512 (&b)[Vectors], const GatherFold& fold)
{
#pragma GCC unroll 16
    for (int k = 0; k < Vectors; k++)
    {
        const int col = x + 16 * k;
        const __mmask16 lanes = k + 1 < Vectors ? __mmask16(0xffffu) : last;
        __m512 sa = a[k], sb = b[k];
        if (!fold.writes())
        {
            const int added = std::min(16, std::max(0, fold.split - col));
            const __mmask16 add = lanes & __mmask16(added >= 16 ? 0xffffu : (1u << added) - 1u);
            if (fold.weight)
            {
                const __m512 w = _mm512_maskz_loadu_ps(lanes, fold.weight + col);
                const __m512 wa = _mm512_mul_ps(w, sa), wb = _mm512_mul_ps(w, sb);
                if (add)
                {
                    sa = _mm512_mask_fmadd_ps(sa, add, w, _mm512_maskz_loadu_ps(add, out0 + col));
                    sb = _mm512_mask_fmadd_ps(sb, add, w, _mm512_maskz_loadu_ps(add, out1 + col));
                }
                sa = _mm512_mask_mov_ps(wa, add, sa);
                sb = _mm512_mask_mov_ps(wb, add, sb);
            }
            else if (add)
            {
                sa = _mm512_mask_add_ps(sa, add, sa, _mm512_maskz_loadu_ps(add, out0 + col));
                sb = _mm512_mask_add_ps(sb, add, sb, _mm512_maskz_loadu_ps(add, out1 + col));
            }
        }
        _mm512_mask_storeu_ps(out0 + col, lanes, sa);
        _mm512_mask_storeu_ps(out1 + col, lanes, sb);
    }
}

/* Up to Vectors × 16 columns of both output rows from x (the last vector cut by `end`): one sum per
   vector and row in a zmm register while all taps stream past. The last vector's masked load reads
   nothing past `end`, so no column is left to a scalar tail; only it is masked (a mask per vector
   would need more than the seven mask registers at 9 and 10). The loops over the vectors are
   unrolled by pragma: GCC otherwise gave the sums a place on the stack and stored them at every tap. */
template <int Vectors>
DYNBLUR_BF16_TARGET __attribute__((always_inline)) inline void
packedBlock(float* __restrict out0, float* __restrict out1, const uint32_t* source, size_t sourceStep,
            const PackedTap* taps, int tapCount, int x, int end, const GatherFold& fold)
{
    const __mmask16 last = lastVectorMask<Vectors>(x, end);
    __m512 a[Vectors], b[Vectors];
#pragma GCC unroll 16
    for (int k = 0; k < Vectors; k++)
        a[k] = b[k] = _mm512_setzero_ps();
    for (int t = 0; t < tapCount; t++)
    {
        const uint32_t* p = source + size_t(taps[t].pair) * sourceStep + (taps[t].col + x);
        const __m512bh w = (__m512bh)_mm512_set1_epi32(int(taps[t].weight[0]));
        const __m512bh u = (__m512bh)_mm512_set1_epi32(int(taps[t].weight[1]));
#pragma GCC unroll 16
        for (int k = 0; k < Vectors; k++)
        {
            const __m512bh l = (__m512bh)(k + 1 < Vectors ? _mm512_loadu_si512(p + 16 * k)
                                                          : _mm512_maskz_loadu_epi32(last, p + 16 * k));
            a[k] = _mm512_dpbf16_ps(a[k], l, w);
            b[k] = _mm512_dpbf16_ps(b[k], l, u);
        }
    }
    foldBlock<Vectors>(out0, out1, x, last, a, b, fold);
}

/* KernelTable::packedPair: blocks of 128 columns, the last up to 160 in one block (the caller's
   column chunks are at most that wide). */
DYNBLUR_BF16_TARGET void gatherPackedPairBf16(float* out0, float* out1, const uint32_t* source, size_t sourceStep,
                                              const PackedTap* taps, int tapCount, int begin, int end,
                                              const GatherFold& fold)
{
    int x = begin;
    for (; end - x > 160; x += 128)
        packedBlock<8>(out0, out1, source, sourceStep, taps, tapCount, x, x + 128, fold);
    switch ((end - x + 15) / 16)
    {
    case 10: packedBlock<10>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 9: packedBlock<9>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 8: packedBlock<8>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 7: packedBlock<7>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 6: packedBlock<6>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 5: packedBlock<5>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 4: packedBlock<4>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 3: packedBlock<3>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 2: packedBlock<2>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 1: packedBlock<1>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    default: break;
    }
}

//! CPUID leaf 7, sub-leaf 1, EAX bit 5: AVX512_BF16 (the caller has checked AVX-512 and its OS support).
bool cpuHasAvx512Bf16()
{
    unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
    return __get_cpuid_count(7, 1, &eax, &ebx, &ecx, &edx) && (eax & (1u << 5)) != 0;
}

}  // namespace

const KernelTable* avx512Bf16Kernels()
{
    static const KernelTable* kernels = []() -> const KernelTable* {
        static KernelTable table;
        const KernelTable* wide = avx512Kernels();
        if (!wide || !cpuHasAvx512Bf16())
            return nullptr;
        table = *wide;
        table.packedPair = gatherPackedPairBf16;
        return &table;
    }();
    return kernels;
}

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv

#else

namespace cv {
namespace dynblur {
namespace kernels {

const KernelTable* avx512Bf16Kernels()
{
    return nullptr;
}

}  // namespace kernels
}  // namespace dynblur
}  // namespace cv

#endif
