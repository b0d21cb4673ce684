// SPDX-License-Identifier: Apache-2.0
// A simulated hand-held clip put on disk as a device would: the video (constant frame rate, frame k
// at k / fps, its start on the camera's clock), the gyro log in a chosen layout and units, the camera
// (ViSP XML), a frame log, and the truth (YAML) the device would not know.
#ifndef DYNBLUR_SAMPLES_CLIP_WRITER_HPP
#define DYNBLUR_SAMPLES_CLIP_WRITER_HPP

#include "handheld_clip.hpp"

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace dynblur_samples {

//! The layouts of a gyro log.
enum class GyroFormat
{
    Gcsv,         //!< Gyroflow's gcsv: header lines (orientation, tscale, gscale), then t,gx,gy,gz
    Csv,          //!< plain CSV: a `#` line stating the units, the header t,gx,gy,gz, then samples
    SensorLogger  //!< the Sensor Logger app's Gyroscope.csv: time,seconds_elapsed,z,y,x (ns since the epoch; rad/s)
};

//! "gcsv", "csv", "sensor-logger".
const char* gyroFormatName(GyroFormat format);
//! The inverse of gyroFormatName; throws cv::Exception naming the allowed names.
GyroFormat gyroFormatFromName(const std::string& name);

//! How a gyro log is written.
struct GyroFileOptions
{
    GyroFormat format = GyroFormat::Gcsv;
    /** The axis string (GyroLog::orientationMatrix) S that takes the sensor's axes to the camera's,
    ω_camera = S·ω_sensor: the file holds Sᵀ·ω_camera; gcsv states it on its `orientation` line. */
    std::string axes = "XYZ";
    double timeUnit = 1e-3;          //!< seconds per unit of `t` (gcsv: tscale; csv), > 0
    double rateUnit = CV_PI / 180;   //!< rad/s per unit of gx, gy, gz (gcsv: gscale; csv), > 0
    double logEpoch = 1.7e9;         //!< Sensor Logger: Unix time of the log clock's zero, seconds, ≥ 0
};

/** @brief Writes a gyro log (camera axes, GyroLog::times on the log's clock) whole (temporary file
renamed into place). Throws cv::Exception naming the file or the option out of range. Sensor Logger's
`time` is logEpoch + t in integer nanoseconds, its `seconds_elapsed` t minus the first sample's t. */
void writeGyroLog(const cv::dynblur::GyroLog& log, const std::string& path, const GyroFileOptions& options);

//! Where and how a clip is written, in one folder.
struct ClipFiles
{
    /** The video's file name: .avi (MJPG), .mp4 (mp4v), or an image sequence whose name holds a
    printf integer (frame_%04d.png; .png, .tif, .bmp: lossless). */
    std::string video = "clip.avi";
    //! The truth views (ClipFrame::truth) as an image sequence (truth_%04d.png); "": not written.
    std::string truth;
    GyroFileOptions gyro;
    //! The gyro log's name; "": gyro.gcsv, gyro.csv or Gyroscope.csv by format.
    std::string gyroName;
    int videoQuality = 95;  //!< MJPG quality, in [1, 100]
    bool frameLog = true;   //!< also frames.csv (frame, frame_start, exposure, line_delay; docs/recording-format.md)
    //! The line delay frames.csv states, seconds (a nominal value that differs from the truth); NaN: the true one.
    double frameLogLineDelay = std::numeric_limits<double>::quiet_NaN();

    /** Throws cv::Exception naming the field ("ClipFiles.video", "ClipFiles.gyro.axes", ...) that is out of
    range or names no format; writeClip checks it before rendering. */
    void validate() const;
};

//! What writeClip wrote, and what it measured.
struct WrittenClip
{
    std::vector<std::string> paths;  //!< every file written, the video first
    double minBlurPx = 0, maxBlurPx = 0;  //!< over the frames (FrameTruth::blurPx)
    double renderSeconds = 0;        //!< wall time spent rendering frames (not encoding or writing)
};

/** @brief Renders every frame of `simulator` (one at a time) into the video (and its truth view into
ClipFiles::truth when named), then writes the gyro log,
camera.xml, frames.csv and truth.yml (the description, the reached peak rate and margin, the gyro's
offset, bias, scale, axes and units, the translation, and per frame its start, reference time, blur
and stillness). Every file is written whole, the video last (a temporary file renamed into place once
the others are written): a folder whose video is there holds the whole clip. An image sequence's
frames are each written whole as they come. `progress` is called after each frame.
@param simulator the clip. @param dir an existing folder. @param files names and formats.
@param progress called with each rendered frame (may be empty). */
WrittenClip writeClip(const HandHeldSimulator& simulator, const std::string& dir, const ClipFiles& files,
                      const std::function<void(const ClipFrame&, double renderSeconds)>& progress = {});

}  // namespace dynblur_samples

#endif
