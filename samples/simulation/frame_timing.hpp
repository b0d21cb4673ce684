// SPDX-License-Identifier: Apache-2.0
// Choosing when a frame is taken so that it falls in a given exposure window.
#ifndef DYNBLUR_SAMPLES_FRAME_TIMING_HPP
#define DYNBLUR_SAMPLES_FRAME_TIMING_HPP

#include <opencv2/dynblur.hpp>

namespace dynblur_samples {

/** Finds a frame start (seconds) whose readout falls in exposure window `window`: the middle of
    the first run of such starts, scanned in `step` seconds from one readout before the first
    switch to `horizon` seconds after it. The middle keeps the frame clear of the run's edges,
    where a small timing error would change the window. Returns false when no start qualifies. */
bool frameStartInWindow(const cv::Ptr<cv::dynblur::Plant>& plant, const cv::dynblur::SwitchSchedule& schedule,
                        cv::dynblur::RollingShutter shutter, int window, double& frameStart, double step = 2.5e-4,
                        double horizon = 0.3);

//! "I", "II", "III", "IV" for cv::dynblur::ExposureWindow values, "?" otherwise.
const char* exposureWindowName(int window);

}  // namespace dynblur_samples

#endif
