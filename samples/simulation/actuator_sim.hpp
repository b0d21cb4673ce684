// SPDX-License-Identifier: Apache-2.0
// The actuator controller simulator: serves the register map of docs/actuator-bus.md over Modbus
// TCP (127.0.0.1 only) and Modbus RTU on a pseudo-terminal for one axis or several (actuator_axis.hpp),
// runs each axis's plant in real time while a schedule runs, logs θ(t) as CSV (t,theta,level; with
// several axes t,theta0,level0,theta1,level1,...) and injects faults for tests. Used by the
// dynblur_actuator_sim program and, in-process, by tests/bus/.
#ifndef DYNBLUR_SAMPLES_ACTUATOR_SIM_HPP
#define DYNBLUR_SAMPLES_ACTUATOR_SIM_HPP

#include "actuator_axis.hpp"

#include <opencv2/dynblur.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dynblur_samples {

//! Kinds of injected faults (bit i of SimFaults::randomKinds enables kind i).
enum SimFaultKind
{
    SIM_FAULT_DROP_REQUEST = 0,  //!< close the connection; the request is not executed
    SIM_FAULT_DROP_REPLY = 1,    //!< execute the request, then close the connection without answering
    SIM_FAULT_DELAY = 2,         //!< execute and answer late (after the delay)
    SIM_FAULT_EXCEPTION = 3,     //!< answer with a Modbus exception; the request is not executed
    SIM_FAULT_GARBAGE = 4,       //!< answer with random bytes (random faults: executed or not, at random)
    SIM_FAULT_SHORT = 5,         //!< answer with the start of a reply (random faults: executed or not, at random)
    SIM_FAULT_KINDS = 6
};

//! Name of a SimFaultKind, e.g. "drop request".
const char* simFaultName(int kind);

//! Faults to inject. Counted requests are those received after setFaults(); -1 disables.
struct SimFaults
{
    int dropAfter = -1;          //!< close the connection instead of answering request N (1-based), once
    int delayMs = 0;             //!< delay every reply, milliseconds
    int exceptionFunction = -1;  //!< answer this function code (3, 4, 6, 16) with an exception...
    int exceptionRegister = -1;  //!< ...when the request covers this register (-1: any register)
    int exceptionCode = 4;       //!< Modbus exception code sent (4: server device failure)
    int garbageAfter = -1;       //!< answer request N with random bytes, once
    int shortAfter = -1;         //!< answer request N with the first half of its reply, once
    int corruptRegister = -1;    //!< store every write to this holding register with its lowest bit flipped (a memory fault)

    // Random faults: each request gets one fault with probability randomRate, of a kind drawn
    // uniformly among randomKinds, from a generator seeded with randomSeed (the same seed gives
    // the same decisions for the same sequence of requests).
    double randomRate = 0;                             //!< in [0, 1]
    unsigned randomSeed = 1;
    int randomKinds = (1 << SIM_FAULT_KINDS) - 1;      //!< bit mask of SimFaultKind
    int randomDelayMs = 300;                           //!< delay of SIM_FAULT_DELAY (choose beyond the host's timeout)
    int randomExceptionCode = 4;                       //!< code of SIM_FAULT_EXCEPTION (4: server device failure)
};

//! Faults injected so far (one-shot and random; a delayMs reply counts as SIM_FAULT_DELAY).
struct SimFaultCounts
{
    int byKind[SIM_FAULT_KINDS] = {};
    int total = 0;
    int retriableOnReads = 0;  //!< faults on reads (function 3, 4) other than exception replies: a host may retry these
};

//! What the simulator started: the loaded schedule as it held it at START.
struct SimStartRecord
{
    int axis = 0;                    //!< the axis started (one record per axis a START started)
    int initialLevel = 0;            //!< cells
    std::vector<uint32_t> offsetsUs; //!< entry offsets from the start, microseconds
    std::vector<int> levels;         //!< cells
    int checksum = 0;                //!< CRC the simulator computed at LOAD
};

struct SimConfig
{
    cv::Ptr<cv::dynblur::Plant> plant;  //!< default: the seed's 14.4 Hz, ζ 0.12, 1°/level
    int axes = 1;                       //!< axes the controller drives, in [1, busmap::MAX_AXES]
    std::vector<cv::Ptr<cv::dynblur::Plant>> axisPlants;  //!< plant of axis k when given (k < size), else `plant`
    bool oneAxisMap = false;            //!< serve the protocol 1.0 map (no IR_AXIS_COUNT), as a device made before several axes
    int maxLevel = 16;                  //!< advertised, cells
    int minDwellUs = 1000;              //!< advertised, microseconds
    int capacity = 256;                 //!< advertised, entries
    bool tcp = true;                    //!< serve Modbus TCP on 127.0.0.1
    int tcpPort = 0;                    //!< 0: any free port (see tcpPort())
    bool rtu = false;                   //!< serve Modbus RTU on a pseudo-terminal (see ptyPath())
    int rtuSlave = 1;                   //!< RTU slave address
    std::string csvPath;                //!< θ(t) log while running ("" = none)
    double logRateHz = 1000;            //!< log and level-update rate
    double logTail = 1.0;               //!< keep logging this long after the last switch, seconds
    double startLatency = 0.0;          //!< the plant moves this long after a level is applied, seconds
};

class ActuatorSim
{
public:
    explicit ActuatorSim(const SimConfig& config);
    ~ActuatorSim();  // stops
    ActuatorSim(const ActuatorSim&) = delete;
    ActuatorSim& operator=(const ActuatorSim&) = delete;

    //! Opens the listening socket / pseudo-terminal and starts the threads; throws on failure.
    void start();
    //! Stops the threads and closes everything (idempotent).
    void stop();

    int tcpPort() const;          //!< bound TCP port (0 when TCP is off)
    std::string ptyPath() const;  //!< slave pseudo-terminal path ("" when RTU is off)

    //! Replaces the faults (one-shot counters restart from here); the counts are kept.
    void setFaults(const SimFaults& faults);
    SimFaultCounts faultCounts() const;
    //! The schedules started since the last call (at most the last 1000 are kept), oldest first.
    std::vector<SimStartRecord> takeStarts();

    // Inspection (thread-safe); `axis` in [0, axes).
    int axisCount() const;
    int state(int axis = 0) const;         //!< cv::dynblur::ActuatorState
    int fault(int axis = 0) const;         //!< cv::dynblur::ActuatorFault
    int currentLevel(int axis = 0) const;  //!< cells
    int startCount() const;                //!< START commands that started something
    int requestCount() const;              //!< requests received so far
    double theta(int axis = 0) const;      //!< current plant angle, radians
    //! Host steady_clock time (seconds) of the axis's last start, the truth a driver's StartReport estimates.
    double lastStartHostTime(int axis = 0) const;
    //! Host steady_clock time (seconds) when the switching loop applied the axis's entry 1 in its last run; 0 before.
    double lastFirstSwitchHostTime(int axis = 0) const;
    std::string statusLine() const;  //!< one line for progress output

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace dynblur_samples

#endif
