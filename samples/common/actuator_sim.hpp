// The actuator controller simulator: serves the register map of docs/actuator-bus.md over Modbus
// TCP (127.0.0.1 only) and Modbus RTU on a pseudo-terminal, runs the plant in real time while a
// schedule runs, logs θ(t) as CSV (t,theta,level) and injects faults for tests. Used by the
// dynblur_actuator_sim program and, in-process, by tests/test_bus.cpp.
#ifndef DYNBLUR_SAMPLES_ACTUATOR_SIM_HPP
#define DYNBLUR_SAMPLES_ACTUATOR_SIM_HPP

#include <opencv2/dynblur.hpp>

#include <memory>
#include <string>

namespace dynblur_samples {

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
};

struct SimConfig
{
    cv::Ptr<cv::dynblur::Plant> plant;  //!< default: the seed's 14.4 Hz, ζ 0.12, 1°/level
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

    void setFaults(const SimFaults& faults);

    // Inspection (thread-safe).
    int state() const;            //!< cv::dynblur::ActuatorState
    int fault() const;            //!< cv::dynblur::ActuatorFault
    int currentLevel() const;     //!< cells
    int startCount() const;       //!< schedules started so far
    int requestCount() const;     //!< requests received so far
    double theta() const;         //!< current plant angle, radians
    //! Host steady_clock time (seconds) of the last start, the truth a driver's StartReport estimates.
    double lastStartHostTime() const;
    std::string statusLine() const;  //!< one line for progress output

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace dynblur_samples

#endif
