// SPDX-License-Identifier: Apache-2.0
#include "video_clip.hpp"

#include <cmath>
#include <fstream>

namespace dynblur_samples {

using namespace cv;

FrameClock chooseFrameClock(double firstMsec, double secondMsec, double fps, const std::string& option,
                            const std::string& path)
{
    if (std::isfinite(firstMsec) && std::isfinite(secondMsec) && secondMsec > firstMsec)
        return FrameClock::Timestamps;
    if (std::isfinite(fps) && fps > 0 && fps <= 1000)
        return FrameClock::FrameIndex;
    CV_Error(Error::StsBadArg,
             format("%s: '%s' has no frame timestamps and no frame rate (its first two frames are stamped %g and %g "
                    "ms, its rate is %g fps): give the frames' times in a frame log, --frames FRAMES.csv "
                    "(docs/recording-format.md)",
                    option.c_str(), path.c_str(), firstMsec, secondMsec, fps));
}

void openVideo(VideoCapture& capture, const std::string& path, const std::string& option)
{
    if (path.find('%') != std::string::npos)
    {
        if (!capture.open(path, CAP_IMAGES))
            CV_Error(Error::StsError, option + ": no image of the sequence '" + path + "' can be read");
        return;
    }
    // A missing file is named here: VideoCapture would try every backend on it.
    if (!std::ifstream(path).good())
        CV_Error(Error::StsError, option + ": '" + path + "' does not exist");
    const int backend = videoio_registry::hasBackend(CAP_FFMPEG) ? CAP_FFMPEG : CAP_ANY;
    if (!capture.open(path, backend))
        CV_Error(Error::StsError, option + ": cannot open '" + path + "' (not a video this OpenCV reads)");
    // A phone's portrait clip is stored sideways with a rotation in its metadata. Turned upright, its
    // rows would no longer be the sensor's rows, which the rolling shutter reads one after another.
    capture.set(CAP_PROP_ORIENTATION_AUTO, 0);
}

void VideoClip::open(const std::string& path, const std::string& option)
{
    path_ = path, option_ = option;
    if (path.find('%') != std::string::npos)
        CV_Error(Error::StsBadArg, option + ": '" + path + "' is an image sequence, which has no frame timestamps: "
                                   "give the frames' times in a frame log, --frames FRAMES.csv "
                                   "(docs/recording-format.md)");
    openVideo(capture_, path, option);
    fps_ = capture_.get(CAP_PROP_FPS);
    const double rotation = capture_.get(CAP_PROP_ORIENTATION_META);
    storedTurnDegrees_ = std::isfinite(rotation) ? (int(std::lround(rotation)) % 360 + 360) % 360 : 0;
    if (!(fps_ > 0 && fps_ <= 1000))
        fps_ = NAN;
    double msec[2] = {NAN, NAN};
    for (aheadCount_ = 0; aheadCount_ < 2 && capture_.read(ahead_[aheadCount_]); aheadCount_++)
        msec[aheadCount_] = capture_.get(CAP_PROP_POS_MSEC);
    if (aheadCount_ == 0)
        CV_Error(Error::StsError, option + ": '" + path + "' holds no frame that can be decoded");
    size_ = ahead_[0].size();
    // A single frame has no time step to judge by: its timestamp is its time.
    clock_ = aheadCount_ == 1 ? FrameClock::Timestamps : chooseFrameClock(msec[0], msec[1], fps_, option, path);
    for (int k = 0; k < aheadCount_; k++)
        aheadSeconds_[k] = clock_ == FrameClock::Timestamps ? msec[k] * 1e-3 : k / fps_;
}

bool VideoClip::read(Mat& image, double& seconds)
{
    if (next_ < aheadCount_)
    {
        image = ahead_[next_];
        ahead_[next_] = Mat();
        seconds = aheadSeconds_[next_];
    }
    else
    {
        Mat frame;  // a fresh buffer: the caller may still hold the previous frame
        if (!capture_.read(frame))
            return false;
        image = frame;
        seconds = clock_ == FrameClock::Timestamps ? capture_.get(CAP_PROP_POS_MSEC) * 1e-3 : next_ / fps_;
        if (!(seconds > lastSeconds_))
            CV_Error(Error::StsBadArg, format("%s: '%s': frame %d is stamped %.6f s, not after frame %d's %.6f s (a "
                                              "damaged container? give the frames' times with --frames FRAMES.csv)",
                                              option_.c_str(), path_.c_str(), next_, seconds, next_ - 1,
                                              lastSeconds_));
    }
    lastSeconds_ = seconds;
    next_++;
    return true;
}

double VideoClip::framePeriod() const
{
    if (std::isfinite(fps_))
        return 1 / fps_;
    return aheadCount_ == 2 ? aheadSeconds_[1] - aheadSeconds_[0] : NAN;
}

std::string VideoClip::clockText() const
{
    std::string text = clock_ == FrameClock::Timestamps ? std::string("the container's timestamps")
                                                        : format("the frame index at the stream's %.6g fps", fps_);
    if (storedTurnDegrees_ != 0)
        text += format(" (the video is shown turned %d deg by its metadata: read and written as stored, its rows the "
                       "sensor's)", storedTurnDegrees_);
    return text;
}

}  // namespace dynblur_samples
