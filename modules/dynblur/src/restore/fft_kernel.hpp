// SPDX-License-Identifier: Apache-2.0
// Private: FFTW-backed convolution with one kernel (single precision, threaded, plans cached).
// FFTW stays out of the public headers; only this file and fft_kernel.cpp see it.
#ifndef OPENCV_DYNBLUR_FFT_KERNEL_HPP
#define OPENCV_DYNBLUR_FFT_KERNEL_HPP

#include <opencv2/core.hpp>

#include <memory>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief One kernel's spectrum on a fixed transform grid, and the products that use it.

The kernel's centre element ((cols−1)/2, (rows−1)/2), moved by `shift`, sits at the grid origin, so
circular convolution reads dst(p) = Σ_u k(u) src(p − shift − (u − c)). Images smaller than the grid
are embedded at its top-left corner with zeros around them: with a grid at least
image + kernel − 1 (and no shift) the circular products equal linear "same" convolution with zero
outside the image. Not thread safe per instance (it owns its scratch buffers). */
class CV_EXPORTS FftKernel
{
public:
    /** @param transformSize FFT grid, pixels (use linearSize() or cv::getOptimalDFTSize).
        @param kernel CV_32F, one channel, odd size. @param shift integer displacement, pixels. */
    FftKernel(Size transformSize, const Mat& kernel, Point shift = Point());
    ~FftKernel();

    //! Grid big enough for zero-padded linear convolution of an image of `imageSize` by a kernel of `kernelSize`.
    static Size linearSize(Size imageSize, Size kernelSize);

    Size transformSize() const;

    /** @brief dst = src ⊛ k (or the correlation, the adjoint, with `adjoint`), same size as src.
        @param src CV_32FC1, at most the grid size. */
    void convolve(const Mat& src, Mat& dst, bool adjoint = false);

    /** @brief Wiener deconvolution of a grid-sized, periodic image:
        dst = IFFT(conj(K) · FFT(src) / (|K|² + noiseToSignal)). */
    void wiener(const Mat& src, Mat& dst, float noiseToSignal);

private:
    //! src → spectrum × gain(kernel spectrum) → dst (defined and used in fft_kernel.cpp only).
    template <typename Gain>
    void filter(const Mat& src, Mat& dst, Gain gain);

    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
