// SPDX-License-Identifier: Apache-2.0
// One axis's registers as both drivers read and write them (docs/actuator-bus.md).
#include "precomp.hpp"
#include "bus/axis_registers.hpp"

#include <chrono>

namespace cv {
namespace dynblur {
namespace bus_detail {

using namespace busmap;

namespace {

int asInt16(int word) { return word >= 32768 ? word - 65536 : word; }

uint64_t asU64(const std::vector<int>& r, int at)
{
    uint64_t v = 0;
    for (int i = 0; i < 4; ++i)
        v = (v << 16) | static_cast<uint64_t>(r[at + i] & 0xFFFF);
    return v;
}

const int kInputs = IR_COUNT - IR_STATUS;  // registers of an input block
const int kChunk = 120;                    // entry words per request: 40 entries (Modbus allows 123 words)

}  // namespace

double steadyNow()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void checkDriverArguments(const Ptr<ActuatorBus>& bus, const ActuatorLimits& limits, const char* who)
{
    if (!bus)
        CV_Error(Error::StsNullPtr, cv::format("%s: bus is empty", who));
    if (limits.maxLevel < 0 || limits.maxLevel > 32767)
        CV_Error(Error::StsOutOfRange, cv::format("%s: limits.maxLevel = %d must be in [0, 32767]", who, limits.maxLevel));
    if (!(limits.minDwell >= 0 && limits.minDwell <= 1))
        CV_Error(Error::StsOutOfRange, cv::format("%s: limits.minDwell = %g s must be in [0, 1]", who, limits.minDwell));
    if (limits.maxEntries < 1 || limits.maxEntries > 65535)
        CV_Error(Error::StsOutOfRange, cv::format("%s: limits.maxEntries = %d must be in [1, 65535]", who, limits.maxEntries));
    if (std::abs(limits.safeLevel) > limits.maxLevel)
        CV_Error(Error::StsOutOfRange, cv::format("%s: limits.safeLevel = %d must be within ±maxLevel = %d", who,
                                                  limits.safeLevel, limits.maxLevel));
}

ActuatorInfo identify(ActuatorBus& bus, const ActuatorLimits& limits, const char* who)
{
    const std::vector<int> id = bus.readInputRegisters(IR_MAGIC, IR_CAPACITY + 1);
    if (id[IR_MAGIC] != MAGIC)
        CV_Error(Error::StsError, cv::format("%s::connect: '%s' is not a dynblur actuator controller "
                                             "(input register 0 = 0x%04X, expected 0x%04X)",
                                             who, bus.getUri().c_str(), id[IR_MAGIC], (int)MAGIC));
    ActuatorInfo info;
    info.protocolMajor = id[IR_VERSION] >> 8;
    info.protocolMinor = id[IR_VERSION] & 0xFF;
    if (info.protocolMajor != PROTOCOL_MAJOR)
        CV_Error(Error::StsError, cv::format("%s::connect: protocol version %d.%d not supported (driver speaks %d.x)",
                                             who, info.protocolMajor, info.protocolMinor, (int)PROTOCOL_MAJOR));
    info.maxLevel = id[IR_MAX_LEVEL];
    info.minDwell = id[IR_MIN_DWELL_US] * 1e-6;
    info.capacity = id[IR_CAPACITY];
    if (info.capacity < 1)
        CV_Error(Error::StsError, cv::format("%s::connect: the device advertises a schedule capacity of 0", who));
    if (std::abs(limits.safeLevel) > info.maxLevel)
        CV_Error(Error::StsOutOfRange, cv::format("%s::connect: limits.safeLevel = %d exceeds the device's max level %d",
                                                  who, limits.safeLevel, info.maxLevel));
    info.axes = 1;  // a 1.0 device has no IR_AXIS_COUNT
    if (info.protocolMinor >= PROTOCOL_MINOR_AXES)
    {
        info.axes = bus.readInputRegisters(IR_AXIS_COUNT, 1)[0];
        if (info.axes < 1 || info.axes > MAX_AXES)
            CV_Error(Error::StsError, cv::format("%s::connect: the device reports %d axes; the map addresses 1 to %d",
                                                 who, info.axes, (int)MAX_AXES));
    }
    return info;
}

void checkScheduleLimits(const SwitchSchedule& s, const ActuatorLimits& limits, const ActuatorInfo* info,
                         const std::string& prefix)
{
    s.validate();
    const char* p = prefix.c_str();
    const int n = (int)s.times.size();
    const int maxLevel = info ? std::min(limits.maxLevel, info->maxLevel) : limits.maxLevel;
    const char* whose = info && info->maxLevel < limits.maxLevel ? "device max level" : "limits.maxLevel";
    for (int i = 0; i < n; ++i)
        if (std::abs(s.levels[i]) > maxLevel)
            CV_Error(Error::StsOutOfRange, cv::format("%s: schedule refused: levels[%d] = %d exceeds %s = ±%d", p, i,
                                                      s.levels[i], whose, maxLevel));
    if (std::abs(s.initialLevel) > maxLevel)
        CV_Error(Error::StsOutOfRange, cv::format("%s: schedule refused: initialLevel = %d exceeds %s = ±%d", p,
                                                  s.initialLevel, whose, maxLevel));
    const int maxEntries = info ? std::min(limits.maxEntries, info->capacity) : limits.maxEntries;
    if (n > maxEntries)
        CV_Error(Error::StsOutOfRange, cv::format("%s: schedule refused: %d entries exceed %s = %d", p, n,
                                                  info && info->capacity < limits.maxEntries ? "device capacity"
                                                                                             : "limits.maxEntries",
                                                  maxEntries));
    const double minDwell = info ? std::max(limits.minDwell, info->minDwell) : limits.minDwell;
    for (int i = 1; i < n; ++i)
    {
        // Compare what will be sent: whole microseconds.
        const double dwellUs = std::round((s.times[i] - s.times[0]) * 1e6) - std::round((s.times[i - 1] - s.times[0]) * 1e6);
        if (dwellUs < std::round(minDwell * 1e6))
            CV_Error(Error::StsOutOfRange, cv::format("%s: schedule refused: dwell times[%d] - times[%d] = %.6f s "
                                                      "is below the minimum dwell %s = %.6f s",
                                                      p, i, i - 1, dwellUs * 1e-6,
                                                      info && info->minDwell > limits.minDwell ? "of the device"
                                                                                               : "limits.minDwell",
                                                      minDwell));
    }
    if ((s.times.back() - s.times.front()) * 1e6 > 4294967295.0)
        CV_Error(Error::StsOutOfRange, prefix + ": schedule refused: span exceeds 2^32 µs (71 min)");
}

std::vector<int> readAxisInputs(ActuatorBus& bus, int axis)
{
    return bus.readInputRegisters(axisInputBase(axis), kInputs);
}

ActuatorStatus statusFromInputs(const std::vector<int>& ir)
{
    ActuatorStatus st;
    st.state = ir[0];
    st.fault = ir[IR_FAULT - IR_STATUS];
    st.currentLevel = asInt16(ir[IR_CURRENT_LEVEL - IR_STATUS]);
    const int idx = ir[IR_ENTRY_INDEX - IR_STATUS];
    st.entryIndex = idx == 0xFFFF ? -1 : idx;
    return st;
}

int loadedChecksum(const std::vector<int>& ir) { return ir[IR_LOADED_CHECKSUM - IR_STATUS]; }

int writeAndVerify(ActuatorBus& bus, int axis, const SwitchSchedule& s)
{
    const std::vector<int> regs = encodeSchedule(s);
    const int crc = busChecksum(regs);
    const int base = axisHoldingBase(axis);
    const int entriesAt = base + HR_ENTRIES - HR_COMMAND, lengthAt = base + HR_LENGTH - HR_COMMAND;
    // Entries first, then length/initial level/checksum, then LOAD: the device checks what it
    // holds against the checksum, so a torn upload cannot become LOADED.
    const std::vector<int> entries(regs.begin() + 2, regs.end());
    for (size_t off = 0; off < entries.size(); off += kChunk)
    {
        const size_t end = std::min(entries.size(), off + kChunk);
        bus.writeRegisters(entriesAt + (int)off, std::vector<int>(entries.begin() + off, entries.begin() + end));
    }
    bus.writeRegisters(lengthAt, {regs[0], regs[1], crc});
    bus.writeRegister(base, CMD_LOAD);

    // Read back and compare everything.
    const std::vector<int> head = bus.readHoldingRegisters(lengthAt, 3);
    if (head[0] != regs[0] || head[1] != regs[1] || head[2] != crc)
        CV_Error(Error::StsError, cv::format("read-back of length/initial level/checksum gave %d/%d/0x%04X, "
                                             "sent %d/%d/0x%04X",
                                             head[0], asInt16(head[1]), head[2], regs[0], s.initialLevel, crc));
    for (size_t off = 0; off < entries.size(); off += kChunk)
    {
        const int count = (int)std::min<size_t>(kChunk, entries.size() - off);
        const std::vector<int> back = bus.readHoldingRegisters(entriesAt + (int)off, count);
        for (int k = 0; k < count; ++k)
            if (back[k] != entries[off + k])
                CV_Error(Error::StsError, cv::format("read-back mismatch at entry %d (register %d = %d, sent %d)",
                                                     (int)(off + k) / ENTRY_WORDS, entriesAt + (int)(off + k), back[k],
                                                     entries[off + k]));
    }
    const std::vector<int> ir = readAxisInputs(bus, axis);
    if (ir[0] != ACTUATOR_LOADED)
        CV_Error(Error::StsError, cv::format("the device refused the schedule (%d entries): %s", regs[0],
                                             statusFromInputs(ir).describe().c_str()));
    if (loadedChecksum(ir) != crc)
        CV_Error(Error::StsError, cv::format("the device's checksum 0x%04X differs from the host's 0x%04X",
                                             loadedChecksum(ir), crc));
    return crc;
}

StartStamp readStartStamp(ActuatorBus& bus, int axis)
{
    const std::vector<int> r = readAxisInputs(bus, axis);
    StartStamp stamp;
    stamp.roundTrip = bus.getLastRoundTrip();
    const double mid = bus.getLastSendTime() + 0.5 * stamp.roundTrip;
    const uint64_t startUs = asU64(r, IR_START_TIME_US - IR_STATUS);
    const uint64_t clockUs = asU64(r, IR_CLOCK_US - IR_STATUS);
    if (clockUs < startUs)
        CV_Error(Error::StsError, "the device's clock is before its start stamp");
    stamp.status = statusFromInputs(r);
    stamp.controllerStartTime = startUs * 1e-6;
    stamp.hostStartTime = mid - (clockUs - startUs) * 1e-6;
    return stamp;
}

StartStamp readStartStampFastest(ActuatorBus& bus, int axis)
{
    StartStamp best = readStartStamp(bus, axis);
    for (int i = 1; i < 3; ++i)
    {
        const StartStamp stamp = readStartStamp(bus, axis);
        if (stamp.roundTrip < best.roundTrip)
            best = stamp;
    }
    return best;
}

void runGuarded(ActuatorBus& bus, const std::string& who, const char* what, const std::function<void()>& body,
                const std::function<std::string()>& describeStatus)
{
    try
    {
        body();
    }
    catch (const cv::Exception& e)
    {
        // Apply the safe level, then read the status: a failed status read does not mean that
        // the acknowledged stop was not applied.
        std::string after;
        bool stopped = false;
        try
        {
            bus.writeRegister(HR_COMMAND, CMD_STOP);
            stopped = true;
            after = "; safe level applied, device status: " + describeStatus();
        }
        catch (const cv::Exception& e2)
        {
            after = stopped ? "; safe level applied, device status unreadable: " + e2.err
                            : "; could not apply the safe level: " + e2.err;
        }
        CV_Error(Error::StsError, who + "::" + what + " failed: " + e.err + after);
    }
}

}  // namespace bus_detail
}  // namespace dynblur
}  // namespace cv
