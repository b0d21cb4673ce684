// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/uniform_operator.hpp"

#include "restore/fft_kernel.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace cv {
namespace dynblur {
namespace detail {

UniformBlurOperator::UniformBlurOperator(Size frameSize, const Mat& kernel32f, bool pad) : BlurOperator(frameSize)
{
    CV_Assert(kernel32f.type() == CV_32FC1);
    double peak = 0;
    minMaxLoc(kernel32f, nullptr, &peak);
    spotGain_ = peak > 0 ? 1.0 / peak : 1.0;
    if (pad)
    {
        origin_ = Point((kernel32f.cols - 1) / 2, (kernel32f.rows - 1) / 2);
        latent_ = Size(frame_.width + kernel32f.cols - 1, frame_.height + kernel32f.rows - 1);
    }
    fft_.reset(new FftKernel(FftKernel::linearSize(latent_, kernel32f.size()), kernel32f));
}

UniformBlurOperator::~UniformBlurOperator() {}

/* A float FFT's product is exact only to its rounding: where A x is zero (every latent pixel that
   reaches the frame pixel is zero, as RL's multiplicative update keeps the start's zeros) it returns
   ±1e-8 instead, b / (A x) turns that into a ratio of 1e8 on a lit pixel, and the adjoint's rounding
   spreads it over the whole row (a 64-pixel checkerboard under two taps came back black). Values
   within the rounding are taken as zero, so the ratio there is 0 as for an exact zero; the adjoint
   then carries it only to latent pixels that are zero already, as in exact arithmetic. The rounding
   measured up to 7.4 ε·rms(x) on frames up to 1280×960 (random, half zeros); the floor is
   2·log2(grid elements)·ε·rms(x), 40 ε·rms(x) on such a grid. */
void UniformBlurOperator::forward(const Mat& latent, Mat& frame)
{
    const double rms = norm(latent, NORM_L2) / std::sqrt(double(latent.total()));
    const Size grid = fft_->transformSize();
    const double floor = 2.0 * std::log2(std::max(2.0, double(grid.area()))) * FLT_EPSILON * rms;
    if (latent_ == frame_)
        fft_->convolve(latent, frame);
    else
    {
        fft_->convolve(latent, scratch_);
        scratch_(Rect(origin_, frame_)).copyTo(frame);
    }
    const float f = float(floor);
    for (int y = 0; y < frame.rows; y++)
    {
        float* row = frame.ptr<float>(y);
        for (int x = 0; x < frame.cols; x++)
            row[x] = row[x] > f ? row[x] : 0.f;
    }
}

void UniformBlurOperator::adjoint(const Mat& frame, Mat& latent)
{
    if (latent_ == frame_)
    {
        fft_->convolve(frame, latent, true);
        return;
    }
    scratch_.create(latent_, CV_32FC1);
    scratch_.setTo(0);
    frame.copyTo(scratch_(Rect(origin_, frame_)));
    fft_->convolve(scratch_, latent, true);
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
