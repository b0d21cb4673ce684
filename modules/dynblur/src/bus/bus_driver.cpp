// SPDX-License-Identifier: Apache-2.0
// ActuatorDriver: safety checks, upload with read-back, start with clock mapping.
#include "precomp.hpp"
#include "bus/axis_registers.hpp"

#include <chrono>
#include <thread>

namespace cv {
namespace dynblur {

using namespace busmap;
using namespace bus_detail;

namespace {

const char* stateName(int s)
{
    switch (s)
    {
    case ACTUATOR_IDLE: return "IDLE";
    case ACTUATOR_LOADED: return "LOADED";
    case ACTUATOR_RUNNING: return "RUNNING";
    case ACTUATOR_DONE: return "DONE";
    case ACTUATOR_FAULT: return "FAULT";
    default: return "UNKNOWN STATE";
    }
}

const char* faultName(int f)
{
    switch (f)
    {
    case FAULT_NONE: return "none";
    case FAULT_BAD_LENGTH: return "bad length";
    case FAULT_BAD_CHECKSUM: return "bad checksum";
    case FAULT_LEVEL_RANGE: return "level out of range";
    case FAULT_DWELL: return "dwell too short";
    case FAULT_NOT_LOADED: return "start without a loaded schedule";
    case FAULT_BAD_COMMAND: return "unknown command";
    default: return "unknown fault";
    }
}

}  // namespace

String ActuatorStatus::describe() const
{
    String s = stateName(state);
    if (state == ACTUATOR_FAULT || fault != FAULT_NONE)
        s += cv::format(" (fault %d: %s)", fault, faultName(fault));
    s += cv::format(", level %d", currentLevel);
    if (entryIndex >= 0)
        s += cv::format(", entry %d", entryIndex);
    return s;
}

int busChecksum(const std::vector<int>& registers)
{
    uint16_t crc = 0xFFFF;
    for (int word : registers)
    {
        const uint8_t bytes[2] = {static_cast<uint8_t>((word >> 8) & 0xFF), static_cast<uint8_t>(word & 0xFF)};
        for (uint8_t b : bytes)
        {
            crc ^= b;
            for (int k = 0; k < 8; ++k)
                crc = (crc & 1) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001) : static_cast<uint16_t>(crc >> 1);
        }
    }
    return crc;
}

std::vector<int> encodeSchedule(const SwitchSchedule& schedule)
{
    schedule.validate(32767);
    std::vector<int> regs;
    regs.reserve(2 + ENTRY_WORDS * schedule.times.size());
    regs.push_back(static_cast<int>(schedule.times.size()));
    if (schedule.times.size() > 65535)
        CV_Error(Error::StsOutOfRange, "encodeSchedule: more than 65535 entries");
    if (schedule.initialLevel < -32768 || schedule.initialLevel > 32767)
        CV_Error(Error::StsOutOfRange, "encodeSchedule: initialLevel must fit in int16");
    regs.push_back(schedule.initialLevel & 0xFFFF);
    for (size_t i = 0; i < schedule.times.size(); ++i)
    {
        const double us = std::round((schedule.times[i] - schedule.times[0]) * 1e6);
        if (us > 4294967295.0)
            CV_Error(Error::StsOutOfRange, cv::format("encodeSchedule: times[%d] - times[0] = %g s exceeds 2^32 µs", (int)i,
                                                      schedule.times[i] - schedule.times[0]));
        const uint32_t u = static_cast<uint32_t>(us);
        regs.push_back(static_cast<int>(u >> 16));
        regs.push_back(static_cast<int>(u & 0xFFFF));
        regs.push_back(schedule.levels[i] & 0xFFFF);
    }
    return regs;
}

namespace {

class ActuatorDriverImpl CV_FINAL : public ActuatorDriver
{
public:
    ActuatorDriverImpl(const Ptr<ActuatorBus>& bus, const ActuatorLimits& limits) : bus_(bus), limits_(limits)
    {
        checkDriverArguments(bus, limits, "ActuatorDriver::create");
    }

    ActuatorInfo connect() CV_OVERRIDE
    {
        if (!bus_->isConnected())
            bus_->connect();
        const ActuatorInfo info = identify(*bus_, limits_, "ActuatorDriver");
        bus_->writeRegister(HR_SAFE_LEVEL, limits_.safeLevel & 0xFFFF);
        info_ = info;
        connected_ = true;
        return info;
    }

    void checkSchedule(const SwitchSchedule& s) const CV_OVERRIDE
    {
        checkScheduleLimits(s, limits_, connected_ ? &info_ : nullptr, "ActuatorDriver");
    }

    void upload(const SwitchSchedule& s) CV_OVERRIDE
    {
        if (!connected_)
            connect();
        checkSchedule(s);  // nothing is sent before this passes
        verified_ = false;
        const ActuatorStatus st0 = status();
        if (st0.state == ACTUATOR_RUNNING)
            CV_Error(Error::StsError, "ActuatorDriver::upload: the device is running a schedule; stop() first");
        guarded("upload", [&] {
            if (st0.state == ACTUATOR_FAULT)
                bus_->writeRegister(HR_COMMAND, CMD_CLEAR_FAULT);
            crc_ = writeAndVerify(*bus_, 0, s);
        });
        verified_ = true;
        schedule_ = s;
    }

    StartReport start() CV_OVERRIDE
    {
        if (!verified_)
            CV_Error(Error::StsError, "ActuatorDriver::start: no verified schedule; call upload() first");
        StartReport report;
        const std::vector<int> ir = readAxisInputs(*bus_, 0);
        const ActuatorStatus st = statusFromInputs(ir);
        if (st.state != ACTUATOR_LOADED)
            CV_Error(Error::StsError, "ActuatorDriver::start: the device no longer holds the verified schedule: " +
                                          st.describe());
        if (loadedChecksum(ir) != crc_)
            CV_Error(Error::StsError, cv::format("ActuatorDriver::start: loaded checksum 0x%04X differs from the verified 0x%04X",
                                                 loadedChecksum(ir), crc_));
        if (st.currentLevel != schedule_.initialLevel)
            CV_Error(Error::StsError, cv::format("ActuatorDriver::start: the actuators hold level %d but the schedule's "
                                                 "initialLevel is %d", st.currentLevel, schedule_.initialLevel));
        verified_ = false;  // a schedule is started once
        guarded("start", [&] {
            bus_->writeRegister(HR_COMMAND, CMD_START);
            report.commandRoundTrip = bus_->getLastRoundTrip();
            const StartStamp stamp = readStartStampFastest(*bus_, 0);
            if (stamp.status.state != ACTUATOR_RUNNING && stamp.status.state != ACTUATOR_DONE)
                CV_Error(Error::StsError, "the device did not start: " + stamp.status.describe());
            report.controllerStartTime = stamp.controllerStartTime;
            report.hostStartTime = stamp.hostStartTime;
            report.uncertainty = stamp.roundTrip;
            report.scheduleOrigin = schedule_.times.front();
        });
        return report;
    }

    ActuatorStatus status() CV_OVERRIDE { return statusFromInputs(readAxisInputs(*bus_, 0)); }

    void stop() CV_OVERRIDE
    {
        verified_ = false;
        bus_->writeRegister(HR_COMMAND, CMD_STOP);
    }

    void clearFault() CV_OVERRIDE { bus_->writeRegister(HR_COMMAND, CMD_CLEAR_FAULT); }

    ActuatorStatus waitUntilDone(double timeout) CV_OVERRIDE
    {
        if (!(timeout >= 0 && timeout <= 3600))
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver::waitUntilDone: timeout = %g s must be in [0, 3600]", timeout));
        const double end = steadyNow() + timeout;
        for (;;)
        {
            const ActuatorStatus st = status();
            if (st.state != ACTUATOR_RUNNING || steadyNow() >= end)
                return st;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }

    ActuatorLimits getLimits() const CV_OVERRIDE { return limits_; }
    ActuatorInfo getInfo() const CV_OVERRIDE { return info_; }
    Ptr<ActuatorBus> getBus() const CV_OVERRIDE { return bus_; }

private:
    template <class F>
    void guarded(const char* what, F body)
    {
        verified_ = false;
        runGuarded(*bus_, "ActuatorDriver", what, body, [this] { return status().describe(); });
    }

    Ptr<ActuatorBus> bus_;
    ActuatorLimits limits_;
    ActuatorInfo info_;
    bool connected_ = false;
    bool verified_ = false;
    int crc_ = 0;
    SwitchSchedule schedule_;
};

}  // namespace

Ptr<ActuatorDriver> ActuatorDriver::create(const Ptr<ActuatorBus>& bus, const ActuatorLimits& limits)
{
    return makePtr<ActuatorDriverImpl>(bus, limits);
}

}  // namespace dynblur
}  // namespace cv
