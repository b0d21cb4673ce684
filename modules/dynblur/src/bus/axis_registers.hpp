// SPDX-License-Identifier: Apache-2.0
// What the one-axis and the multi-axis drivers share: the identification, the host's checks of a
// schedule, one axis's upload with read-back, one axis's status and start stamp, and the guard that
// applies the safe level when a step fails.
#ifndef OPENCV_DYNBLUR_BUS_AXIS_REGISTERS_HPP
#define OPENCV_DYNBLUR_BUS_AXIS_REGISTERS_HPP

#include "opencv2/dynblur/bus.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace cv {
namespace dynblur {
namespace bus_detail {

//! Host steady-clock time, seconds.
double steadyNow();

//! Refuses an empty bus or limits out of range, naming `who` (e.g. "ActuatorDriver::create").
void checkDriverArguments(const Ptr<ActuatorBus>& bus, const ActuatorLimits& limits, const char* who);

//! Reads registers 0..6 (and IR_AXIS_COUNT from protocol 1.1 on), checks the magic, the major
//! version, the capacity and that limits.safeLevel is within the device's max level.
ActuatorInfo identify(ActuatorBus& bus, const ActuatorLimits& limits, const char* who);

/** Refuses (cv::Exception starting with `prefix`) a schedule that breaks the host limits or, when
`info` is given, the device's. */
void checkScheduleLimits(const SwitchSchedule& s, const ActuatorLimits& limits, const ActuatorInfo* info,
                         const std::string& prefix);

//! One axis's input block (axisInputBase(axis), IR_STATUS..IR_ENTRY_INDEX).
std::vector<int> readAxisInputs(ActuatorBus& bus, int axis);
//! Status from an input block read by readAxisInputs.
ActuatorStatus statusFromInputs(const std::vector<int>& inputs);
//! The device's CRC of the loaded schedule, from an input block.
int loadedChecksum(const std::vector<int>& inputs);

/** Writes one axis's schedule (entries, then length/initial level/CRC), asks the device to LOAD it
through the axis's command register, reads everything back and requires LOADED with the same CRC.
Throws naming what differed; the caller applies the safe level. @return the CRC. */
int writeAndVerify(ActuatorBus& bus, int axis, const SwitchSchedule& s);

//! An axis's start stamp read with the clock in one request, mapped onto the host's clock.
struct StartStamp
{
    double hostStartTime = 0, controllerStartTime = 0;  //!< seconds, host steady clock and controller clock
    double roundTrip = 0;                                //!< of the read, seconds
    ActuatorStatus status;                               //!< the axis's, from the same read
};
StartStamp readStartStamp(ActuatorBus& bus, int axis);
//! The fastest of three readStartStamp: the tightest bracket of the clock mapping.
StartStamp readStartStampFastest(ActuatorBus& bus, int axis);

/** Runs `body`; on a cv::Exception writes STOP (the safe level on every axis), then rethrows as
"<who>::<what> failed: <error>; safe level applied, device status: <describeStatus()>". */
void runGuarded(ActuatorBus& bus, const std::string& who, const char* what, const std::function<void()>& body,
                const std::function<std::string()>& describeStatus);

}  // namespace bus_detail
}  // namespace dynblur
}  // namespace cv

#endif
