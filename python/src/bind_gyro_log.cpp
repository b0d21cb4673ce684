// SPDX-License-Identifier: Apache-2.0
// Bindings of gyro_log.hpp: GyroLogOptions, GyroLog.
#include "bindings.hpp"

#include <opencv2/dynblur/gyro_log.hpp>

namespace dynblur_py {

using namespace cv::dynblur;

void bindGyroLog(py::module_& m)
{
    // ---------------------------------------------------------------- GyroLog
    m.attr("READOUT_DIRECTION_UNKNOWN") = int(READOUT_DIRECTION_UNKNOWN);
    m.attr("READOUT_TOP_TO_BOTTOM") = int(READOUT_TOP_TO_BOTTOM);
    m.attr("READOUT_BOTTOM_TO_TOP") = int(READOUT_BOTTOM_TO_TOP);
    m.attr("READOUT_LEFT_TO_RIGHT") = int(READOUT_LEFT_TO_RIGHT);
    m.attr("READOUT_RIGHT_TO_LEFT") = int(READOUT_RIGHT_TO_LEFT);

    py::class_<GyroLogOptions>(m, "GyroLogOptions", "How GyroLog.load finds a CSV log's columns and units, maps the log "
                                                    "to camera axes and estimates the bias.")
        .def(py::init<>())
        .def_readwrite("orientation", &GyroLogOptions::orientation,
                       "axis string replacing the file's; empty: the gcsv file's, 'XYZ' for a plain CSV")
        .def_readwrite("cameraFromGyro", &GyroLogOptions::cameraFromGyro,
                       "3×3 rotation applied after the axis string (identity by default)")
        .def_readwrite("timeScale", &GyroLogOptions::timeScale,
                       "seconds per unit of a CSV log's time column, in place of the layout's (gcsv: keep 1)")
        .def_readwrite("rateScale", &GyroLogOptions::rateScale,
                       "rad/s per unit of a CSV log's rates; pi/180 for deg/s (gcsv: keep 1)")
        .def_readwrite("columns", &GyroLogOptions::columns,
                       "a CSV log's time, x, y, z rate columns: header names or 1-based positions, e.g. 'time,x,y,z' or "
                       "'4,1,2,3'; empty: told by the header row")
        .def_readwrite("timeUnit", &GyroLogOptions::timeUnit, "a CSV log's time unit: 's', 'ms', 'us', 'ns'; empty: the "
                                                              "layout's")
        .def_readwrite("rateUnit", &GyroLogOptions::rateUnit, "a CSV log's rate unit: 'rad/s', 'deg/s'; empty: the layout's")
        .def_readwrite("gcsvAxes", &GyroLogOptions::gcsvAxes,
                       "what a gcsv axis string maps to: 'camera' (x right, y down, z forward) or 'gyroflow' (x up, y "
                       "left, z backward)")
        .def_readwrite("timeOrigin", &GyroLogOptions::timeOrigin,
                       "seconds to subtract from the log's clock; NaN (default): 0 below 1e6 s, else the first "
                       "sample's whole second")
        .def_readwrite("dropRepeatedSamples", &GyroLogOptions::dropRepeatedSamples,
                       "drop a sample repeating the previous one whole (time and rates)")
        .def_readwrite("estimateBias", &GyroLogOptions::estimateBias, "estimate the bias from still intervals")
        .def_readwrite("stillThreshold", &GyroLogOptions::stillThreshold, "|ω| below this is still, rad/s")
        .def_readwrite("stillMinDuration", &GyroLogOptions::stillMinDuration,
                       "shortest still interval that counts, seconds");

    py::class_<GyroLog>(m, "GyroLog", R"doc(A gyroscope log in camera axes (Gyroflow's gcsv, CSV 't,gx,gy,gz', Sensor
Logger's Gyroscope.csv, OpenCamera Sensors' <video>_gyro.csv, or a CSV described by GyroLogOptions): times (N,)
seconds from timeOrigin, rates (N, 3) rad/s as measured, bias (rad/s) subtracted by toMotion(). GyroLog.fromVideo
reads the gyro a video embeds (telemetry-parser).)doc")
        .def(py::init<>())
        .def_property(
            "times", [](const GyroLog& g) { return py::array_t<double>(py::ssize_t(g.times.size()), g.times.data()); },
            [](GyroLog& g, py::handle a) {
                Doubles keep;
                const cv::Mat t = timesArg(a, keep);
                g.times.assign(t.ptr<double>(), t.ptr<double>() + t.rows);
            },
            "sample times, seconds, (N,) (a copy: assign a new array to change them)")
        .def_property(
            "rates", [](const GyroLog& g) { return fromMat(g.rates.clone()); },
            [](GyroLog& g, py::handle a) {
                Doubles keep;
                g.rates = rowsArg(a, keep, "rates", {3}, "(N, 3): rad/s, camera axes").clone();
            },
            "body rates, rad/s, camera axes, (N, 3), bias not removed (a copy: assign a new array to change them)")
        .def_readwrite("bias", &GyroLog::bias, "gyro bias, rad/s, camera axes (subtracted by toMotion)")
        .def_readwrite("biasStillSeconds", &GyroLog::biasStillSeconds,
                       "duration of the still intervals the bias came from, seconds (0: not estimated)")
        .def_readwrite("cameraFromGyro", &GyroLog::cameraFromGyro, "ω_camera = cameraFromGyro · ω_gyro (3×3)")
        .def_readwrite("id", &GyroLog::id, "a gcsv file's id")
        .def_readwrite("orientation", &GyroLog::orientation, "the axis string used")
        .def_readwrite("layout", &GyroLog::layout,
                       "the layout read: 'gcsv', 'csv', 'sensor-logger', 'opencamera-sensors' or 'columns'")
        .def_readwrite("timeOrigin", &GyroLog::timeOrigin,
                       "seconds subtracted from the log's clock to give times (0, or whole seconds for a clock >= 1e6 s)")
        .def_readwrite("frameReadoutTime", &GyroLog::frameReadoutTime,
                       "a rolling shutter's whole-frame readout time, seconds, as the log states it; NaN when it does not")
        .def_readwrite("frameReadoutDirection", &GyroLog::frameReadoutDirection,
                       "READOUT_TOP_TO_BOTTOM .. READOUT_RIGHT_TO_LEFT, or READOUT_DIRECTION_UNKNOWN")
        .def_readwrite("droppedSamples", &GyroLog::droppedSamples, "whole repeats dropped (dropRepeatedSamples)")
        .def_static("load", &GyroLog::load, py::arg("filename"), py::arg("options") = GyroLogOptions(),
                    "Reads a gyro log (gcsv, CSV, a phone app's CSV); raises dynblur.error naming the file, line and "
                    "field.")
        .def_static("orientationMatrix", &GyroLog::orientationMatrix, py::arg("orientation"),
                    "The 3×3 matrix S of an axis string ('YxZ': camera x = gyro y, camera y = −gyro x, ...).")
        .def("estimateBias", &GyroLog::estimateBias, py::arg("stillThreshold") = 0.05,
             py::arg("stillMinDuration") = 0.5,
             "Sets and returns the bias: the mean rate where |ω| < stillThreshold (rad/s) for ≥ stillMinDuration (s).")
        .def("toMotion",
             [](const GyroLog& g, const cv::Matx33d& q0) { return shared(g.toMotion(q0)); },
             py::arg("initialOrientation") = cv::Matx33d::eye(),
             "CameraMotion.fromAngularVelocity(times, rates - bias, initialOrientation).")
        .def("withAxisCorrection", &GyroLog::withAxisCorrection, py::arg("axisCorrection"),
             "The log with its camera axes turned as a calibration found them (TimingCalibration.axisCorrection).");
}

}  // namespace dynblur_py
