// SPDX-License-Identifier: Apache-2.0
// Bindings of gyro_log.hpp: GyroLogOptions, GyroLog.
#include "bindings.hpp"

#include <opencv2/dynblur/gyro_log.hpp>

namespace dynblur_py {

using namespace cv::dynblur;

void bindGyroLog(py::module_& m)
{
    // ---------------------------------------------------------------- GyroLog
    py::class_<GyroLogOptions>(m, "GyroLogOptions", "How GyroLog.load maps a log to camera axes, scales a plain CSV and "
                                                    "estimates the bias.")
        .def(py::init<>())
        .def_readwrite("orientation", &GyroLogOptions::orientation,
                       "axis string replacing the file's; empty: the gcsv file's, 'XYZ' for a plain CSV")
        .def_readwrite("cameraFromGyro", &GyroLogOptions::cameraFromGyro,
                       "3×3 rotation applied after the axis string (identity by default)")
        .def_readwrite("timeScale", &GyroLogOptions::timeScale, "seconds per unit of a plain CSV's t (gcsv: keep 1)")
        .def_readwrite("rateScale", &GyroLogOptions::rateScale,
                       "rad/s per unit of a plain CSV's gx, gy, gz; pi/180 for deg/s (gcsv: keep 1)")
        .def_readwrite("estimateBias", &GyroLogOptions::estimateBias, "estimate the bias from still intervals")
        .def_readwrite("stillThreshold", &GyroLogOptions::stillThreshold, "|ω| below this is still, rad/s")
        .def_readwrite("stillMinDuration", &GyroLogOptions::stillMinDuration,
                       "shortest still interval that counts, seconds");

    py::class_<GyroLog>(m, "GyroLog", R"doc(A gyroscope log in camera axes (Gyroflow's gcsv or a plain CSV
't,gx,gy,gz'): times (N,) seconds, rates (N, 3) rad/s as measured, bias (rad/s) subtracted by toMotion().)doc")
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
        .def_static("load", &GyroLog::load, py::arg("filename"), py::arg("options") = GyroLogOptions(),
                    "Reads a gcsv or plain CSV gyro log; raises dynblur.error naming the file, line and field.")
        .def_static("orientationMatrix", &GyroLog::orientationMatrix, py::arg("orientation"),
                    "The 3×3 matrix S of an axis string ('YxZ': camera x = gyro y, camera y = −gyro x, ...).")
        .def("estimateBias", &GyroLog::estimateBias, py::arg("stillThreshold") = 0.05,
             py::arg("stillMinDuration") = 0.5,
             "Sets and returns the bias: the mean rate where |ω| < stillThreshold (rad/s) for ≥ stillMinDuration (s).")
        .def("toMotion",
             [](const GyroLog& g, const cv::Matx33d& q0) { return shared(g.toMotion(q0)); },
             py::arg("initialOrientation") = cv::Matx33d::eye(),
             "CameraMotion.fromAngularVelocity(times, rates - bias, initialOrientation).");
}

}  // namespace dynblur_py
