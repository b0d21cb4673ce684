// SPDX-License-Identifier: Apache-2.0
// Private: a measured motion as a MotionCorrection corrects it (clock offset, gyro bias), seen from a
// reference time: what refinement fits and what DynamicDeblurrer restores with.
#ifndef OPENCV_DYNBLUR_MOTION_CORRECTED_MOTION_HPP
#define OPENCV_DYNBLUR_MOTION_CORRECTED_MOTION_HPP

#include "opencv2/dynblur/camera_motion.hpp"
#include "opencv2/dynblur/refinement.hpp"

#include "motion/view_motion.hpp"

namespace cv {
namespace dynblur {
namespace detail {

//! The middle row's mid-exposure instant of `shutter`, seconds: a sampled motion's default reference time.
inline double midExposure(const RollingShutter& shutter)
{
    return shutter.frameStart + 0.5 * (shutter.rows - 1) * shutter.lineDelay + 0.5 * shutter.exposure;
}

/** @brief `motion` with a constant gyro bias b (rad/s, camera axes) removed from its rates, to first
order in b: Q_b(t) = Q(t)·exp(−[b·(t − t0)]×), whose body rate is exp([b·(t − t0)]×)·ω(t) − b exactly.
It equals re-integrating ω − b from t0 up to the bias's turn carried through the camera's own turn
between t0 and t (|b|·|t − t0| times that angle: 0.5 °/s over 0.1 s and 1° of shake, 1.5e-5 rad). The
time span is `motion`'s. With `rateScale` s ≠ 1 its turn from t0 is scaled by s as well (rates s·(ω − b)
for a turn about a fixed axis): the image motion a camera's translation adds to its rotation, seen as
longer turns. An empty `motion`, or b = 0 and s = 1, returns `motion` itself. */
Ptr<CameraMotion> withCorrectedRates(const Ptr<CameraMotion>& motion, const Vec3d& bias, double rateScale, double t0);

/** @brief The view motion of a measured `motion` for a frame read by `corrected` (the shutter
`correction` has corrected: its clock offset and line delay applied), relative to the orientation at
`tRef` (a camera time, seconds, which the correction's clock offset moves onto the motion's clock as
it moves the frame; NaN: the corrected shutter's mid-exposure), with `correction.gyroBias` removed
and its rates scaled by `correction.rateScale` about that instant. */
ViewMotion correctedView(const Ptr<CameraMotion>& motion, const MotionCorrection& correction, double tRef,
                         const RollingShutter& corrected);

/** @brief Throws cv::Exception naming `function` and `name` unless `motion` covers the readout of
`shutter` widened by `margin` seconds on both sides and by a line delay 15 % longer at its end:
every clock offset and line delay a refinement within `margin` may try. */
void checkMotionCoversSearch(const Ptr<CameraMotion>& motion, const RollingShutter& shutter, double margin,
                             const char* function, const String& name);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
