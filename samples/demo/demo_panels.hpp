// SPDX-License-Identifier: Apache-2.0
// What the demo's rows share: the pictures of a restored frame beside its input and truth, the pixels
// they are judged on, and the table row that scores them.
#ifndef DYNBLUR_SAMPLES_DEMO_PANELS_HPP
#define DYNBLUR_SAMPLES_DEMO_PANELS_HPP

#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

namespace dynblur_demo {

//! Pixels the frame never observed, hatched so nobody mistakes the fill for restored content.
cv::Mat shadeUnobserved(const cv::Mat& image, const cv::Mat& valid);

//! `image` scaled to `width` pixels with `text` on a black band at its top.
cv::Mat labelled(const cv::Mat& image, const std::string& text, int width);

//! The pixels a restoration is judged on: those the frame observed (`valid`), away from its top and bottom edges.
cv::Mat judgedPixels(const cv::Mat& valid);

/** One row of the demo's table: the frame, its exposure window, PSNR and SSIM of the blurred frame,
the seed's single PSF and the spatially variant restoration against `truth` over `judged`, and the two
restorations' times, milliseconds. */
std::string tableRow(const std::string& name, int window, const cv::Mat& truth, const cv::Mat& blurred,
                     const cv::Mat& uniform, const cv::Mat& variant, const cv::Mat& judged, double uniformMs,
                     double variantMs);

//! A frame restored twice from its motion, with the seed's single PSF and the spatially variant default.
struct BothRestorations
{
    cv::Mat uniform, variant, valid;  //!< valid: the variant's observed pixels
    double uniformMs = 0, variantMs = 0;
    int window = 0;                   //!< the frame's exposure window
};

//! `frame` restored from `motion` both ways, with `params` (the RL settings) and the reference view at tRef NaN.
BothRestorations restoreBothWays(const cv::Mat& frame, const cv::Ptr<cv::dynblur::CameraMotion>& motion,
                                 const cv::Ptr<cv::dynblur::CameraModel>& camera,
                                 const cv::dynblur::RollingShutter& shutter, const cv::dynblur::RLParams& params);

/* A diagonal saccade of a pan-tilt head: 10 deg pan and 6 deg tilt together (MountPlanner, robust), each
   axis the seed's positioner, recorded by `camera` through a rolling shutter while every row moves and
   restored with the seed's single PSF and with the head's exact motion. Appends a panel row (blurred,
   with the paths its points blur along | single PSF | restored | truth) and a table row. */
void runPanTilt(const cv::Ptr<cv::dynblur::CameraModel>& camera, const cv::Mat& scene, double exposure,
                double lineDelay, const cv::dynblur::RLParams& params, std::vector<cv::Mat>& panelRows,
                std::vector<std::string>& tableRows);

}  // namespace dynblur_demo

#endif
