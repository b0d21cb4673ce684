// SPDX-License-Identifier: Apache-2.0
// Bindings of camera_motion.hpp: CameraMotion, classifyExposure of any camera motion.
#include "bindings.hpp"

#include <opencv2/dynblur/camera_motion.hpp>

#include <memory>
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
}

}  // namespace dynblur_py
