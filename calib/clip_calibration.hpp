// SPDX-License-Identifier: Apache-2.0
// dynblur_calibrate_timing --gyro on a clip in continuous motion (no still frame, or no frame log):
// ClipTimingCalibrator over a stretch of the clip, streamed (docs/hand-held.md).
#ifndef DYNBLUR_CALIB_CLIP_CALIBRATION_HPP
#define DYNBLUR_CALIB_CLIP_CALIBRATION_HPP

#include "cli_args.hpp"  // samples/support
#include "gyro_recording.hpp"

/** Calibrates the opened recording from the motion between its frames over --clip-from, --clip-seconds
(the offset within --max-offset, default 2 s; --refine), writes the timing file with the shutter it
was told (saveClipCalibration) and the offset scan's picture; returns the exit status. Throws
cv::Exception naming the file and the option (a log that covers no frame, or too few, at any offset
within the window; a log the frames contradict), std::runtime_error on bad usage. */
int calibrateClipTiming(const dynblur_samples::CliArgs& args, dynblur_samples::GyroRecording& recording);

#endif
