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

/** @brief The order in which a rolling shutter reads a frame out, as a gcsv file's
`frame_readout_direction` states it @cite GyroflowGcsv. */
enum ReadoutDirection
{
    READOUT_DIRECTION_UNKNOWN = -1,  //!< the log does not say
    READOUT_TOP_TO_BOTTOM = 0,       //!< rows, first row first (RollingShutter's model)
    READOUT_BOTTOM_TO_TOP = 1,       //!< rows, last row first
    READOUT_LEFT_TO_RIGHT = 2,       //!< columns, first column first
    READOUT_RIGHT_TO_LEFT = 3        //!< columns, last column first
};

/** @brief How GyroLog::load finds a CSV log's columns and units, maps the log to camera axes and
estimates the bias. */
struct CV_EXPORTS_W_SIMPLE GyroLogOptions
{
    CV_WRAP GyroLogOptions();

    /** Axis string replacing the file's (see GyroLog::orientationMatrix); empty: the gcsv file's
        `orientation` line, the layout's own for a CSV ("Xyz" for a phone app's, "XYZ" otherwise). */
    CV_PROP_RW String orientation;
    /** A rotation applied after the axis string: ω_camera = cameraFromGyro · S · ω_gyro, S the axis
        string's matrix. Identity by default; det must be +1 (within 1e-3). For a gyro mounted at an
        angle no axis string describes. */
    CV_PROP_RW Matx33d cameraFromGyro;
    /** Seconds per unit of a CSV log's time column, > 0 (default 1; 1e-3 for milliseconds), in place of
        the layout's unit. A gcsv file states its own (`tscale`); this must then stay 1, as it must
        when timeUnit is given. */
    CV_PROP_RW double timeScale;
    /** rad/s per unit of a CSV log's rate columns, > 0 (default 1; π/180 for deg/s), in place of the
        layout's unit. A gcsv file states its own (`gscale`); this must then stay 1, as it must when
        rateUnit is given. */
    CV_PROP_RW double rateScale;
    /** The four columns of a CSV log, comma-separated: the time, then the rates about the gyro's x, y
        and z. Each is a name from the header row (case and blanks around it ignored) or a 1-based
        position; with positions only, a first row of numbers is data (a file without a header row).
        Empty: the columns of the layout the header row names (see GyroLog). Not for gcsv. */
    CV_PROP_RW String columns;
    /** Unit of a CSV log's time column: "s", "ms", "us" (or "µs") or "ns"; empty: the layout's
        (seconds for columns given by `columns`). Not for gcsv. */
    CV_PROP_RW String timeUnit;
    /** Unit of a CSV log's rate columns: "rad/s" or "deg/s"; empty: the layout's (rad/s for columns
        given by `columns`). Not for gcsv. */
    CV_PROP_RW String rateUnit;
    /** The frame a gcsv file's axis string takes the gyro's axes to: "camera" (the default), this
        module's camera axes (x right, y down, z forward), as the project's own gcsv writers use it; or
        "gyroflow", Gyroflow's frame (x up, y left, z backward for a level camera looking forward
        @cite GyroflowOrientation), which load then takes to camera axes by the axis string "yxz".
        "gyroflow" is for gcsv files written for Gyroflow (cameras, loggers, telemetry extractors). */
    CV_PROP_RW String gcsvAxes;
    /** Seconds to subtract from the log's clock (GyroLog::timeOrigin), finite or NaN. NaN (the default):
        0 for a clock reading under 10⁶ s at the first sample, else that sample's whole second. Give
        it to put `times` on a known origin, e.g. the Unix time that frame timestamps count from. */
    CV_PROP_RW double timeOrigin;
    /** Drop a sample that repeats the previous one whole (same time, same three rates), as a logger
        re-sending a cached sample writes it (Sensor Logger's documentation warns of these); counted in
        GyroLog::droppedSamples. A repeated time with other rates is refused either way. */
    CV_PROP_RW bool dropRepeatedSamples;
    /** Estimate the gyro bias from still intervals on load (GyroLog::estimateBias). */
    CV_PROP_RW bool estimateBias;
    /** A sample is still when |ω| (camera axes, rad/s) is below this, > 0 (default 0.05 rad/s ≈ 2.9 °/s:
        above a phone's or an action camera's bias and noise at rest, below any hand-held motion). */
    CV_PROP_RW double stillThreshold;
    /** A still interval counts when it lasts at least this long, seconds, > 0 (default 0.5 s). */
    CV_PROP_RW double stillMinDuration;
};

/** @brief A gyroscope log in camera axes: what CameraMotion::fromAngularVelocity integrates.

GyroLog::load reads these layouts, told apart by the first line (gcsv) or the header row (CSV):
- `gcsv`, Gyroflow's format @cite GyroflowGcsv (version 1.x, 1.3 included): a first line
  `GYROFLOW IMU LOG` or `CAMERA IMU LOG`, then `key,value` lines: `version`, `id`, `orientation`,
  `tscale` seconds per time unit, `gscale` rad/s per gyro unit, `frame_readout_time` milliseconds,
  `frame_readout_direction` 0–3 (kept in frameReadoutTime and frameReadoutDirection); `ascale`,
  `mscale` and other metadata are read past. Then the column row `t,gx,gy,gz`, optionally followed
  by `ax,ay,az` and `mx,my,mz`, and one sample per line.
- `csv`: optional `#` comment lines, a header row whose first four columns are `t,gx,gy,gz` (further
  columns are ignored), then seconds and rad/s.
- `sensor-logger`: Sensor Logger's `Gyroscope.csv` @cite SensorLogger, a header row with `time`,
  `seconds_elapsed`, `x`, `y`, `z` (the app writes `time,seconds_elapsed,z,y,x`): `time` in
  nanoseconds of the Unix epoch, rates in rad/s about the phone's axes.
- `opencamera-sensors`: OpenCamera Sensors' `<video>_gyro.csv` @cite OpenCameraSensors, told by that
  file name and a first row of four numbers (no header row): `x,y,z,timestamp` with rates in rad/s
  about the phone's axes and the time in nanoseconds of the clock of the video's frame timestamps.
- `columns`: any other CSV, its columns and units given by GyroLogOptions::columns, timeUnit and
  rateUnit.

A phone's axes (Android's sensor frame @cite AndroidSensorAxes, which Sensor Logger also uses on iOS:
x to the right of the screen, y up, z out of the screen) are taken to camera axes by the axis string
"Xyz" (x right, y down, z forward: the back camera, phone upright in its natural orientation); a
video whose frames are stored in the sensor's orientation (rotated 90° from a portrait phone's view)
needs "yxz" (GyroLogOptions::orientation).

All are comma-separated, spaces around fields allowed. The reader refuses, with a cv::Exception
naming the file, the line and the field: an empty file, a missing first line or column row, a header
row of no known layout (the message names the layouts and the options that describe a custom CSV), a
column it names that is missing, a row with another number of fields than the header row, a field
it reads that is not a finite number, timestamps not strictly increasing, a gap longer than three
median sample intervals, fewer than two samples, an unknown or left-handed axis string, a missing or
non-positive `tscale`/`gscale`, and options out of their allowed values.

Times keep the file's precision: a clock reading 10⁶ s or more (a Unix epoch in nanoseconds) is
counted from `timeOrigin` (a whole number of seconds, or GyroLogOptions::timeOrigin), so that `times`
keep nanoseconds. The rates are
kept as measured (mapped to camera axes); `bias` is subtracted by toMotion().
*/
struct CV_EXPORTS_W_SIMPLE GyroLog
{
    CV_WRAP GyroLog();

    /** Sample times, seconds, strictly increasing: the log's clock minus timeOrigin. */
    CV_PROP_RW std::vector<double> times;
    CV_PROP_RW Mat rates;  //!< N×3 CV_64F body rates, rad/s, camera axes, bias not removed
    CV_PROP_RW Vec3d bias; //!< gyro bias, rad/s, camera axes, subtracted by toMotion(); 0 unless estimated
    /** Total duration of the still intervals the bias was estimated from, seconds (0: not estimated). */
    CV_PROP_RW double biasStillSeconds;
    /** The rotation that took the log's gyro axes to camera axes: ω_camera = cameraFromGyro · ω_gyro. */
    CV_PROP_RW Matx33d cameraFromGyro;
    CV_PROP_RW String id;           //!< a gcsv file's `id` (the logger), empty otherwise
    CV_PROP_RW String orientation;  //!< the axis string used ("XYZ" when none was given)
    /** The layout read: "gcsv", "csv", "sensor-logger", "opencamera-sensors" or "columns". */
    CV_PROP_RW String layout;
    /** Seconds subtracted from the log's clock to give `times`: GyroLogOptions::timeOrigin when given,
        else 0, or for a clock reading 10⁶ s or more at the first sample, that sample's time in whole
        seconds (so a frame timestamp t on the log's clock is t − timeOrigin here). */
    CV_PROP_RW double timeOrigin;
    /** The time a rolling shutter takes to read a whole frame, seconds, as the log states it (gcsv
        `frame_readout_time`); NaN when it does not. RollingShutter::lineDelay is this over the rows. */
    CV_PROP_RW double frameReadoutTime;
    /** The readout's order (gcsv `frame_readout_direction`, a ReadoutDirection);
        READOUT_DIRECTION_UNKNOWN when the log does not say. */
    CV_PROP_RW int frameReadoutDirection;
    /** Samples dropped as whole repeats of the previous one (GyroLogOptions::dropRepeatedSamples). */
    CV_PROP_RW int droppedSamples;

    /** @brief Reads a gyro log in one of the layouts above.
    @param filename the file.
    @param options columns and units of a CSV, axis mapping, repeated samples, bias estimation. */
    CV_WRAP static GyroLog load(const String& filename, const GyroLogOptions& options = GyroLogOptions());

    /** @brief The matrix S of an axis string, ω_camera = S · ω_gyro.

    The string has three letters, one each of x, y, z in any order and case; its i-th letter names the
    gyro axis that gives camera axis i (x right, y down, z forward), lowercase meaning that gyro axis
    points the opposite way. "XYZ" is the identity; "YxZ" gives ω_camera = (ω_gy, −ω_gx, ω_gz). A
    string whose matrix has det = −1 (e.g. "XYz") describes a mirrored, left-handed frame, which no
    mounting produces, and is refused. Gyroflow reads the same letters into its own frame (x up, y
    left, z backward @cite GyroflowOrientation): GyroLogOptions::gcsvAxes says which frame a gcsv
    file's string is meant for. Check the mapping on a recording: a pan to the right must give a
    positive ω_y.
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
    initialOrientation). Its clock is `times`' (the log's minus timeOrigin); a constant gyro–camera
    offset is the shutter's (or the refinement's) business.
    @param initialOrientation Q at the first sample, a rotation. */
    CV_WRAP Ptr<CameraMotion> toMotion(const Matx33d& initialOrientation = Matx33d::eye()) const;

    /** @brief The log with its camera axes turned as a calibration found them (TimingCalibration::
    axisCorrection, ClipTimingCalibrator): rates and bias mapped, cameraFromGyro composed.
    @param axisCorrection a rotation R: the rates become R·ω, the bias R·bias. */
    CV_WRAP GyroLog withAxisCorrection(const Matx33d& axisCorrection) const;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
