// A stand-in kernel for scripts/arm_check.sh until the restoration kernels move here: the shape of
// the row gathers, out[x] += sum_t w[t] * src[x + offset[t]], over float rows and over bfloat16-packed
// rows (the upper 16 bits of a float), each with a plain C++ reference. Header-only over OpenCV's
// universal intrinsics (no libopencv call), so that its test cross-compiles for aarch64 and runs
// under qemu.
#ifndef DYNBLUR_RESTORE_KERNELS_TOY_GATHER_HPP
#define DYNBLUR_RESTORE_KERNELS_TOY_GATHER_HPP

#include <opencv2/core/hal/intrin.hpp>

#include <cstdint>
#include <cstring>

namespace cv { namespace dynblur { namespace kernels {

//! The float a bfloat16 stands for: its 16 bits are the float's upper half.
inline float bf16ToFloat(uint16_t b)
{
    const uint32_t bits = uint32_t(b) << 16;
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

/* out[x] += sum over t < taps of weights[t] * src[x + offsets[t]], x in [0, width): the reference.
   src[x + offsets[t]] must be readable for every x and t. */
inline void toyGatherRef(const float* src, const int* offsets, const float* weights, int taps, float* out, int width)
{
    for (int x = 0; x < width; x++)
    {
        float acc = out[x];
        for (int t = 0; t < taps; t++)
            acc += weights[t] * src[x + offsets[t]];
        out[x] = acc;
    }
}

//! toyGatherRef with the widest universal-intrinsics vector the compiler was told of.
inline void toyGather(const float* src, const int* offsets, const float* weights, int taps, float* out, int width)
{
    int x = 0;
#if CV_SIMD || CV_SIMD128
    const int lanes = v_float32::nlanes;
    for (; x + lanes <= width; x += lanes)
    {
        v_float32 acc = vx_load(out + x);
        for (int t = 0; t < taps; t++)
            acc = v_fma(vx_setall_f32(weights[t]), vx_load(src + x + offsets[t]), acc);
        v_store(out + x, acc);
    }
    vx_cleanup();
#endif
    toyGatherRef(src + x, offsets, weights, taps, out + x, width - x);  // the tail
}

//! toyGatherRef over a bfloat16-packed source row: the reference.
inline void toyGatherBf16Ref(const uint16_t* src, const int* offsets, const float* weights, int taps, float* out,
                             int width)
{
    for (int x = 0; x < width; x++)
    {
        float acc = out[x];
        for (int t = 0; t < taps; t++)
            acc += weights[t] * bf16ToFloat(src[x + offsets[t]]);
        out[x] = acc;
    }
}

//! toyGatherBf16Ref with universal intrinsics: widen 16 → 32 bits, shift into the upper half.
inline void toyGatherBf16(const uint16_t* src, const int* offsets, const float* weights, int taps, float* out,
                          int width)
{
    int x = 0;
#if CV_SIMD || CV_SIMD128
    const int lanes = v_float32::nlanes;
    for (; x + lanes <= width; x += lanes)
    {
        v_float32 acc = vx_load(out + x);
        for (int t = 0; t < taps; t++)
        {
            const v_float32 s = v_reinterpret_as_f32(v_shl<16>(vx_load_expand(src + x + offsets[t])));
            acc = v_fma(vx_setall_f32(weights[t]), s, acc);
        }
        v_store(out + x, acc);
    }
    vx_cleanup();
#endif
    toyGatherBf16Ref(src + x, offsets, weights, taps, out + x, width - x);
}

}}}  // namespace cv::dynblur::kernels

#endif
