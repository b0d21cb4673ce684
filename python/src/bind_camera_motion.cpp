// SPDX-License-Identifier: Apache-2.0
// Bindings of camera_motion.hpp, mount.hpp and gyro_log.hpp.
#include "bindings.hpp"

#include <opencv2/dynblur/camera_motion.hpp>
#include <opencv2/dynblur/gyro_log.hpp>
#include <opencv2/dynblur/mount.hpp>

#include <sstream>

namespace dynblur_py {

using namespace cv::dynblur;

void bindCameraMotion(py::module_& m)
{
    // ---------------------------------------------------------------- CameraMotion
    py::class_<CameraMotion, std::shared_ptr<CameraMotion>>(m, "CameraMotion", R"doc(How the camera turns over time:
any rotation, from a plant's response to its schedule or from measurements.

Q(t) is the camera frame (x right, y down, z forward) in the mount's base frame; it evolves with the
body rates ω (rad/s, camera frame, as a gyroscope fixed to the camera measures them):
dQ/dt = Q·[ω]×. The view at t relative to Q_ref is R(t) = Q_refᵀ·Q(t). Made by fromPlant,
fromAngularVelocity or fromOrientations.)doc")
        .def("orientation", &CameraMotion::orientation, py::arg("t"),
             "Q(t), a 3×3 rotation (numpy float64); t in seconds within getTimeSpan().")
        .def("angularVelocity", &CameraMotion::angularVelocity, py::arg("t"),
             "Body rates ω(t), rad/s, camera frame, as a tuple; t in seconds within getTimeSpan().")
        .def("getTimeSpan", &CameraMotion::getTimeSpan,
             "(start, end), seconds: a sampled motion's first and last sample, (-inf, inf) for a plant's.")
        .def("referenceOrientation", &CameraMotion::referenceOrientation, py::arg("tRef"), py::arg("shutter"),
             R"doc(The reference orientation Q_ref of a frame (3×3). tRef: seconds, or NaN for the default: a plant
motion's final rest, a sampled motion's orientation at the middle row's mid-exposure of `shutter`.)doc")
        .def("isPlantMotion", &CameraMotion::isPlantMotion, "True for a motion made by fromPlant.")
        .def("relativeRotation", &CameraMotion::relativeRotation, py::arg("t"), py::arg("reference"),
             "R(t) = referenceᵀ·Q(t), 3×3; t in seconds.")
        .def_static(
            "fromPlant",
            [](const std::shared_ptr<Plant>& plant, const SwitchSchedule& schedule, const cv::Vec3d& axis) {
                return shared(CameraMotion::fromPlant(required(plant, "plant"), schedule, axis));
            },
            py::arg("plant"), py::arg("schedule"), py::arg("axis") = cv::Vec3d(1, 0, 0),
            R"doc(The motion of a one-axis positioner: Q(t) = R_axis(θ(t)), θ the plant's response to the schedule.
axis: the rotation axis in the camera frame, non-zero (normalised); default (1, 0, 0), tilt.)doc")
        .def_static(
            "fromAngularVelocity",
            [](py::handle times, py::handle rates, const cv::Matx33d& initialOrientation) {
                Doubles t, w;
                const cv::Mat tm = timesArg(times, t);
                const cv::Mat wm = rowsArg(rates, w, "rates", {3}, "(N, 3): body rates, rad/s, camera axes");
                return shared(CameraMotion::fromAngularVelocity(tm, wm, initialOrientation));
            },
            py::arg("times"), py::arg("rates"), py::arg("initialOrientation") = cv::Matx33d::eye(),
            R"doc(A motion measured by a gyroscope: times (N,) seconds, strictly increasing, N ≥ 2, no gap over three
median intervals; rates (N, 3) rad/s in camera axes; initialOrientation: Q at the first sample (3×3
rotation). Rates are linear between samples, integrated by the 4th-order Magnus step.)doc")
        .def_static(
            "fromOrientations",
            [](py::handle times, py::handle rotations) {
                Doubles t, r;
                const cv::Mat tm = timesArg(times, t);
                const cv::Mat rm = rowsArg(rotations, r, "rotations", {3, 4, 9},
                                           "(N, 3) rotation vectors, (N, 4) unit quaternions (w, x, y, z), (N, 9) "
                                           "row-major or (N, 3, 3) rotation matrices");
                return shared(CameraMotion::fromOrientations(tm, rm));
            },
            py::arg("times"), py::arg("rotations"),
            R"doc(A motion measured as orientations (encoders, motion capture, a pose stream), joined by a C¹ cubic on
SO(3). times (N,) seconds as for fromAngularVelocity; rotations: (N, 3) rotation vectors (rad), (N, 4)
unit quaternions (w, x, y, z), (N, 9) row-major or (N, 3, 3) rotation matrices.)doc")
        .def("__repr__", [](const CameraMotion& c) {
            const cv::Vec2d span = c.getTimeSpan();
            std::ostringstream o;
            o << "<CameraMotion " << c.getDefaultName() << " over [" << span[0] << ", " << span[1] << "] s>";
            return o.str();
        });

    m.def("classifyExposure",
          [](const std::shared_ptr<CameraMotion>& motion, const RollingShutter& sh, double a, double v) {
              if (!motion)
                  throw py::value_error("argument 'motion' is None");
              return classifyExposure(cv::Ptr<CameraMotion>(motion), sh, a, v);
          },
          py::arg("motion"), py::arg("shutter"), py::arg("angleTol") = 2e-4, py::arg("velocityTol") = 0.02,
          R"doc(The exposure window of a frame for any camera motion: a plant's motion as the plant form; any
other is "moving" where its rate |ω| exceeds velocityTol (rad/s), sampled every 0.25 ms.)doc");

    // ---------------------------------------------------------------- Mount
    py::class_<Mount, std::shared_ptr<Mount>>(m, "Mount", R"doc(A chain of rotation axes, each turned by its own plant (a pan-tilt
head, a gimbal): Q(q) = R_a1(q1)·R_a2(q2)·…, axes in the camera frame at rest, base first.)doc")
        .def_static("create", [] { return std::shared_ptr<Mount>(Mount::create()); },
                    "An empty chain: add its axes with addAxis, base first.")
        .def(
            "addAxis",
            [](Mount& self, const cv::Vec3d& axis, const std::shared_ptr<Plant>& plant, int minLevel, int maxLevel) {
                self.addAxis(axis, required(plant, "plant"), minLevel, maxLevel);
            },
            py::arg("axis"), py::arg("plant"), py::arg("minLevel"), py::arg("maxLevel"),
            "Appends an axis carried by the previous ones: its unit vector in the camera frame at rest, its plant "
            "(joint angle in radians) and its actuator's level range.")
        .def("getAxisCount", &Mount::getAxisCount, "The number of axes.")
        .def("getAxis", &Mount::getAxis, py::arg("index"), "The unit axis `index` (0 = base), camera frame at rest.")
        .def("getPlant", [](const Mount& self, int index) { return std::shared_ptr<Plant>(self.getPlant(index)); },
             py::arg("index"), "The plant of axis `index`.")
        .def("getLevelRange", &Mount::getLevelRange, py::arg("index"), "(minLevel, maxLevel) of axis `index`.")
        .def("getAngleRange", &Mount::getAngleRange, py::arg("index"),
             "The joint angles axis `index` reaches, radians (lowest, highest).")
        .def("orientation", &Mount::orientation, py::arg("angles"),
             "Q(q), 3×3: the camera frame in the base frame at joint angles q (radians, one per axis).")
        .def("pointing", &Mount::pointing, py::arg("angles"),
             "The optical axis Q(q)·(0, 0, 1) in the base frame at joint angles q (radians).")
        .def("anglesFor", &Mount::anglesFor, py::arg("direction"), py::arg("current") = std::vector<double>(),
             "Joint angles (radians) that point the optical axis along `direction` (base frame): the first two axes "
             "solved, the others kept from `current` (empty: 0); the reachable solution nearest `current`.")
        .def(
            "motion",
            [](const Mount& self, const std::vector<SwitchSchedule>& schedules) {
                return shared(self.motion(schedules));
            },
            py::arg("schedules"),
            "The CameraMotion while each axis follows its own schedule (one per axis, camera clock), exact at every "
            "instant; its reference view for a NaN tRef is every axis at its final rest.");

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
