// SPDX-License-Identifier: Apache-2.0
// A hand-held recording with a gyro log, rendered: what dynblur_calibrate_timing --simulate-gyro writes
// for its command-line test and for users to try the gyro path without a camera.
#ifndef DYNBLUR_SAMPLES_GYRO_SIMULATION_HPP
#define DYNBLUR_SAMPLES_GYRO_SIMULATION_HPP

#include <opencv2/core.hpp>

#include <string>

namespace dynblur_samples {

//! The truth of a simulated gyro recording.
struct GyroSimulation
{
    double timeOffset = 0.005;     //!< s: the log's clock is this far ahead of the camera's
    double lineDelayScale = 1.03;  //!< the true line delay over the one the frame log states
    cv::Vec3d bias{0.5 * CV_PI / 180, -0.5 * CV_PI / 180, 0.5 * CV_PI / 180};  //!< the gyro's bias, rad/s
    double seconds = 2.0;          //!< length of the recording
};

/** @brief Renders into `dir` a 320×240 rolling-shutter recording at 30 fps (10 ms exposure, a readout of
30 ms × truth.lineDelayScale) of a generated scene seen by a hand that shakes (band-limited between 2 and 17 Hz, up to
40 °/s) and holds still for 0.3 s in every 0.8 s, with a 200 Hz gyro log of the hand's rates on a clock
`truth.timeOffset` ahead, plus the bias and 0.1 °/s of noise (HandHeldSimulator): frame_%04d.png,
frames.csv (stating the nominal line delay, 30 ms / 240 rows), gyro.gcsv (Gyroflow's gcsv, deg/s and
ms), camera.xml and truth.yml. Returns the number of frames. */
int simulateGyroRecording(const std::string& dir, const GyroSimulation& truth);

}  // namespace dynblur_samples

#endif
