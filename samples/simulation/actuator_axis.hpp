// SPDX-License-Identifier: Apache-2.0
// One axis of the simulated actuator controller: its state machine (LOAD checks, start, switching,
// stop, faults) over its block of registers, and the plant it moves (θ(t) from the levels it
// applied). ActuatorSim (actuator_sim.hpp) holds one per axis and serves their registers.
#ifndef DYNBLUR_SAMPLES_ACTUATOR_AXIS_HPP
#define DYNBLUR_SAMPLES_ACTUATOR_AXIS_HPP

#include <opencv2/dynblur.hpp>

#include <cstdint>
#include <vector>

namespace dynblur_samples {

//! What a device advertises for every axis (input registers 4..6).
struct SimAxisLimits
{
    int maxLevel = 16;      //!< cells
    int minDwellUs = 1000;  //!< microseconds
    int capacity = 256;     //!< entries
};

class SimAxis
{
public:
    SimAxis(const cv::Ptr<cv::dynblur::Plant>& plant, double startLatency);

    /** Checks the schedule in its holding block (`holding` points at its command register, laid out
    as HR_COMMAND..the entries): LOADED, or FAULT with the safe level applied. Ignored while RUNNING. */
    void load(const uint16_t* holding, const SimAxisLimits& limits, uint64_t nowUs);
    //! Starts the loaded schedule at nowUs (the state must be LOADED).
    void start(uint64_t nowUs);
    //! Switches the entries due by nowUs; DONE after the last.
    void tick(uint64_t nowUs);
    //! The safe level; back to IDLE unless in FAULT.
    void stop(int safeLevel, uint64_t nowUs);
    void enterFault(int code, int safeLevel, uint64_t nowUs);
    void clearFault();
    //! A write to the schedule registers: a LOADED schedule must be loaded again.
    void unload();

    /** Fills its input block (laid out as IR_STATUS..IR_ENTRY_INDEX). */
    void fillInputs(uint16_t* inputs, uint64_t clockUs) const;
    double thetaAt(double tSec) const;  //!< radians, controller seconds

    int state() const { return state_; }
    int fault() const { return fault_; }
    int level() const { return level_; }
    int entryIndex() const { return entryIndex_; }
    int checksum() const { return loadedCrc_; }
    int initialLevel() const { return loadedInitial_; }
    uint64_t startUs() const { return startUs_; }
    //! Controller clock when entry 1 was switched (the loop's tick), 0 before.
    uint64_t firstSwitchUs() const { return firstSwitchUs_; }
    const std::vector<uint32_t>& offsetsUs() const { return offsets_; }
    const std::vector<int>& levels() const { return levels_; }
    //! Controller seconds of the run's last switch.
    double lastSwitch() const { return (startUs_ + (offsets_.empty() ? 0 : offsets_.back())) * 1e-6; }

private:
    void applyLevel(int newLevel, double tSec);
    void pruneHistory(double nowSec);

    cv::Ptr<cv::dynblur::Plant> plant_;
    double startLatency_ = 0;
    int state_ = 0, fault_ = 0, level_ = 0, entryIndex_ = -1;
    uint64_t startUs_ = 0, firstSwitchUs_ = 0;
    int loadedCrc_ = 0, loadedInitial_ = 0;
    std::vector<uint32_t> offsets_;  // loaded schedule, µs from start
    std::vector<int> levels_;
    cv::dynblur::SwitchSchedule history_;  // every level change, controller seconds
    double historyHorizon_ = -1;           // s after which a switch no longer moves θ; -1: keep all
};

}  // namespace dynblur_samples

#endif
