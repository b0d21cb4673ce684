// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_RENDER_HPP
#define OPENCV_DYNBLUR_RENDER_HPP

#include <opencv2/dynblur/camera.hpp>
#include <opencv2/dynblur/camera_motion.hpp>
#include <opencv2/dynblur/plant.hpp>
#include <opencv2/dynblur/shutter.hpp>

#include <limits>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_imaging
//! @{

/** @brief The physical forward model (DESIGN §2): the frame a rolling-shutter sensor records
while the positioner follows a schedule.

The trajectory is sampled in time with a step small enough that the image moves less than
maxStepPx between samples; for each sample the sharp view is warped to the camera's angle and
added, with its dwell time as weight, to every row whose exposure interval covers it. Row r is
the time average over its own interval. Averaging happens in linear intensity: a CV_32F/CV_64F
input is taken as linear, an 8-bit input as sRGB (linearised, averaged, re-encoded).

This deliberately shares no code with PsfGenerator, so it can serve as ground truth for it.

@param sharp the motion-free view at θ_ref: the camera's image size, or larger by the same margin
       on each side (a wider view by the same camera, centred on the frame), 1–4 channels,
       CV_8U, CV_32F or CV_64F. Content a row sees beyond it is extended with borderMode.
@param plant the positioner.
@param schedule its command.
@param camera the camera (intrinsics, distortion, mount axis).
@param shutter frame timing; shutter.rows must equal the camera's image height.
@param blurred output, the camera's image size, same type as sharp.
@param thetaRef reference angle, radians; NaN: the schedule's final resting angle.
@param maxStepPx largest image motion between two time samples, pixels, in (0, 1].
@param borderMode cv::BorderTypes used beyond `sharp`.
*/
CV_EXPORTS_W void renderBlurred(InputArray sharp, const Ptr<Plant>& plant, const SwitchSchedule& schedule,
                                const Ptr<CameraModel>& camera, const RollingShutter& shutter,
                                OutputArray blurred, double thetaRef = std::numeric_limits<double>::quiet_NaN(),
                                double maxStepPx = 0.25, int borderMode = BORDER_REFLECT_101);

/** @brief The physical forward model for any camera motion (DESIGN §2, Rotation): each time
sample's view is the sharp view turned by R(t) = Q_refᵀ·Q(t), I_t(p) = I_ref(K·R(t)·K⁻¹·p), added to
the rows whose exposure covers it, as the plant overload does. A motion made by
CameraMotion::fromPlant renders the same frame, to the bit, as the plant overload with that plant
and the motion's axis as the camera's mount axis.
@param sharp the motion-free view at Q_ref (see the plant overload for sizes and types).
@param motion the camera's motion; its time span must cover the frame's readout.
@param camera the camera (intrinsics, distortion).
@param shutter frame timing (the motion's clock); shutter.rows must equal the camera's image height.
@param blurred output, the camera's image size, same type as sharp.
@param tRef reference time, seconds: `sharp` is the view at Q(tRef); NaN: the motion's default
       (CameraMotion::referenceOrientation: a plant's final rest, a sampled motion's mid-exposure).
@param maxStepPx largest image motion between two time samples, pixels, in (0, 1].
@param borderMode cv::BorderTypes used beyond `sharp`. */
CV_EXPORTS_W void renderBlurred(InputArray sharp, const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera,
                                const RollingShutter& shutter, OutputArray blurred,
                                double tRef = std::numeric_limits<double>::quiet_NaN(), double maxStepPx = 0.25,
                                int borderMode = BORDER_REFLECT_101);

/** @brief Adds webcam sensor noise to a linear-intensity image: Poisson shot noise (photons and
dark current) and Gaussian read noise, then clips to [0, 1].
@param linear input, CV_32F, values in [0, 1] (1 = full well).
@param noisy output, CV_32F.
@param fullWellElectrons electrons at intensity 1, > 0 (C270-like: 4000).
@param readNoiseElectrons read noise standard deviation, electrons, ≥ 0.
@param darkElectrons mean dark-current electrons per pixel over the exposure, ≥ 0.
@param seed random seed (the same seed gives the same noise). */
CV_EXPORTS_W void addSensorNoise(InputArray linear, OutputArray noisy, double fullWellElectrons = 4000.0,
                                 double readNoiseElectrons = 8.0, double darkElectrons = 5.0,
                                 uint64 seed = 0x5eed);

/** @brief sRGB (8-bit or [0,1] float) to linear intensity in [0, 1], CV_32F, same channels. */
CV_EXPORTS_W void srgbToLinear(InputArray srgb, OutputArray linear);
/** @brief Linear intensity (CV_32F) to sRGB of the requested depth (CV_8U or CV_32F). */
CV_EXPORTS_W void linearToSrgb(InputArray linear, OutputArray srgb, int depth = CV_8U);

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
