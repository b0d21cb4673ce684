// SPDX-License-Identifier: Apache-2.0
// Private: a clip's fine calibration from features tracked across frames, under the rolling-shutter model.
#ifndef OPENCV_DYNBLUR_REFINE_TRACK_FIT_HPP
#define OPENCV_DYNBLUR_REFINE_TRACK_FIT_HPP

#include <opencv2/dynblur/camera_motion.hpp>

#include "refine/clip_sync.hpp"
#include "refine/fit_parameters.hpp"
#include "refine/level_fit.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The reprojection errors of tracked features under a correction of a measured motion: the
point seen at row y of frame a at the instant t_a = frameStart + y·lineDelay·lineDelayScale +
exposure/2 + timeOffset (its blurred image's centroid is its mid-exposure position) is carried by
R = Q(t_a)ᵀ·Q(t_b), with the bias's turn removed and the turn scaled by the rate scale as
withCorrectedRates does it about t_a, to frame b: K⁻¹·p_b ∝ Rᵀ·K⁻¹·p_a. Residuals in pixels (the
normalized error times the focal length), two per pair. */
class TrackResiduals : public FitResiduals
{
public:
    /** @param motion the log's motion (its axes corrected), on the log's clock.
    @param camera the clip's camera.
    @param pairs the tracked pairs; kept by reference, they must outlive this.
    @param frames each frame's timing as the video reports it. */
    TrackResiduals(const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera, const std::vector<TrackPair>& pairs,
                   const std::vector<ClipFrame>& frames);

    void residuals(const MotionCorrection& c, std::vector<float>& out) CV_OVERRIDE;

    //! Each used pair's reprojection error under `c`, pixels.
    std::vector<double> errors(const MotionCorrection& c);
    /** @brief Where `c` carries each used pair's point of frame a in frame b, full-resolution pixels
    (its instant there read at the pair's row in b); NaN where the motion does not cover it. */
    std::vector<Point2d> carried(const MotionCorrection& c);
    //! Leaves out the used pairs whose `keep` is false (in the order errors() gives them).
    void select(const std::vector<bool>& keep);
    //! The pairs in use, as indices into the pairs given.
    const std::vector<int>& used() const { return used_; }

private:
    //! The predicted normalized position of pair k's point in frame b under `c`, into `predicted`.
    bool predict(int k, const MotionCorrection& c, Point2d& predicted) const;

    Ptr<CameraMotion> motion_;
    Ptr<CameraModel> camera_;
    double focal_;
    const std::vector<TrackPair>& pairs_;
    std::vector<ClipFrame> frames_;
    std::vector<Vec3d> rays_;       // each pair's ray in frame a, normalized coordinates (x, y, 1)
    std::vector<Point2d> targets_;  // its position in frame b, normalized
    std::vector<int> used_;
};

//! What the fine stage found.
struct TrackFit
{
    MotionCorrection correction;  //!< relative to the frames' timing as given: timeOffset, scales, bias
    FitVector deviation;          //!< standard deviations in the correction's units (0 when not fitted)
    int held = 0;                 //!< MotionRefinement flags of parameters the tracks did not determine
    int heldParameters = 0;       //!< their bits (bit j: kFitTable[j])
    double rms = 0;               //!< the inlier pairs' RMS reprojection error, pixels
    std::vector<double> frameRms; //!< each frame's inlier pairs' RMS error, pixels (NaN: none)
    size_t inliers = 0, pairs = 0;
};

/** @brief Levenberg–Marquardt over the flagged parameters (the refinement's table, measured-motion
rows) from `start`, the clock offset within ±maxTimeOffset of it, on the tracks' reprojection errors;
twice the pairs beyond three robust deviations (and 1 px) are left out and the fit runs again. A
parameter among `holdable` whose deviation (the tracks of a frame counted as one measurement)
exceeds its table's `observable` is held at its start and reported. */
TrackFit fitTracks(const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera,
                   const std::vector<TrackPair>& pairs, const std::vector<ClipFrame>& frames,
                   const MotionCorrection& start, int flags, int holdable, double maxTimeOffset);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
