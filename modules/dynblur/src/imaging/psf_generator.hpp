// SPDX-License-Identifier: Apache-2.0
// Private: a PsfGenerator's bank for a view motion in either form (one axis or any rotation), for
// pipelines that resolve the motion and its reference themselves (DynamicDeblurrer).
#ifndef OPENCV_DYNBLUR_IMAGING_PSF_GENERATOR_HPP
#define OPENCV_DYNBLUR_IMAGING_PSF_GENERATOR_HPP

#include "opencv2/dynblur/psf.hpp"

#include "imaging/trajectory.hpp"

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The bank `generator` makes (its settings, its camera) of `model` for `motion` over the
frame read by `shutter`, whose rows must be the camera's height; a plant is not needed. With
PSF_AUTO, what was chosen goes to `plan` when given. */
PsfBank generatePsfBank(const PsfGenerator& generator, int model, const ViewMotion& motion,
                        const RollingShutter& shutter, PsfPlan* plan = nullptr);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
