// SPDX-License-Identifier: Apache-2.0
// Private: the plant's CameraMotion (fromPlant), which pipelines recognise to take the one-axis path.
#ifndef OPENCV_DYNBLUR_MOTION_CAMERA_MOTION_HPP
#define OPENCV_DYNBLUR_MOTION_CAMERA_MOTION_HPP

#include "opencv2/dynblur/camera_motion.hpp"

namespace cv {
namespace dynblur {
namespace detail {

//! Q(t) = R_axis(θ(t)) for a plant's response θ to a schedule (CameraMotion::fromPlant).
class PlantMotion CV_FINAL : public CameraMotion
{
public:
    PlantMotion(const Ptr<Plant>& plant, const SwitchSchedule& schedule, const Vec3d& unitAxis)
        : plant_(plant), schedule_(schedule), axis_(unitAxis)
    {
    }
    Matx33d orientation(double t) const CV_OVERRIDE;
    Vec3d angularVelocity(double t) const CV_OVERRIDE;
    Vec2d getTimeSpan() const CV_OVERRIDE;
    Matx33d referenceOrientation(double tRef, const RollingShutter& shutter) const CV_OVERRIDE;
    bool isPlantMotion() const CV_OVERRIDE { return true; }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.CameraMotion.Plant"; }

    const Ptr<Plant>& plant() const { return plant_; }
    const SwitchSchedule& schedule() const { return schedule_; }
    const Vec3d& axis() const { return axis_; }  //!< unit
    /** The angle θ_ref whose view is the reference at `tRef` (seconds): the final resting angle for
        NaN, θ(tRef) otherwise. */
    double referenceAngle(double tRef) const;

private:
    Ptr<Plant> plant_;
    SwitchSchedule schedule_;
    Vec3d axis_;
};

//! `f` (Plant::response or Plant::velocity) of `plant` under `schedule` at one time `t`, seconds.
inline double sampleAt(void (Plant::*f)(const SwitchSchedule&, InputArray, OutputArray) const, const Plant& plant,
                       const SwitchSchedule& schedule, double t)
{
    Mat out;
    (plant.*f)(schedule, Mat(1, 1, CV_64F, &t), out);
    return out.at<double>(0);
}

//! The motion as a PlantMotion, or null when it is not one.
inline const PlantMotion* asPlantMotion(const CameraMotion& motion)
{
    return dynamic_cast<const PlantMotion*>(&motion);
}

/** @brief Throws cv::Exception naming `function` and `name` when `motion` is empty or does not
cover the time span [start, end] (seconds), with both spans in the message. */
void checkMotionCovers(const Ptr<CameraMotion>& motion, const Vec2d& span, const char* function, const char* name);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
