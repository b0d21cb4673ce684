// SPDX-License-Identifier: Apache-2.0
// ActuatorDriver: safety checks, upload with read-back, start with clock mapping.
#include "precomp.hpp"
#include "opencv2/dynblur/bus.hpp"

#include <chrono>
#include <cstdint>
#include <thread>

namespace cv {
namespace dynblur {

using namespace busmap;

namespace {

double steadyNow()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int asInt16(int word) { return word >= 32768 ? word - 65536 : word; }

uint64_t asU64(const std::vector<int>& r, int at)
{
    uint64_t v = 0;
    for (int i = 0; i < 4; ++i)
        v = (v << 16) | static_cast<uint64_t>(r[at + i] & 0xFFFF);
    return v;
}

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
        if (!bus)
            CV_Error(Error::StsNullPtr, "ActuatorDriver::create: bus is empty");
        if (limits.maxLevel < 0 || limits.maxLevel > 32767)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver::create: limits.maxLevel = %d must be in [0, 32767]", limits.maxLevel));
        if (!(limits.minDwell >= 0 && limits.minDwell <= 1))
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver::create: limits.minDwell = %g s must be in [0, 1]", limits.minDwell));
        if (limits.maxEntries < 1 || limits.maxEntries > 65535)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver::create: limits.maxEntries = %d must be in [1, 65535]", limits.maxEntries));
        if (std::abs(limits.safeLevel) > limits.maxLevel)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver::create: limits.safeLevel = %d must be within ±maxLevel = %d",
                                                      limits.safeLevel, limits.maxLevel));
    }

    ActuatorInfo connect() CV_OVERRIDE
    {
        if (!bus_->isConnected())
            bus_->connect();
        const std::vector<int> id = bus_->readInputRegisters(IR_MAGIC, IR_CAPACITY + 1);
        if (id[IR_MAGIC] != MAGIC)
            CV_Error(Error::StsError, cv::format("ActuatorDriver::connect: '%s' is not a dynblur actuator controller "
                                                 "(input register 0 = 0x%04X, expected 0x%04X)",
                                                 bus_->getUri().c_str(), id[IR_MAGIC], (int)MAGIC));
        ActuatorInfo info;
        info.protocolMajor = id[IR_VERSION] >> 8;
        info.protocolMinor = id[IR_VERSION] & 0xFF;
        if (info.protocolMajor != PROTOCOL_MAJOR)
            CV_Error(Error::StsError, cv::format("ActuatorDriver::connect: protocol version %d.%d not supported (driver speaks %d.x)",
                                                 info.protocolMajor, info.protocolMinor, (int)PROTOCOL_MAJOR));
        info.maxLevel = id[IR_MAX_LEVEL];
        info.minDwell = id[IR_MIN_DWELL_US] * 1e-6;
        info.capacity = id[IR_CAPACITY];
        if (info.capacity < 1)
            CV_Error(Error::StsError, "ActuatorDriver::connect: the device advertises a schedule capacity of 0");
        if (std::abs(limits_.safeLevel) > info.maxLevel)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver::connect: limits.safeLevel = %d exceeds the device's max level %d",
                                                      limits_.safeLevel, info.maxLevel));
        bus_->writeRegister(HR_SAFE_LEVEL, limits_.safeLevel & 0xFFFF);
        info_ = info;
        connected_ = true;
        return info;
    }

    void checkSchedule(const SwitchSchedule& s) const CV_OVERRIDE
    {
        s.validate();
        const int n = (int)s.times.size();
        const int maxLevel = connected_ ? std::min(limits_.maxLevel, info_.maxLevel) : limits_.maxLevel;
        const char* whose = connected_ && info_.maxLevel < limits_.maxLevel ? "device max level" : "limits.maxLevel";
        for (int i = 0; i < n; ++i)
            if (std::abs(s.levels[i]) > maxLevel)
                CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver: schedule refused: levels[%d] = %d exceeds %s = ±%d",
                                                          i, s.levels[i], whose, maxLevel));
        if (std::abs(s.initialLevel) > maxLevel)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver: schedule refused: initialLevel = %d exceeds %s = ±%d",
                                                      s.initialLevel, whose, maxLevel));
        const int maxEntries = connected_ ? std::min(limits_.maxEntries, info_.capacity) : limits_.maxEntries;
        if (n > maxEntries)
            CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver: schedule refused: %d entries exceed %s = %d", n,
                                                      connected_ && info_.capacity < limits_.maxEntries ? "device capacity" : "limits.maxEntries",
                                                      maxEntries));
        const double minDwell = connected_ ? std::max(limits_.minDwell, info_.minDwell) : limits_.minDwell;
        for (int i = 1; i < n; ++i)
        {
            // Compare what will be sent: whole microseconds.
            const double dwellUs = std::round((s.times[i] - s.times[0]) * 1e6) - std::round((s.times[i - 1] - s.times[0]) * 1e6);
            if (dwellUs < std::round(minDwell * 1e6))
                CV_Error(Error::StsOutOfRange, cv::format("ActuatorDriver: schedule refused: dwell times[%d] - times[%d] = %.6f s "
                                                          "is below the minimum dwell %s = %.6f s",
                                                          i, i - 1, dwellUs * 1e-6,
                                                          connected_ && info_.minDwell > limits_.minDwell ? "of the device" : "limits.minDwell",
                                                          minDwell));
        }
        if ((s.times.back() - s.times.front()) * 1e6 > 4294967295.0)
            CV_Error(Error::StsOutOfRange, "ActuatorDriver: schedule refused: span exceeds 2^32 µs (71 min)");
    }

    void upload(const SwitchSchedule& s) CV_OVERRIDE
    {
        if (!connected_)
            connect();
        checkSchedule(s);  // nothing is sent before this passes
        verified_ = false;
        const std::vector<int> regs = encodeSchedule(s);
        const int crc = busChecksum(regs);
        const int n = (int)s.times.size();
        const ActuatorStatus st0 = status();
        if (st0.state == ACTUATOR_RUNNING)
            CV_Error(Error::StsError, "ActuatorDriver::upload: the device is running a schedule; stop() first");
        guarded("upload", [&] {
            if (st0.state == ACTUATOR_FAULT)
                bus_->writeRegister(HR_COMMAND, CMD_CLEAR_FAULT);
            // Entries first, then length/initial level/checksum, then LOAD: the device checks
            // what it holds against the checksum, so a torn upload cannot become LOADED.
            const std::vector<int> entries(regs.begin() + 2, regs.end());
            const int chunk = 120;  // 40 entries per request (Modbus allows 123 words)
            for (size_t off = 0; off < entries.size(); off += chunk)
            {
                const size_t end = std::min(entries.size(), off + chunk);
                bus_->writeRegisters(HR_ENTRIES + (int)off, std::vector<int>(entries.begin() + off, entries.begin() + end));
            }
            bus_->writeRegisters(HR_LENGTH, {regs[0], regs[1], crc});
            bus_->writeRegister(HR_COMMAND, CMD_LOAD);

            // Read back and compare everything.
            const std::vector<int> head = bus_->readHoldingRegisters(HR_LENGTH, 3);
            if (head[0] != regs[0] || head[1] != regs[1] || head[2] != crc)
                CV_Error(Error::StsError, cv::format("ActuatorDriver::upload: read-back of length/initial level/checksum "
                                                     "gave %d/%d/0x%04X, sent %d/%d/0x%04X",
                                                     head[0], asInt16(head[1]), head[2], regs[0], s.initialLevel, crc));
            for (size_t off = 0; off < entries.size(); off += chunk)
            {
                const int count = (int)std::min<size_t>(chunk, entries.size() - off);
                const std::vector<int> back = bus_->readHoldingRegisters(HR_ENTRIES + (int)off, count);
                for (int k = 0; k < count; ++k)
                    if (back[k] != entries[off + k])
                        CV_Error(Error::StsError, cv::format("ActuatorDriver::upload: read-back mismatch at entry %d "
                                                             "(register %d = %d, sent %d)",
                                                             (int)(off + k) / ENTRY_WORDS, HR_ENTRIES + (int)(off + k),
                                                             back[k], entries[off + k]));
            }
            const std::vector<int> ir = bus_->readInputRegisters(IR_STATUS, IR_COUNT - IR_STATUS);
            const int state = ir[0], devCrc = ir[IR_LOADED_CHECKSUM - IR_STATUS];
            if (state != ACTUATOR_LOADED)
                CV_Error(Error::StsError, cv::format("ActuatorDriver::upload: the device refused the schedule (%d entries): %s",
                                                     n, statusFrom(ir).describe().c_str()));
            if (devCrc != crc)
                CV_Error(Error::StsError, cv::format("ActuatorDriver::upload: the device's checksum 0x%04X differs from the "
                                                     "host's 0x%04X", devCrc, crc));
        });
        verified_ = true;
        crc_ = crc;
        schedule_ = s;
    }

    StartReport start() CV_OVERRIDE
    {
        if (!verified_)
            CV_Error(Error::StsError, "ActuatorDriver::start: no verified schedule; call upload() first");
        StartReport report;
        const std::vector<int> ir = bus_->readInputRegisters(IR_STATUS, IR_COUNT - IR_STATUS);
        const ActuatorStatus st = statusFrom(ir);
        if (st.state != ACTUATOR_LOADED)
            CV_Error(Error::StsError, "ActuatorDriver::start: the device no longer holds the verified schedule: " +
                                          st.describe());
        if (ir[IR_LOADED_CHECKSUM - IR_STATUS] != crc_)
            CV_Error(Error::StsError, cv::format("ActuatorDriver::start: loaded checksum 0x%04X differs from the verified 0x%04X",
                                                 ir[IR_LOADED_CHECKSUM - IR_STATUS], crc_));
        if (st.currentLevel != schedule_.initialLevel)
            CV_Error(Error::StsError, cv::format("ActuatorDriver::start: the actuators hold level %d but the schedule's "
                                                 "initialLevel is %d", st.currentLevel, schedule_.initialLevel));
        verified_ = false;  // a schedule is started once
        guarded("start", [&] {
            bus_->writeRegister(HR_COMMAND, CMD_START);
            report.commandRoundTrip = bus_->getLastRoundTrip();
            // Start stamp and clock in one read; keep the fastest of a few (the tightest bracket).
            double best = 1e9;
            for (int k = 0; k < 3; ++k)
            {
                const std::vector<int> r = bus_->readInputRegisters(IR_STATUS, IR_COUNT - IR_STATUS);
                const double rtt = bus_->getLastRoundTrip();
                const double mid = bus_->getLastSendTime() + 0.5 * rtt;
                const uint64_t startUs = asU64(r, IR_START_TIME_US - IR_STATUS);
                const uint64_t clockUs = asU64(r, IR_CLOCK_US - IR_STATUS);
                if (k == 0 && r[0] != ACTUATOR_RUNNING && r[0] != ACTUATOR_DONE)
                    CV_Error(Error::StsError, "ActuatorDriver::start: the device did not start: " + statusFrom(r).describe());
                if (clockUs < startUs)
                    CV_Error(Error::StsError, "ActuatorDriver::start: the device's clock is before its start stamp");
                if (rtt < best)
                {
                    best = rtt;
                    report.controllerStartTime = startUs * 1e-6;
                    report.hostStartTime = mid - (clockUs - startUs) * 1e-6;
                    report.uncertainty = rtt;
                }
            }
            report.scheduleOrigin = schedule_.times.front();
        });
        return report;
    }

    ActuatorStatus status() CV_OVERRIDE
    {
        return statusFrom(bus_->readInputRegisters(IR_STATUS, IR_COUNT - IR_STATUS));
    }

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
    static ActuatorStatus statusFrom(const std::vector<int>& ir)  // ir starts at IR_STATUS
    {
        ActuatorStatus st;
        st.state = ir[0];
        st.fault = ir[IR_FAULT - IR_STATUS];
        st.currentLevel = asInt16(ir[IR_CURRENT_LEVEL - IR_STATUS]);
        const int idx = ir[IR_ENTRY_INDEX - IR_STATUS];
        st.entryIndex = idx == 0xFFFF ? -1 : idx;
        return st;
    }

    // Runs `body`; on any error applies the safe level when it can and rethrows with the status.
    template <class F>
    void guarded(const char* what, F body)
    {
        try
        {
            body();
        }
        catch (const cv::Exception& e)
        {
            verified_ = false;
            // Apply the safe level, then read the status: a failed status read does not mean that
            // the acknowledged stop was not applied.
            std::string after;
            bool stopped = false;
            try
            {
                bus_->writeRegister(HR_COMMAND, CMD_STOP);
                stopped = true;
                after = "; safe level applied, device status: " + status().describe();
            }
            catch (const cv::Exception& e2)
            {
                after = stopped ? "; safe level applied, device status unreadable: " + e2.err
                                : "; could not apply the safe level: " + e2.err;
            }
            CV_Error(Error::StsError, std::string("ActuatorDriver::") + what + " failed: " + e.err + after);
        }
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
