// SPDX-License-Identifier: Apache-2.0
// A video as it comes off a phone or an action camera, with no frame log: read frame by frame, each
// frame with its time on the video's clock, from the container's timestamps (CAP_PROP_POS_MSEC) or,
// where the container has none, from the frame index at the stream's rate.
#ifndef DYNBLUR_SAMPLES_VIDEO_CLIP_HPP
#define DYNBLUR_SAMPLES_VIDEO_CLIP_HPP

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <opencv2/videoio/registry.hpp>

#include <string>

namespace dynblur_samples {

//! Where a video's frame times come from.
enum class FrameClock
{
    Timestamps,  //!< the container's timestamps
    FrameIndex   //!< frame k at k / the stream's rate
};

/** @brief Opens a video file, or an image sequence (a name holding '%'), for reading. A file is read
through FFmpeg where this OpenCV has it: its timestamps are the ones the clock trusts, and no other
backend is tried on a file FFmpeg refuses (GStreamer's device probing leaks inside libusb). Throws
cv::Exception naming `option` and `path` when the file is missing or no backend opens it. */
void openVideo(cv::VideoCapture& capture, const std::string& path, const std::string& option);

/** @brief The clock of a video from the container's first two timestamps (milliseconds, as
CAP_PROP_POS_MSEC reports them after each read) and its stream rate (CAP_PROP_FPS): its timestamps
when the second follows the first, else the frame index at `fps`. Throws cv::Exception naming
`option` and `path` when neither is usable (no timestamps and no rate in (0, 1000]). */
FrameClock chooseFrameClock(double firstMsec, double secondMsec, double fps, const std::string& option,
                            const std::string& path);

/** @brief A video read in order with each frame's time. Opening reads the first two frames to choose
the clock (chooseFrameClock). An image sequence (a name holding '%') has no time of its own and is
refused, as are a missing file, one no backend opens and a video with no frame. */
class VideoClip
{
public:
    /** @param path the video. @param option the option that named it, for messages ("--video"). */
    void open(const std::string& path, const std::string& option);

    /** The next frame and its time, seconds on the video's clock (the first frame's is its timestamp,
    usually 0); false after the last frame. Throws cv::Exception naming the option and the frame when
    a timestamp does not follow the previous one. */
    bool read(cv::Mat& image, double& seconds);

    //! The stream's rate, frames per second (CAP_PROP_FPS); NaN when the container does not say.
    double fps() const { return fps_; }
    //! One over the stream's rate, else the step between the first two frames' times; NaN for one frame.
    double framePeriod() const;
    FrameClock clock() const { return clock_; }
    /** The turn a player applies to show the video, degrees in {0, 90, 180, 270} (its rotation
    metadata; a phone's portrait clip). The frames are read as stored, unturned: their rows are the
    sensor's rows, in the order the rolling shutter reads them. */
    int storedTurnDegrees() const { return storedTurnDegrees_; }
    //! How the times were found: "the container's timestamps" or "the frame index at 29.97 fps",
    //! and the turn the frames are not given, if any.
    std::string clockText() const;
    //! The frames read so far.
    int framesRead() const { return next_; }
    cv::Size frameSize() const { return size_; }
    const std::string& path() const { return path_; }

private:
    cv::VideoCapture capture_;
    std::string path_, option_;
    double fps_ = 0;
    int storedTurnDegrees_ = 0;
    FrameClock clock_ = FrameClock::Timestamps;
    cv::Size size_;
    // The two frames read ahead to choose the clock, and their times.
    cv::Mat ahead_[2];
    double aheadSeconds_[2] = {0, 0};
    int aheadCount_ = 0, next_ = 0;
    double lastSeconds_ = 0;
};

}  // namespace dynblur_samples

#endif
