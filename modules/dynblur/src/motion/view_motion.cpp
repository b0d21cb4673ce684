// SPDX-License-Identifier: Apache-2.0
// The motion a frame's views follow: a plant's one-axis form, or any CameraMotion with its reference.
#include "precomp.hpp"

#include "motion/camera_motion.hpp"
#include "motion/view_motion.hpp"

namespace cv {
namespace dynblur {
namespace detail {

ViewMotion ViewMotion::ofPlant(const char* where, const Ptr<Plant>& plant, const SwitchSchedule& schedule,
                               const Vec3d& axis, double thetaRef)
{
    if (std::isinf(thetaRef))
        CV_Error_(Error::StsBadArg, ("%s: thetaRef must be finite (radians) or NaN (the schedule's final resting angle)",
                                     where));
    ViewMotion view;
    view.plant = plant;
    view.schedule = schedule;
    view.axis = axis;
    view.thetaRef = std::isnan(thetaRef) ? plant->restingAngle(schedule.finalLevel()) : thetaRef;
    double lowest = plant->restingAngle(schedule.initialLevel), highest = lowest;
    for (int level : schedule.levels)
    {
        lowest = std::min(lowest, plant->restingAngle(level));
        highest = std::max(highest, plant->restingAngle(level));
    }
    const double distance = std::max(lowest - view.thetaRef, view.thetaRef - highest);
    if (distance > CV_PI / 2)
        CV_Error_(Error::StsOutOfRange,
                  ("%s: thetaRef = %g rad (%.1f deg) lies %.3g rad beyond the angles the schedule reaches [%g, %g] rad, "
                   "more than a quarter turn: radians expected (10 deg is 0.1745)",
                   where, view.thetaRef, view.thetaRef * 180 / CV_PI, distance, lowest, highest));
    return view;
}

ViewMotion ViewMotion::of(const Ptr<CameraMotion>& motion, double tRef, const RollingShutter& shutter)
{
    ViewMotion view;
    if (const PlantMotion* plantMotion = asPlantMotion(*motion))
    {
        view.plant = plantMotion->plant();
        view.schedule = plantMotion->schedule();
        view.axis = plantMotion->axis();
        view.thetaRef = plantMotion->referenceAngle(tRef);
        return view;
    }
    view.motion = motion;
    view.reference = motion->referenceOrientation(tRef, shutter);
    return view;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
