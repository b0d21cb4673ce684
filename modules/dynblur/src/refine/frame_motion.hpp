// SPDX-License-Identifier: Apache-2.0
// Private: what consecutive frames of a clip say about the camera's turn between them.
#ifndef OPENCV_DYNBLUR_REFINE_FRAME_MOTION_HPP
#define OPENCV_DYNBLUR_REFINE_FRAME_MOTION_HPP

#include <opencv2/dynblur/camera.hpp>

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! The turn the image shows in one band of rows between two frames.
struct BandTurn
{
    int frameA = 0, frameB = 0;  //!< the frames' indices in the clip
    double row = 0;              //!< the band's middle row, full-resolution pixels
    Vec3d turn;                  //!< the body rotation from frame a's band to frame b's, rad, camera axes (first order)
    double weight = 0;           //!< the patches' phase-correlation peaks, summed
};

//! A patch's shift between two frames, full-resolution pixels.
struct PatchShift
{
    int index = 0;      //!< its place in FrameMotionMeter::patchCentres()
    int band = 0;       //!< its band of rows
    Point2d centre;     //!< its centre in the first frame
    Point2d shift;      //!< where its content went in the second, minus where it was
    double response = 0;  //!< the phase-correlation peak, in (0, 1]
};

//! One feature seen in two frames, at full-resolution pixels.
struct TrackPair
{
    int frameA = 0, frameB = 0;
    Point2f a, b;
};

/** @brief Measures consecutive frames of a clip, one frame at a time: in each of kBands bands of
rows, the turn that best explains the phase-correlation shifts of its kColumns patches (the rotation
flow of a pinhole camera, to first order: ∆u = fx·(xy·rx − (1 + x²)·ry + y·rz),
∆v = fy·((1 + y²)·rx − xy·ry − x·rz) at normalized coordinates (x, y)); and features tracked by
pyramidal Lucas–Kanade, kept when the backward track returns within kBackTrackPx, as pairs between
consecutive frames and, every kAnchorSpan frames, between a track's anchor and its current position
(a longer baseline, which a gyro bias turns further). Only the last frame's reduced image is kept. */
class FrameMotionMeter
{
public:
    static const int kBands = 4, kColumns = 3, kAnchorSpan = 8;

    /** @param camera the clip's camera.
    @param analysisWidth frames are measured at this width, pixels (at most their own). */
    FrameMotionMeter(const Ptr<CameraModel>& camera, int analysisWidth);

    /** @brief Measures `frame` (a camera frame, checked by the caller) against the previous one when
    `follows`, appending to `turns` (when given) and `pairs`; otherwise starts afresh from it.
    @param index its index in the clip. */
    void add(const Mat& frame, int index, bool follows, std::vector<BandTurn>* turns, std::vector<TrackPair>& pairs);

    //! `frame` (a camera frame) reduced as the meter measures it: 8-bit luminance at the analysis width.
    Mat reduce(const Mat& frame) const;
    //! The centres of the kBands × kColumns patches shifts() measures, band by band, full-resolution pixels.
    std::vector<Point2d> patchCentres() const;
    /** @brief The shifts of the patches from `previous` to `next` (both reduce()d). Each patch is read
    in `next` where its content is expected, so a turn of tens of pixels leaves only a small residual
    shift to find: at `expected` (one shift per patch of patchCentres(), full-resolution pixels), or
    when that is empty after the whole frame's shift, the patch read where it overlaps the frame.
    Patches whose peak is too weak are left out. */
    std::vector<PatchShift> shifts(const Mat& previous, const Mat& next,
                                   const std::vector<Point2d>& expected = std::vector<Point2d>()) const;

private:
    void measureTurns(const Mat& next, int index, std::vector<BandTurn>& turns) const;
    //! Patch `column` of `band`, reduced pixels.
    Rect patch(int band, int column) const;
    void track(const Mat& next, int index, std::vector<TrackPair>& pairs);
    Point2f toFull(const Point2f& p) const;

    Ptr<CameraModel> camera_;
    double scale_;           // analysis pixels per full-resolution pixel
    Size analysisSize_;
    Mat previous_;           // the last frame, CV_8U luminance at the analysis size
    int previousIndex_ = -1;
    std::vector<Point2f> points_;   // active tracks in previous_, analysis pixels
    std::vector<Point2f> anchors_;  // each track's anchor, analysis pixels ...
    std::vector<int> anchorFrames_; // ... and its frame
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
