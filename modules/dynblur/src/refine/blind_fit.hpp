// SPDX-License-Identifier: Apache-2.0
// Private: the time offset of a frame without a reference frame (blind refinement, refinement.hpp).
#ifndef OPENCV_DYNBLUR_BLIND_FIT_HPP
#define OPENCV_DYNBLUR_BLIND_FIT_HPP

#include <opencv2/dynblur/refinement.hpp>

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! Fewer rows than this still under every candidate, and the blind criterion does not measure the scene.
const int kBlindMinStillRows = 24;

/** @brief A frame as the blind criterion reads it: its linear luminance halved to at most
kFitFineWidth pixels wide, the noise, and each row's vertical variogram. */
struct BlindFrame
{
    Mat luminance;                 //!< CV_32FC1
    Ptr<CameraModel> camera;       //!< the camera of that resolution
    int halvings = 0;              //!< how often the frame was halved
    double noiseVariance = 0;      //!< Immerkær's estimate, squared
    int maxLag = 0;                //!< the variogram's largest lag, rows
    /** rows × (maxLag + 1): the mean over the columns of (Y(r + t) − Y(r))², −1 past the last row */
    Mat variogram;
};

//! Prepares `frame` (a camera frame, any type checkCameraFrame accepts).
BlindFrame prepareBlindFrame(const Mat& frame, const Ptr<CameraModel>& camera, int maxWidth);

/** @brief The blind criterion of each candidate: how far the variograms between the frame's moving
rows, as the candidate's blur predicts them from the scene's statistics, are from the measured ones
(mean squared log ratio). The scene's vertical variogram is measured on the rows every candidate
keeps still. All NaN when fewer than kBlindMinStillRows rows are still under every candidate (a
global-shutter frame in motion throughout, window II). */
std::vector<double> blindObjective(const Ptr<Plant>& plant, const BlindFrame& frame, const SwitchSchedule& schedule,
                                   const RollingShutter& shutter, const std::vector<MotionCorrection>& candidates);

//! The blind fit's outcome.
struct BlindResult
{
    MotionCorrection correction;  //!< the start, or the start with the time offset found
    bool observed = false;        //!< false: the frame has too few still rows to measure the scene on
    bool applied = false;         //!< the offset found replaced the start's
    double score = 0;             //!< the criterion at the correction kept
    double decisiveness = 0;      //!< (criterion at the start − at the best offset) / at the best offset
    int candidates = 0;           //!< blur models evaluated
};

/** @brief Scans the time offset within ±maxTimeOffset of `start` and keeps the best one when it
lowers the criterion by more than `decisive` (relative). */
BlindResult fitBlindTimeOffset(const Ptr<Plant>& plant, const BlindFrame& frame, const SwitchSchedule& schedule,
                               const RollingShutter& shutter, const MotionCorrection& start, double maxTimeOffset,
                               double decisive);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
