// SPDX-License-Identifier: Apache-2.0
// Private: the motion a frame's views follow relative to the reference view.
#ifndef OPENCV_DYNBLUR_MOTION_VIEW_MOTION_HPP
#define OPENCV_DYNBLUR_MOTION_VIEW_MOTION_HPP

#include "opencv2/dynblur/camera_motion.hpp"
#include "opencv2/dynblur/plant.hpp"

namespace cv {
namespace dynblur {
namespace detail {

/** The motion a frame's views follow, relative to the reference view, in one of two forms: a
one-axis plant (the form the one-axis API always used, kept so its results stay the same to the
bit), or any CameraMotion with its reference orientation. */
struct ViewMotion
{
    // One axis: θ(t) of `plant` under `schedule`, about the unit `axis`, relative to thetaRef (radians).
    Ptr<Plant> plant;
    SwitchSchedule schedule;
    Vec3d axis;
    double thetaRef = 0;
    // Any rotation: R(t) = referenceᵀ·Q(t) of `motion`.
    Ptr<CameraMotion> motion;
    Matx33d reference;

    bool oneAxis() const { return !plant.empty(); }

    /** The view motion of `motion` for a frame read by `shutter`, relative to its orientation at
        tRef (seconds; NaN: CameraMotion::referenceOrientation's default): the one-axis form for a
        plant's motion, the general one otherwise. */
    static ViewMotion of(const Ptr<CameraMotion>& motion, double tRef, const RollingShutter& shutter);

    /** The one-axis view motion of `plant` under `schedule` about `axis`, relative to thetaRef
        (radians; NaN: the schedule's final resting angle). Throws naming thetaRef, in the message of
        `where`, when it is infinite or more than a quarter turn from every angle the schedule holds
        (degrees given as radians: the view would turn behind the camera). */
    static ViewMotion ofPlant(const char* where, const Ptr<Plant>& plant, const SwitchSchedule& schedule,
                              const Vec3d& axis, double thetaRef);
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
