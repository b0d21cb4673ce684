// SPDX-License-Identifier: Apache-2.0
// A measured motion corrected by a MotionCorrection: its gyro bias removed and its rates scaled about a
// reference time.
#include "precomp.hpp"

#include "motion/corrected_motion.hpp"
#include "motion/so3.hpp"

namespace cv {
namespace dynblur {
namespace detail {

namespace {

/* Q(t)·exp(−[b·(t − t0)]×): the first-order removal of a constant bias b; with a rate scale s ≠ 1,
   that motion's turn from t0 scaled: Q(t0)·exp(s·log(Q(t0)ᵀ·Q(t)·exp(−[b·(t − t0)]×))), whose rate
   is s times the unbiased one for a turn about a fixed axis (withCorrectedRates). */
class RateCorrectedMotion CV_FINAL : public CameraMotion
{
public:
    RateCorrectedMotion(const Ptr<CameraMotion>& motion, const Vec3d& bias, double rateScale, double t0)
        : motion_(motion), bias_(bias), scale_(rateScale), t0_(t0), start_(motion->orientation(t0))
    {
    }
    Matx33d orientation(double t) const CV_OVERRIDE
    {
        const Matx33d unbiased = motion_->orientation(t) * drift(t).t();
        if (scale_ == 1)
            return unbiased;
        const Vec3d turn = so3::rotationVectorFromQuat(so3::quatFromMatrix(start_.t() * unbiased));
        return start_ * so3::matrixFromQuat(so3::quatFromRotationVector(turn * scale_));
    }
    Vec3d angularVelocity(double t) const CV_OVERRIDE
    {
        // d/dt [Q·Eᵀ] = Q·Eᵀ·[E·ω − b]× with E = exp([b·(t − t0)]×), which commutes with [b]×.
        return (drift(t) * motion_->angularVelocity(t) - bias_) * scale_;
    }
    Vec2d getTimeSpan() const CV_OVERRIDE { return motion_->getTimeSpan(); }
    Matx33d referenceOrientation(double tRef, const RollingShutter& shutter) const CV_OVERRIDE
    {
        if (std::isinf(tRef))
            CV_Error(Error::StsBadArg, "CameraMotion::referenceOrientation: tRef must be finite (seconds) or NaN "
                                       "(the middle of the frame's exposure)");
        return orientation(std::isnan(tRef) ? midExposure(shutter) : tRef);
    }
    bool isPlantMotion() const CV_OVERRIDE { return false; }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.CameraMotion.RateCorrected"; }

private:
    //! exp([b·(t − t0)]×): the turn the bias adds from t0 to t.
    Matx33d drift(double t) const { return so3::matrixFromQuat(so3::quatFromRotationVector(bias_ * (t - t0_))); }

    Ptr<CameraMotion> motion_;
    Vec3d bias_;
    double scale_, t0_;
    Matx33d start_;  // Q(t0)
};

}  // namespace

Ptr<CameraMotion> withCorrectedRates(const Ptr<CameraMotion>& motion, const Vec3d& bias, double rateScale, double t0)
{
    if (motion.empty() || (bias == Vec3d() && rateScale == 1))
        return motion;
    return makePtr<RateCorrectedMotion>(motion, bias, rateScale, t0);
}

ViewMotion correctedView(const Ptr<CameraMotion>& motion, const MotionCorrection& correction, double tRef,
                         const RollingShutter& corrected)
{
    const double t0 = std::isnan(tRef) ? midExposure(corrected) : tRef + correction.timeOffset;
    if (correction.gyroBias == Vec3d() && correction.rateScale == 1)
        return ViewMotion::of(motion, t0, corrected);
    ViewMotion view;
    view.motion = withCorrectedRates(motion, correction.gyroBias, correction.rateScale, t0);
    view.reference = motion->orientation(t0);  // neither the bias nor the scale turns the view at t0
    return view;
}

void checkMotionCoversSearch(const Ptr<CameraMotion>& motion, const RollingShutter& shutter, double margin,
                             const char* function, const String& name)
{
    const Vec2d readout = shutter.readoutInterval();
    const double lineDelaySearch = 0.15 * (shutter.rows - 1) * shutter.lineDelay;
    const Vec2d span = motion->getTimeSpan();
    if (!(readout[0] - margin >= span[0] && readout[1] + margin + lineDelaySearch <= span[1]))
        CV_Error(Error::StsOutOfRange,
                 format("%s: the readout of %s, [%.6f, %.6f] s, widened by the refinement's search (%.6f s of clock "
                        "offset, a line delay 15 %% longer) lies outside the time span of the motion, [%.6f, %.6f] "
                        "s: its samples must cover it (same clock as the shutters' frameStart)",
                        function, name.c_str(), readout[0], readout[1], margin, span[0], span[1]));
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
