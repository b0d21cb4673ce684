// SPDX-License-Identifier: Apache-2.0
// Private: DynamicDeblurrer's correction stage, from a frame and its predicted motion to the
// correction it is restored with, or the reason it is not.
#ifndef OPENCV_DYNBLUR_PIPELINE_FRAME_CORRECTION_HPP
#define OPENCV_DYNBLUR_PIPELINE_FRAME_CORRECTION_HPP

#include <opencv2/dynblur/refinement.hpp>

#include "pipeline/neighbour_check.hpp"
#include "refine/fit_pyramid.hpp"

#include <limits>
#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

struct FitFrame;
struct FitSettings;

//! What the correction stage found for one frame.
struct FrameCorrection
{
    /** the correction to restore with; applied = false: the frame is returned unchanged, and
        `reason` says why (or how the correction was found) */
    MotionCorrection correction;
    int window = 0;  //!< the frame's ExposureWindow under the corrected motion
};

//! What the correction stage may refine and when it refuses: DynamicDeblurrer's refinement settings.
struct CorrectionSettings
{
    int refinement = REFINE_ALL;  //!< MotionRefinement flags
    bool blind = false;           //!< refine frames without a still blind
    double blindLimit = std::numeric_limits<double>::infinity();  //!< blind criterion above it: refused
    double consistencyLimit = std::numeric_limits<double>::quiet_NaN();  //!< NaN: by the noise's source
    //! The correction every frame starts from (its consistency, applied and reason unused).
    MotionCorrection calibration;
    bool calibrated = false;  //!< `calibration` was set
    //! A measured motion's frame its neighbour implies a blur error above this (px; and a share of its blur) is refused.
    double neighbourLimitPx = 1.0;
};

/** @brief The correction stage: the still frames a stream's frames are compared with, the noise
their residuals are weighed by, the refinement's settings, and the choice and fit of each frame's
correction (a plant's frame against the still that saw its moving rows, a measured motion's against
a still placed by its capture time, or blind) with the decision to refuse it. */
class FrameCorrector
{
public:
    /** @param plant the positioner (null for a deblurrer of measured motion).
    @param camera the frames' camera. */
    FrameCorrector(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera);

    //! A plant's frame under `schedule`, read by `shutter` as reported.
    FrameCorrection correct(const Mat& frame, const SwitchSchedule& schedule, const RollingShutter& shutter) const;
    /** A measured motion's frame, read by `shutter` as reported; checks the motion covers the corrected
        readout. A mount's motion (Mount::motion) is plant-driven: its frame is corrected as a plant's is,
        against the stills at rest before and after its move, each axis's plant refined. */
    FrameCorrection correct(const Mat& frame, const Ptr<CameraMotion>& motion, const RollingShutter& shutter) const;

    /** @brief Checks and keeps the stills (an empty Mat: none on that side), naming each argument as
    the caller `fn` calls it; `single`: one still for every frame, whatever its window. */
    void setStills(const char* fn, const Mat& before, const char* beforeName, double angleBefore,
                   const char* angleBeforeName, const Mat& after, const char* afterName, double angleAfter,
                   const char* angleAfterName, bool single);
    //! One still of a measured motion, placed by its capture time (the middle row's mid-exposure of `stillShutter`).
    void setTimedStill(const char* fn, const Mat& still, const RollingShutter& stillShutter);
    //! Keeps the frame before the next measured-motion frame (empty: forget it), checked by the caller.
    void setNeighbour(const Mat& frame, const RollingShutter& shutter) { neighbour_.set(frame, shutter); }
    //! Measures the noise from two stills at rest (both empty: forget it).
    void setNoiseFrames(const Mat& stillA, const Mat& stillB);
    void clearStills();

    CorrectionSettings settings;  //!< checked by the caller

    //! The consistency limit in force: consistencyLimit, or the default for the noise's source.
    double effectiveConsistencyLimit() const;

private:
    //! A still frame of the stream: its luminance, halved down to the fit's coarse width, and its angle.
    struct Still
    {
        LuminancePyramid pyramid;
        double angle = std::numeric_limits<double>::quiet_NaN();  // radians; NaN: the schedule's resting angle
        double time = std::numeric_limits<double>::quiet_NaN();   // a measured motion's still: capture time, s
        std::vector<double> estimatedNoise;  // Immerkær's estimate at each level
        bool present() const { return pyramid.levels() > 0; }
    };

    //! The noise each still's pyramid weighs residuals by: the noise frames' when given, else Immerkær's.
    void weighStills();
    void checkStreamType(const char* fn, const Mat& frame) const;
    MotionCorrection fitAgainst(const std::vector<FitFrame>& frames, const String& against,
                                MotionCorrection correction, const FitSettings& settings) const;
    MotionCorrection blindCorrection(const Mat& frame, const SwitchSchedule& schedule, const RollingShutter& shutter,
                                     MotionCorrection correction) const;
    MotionCorrection correctPlantFrame(const Mat& frame, const SwitchSchedule& schedule,
                                       const RollingShutter& shutter) const;
    MotionCorrection correctMeasuredFrame(const Mat& frame, const Ptr<CameraMotion>& motion,
                                          const RollingShutter& shutter) const;
    MotionCorrection correctMountFrame(const Mat& frame, const Ptr<CameraMotion>& motion,
                                       const RollingShutter& shutter) const;
    /** The stills a frame in `window` is compared with (0: before the move, 1: after it), and
        `against`, how the reason names them. */
    std::vector<int> stillsFor(int window, String& against) const;
    //! One pair per still in `chosen`: the frame `input`, read by `shutter`, against it.
    std::vector<FitFrame> pairWithStills(const Mat& input, const std::vector<int>& chosen,
                                         const RollingShutter& shutter) const;

    //! A measured motion's frame checked against its neighbour: `correction` refused when the tracks disagree.
    void checkAgainstNeighbour(const Mat& frame, const Ptr<CameraMotion>& motion, const RollingShutter& shutter,
                               MotionCorrection& correction) const;

    Ptr<Plant> plant_;
    Ptr<CameraModel> camera_;
    NeighbourCheck neighbour_;
    Still stills_[2];                 // before the move, after it
    std::vector<double> noiseSigma_;  // setNoiseFrames: one frame's noise at each pyramid level; empty: Immerkær's
    int noiseType_ = -1;              // the noise frames' type
    int referenceType_ = -1;          // the stills' type
    bool single_ = false;             // one still for every frame, whatever its window
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
