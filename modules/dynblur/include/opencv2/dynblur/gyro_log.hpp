// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_GYRO_LOG_HPP
#define OPENCV_DYNBLUR_GYRO_LOG_HPP

#include <opencv2/core.hpp>
#include <opencv2/dynblur/camera_motion.hpp>

#include <vector>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

/** @brief How GyroLog::load maps a log to camera axes, scales a plain CSV and estimates the bias. */
struct CV_EXPORTS_W_SIMPLE GyroLogOptions
{
    CV_WRAP GyroLogOptions();

    /** Axis string replacing the file's (see GyroLog::orientationMatrix); empty: the gcsv file's
        `orientation` line, "XYZ" for a plain CSV. */
    CV_PROP_RW String orientation;
    /** A rotation applied after the axis string: ω_camera = cameraFromGyro · S · ω_gyro, S the axis
        string's matrix. Identity by default; det must be +1 (within 1e-3). For a gyro mounted at an
        angle no axis string describes. */
    CV_PROP_RW Matx33d cameraFromGyro;
    /** Seconds per unit of a plain CSV's `t` column, > 0 (default 1; 1e-3 for milliseconds). A gcsv
        file states its own (`tscale`); this must then stay 1. */
    CV_PROP_RW double timeScale;
    /** rad/s per unit of a plain CSV's `gx, gy, gz`, > 0 (default 1; π/180 for deg/s). A gcsv file
        states its own (`gscale`); this must then stay 1. */
    CV_PROP_RW double rateScale;
    /** Estimate the gyro bias from still intervals on load (GyroLog::estimateBias). */
    CV_PROP_RW bool estimateBias;
    /** A sample is still when |ω| (camera axes, rad/s) is below this, > 0 (default 0.05 rad/s ≈ 2.9 °/s:
        above a phone's or an action camera's bias and noise at rest, below any hand-held motion). */
    CV_PROP_RW double stillThreshold;
    /** A still interval counts when it lasts at least this long, seconds, > 0 (default 0.5 s). */
    CV_PROP_RW double stillMinDuration;
};

/** @brief A gyroscope log in camera axes: what CameraMotion::fromAngularVelocity integrates.

Read from two text forms (GyroLog::load):
- Gyroflow's `gcsv` @cite GyroflowGcsv (version 1.x, 1.3 included): a first line `GYROFLOW IMU LOG` or `CAMERA IMU LOG`, then
  `key,value` lines (`version`, `id`, `orientation`, `tscale` seconds per time unit, `gscale` rad/s per
  gyro unit, `ascale`, `mscale` and any other metadata, which is ignored), then the column row
  `t,gx,gy,gz`, optionally followed by `ax,ay,az` and `mx,my,mz`, then one sample per line. Time is
  t·tscale seconds, the rate (gx, gy, gz)·gscale rad/s in the gyro's axes.
- plain CSV: optional `#` comment lines, a header row whose first four columns are `t,gx,gy,gz`
  (further columns are ignored), then one sample per line: seconds and rad/s unless
  GyroLogOptions::timeScale / rateScale say otherwise (rateScale = π/180 for deg/s).

Both are comma-separated, spaces around fields allowed. The reader refuses, with a cv::Exception
naming the file, the line and the field: an empty file, a missing first line or column row, a row
with another number of fields than the column row, a field that is not a finite number, timestamps
not strictly increasing, a gap longer than three median sample intervals, fewer than two samples,
an unknown or left-handed axis string, a missing or non-positive `tscale`/`gscale`.

The rates are kept as measured (mapped to camera axes); `bias` is subtracted by toMotion().
*/
struct CV_EXPORTS_W_SIMPLE GyroLog
{
    CV_WRAP GyroLog();

    CV_PROP_RW std::vector<double> times;  //!< sample times, seconds, strictly increasing (the log's clock)
    CV_PROP_RW Mat rates;                  //!< N×3 CV_64F body rates, rad/s, camera axes, bias not removed
    CV_PROP_RW Vec3d bias;                 //!< gyro bias, rad/s, camera axes, subtracted by toMotion(); 0 unless estimated
    /** Total duration of the still intervals the bias was estimated from, seconds (0: not estimated). */
    CV_PROP_RW double biasStillSeconds;
    /** The rotation that took the log's gyro axes to camera axes: ω_camera = cameraFromGyro · ω_gyro. */
    CV_PROP_RW Matx33d cameraFromGyro;
    CV_PROP_RW String id;           //!< a gcsv file's `id` (the logger), empty otherwise
    CV_PROP_RW String orientation;  //!< the axis string used ("XYZ" when none was given)

    /** @brief Reads a gcsv or plain CSV gyro log (the form is told by the first line).
    @param filename the file.
    @param options axis mapping, plain-CSV scales, bias estimation. */
    CV_WRAP static GyroLog load(const String& filename, const GyroLogOptions& options = GyroLogOptions());

    /** @brief The matrix S of an axis string, ω_camera = S · ω_gyro.

    The string has three letters, one each of x, y, z in any order and case; its i-th letter names the
    gyro axis that gives camera axis i (x right, y down, z forward), lowercase meaning that gyro axis
    points the opposite way. "XYZ" is the identity; "YxZ" gives ω_camera = (ω_gy, −ω_gx, ω_gz). A
    string whose matrix has det = −1 (e.g. "XYz") describes a mirrored, left-handed frame, which no
    mounting produces, and is refused. Gyroflow reads the same letters; whether its camera frame is this
    module's (x right, y down, z forward) is not stated in the format's description, so check the
    mapping on a recording: a pan to the right must give a positive ω_y.
    @param orientation the axis string. */
    CV_WRAP static Matx33d orientationMatrix(const String& orientation);

    /** @brief Estimates the bias as the mean rate over the still intervals: runs of consecutive
    samples with |ω| < stillThreshold lasting at least stillMinDuration. Sets `bias` and
    `biasStillSeconds`; throws when there is none (naming both parameters and the longest run).
    @param stillThreshold rad/s, > 0; it must exceed the bias plus the noise at rest.
    @param stillMinDuration seconds, > 0.
    @return the bias, rad/s, camera axes. */
    CV_WRAP Vec3d estimateBias(double stillThreshold = 0.05, double stillMinDuration = 0.5);

    /** @brief The motion of the log: CameraMotion::fromAngularVelocity(times, rates − bias,
    initialOrientation). Its clock is the log's; a constant gyro–camera offset is the shutter's (or
    the refinement's) business.
    @param initialOrientation Q at the first sample, a rotation. */
    CV_WRAP Ptr<CameraMotion> toMotion(const Matx33d& initialOrientation = Matx33d::eye()) const;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
