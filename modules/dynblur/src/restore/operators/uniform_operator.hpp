// SPDX-License-Identifier: Apache-2.0
// Private: the blur of one kernel everywhere, through FFTW.
#ifndef OPENCV_DYNBLUR_RESTORE_UNIFORM_OPERATOR_HPP
#define OPENCV_DYNBLUR_RESTORE_UNIFORM_OPERATOR_HPP

#include "restore/operators/blur_operator.hpp"

#include <memory>

namespace cv {
namespace dynblur {
namespace detail {

class FftKernel;

/** @brief One kernel everywhere (convolution form), through FFTW. With `pad` the latent domain is
the frame grown by the kernel's half-size on each side; otherwise it is the frame, zero outside. */
class CV_EXPORTS UniformBlurOperator CV_FINAL : public BlurOperator
{
public:
    UniformBlurOperator(Size frameSize, const Mat& kernel32f, bool pad);
    ~UniformBlurOperator();
    void forward(const Mat& latent, Mat& frame) CV_OVERRIDE;
    void adjoint(const Mat& frame, Mat& latent) CV_OVERRIDE;

private:
    std::unique_ptr<FftKernel> fft_;
    Mat scratch_;
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
