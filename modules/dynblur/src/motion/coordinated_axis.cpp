// SPDX-License-Identifier: Apache-2.0
// followLeader: an axis's vibration-free schedule nearest the leading axis's motion scaled to its
// move. The candidates are SwitchPlanner's (integer levels, instants solved so that the phasors
// close), their levels drawn near the leader's levels scaled to this move and their Newton solves
// started from the leader's instants, so that the nearest root is the proportional one.
#include "precomp.hpp"

#include "motion/coordinated_axis.hpp"
#include "motion/switch_phasors.hpp"

namespace cv {
namespace dynblur {

using namespace phasors;

namespace {

//! Samples of the leader's motion over the move and the follower's wanted angle at each, in levels.
struct ScaledLeader
{
    std::vector<double> tau;     //!< sample instants in the follower's normalised time (0 at the first switch)
    std::vector<double> wanted;  //!< the follower's wanted angle there, levels
};

ScaledLeader scaleLeader(const SwitchSchedule& leader, const Plant& leaderPlant, int startLevel, int targetLevel,
                         double omegaN)
{
    const int samples = 400;
    const double start = leader.times.front();
    const double period = 1 / leaderPlant.getNaturalFreqHz();
    const double end = std::max(leader.times.back() - start, leader.settleTime) + period;
    std::vector<double> t(samples);
    for (int k = 0; k < samples; k++)
        t[size_t(k)] = start + end * k / (samples - 1);
    std::vector<double> theta;
    leaderPlant.response(leader, t, theta);
    const double from = leaderPlant.restingAngle(leader.initialLevel);
    const double move = leaderPlant.restingAngle(leader.finalLevel()) - from;
    ScaledLeader scaled;
    for (int k = 0; k < samples; k++)
    {
        scaled.tau.push_back(omegaN * (t[size_t(k)] - start));
        scaled.wanted.push_back(startLevel + (theta[size_t(k)] - from) / move * (targetLevel - startLevel));
    }
    return scaled;
}

//! Largest distance, levels, between the candidate's angle and the wanted one.
double distanceTo(const ScaledLeader& scaled, const NormalisedPole& pole, int startLevel, const Candidate& c)
{
    double worst = 0;
    for (size_t k = 0; k < scaled.tau.size(); k++)
        worst = std::max(worst,
                         std::abs(angleInLevels(pole, startLevel, c.levels, c.tau, scaled.tau[k]) - scaled.wanted[k]));
    return worst;
}

//! `c` with every instant (and its settle time) later by `delay`, normalised time.
Candidate delayed(Candidate c, double delay)
{
    for (double& tau : c.tau)
        tau += delay;
    c.settle += delay;
    return c;
}

//! For each intermediate switch, the levels to try: the leader's level scaled to this move ± spread.
std::vector<std::vector<int>> levelChoices(const SwitchSchedule& leader, int startLevel, int targetLevel,
                                           int maxLevel, int spread)
{
    const double ratio = double(targetLevel - startLevel) / (leader.finalLevel() - leader.initialLevel);
    std::vector<std::vector<int>> choices;
    for (size_t j = 0; j + 1 < leader.levels.size(); j++)
    {
        const int centre = cvRound(startLevel + ratio * (leader.levels[j] - leader.initialLevel));
        std::vector<int> levels;
        for (int level = std::max(-maxLevel, centre - spread); level <= std::min(maxLevel, centre + spread); level++)
            levels.push_back(level);
        choices.push_back(levels);
    }
    return choices;
}

//! Every level sequence start → one choice per intermediate switch → target whose steps all move.
std::vector<std::vector<int>> levelSequences(const std::vector<std::vector<int>>& choices, int startLevel,
                                             int targetLevel)
{
    std::vector<std::vector<int>> sequences(1);
    for (const std::vector<int>& options : choices)
    {
        std::vector<std::vector<int>> longer;
        for (const std::vector<int>& s : sequences)
            for (int level : options)
                if (level != (s.empty() ? startLevel : s.back()))
                {
                    longer.push_back(s);
                    longer.back().push_back(level);
                }
        sequences.swap(longer);
    }
    std::vector<std::vector<int>> complete;
    for (std::vector<int>& s : sequences)
        if ((s.empty() ? startLevel : s.back()) != targetLevel)
        {
            s.push_back(targetLevel);
            complete.push_back(s);
        }
    return complete;
}


//! The follower's problem: its plant and planner settings, its move, the leader's motion scaled to it.
struct Follower
{
    const SwitchPlanner& planner;
    NormalisedPole pole;
    double omegaN;
    int startLevel, targetLevel;
    ScaledLeader scaled;
    double latestSettle;  //!< the leader's settle time, normalised to the follower's ωn

    double move() const { return std::abs(targetLevel - startLevel); }
    bool robust() const { return planner.getMode() == PLAN_ROBUST; }
};

//! The vibration-free (robust in robust mode) schedules of `sequence` whose instants Newton finds from `starts`.
std::vector<Candidate> solvedCandidates(const Follower& f, const std::vector<int>& sequence,
                                        const std::vector<std::vector<double>>& starts)
{
    const int freeInstants = int(sequence.size()) - 1;
    const double maxTau = 2 * 2 * CV_PI / f.pole.dampedFactor;  // two damped periods, as SwitchPlanner
    const double minDwellTau = f.planner.getMinDwell() * f.omegaN;
    int steps[5];
    for (int i = 0; i <= freeInstants; i++)
        steps[i] = sequence[size_t(i)] - (i == 0 ? f.startLevel : sequence[size_t(i) - 1]);
    std::vector<Candidate> found;
    for (const std::vector<double>& from : starts)
    {
        double tau[5] = {0};
        std::copy(from.begin(), from.end(), tau + 1);
        const bool solved = freeInstants == 4 ? solveInstants<4>(f.pole, steps, tau, minDwellTau, maxTau)
                                              : solveInstants<2>(f.pole, steps, tau, minDwellTau, maxTau);
        if (!solved)
            continue;
        Candidate c;
        c.levels = sequence;
        c.tau.assign(tau, tau + freeInstants + 1);
        if (f.robust() && worstVibration(f.pole, f.startLevel, c, f.move(), f.planner.getRobustRange(),
                                         f.planner.getRobustTolerance()) > f.planner.getRobustTolerance())
            continue;
        c.settle = settleTime(f.pole, f.startLevel, c, f.planner.getSettleBand() * f.move());
        if (c.settle <= f.latestSettle)
            found.push_back(c);
    }
    return found;
}

/** Replaces `best` by `c`, started at once or later, if one of them is nearer the scaled leader. A
faster plant's schedule started later ends with the leader and tracks its motion better. */
void keepNearest(const Follower& f, const Candidate& c, Candidate& best, double& bestDistance)
{
    const int delays = 12;
    const double latestDelay = f.latestSettle - c.settle;
    for (int k = 0; k <= delays; k++)
    {
        const Candidate shifted = delayed(c, latestDelay * k / delays);
        const double distance = distanceTo(f.scaled, f.pole, f.startLevel, shifted);
        if (distance < bestDistance)
            best = shifted, bestDistance = distance;
    }
}

SwitchSchedule toSchedule(const Follower& f, const Candidate& best, double start)
{
    SwitchSchedule schedule;
    schedule.initialLevel = f.startLevel;
    schedule.levels = best.levels;
    for (double tau : best.tau)
        schedule.times.push_back(start + tau / f.omegaN);
    schedule.settleTime = best.settle / f.omegaN;
    const double period = 2 * CV_PI / f.pole.dampedFactor;
    double peak = 0;
    for (double tau = 0; tau <= best.tau.back() + period; tau += period / 1000)
        peak = std::max(peak, std::abs(rateInLevels(f.pole, f.startLevel, best.levels, best.tau, tau)));
    const Plant& plant = *f.planner.getPlant();
    schedule.peakVelocity = peak * f.omegaN * std::abs(plant.getGain());
    schedule.residualVibration = residualVibration(schedule, plant.getNaturalFreqHz(), plant.getDampingRatio());
    return schedule;
}

}  // namespace

SwitchSchedule followLeader(const SwitchPlanner& planner, const SwitchSchedule& own, const SwitchSchedule& leader,
                            const Plant& leaderPlant)
{
    const int freeInstants = int(leader.levels.size()) - 1;
    if (freeInstants != 2 && freeInstants != 4)
        return own;  // the leader's plan is not a planner's three- or five-switch move
    const Plant& plant = *planner.getPlant();
    const double omegaN = 2 * CV_PI * plant.getNaturalFreqHz();
    const double start = leader.times.front();
    const int startLevel = own.initialLevel, targetLevel = own.finalLevel();
    const Follower f{planner, NormalisedPole(plant.getDampingRatio()), omegaN, startLevel, targetLevel,
                     scaleLeader(leader, leaderPlant, startLevel, targetLevel, omegaN),
                     leader.settleTime * omegaN};

    // The axis's own plan first: coordination never takes a schedule farther from the leader's path.
    Candidate ownCandidate;
    ownCandidate.levels = own.levels;
    for (double t : own.times)
        ownCandidate.tau.push_back(omegaN * (t - start));
    ownCandidate.settle = own.settleTime * omegaN;
    Candidate best = ownCandidate;
    double bestDistance = distanceTo(f.scaled, f.pole, startLevel, best);
    keepNearest(f, ownCandidate, best, bestDistance);

    // Newton from the leader's instants first: the root nearest them is the proportional one.
    std::vector<std::vector<double>> starts = startingPoints(freeInstants, 2 * CV_PI / f.pole.dampedFactor);
    std::vector<double> leaderStart;
    for (int j = 1; j <= freeInstants; j++)
        leaderStart.push_back(omegaN * (leader.times[size_t(j)] - start));
    starts.insert(starts.begin(), leaderStart);
    const int spread = 2;
    for (const std::vector<int>& sequence : levelSequences(
             levelChoices(leader, startLevel, targetLevel, planner.getMaxLevel(), spread), startLevel, targetLevel))
        for (const Candidate& c : solvedCandidates(f, sequence, starts))
            keepNearest(f, c, best, bestDistance);
    return best.levels == own.levels && best.tau == ownCandidate.tau ? own : toSchedule(f, best, start);
}

}  // namespace dynblur
}  // namespace cv
