// SPDX-License-Identifier: Apache-2.0
// Private: PSF_AUTO's choice of operator per frame and per band of rows (PsfPlan), from the motion.
#ifndef OPENCV_DYNBLUR_IMAGING_PSF_PLAN_HPP
#define OPENCV_DYNBLUR_IMAGING_PSF_PLAN_HPP

#include "opencv2/dynblur/psf.hpp"

#include "imaging/pinhole.hpp"
#include "imaging/trajectory.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The plan of a frame of `size` read by `shutter` whose views follow `tr` through `pinhole`:
its bands are the node rows `nodeRows` (PSF_TILES's), `tolerance` in pixels (PsfPlan's rule). */
PsfPlan planPsf(const Trajectory& tr, const Pinhole& pinhole, const RollingShutter& shutter, Size size,
                const std::vector<double>& nodeRows, double tolerance);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
