// SPDX-License-Identifier: Apache-2.0
#include "reference_pairing.hpp"

#include <algorithm>

namespace dynblur_samples {

ReferencePairing::ReferencePairing(const CommandedMotion& motion, const cv::Ptr<cv::dynblur::CameraModel>& camera,
                                   const CommandLog& commands, const cv::dynblur::MotionCorrection& correction,
                                   double maxOffset, size_t maxPending)
    : motion_(motion.corrected(correction)), camera_(camera), commands_(commands),
      correction_(correction), maxOffset_(maxOffset), maxPending_(maxPending)
{
}

bool ReferencePairing::isStill(const FrameRecord& record, int rows) const
{
    const cv::dynblur::RollingShutter corrected =
        correction_.correctShutter(cv::dynblur::RollingShutter(record.frameStart, record.exposure, record.lineDelay, rows));
    return stillUnder(corrected, schedulesFor(corrected));
}

std::vector<cv::dynblur::SwitchSchedule> ReferencePairing::schedulesFor(const cv::dynblur::RollingShutter& corrected) const
{
    const cv::Vec2d readout = corrected.readoutInterval();
    const double restSince = motion_.isMount() ? lastStillStart_ : std::numeric_limits<double>::quiet_NaN();
    return commands_.schedulesAround(readout[0] - maxOffset_, readout[1] + maxOffset_, restSince);
}

bool ReferencePairing::stillUnder(const cv::dynblur::RollingShutter& corrected,
                                  const std::vector<cv::dynblur::SwitchSchedule>& schedules) const
{
    using namespace cv::dynblur;
    const double pixelAngle = 0.25 / camera_->getFx();
    for (double shift : {-maxOffset_, 0.0, maxOffset_})
    {
        RollingShutter shifted = corrected;
        shifted.frameStart += shift;
        if (motion_.classify(schedules, shifted, pixelAngle, pixelAngle / corrected.exposure) != EXPOSURE_IV)
            return false;
    }
    return true;
}

std::vector<ReferencePairing::Item> ReferencePairing::push(const FrameRecord& record, const cv::Mat& image)
{
    using namespace cv::dynblur;
    Item item;
    item.record = record;
    item.image = image;
    item.shutter = RollingShutter(record.frameStart, record.exposure, record.lineDelay, image.rows);
    const RollingShutter corrected = correction_.correctShutter(item.shutter);
    const cv::Vec2d readout = corrected.readoutInterval();
    item.schedules = schedulesFor(corrected);
    item.window = motion_.classify(item.schedules, corrected);
    item.still = stillUnder(corrected, item.schedules);

    std::vector<Item> ready;
    if (item.still)
    {
        const double angle = motion_.plant()->restingAngle(item.schedules[0].levelAt(readout[0]));
        release(ready, image, angle, readout[0]);
        lastStill_ = image;
        lastStillAngle_ = angle;
        lastStillStart_ = readout[0];
        ready.push_back(item);
    }
    else if (item.window == EXPOSURE_I && waiting_.empty())
    {
        item.reference = item.before = lastStill_;
        item.referenceAngle = item.angleBefore = lastStillAngle_;
        ready.push_back(item);
    }
    else
    {
        waiting_.push_back(item);
        if (waiting_.size() > maxPending_)
            release(ready, cv::Mat(), 0, 0);
    }
    return ready;
}

std::vector<ReferencePairing::Item> ReferencePairing::finish()
{
    std::vector<Item> ready;
    release(ready, cv::Mat(), 0, 0);
    return ready;
}

/* Hands out every waiting frame: a frame that starts at rest with the still frame before it, one that
   ends at rest with `reference` (the still frame starting at `stillStart`) when no switch comes
   between, else with the still frame before it. */
void ReferencePairing::release(std::vector<Item>& ready, const cv::Mat& reference, double angle, double stillStart)
{
    for (Item& w : waiting_)
    {
        const double end = correction_.correctShutter(w.shutter).readoutInterval()[1];
        const auto next = std::upper_bound(commands_.times.begin(), commands_.times.end(), end + maxOffset_);
        const bool after = !reference.empty() && w.window != cv::dynblur::EXPOSURE_I &&
                           (next == commands_.times.end() || *next >= stillStart - maxOffset_);
        w.reference = after ? reference : lastStill_;
        w.referenceAngle = after ? angle : lastStillAngle_;
        w.before = lastStill_, w.angleBefore = lastStillAngle_;
        if (!reference.empty() && (next == commands_.times.end() || *next >= stillStart - maxOffset_))
            w.after = reference, w.angleAfter = angle;
        ready.push_back(w);
    }
    waiting_.clear();
}

}  // namespace dynblur_samples
