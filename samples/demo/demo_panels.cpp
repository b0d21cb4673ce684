// SPDX-License-Identifier: Apache-2.0
#include "demo_panels.hpp"

#include "frame_timing.hpp"
#include "image_metrics.hpp"

#include <opencv2/imgproc.hpp>

#include <limits>

using namespace cv;

namespace dynblur_demo {

Mat shadeUnobserved(const Mat& image, const Mat& valid)
{
    Mat shaded = image.clone(), grey(image.size(), image.type(), Scalar::all(90));
    for (int y = 0; y < image.rows; ++y)
        for (int x = 0; x < image.cols; ++x)
            if (((x + y) / 6) % 2 == 0)
                grey.at<Vec3b>(y, x) = Vec3b(140, 140, 140);
    addWeighted(image, 0.35, grey, 0.65, 0.0, grey);
    grey.copyTo(shaded, valid == 0);
    return shaded;
}

Mat labelled(const Mat& image, const std::string& text, int width)
{
    Mat small;
    resize(image, small, Size(width, image.rows * width / image.cols), 0, 0, INTER_AREA);
    if (small.channels() == 1)
        cvtColor(small, small, COLOR_GRAY2BGR);
    rectangle(small, Rect(0, 0, width, 24), Scalar(0, 0, 0), FILLED);
    putText(small, text, Point(6, 17), FONT_HERSHEY_SIMPLEX, 0.5, Scalar(255, 255, 255), 1, LINE_AA);
    return small;
}

Mat judgedPixels(const Mat& valid)
{
    Mat judged = valid.clone();
    judged(Rect(0, 0, judged.cols, 8)).setTo(0);
    judged(Rect(0, judged.rows - 8, judged.cols, 8)).setTo(0);
    return judged;
}

std::string tableRow(const std::string& name, int window, const Mat& truth, const Mat& blurred, const Mat& uniform,
                     const Mat& variant, const Mat& judged, double uniformMs, double variantMs)
{
    using dynblur_samples::maskedPsnr;
    using dynblur_samples::maskedSsim;
    return format("%-22s %6s | %7.2f dB %6.3f | %7.2f dB %6.3f | %7.2f dB %6.3f | %7.0f ms %7.0f ms", name.c_str(),
                  dynblur_samples::exposureWindowName(window), maskedPsnr(truth, blurred, judged, 255),
                  maskedSsim(truth, blurred, judged), maskedPsnr(truth, uniform, judged, 255),
                  maskedSsim(truth, uniform, judged), maskedPsnr(truth, variant, judged, 255),
                  maskedSsim(truth, variant, judged), uniformMs, variantMs);
}

BothRestorations restoreBothWays(const Mat& frame, const Ptr<cv::dynblur::CameraMotion>& motion,
                                 const Ptr<cv::dynblur::CameraModel>& camera, const cv::dynblur::RollingShutter& shutter,
                                 const cv::dynblur::RLParams& params)
{
    using namespace cv::dynblur;
    Ptr<DynamicDeblurrer> variant = DynamicDeblurrer::create(camera), uniform = DynamicDeblurrer::create(camera);
    variant->setRLParams(params);
    uniform->setRLParams(params);
    uniform->setPsfModel(PSF_UNIFORM);
    BothRestorations r;
    TickMeter uniformTimer, variantTimer;
    uniformTimer.start();
    uniform->deblur(frame, motion, shutter, r.uniform);
    uniformTimer.stop();
    variantTimer.start();
    variant->deblur(frame, motion, shutter, r.variant, std::numeric_limits<double>::quiet_NaN(), r.valid);
    variantTimer.stop();
    r.uniformMs = uniformTimer.getTimeMilli();
    r.variantMs = variantTimer.getTimeMilli();
    r.window = variant->getLastExposureWindow();
    return r;
}

}  // namespace dynblur_demo
