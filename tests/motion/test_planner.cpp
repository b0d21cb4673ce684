// SPDX-License-Identifier: Apache-2.0
// SwitchPlanner: integer-level schedules with free switching instants (DESIGN §2, planner.hpp).
// Every figure the issue requires is computed here, never copied from a run.
#include "test_common.hpp"

#include <opencv2/dynblur.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace cv;
using namespace cv::dynblur;

const double kSeedHz = 14.4;
const double kSeedZeta = 0.12;
const double kDegree = CV_PI / 180.0;
const int kMaxLevel = 16;

Ptr<Plant> seedPlant() { return Plant::create(kSeedHz, kSeedZeta, kDegree); }

//! Worst |θ − target| / |move| sampled every 0.1 ms over [from, to] on `plant`.
double worstDeviation(const Ptr<Plant>& plant, const SwitchSchedule& schedule, double from, double to)
{
    std::vector<double> t;
    for (double x = from; x <= to; x += 1e-4)
        t.push_back(x);
    Mat theta;
    plant->response(schedule, t, theta);
    const double target = plant->restingAngle(schedule.finalLevel());
    const double move = std::abs(plant->restingAngle(schedule.finalLevel() - schedule.initialLevel));
    double worst = 0;
    for (int i = 0; i < theta.rows * theta.cols; ++i)
        worst = std::max(worst, std::abs(theta.at<double>(i) - target));
    return worst / move;
}

//! Residual vibration by simulation: over one undamped period and a half after the last switch.
double simulatedResidual(const Ptr<Plant>& plant, const SwitchSchedule& schedule)
{
    const double period = 1.0 / plant->getNaturalFreqHz();
    const double last = schedule.times.back();
    return worstDeviation(plant, schedule, last + 1e-5, last + 1.5 * period);
}

//! Settle time into ±band·move measured by simulation (0.02 ms samples), from times[0].
double simulatedSettleTime(const Ptr<Plant>& plant, const SwitchSchedule& schedule, double band)
{
    const double start = schedule.times.front();
    const double end = schedule.times.back() + 2.0 / plant->getNaturalFreqHz();
    std::vector<double> t;
    for (double x = start; x <= end; x += 2e-5)
        t.push_back(x);
    Mat theta;
    plant->response(schedule, t, theta);
    const double target = plant->restingAngle(schedule.finalLevel());
    const double tolerance = band * std::abs(plant->restingAngle(schedule.finalLevel() - schedule.initialLevel));
    double settle = 0;
    for (size_t i = 0; i < t.size(); ++i)
        if (std::abs(theta.at<double>(static_cast<int>(i)) - target) > tolerance)
            settle = t[i] + 2e-5 - start;
    return settle;
}

double simulatedPeakVelocity(const Ptr<Plant>& plant, const SwitchSchedule& schedule)
{
    std::vector<double> t;
    for (double x = schedule.times.front(); x <= schedule.times.back() + 0.1; x += 2e-5)
        t.push_back(x);
    Mat omega;
    plant->velocity(schedule, t, omega);
    double minValue, maxValue;
    minMaxLoc(omega, &minValue, &maxValue);
    return std::max(std::abs(minValue), std::abs(maxValue));
}

//! The hard constraints: integer levels in range, increasing instants, dwell ≥ minDwell.
void expectFeasible(const SwitchSchedule& schedule, int maxLevel, double minDwell, double startTime)
{
    ASSERT_FALSE(schedule.times.empty());
    ASSERT_EQ(schedule.times.size(), schedule.levels.size());
    EXPECT_NEAR(schedule.times.front(), startTime, 1e-12);
    for (size_t i = 0; i < schedule.levels.size(); ++i)
    {
        EXPECT_LE(std::abs(schedule.levels[i]), maxLevel);
        if (i > 0)
        {
            EXPECT_GE(schedule.times[i] - schedule.times[i - 1], minDwell * (1 - 1e-9)) << "switch " << i;
        }
    }
    EXPECT_NO_THROW(schedule.validate(maxLevel));
}

struct Move
{
    int from, to;
};

//! Every move of 1..16 levels: 0→k, k→0, −k→0, 0→−k, plus wide moves through zero.
std::vector<Move> requiredMoves()
{
    std::vector<Move> moves;
    for (int k = 1; k <= kMaxLevel; ++k)
    {
        moves.push_back({0, k});
        moves.push_back({k, 0});
        moves.push_back({0, -k});
        moves.push_back({-k, 0});
    }
    moves.push_back({-8, 8});
    moves.push_back({8, -8});
    moves.push_back({-3, 7});
    moves.push_back({16, 6});
    moves.push_back({-16, -15});
    return moves;
}

// ---------------------------------------------------------------------------------------------

TEST(PlannerFast, CancelsVibrationForEveryMoveSize)
{
    const Ptr<Plant> plant = seedPlant();
    const Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant, kMaxLevel, PLAN_FAST, 0.002);
    for (const Move& move : requiredMoves())
    {
        SCOPED_TRACE(format("move %d -> %d", move.from, move.to));
        const SwitchSchedule schedule = planner->plan(move.from * kDegree, move.to * kDegree, 0.25);
        expectFeasible(schedule, kMaxLevel, 0.002, 0.25);
        EXPECT_EQ(schedule.initialLevel, move.from);
        EXPECT_EQ(schedule.finalLevel(), move.to);
        const double formula = residualVibration(schedule, kSeedHz, kSeedZeta);
        const double simulated = simulatedResidual(plant, schedule);
        EXPECT_LE(formula, 0.005);
        EXPECT_LE(simulated, 0.005);
        EXPECT_NEAR(schedule.residualVibration, formula, 1e-12);
        EXPECT_NEAR(schedule.settleTime, simulatedSettleTime(plant, schedule, 0.02), 1e-4);
    }
}

TEST(PlannerFast, TenDegreeMoveIsQuick)
{
    const Ptr<Plant> plant = seedPlant();
    const Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant);  // defaults: 16 cells, fast, 2 ms
    const SwitchSchedule schedule = planner->plan(0, 10 * kDegree);
    const double settle = simulatedSettleTime(plant, schedule, 0.02);
    const double peak = simulatedPeakVelocity(plant, schedule);
    EXPECT_LE(settle, 0.060);
    EXPECT_GE(peak / kDegree, 250.0);
    EXPECT_NEAR(schedule.settleTime, settle, 1e-4);
    EXPECT_NEAR(schedule.peakVelocity, peak, 0.01 * peak);
    std::printf("[ PLANNER  ] fast 10 deg: settle %.2f ms, peak %.0f deg/s, V %.2e, %zu switches\n",
                settle * 1e3, peak / kDegree, schedule.residualVibration, schedule.times.size());
}

TEST(PlannerRobust, ToleratesTenPercentFrequencyError)
{
    const Ptr<Plant> nominal = seedPlant();
    const Ptr<SwitchPlanner> planner = SwitchPlanner::create(nominal, kMaxLevel, PLAN_ROBUST, 0.002);
    for (const Move& move : requiredMoves())
    {
        SCOPED_TRACE(format("move %d -> %d", move.from, move.to));
        const SwitchSchedule schedule = planner->plan(move.from * kDegree, move.to * kDegree);
        expectFeasible(schedule, kMaxLevel, 0.002, 0.0);
        EXPECT_EQ(schedule.finalLevel(), move.to);
        EXPECT_LE(simulatedResidual(nominal, schedule), 0.005);
        double worstFormula = 0, worstSimulated = 0;
        for (int k = -20; k <= 20; ++k)
        {
            const double hz = kSeedHz * (1 + 0.005 * k);
            worstFormula = std::max(worstFormula, residualVibration(schedule, hz, kSeedZeta));
            worstSimulated = std::max(worstSimulated, simulatedResidual(Plant::create(hz, kSeedZeta, kDegree), schedule));
        }
        EXPECT_LE(worstFormula, 0.03);
        EXPECT_LE(worstSimulated, 0.03);
    }
}

TEST(PlannerRobust, TenDegreeMoveSettlesWithin50ms)
{
    const Ptr<Plant> plant = seedPlant();
    const Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant, kMaxLevel, PLAN_ROBUST);
    const SwitchSchedule schedule = planner->plan(0, 10 * kDegree);
    const double settle = simulatedSettleTime(plant, schedule, 0.02);
    EXPECT_LE(settle, 0.050);
    EXPECT_NEAR(schedule.settleTime, settle, 1e-4);
    std::printf("[ PLANNER  ] robust 10 deg: settle %.2f ms, peak %.0f deg/s, %zu switches\n", settle * 1e3,
                schedule.peakVelocity / kDegree, schedule.times.size());
}

TEST(PlannerFast, BeatsRoundedZeroVibrationShaper)
{
    // DESIGN §2: a ZV shaper's amplitudes rounded to integers (4 levels → 2 + 2 half a damped
    // period apart) leave ≈16% vibration; the planner's integer schedule closes the polygon.
    const double omegaN = 2 * CV_PI * kSeedHz;
    const double dampedPeriod = 2 * CV_PI / (omegaN * std::sqrt(1 - kSeedZeta * kSeedZeta));
    const SwitchSchedule rounded({0.0, dampedPeriod / 2}, {2, 4});
    const double roundedVibration = residualVibration(rounded, kSeedHz, kSeedZeta);
    const double k = std::exp(-kSeedZeta * CV_PI / std::sqrt(1 - kSeedZeta * kSeedZeta));
    EXPECT_NEAR(roundedVibration, (1 - k) / 2, 1e-9);
    EXPECT_GT(roundedVibration, 0.15);
    const SwitchSchedule planned = SwitchPlanner::create(seedPlant())->plan(0, 4 * kDegree);
    EXPECT_LT(residualVibration(planned, kSeedHz, kSeedZeta), 1e-6);
}

TEST(PlannerFast, RoundsAnglesAndHonoursStartTimeAndLimits)
{
    const Ptr<Plant> plant = seedPlant();
    const Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant, 6, PLAN_FAST, 0.004);
    // 1.4° rounds to level 1, 4.6° to level 5; the start time only shifts the schedule.
    const SwitchSchedule early = planner->plan(1.4 * kDegree, 4.6 * kDegree, 0.0);
    const SwitchSchedule late = planner->plan(1.4 * kDegree, 4.6 * kDegree, 12.5);
    EXPECT_EQ(early.initialLevel, 1);
    EXPECT_EQ(early.finalLevel(), 5);
    ASSERT_EQ(early.times.size(), late.times.size());
    for (size_t i = 0; i < early.times.size(); ++i)
    {
        EXPECT_NEAR(late.times[i] - early.times[i], 12.5, 1e-9);
        EXPECT_EQ(late.levels[i], early.levels[i]);
    }
    expectFeasible(early, 6, 0.004, 0.0);
    EXPECT_LE(simulatedResidual(plant, late), 0.005);
    EXPECT_NEAR(late.settleTime, early.settleTime, 1e-12);

    // A zero move is an empty schedule resting at the start level.
    const SwitchSchedule still = planner->plan(3 * kDegree, 3.2 * kDegree);
    EXPECT_TRUE(still.times.empty());
    EXPECT_EQ(still.initialLevel, 3);
    EXPECT_EQ(still.settleTime, 0.0);
}

TEST(PlannerFast, LongerDwellIsRespected)
{
    const Ptr<Plant> plant = seedPlant();
    for (double dwell : {0.0, 0.005, 0.010})
    {
        SCOPED_TRACE(format("minDwell %g", dwell));
        const Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant, kMaxLevel, PLAN_FAST, dwell);
        const SwitchSchedule schedule = planner->plan(-2 * kDegree, 9 * kDegree);
        expectFeasible(schedule, kMaxLevel, dwell, 0.0);
        EXPECT_LE(simulatedResidual(plant, schedule), 0.005);
    }
}

TEST(PlannerRobust, FastScheduleIsNotRobustButRobustOneIs)
{
    // The robust mode earns its extra switches: at ωn −10% the fast schedule vibrates far more.
    const Ptr<Plant> plant = seedPlant();
    const SwitchSchedule fast = SwitchPlanner::create(plant, kMaxLevel, PLAN_FAST)->plan(0, 10 * kDegree);
    const SwitchSchedule robust = SwitchPlanner::create(plant, kMaxLevel, PLAN_ROBUST)->plan(0, 10 * kDegree);
    const double fastOff = residualVibration(fast, 0.9 * kSeedHz, kSeedZeta);
    const double robustOff = residualVibration(robust, 0.9 * kSeedHz, kSeedZeta);
    EXPECT_GT(fastOff, 0.05);
    EXPECT_LE(robustOff, 0.03);
    std::printf("[ PLANNER  ] V at wn-10%%: fast %.1f%%, robust %.2f%%\n", fastOff * 100, robustOff * 100);
}

TEST(PlannerApi, RejectsBadArguments)
{
    const Ptr<Plant> plant = seedPlant();
    EXPECT_THROW(SwitchPlanner::create(Ptr<Plant>(), 16), cv::Exception);
    EXPECT_THROW(SwitchPlanner::create(plant, 0), cv::Exception);
    EXPECT_THROW(SwitchPlanner::create(plant, 16, 2), cv::Exception);
    EXPECT_THROW(SwitchPlanner::create(plant, 16, -1), cv::Exception);
    EXPECT_THROW(SwitchPlanner::create(plant, 16, PLAN_FAST, -0.001), cv::Exception);
    EXPECT_THROW(SwitchPlanner::create(plant, 16, PLAN_FAST, std::nan("")), cv::Exception);
    EXPECT_THROW(SwitchPlanner::create(plant, 16, PLAN_FAST, HUGE_VAL), cv::Exception);

    const Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant, 16);
    EXPECT_THROW(planner->plan(std::nan(""), 0.1), cv::Exception);
    EXPECT_THROW(planner->plan(0, HUGE_VAL), cv::Exception);
    EXPECT_THROW(planner->plan(0, 0.1, std::nan("")), cv::Exception);
    EXPECT_THROW(planner->plan(0, 16.5 * kDegree), cv::Exception);
    EXPECT_THROW(planner->plan(-16.6 * kDegree, 0), cv::Exception);
    EXPECT_NO_THROW(planner->plan(-16.4 * kDegree, 16.4 * kDegree));
    EXPECT_THROW(planner->setMaxLevel(0), cv::Exception);
    EXPECT_THROW(planner->setMode(7), cv::Exception);
    EXPECT_THROW(planner->setMinDwell(-1), cv::Exception);
    EXPECT_THROW(planner->setSettleBand(0), cv::Exception);
    EXPECT_THROW(planner->setRobustRange(-0.1), cv::Exception);

    // The message names the argument and the allowed range.
    try
    {
        planner->plan(0, 20 * kDegree);
        ADD_FAILURE() << "no exception";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(e.err.find("toAngle"), std::string::npos) << e.err;
        EXPECT_NE(e.err.find("[-16, 16]"), std::string::npos) << e.err;
    }
    try
    {
        SwitchPlanner::create(plant, 16, PLAN_FAST, -0.5);
        ADD_FAILURE() << "no exception";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(e.err.find("minDwell"), std::string::npos) << e.err;
        EXPECT_NE(e.err.find(">= 0"), std::string::npos) << e.err;
    }
}

TEST(PlannerApi, SettersTakeEffect)
{
    const Ptr<Plant> plant = seedPlant();
    const Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant, 16, PLAN_FAST);
    EXPECT_EQ(planner->getPlant(), plant);
    EXPECT_EQ(planner->getMaxLevel(), 16);
    EXPECT_DOUBLE_EQ(planner->getSettleBand(), 0.02);
    EXPECT_DOUBLE_EQ(planner->getRobustRange(), 0.10);
    const SwitchSchedule wide = planner->plan(0, 5 * kDegree);
    planner->setMaxLevel(6);  // clears the cache: the new plan must respect the new limit
    const SwitchSchedule narrow = planner->plan(0, 5 * kDegree);
    expectFeasible(narrow, 6, planner->getMinDwell(), 0.0);
    EXPECT_GE(narrow.settleTime, wide.settleTime);
    planner->setMode(PLAN_ROBUST);
    EXPECT_EQ(planner->getMode(), PLAN_ROBUST);
    EXPECT_EQ(planner->plan(0, 5 * kDegree).times.size(), 5u);
}

}  // namespace
