// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_BUS_HPP
#define OPENCV_DYNBLUR_BUS_HPP

#include <opencv2/core.hpp>

#include "opencv2/dynblur/plant.hpp"

#include <string>
#include <vector>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

/** @brief Register map of the actuator controller (docs/actuator-bus.md is the reference).

Input registers (Modbus function 04) are read-only; holding registers (03 to read, 06/16 to
write) carry the schedule and the command. Every multi-register number is big-endian by word
(high word first); levels are two's-complement int16.

A controller of several axes (protocol 1.1) keeps axis 0 at the addresses below, so that a one-axis
host drives it unchanged, reports its number of axes in IR_AXIS_COUNT and gives each further axis k
a block of input registers at axisInputBase(k) (laid out as IR_STATUS..IR_ENTRY_INDEX) and one of
holding registers at axisHoldingBase(k) (laid out as HR_COMMAND..the entries; the block's first
register takes only CMD_LOAD, for that axis). One CMD_START in HR_COMMAND starts every LOADED axis
at one instant of the controller's clock; CMD_STOP and CMD_CLEAR_FAULT act on every axis.
*/
namespace busmap {
enum : int
{
    // ---- input registers (read-only) ----
    IR_MAGIC = 0,             //!< 0x4459 ("DY")
    IR_VERSION = 1,           //!< protocol version, major << 8 | minor (this driver: major 1)
    IR_STATUS = 2,            //!< one of ActuatorState
    IR_FAULT = 3,             //!< one of ActuatorFault
    IR_MAX_LEVEL = 4,         //!< largest |level| the device accepts, cells
    IR_MIN_DWELL_US = 5,      //!< shortest time between two switches, microseconds
    IR_CAPACITY = 6,          //!< most schedule entries the device stores
    IR_CURRENT_LEVEL = 7,     //!< level in force now, int16 cells
    IR_START_TIME_US = 8,     //!< 4 registers: controller clock at the last start, microseconds
    IR_CLOCK_US = 12,         //!< 4 registers: controller clock now, microseconds
    IR_LOADED_CHECKSUM = 16,  //!< CRC-16 the device computed over the loaded schedule
    IR_ENTRY_INDEX = 17,      //!< index of the entry in force while running (0xFFFF before start)
    IR_COUNT = 18,            //!< end of axis 0's input registers (and of the whole 1.0 map)
    IR_AXIS_COUNT = 18,       //!< number of axes, 1..MAX_AXES (protocol 1.1; absent before: 1 axis)
    IR_AXES = 32,             //!< input block of axis 1; axis k's at IR_AXES + (k - 1) * IR_AXIS_STRIDE
    IR_AXIS_STRIDE = 16,      //!< registers per input block, laid out as IR_STATUS..IR_ENTRY_INDEX

    // ---- holding registers (read/write) ----
    HR_COMMAND = 100,         //!< write one of ActuatorCommand; reads 0 once executed
    HR_LENGTH = 101,          //!< number of schedule entries
    HR_INITIAL_LEVEL = 102,   //!< level before the first entry, int16 cells
    HR_CHECKSUM = 103,        //!< CRC-16/MODBUS of the schedule as written by the host
    HR_SAFE_LEVEL = 104,      //!< level the device applies on STOP and on a fault, int16 cells
    HR_ENTRIES = 200,         //!< entry i at 200 + 3i: time offset µs (hi, lo word), level int16
    ENTRY_WORDS = 3,
    HR_AXES = 16384,          //!< holding block of axis 1; axis k's at HR_AXES + (k - 1) * HR_AXIS_STRIDE
    HR_AXIS_STRIDE = 8192,    //!< registers per holding block, laid out as HR_COMMAND..the entries
    MAX_AXES = 7,             //!< most axes the map addresses (axis 6's block ends at 65535)
    MAX_AXIS_CAPACITY = (HR_AXIS_STRIDE - (HR_ENTRIES - HR_COMMAND)) / ENTRY_WORDS,  //!< entries a block holds: 2697

    MAGIC = 0x4459,
    PROTOCOL_MAJOR = 1,
    PROTOCOL_MINOR = 1,       //!< 1.1: several axes; a 1.0 device has one
    PROTOCOL_MINOR_AXES = 1   //!< first minor version with IR_AXIS_COUNT
};

/** @brief Address of axis `axis`'s IR_STATUS; its other input registers follow as in axis 0's
layout (IR_FAULT at + IR_FAULT - IR_STATUS, ...). @param axis in [0, MAX_AXES). */
inline int axisInputBase(int axis)
{
    return axis == 0 ? IR_STATUS : IR_AXES + (axis - 1) * IR_AXIS_STRIDE;
}

/** @brief Address of axis `axis`'s command register; its schedule registers follow as in axis 0's
layout (length at + HR_LENGTH - HR_COMMAND, entries at + HR_ENTRIES - HR_COMMAND).
@param axis in [0, MAX_AXES). */
inline int axisHoldingBase(int axis)
{
    return axis == 0 ? HR_COMMAND : HR_AXES + (axis - 1) * HR_AXIS_STRIDE;
}
}  // namespace busmap

//! @brief State reported in IR_STATUS.
enum ActuatorState
{
    ACTUATOR_IDLE = 0,     //!< no valid schedule loaded
    ACTUATOR_LOADED = 1,   //!< a schedule passed the device's checks and can be started
    ACTUATOR_RUNNING = 2,  //!< switching the loaded schedule
    ACTUATOR_DONE = 3,     //!< last entry reached; its level is held
    ACTUATOR_FAULT = 4     //!< see IR_FAULT; the safe level is applied; CLEAR_FAULT to leave
};

//! @brief Fault code reported in IR_FAULT.
enum ActuatorFault
{
    FAULT_NONE = 0,
    FAULT_BAD_LENGTH = 1,     //!< length 0 or above the capacity
    FAULT_BAD_CHECKSUM = 2,   //!< CRC of the stored entries differs from HR_CHECKSUM
    FAULT_LEVEL_RANGE = 3,    //!< a level outside ±max level
    FAULT_DWELL = 4,          //!< offsets not increasing by at least the minimum dwell, or first offset not 0
    FAULT_NOT_LOADED = 5,     //!< START without a loaded schedule
    FAULT_BAD_COMMAND = 6     //!< unknown command code
};

//! @brief Command codes written to HR_COMMAND.
enum ActuatorCommand
{
    CMD_NONE = 0,
    CMD_LOAD = 1,         //!< check the written schedule; LOADED or FAULT
    CMD_START = 2,        //!< start the loaded schedule now; records IR_START_TIME_US
    CMD_STOP = 3,         //!< apply the safe level, end any run, forget the loaded schedule (IDLE)
    CMD_CLEAR_FAULT = 4   //!< leave FAULT for IDLE
};

/** @brief CRC-16/MODBUS (poly 0xA001 reflected, init 0xFFFF) over registers sent high byte first.
It is the checksum of HR_CHECKSUM: over [length, initialLevel, entry words...]. */
CV_EXPORTS int busChecksum(const std::vector<int>& registers);

/** @brief Registers of a schedule: [length, initialLevel, then 3 words per entry].
Time offsets are rounded to whole microseconds from times[0].
@param schedule a validated schedule whose span fits in 32 bits of microseconds. */
CV_EXPORTS std::vector<int> encodeSchedule(const SwitchSchedule& schedule);

/** @brief One Modbus link (TCP or RTU over a serial line) to the actuator controller.

Every call is bounded in time: connecting, and each request, waits at most the response timeout;
reads are retried (after reconnecting a TCP link or flushing a serial one) up to getRetries()
times. After a transport error on a serial line, what arrives is discarded until the line has been
quiet for one response timeout (at most four), so that a late reply is not taken for the answer to
the next request. Failures throw cv::Exception with the URI, the register range and the Modbus error (for
example "Illegal data address" for an exception reply, "Connection timed out", "Invalid CRC").
*/
class CV_EXPORTS_W ActuatorBus : public Algorithm
{
public:
    /** @brief Opens nothing yet; parses the address.
    @param uri `tcp://HOST:PORT` (Modbus TCP, unit id 255; `?unit=N` to change), or
           `rtu:DEVICE?baud=115200&parity=N&slave=1` (Modbus RTU, 8 data bits, 1 stop bit).
    @param responseTimeout longest wait for a reply (and for connecting), seconds, in (0, 60].
    @param retries extra attempts of a failed read, in [0, 10]. */
    CV_WRAP static Ptr<ActuatorBus> create(const String& uri, double responseTimeout = 0.5,
                                           int retries = 2);

    //! @brief Connects (bounded by the response timeout); throws when refused or timed out.
    CV_WRAP virtual void connect() = 0;
    //! @brief Closes the link (no-op when closed).
    CV_WRAP virtual void close() = 0;
    CV_WRAP virtual bool isConnected() const = 0;

    /** @brief Reads input registers (function 04), retried. @param address first register.
    @param count number of registers, in [1, 125]. @return values, 0..65535. */
    CV_WRAP virtual std::vector<int> readInputRegisters(int address, int count) = 0;
    /** @brief Reads holding registers (function 03), retried. @param address first register.
    @param count number of registers, in [1, 125]. */
    CV_WRAP virtual std::vector<int> readHoldingRegisters(int address, int count) = 0;
    /** @brief Writes holding registers (function 16), not retried.
    @param address first register. @param values 1..123 values, each in [-32768, 65535]
    (negative values are sent as two's complement). */
    CV_WRAP virtual void writeRegisters(int address, const std::vector<int>& values) = 0;
    /** @brief Writes one holding register (function 06), not retried. */
    CV_WRAP virtual void writeRegister(int address, int value) = 0;

    //! @brief The address given to create().
    CV_WRAP virtual String getUri() const = 0;
    //! @brief Response timeout, seconds. @see setResponseTimeout
    CV_WRAP virtual double getResponseTimeout() const = 0;
    //! @copybrief getResponseTimeout
    CV_WRAP virtual void setResponseTimeout(double seconds) = 0;
    //! @brief Extra attempts of a failed read.
    CV_WRAP virtual int getRetries() const = 0;
    //! @copybrief getRetries
    CV_WRAP virtual void setRetries(int retries) = 0;
    //! @brief Round-trip time of the last successful request, seconds (host steady clock).
    CV_WRAP virtual double getLastRoundTrip() const = 0;
    //! @brief Host steady-clock time (seconds) when the last successful request was sent.
    CV_WRAP virtual double getLastSendTime() const = 0;
};

/** @brief Host-side safety limits, checked before anything is sent. */
struct CV_EXPORTS_W_SIMPLE ActuatorLimits
{
    CV_WRAP ActuatorLimits() {}
    CV_PROP_RW int maxLevel = 16;          //!< largest |level|, cells
    CV_PROP_RW double minDwell = 1e-3;     //!< shortest time between two switches, seconds
    CV_PROP_RW int maxEntries = 256;       //!< most switches in one schedule
    CV_PROP_RW int safeLevel = 0;          //!< level applied on stop and on errors, cells
};

/** @brief What the controller advertises (input registers 0..6). */
struct CV_EXPORTS_W_SIMPLE ActuatorInfo
{
    CV_PROP_RW int protocolMajor = 0;
    CV_PROP_RW int protocolMinor = 0;
    CV_PROP_RW int maxLevel = 0;       //!< cells
    CV_PROP_RW double minDwell = 0;    //!< seconds
    CV_PROP_RW int capacity = 0;       //!< entries
    CV_PROP_RW int axes = 1;           //!< axes the controller drives (IR_AXIS_COUNT; 1 on a 1.0 device)
};

/** @brief Status of the controller. */
struct CV_EXPORTS_W_SIMPLE ActuatorStatus
{
    CV_PROP_RW int state = ACTUATOR_IDLE;  //!< ActuatorState
    CV_PROP_RW int fault = FAULT_NONE;     //!< ActuatorFault
    CV_PROP_RW int currentLevel = 0;       //!< cells
    CV_PROP_RW int entryIndex = -1;        //!< entry in force while running, -1 before start
    /** @brief e.g. "RUNNING, level 4, entry 2" or "FAULT (bad checksum), level 0". */
    CV_WRAP String describe() const;
};

/** @brief When a schedule started, on the host's clock.

hostStartTime is std::chrono::steady_clock time, seconds, of the schedule's first switch
(times[0]). It comes from one read of the controller's start stamp and clock, placed at the
midpoint of that request; the true value lies within ±uncertainty (the round trip of the
fastest of a few such reads). So a schedule time s maps to host time
hostStartTime + (s - scheduleOrigin). */
struct CV_EXPORTS_W_SIMPLE StartReport
{
    CV_PROP_RW double hostStartTime = 0;     //!< seconds, host steady clock
    CV_PROP_RW double uncertainty = 0;       //!< seconds (the measured round trip)
    CV_PROP_RW double controllerStartTime = 0;  //!< seconds, controller clock
    CV_PROP_RW double scheduleOrigin = 0;    //!< times[0] of the started schedule, seconds
    CV_PROP_RW double commandRoundTrip = 0;  //!< round trip of the START request, seconds
};

/** @brief Uploads a SwitchSchedule to the actuator controller, checks it, starts it, stops it.

Safety: checkSchedule() refuses (cv::Exception naming the limit) a schedule that breaks the host
limits or the device's advertised ones, before any register is written. upload() writes the
entries, the length, the initial level and a CRC, asks the device to LOAD (it checks them too),
reads everything back and compares; start() starts only a schedule verified this way, and only
when the device still reports it LOADED with the same CRC and holds the schedule's initial level.
On any error during upload or start the driver tries to apply the safe level (STOP), then throws
a message that includes the device's status when it could be read.
*/
class CV_EXPORTS_W ActuatorDriver : public Algorithm
{
public:
    /** @param bus the link (connected by connect() when not yet).
    @param limits host-side limits; maxLevel ≥ 0, minDwell in [0, 1] s, maxEntries in [1, 65535]. */
    CV_WRAP static Ptr<ActuatorDriver> create(const Ptr<ActuatorBus>& bus,
                                              const ActuatorLimits& limits = ActuatorLimits());

    /** @brief Connects, reads the identification and checks the magic and protocol major
    version; writes the safe level. @return what the device advertises. */
    CV_WRAP virtual ActuatorInfo connect() = 0;
    /** @brief Throws cv::Exception naming the broken limit (host or device); sends nothing. */
    CV_WRAP virtual void checkSchedule(const SwitchSchedule& schedule) const = 0;
    /** @brief Checks, writes, loads and reads back a schedule (see the class description). */
    CV_WRAP virtual void upload(const SwitchSchedule& schedule) = 0;
    /** @brief Starts the verified schedule. @return its start time on the host's clock. */
    CV_WRAP virtual StartReport start() = 0;
    //! @brief Reads the status (retried read).
    CV_WRAP virtual ActuatorStatus status() = 0;
    //! @brief Applies the safe level and ends any run.
    CV_WRAP virtual void stop() = 0;
    //! @brief Leaves the FAULT state.
    CV_WRAP virtual void clearFault() = 0;
    /** @brief Polls the status until DONE, FAULT or IDLE, or until timeout seconds have passed.
    @return the last status read. */
    CV_WRAP virtual ActuatorStatus waitUntilDone(double timeout) = 0;

    CV_WRAP virtual ActuatorLimits getLimits() const = 0;
    CV_WRAP virtual ActuatorInfo getInfo() const = 0;
    CV_WRAP virtual Ptr<ActuatorBus> getBus() const = 0;
};

/** @brief Uploads one SwitchSchedule per axis to a controller of several axes (a pan-tilt head),
verifies every one, then starts them all with one START.

Axis k of the host is axis k of the controller (docs/actuator-bus.md, "Several axes"). The safety
rules of ActuatorDriver hold per axis, with one more: **no axis starts unless every axis was
verified**. upload() checks every schedule on the host before it sends anything; then, axis by
axis, writes, loads and reads back, and requires each LOADED with the host's CRC. start() checks
every axis again (LOADED, same CRC, holding its schedule's initial level) and only then writes the
one START, which the controller applies to every axis at the same instant of its clock. An error on
any axis applies the safe level to all (STOP) and throws a message that names the axis and why.
*/
class CV_EXPORTS_W MultiAxisDriver : public Algorithm
{
public:
    /** @param bus the link (connected by connect() when not yet).
    @param axes axes the host drives, in [1, busmap::MAX_AXES]; the controller must have at least as many.
    @param limits host-side limits of every axis, as for ActuatorDriver::create. */
    CV_WRAP static Ptr<MultiAxisDriver> create(const Ptr<ActuatorBus>& bus, int axes,
                                               const ActuatorLimits& limits = ActuatorLimits());

    /** @brief Connects, checks the magic and the protocol major version, reads the number of axes
    (1 on a 1.0 device) and refuses a controller with fewer axes than getAxisCount(), naming both
    counts; writes every axis's safe level. @return what the device advertises. */
    CV_WRAP virtual ActuatorInfo connect() = 0;
    /** @brief Throws cv::Exception naming the axis and the broken limit; sends nothing.
    @param schedules one per axis, in axis order; their number must be getAxisCount(). */
    CV_WRAP virtual void checkSchedules(const std::vector<SwitchSchedule>& schedules) const = 0;
    /** @brief Checks every schedule, then writes, loads and reads back each axis's (see the class
    description). @param schedules one per axis, in axis order (schedule times in seconds). */
    CV_WRAP virtual void upload(const std::vector<SwitchSchedule>& schedules) = 0;
    /** @brief Starts every verified schedule with one START.
    @return one report per axis; their controllerStartTime are one instant of the controller's clock
    (seconds), their hostStartTime that instant on the host's steady clock (seconds, within ±uncertainty). */
    CV_WRAP virtual std::vector<StartReport> start() = 0;
    /** @brief Reads the status of one axis (retried read). @param axis in [0, getAxisCount()). */
    CV_WRAP virtual ActuatorStatus status(int axis) = 0;
    //! @brief Reads the status of every axis, in axis order.
    CV_WRAP virtual std::vector<ActuatorStatus> statusAll() = 0;
    //! @brief Applies the safe level on every axis and ends any run.
    CV_WRAP virtual void stop() = 0;
    //! @brief Leaves the FAULT state on every axis.
    CV_WRAP virtual void clearFault() = 0;
    /** @brief Polls until no axis is RUNNING, or until timeout seconds have passed.
    @param timeout seconds, in [0, 3600]. @return the last status of every axis. */
    CV_WRAP virtual std::vector<ActuatorStatus> waitUntilDone(double timeout) = 0;

    //! @brief Axes the host drives (given to create()).
    CV_WRAP virtual int getAxisCount() const = 0;
    CV_WRAP virtual ActuatorLimits getLimits() const = 0;
    //! @brief What connect() read; its `axes` may exceed getAxisCount() (further axes stay idle).
    CV_WRAP virtual ActuatorInfo getInfo() const = 0;
    CV_WRAP virtual Ptr<ActuatorBus> getBus() const = 0;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
