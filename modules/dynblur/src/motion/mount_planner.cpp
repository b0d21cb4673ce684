// SPDX-License-Identifier: Apache-2.0
// MountPlanner: one SwitchPlanner per axis, the axes coordinated behind the slowest (followLeader),
// and the move's report from the mount's chain.
#include "precomp.hpp"

#include "motion/coordinated_axis.hpp"

#include "opencv2/dynblur/mount_planner.hpp"

namespace cv {
namespace dynblur {

MountMove::MountMove()
    : settleTime(std::numeric_limits<double>::quiet_NaN()), peakRate(std::numeric_limits<double>::quiet_NaN()),
      pathDeviation(std::numeric_limits<double>::quiet_NaN())
{
}

namespace {

//! An axis that does not move: one switch to the level it holds (a valid schedule, no motion).
SwitchSchedule holding(int level, double startTime)
{
    SwitchSchedule schedule({startTime}, {level}, level);
    schedule.settleTime = schedule.peakVelocity = schedule.residualVibration = 0;
    return schedule;
}

//! Peak |ω| (rad/s) and the largest angle between the optical axis and the great circle through its
//! end directions (rad), sampled over the move.
void chainFigures(const Mount& mount, MountMove& move, double startTime)
{
    const Ptr<CameraMotion> motion = mount.motion(move.schedules);
    double end = 0, shortestPeriod = std::numeric_limits<double>::infinity(), longestPeriod = 0;
    for (size_t i = 0; i < move.schedules.size(); i++)
    {
        end = std::max(end, std::max(move.schedules[i].times.back() - startTime, move.axisSettleTimes[i]));
        const double period = 1 / mount.getPlant(int(i))->getNaturalFreqHz();
        shortestPeriod = std::min(shortestPeriod, period);
        longestPeriod = std::max(longestPeriod, period);
    }
    end += longestPeriod;
    const Vec3d p0 = mount.pointing(move.fromAngles), p1 = mount.pointing(move.toAngles);
    const Vec3d normal = p0.cross(p1);
    const bool circle = norm(normal) > 1e-12;
    move.peakRate = move.pathDeviation = 0;
    const double step = shortestPeriod / 400;
    for (double t = startTime; t <= startTime + end; t += step)
    {
        move.peakRate = std::max(move.peakRate, norm(motion->angularVelocity(t)));
        const Vec3d p = motion->orientation(t) * Vec3d(0, 0, 1);
        const double off = circle ? std::asin(std::min(1.0, std::abs(p.dot(normal) / norm(normal))))
                                  : std::acos(std::min(1.0, p.dot(p0)));
        move.pathDeviation = std::max(move.pathDeviation, off);
    }
}

class MountPlannerImpl CV_FINAL : public MountPlanner
{
public:
    MountPlannerImpl(const Ptr<Mount>& mount, int mode, double minDwell, int coordination)
        : mount_(mount), mode_(mode), minDwell_(minDwell), coordination_(coordination)
    {
        for (int i = 0; i < mount->getAxisCount(); i++)
        {
            const Vec2i range = mount->getLevelRange(i);
            const int cap = std::min(-range[0], range[1]);
            if (cap < 1)
                CV_Error_(Error::StsOutOfRange,
                          ("MountPlanner::create: axis %d's level range [%d, %d] must hold [-1, 1] (the planner's "
                           "levels are symmetric: ±min(-minLevel, maxLevel))",
                           i, range[0], range[1]));
            planners_.push_back(SwitchPlanner::create(mount->getPlant(i), cap, mode, minDwell));
        }
    }

    MountMove plan(const std::vector<double>& fromAngles, const std::vector<double>& toAngles,
                   double startTime) const CV_OVERRIDE
    {
        checkAngles(fromAngles, "fromAngles");
        checkAngles(toAngles, "toAngles");
        if (!std::isfinite(startTime))
            CV_Error_(Error::StsBadArg, ("MountPlanner::plan: startTime = %g must be finite (seconds)", startTime));
        std::vector<SwitchSchedule> own;
        size_t leader = 0;
        for (size_t i = 0; i < planners_.size(); i++)
        {
            own.push_back(planners_[i]->plan(fromAngles[i], toAngles[i], startTime));
            if (!own[i].levels.empty() && !(own[i].settleTime <= own[leader].settleTime))
                leader = i;
        }
        MountMove move;
        for (size_t i = 0; i < planners_.size(); i++)
        {
            const Plant& plant = *planners_[i]->getPlant();
            SwitchSchedule schedule = own[i];
            if (schedule.levels.empty())
                schedule = holding(schedule.initialLevel, startTime);
            else if (coordination_ == MOUNT_COORDINATED && i != leader)
                schedule = followLeader(*planners_[i], own[i], own[leader], *planners_[leader]->getPlant());
            move.schedules.push_back(schedule);
            move.fromAngles.push_back(plant.restingAngle(schedule.initialLevel));
            move.toAngles.push_back(plant.restingAngle(schedule.finalLevel()));
            move.axisSettleTimes.push_back(schedule.settleTime);
            move.residualVibration.push_back(schedule.residualVibration);
        }
        move.settleTime = *std::max_element(move.axisSettleTimes.begin(), move.axisSettleTimes.end());
        chainFigures(*mount_, move, startTime);
        return move;
    }

    MountMove planToDirection(const Vec3d& direction, const std::vector<double>& fromAngles,
                              double startTime) const CV_OVERRIDE
    {
        checkAngles(fromAngles, "fromAngles");
        return plan(fromAngles, mount_->anglesFor(direction, fromAngles), startTime);
    }

    MountMove planToPixel(const Ptr<CameraModel>& camera, const Point2d& pixel,
                          const std::vector<double>& fromAngles, double startTime) const CV_OVERRIDE
    {
        if (camera.empty())
            CV_Error(Error::StsNullPtr, "MountPlanner::planToPixel: camera is empty");
        if (!std::isfinite(pixel.x) || !std::isfinite(pixel.y))
            CV_Error_(Error::StsBadArg,
                      ("MountPlanner::planToPixel: pixel (%g, %g) must be finite (pixels)", pixel.x, pixel.y));
        checkAngles(fromAngles, "fromAngles");
        const Point2d ray = camera->pixelToNormalized(pixel);
        return planToDirection(mount_->orientation(fromAngles) * Vec3d(ray.x, ray.y, 1), fromAngles, startTime);
    }

    Ptr<Mount> getMount() const CV_OVERRIDE { return mount_; }
    int getMode() const CV_OVERRIDE { return mode_; }
    double getMinDwell() const CV_OVERRIDE { return minDwell_; }
    int getCoordination() const CV_OVERRIDE { return coordination_; }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.MountPlanner"; }

private:
    //! One finite angle per axis, within the levels its planner uses.
    void checkAngles(const std::vector<double>& angles, const char* name) const
    {
        if (angles.size() != planners_.size())
            CV_Error_(Error::StsBadSize, ("MountPlanner: %s has %zu values for %zu axes (one joint angle per axis, "
                                          "radians, base first)",
                                          name, angles.size(), planners_.size()));
        for (size_t i = 0; i < angles.size(); i++)
        {
            const double reach = planners_[i]->getMaxLevel() * std::abs(planners_[i]->getPlant()->getGain());
            if (!std::isfinite(angles[i]))
                CV_Error_(Error::StsBadArg,
                          ("MountPlanner: %s[%zu] = %g must be finite (radians)", name, i, angles[i]));
            if (std::abs(angles[i]) > reach * (1 + 1e-12))
                CV_Error_(Error::StsOutOfRange,
                          ("MountPlanner: %s[%zu] = %.6g rad (%.4g deg) is outside axis %zu's range [%.6g, %.6g] rad "
                           "(levels -%d to %d)",
                           name, i, angles[i], angles[i] * 180 / CV_PI, i, -reach, reach,
                           planners_[i]->getMaxLevel(), planners_[i]->getMaxLevel()));
        }
    }

    Ptr<Mount> mount_;
    int mode_;
    double minDwell_;
    int coordination_;
    std::vector<Ptr<SwitchPlanner>> planners_;
};

}  // namespace

Ptr<MountPlanner> MountPlanner::create(const Ptr<Mount>& mount, int mode, double minDwell, int coordination)
{
    if (mount.empty())
        CV_Error(Error::StsNullPtr, "MountPlanner::create: mount is empty");
    if (mount->getAxisCount() == 0)
        CV_Error(Error::StsBadArg, "MountPlanner::create: the mount has no axis (add them with Mount::addAxis)");
    if (mode != PLAN_FAST && mode != PLAN_ROBUST)
        CV_Error_(Error::StsOutOfRange,
                  ("MountPlanner::create: mode = %d must be PLAN_FAST (0) or PLAN_ROBUST (1)", mode));
    if (!(std::isfinite(minDwell) && minDwell >= 0))
        CV_Error_(Error::StsOutOfRange,
                  ("MountPlanner::create: minDwell = %g must be finite and >= 0 (seconds)", minDwell));
    if (coordination != MOUNT_COORDINATED && coordination != MOUNT_INDEPENDENT)
        CV_Error_(Error::StsOutOfRange, ("MountPlanner::create: coordination = %d must be MOUNT_COORDINATED (0) or "
                                         "MOUNT_INDEPENDENT (1)",
                                         coordination));
    return makePtr<MountPlannerImpl>(mount, mode, minDwell, coordination);
}

}  // namespace dynblur
}  // namespace cv
