// A stand-in kernel for scripts/arm_check.sh until the restoration kernels move here: the shape of
// the row gathers, out[x] += sum_t w[t] * src[x + offset[t]], over float rows and over bfloat16-packed
// rows (uint16_t, the upper 16 bits of a float), each with a plain C++ reference. Header-only over
// OpenCV's universal intrinsics (no libopencv call), so that its test cross-compiles for aarch64 and
// runs under qemu.
#ifndef DYNBLUR_RESTORE_KERNELS_TOY_GATHER_HPP
#define DYNBLUR_RESTORE_KERNELS_TOY_GATHER_HPP

#include <opencv2/core/hal/intrin.hpp>

#include <cstdint>
#include <cstring>

namespace cv { namespace dynblur { namespace kernels {

//! A source value as a float: a float itself, or the float a bfloat16 stands for.
inline float toFloat(float v)
{
    return v;
}
inline float toFloat(uint16_t b)
{
    const uint32_t bits = uint32_t(b) << 16;
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

/* out[x] += sum over t < taps of weights[t] * src[x + offsets[t]], x in [0, width), for a float or a
   bfloat16 (uint16_t) source row: the reference. src[x + offsets[t]] must be readable for every x, t. */
template <typename Src>
void toyGatherRef(const Src* src, const int* offsets, const float* weights, int taps, float* out, int width)
{
    for (int x = 0; x < width; x++)
    {
        float acc = out[x];
        for (int t = 0; t < taps; t++)
            acc += weights[t] * toFloat(src[x + offsets[t]]);
        out[x] = acc;
    }
}

#if CV_SIMD
//! A vector of source values as floats; a bfloat16 is widened to 32 bits and shifted into the upper half.
inline v_float32 vxLoadFloat(const float* p)
{
    return vx_load(p);
}
inline v_float32 vxLoadFloat(const uint16_t* p)
{
    return v_reinterpret_as_f32(v_shl<16>(vx_load_expand(p)));
}
#endif

//! toyGatherRef with the widest universal-intrinsics vector the compiler was told of.
template <typename Src>
void toyGather(const Src* src, const int* offsets, const float* weights, int taps, float* out, int width)
{
    int x = 0;
#if CV_SIMD
    const int lanes = v_float32::nlanes;
    for (; x + lanes <= width; x += lanes)
    {
        v_float32 acc = vx_load(out + x);
        for (int t = 0; t < taps; t++)
            acc = v_fma(vx_setall_f32(weights[t]), vxLoadFloat(src + x + offsets[t]), acc);
        v_store(out + x, acc);
    }
    vx_cleanup();
#endif
    toyGatherRef(src + x, offsets, weights, taps, out + x, width - x);  // the tail
}

}}}  // namespace cv::dynblur::kernels

#endif
