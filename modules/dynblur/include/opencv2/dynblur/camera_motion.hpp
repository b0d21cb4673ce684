// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_CAMERA_MOTION_HPP
#define OPENCV_DYNBLUR_CAMERA_MOTION_HPP

#include <opencv2/core.hpp>
#include <opencv2/dynblur/plant.hpp>
#include <opencv2/dynblur/schedule.hpp>
#include <opencv2/dynblur/shutter.hpp>

#include <limits>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

/** @brief How the camera turns over time: any rotation, from a plant's response to its schedule or
from measurements (a gyroscope, encoders, motion capture).

The orientation Q(t) ∈ SO(3) is the camera frame (x right, y down, z forward) expressed in the
mount's base frame, the identity at rest unless the source says otherwise; it evolves with the body
rates ω(t) (rad/s, camera frame, as a gyroscope rigidly fixed to the camera measures them):
\f[\dot Q = Q\,[\omega]_\times.\f]
The view at time t relative to a reference orientation Q_ref is
\f[R(t) = Q_{ref}^\top Q(t), \qquad I_t(p) = I_{ref}(K\,R(t)\,K^{-1} p)\f]
(DESIGN §2, Rotation). The one-axis plant of Plant is the special case Q(t) = R_axis(θ(t)),
ω = θ'·axis, and fromPlant() keeps every one-axis result unchanged.

Everything that takes a (plant, schedule) pair also takes a CameraMotion: classifyExposure,
renderBlurred, PsfGenerator and DynamicDeblurrer.
*/
class CV_EXPORTS_W CameraMotion : public Algorithm
{
public:
    /** @brief The orientation Q(t), a 3×3 rotation (camera frame in the base frame).
    @param t time, seconds, within getTimeSpan(). */
    CV_WRAP virtual Matx33d orientation(double t) const = 0;

    /** @brief The body rates ω(t), rad/s, in the camera frame.
    @param t time, seconds, within getTimeSpan(). */
    CV_WRAP virtual Vec3d angularVelocity(double t) const = 0;

    /** @brief The time span over which the motion is known, seconds (start, end): the samples'
    first and last time for a sampled motion, (−∞, +∞) for a plant's. */
    CV_WRAP virtual Vec2d getTimeSpan() const = 0;

    /** @brief The reference orientation Q_ref of a frame: the view a restoration returns.
    @param tRef reference time, seconds; NaN chooses the default: a plant motion's final rest (the
           schedule's last level held), a sampled motion's orientation at the middle of the frame's
           exposure (the middle row's mid-exposure instant of `shutter`).
    @param shutter the frame's timing (read only for a NaN tRef of a sampled motion). */
    CV_WRAP virtual Matx33d referenceOrientation(double tRef, const RollingShutter& shutter) const = 0;

    /** @brief True for a motion made by fromPlant (one axis, a plant and a schedule). */
    CV_WRAP virtual bool isPlantMotion() const = 0;

    /** @brief The rotation of the view at time t relative to `reference`: R(t) = referenceᵀ·Q(t).
    @param t time, seconds, within getTimeSpan().
    @param reference the reference orientation Q_ref (referenceOrientation()). */
    CV_WRAP Matx33d relativeRotation(double t, const Matx33d& reference) const
    {
        return reference.t() * orientation(t);
    }

    /** @brief The motion of a one-axis positioner: Q(t) = R_axis(θ(t)) with θ the plant's response
    to the schedule, ω = θ'(t)·axis. Pipelines given this motion take the one-axis path they take
    for (plant, schedule) and return the same results.
    @param plant the positioner.
    @param schedule its command (times on the camera's clock, as for the one-axis API).
    @param axis the rotation axis in the camera frame, non-zero (normalised); default +x, tilt. It
           replaces the camera's mount axis (CameraModel::getMountAxis) wherever the motion is used. */
    CV_WRAP static Ptr<CameraMotion> fromPlant(const Ptr<Plant>& plant, const SwitchSchedule& schedule,
                                               const Vec3d& axis = Vec3d(1, 0, 0));

    /** @brief A motion measured by a gyroscope: body rates integrated on SO(3) from
    `initialOrientation` at the first sample.

    Between two samples the rate is the C¹ cubic Hermite curve through them, its slopes the
    three-point derivative of the samples (exact for a rate quadratic in time; linear rates would
    err by O(h²) on a smooth motion, cubic ones by O(h⁴)), and angularVelocity(t) returns it. The
    orientation is advanced by the fourth-order Magnus step (two Gauss points, one exponential map
    per step) @cite Iserles2000Lie, exact for a rotation about a fixed axis whose rate is at most
    cubic between samples; orientation(t) between samples takes the same step over the partial
    interval, so it is continuous and its derivative is the interpolated rate. A step that turns
    by π or more (undersampled, or rates in deg/s) is refused.
    @param times sample times, seconds, strictly increasing, ≥ 2 samples, no gap longer than three
           times the median sample interval (N×1 or 1×N, CV_64F or CV_32F).
    @param rates body rates ω, rad/s, in camera axes (x right, y down, z forward), finite: N×3
           1-channel or N×1 3-channel, CV_64F or CV_32F. Map a gyroscope's own axes to these first
           (readGyroLog does).
    @param initialOrientation Q at the first sample, a rotation (det = +1). */
    CV_WRAP static Ptr<CameraMotion> fromAngularVelocity(InputArray times, InputArray rates,
                                                         const Matx33d& initialOrientation = Matx33d::eye());

    /** @brief A motion measured as orientations (encoders, motion capture, a visual-inertial pose
    stream), interpolated between samples by a C¹ cubic on SO(3): on [t_k, t_{k+1}],
    Q(t) = Q_k·exp([v(t)]×) with v a cubic Hermite curve in the tangent space at Q_k from 0 to
    log(Q_kᵀQ_{k+1}) (consecutive orientations are joined by the shorter rotation, so they must be
    sampled less than half a turn apart) whose end slopes make the body rate equal the sample rates
    there @cite Kim1995General. The sample rates are the three-point (second-order) derivative of the
    neighbouring orientations; angularVelocity(t) is the interpolant's own derivative, in the body
    frame.
    @param times sample times, seconds, strictly increasing, ≥ 2 samples, no gap longer than three
           times the median sample interval.
    @param rotations one orientation Q per sample (camera frame in the base frame): N×3 rotation
           vectors (radians, cv::Rodrigues' convention), N×4 unit quaternions (w, x, y, z, cv::Quat's
           order; norm within 1e-3 of 1, renormalised), or N×9 row-major rotation matrices
           (det within 1e-3 of +1); 1-channel CV_64F or CV_32F. */
    CV_WRAP static Ptr<CameraMotion> fromOrientations(InputArray times, InputArray rotations);
};

/** @brief Which exposure window (ExposureWindow) a frame falls in for any camera motion.

A plant's motion (CameraMotion::fromPlant) is classified exactly as
classifyExposure(plant, schedule, shutter, angleTol, velocityTol). Any other motion has no rest
angle to settle to: it is "moving" at t when its rate |ω(t)| exceeds `velocityTol`, sampled every
0.25 ms over the readout (a hand-held camera is usually in window II).
@param motion the camera's motion; its time span must cover the frame's readout.
@param shutter the frame's timing (the motion's clock).
@param angleTol angle tolerance for a plant's motion, radians, > 0 (see the plant overload).
@param velocityTol rate tolerance, rad/s, > 0 (default 0.02 rad/s ≈ 0.2 px over 8 ms at f = 1230 px). */
CV_EXPORTS_W int classifyExposure(const Ptr<CameraMotion>& motion, const RollingShutter& shutter,
                                  double angleTol = 2e-4, double velocityTol = 0.02);

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
