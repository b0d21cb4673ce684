// SPDX-License-Identifier: Apache-2.0
#include "frame_restorer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

void ProgressLine::show(const char* doing) const
{
    const double perMoving = movingDone_ ? clock_.getTimeSec() / movingDone_ : NAN;
    const std::string eta =
        std::isnan(perMoving) ? "after the first moving frame" : format("%.0f s", movingLeft_ * perMoving);
    std::printf("\r%d of %zu frames written%s, %d moving frame(s) left, ETA %s, %zu held for the still after "
                "their move   ",
                written_, frames_, doing, movingLeft_, eta.c_str(), pairing_.pending());
    std::fflush(stdout);
}

void ProgressLine::restoring()
{
    show(": restoring");
    clock_.start();
}

void ProgressLine::restored()
{
    clock_.stop();
    movingDone_++;
    movingLeft_ = std::max(0, movingLeft_ - 1);
}

FrameRestorer::FrameRestorer(const Ptr<DynamicDeblurrer>& deblurrer, const CommandedMotion& motion,
                             const Ptr<CameraModel>& camera, const MotionCorrection& calibration,
                             bool unrefinedUnchanged)
    : deblurrer_(deblurrer), motion_(motion.corrected(calibration)), correctedPlant_(calibration.correctPlant(motion.plant())),
      focalPx_(std::max(camera->getFx(), camera->getFy())), calibration_(calibration),
      unrefinedUnchanged_(unrefinedUnchanged)
{
}

RestoredFrame FrameRestorer::restore(const ReferencePairing::Item& item, ProgressLine& progress)
{
    RestoredFrame r;
    r.image = item.image;
    r.window = item.window;
    if (item.still)
    {
        observeStill(item);
        return r;
    }
    /* Each frame is restored to the view the camera had at its middle row's mid-exposure (the video
       does not jump to where a move will end, and the frame saw most of that view), on the calibrated
       clock and plant. */
    if (!motion_.isMount())
    {
        const Vec2d middle = calibration_.correctShutter(item.shutter).rowInterval(item.shutter.rows / 2);
        Mat t(1, 1, CV_64F, Scalar((middle[0] + middle[1]) / 2)), theta;
        correctedPlant_->response(item.schedules[0], t, theta);
        r.thetaRef = theta.at<double>(0);
    }
    // A frame that ends its move at rest is refined against the still after it.
    r.noStillAfter = item.after.empty() && item.window == EXPOSURE_III;
    if (r.noStillAfter && unrefinedUnchanged_)
    {
        r.correction.applied = false;
        r.correction.reason = "no still after the move: not refined; written as recorded (--no-still-after unchanged)";
    }
    else
    {
        useReferences(item, r.noStillAfter);
        useNoise();
        progress.restoring();
        if (motion_.isMount())
            deblurMount(item, r);
        else
            deblurrer_->deblur(item.image, item.schedules[0], item.shutter, restored_, r.thetaRef);
        progress.restored();
        r.correction = deblurrer_->getLastCorrection();
        r.window = deblurrer_->getLastExposureWindow();
        if (r.noStillAfter)
            r.correction.reason = "no still after the move: not refined; restored as told (--no-still-after as-told)";
        r.image = restored_;
    }
    r.blurPx = motion_.largestRowTurn(item.schedules, calibration_.correctShutter(item.shutter)) * focalPx_;
    return r;
}

void FrameRestorer::deblurMount(const ReferencePairing::Item& item, RestoredFrame& r)
{
    // tRef is a camera time: the calibration's and the refinement's clock offsets move it with the frame.
    const Vec2d middle = item.shutter.rowInterval(item.shutter.rows / 2);
    const double tRef = (middle[0] + middle[1]) / 2;
    const Ptr<CameraMotion> told = motion_.motion(item.schedules);
    deblurrer_->deblur(item.image, told, item.shutter, restored_, tRef);
    const MotionCorrection used = deblurrer_->getLastCorrection().applied ? deblurrer_->getLastCorrection() : calibration_;
    r.orientation = used.correctMotion(told)->orientation(tRef + used.timeOffset);
}

void FrameRestorer::useReferences(const ReferencePairing::Item& item, bool noStillAfter)
{
    if (noStillAfter || (item.before.empty() && item.after.empty()))
        deblurrer_->clearReferenceFrame(), lastBefore_ = lastAfter_ = Mat();
    else if (item.before.data != lastBefore_.data || item.after.data != lastAfter_.data)
        motion_.isMount() ? deblurrer_->setReferenceFrames(item.before, item.after)  // every axis at rest
                          : deblurrer_->setReferenceFrames(item.before, item.after, item.angleBefore, item.angleAfter);
    if (!noStillAfter)
        lastBefore_ = item.before, lastAfter_ = item.after;
}

void FrameRestorer::useNoise()
{
    if (!noisePending_)
        return;
    noisePending_ = false;
    try
    {
        deblurrer_->setNoiseFrames(noiseA_, noiseB_);
    }
    catch (const cv::Exception& e)
    {
        std::fprintf(stderr, "\nnote: the noise stays as measured before (or Immerkaer's estimate on each still): %s\n",
                     e.err.c_str());
    }
}

void FrameRestorer::observeStill(const ReferencePairing::Item& item)
{
    /* The last two consecutive still frames at one resting level: the noise refinement weighs its
       residuals by is measured from their difference (setNoiseFrames), compression included. */
    std::vector<int> levels;
    for (const SwitchSchedule& axis : item.schedules)
        levels.push_back(axis.levelAt(item.shutter.frameStart));
    if (item.record.frame == lastStillFrame_ + 1 && levels == lastStillLevels_)
    {
        noiseA_ = noiseB_, noiseB_ = item.image;
        noisePending_ = !noiseA_.empty();
    }
    else
        noiseA_ = Mat(), noiseB_ = item.image;
    lastStillFrame_ = item.record.frame, lastStillLevels_ = levels;
}

}  // namespace dynblur_samples
