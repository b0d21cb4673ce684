// SPDX-License-Identifier: Apache-2.0
#include "actuator_axis.hpp"

#include <cmath>
#include <cstdlib>

namespace dynblur_samples {

using namespace cv::dynblur;
using namespace cv::dynblur::busmap;

namespace {

int16_t asInt16(uint16_t w) { return static_cast<int16_t>(w); }

void setU64(uint16_t* regs, uint64_t v)
{
    for (int i = 3; i >= 0; --i)
    {
        regs[i] = static_cast<uint16_t>(v & 0xFFFF);
        v >>= 16;
    }
}

}  // namespace

SimAxis::SimAxis(const cv::Ptr<Plant>& plant, double startLatency) : plant_(plant), startLatency_(startLatency)
{
    const double sigma = 2 * CV_PI * plant_->getNaturalFreqHz() * plant_->getDampingRatio();
    if (sigma > 0 && std::isfinite(sigma))
        historyHorizon_ = 28.0 / sigma;  // e^-28 < 1e-12
}

void SimAxis::applyLevel(int newLevel, double tSec)
{
    if (newLevel == level_)
        return;
    if (!history_.times.empty() && tSec <= history_.times.back())
        tSec = history_.times.back() + 1e-6;
    history_.times.push_back(tSec);
    history_.levels.push_back(newLevel);
    level_ = newLevel;
    pruneHistory(tSec);
}

// θ is only evaluated from now on, where a switch older than the horizon contributes less than
// e^-28 of its step: fold such switches into the initial level so that the history (and the
// cost of thetaAt) stays bounded however long the simulator runs.
void SimAxis::pruneHistory(double nowSec)
{
    if (historyHorizon_ <= 0 || history_.times.size() < 64)
        return;
    size_t k = 0;  // entries [0, k) are older than the horizon
    while (k + 1 < history_.times.size() && history_.times[k] < nowSec - historyHorizon_)
        ++k;
    if (k < 32)
        return;
    history_.initialLevel = history_.levels[k - 1];
    history_.times.erase(history_.times.begin(), history_.times.begin() + k);
    history_.levels.erase(history_.levels.begin(), history_.levels.begin() + k);
}

double SimAxis::thetaAt(double tSec) const
{
    if (history_.times.empty())
        return plant_->restingAngle(history_.initialLevel);
    cv::Mat out;
    plant_->response(history_, cv::Mat(1, 1, CV_64F, cv::Scalar(tSec - startLatency_)), out);
    return out.at<double>(0);
}

void SimAxis::enterFault(int code, int safeLevel, uint64_t nowUs)
{
    state_ = ACTUATOR_FAULT;
    fault_ = code;
    entryIndex_ = -1;
    applyLevel(safeLevel, nowUs * 1e-6);
}

void SimAxis::load(const uint16_t* hr, const SimAxisLimits& limits, uint64_t nowUs)
{
    if (state_ == ACTUATOR_RUNNING)
        return;  // ignored while running
    const int safeLevel = asInt16(hr[HR_SAFE_LEVEL - HR_COMMAND]);
    const int n = hr[HR_LENGTH - HR_COMMAND];
    if (n < 1 || n > limits.capacity)
        return enterFault(FAULT_BAD_LENGTH, safeLevel, nowUs);
    const uint16_t* entries = hr + HR_ENTRIES - HR_COMMAND;
    std::vector<int> regs = {n, hr[HR_INITIAL_LEVEL - HR_COMMAND]};
    for (int i = 0; i < n * ENTRY_WORDS; ++i)
        regs.push_back(entries[i]);
    const int crc = busChecksum(regs);
    if (crc != hr[HR_CHECKSUM - HR_COMMAND])
        return enterFault(FAULT_BAD_CHECKSUM, safeLevel, nowUs);
    offsets_.assign(n, 0);
    levels_.assign(n, 0);
    loadedInitial_ = asInt16(hr[HR_INITIAL_LEVEL - HR_COMMAND]);
    if (std::abs(loadedInitial_) > limits.maxLevel)
        return enterFault(FAULT_LEVEL_RANGE, safeLevel, nowUs);
    for (int i = 0; i < n; ++i)
    {
        const uint16_t* e = entries + ENTRY_WORDS * i;
        offsets_[i] = (static_cast<uint32_t>(e[0]) << 16) | e[1];
        levels_[i] = asInt16(e[2]);
        if (std::abs(levels_[i]) > limits.maxLevel)
            return enterFault(FAULT_LEVEL_RANGE, safeLevel, nowUs);
        if ((i == 0 && offsets_[0] != 0) ||
            (i > 0 && (offsets_[i] <= offsets_[i - 1] || offsets_[i] - offsets_[i - 1] < (uint32_t)limits.minDwellUs)))
            return enterFault(FAULT_DWELL, safeLevel, nowUs);
    }
    state_ = ACTUATOR_LOADED;
    fault_ = FAULT_NONE;
    loadedCrc_ = crc;
}

void SimAxis::start(uint64_t nowUs)
{
    startUs_ = nowUs;
    firstSwitchUs_ = 0;
    state_ = offsets_.size() == 1 ? ACTUATOR_DONE : ACTUATOR_RUNNING;
    entryIndex_ = 0;
    applyLevel(levels_[0], nowUs * 1e-6);
}

void SimAxis::tick(uint64_t nowUs)
{
    if (state_ != ACTUATOR_RUNNING)
        return;
    while (entryIndex_ + 1 < (int)offsets_.size() && startUs_ + offsets_[entryIndex_ + 1] <= nowUs)
    {
        ++entryIndex_;
        if (entryIndex_ == 1)
            firstSwitchUs_ = nowUs;
        applyLevel(levels_[entryIndex_], (startUs_ + offsets_[entryIndex_]) * 1e-6);
    }
    if (entryIndex_ + 1 == (int)offsets_.size())
        state_ = ACTUATOR_DONE;
}

void SimAxis::stop(int safeLevel, uint64_t nowUs)
{
    applyLevel(safeLevel, nowUs * 1e-6);
    if (state_ != ACTUATOR_FAULT)
        state_ = ACTUATOR_IDLE;
    entryIndex_ = -1;
}

void SimAxis::clearFault()
{
    if (state_ == ACTUATOR_FAULT)
    {
        state_ = ACTUATOR_IDLE;
        fault_ = FAULT_NONE;
    }
}

void SimAxis::unload()
{
    if (state_ == ACTUATOR_LOADED)
        state_ = ACTUATOR_IDLE;
}

void SimAxis::fillInputs(uint16_t* ir, uint64_t clockUs) const
{
    ir[IR_STATUS - IR_STATUS] = static_cast<uint16_t>(state_);
    ir[IR_FAULT - IR_STATUS] = static_cast<uint16_t>(fault_);
    ir[IR_CURRENT_LEVEL - IR_STATUS] = static_cast<uint16_t>(level_ & 0xFFFF);
    setU64(ir + IR_START_TIME_US - IR_STATUS, startUs_);
    setU64(ir + IR_CLOCK_US - IR_STATUS, clockUs);
    ir[IR_LOADED_CHECKSUM - IR_STATUS] = static_cast<uint16_t>(state_ == ACTUATOR_LOADED ? loadedCrc_ : 0);
    ir[IR_ENTRY_INDEX - IR_STATUS] = static_cast<uint16_t>(entryIndex_ < 0 ? 0xFFFF : entryIndex_);
}

}  // namespace dynblur_samples
