// SPDX-License-Identifier: Apache-2.0
// Private: the residuals a MotionCorrection fit minimises, frames against their stills carried
// through the predicted blur, at one resolution.
#ifndef OPENCV_DYNBLUR_REFINE_LEVEL_RESIDUALS_HPP
#define OPENCV_DYNBLUR_REFINE_LEVEL_RESIDUALS_HPP

#include <opencv2/dynblur/refinement.hpp>

#include "refine/fit_pyramid.hpp"
#include "refine/level_fit.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! One frame and the still frame it is compared with.
struct FitFrame
{
    const LuminancePyramid* reference = nullptr;
    LuminancePyramid frame;  //!< the same levels as the reference's (or fewer)
    SwitchSchedule schedule;
    RollingShutter shutter;  //!< as reported, full resolution
    double referenceAngle = 0;  //!< radians
    /** a measured motion or a mount's (CameraMotion not a plant's; then `schedule` and `referenceAngle`
        are unused): every frame of a fit has one of the same kind, or none does */
    Ptr<CameraMotion> motion;
    double referenceTime = 0;  //!< with a measured `motion`: the still's capture time, the frames' clock, seconds
    Matx33d referenceOrientation;  //!< with a mount's `motion`: its still's orientation, the chain at rest
};

/** @brief The frames' residuals at one pyramid level: (frame − gain × predicted) / σ over each
frame's fixed mask, the prediction being the frame's still carried through the blur a correction
predicts (tile kernels, kFitTileColumns node columns). */
class LevelResiduals : public FitResiduals
{
public:
    /** @param plant the nominal plant (null for frames of a measured motion).
    @param frames the frames with their stills; they must outlive this object.
    @param width each frame is compared at its pyramid's level at most this wide, pixels. */
    LevelResiduals(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames, int width);

    /** Fixes each frame's mask: pixels the reference fully covers under `c` (eroded by two pixels,
        so the fit's steps do not move them across the edge), away from the border, not saturated. */
    void fixMasks(const MotionCorrection& c);

    size_t pixels() const { return pixels_; }
    //! Each frame's brightness gain over its still at the last residuals() (frame ≈ gain × still blurred).
    const std::vector<double>& gains() const { return gains_; }
    size_t frames() const { return frames_.size(); }
    //! Whether the frames carry a measured motion (FitFrame::motion) rather than a plant's.
    bool measured() const { return !frames_[0].motion.empty(); }
    int evaluations() const { return evaluations_; }

    /** Appends every frame's residuals under `c` to `out` (in mask order); `perFrame`, when given,
        receives each frame's mean squared residual. */
    void residuals(const MotionCorrection& c, std::vector<float>& out, std::vector<double>* perFrame);
    void residuals(const MotionCorrection& c, std::vector<float>& out) CV_OVERRIDE { residuals(c, out, nullptr); }

private:
    //! Frame i's still carried through the blur `c` predicts, and the light each pixel receives from it.
    void predict(size_t i, const MotionCorrection& c, Mat& predicted, Mat& coverage);

    Ptr<Plant> plant_;
    const std::vector<FitFrame>& frames_;
    std::vector<int> levels_;
    std::vector<double> sigma_;
    std::vector<Mat> masks_, weights_;  // weights_: the masks as 0 and 1 in CV_32F
    std::vector<double> gains_;
    Mat ones_;
    size_t pixels_ = 0;
    int evaluations_ = 0;
};


}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
