// SPDX-License-Identifier: Apache-2.0
// MultiAxisDriver: one schedule per axis, each verified, then one START for them all.
#include "precomp.hpp"
#include "bus/axis_registers.hpp"

#include <chrono>
#include <thread>

namespace cv {
namespace dynblur {

using namespace busmap;
using namespace bus_detail;

namespace {

std::string axisLabel(int axis) { return cv::format("axis %d", axis); }

class MultiAxisDriverImpl CV_FINAL : public MultiAxisDriver
{
public:
    MultiAxisDriverImpl(const Ptr<ActuatorBus>& bus, int axes, const ActuatorLimits& limits)
        : bus_(bus), axes_(axes), limits_(limits)
    {
        if (axes < 1 || axes > MAX_AXES)
            CV_Error(Error::StsOutOfRange, cv::format("MultiAxisDriver::create: axes = %d must be in [1, %d]", axes,
                                                      (int)MAX_AXES));
        checkDriverArguments(bus, limits, "MultiAxisDriver::create");
    }

    ActuatorInfo connect() CV_OVERRIDE
    {
        if (!bus_->isConnected())
            bus_->connect();
        const ActuatorInfo info = identify(*bus_, limits_, "MultiAxisDriver");
        if (info.axes < axes_)
            CV_Error(Error::StsError, cv::format("MultiAxisDriver::connect: the controller at '%s' has %d ax%s, the host "
                                                 "asks for %d",
                                                 bus_->getUri().c_str(), info.axes, info.axes == 1 ? "is" : "es", axes_));
        for (int k = 0; k < info.axes; ++k)
            bus_->writeRegister(axisHoldingBase(k) + HR_SAFE_LEVEL - HR_COMMAND, limits_.safeLevel & 0xFFFF);
        info_ = info;
        connected_ = true;
        return info;
    }

    void checkSchedules(const std::vector<SwitchSchedule>& schedules) const CV_OVERRIDE
    {
        if ((int)schedules.size() != axes_)
            CV_Error(Error::StsBadArg, cv::format("MultiAxisDriver: %d schedules for %d axes: give one per axis, in axis "
                                                  "order", (int)schedules.size(), axes_));
        for (int k = 0; k < axes_; ++k)
            checkScheduleLimits(schedules[k], limits_, connected_ ? &info_ : nullptr, "MultiAxisDriver: " + axisLabel(k));
    }

    void upload(const std::vector<SwitchSchedule>& schedules) CV_OVERRIDE
    {
        if (!connected_)
            connect();
        checkSchedules(schedules);  // nothing is sent before every schedule passes
        verified_ = false;
        const std::vector<ActuatorStatus> before = deviceStatus();
        bool fault = false;
        for (int k = 0; k < (int)before.size(); ++k)
        {
            if (before[k].state == ACTUATOR_RUNNING)
                CV_Error(Error::StsError, cv::format("MultiAxisDriver::upload: axis %d is running a schedule; stop() first", k));
            fault = fault || before[k].state == ACTUATOR_FAULT;
        }
        std::vector<int> crcs(axes_);
        guarded("upload", [&] {
            if (fault)
                bus_->writeRegister(HR_COMMAND, CMD_CLEAR_FAULT);
            // A further axis the host does not drive must not start with these: a zero length
            // leaves it IDLE (a write to its schedule unloads it).
            for (int k = axes_; k < info_.axes; ++k)
                bus_->writeRegister(axisHoldingBase(k) + HR_LENGTH - HR_COMMAND, 0);
            for (int k = 0; k < axes_; ++k)
                crcs[k] = onAxis(k, [&] { return writeAndVerify(*bus_, k, schedules[k]); });
        });
        crcs_ = crcs;
        schedules_ = schedules;
        verified_ = true;
    }

    std::vector<StartReport> start() CV_OVERRIDE
    {
        if (!verified_)
            CV_Error(Error::StsError, "MultiAxisDriver::start: no verified schedules; call upload() first");
        verified_ = false;  // schedules are started once
        checkStillLoaded();
        std::vector<StartReport> reports(axes_);
        guarded("start", [&] {
            bus_->writeRegister(HR_COMMAND, CMD_START);
            const double commandRoundTrip = bus_->getLastRoundTrip();
            // One clock mapping for every axis (axis 0's tightest bracket), so that the host start
            // times differ exactly as the controller's do.
            const StartStamp mapping = readStartStampFastest(*bus_, 0);
            for (int k = 0; k < axes_; ++k)
            {
                reports[k] = onAxis(k, [&] { return startReport(k, mapping); });
                reports[k].commandRoundTrip = commandRoundTrip;
            }
        });
        return reports;
    }

    ActuatorStatus status(int axis) CV_OVERRIDE
    {
        if (axis < 0 || axis >= axes_)
            CV_Error(Error::StsOutOfRange, cv::format("MultiAxisDriver::status: axis = %d must be in [0, %d)", axis, axes_));
        return statusFromInputs(readAxisInputs(*bus_, axis));
    }

    std::vector<ActuatorStatus> statusAll() CV_OVERRIDE
    {
        std::vector<ActuatorStatus> all(axes_);
        for (int k = 0; k < axes_; ++k)
            all[k] = status(k);
        return all;
    }

    void stop() CV_OVERRIDE
    {
        verified_ = false;
        bus_->writeRegister(HR_COMMAND, CMD_STOP);
    }

    void clearFault() CV_OVERRIDE { bus_->writeRegister(HR_COMMAND, CMD_CLEAR_FAULT); }

    std::vector<ActuatorStatus> waitUntilDone(double timeout) CV_OVERRIDE
    {
        if (!(timeout >= 0 && timeout <= 3600))
            CV_Error(Error::StsOutOfRange, cv::format("MultiAxisDriver::waitUntilDone: timeout = %g s must be in [0, 3600]",
                                                      timeout));
        const double end = steadyNow() + timeout;
        for (;;)
        {
            const std::vector<ActuatorStatus> all = statusAll();
            const bool running = std::any_of(all.begin(), all.end(),
                                             [](const ActuatorStatus& st) { return st.state == ACTUATOR_RUNNING; });
            if (!running || steadyNow() >= end)
                return all;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }

    int getAxisCount() const CV_OVERRIDE { return axes_; }
    ActuatorLimits getLimits() const CV_OVERRIDE { return limits_; }
    ActuatorInfo getInfo() const CV_OVERRIDE { return info_; }
    Ptr<ActuatorBus> getBus() const CV_OVERRIDE { return bus_; }

private:
    // Every axis the controller has, the host's and the further ones.
    std::vector<ActuatorStatus> deviceStatus()
    {
        std::vector<ActuatorStatus> all(info_.axes);
        for (int k = 0; k < info_.axes; ++k)
            all[k] = statusFromInputs(readAxisInputs(*bus_, k));
        return all;
    }

    // Before the START: each axis still LOADED with its verified CRC and at its schedule's initial
    // level, and no further axis LOADED (it would start too).
    void checkStillLoaded()
    {
        for (int k = 0; k < info_.axes; ++k)
        {
            const std::vector<int> ir = readAxisInputs(*bus_, k);
            const ActuatorStatus st = statusFromInputs(ir);
            const char* p = "MultiAxisDriver::start: axis";
            if (k >= axes_)
            {
                if (st.state == ACTUATOR_LOADED)
                    CV_Error(Error::StsError, cv::format("%s %d, which the host does not drive, holds a loaded schedule "
                                                         "that would start too; nothing started", p, k));
                continue;
            }
            if (st.state != ACTUATOR_LOADED)
                CV_Error(Error::StsError, cv::format("%s %d no longer holds its verified schedule: %s; nothing started", p,
                                                     k, st.describe().c_str()));
            if (loadedChecksum(ir) != crcs_[k])
                CV_Error(Error::StsError, cv::format("%s %d: loaded checksum 0x%04X differs from the verified 0x%04X; "
                                                     "nothing started", p, k, loadedChecksum(ir), crcs_[k]));
            if (st.currentLevel != schedules_[k].initialLevel)
                CV_Error(Error::StsError, cv::format("%s %d holds level %d but its schedule's initialLevel is %d; nothing "
                                                     "started", p, k, st.currentLevel, schedules_[k].initialLevel));
        }
    }

    StartReport startReport(int k, const StartStamp& mapping)
    {
        const StartStamp stamp = readStartStamp(*bus_, k);
        if (stamp.status.state != ACTUATOR_RUNNING && stamp.status.state != ACTUATOR_DONE)
            CV_Error(Error::StsError, "the device did not start it: " + stamp.status.describe());
        StartReport report;
        report.controllerStartTime = stamp.controllerStartTime;
        report.hostStartTime = mapping.hostStartTime + (stamp.controllerStartTime - mapping.controllerStartTime);
        report.uncertainty = mapping.roundTrip;
        report.scheduleOrigin = schedules_[k].times.front();
        return report;
    }

    // Runs a step of axis k; its error names the axis.
    template <class F>
    auto onAxis(int k, F step) -> decltype(step())
    {
        try
        {
            return step();
        }
        catch (const cv::Exception& e)
        {
            CV_Error(Error::StsError, axisLabel(k) + ": " + e.err);
        }
    }

    void guarded(const char* what, const std::function<void()>& body)
    {
        verified_ = false;
        runGuarded(*bus_, "MultiAxisDriver", what, body, [this] {
            std::string text;
            const std::vector<ActuatorStatus> all = deviceStatus();
            for (size_t k = 0; k < all.size(); ++k)
                text += cv::format("%saxis %d %s", k ? ", " : "", (int)k, all[k].describe().c_str());
            return text;
        });
    }

    Ptr<ActuatorBus> bus_;
    int axes_;
    ActuatorLimits limits_;
    ActuatorInfo info_;
    bool connected_ = false;
    bool verified_ = false;
    std::vector<int> crcs_;
    std::vector<SwitchSchedule> schedules_;
};

}  // namespace

Ptr<MultiAxisDriver> MultiAxisDriver::create(const Ptr<ActuatorBus>& bus, int axes, const ActuatorLimits& limits)
{
    return makePtr<MultiAxisDriverImpl>(bus, axes, limits);
}

}  // namespace dynblur
}  // namespace cv
