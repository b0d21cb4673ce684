// SPDX-License-Identifier: Apache-2.0
// Private: whether a frame is sharp, measured from its corrected motion before any kernel is made
// (DynamicDeblurrer::setSharpThreshold), and where a sharp frame recorded each pixel of the
// reference view.
#ifndef OPENCV_DYNBLUR_PIPELINE_FRAME_SHARPNESS_HPP
#define OPENCV_DYNBLUR_PIPELINE_FRAME_SHARPNESS_HPP

#include "opencv2/dynblur/camera.hpp"
#include "opencv2/dynblur/shutter.hpp"

#include "motion/view_motion.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief How far a frame strays from the reference view, from its motion alone. Over a grid of
points (17 columns edge to edge, every 8th row and the last), each point's path during its row's
exposure (17 instants, ends included) is where the views of those instants show it relative to the
reference view:
- blurPx: the largest extent of a path (the greatest distance between two of its positions): the
  length of the point's kernel, which a frame that is not deconvolved keeps;
- shiftPx: the largest distance from a path's mean position (the kernel's centre of mass, its
  instants weighed by dwell time) to where the reference view has the point: the rolling-shutter
  geometry and the offset from the reference view that a frame passed through keeps.
A path sampled at 17 instants misses at most 1/16 of its extent between two of them (a point moving
at constant speed). A point that turns behind the camera counts as infinitely far. */
struct FrameSharpness
{
    double blurPx = 0;   //!< the largest extent of a point's path during its row's exposure, pixels
    double shiftPx = 0;  //!< the largest distance of a path's mean from the reference position, pixels
    Point2d blurAt;      //!< the pixel where blurPx was measured
    Point2d shiftAt;     //!< the pixel where shiftPx was measured
    //! The grid: its rows (pixels) and the spacing of its columns, which start at 0 (pixels).
    std::vector<double> rows;
    double columnStep = 0;
    /** rows × columns, CV_64FC2: each path's mean displacement, the grid pixel minus where the
        reference view has what it recorded (pixels) */
    Mat meanDisplacement;
    std::vector<double> rowBlurPx;   //!< blurPx of each grid row alone, pixels
    std::vector<double> rowShiftPx;  //!< shiftPx of each grid row alone, pixels

    /** @brief True when both stay strictly below `thresholdPx` (pixels; 0: never). */
    bool within(double thresholdPx) const { return blurPx < thresholdPx && shiftPx < thresholdPx; }
    //! The mean displacement at any pixel of the frame, bilinear between the grid's nodes (clamped to it).
    Point2d meanDisplacementAt(const Point2d& pixel) const;
};

/** @brief The sharpness of a frame of `camera` read by `shutter` (the corrected shutter, rows = the
camera's height) whose views follow `view` (the corrected motion and its reference). */
CV_EXPORTS FrameSharpness measureSharpness(const ViewMotion& view, const RollingShutter& shutter,
                                           const CameraModel& camera);

/** @brief For each pixel p of the reference view, the frame pixel q that recorded it, q − d̄(q) = p
with d̄ the mean displacement of `sharpness`: CV_32F maps of the frame's size, for cv::remap. Solved
at the grid's nodes by fixed-point iteration, bilinear between them as d̄ is. The iteration converges
where d̄ changes by less than a pixel per pixel, as it does in a frame whose blur and shift stay
within a pixel; where the rows' displacements fold over one another (a vibration faster than the
readout) it does not.
@return false (maps unset) when some node's position still moved by more than 0.01 px at the last
iteration. */
bool recordedPositions(const FrameSharpness& sharpness, Size size, Mat& mapX, Mat& mapY);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
