// SPDX-License-Identifier: Apache-2.0
// A recording whose motion is a gyro log (docs/recording-format.md, "Gyro log"; docs/hand-held.md):
// the frames with their times (a frame log, or the video's own timestamps), the camera, the log and
// the shutter as told, as dynblur_restore_video --gyro and dynblur_calibrate_timing --gyro open them;
// and the timing file of a clip's calibration.
#ifndef DYNBLUR_SAMPLES_GYRO_RECORDING_HPP
#define DYNBLUR_SAMPLES_GYRO_RECORDING_HPP

#include "cli_args.hpp"
#include "recording.hpp"
#include "video_clip.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/videoio.hpp>

#include <limits>
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

/** @brief The log --gyro names, read with gyroOptions(args), a bias given by --gyro-bias in place of
none. Throws cv::Exception prefixed "--gyro: " (the reader names the file, the line and the field),
std::runtime_error naming the option on a bad value. */
cv::dynblur::GyroLog loadGyroLog(const CliArgs& args);

//! An exposure and a line delay as told, seconds (NaN: not told), and who told each (for messages).
struct ToldShutter
{
    double exposure = std::numeric_limits<double>::quiet_NaN();
    double lineDelay = std::numeric_limits<double>::quiet_NaN();
    std::string exposureFrom, lineDelayFrom;  //!< "--exposure", "--timing 'timing.yml'", "the frame log", ...
};

/** @brief Writes a clip's calibration whole: TimingCalibration::save's fields, then the shutter it
was told (`exposure`, and `lineDelay`, the line delay its lineDelayScale scales), so that the
restorer reproduces the calibrated line delay whatever its command line tells. `path` names a YAML
file (.yml or .yaml). Throws cv::Exception naming --out when it cannot be written. */
void saveClipCalibration(const cv::dynblur::TimingCalibration& calibration, const ToldShutter& told,
                         const std::string& path);

/** @brief The shutter a timing file records (saveClipCalibration); NaN where it records none (a
calibration against still frames, whose frame log tells the shutter). */
ToldShutter toldShutterOf(const std::string& timingPath);

//! What GyroRecording::open does when nothing tells the readout.
enum class UntoldReadout
{
    Guess,  //!< half the frame period (a calibration searches from a quarter to twice it)
    Refuse  //!< a usage error naming the options that tell it
};

/** @brief A recording whose motion is a gyro log: --gyro LOG and --video V (required); the frames'
times from --frames FRAMES.csv or, without it, from the video's own timestamps (VideoClip); the
camera (--camera); the shutter as told: --exposure, --line-delay or --readout, the timing file's
record of them (--timing where the program declares it, which wins for the line delay), the gcsv
log's frame_readout_time, the frame log's columns. The frames stream: next() reads them in order.
Throws cv::Exception naming the file and the option (a video that cannot be opened or has no
timestamps, frames of another size than the camera's, an exposure or a readout longer than the
frame period, a log read out of another order than top to bottom), std::runtime_error naming the
option on bad usage. */
struct GyroRecording
{
    cv::Ptr<cv::dynblur::CameraModel> camera;
    std::string cameraPath;
    cv::dynblur::GyroLog gyro;     //!< as read, the bias of --gyro-bias (or its estimate) in `bias`
    std::string gyroPath;          //!< --gyro
    ToldShutter told;              //!< NaN where the frame log's columns tell it frame by frame
    std::string timingPath;        //!< --timing; "" when none was given
    std::vector<FrameRecord> log;  //!< --frames: every frame's record; empty: the video's own times
    std::string timeSource;        //!< where the frames' times come from, for messages
    double fps = 0;                //!< the video's rate: the stream's, or the frame log's

    static void open(const CliArgs& args, const std::string& defaultCameraPath, UntoldReadout untold,
                     GyroRecording& recording);
    /** The next frame (as read: CV_8UC3) and its record (index in the video, start on the video's clock,
        the shutter as told); false after the last. Throws cv::Exception naming the option for a frame
        the video does not hold, one of another size, or a timestamp out of order. */
    bool next(cv::Mat& image, FrameRecord& record);
    //! The frame's shutter as told.
    cv::dynblur::RollingShutter shutterOf(const FrameRecord& record) const;
    //! "exposure 10 ms (--exposure), line delay 41.67 us, readout 20.00 ms (a guess: ...)".
    std::string toldText() const;

private:
    VideoClip clip_;
    cv::VideoCapture video_;  // with --frames
    size_t logNext_ = 0;
    int position_ = 0;
};

}  // namespace dynblur_samples

#endif
