// SPDX-License-Identifier: Apache-2.0
// Bindings of mount_planner.hpp: MountPlanner, its coordinations and the MountMove it returns.
#include "bindings.hpp"

#include <opencv2/dynblur/mount_planner.hpp>

#include <memory>
#include <vector>

namespace dynblur_py {

using namespace cv::dynblur;

void bindMountPlanner(py::module_& m)
{
    m.attr("MOUNT_COORDINATED") = int(MOUNT_COORDINATED);
    m.attr("MOUNT_INDEPENDENT") = int(MOUNT_INDEPENDENT);

    // ---------------------------------------------------------------- MountMove
    py::class_<MountMove>(m, "MountMove", "A planned move of every axis of a mount and its report (times in seconds "
                                          "from the plan's startTime).")
        .def(py::init<>())
        .def_readwrite("schedules", &MountMove::schedules, "one SwitchSchedule per axis, base first")
        .def_readwrite("fromAngles", &MountMove::fromAngles, "joint angles held at the start, radians")
        .def_readwrite("toAngles", &MountMove::toAngles, "joint angles at the end, radians")
        .def_readwrite("axisSettleTimes", &MountMove::axisSettleTimes, "each axis's settle time, seconds")
        .def_readwrite("residualVibration", &MountMove::residualVibration,
                       "each axis's residual vibration, fraction of its move")
        .def_readwrite("settleTime", &MountMove::settleTime, "the whole move's settle time (the last axis), seconds")
        .def_readwrite("peakRate", &MountMove::peakRate, "peak |ω| of the camera from the chain, rad/s")
        .def_readwrite("pathDeviation", &MountMove::pathDeviation,
                       "largest angle between the optical axis and the great circle through its end directions, "
                       "radians (0: a straight path in the image)");

    // ---------------------------------------------------------------- MountPlanner
    py::class_<MountPlanner, std::shared_ptr<MountPlanner>>(m, "MountPlanner", R"doc(Plans a move of every axis of a
Mount (one SwitchPlanner problem per axis). Coordinated (the default), the slowest axis leads and the
others follow its motion scaled to their moves, so the axes arrive together along a near-straight
image path; independent, each axis is as fast as it can be.)doc")
        .def_static(
            "create",
            [](const std::shared_ptr<Mount>& mount, int mode, double minDwell, int coordination) {
                return shared(MountPlanner::create(required(mount, "mount"), mode, minDwell, coordination));
            },
            py::arg("mount"), py::arg("mode") = int(PLAN_FAST), py::arg("minDwell") = 0.002,
            py::arg("coordination") = int(MOUNT_COORDINATED),
            "mount: the mount (every axis's level range must hold [-1, 1]); mode: PLAN_FAST or PLAN_ROBUST; "
            "minDwell: shortest time between two switches of an axis, seconds; coordination: MOUNT_COORDINATED or "
            "MOUNT_INDEPENDENT.")
        .def(
            "plan",
            [](const MountPlanner& self, const std::vector<double>& from, const std::vector<double>& to, double start) {
                py::gil_scoped_release release;
                return self.plan(from, to, start);
            },
            py::arg("fromAngles"), py::arg("toAngles"), py::arg("startTime") = 0.0,
            "Plans the move from fromAngles to toAngles (radians, one per axis, each within its axis's range); the "
            "first switch at startTime (seconds). Returns a MountMove.")
        .def(
            "planToDirection",
            [](const MountPlanner& self, const cv::Vec3d& direction, const std::vector<double>& from, double start) {
                py::gil_scoped_release release;
                return self.planToDirection(direction, from, start);
            },
            py::arg("direction"), py::arg("fromAngles"), py::arg("startTime") = 0.0,
            "Plans the move that points the optical axis along direction (the mount's base frame).")
        .def(
            "planToPixel",
            [](const MountPlanner& self, const std::shared_ptr<CameraModel>& camera, const cv::Point2d& pixel,
               const std::vector<double>& from, double start) {
                const cv::Ptr<CameraModel> model = required(camera, "camera");
                py::gil_scoped_release release;
                return self.planToPixel(model, pixel, from, start);
            },
            py::arg("camera"), py::arg("pixel"), py::arg("fromAngles"), py::arg("startTime") = 0.0,
            "Plans the move that brings the scene point seen now at pixel to the optical axis.")
        .def("getMount", [](const MountPlanner& self) { return shared(self.getMount()); })
        .def("getMode", &MountPlanner::getMode)
        .def("getMinDwell", &MountPlanner::getMinDwell, "Shortest time between two switches of an axis, seconds.")
        .def("getCoordination", &MountPlanner::getCoordination);
}

}  // namespace dynblur_py
