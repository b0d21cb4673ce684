// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_HPP
#define OPENCV_DYNBLUR_HPP

/** @defgroup dynblur Dynamics-based motion deblurring for a robotic camera

Removes the motion blur that a fast camera-positioning mechanism puts into its own frames. The
blur is not estimated from the image: it is predicted from the mechanism's known dynamics and the
commands it was sent @cite DynblurSeed, per sensor row for rolling-shutter cameras, and
undone with Richardson–Lucy deconvolution.

Follow one frame: DynamicDeblurrer::deblur → trajectory from Plant → per-row intervals from
RollingShutter → kernels from PsfGenerator → richardsonLucyVariant → restored frame.

@{
    @defgroup dynblur_motion Plant, switching planner and exposure windows
    @defgroup dynblur_imaging Camera, forward model and PSFs
    @defgroup dynblur_restoration Deconvolution and the deblurring pipeline
@}
*/

#include "opencv2/dynblur/parameter_file.hpp"
#include "opencv2/dynblur/schedule.hpp"
#include "opencv2/dynblur/plant.hpp"
#include "opencv2/dynblur/camera_motion.hpp"
#include "opencv2/dynblur/mount.hpp"
#include "opencv2/dynblur/gyro_log.hpp"
#include "opencv2/dynblur/planner.hpp"
#include "opencv2/dynblur/shutter.hpp"
#include "opencv2/dynblur/camera.hpp"
#include "opencv2/dynblur/mount_planner.hpp"
#include "opencv2/dynblur/calibration.hpp"
#include "opencv2/dynblur/render.hpp"
#include "opencv2/dynblur/psf.hpp"
#include "opencv2/dynblur/deconv.hpp"
#include "opencv2/dynblur/refinement.hpp"
#include "opencv2/dynblur/clip_timing.hpp"
#include "opencv2/dynblur/deblurrer.hpp"
#include "opencv2/dynblur/bus.hpp"

#endif
