// SPDX-License-Identifier: Apache-2.0
// The visual-servoing samples' target: a column of AprilTags 36h11 (ids 0, 1, ...) found in an 8-bit
// frame with ViSP's vpDetectorAprilTag. ViSP stays in target_detector.cpp: this header needs OpenCV only.
#ifndef DYNBLUR_SAMPLES_TARGET_DETECTOR_HPP
#define DYNBLUR_SAMPLES_TARGET_DETECTOR_HPP

#include <opencv2/core.hpp>

#include <memory>
#include <vector>

namespace dynblur_samples {

struct Detection
{
    bool found = false;                 //!< every tag of the target was found
    int tagsFound = 0;
    cv::Point2d centre;                 //!< the target's centre, pixels (from the tags found, when tagsFound > 0)
    std::vector<std::vector<cv::Point2d>> corners;  //!< each tag found: its four corners, pixels
};

/** One detector, default settings, for the raw and the restored frames alike; one thread, so its
output does not depend on how the threads interleave (a closed loop would amplify any difference
into another trajectory). */
class TargetDetector
{
public:
    TargetDetector();
    ~TargetDetector();
    TargetDetector(const TargetDetector&) = delete;
    TargetDetector& operator=(const TargetDetector&) = delete;

    /** The target's tags in an 8-bit grey frame. Its centre is the mean of (tag centre − the tag's
    offset in the target), so a target half out of view still gives a measurement.
    @param grey8 CV_8U frame.
    @param tagOffsets tag id k's centre below the target's centre, pixels, one per tag of the target. */
    Detection detect(const cv::Mat& grey8, const std::vector<double>& tagOffsets);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace dynblur_samples

#endif
