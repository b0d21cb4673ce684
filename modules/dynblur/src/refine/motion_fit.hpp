// SPDX-License-Identifier: Apache-2.0
// Private: fitting a MotionCorrection to frames against still reference frames (refinement.hpp).
#ifndef OPENCV_DYNBLUR_REFINE_MOTION_FIT_HPP
#define OPENCV_DYNBLUR_REFINE_MOTION_FIT_HPP

#include "refine/fit_parameters.hpp"
#include "refine/level_residuals.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

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
    int unobservedParameters = 0;    //!< the bits (bit j: kFitTable[j]) of the parameters `unobserved` stands for
    int ridgeParameters = 0;         //!< the bits of the parameters `ridge` stands for
    int heldParameters = 0;          //!< unobservedParameters | ridgeParameters
    FitVector information;           //!< eigenvalues of the frames' information in prior units, descending (0 when not analysed)
    int pinned = 0;                  //!< MotionRefinement flags of fitted parameters that ended at a search bound
    double gain = 1;                 //!< the first frame's brightness over its still's at the result
    String pinnedNote;               //!< which parameter, at which value and bound
};

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
