// SPDX-License-Identifier: Apache-2.0
// Private: a measured motion's frame checked against the frame before it, with no still frame.
#ifndef OPENCV_DYNBLUR_PIPELINE_NEIGHBOUR_CHECK_HPP
#define OPENCV_DYNBLUR_PIPELINE_NEIGHBOUR_CHECK_HPP

#include <opencv2/dynblur/refinement.hpp>

#include "refine/frame_motion.hpp"

namespace cv {
namespace dynblur {
namespace detail {

//! How well a motion carries a frame's neighbour onto it, patch by patch.
struct NeighbourAgreement
{
    /** each textured patch's error: how far from where the motion carries it its content was found,
        pixels (+inf: not found there) */
    std::vector<double> errorPx;
    std::vector<double> shiftPx;  //!< each one's shift as the motion predicts it, pixels
};

/** @brief The frame before a measured motion's frame, as the check of that frame sees it: the shifts
of a grid of patches from it to the frame (phase correlation, FrameMotionMeter::shifts: it holds
where blur defeats feature trackers), which the motion, with a correction's clock offset, line
delay, bias and rate scale, must reproduce from each patch's row exposure instant in the neighbour to
its row's in the frame (TrackResiduals): what the frame-to-frame geometry says about a frame when no
still frame is at hand. The median error ignores a moving object; a wrong log, axes or clock move
every patch. */
class NeighbourCheck
{
public:
    explicit NeighbourCheck(const Ptr<CameraModel>& camera);

    //! Keeps `frame` (a camera frame, checked by the caller) and its timing; an empty frame forgets it.
    void set(const Mat& frame, const RollingShutter& shutter);
    bool present() const { return present_; }
    //! Seconds from the neighbour's exposure to `shutter`'s (their frame starts); negative for a neighbour after it.
    double interval(const RollingShutter& shutter) const { return shutter.frameStart - shutter_.frameStart; }
    //! The agreement of `motion` corrected by `c` with the tracks from the neighbour to `frame`.
    NeighbourAgreement measure(const Mat& frame, const RollingShutter& shutter, const Ptr<CameraMotion>& motion,
                               const MotionCorrection& c) const;

private:
    Ptr<CameraModel> camera_;
    FrameMotionMeter meter_;
    Mat neighbour_;  // reduced as the meter reduces frames
    RollingShutter shutter_;
    bool present_ = false;
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
