// SPDX-License-Identifier: Apache-2.0
// A recording whose motion is a gyro log (docs/recording-format.md, "Gyro log"): the frames, their
// frame log, the camera and the log, as dynblur_restore_video --gyro and dynblur_calibrate_timing
// --gyro open them, and the frames that serve as stills.
#ifndef DYNBLUR_SAMPLES_GYRO_RECORDING_HPP
#define DYNBLUR_SAMPLES_GYRO_RECORDING_HPP

#include "cli_args.hpp"
#include "recording.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/videoio.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {

/** @brief --gyro LOG and the options gyroOptions reads, under `heading` and `text` (the program's
gyro mode). */
CliOptionGroup gyroLogOptions(const std::string& heading, const std::string& text);

/** @brief The gyro log's reading options from --gyro-orientation STR, --gyro-columns T,X,Y,Z,
--gyro-time-unit s|ms|us|ns, --gyro-rate-unit rad/s|deg/s, --gyro-gcsv-axes camera|gyroflow,
--gyro-time-origin S, --gyro-drop-repeats and --gyro-bias estimate|none|BX,BY,BZ (rad/s, camera axes; `estimate`: from
still intervals of at least --gyro-still-seconds S). Throws std::runtime_error naming the option on
a bad value; `bias` receives a given bias (else 0). */
cv::dynblur::GyroLogOptions gyroOptions(const CliArgs& args, cv::Vec3d& bias);

/** @brief A recording whose motion is a gyro log: --gyro LOG, --video, --frames (all required),
--camera, --exposure, --line-delay, the options of gyroOptions, and --timing where the program
declares it. Throws
cv::Exception naming the file and what is wrong (a frame outside the log's time span included),
std::runtime_error naming the option on bad usage. */
struct GyroRecording
{
    std::vector<FrameRecord> log;
    cv::Ptr<cv::dynblur::CameraModel> camera;
    cv::dynblur::GyroLog gyro;
    cv::Ptr<cv::dynblur::CameraMotion> motion;  //!< the log's motion, its bias removed
    std::string timingPath;                     //!< --timing, or DIR/timing.yml when present; "" otherwise
    cv::VideoCapture video;
    int position = 0;

    static void open(const CliArgs& args, const std::string& defaultCameraPath, GyroRecording& recording);
    //! The image of `record`, read after those of the previous records.
    cv::Mat read(const FrameRecord& record);
    //! The frame's shutter as logged.
    static cv::dynblur::RollingShutter shutterOf(const FrameRecord& record, int rows);
    /** The largest rate of the log's motion over the frame's readout (rad/s, sampled every 0.5 ms),
        or +inf when the readout lies outside the log. */
    double peakRate(const FrameRecord& record) const;
};

}  // namespace dynblur_samples

#endif
