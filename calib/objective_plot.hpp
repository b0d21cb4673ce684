// SPDX-License-Identifier: Apache-2.0
// dynblur_calibrate_timing's picture: the calibration's objective against the clock offset around its
// result (the plant path and the gyro path against stills draw the same one), or, for a clip in
// continuous motion, the share of the image's turn the log explains at each offset.
#ifndef DYNBLUR_CALIB_OBJECTIVE_PLOT_HPP
#define DYNBLUR_CALIB_OBJECTIVE_PLOT_HPP

#include <opencv2/dynblur/refinement.hpp>

#include <string>

/** Writes `t`'s scanned objective (mean squared residual, noise²) against the offset (ms) to `path`
whole or not at all, titled `title`, the curve labelled `curve`; prints the path. Throws
cv::Exception when it cannot be written. */
void writeObjectivePlot(const cv::dynblur::TimingCalibration& t, const std::string& title, const std::string& curve,
                        const std::string& path);

/** Writes a clip calibration's scan (ClipTimingCalibrator: the share of the image's turn the log
explains against the offset, TimingCalibration::scanObjective) to `path` whole or not at all: the
whole window searched above, the 50 ms around the offset found below; prints the path. Throws
cv::Exception when it cannot be written. */
void writeOffsetScanPlot(const cv::dynblur::TimingCalibration& t, const std::string& title, const std::string& path);

#endif
