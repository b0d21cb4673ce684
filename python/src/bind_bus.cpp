// SPDX-License-Identifier: Apache-2.0
// Bindings of bus.hpp: ActuatorBus, ActuatorDriver (one axis), MultiAxisDriver (several axes, one
// START) and their value types. Calls that wait on the link release the GIL.
#include "bindings.hpp"

#include <opencv2/dynblur/bus.hpp>

#include <memory>
#include <sstream>
#include <vector>

namespace dynblur_py {

using namespace cv::dynblur;

namespace {

using Release = py::call_guard<py::gil_scoped_release>;

void bindValues(py::module_& m)
{
    py::class_<ActuatorLimits>(m, "ActuatorLimits", "Host-side safety limits, checked before anything is sent.")
        .def(py::init<>())
        .def_readwrite("maxLevel", &ActuatorLimits::maxLevel, "largest |level|, cells")
        .def_readwrite("minDwell", &ActuatorLimits::minDwell, "shortest time between two switches, seconds")
        .def_readwrite("maxEntries", &ActuatorLimits::maxEntries, "most switches in one schedule")
        .def_readwrite("safeLevel", &ActuatorLimits::safeLevel, "level applied on stop and on errors, cells");
    py::class_<ActuatorInfo>(m, "ActuatorInfo", "What the controller advertises.")
        .def_readonly("protocolMajor", &ActuatorInfo::protocolMajor)
        .def_readonly("protocolMinor", &ActuatorInfo::protocolMinor)
        .def_readonly("maxLevel", &ActuatorInfo::maxLevel, "cells")
        .def_readonly("minDwell", &ActuatorInfo::minDwell, "seconds")
        .def_readonly("capacity", &ActuatorInfo::capacity, "schedule entries per axis")
        .def_readonly("axes", &ActuatorInfo::axes, "axes the controller drives (1 on a protocol 1.0 device)");
    py::class_<ActuatorStatus>(m, "ActuatorStatus", "Status of one axis of the controller.")
        .def_readonly("state", &ActuatorStatus::state, "one of ACTUATOR_IDLE .. ACTUATOR_FAULT")
        .def_readonly("fault", &ActuatorStatus::fault, "one of FAULT_NONE ..")
        .def_readonly("currentLevel", &ActuatorStatus::currentLevel, "cells")
        .def_readonly("entryIndex", &ActuatorStatus::entryIndex, "entry in force while running, -1 before start")
        .def("describe", &ActuatorStatus::describe, "e.g. 'RUNNING, level 4, entry 2'")
        .def("__repr__", [](const ActuatorStatus& s) { return "ActuatorStatus(" + s.describe() + ")"; });
    py::class_<StartReport>(m, "StartReport", R"doc(When a schedule started. hostStartTime is the host's steady
clock (time.monotonic() on Linux), seconds, of the schedule's first switch, within ±uncertainty seconds;
controllerStartTime the same instant on the controller's clock, seconds.)doc")
        .def_readonly("hostStartTime", &StartReport::hostStartTime, "seconds, host steady clock")
        .def_readonly("uncertainty", &StartReport::uncertainty, "seconds")
        .def_readonly("controllerStartTime", &StartReport::controllerStartTime, "seconds, controller clock")
        .def_readonly("scheduleOrigin", &StartReport::scheduleOrigin, "times[0] of the started schedule, seconds")
        .def_readonly("commandRoundTrip", &StartReport::commandRoundTrip, "round trip of the START request, seconds");

    m.attr("ACTUATOR_IDLE") = int(ACTUATOR_IDLE);
    m.attr("ACTUATOR_LOADED") = int(ACTUATOR_LOADED);
    m.attr("ACTUATOR_RUNNING") = int(ACTUATOR_RUNNING);
    m.attr("ACTUATOR_DONE") = int(ACTUATOR_DONE);
    m.attr("ACTUATOR_FAULT") = int(ACTUATOR_FAULT);
}

void bindLink(py::module_& m)
{
    py::class_<ActuatorBus, std::shared_ptr<ActuatorBus>>(m, "ActuatorBus", R"doc(One Modbus link (TCP or RTU) to the
actuator controller; every call is bounded by the response timeout.)doc")
        .def_static(
            "create",
            [](const std::string& uri, double responseTimeout, int retries) {
                return shared(ActuatorBus::create(uri, responseTimeout, retries));
            },
            py::arg("uri"), py::arg("responseTimeout") = 0.5, py::arg("retries") = 2,
            "uri: tcp://HOST:PORT or rtu:DEVICE?baud=115200&slave=1; responseTimeout: seconds, in (0, 60]; retries: "
            "extra attempts of a failed read, in [0, 10].")
        .def("connect", &ActuatorBus::connect, Release())
        .def("close", &ActuatorBus::close, Release())
        .def("isConnected", &ActuatorBus::isConnected)
        .def("readInputRegisters", &ActuatorBus::readInputRegisters, py::arg("address"), py::arg("count"), Release(),
             "Function 04; count in [1, 125]; values 0..65535.")
        .def("readHoldingRegisters", &ActuatorBus::readHoldingRegisters, py::arg("address"), py::arg("count"),
             Release(), "Function 03; count in [1, 125].")
        .def("writeRegisters", &ActuatorBus::writeRegisters, py::arg("address"), py::arg("values"), Release(),
             "Function 16; 1..123 values, each in [-32768, 65535].")
        .def("writeRegister", &ActuatorBus::writeRegister, py::arg("address"), py::arg("value"), Release(),
             "Function 06; value in [-32768, 65535].")
        .def("getUri", &ActuatorBus::getUri)
        .def("getLastRoundTrip", &ActuatorBus::getLastRoundTrip, "Round trip of the last successful request, seconds.");
}

void bindDrivers(py::module_& m)
{
    py::class_<ActuatorDriver, std::shared_ptr<ActuatorDriver>>(m, "ActuatorDriver", R"doc(Uploads one schedule to
the controller (axis 0), verifies it by reading it back, starts it, stops it.)doc")
        .def_static(
            "create",
            [](const std::shared_ptr<ActuatorBus>& bus, const ActuatorLimits& limits) {
                return shared(ActuatorDriver::create(required(bus, "bus"), limits));
            },
            py::arg("bus"), py::arg("limits") = ActuatorLimits())
        .def("connect", &ActuatorDriver::connect, Release())
        .def("checkSchedule", &ActuatorDriver::checkSchedule, py::arg("schedule"))
        .def("upload", &ActuatorDriver::upload, py::arg("schedule"), Release())
        .def("start", &ActuatorDriver::start, Release())
        .def("status", &ActuatorDriver::status, Release())
        .def("stop", &ActuatorDriver::stop, Release())
        .def("clearFault", &ActuatorDriver::clearFault, Release())
        .def("waitUntilDone", &ActuatorDriver::waitUntilDone, py::arg("timeout"), Release(),
             "Polls until the schedule is no longer RUNNING or timeout seconds have passed.")
        .def("getInfo", &ActuatorDriver::getInfo);

    py::class_<MultiAxisDriver, std::shared_ptr<MultiAxisDriver>>(m, "MultiAxisDriver", R"doc(One schedule per axis of
a controller of several axes (a pan-tilt head): every axis uploaded and verified, then one START starts
them all at one instant of the controller's clock. No axis starts unless every axis was verified.)doc")
        .def_static(
            "create",
            [](const std::shared_ptr<ActuatorBus>& bus, int axes, const ActuatorLimits& limits) {
                return shared(MultiAxisDriver::create(required(bus, "bus"), axes, limits));
            },
            py::arg("bus"), py::arg("axes"), py::arg("limits") = ActuatorLimits(),
            "axes: axes the host drives, in [1, 7]; the controller must have at least as many.")
        .def("connect", &MultiAxisDriver::connect, Release(),
             "Identifies the controller; an error names both counts when it has fewer axes than asked.")
        .def("checkSchedules", &MultiAxisDriver::checkSchedules, py::arg("schedules"))
        .def("upload", &MultiAxisDriver::upload, py::arg("schedules"), Release(),
             "One schedule per axis, in axis order; each written, loaded and read back.")
        .def("start", &MultiAxisDriver::start, Release(), "One START for every axis; one StartReport per axis.")
        .def("status", &MultiAxisDriver::status, py::arg("axis"), Release())
        .def("statusAll", &MultiAxisDriver::statusAll, Release())
        .def("stop", &MultiAxisDriver::stop, Release())
        .def("clearFault", &MultiAxisDriver::clearFault, Release())
        .def("waitUntilDone", &MultiAxisDriver::waitUntilDone, py::arg("timeout"), Release(),
             "Polls until no axis is RUNNING or timeout seconds have passed; the status of every axis.")
        .def("getAxisCount", &MultiAxisDriver::getAxisCount)
        .def("getInfo", &MultiAxisDriver::getInfo);
}

}  // namespace

void bindBus(py::module_& m)
{
    bindValues(m);
    bindLink(m);
    bindDrivers(m);
}

}  // namespace dynblur_py
