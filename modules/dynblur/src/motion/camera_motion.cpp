// SPDX-License-Identifier: Apache-2.0
// CameraMotion: the plant's motion about one axis (fromPlant), and the checks every motion shares.
#include "precomp.hpp"

#include "motion/axis_rotation.hpp"
#include "motion/camera_motion.hpp"

namespace cv {
namespace dynblur {
namespace detail {

Matx33d PlantMotion::orientation(double t) const
{
    return axisRotation(axis_, sampleAt(&Plant::response, *plant_, schedule_, t));
}

Vec3d PlantMotion::angularVelocity(double t) const
{
    return axis_ * sampleAt(&Plant::velocity, *plant_, schedule_, t);
}

Vec2d PlantMotion::getTimeSpan() const
{
    return Vec2d(-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
}

double PlantMotion::referenceAngle(double tRef) const
{
    return std::isnan(tRef) ? plant_->restingAngle(schedule_.finalLevel())
                            : sampleAt(&Plant::response, *plant_, schedule_, tRef);
}

Matx33d PlantMotion::referenceOrientation(double tRef, const RollingShutter&) const
{
    if (std::isinf(tRef))
        CV_Error(Error::StsBadArg, "CameraMotion::referenceOrientation: tRef must be finite (seconds) or NaN "
                                   "(the plant motion's final rest)");
    return axisRotation(axis_, referenceAngle(tRef));
}

void checkMotionCovers(const Ptr<CameraMotion>& motion, const Vec2d& span, const char* function, const char* name)
{
    if (motion.empty())
        CV_Error_(Error::StsNullPtr, ("%s: %s is empty", function, name));
    const Vec2d known = motion->getTimeSpan();
    if (!(span[0] >= known[0] && span[1] <= known[1]))
        CV_Error_(Error::StsOutOfRange,
                  ("%s: the frame's readout [%.6f, %.6f] s lies outside the time span of %s, [%.6f, %.6f] s: "
                   "the motion's samples must cover every row's exposure (same clock as the shutter's frameStart, "
                   "seconds)",
                   function, span[0], span[1], name, known[0], known[1]));
}

}  // namespace detail

int classifyExposure(const Ptr<CameraMotion>& motion, const RollingShutter& shutter, double angleTol,
                     double velocityTol)
{
    shutter.validate();
    const Vec2d readout = shutter.readoutInterval();
    detail::checkMotionCovers(motion, readout, "classifyExposure", "motion");
    if (const detail::PlantMotion* plantMotion = detail::asPlantMotion(*motion))
        return classifyExposure(plantMotion->plant(), plantMotion->schedule(), shutter, angleTol, velocityTol);
    if (!(velocityTol > 0 && std::isfinite(velocityTol)))
        CV_Error(Error::StsOutOfRange,
                 format("classifyExposure: velocityTol = %g must be finite and > 0 (rad/s)", velocityTol));
    // Rates sampled this often: a 20 Hz shake turns through a tenth of its period between samples.
    const double step = 2.5e-4;
    const int samples = std::max(2, int(std::ceil((readout[1] - readout[0]) / step)) + 1);
    std::vector<bool> moving(size_t(samples), false);
    bool movingAnywhere = false;
    for (int i = 0; i < samples; ++i)
    {
        const double t = readout[0] + (readout[1] - readout[0]) * i / (samples - 1);
        moving[size_t(i)] = cv::norm(motion->angularVelocity(t)) > velocityTol;
        movingAnywhere = movingAnywhere || moving[size_t(i)];
    }
    if (!movingAnywhere)
        return EXPOSURE_IV;
    if (moving.front())
        return moving.back() ? EXPOSURE_II : EXPOSURE_III;
    return EXPOSURE_I;
}

Ptr<CameraMotion> CameraMotion::fromPlant(const Ptr<Plant>& plant, const SwitchSchedule& schedule, const Vec3d& axis)
{
    if (plant.empty())
        CV_Error(Error::StsNullPtr, "CameraMotion::fromPlant: plant is empty");
    schedule.validate();
    const double norm = cv::norm(axis);
    if (!(norm > 1e-12) || !std::isfinite(norm))
        CV_Error_(Error::StsBadArg, ("CameraMotion::fromPlant: axis (%g, %g, %g) must be a finite non-zero vector "
                                     "(the rotation axis in the camera frame)",
                                     axis[0], axis[1], axis[2]));
    return makePtr<detail::PlantMotion>(plant, schedule, axis * (1.0 / norm));
}

}  // namespace dynblur
}  // namespace cv
