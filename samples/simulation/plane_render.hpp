// SPDX-License-Identifier: Apache-2.0
// A reference renderer of its own for a camera that turns and moves in front of a plane: the
// hand-held clip simulator's frames with translation, where cv::dynblur::renderBlurred (rotation only)
// does not apply.
#ifndef DYNBLUR_SAMPLES_PLANE_RENDER_HPP
#define DYNBLUR_SAMPLES_PLANE_RENDER_HPP

#include "hand_motion.hpp"

#include <opencv2/dynblur.hpp>

namespace dynblur_samples {

/** @brief The frame a rolling-shutter sensor records while the camera follows `path` in front of a
plane (DESIGN §2's shutter model, with the plane homography in place of the rotation's).

The readout is cut into time cells over which every border pixel moves by at most `maxStepPx`
(equal steps of the path's length, measured on a fine grid); each cell's view, the home view warped
by homeFromView at the cell's midpoint (cv::warpPerspective, bilinear), is added to every row with
the overlap of the cell and the row's exposure as weight; each row is then divided by its exposure.
A zero exposure gives each row the view at its start. Shares no code with renderBlurred, so the two
check each other where the translation is zero.
@param sceneLinear the home view, linear intensity CV_32F (1–4 channels): `size` plus `margin`
       pixels on each side.
@param margin pixels, ≥ 0.
@param path the camera's motion (camera clock).
@param K camera matrix, pixels.
@param size frame size, pixels; shutter.rows must be its height.
@param shutter frame timing, camera clock.
@param maxStepPx largest image motion within a time cell, pixels, > 0.
@param rotationOnly leave the translation out (for the check against renderBlurred).
@return the frame, linear intensity, CV_32F. */
cv::Mat renderPlaneBlurred(const cv::Mat& sceneLinear, int margin, const CameraPath& path, const cv::Matx33d& K,
                           const cv::Size& size, const cv::dynblur::RollingShutter& shutter, double maxStepPx,
                           bool rotationOnly = false);

/** @brief The home view warped to the view at time t (the sharp frame there), linear CV_32F.
@param sceneLinear, margin, path, K, size as renderPlaneBlurred. @param t seconds, camera clock.
@param rotationOnly leave the translation out. */
cv::Mat viewAt(const cv::Mat& sceneLinear, int margin, const CameraPath& path, const cv::Matx33d& K,
               const cv::Size& size, double t, bool rotationOnly = false);

}  // namespace dynblur_samples

#endif
