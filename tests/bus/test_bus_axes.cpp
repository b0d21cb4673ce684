// SPDX-License-Identifier: Apache-2.0
// A controller of several axes: MultiAxisDriver against the simulator over Modbus TCP (and RTU on a
// pty): every axis verified before one START starts them all, none started when any axis fails,
// the refusals of a count mismatch, and a one-axis host on a device of several axes.
#include "actuator_sim.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <thread>
#include <vector>

using namespace cv::dynblur;
using namespace dynblur_samples;

namespace {

// Axis k's move: a different one per axis (levels and switching times), as a pan and a tilt make.
SwitchSchedule axisMove(int k)
{
    const double d = 0.002 * k;
    return SwitchSchedule({0.0, 0.0113 + d, 0.0262 + d, 0.040 + d}, {4 + k, 10 - k, 7, 10 - 2 * k}, 0);
}

std::vector<SwitchSchedule> moves(int axes)
{
    std::vector<SwitchSchedule> all;
    for (int k = 0; k < axes; ++k)
        all.push_back(axisMove(k));
    return all;
}

SimConfig axesConfig(int axes, bool tcp = true)
{
    SimConfig cfg;
    cfg.axes = axes;
    cfg.tcp = tcp;
    cfg.rtu = !tcp;
    cfg.tcpPort = 0;
    return cfg;
}

// A simulator of `cfg.axes` axes and a host that drives `hostAxes` of them (not connected yet).
struct AxesRig
{
    AxesRig(const SimConfig& cfg, int hostAxes, double timeout = 2.0, int retries = 2) : sim(cfg)
    {
        sim.start();
        const std::string uri = cfg.tcp ? cv::format("tcp://127.0.0.1:%d", sim.tcpPort())
                                        : "rtu:" + sim.ptyPath() + "?baud=115200&slave=1";
        bus = ActuatorBus::create(uri, timeout, retries);
        driver = MultiAxisDriver::create(bus, hostAxes);
    }
    ActuatorSim sim;
    cv::Ptr<ActuatorBus> bus;
    cv::Ptr<MultiAxisDriver> driver;
};

void expectThrowsWith(const std::function<void()>& f, const std::vector<std::string>& needles)
{
    try
    {
        f();
        ADD_FAILURE() << "expected a cv::Exception containing '" << needles[0] << "'";
    }
    catch (const cv::Exception& e)
    {
        std::printf("[ refused ] %s\n", e.err.c_str());
        for (const std::string& needle : needles)
            EXPECT_NE(e.err.find(needle), std::string::npos) << "message: " << e.err;
    }
}

void expectNoAxisStarted(AxesRig& rig)
{
    EXPECT_EQ(rig.sim.startCount(), 0);
    for (int k = 0; k < rig.sim.axisCount(); ++k)
    {
        EXPECT_NE(rig.sim.state(k), ACTUATOR_LOADED) << "axis " << k;
        EXPECT_NE(rig.sim.state(k), ACTUATOR_RUNNING) << "axis " << k;
        EXPECT_EQ(rig.sim.currentLevel(k), 0) << "axis " << k;
    }
}

// Upload, verify, start all; one controller instant for every axis, within the reported
// uncertainty of the simulator's truth; each axis runs its own schedule to its end.
void uploadStartAll(AxesRig& rig, int axes)
{
    const ActuatorInfo info = rig.driver->connect();
    EXPECT_EQ(info.axes, rig.sim.axisCount());
    EXPECT_EQ(info.protocolMinor, busmap::PROTOCOL_MINOR);
    rig.driver->upload(moves(axes));
    for (const ActuatorStatus& st : rig.driver->statusAll())
        EXPECT_EQ(st.state, ACTUATOR_LOADED) << st.describe();
    const std::vector<StartReport> reports = rig.driver->start();
    ASSERT_EQ((int)reports.size(), axes);
    EXPECT_EQ(rig.sim.startCount(), 1);
    for (int k = 0; k < axes; ++k)
    {
        EXPECT_EQ(reports[k].controllerStartTime, reports[0].controllerStartTime) << "axis " << k;
        EXPECT_EQ(reports[k].hostStartTime, reports[0].hostStartTime) << "axis " << k;
        EXPECT_EQ(rig.sim.lastStartHostTime(k), rig.sim.lastStartHostTime(0)) << "axis " << k;
        EXPECT_LE(std::abs(reports[k].hostStartTime - rig.sim.lastStartHostTime(k)), reports[k].uncertainty + 2e-6);
    }
    const std::vector<SimStartRecord> started = rig.sim.takeStarts();
    ASSERT_EQ((int)started.size(), axes);
    for (int k = 0; k < axes; ++k)
    {
        EXPECT_EQ(started[k].axis, k);
        EXPECT_EQ(started[k].levels, axisMove(k).levels);
    }
    const std::vector<ActuatorStatus> done = rig.driver->waitUntilDone(2.0);
    for (int k = 0; k < axes; ++k)
    {
        EXPECT_EQ(done[k].state, ACTUATOR_DONE) << done[k].describe();
        EXPECT_EQ(done[k].currentLevel, axisMove(k).levels.back());
    }
    expectThrowsWith([&] { rig.driver->start(); }, {"no verified schedules"});  // started once
}

}  // namespace

TEST(BusAxes, UploadVerifyStartTwoAxesOverTcp)
{
    AxesRig rig(axesConfig(2), 2);
    uploadStartAll(rig, 2);
}

TEST(BusAxes, UploadVerifyStartThreeAxesOverTcp)
{
    AxesRig rig(axesConfig(3), 3);
    uploadStartAll(rig, 3);
    // Again from where they rest: a schedule that starts at each axis's held level.
    std::vector<SwitchSchedule> back;
    for (int k = 0; k < 3; ++k)
        back.push_back(SwitchSchedule({0.0, 0.01}, {5, 0}, axisMove(k).levels.back()));
    rig.driver->upload(back);
    rig.driver->start();
    for (const ActuatorStatus& st : rig.driver->waitUntilDone(2.0))
        EXPECT_EQ(st.currentLevel, 0) << st.describe();
}

TEST(BusAxes, UploadVerifyStartTwoAxesOverRtuPty)
{
    AxesRig rig(axesConfig(2, false), 2);
    uploadStartAll(rig, 2);
}

TEST(BusAxes, EachAxisMovesItsOwnPlant)
{
    SimConfig cfg = axesConfig(2);
    cfg.axisPlants = {Plant::create(14.4, 0.12, CV_PI / 180), Plant::create(9.0, 0.2, 0.5 * CV_PI / 180)};
    AxesRig rig(cfg, 2);
    uploadStartAll(rig, 2);
    std::this_thread::sleep_for(std::chrono::milliseconds(600));  // both settle (ζωn ≥ 10 /s)
    EXPECT_NEAR(rig.sim.theta(0), 10 * CV_PI / 180, 0.2 * CV_PI / 180);
    EXPECT_NEAR(rig.sim.theta(1), 8 * 0.5 * CV_PI / 180, 0.2 * CV_PI / 180);
}

TEST(BusAxes, ABadScheduleOnOneAxisStartsNone)
{
    AxesRig rig(axesConfig(3), 3);
    rig.driver->connect();
    // Refused on the host: nothing is sent to any axis.
    std::vector<SwitchSchedule> bad = moves(3);
    bad[1] = SwitchSchedule({0, 0.01}, {4, 17}, 0);
    const int before = rig.sim.requestCount();
    expectThrowsWith([&] { rig.driver->upload(bad); }, {"axis 1", "levels[1] = 17 exceeds limits.maxLevel"});
    EXPECT_EQ(rig.sim.requestCount(), before) << "a refused schedule must send nothing";
    expectNoAxisStarted(rig);

    // Refused by the device: axis 2's memory flips a bit of its second entry's level, its LOAD fails
    // the checksum; axes 0 and 1, already verified, are stopped with it.
    SimFaults memory;
    memory.corruptRegister = busmap::axisHoldingBase(2) + busmap::HR_ENTRIES - busmap::HR_COMMAND + 5;
    rig.sim.setFaults(memory);
    expectThrowsWith([&] { rig.driver->upload(moves(3)); },
                     {"MultiAxisDriver::upload failed: axis 2: read-back mismatch at entry 1", "safe level applied",
                      "axis 2 FAULT (fault 2: bad checksum)"});
    expectNoAxisStarted(rig);
    expectThrowsWith([&] { rig.driver->start(); }, {"no verified schedules"});
    EXPECT_EQ(rig.sim.startCount(), 0);

    // A Modbus exception to axis 1's LOAD: the message names the axis and the Modbus error.
    SimFaults refuse;
    refuse.exceptionFunction = 6;
    refuse.exceptionRegister = busmap::axisHoldingBase(1);
    rig.sim.setFaults(refuse);
    expectThrowsWith([&] { rig.driver->upload(moves(3)); }, {"axis 1: ", "Modbus exception reply"});
    expectNoAxisStarted(rig);

    // The faults gone, the same schedules start.
    rig.sim.setFaults(SimFaults());
    rig.driver->upload(moves(3));
    rig.driver->start();
    EXPECT_EQ(rig.sim.startCount(), 1);
}

TEST(BusAxes, AnAxisChangedAfterVerificationStartsNone)
{
    AxesRig rig(axesConfig(2), 2);
    rig.driver->connect();
    rig.driver->upload(moves(2));
    // Another host rewrites axis 1's length: the device unloads it; the START is not sent.
    rig.bus->writeRegister(busmap::axisHoldingBase(1) + busmap::HR_LENGTH - busmap::HR_COMMAND, 4);
    expectThrowsWith([&] { rig.driver->start(); }, {"axis 1 no longer holds its verified schedule", "nothing started"});
    EXPECT_EQ(rig.sim.startCount(), 0);
    EXPECT_EQ(rig.sim.state(0), ACTUATOR_LOADED);  // nothing was sent: axis 0 still waits
}

TEST(BusAxes, DeviceStartsNothingWhileAnAxisIsInFault)
{
    // Written by hand (not through the driver): axis 0 loaded, axis 1 refused; one START.
    AxesRig rig(axesConfig(2), 2);
    rig.driver->connect();
    for (int k = 0; k < 2; ++k)
    {
        const std::vector<int> regs = encodeSchedule(axisMove(k));
        const int base = busmap::axisHoldingBase(k);
        rig.bus->writeRegisters(base + busmap::HR_ENTRIES - busmap::HR_COMMAND, std::vector<int>(regs.begin() + 2, regs.end()));
        rig.bus->writeRegisters(base + busmap::HR_LENGTH - busmap::HR_COMMAND,
                                {regs[0], regs[1], busChecksum(regs) ^ (k == 1 ? 1 : 0)});
        rig.bus->writeRegister(base, CMD_LOAD);
    }
    EXPECT_EQ(rig.sim.state(0), ACTUATOR_LOADED);
    EXPECT_EQ(rig.sim.fault(1), FAULT_BAD_CHECKSUM);
    rig.bus->writeRegister(busmap::HR_COMMAND, CMD_START);
    EXPECT_EQ(rig.sim.startCount(), 0);
    const std::vector<ActuatorStatus> st = rig.driver->statusAll();
    EXPECT_EQ(st[0].fault, FAULT_NOT_LOADED) << st[0].describe();
    EXPECT_EQ(st[1].fault, FAULT_BAD_CHECKSUM) << st[1].describe();  // its own fault is kept
    // An axis's command register takes LOAD only.
    rig.driver->clearFault();
    rig.bus->writeRegister(busmap::axisHoldingBase(1), CMD_START);
    EXPECT_EQ(rig.driver->status(1).fault, FAULT_BAD_COMMAND);
    EXPECT_EQ(rig.driver->status(0).state, ACTUATOR_IDLE);
}

TEST(BusAxes, FewerAxesThanAskedIsAnError)
{
    AxesRig rig(axesConfig(2), 3);
    expectThrowsWith([&] { rig.driver->connect(); }, {"has 2 axes, the host asks for 3"});
    // A device made before several axes (protocol 1.0, no axis count) has one.
    SimConfig old = axesConfig(1);
    old.oneAxisMap = true;
    AxesRig oldRig(old, 2);
    expectThrowsWith([&] { oldRig.driver->connect(); }, {"has 1 axis, the host asks for 2"});
    // One axis of it drives as any one-axis device.
    AxesRig oneRig(old, 1);
    EXPECT_EQ(oneRig.driver->connect().protocolMinor, 0);
    oneRig.driver->upload(moves(1));
    oneRig.driver->start();
    EXPECT_EQ(oneRig.driver->waitUntilDone(2.0)[0].state, ACTUATOR_DONE);
}

TEST(BusAxes, ScheduleCountMustMatchTheAxes)
{
    AxesRig rig(axesConfig(3), 2);
    rig.driver->connect();
    const int before = rig.sim.requestCount();
    expectThrowsWith([&] { rig.driver->upload(moves(3)); }, {"3 schedules for 2 axes"});
    expectThrowsWith([&] { rig.driver->upload(moves(1)); }, {"1 schedules for 2 axes"});
    EXPECT_EQ(rig.sim.requestCount(), before);
    expectThrowsWith([&] { rig.driver->status(2); }, {"axis = 2 must be in [0, 2)"});
    expectThrowsWith([] { MultiAxisDriver::create(ActuatorBus::create("tcp://127.0.0.1:1502"), 0); },
                     {"axes = 0 must be in [1, 7]"});
    expectThrowsWith([] { MultiAxisDriver::create(cv::Ptr<ActuatorBus>(), 2); }, {"MultiAxisDriver::create: bus is empty"});
}

TEST(BusAxes, FurtherAxesTheHostDoesNotDriveStayIdle)
{
    AxesRig rig(axesConfig(3), 2);
    rig.driver->connect();
    // A schedule left loaded on axis 2 (by another host) must not start with the two driven ones.
    const std::vector<int> regs = encodeSchedule(axisMove(2));
    const int base = busmap::axisHoldingBase(2);
    rig.bus->writeRegisters(base + busmap::HR_ENTRIES - busmap::HR_COMMAND, std::vector<int>(regs.begin() + 2, regs.end()));
    rig.bus->writeRegisters(base + busmap::HR_LENGTH - busmap::HR_COMMAND, {regs[0], regs[1], busChecksum(regs)});
    rig.bus->writeRegister(base, CMD_LOAD);
    ASSERT_EQ(rig.sim.state(2), ACTUATOR_LOADED);
    rig.driver->upload(moves(2));
    EXPECT_EQ(rig.sim.state(2), ACTUATOR_IDLE);
    rig.driver->start();
    EXPECT_EQ(rig.sim.state(2), ACTUATOR_IDLE);
    EXPECT_EQ(rig.sim.currentLevel(2), 0);
    EXPECT_EQ((int)rig.sim.takeStarts().size(), 2);
}

TEST(BusAxes, OneAxisHostOnADeviceOfSeveralAxes)
{
    SimConfig cfg = axesConfig(3);
    ActuatorSim sim(cfg);
    sim.start();
    cv::Ptr<ActuatorDriver> driver = ActuatorDriver::create(ActuatorBus::create(cv::format("tcp://127.0.0.1:%d", sim.tcpPort()), 2.0));
    EXPECT_EQ(driver->connect().axes, 3);
    driver->upload(axisMove(0));
    const StartReport r = driver->start();
    EXPECT_LE(std::abs(r.hostStartTime - sim.lastStartHostTime(0)), r.uncertainty + 2e-6);
    EXPECT_EQ(driver->waitUntilDone(2.0).state, ACTUATOR_DONE);
    for (int k = 1; k < 3; ++k)
    {
        EXPECT_EQ(sim.state(k), ACTUATOR_IDLE);
        EXPECT_EQ(sim.currentLevel(k), 0);
    }
}

TEST(BusAxesFaults, ConnectionLostDuringOneAxisUploadStartsNone)
{
    AxesRig rig(axesConfig(2), 2, 0.3, 2);
    rig.driver->connect();
    SimFaults f;
    f.dropAfter = 9;  // 2 status reads, axis 0's 6 requests, then axis 1's entry write is lost
    rig.sim.setFaults(f);
    expectThrowsWith([&] { rig.driver->upload(moves(2)); }, {"MultiAxisDriver::upload failed: axis 1: "});
    expectNoAxisStarted(rig);
    expectThrowsWith([&] { rig.driver->start(); }, {"no verified schedules"});
    // The link recovers: the next upload succeeds and starts both.
    rig.driver->upload(moves(2));
    rig.driver->start();
    EXPECT_EQ(rig.sim.startCount(), 1);
}

TEST(BusAxesFaults, BadReplyDuringAReadBackStartsNone)
{
    for (int kind = 0; kind < 2; ++kind)
    {
        AxesRig rig(axesConfig(3), 3, 0.2, 0);
        rig.driver->connect();
        SimFaults f;
        (kind == 0 ? f.garbageAfter : f.shortAfter) = 3 + 6 + 6 + 4;  // axis 2's first read-back
        rig.sim.setFaults(f);
        expectThrowsWith([&] { rig.driver->upload(moves(3)); }, {"axis 2: "});
        expectNoAxisStarted(rig);
    }
}
