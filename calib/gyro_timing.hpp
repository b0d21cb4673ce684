// SPDX-License-Identifier: Apache-2.0
// dynblur_calibrate_timing --gyro: the gyro log's clock offset, the line delay and the gyro bias of a
// hand-held recording (gyro_timing.cpp), and --simulate-gyro.
#ifndef DYNBLUR_CALIB_GYRO_TIMING_HPP
#define DYNBLUR_CALIB_GYRO_TIMING_HPP

#include "cli_args.hpp"  // samples/support

#include <string>

//! What --refine estimates with --gyro unless told, against stills or on a clip.
extern const char* const kGyroRefinement;

//! The gyro path's options (the gyro log's, the stills', --simulate-gyro's) under their heading.
dynblur_samples::CliOptionGroup gyroTimingOptions();
/** Calibrates the recording the options name (--gyro ...), writes the timing file and the plot;
returns the exit status. Throws as the program's main expects (std::runtime_error: usage). */
int calibrateGyroTiming(const dynblur_samples::CliArgs& args, const std::string& defaultCameraPath);
//! --simulate-gyro DIR: writes a hand-held recording with its gyro log; returns the exit status.
int simulateGyroTiming(const dynblur_samples::CliArgs& args);

#endif
