// SPDX-License-Identifier: Apache-2.0
// Bindings of planner.hpp: SwitchPlanner and its modes.
#include "bindings.hpp"

#include <opencv2/dynblur/planner.hpp>

#include <memory>

namespace dynblur_py {

using namespace cv::dynblur;

void bindPlanner(py::module_& m)
{
    // ---------------------------------------------------------------- SwitchPlanner
    m.attr("PLAN_FAST") = int(PLAN_FAST);
    m.attr("PLAN_ROBUST") = int(PLAN_ROBUST);
    py::class_<SwitchPlanner, std::shared_ptr<SwitchPlanner>>(m, "SwitchPlanner", R"doc(Plans point-to-point moves as integer-level switching schedules that leave no residual vibration.
The switching instants are solved so that the steps' phasors close into a polygon; robust mode
also zeroes the derivative with respect to ωn. A minimum dwell between switches and the level
limits are hard constraints.)doc")
        .def_static("create",
            [](const std::shared_ptr<Plant>& plant, int maxLevel, int mode, double minDwell) {
                return std::shared_ptr<SwitchPlanner>(SwitchPlanner::create(cv::Ptr<Plant>(plant), maxLevel, mode, minDwell));
            },
            py::arg("plant"), py::arg("maxLevel") = 16, py::arg("mode") = int(PLAN_FAST), py::arg("minDwell") = 0.002,
            R"doc(plant: the plant to plan for (its nominal ωn, ζ and gain are used); maxLevel: largest |level|,
cells, ≥ 1; mode: PLAN_FAST or PLAN_ROBUST; minDwell: shortest time between two switches, seconds.)doc")
        .def("plan",
            [](const SwitchPlanner& p, double from, double to, double start) {
                py::gil_scoped_release release;
                return p.plan(from, to, start);
            },
            py::arg("fromAngle"), py::arg("toAngle"), py::arg("startTime") = 0.0,
            R"doc(Plans a move from fromAngle to toAngle (radians, rounded to the nearest level in
[-maxLevel, maxLevel]) whose first switch is at startTime (seconds). Returns the SwitchSchedule
with settleTime, peakVelocity and residualVibration filled in; a zero move returns an empty
schedule at the start level.)doc")
        .def("getMaxLevel", &SwitchPlanner::getMaxLevel)
        .def("setMaxLevel", &SwitchPlanner::setMaxLevel, py::arg("maxLevel"))
        .def("getMode", &SwitchPlanner::getMode)
        .def("setMode", &SwitchPlanner::setMode, py::arg("mode"))
        .def("getMinDwell", &SwitchPlanner::getMinDwell, "Minimum dwell between switches, seconds.")
        .def("setMinDwell", &SwitchPlanner::setMinDwell, py::arg("minDwell"))
        .def("getSettleBand", &SwitchPlanner::getSettleBand,
             "Half-width of the band that defines the settle time, fraction of the move (default 0.02).")
        .def("setSettleBand", &SwitchPlanner::setSettleBand, py::arg("band"))
        .def("getRobustRange", &SwitchPlanner::getRobustRange,
             "Relative ωn error robust mode is designed for (default 0.10 = ±10%).")
        .def("setRobustRange", &SwitchPlanner::setRobustRange, py::arg("range"))
        .def("getRobustTolerance", &SwitchPlanner::getRobustTolerance,
             "Largest residual vibration, fraction of the move, a robust plan may leave in the robust range.")
        .def("setRobustTolerance", &SwitchPlanner::setRobustTolerance, py::arg("tolerance"))
        .def("getPlant", [](const SwitchPlanner& p) { return std::shared_ptr<Plant>(p.getPlant()); });
}

}  // namespace dynblur_py
