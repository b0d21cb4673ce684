// SPDX-License-Identifier: Apache-2.0
// SwitchPlanner: integer-level switching schedules with free switching instants that cancel the
// residual vibration of the lightly damped plant (DESIGN §2, "Residual vibration of a schedule").
//
// How it works. Time is measured in units of 1/ωn (τ = ωn t), so the plant's pole is
// s = ζ + j√(1−ζ²) and a schedule with level steps aᵢ at τᵢ leaves no vibration when the phasors
// close into a polygon:
//     F = Σ aᵢ e^{s τᵢ} = 0                                  (2 real equations)
// and is insensitive to an error in ωn when, in addition, the ωn-derivative vanishes. With
// τᵢ = ωn tᵢ, ∂/∂ωn e^{(ζωn + jωn√(1−ζ²)) tᵢ} = (s tᵢ) e^{s τᵢ}, so the condition is
//     G = Σ aᵢ τᵢ e^{s τᵢ} = 0                               (2 more real equations).
// The steps are integers, so the unknowns are the instants: with the first switch at τ₀ = 0, a
// FAST schedule has 3 switches (2 free instants, 2 equations) and a ROBUST one 5 switches
// (4 free instants, 4 equations). For each candidate sequence of intermediate levels the instants
// are solved by damped Newton from a few fixed starting points; feasible solutions (instants
// increasing, every dwell ≥ minDwell) are scored by their settle time into the band (closed-form
// response), and robust candidates must also keep the vibration under the tolerance for every ωn
// error within the robust range (a zero derivative alone does not bound the curvature).

#include "precomp.hpp"

#include "motion/switch_phasors.hpp"

#include <map>
#include <mutex>
#include <utility>

namespace cv {
namespace dynblur {

using namespace phasors;

class SwitchPlannerImpl CV_FINAL : public SwitchPlanner
{
public:
    SwitchPlannerImpl(const Ptr<Plant>& plant, int maxLevel, int mode, double minDwell)
        : plant_(plant), maxLevel_(maxLevel), mode_(mode), minDwell_(minDwell)
    {
    }

    SwitchSchedule plan(double fromAngle, double toAngle, double startTime) const CV_OVERRIDE
    {
        if (!std::isfinite(startTime))
            CV_Error(Error::StsBadArg, format("startTime = %g must be finite (seconds)", startTime));
        const int startLevel = angleToLevel(fromAngle, "fromAngle");
        const int targetLevel = angleToLevel(toAngle, "toAngle");

        SwitchSchedule schedule;
        schedule.initialLevel = startLevel;
        if (startLevel == targetLevel)
        {
            // Nothing to do: the plant already rests at the target.
            schedule.settleTime = 0;
            schedule.peakVelocity = 0;
            schedule.residualVibration = 0;
            return schedule;
        }

        const Candidate best = bestCandidate(startLevel, targetLevel);
        const double omegaN = 2 * CV_PI * plant_->getNaturalFreqHz();
        for (size_t i = 0; i < best.levels.size(); ++i)
        {
            schedule.times.push_back(startTime + best.tau[i] / omegaN);
            schedule.levels.push_back(best.levels[i]);
        }
        schedule.settleTime = best.settle / omegaN;
        schedule.peakVelocity = peakRateInLevels(startLevel, best) * omegaN * std::abs(plant_->getGain());
        schedule.residualVibration =
            residualVibration(schedule, plant_->getNaturalFreqHz(), plant_->getDampingRatio());
        return schedule;
    }

    int getMaxLevel() const CV_OVERRIDE { return maxLevel_; }
    void setMaxLevel(int maxLevel) CV_OVERRIDE
    {
        checkMaxLevel(maxLevel);
        maxLevel_ = maxLevel;
        clearCache();
    }
    int getMode() const CV_OVERRIDE { return mode_; }
    void setMode(int mode) CV_OVERRIDE
    {
        checkMode(mode);
        mode_ = mode;
        clearCache();
    }
    double getMinDwell() const CV_OVERRIDE { return minDwell_; }
    void setMinDwell(double minDwell) CV_OVERRIDE
    {
        checkMinDwell(minDwell);
        minDwell_ = minDwell;
        clearCache();
    }
    double getSettleBand() const CV_OVERRIDE { return settleBand_; }
    void setSettleBand(double band) CV_OVERRIDE
    {
        if (!(std::isfinite(band) && band > 0 && band < 1))
            CV_Error(Error::StsOutOfRange, format("band = %g must lie in (0, 1) (fraction of the move)", band));
        settleBand_ = band;
        clearCache();
    }
    double getRobustRange() const CV_OVERRIDE { return robustRange_; }
    void setRobustRange(double range) CV_OVERRIDE
    {
        if (!(std::isfinite(range) && range >= 0 && range < 0.5))
            CV_Error(Error::StsOutOfRange, format("range = %g must lie in [0, 0.5) (relative ωn error)", range));
        robustRange_ = range;
        clearCache();
    }
    double getRobustTolerance() const CV_OVERRIDE { return robustTolerance_; }
    void setRobustTolerance(double tolerance) CV_OVERRIDE
    {
        if (!(std::isfinite(tolerance) && tolerance > 0 && tolerance < 1))
            CV_Error(Error::StsOutOfRange,
                     format("tolerance = %g must lie in (0, 1) (fraction of the move)", tolerance));
        robustTolerance_ = tolerance;
        clearCache();
    }
    Ptr<Plant> getPlant() const CV_OVERRIDE { return plant_; }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.SwitchPlanner"; }

    static void checkMaxLevel(int maxLevel)
    {
        if (maxLevel < 1)
            CV_Error(Error::StsOutOfRange, format("maxLevel = %d must be >= 1 (cells)", maxLevel));
    }
    static void checkMode(int mode)
    {
        if (mode != PLAN_FAST && mode != PLAN_ROBUST)
            CV_Error(Error::StsOutOfRange,
                     format("mode = %d must be PLAN_FAST (0) or PLAN_ROBUST (1)", mode));
    }
    static void checkMinDwell(double minDwell)
    {
        if (!(std::isfinite(minDwell) && minDwell >= 0))
            CV_Error(Error::StsOutOfRange, format("minDwell = %g must be finite and >= 0 (seconds)", minDwell));
    }

private:
    int angleToLevel(double angle, const char* argName) const
    {
        const double gain = plant_->getGain();
        const double limit = (maxLevel_ + 0.5) * std::abs(gain);
        if (!(std::isfinite(angle) && std::abs(angle) < limit))
            CV_Error(Error::StsOutOfRange,
                     format("%s = %g rad is outside the reachable range (-%g, %g) rad "
                            "(levels [-%d, %d] of %g rad each; radians expected: 10 deg is 0.1745)",
                            argName, angle, limit, limit, maxLevel_, maxLevel_, std::abs(gain)));
        const int level = cvRound(angle / gain);
        return std::max(-maxLevel_, std::min(maxLevel_, level));
    }

    void clearCache()
    {
        std::lock_guard<std::mutex> lock(cacheMutex_);
        cache_.clear();
    }

    //! The best move between two levels, from the cache or searched now.
    Candidate bestCandidate(int startLevel, int targetLevel) const
    {
        const std::pair<int, int> key(startLevel, targetLevel);
        {
            std::lock_guard<std::mutex> lock(cacheMutex_);
            const auto found = cache_.find(key);
            if (found != cache_.end())
                return found->second;
        }
        const Candidate best = search(startLevel, targetLevel);
        std::lock_guard<std::mutex> lock(cacheMutex_);
        cache_[key] = best;
        return best;
    }

    //! Intermediate levels worth trying: every level (fast), or a coarse set (robust, 4 free levels).
    std::vector<int> intermediateLevels(int startLevel, int targetLevel) const
    {
        std::vector<int> levels;
        if (mode_ == PLAN_FAST)
        {
            for (int level = -maxLevel_; level <= maxLevel_; ++level)
                levels.push_back(level);
            return levels;
        }
        // Fastest robust moves drive the actuator to its limits (bang-bang like); the half levels,
        // zero and the end levels cover the small moves where a full swing would break the dwell.
        const int half = maxLevel_ / 2;
        levels = {-maxLevel_, -half, 0, half, maxLevel_, startLevel, targetLevel};
        std::sort(levels.begin(), levels.end());
        levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
        return levels;
    }

    Candidate search(int startLevel, int targetLevel) const
    {
        const NormalisedPole pole(plant_->getDampingRatio());
        const double omegaN = 2 * CV_PI * plant_->getNaturalFreqHz();
        const double minDwellTau = minDwell_ * omegaN;
        const double dampedPeriodTau = 2 * CV_PI / pole.dampedFactor;
        // Moves longer than two damped periods are never competitive; it also bounds Newton.
        const double maxTau = 2 * dampedPeriodTau;
        const bool robust = mode_ == PLAN_ROBUST;
        const int freeInstants = robust ? 4 : 2;
        const std::vector<std::vector<double>> starts = startingPoints(freeInstants, dampedPeriodTau);
        const std::vector<int> choices = intermediateLevels(startLevel, targetLevel);
        const double move = std::abs(targetLevel - startLevel);

        Candidate best, leastVibrating;
        best.settle = std::numeric_limits<double>::infinity();
        leastVibrating.worstVibration = std::numeric_limits<double>::infinity();
        double bestPeakRate = std::numeric_limits<double>::infinity();

        std::vector<int> sequence(freeInstants + 2);  // start, intermediate levels, target
        sequence.front() = startLevel;
        sequence.back() = targetLevel;
        std::vector<size_t> odometer(freeInstants, 0);
        int steps[5];
        double tau[5];
        for (;;)
        {
            for (int k = 0; k < freeInstants; ++k)
                sequence[k + 1] = choices[odometer[k]];
            bool everyStepMoves = true;
            for (int i = 0; i <= freeInstants; ++i)
            {
                steps[i] = sequence[i + 1] - sequence[i];
                everyStepMoves = everyStepMoves && steps[i] != 0;
            }
            if (everyStepMoves)
            {
                std::vector<std::vector<double>> roots;
                for (const std::vector<double>& start : starts)
                {
                    tau[0] = 0;
                    std::copy(start.begin(), start.end(), tau + 1);
                    const bool solved = robust ? solveInstants<4>(pole, steps, tau, minDwellTau, maxTau)
                                               : solveInstants<2>(pole, steps, tau, minDwellTau, maxTau);
                    if (!solved)
                        continue;
                    // Several starts converge to the same root: evaluate it once.
                    bool seen = false;
                    for (const std::vector<double>& root : roots)
                        seen = seen || std::abs(root.back() - tau[freeInstants]) < 1e-7;
                    if (seen)
                        continue;
                    roots.emplace_back(tau, tau + freeInstants + 1);

                    Candidate candidate;
                    candidate.levels.assign(sequence.begin() + 1, sequence.end());
                    candidate.tau = roots.back();
                    candidate.worstVibration =
                        robust ? worstVibration(pole, startLevel, candidate, move, robustRange_, robustTolerance_) : 0;
                    if (candidate.worstVibration > robustTolerance_)
                    {
                        if (candidate.worstVibration < leastVibrating.worstVibration)
                        {
                            candidate.settle = settleTime(pole, startLevel, candidate, settleBand_ * move);
                            leastVibrating = candidate;
                        }
                        continue;
                    }
                    // Settle time is at most the last instant; candidates that end later than the
                    // best settle time plus its tie margin can still win only if they settle early.
                    candidate.settle = settleTime(pole, startLevel, candidate, settleBand_ * move);
                    const double tieMargin = 1e-3 * dampedPeriodTau;
                    if (candidate.settle < best.settle - tieMargin)
                    {
                        best = candidate;
                        bestPeakRate = peakRateInLevels(startLevel, best);
                    }
                    else if (candidate.settle <= best.settle + tieMargin)
                    {
                        // Equal settle times: the gentler move (lower peak velocity) blurs less.
                        const double peakRate = peakRateInLevels(startLevel, candidate);
                        if (peakRate < bestPeakRate)
                        {
                            best = candidate;
                            bestPeakRate = peakRate;
                        }
                    }
                }
            }
            // Next sequence of intermediate levels.
            int digit = 0;
            while (digit < freeInstants && ++odometer[digit] == choices.size())
                odometer[digit++] = 0;
            if (digit == freeInstants)
                break;
        }

        if (std::isfinite(best.settle))
            return best;
        if (robust && std::isfinite(leastVibrating.worstVibration))
            return leastVibrating;  // nothing meets the tolerance: the most robust move found
        CV_Error(Error::StsNoConv,
                 format("no feasible switching schedule from level %d to level %d with maxLevel = %d and "
                        "minDwell = %g s; reduce minDwell",
                        startLevel, targetLevel, maxLevel_, minDwell_));
    }

    //! Peak |dθ/dτ| in levels per normalised time unit, up to the last switch plus one period.
    double peakRateInLevels(int startLevel, const Candidate& candidate) const
    {
        const NormalisedPole pole(plant_->getDampingRatio());
        const double period = 2 * CV_PI / pole.dampedFactor;
        const double step = period / 1000;
        const double end = candidate.tau.back() + period;
        double peak = 0;
        for (double t = 0; t <= end; t += step)
            peak = std::max(peak, std::abs(rateInLevels(pole, startLevel, candidate.levels, candidate.tau, t)));
        return peak;
    }

    Ptr<Plant> plant_;
    int maxLevel_;
    int mode_;
    double minDwell_;
    double settleBand_ = 0.02;
    double robustRange_ = 0.10;
    double robustTolerance_ = 0.025;

    mutable std::mutex cacheMutex_;
    mutable std::map<std::pair<int, int>, Candidate> cache_;
};

Ptr<SwitchPlanner> SwitchPlanner::create(const Ptr<Plant>& plant, int maxLevel, int mode, double minDwell)
{
    if (plant.empty())
        CV_Error(Error::StsNullPtr, "plant must not be empty");
    SwitchPlannerImpl::checkMaxLevel(maxLevel);
    SwitchPlannerImpl::checkMode(mode);
    SwitchPlannerImpl::checkMinDwell(minDwell);
    return makePtr<SwitchPlannerImpl>(plant, maxLevel, mode, minDwell);
}

}  // namespace dynblur
}  // namespace cv
