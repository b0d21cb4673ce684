// SPDX-License-Identifier: Apache-2.0
// Bindings of schedule.hpp: SwitchSchedule.
#include "bindings.hpp"

#include <opencv2/dynblur/schedule.hpp>

#include <sstream>
#include <string>

namespace dynblur_py {

using namespace cv::dynblur;

namespace {

std::string repr(const SwitchSchedule& s)
{
    std::ostringstream o;
    o << "SwitchSchedule(times=[";
    for (size_t i = 0; i < s.times.size(); ++i)
        o << (i ? ", " : "") << s.times[i];
    o << "], levels=[";
    for (size_t i = 0; i < s.levels.size(); ++i)
        o << (i ? ", " : "") << s.levels[i];
    o << "], initialLevel=" << s.initialLevel << ")";
    return o.str();
}

}  // namespace

void bindSchedule(py::module_& m)
{
    // ---------------------------------------------------------------- SwitchSchedule
    py::class_<SwitchSchedule>(m, "SwitchSchedule", R"doc(A staircase command: integer actuator levels switched at chosen instants.

The level ``levels[i]`` is held from ``times[i]`` to ``times[i+1]`` (the last one forever). Before
``times[0]`` the level ``initialLevel`` is in force and the plant rests at ``gain * initialLevel``.
The planner fills settleTime, peakVelocity and residualVibration; they are NaN for a hand-made
schedule. The list fields are copies: assign a new list to change them.)doc")
        .def(py::init<>())
        .def(py::init<const std::vector<double>&, const std::vector<int>&, int>(), py::arg("times"),
             py::arg("levels"), py::arg("initialLevel") = 0,
             R"doc(times: switching instants, seconds, strictly increasing; levels: level switched on at
each instant (cells), same length; initialLevel: level before times[0] (cells).)doc")
        .def_readwrite("times", &SwitchSchedule::times, "switching instants, seconds, strictly increasing")
        .def_readwrite("levels", &SwitchSchedule::levels, "level from each instant on, cells")
        .def_readwrite("initialLevel", &SwitchSchedule::initialLevel, "level before times[0], cells")
        .def_readwrite("settleTime", &SwitchSchedule::settleTime,
                       "predicted time from times[0] until the angle stays in the settle band, seconds")
        .def_readwrite("peakVelocity", &SwitchSchedule::peakVelocity, "predicted peak |dθ/dt|, rad/s")
        .def_readwrite("residualVibration", &SwitchSchedule::residualVibration,
                       "vibration left after the last switch, fraction of the move")
        .def("finalLevel", &SwitchSchedule::finalLevel,
             "Level in force after the last switch (initialLevel when the schedule is empty).")
        .def("levelAt", &SwitchSchedule::levelAt, py::arg("t"), "Level in force at time t, seconds.")
        .def("validate", &SwitchSchedule::validate, py::arg("maxLevel") = 1 << 20,
             R"doc(Raises dynblur.error naming the offending field when the schedule is malformed: empty,
lengths differ, non-finite or non-increasing times, or a level outside [-maxLevel, maxLevel].)doc")
        .def("save", &SwitchSchedule::save, py::arg("filename"),
             "Writes the schedule to a cv::FileStorage file (YAML, XML or JSON by extension).")
        .def_static("load", &SwitchSchedule::load, py::arg("filename"),
                    "Reads a schedule written by save(); checks it with validate().")
        .def("__repr__", &repr);
}

}  // namespace dynblur_py
