// SPDX-License-Identifier: Apache-2.0
// Private: fitting a MotionCorrection to frames against still reference frames (refinement.hpp).
#ifndef OPENCV_DYNBLUR_MOTION_FIT_HPP
#define OPENCV_DYNBLUR_MOTION_FIT_HPP

#include <opencv2/dynblur/refinement.hpp>

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** The fit's parameters, in this order: the time offset, the line delay, the plant's ωn and ζ (a
plant's motion), the gyro bias's three components (a measured motion). */
const int kFitParameters = 7;
typedef Vec<double, kFitParameters> FitVector;
typedef Matx<double, kFitParameters, kFitParameters> FitMatrix;

//! The fit's two resolutions: the scan and a first fit at most this wide, pixels, then the last fit.
const int kFitCoarseWidth = 160, kFitFineWidth = 320;

/** @brief A linear luminance image and its halvings (cv::resize, INTER_AREA), with the camera of
each: level k is the frame halved k times, as halfResolutionCamera describes it. */
struct LuminancePyramid
{
    std::vector<Mat> images;                  //!< CV_32FC1, level 0 the full size
    std::vector<Ptr<CameraModel>> cameras;    //!< the camera of each level
    std::vector<double> noiseSigma;           //!< Immerkær's noise estimate of each level @cite Immerkaer1996Noise

    int levels() const { return int(images.size()); }
};

/** @brief The linear luminance (mean of the color channels; alpha dropped) of an 8-bit sRGB or
linear CV_32F frame. */
Mat linearLuminance(const Mat& frame);

/** @brief Halves `luminance` while its width exceeds `coarsestWidth` and both sides are even.
@param estimateNoise take each level's noise (what a reference needs). */
LuminancePyramid buildPyramid(const Mat& luminance, const Ptr<CameraModel>& camera, int coarsestWidth,
                              bool estimateNoise);

/** @brief The noise of one frame at each level of the fit's pyramid (buildPyramid down to
kFitCoarseWidth), measured from two stills at rest at the same view: the robust standard deviation
(1.4826 × the median absolute deviation) of their pyramids' difference over √2, over the pixels
neither clips. Throws cv::Exception prefixed by `function` and naming the argument when either is not
a frame of `camera` (checkCameraFrame), their types differ, or they agree in at least half of those
pixels at a level the fit runs at (at most kFitFineWidth wide, or the smallest). */
std::vector<double> measureNoise(const Mat& stillA, const Mat& stillB, const Ptr<CameraModel>& camera,
                                 const char* function);

//! The shutter of a frame halved `halvings` times (halfResolutionShutter applied that often).
RollingShutter shutterAtLevel(const RollingShutter& shutter, int halvings);

//! One frame and the still frame it is compared with.
struct FitFrame
{
    const LuminancePyramid* reference = nullptr;
    LuminancePyramid frame;  //!< the same levels as the reference's (or fewer)
    SwitchSchedule schedule;
    RollingShutter shutter;  //!< as reported, full resolution
    double referenceAngle = 0;  //!< radians
    /** a measured motion (CameraMotion not a plant's; then `schedule` and `referenceAngle` are
        unused): every frame of a fit has one, or none does */
    Ptr<CameraMotion> motion;
    double referenceTime = 0;  //!< with `motion`: the still's capture time, the frames' clock, seconds
};

//! What the fit may change, and how far.
struct FitSettings
{
    int flags = REFINE_ALL;          //!< MotionRefinement
    double maxTimeOffset = 0.003;    //!< the offset scan's half-width around the start, seconds
    double scanStep = 0.0005;        //!< the offset scan's step, seconds
    int coarseWidth = kFitCoarseWidth;  //!< the scan and the first fit run at most this wide, pixels
    int fineWidth = kFitFineWidth;      //!< the last fit runs at most this wide, pixels
    /** false: only the fine level's fit, from `start` (a calibrated start, whose offset a frame's
        jitter moves by a fraction of a millisecond: the fine level's basin holds it) */
    bool coarse = true;
    bool deviation = true;           //!< false: FitResult::deviation of the fine level's parameters is not computed
};

//! The fit's outcome.
struct FitResult
{
    MotionCorrection correction;     //!< consistency over every frame at the fine level
    FitVector deviation;             //!< standard deviations of the parameters (0 when not fitted)
    std::vector<double> frameConsistency;  //!< each frame's consistency at the result
    int evaluations = 0;             //!< forward models computed
    double improvement = 0;          //!< the fit's relative decrease of the fine level's squared residual from the start
    bool unchanged = false;          //!< the start explained the frames as well as the fit (within 1 %): kept
    int unobserved = 0;              //!< MotionRefinement flags of parameters the frames did not determine (kept at the start)
    int ridge = 0;                   //!< MotionRefinement flags of parameters mixed in a combination held at the start (a ridge)
    int held = 0;                    //!< unobserved | ridge
    FitVector information;           //!< eigenvalues of the frames' information in prior units, descending (0 when not analysed)
    int pinned = 0;                  //!< MotionRefinement flags of fitted parameters that ended at a search bound
    double gain = 1;                 //!< the first frame's brightness over its still's at the result
    String pinnedNote;               //!< which parameter, at which value and bound
};

/** @brief Throws cv::Exception naming the argument when `image` is not a frame of `camera`: empty,
not CV_8U or CV_32F, not 1, 3 or 4 channels, another size, or (CV_32F) NaN, Inf or outside [0, 1].
@param function prefixes the message. @param name the argument's name. */
void checkCameraFrame(const Mat& image, const CameraModel& camera, const char* function, const char* name);

/** @brief Fits a correction to `frames` (each against its reference): a scan of the time offset
at the coarse level, then Levenberg–Marquardt on the flagged parameters at the coarse and the fine
level, with a weak prior toward `start`. A parameter the coarse fit leaves uncertain (the frames'
moving rows see content the reference never saw, or their motion does not depend on it) keeps its
start value; combinations the frames determine too weakly (a ridge) stay at the start too, and the
start as a whole stays unless the fit lowers the squared residual significantly. A fitted parameter
left at a search bound is reported in `pinned`. `plant` is unused (may be null) when the frames carry
a measured motion; their fit has the bias in place of the plant. */
FitResult fitMotionCorrection(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames,
                              const MotionCorrection& start, const FitSettings& settings);

//! "time offset, line delay, plant and gyro bias": the parameters of MotionRefinement `flags`, for messages.
String refinementFlagNames(int flags);

/** @brief Consistency of `correction` with each frame at the level at most `width` wide. */
std::vector<double> frameConsistency(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames,
                                     const MotionCorrection& correction, int width);

/** @brief The mean squared residual (noise units) over every frame at the level at most `width`
wide, for each candidate, over the pixels `maskAt` lets both frames observe (one set for all, so the
values form a smooth curve). */
std::vector<double> meanSquaredResiduals(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames,
                                         const MotionCorrection& maskAt,
                                         const std::vector<MotionCorrection>& candidates, int width);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
