// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "pipeline/neighbour_check.hpp"
#include "refine/track_fit.hpp"

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

namespace {
// The neighbour and the frame are measured at this width, pixels: phase correlation's precision there
// is a fraction of a pixel, far below the errors of a wrong log.
const int kAnalysisWidth = 640;
}  // namespace

NeighbourCheck::NeighbourCheck(const Ptr<CameraModel>& camera) : camera_(camera), meter_(camera, kAnalysisWidth) {}

void NeighbourCheck::set(const Mat& frame, const RollingShutter& shutter)
{
    present_ = !frame.empty();
    neighbour_ = present_ ? meter_.reduce(frame) : Mat();
    shutter_ = shutter;
}

NeighbourAgreement NeighbourCheck::measure(const Mat& frame, const RollingShutter& shutter,
                                           const Ptr<CameraMotion>& motion, const MotionCorrection& c) const
{
    // Where the motion carries each patch's centre: the patch is looked for there, and must be found.
    std::vector<TrackPair> pairs;
    for (const Point2d& centre : meter_.patchCentres())
    {
        TrackPair pair;
        pair.frameA = 0, pair.frameB = 1;
        pair.a = pair.b = Point2f(centre);
        pairs.push_back(pair);
    }
    std::vector<ClipFrame> frames(2);
    for (size_t i = 0; i < 2; i++)
    {
        const RollingShutter& s = i == 0 ? shutter_ : shutter;
        frames[i].frameStart = s.frameStart, frames[i].exposure = s.exposure, frames[i].lineDelay = s.lineDelay;
        frames[i].rows = s.rows;
    }
    TrackResiduals motionOf(motion, camera_, pairs, frames);
    const std::vector<Point2d> carried = motionOf.carried(c);
    std::vector<Point2d> expected;
    for (size_t k = 0; k < carried.size(); k++)
        expected.push_back(std::isnan(carried[k].x) ? Point2d(1e9, 1e9) : carried[k] - Point2d(pairs[k].a));
    /* The patches the frames' own correlation finds (texture enough) are the ones judged: found where
       the motion puts them, their residual shift; not found there, an error without bound. */
    const Mat reduced = meter_.reduce(frame);
    std::vector<double> errors(carried.size(), -1.0);
    for (const PatchShift& patch : meter_.shifts(neighbour_, reduced))
        errors[size_t(patch.index)] = std::numeric_limits<double>::infinity();
    for (const PatchShift& patch : meter_.shifts(neighbour_, reduced, expected))
        errors[size_t(patch.index)] = norm(patch.shift - expected[size_t(patch.index)]);
    NeighbourAgreement agreement;
    for (size_t k = 0; k < errors.size(); k++)
        if (errors[k] >= 0)
            agreement.errorPx.push_back(errors[k]), agreement.shiftPx.push_back(norm(expected[k]));
    return agreement;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
