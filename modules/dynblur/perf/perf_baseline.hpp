// The speed targets' reference (issue #8): Richardson–Lucy written plainly with cv::filter2D.
#ifndef DYNBLUR_PERF_BASELINE_HPP
#define DYNBLUR_PERF_BASELINE_HPP

#include <opencv2/imgproc.hpp>

namespace dynblur_perf {

//! The reference kernel: uniform, 21 pixels wide, one row.
inline cv::Mat uniformKernel21x1()
{
    return cv::Mat(1, 21, CV_32F, cv::Scalar(1.0 / 21));
}

//! `iterations` of x ← x ⊙ (k ★ (b / (k ⊛ x))) from x = b, with cv::filter2D (its own SIMD and threads).
inline void filter2DRichardsonLucy(const cv::Mat& blurred, const cv::Mat& kernel, int iterations, cv::Mat& estimate)
{
    cv::Mat flipped, reblurred, ratio, correction;
    cv::flip(kernel, flipped, -1);
    blurred.copyTo(estimate);
    for (int i = 0; i < iterations; i++)
    {
        cv::filter2D(estimate, reblurred, CV_32F, flipped, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
        cv::divide(blurred, reblurred + cv::Scalar::all(1e-12), ratio);
        cv::filter2D(ratio, correction, CV_32F, kernel, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
        cv::multiply(estimate, correction, estimate);
    }
}

}  // namespace dynblur_perf

#endif
