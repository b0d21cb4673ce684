// SPDX-License-Identifier: Apache-2.0
// Image quality over a region: PSNR and SSIM restricted to a mask, so restorations are judged
// only where the frame observed the scene. Used by the demo and by the quality tests.
#ifndef DYNBLUR_SAMPLES_IMAGE_METRICS_HPP
#define DYNBLUR_SAMPLES_IMAGE_METRICS_HPP

#include <opencv2/core.hpp>
#include <opencv2/quality/qualityssim.hpp>

#include <cmath>
#include <limits>

namespace dynblur_samples {

/** PSNR in dB of `test` against `reference` (same size and type, values in [0, peak]) over the
    non-zero pixels of `mask` (CV_8U, empty: everywhere). */
inline double maskedPsnr(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask = cv::Mat(),
                         double peak = 1.0)
{
    CV_Assert(reference.size() == test.size() && reference.type() == test.type());
    cv::Mat difference;
    cv::absdiff(reference, test, difference);
    difference.convertTo(difference, CV_64F);
    difference = difference.mul(difference);
    const cv::Scalar sum = cv::sum(mask.empty() ? difference : difference.setTo(0, mask == 0));
    const double pixels = mask.empty() ? static_cast<double>(reference.total()) : cv::countNonZero(mask);
    double squared = 0;
    for (int c = 0; c < reference.channels(); ++c)
        squared += sum[c];
    const double mse = squared / (pixels * reference.channels());
    return mse > 0 ? 10.0 * std::log10(peak * peak / mse) : std::numeric_limits<double>::infinity();
}

/** Mean SSIM (Wang et al. 2004, OpenCV's quality module) over the non-zero pixels of `mask`,
    averaged over channels. SSIM's constants assume a 0..255 range: pass 8-bit images (or floats scaled to it). */
inline double maskedSsim(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask = cv::Mat())
{
    CV_Assert(reference.size() == test.size() && reference.type() == test.type());
    cv::Mat map;
    cv::quality::QualitySSIM::compute(reference, test, map);
    const cv::Scalar mean = cv::mean(map, mask);
    double total = 0;
    for (int c = 0; c < reference.channels(); ++c)
        total += mean[c];
    return total / reference.channels();
}

}  // namespace dynblur_samples

#endif
