// SPDX-License-Identifier: Apache-2.0
// dynblur_calibrate_timing's picture: the calibration's objective against the clock offset around its
// result (the plant path and the gyro path draw the same one).
#ifndef DYNBLUR_CALIB_OBJECTIVE_PLOT_HPP
#define DYNBLUR_CALIB_OBJECTIVE_PLOT_HPP

#include <opencv2/dynblur/refinement.hpp>

#include <string>

/** Writes `t`'s scanned objective (mean squared residual, noise²) against the offset (ms) to `path`
whole or not at all, titled `title`, the curve labelled `curve`; prints the path. Throws
cv::Exception when it cannot be written. */
void writeObjectivePlot(const cv::dynblur::TimingCalibration& t, const std::string& title, const std::string& curve,
                        const std::string& path);

#endif
