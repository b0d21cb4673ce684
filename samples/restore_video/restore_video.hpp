// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video's two paths (samples/restore_video.cpp reads the options and chooses): a
// recording whose motion is the plant's response to its command log, and one whose motion is a gyro
// log. Each returns the program's exit status; a usage error is thrown as std::runtime_error, a bad
// or unusable recording as cv::Exception, and nothing half-written stays behind either way.
#ifndef DYNBLUR_SAMPLES_RESTORE_VIDEO_HPP
#define DYNBLUR_SAMPLES_RESTORE_VIDEO_HPP

#include "cli_args.hpp"

#include <opencv2/dynblur.hpp>

#include <string>

namespace dynblur_samples {

//! --preset and --model, read before any file is opened (a usage error comes first).
struct RestorationSettings
{
    int preset, psfModel;

    explicit RestorationSettings(const CliArgs& args);
    //! The preset, then the model over the preset's PSF_AUTO.
    void apply(cv::dynblur::DynamicDeblurrer& deblurrer) const;
};

//! The camera a recording without one is restored with.
std::string defaultCameraPath();

/** @brief --recording DIR, or --video, --frames and --commands: each frame taken during a move refined
against the stills of its move and restored, still frames passed through; the video, the CSV and the
contact sheet of the most blurred frames; with --truth, each moving frame's gain. */
int restoreCommandedRecording(const CliArgs& args, const RestorationSettings& settings);

/** @brief --gyro LOG: each frame restored with the log's motion as --timing corrects it, streamed; the
video, the CSV, the contact sheet and the summary; a failure midway keeps the frames written. */
int restoreGyroRecording(const CliArgs& args, const RestorationSettings& settings);

}  // namespace dynblur_samples

#endif
