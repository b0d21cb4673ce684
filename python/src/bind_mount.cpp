// SPDX-License-Identifier: Apache-2.0
// Bindings of mount.hpp: Mount, a chain of rotation axes.
#include "bindings.hpp"

#include <opencv2/dynblur/mount.hpp>

#include <memory>
#include <string>
#include <vector>

namespace dynblur_py {

using namespace cv::dynblur;

void bindMount(py::module_& m)
{
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
        .def("save", [](const Mount& self, const std::string& filename) { self.save(filename); }, py::arg("filename"),
             "Writes the mount as a parameter file (YAML, XML or JSON by the extension), atomically: axisCount, then "
             "per axis i axis<i> (unit, camera frame at rest), axis<i>_naturalFreqHz, axis<i>_dampingRatio, "
             "axis<i>_gain (rad per level), axis<i>_levels ([min, max]).")
        .def_static("load", [](const std::string& filename) { return shared(Mount::load(filename)); },
                    py::arg("filename"),
                    "Reads a mount written by save; refuses a bad file naming it and the entry (an axis off unit "
                    "norm by more than 1e-6, parallel axes, a missing plant entry, a level range upside down, an "
                    "axisCount that does not match).")
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
}

}  // namespace dynblur_py
