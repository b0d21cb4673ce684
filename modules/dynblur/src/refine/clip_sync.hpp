// SPDX-License-Identifier: Apache-2.0
// Private: a clip's coarse synchronisation with its gyro log, from the image's turn between frames.
#ifndef OPENCV_DYNBLUR_REFINE_CLIP_SYNC_HPP
#define OPENCV_DYNBLUR_REFINE_CLIP_SYNC_HPP

#include "refine/frame_motion.hpp"
#include "refine/rate_integral.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! A clip's frame as the video reports it, seconds on the video's clock.
struct ClipFrame
{
    double frameStart = 0, exposure = 0, lineDelay = 0;
    int rows = 0;
};

//! Where the log's turns match the image's best.
struct ClipSync
{
    double timeOffset = 0;       //!< the log's clock minus the video's, seconds
    double lineDelayScale = 1;   //!< × the frames' line delay
    Matx33d axes = Matx33d::eye();  //!< ω_camera = axes · ω_log: a signed permutation (det −1 possible)
    double rateScale = 1;        //!< the image's turn over the log's, least squares
    double explained = 0;        //!< the share of the image's squared turn the log explains, [0, 1]
    double explainedAsTold = 0;  //!< the same with the log's axes as read (identity), at the same offset and readout
    double runnerUp = 0;         //!< the best share at offsets more than kDistinctOffset from the result
    double covered = 0;          //!< the share of the turns' weight the log covers at the result
    std::vector<double> scanOffsets, scanExplained;  //!< the offset scan at the told readout: seconds, share
};

//! Offsets this far from the best one, seconds, compete as another match (runnerUp).
const double kDistinctOffset = 0.1;

/** @brief The clock offset (scanned within ±maxTimeOffset in 1 ms steps, refined by a parabola), the
signed permutation of the log's axes and, when `scanReadout`, the line delay's scale (from 0.25 to 2,
at most one frame period of readout) under which the log's turns over each band's exposure
instants best match the image's (BandTurn), by the share of the image's squared turn they explain
with the scale that fits best. Offsets at which the log covers less than half of the turns' weight
are not considered. */
ClipSync synchronize(const RateIntegral& log, const std::vector<BandTurn>& turns, const std::vector<ClipFrame>& frames,
                     double maxTimeOffset, bool scanReadout);

//! The 48 signed permutation matrices, the identity first.
const std::vector<Matx33d>& signedPermutations();

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
