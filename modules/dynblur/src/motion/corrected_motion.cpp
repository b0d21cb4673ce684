// SPDX-License-Identifier: Apache-2.0
// A measured motion corrected by a MotionCorrection: its gyro bias removed about a reference time.
#include "precomp.hpp"

#include "motion/corrected_motion.hpp"
#include "motion/so3.hpp"

namespace cv {
namespace dynblur {
namespace detail {

namespace {

//! Q(t)·exp(−[b·(t − t0)]×): the first-order removal of a constant bias b (withoutGyroBias).
class BiasFreeMotion CV_FINAL : public CameraMotion
{
public:
    BiasFreeMotion(const Ptr<CameraMotion>& motion, const Vec3d& bias, double t0)
        : motion_(motion), bias_(bias), t0_(t0)
    {
    }
    Matx33d orientation(double t) const CV_OVERRIDE { return motion_->orientation(t) * drift(t).t(); }
    Vec3d angularVelocity(double t) const CV_OVERRIDE
    {
        // d/dt [Q·Eᵀ] = Q·Eᵀ·[E·ω − b]× with E = exp([b·(t − t0)]×), which commutes with [b]×.
        return drift(t) * motion_->angularVelocity(t) - bias_;
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
    String getDefaultName() const CV_OVERRIDE { return "dynblur.CameraMotion.BiasFree"; }

private:
    //! exp([b·(t − t0)]×): the turn the bias adds from t0 to t.
    Matx33d drift(double t) const { return so3::matrixFromQuat(so3::quatFromRotationVector(bias_ * (t - t0_))); }

    Ptr<CameraMotion> motion_;
    Vec3d bias_;
    double t0_;
};

}  // namespace

Ptr<CameraMotion> withoutGyroBias(const Ptr<CameraMotion>& motion, const Vec3d& bias, double t0)
{
    if (motion.empty() || bias == Vec3d())
        return motion;
    return makePtr<BiasFreeMotion>(motion, bias, t0);
}

ViewMotion correctedView(const Ptr<CameraMotion>& motion, const MotionCorrection& correction, double tRef,
                         const RollingShutter& corrected)
{
    const double t0 = std::isnan(tRef) ? midExposure(corrected) : tRef + correction.timeOffset;
    if (correction.gyroBias == Vec3d())
        return ViewMotion::of(motion, t0, corrected);
    ViewMotion view;
    view.motion = withoutGyroBias(motion, correction.gyroBias, t0);
    view.reference = motion->orientation(t0);  // the bias adds no turn at t0
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
