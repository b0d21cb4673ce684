// SPDX-License-Identifier: Apache-2.0
// A recording's frames paired with the still frames that saw what their moving rows see, streamed:
// what dynblur_restore_video and dynblur_calibrate_timing refine each moving frame against.
#ifndef DYNBLUR_SAMPLES_REFERENCE_PAIRING_HPP
#define DYNBLUR_SAMPLES_REFERENCE_PAIRING_HPP

#include "commanded_motion.hpp"
#include "recording.hpp"

#include <opencv2/dynblur.hpp>

#include <limits>
#include <vector>

namespace dynblur_samples {

/** @brief Streams a recording's frames and pairs each frame taken during a move with the still frame
that saw what its moving rows see: the last still frame before it when the frame starts at rest
(window I), the first still frame after it otherwise, unless another switch comes between (then,
and when more than `maxPending` frames wait, the last still frame before it). Frames come back in
their order, as soon as their reference is known: memory holds at most `maxPending` frames. Each
moving frame also carries the stills on both sides of its move (`before`, `after`) for
DynamicDeblurrer::setReferenceFrames, which chooses per frame: a frame that waits for the still after
its move comes back when that still arrives (the latency of a stream: the rest of the move and one
frame), or at finish() without one.

"Still" is what a restoration cannot tell from still: the image moves by less than a quarter pixel
(and by less than that during the exposure), with the clock off by as much as `maxOffset` either
way, so a plant's slow residual vibration is not a move. */
class ReferencePairing
{
public:
    struct Item
    {
        FrameRecord record;
        cv::Mat image;
        std::vector<cv::dynblur::SwitchSchedule> schedules;  //!< the commands around the frame, one per axis
        cv::dynblur::RollingShutter shutter;   //!< as the frame log reports it
        int window = 0;                        //!< exposure window under the model as given
        bool still = false;
        cv::Mat reference;                     //!< the moving frame's still frame (empty: none known)
        double referenceAngle = 0;             //!< its angle, radians (one axis; a mount's stills are at rest)
        cv::Mat before, after;                 //!< the stills before and after its move (empty: none)
        double angleBefore = 0, angleAfter = 0;  //!< their angles, radians
    };

    /** @param motion the nominal motion the commands drive (one plant or a mount). @param camera the
    camera. @param commands the command log, one level column per axis of `motion`.
    @param correction the model's correction (a calibration; MotionCorrection() for none).
    @param maxOffset how far off the clock may be, seconds. @param maxPending frames held at most. */
    ReferencePairing(const CommandedMotion& motion, const cv::Ptr<cv::dynblur::CameraModel>& camera,
                     const CommandLog& commands, const cv::dynblur::MotionCorrection& correction, double maxOffset,
                     size_t maxPending = 32);

    //! Takes the next frame; returns the frames whose reference is now known, in order.
    std::vector<Item> push(const FrameRecord& record, const cv::Mat& image);
    //! At the end of the recording: the frames still waiting (with the last still frame before them).
    std::vector<Item> finish();
    //! Whether push() calls the frame still, read out by `rows` rows (what a progress count needs ahead).
    bool isStill(const FrameRecord& record, int rows) const;
    //! Frames held until the still after their move arrives.
    size_t pending() const { return waiting_.size(); }

private:
    void release(std::vector<Item>& ready, const cv::Mat& reference, double angle, double stillStart);
    /** The commands around a frame read out as `corrected` (the calibrated shutter), ±maxOffset; a mount's
    start from the last still frame (each axis's initial rest is that still's: setReferenceFrames' `before`). */
    std::vector<cv::dynblur::SwitchSchedule> schedulesFor(const cv::dynblur::RollingShutter& corrected) const;
    //! At rest under `schedules` whether the clock is early, right or late by maxOffset.
    bool stillUnder(const cv::dynblur::RollingShutter& corrected,
                    const std::vector<cv::dynblur::SwitchSchedule>& schedules) const;

    CommandedMotion motion_;  //!< as corrected
    cv::Ptr<cv::dynblur::CameraModel> camera_;
    const CommandLog& commands_;
    cv::dynblur::MotionCorrection correction_;
    double maxOffset_;
    size_t maxPending_;
    std::vector<Item> waiting_;
    cv::Mat lastStill_;
    double lastStillAngle_ = 0;
    double lastStillStart_ = std::numeric_limits<double>::quiet_NaN();  //!< its readout start, corrected clock
};

}  // namespace dynblur_samples

#endif
