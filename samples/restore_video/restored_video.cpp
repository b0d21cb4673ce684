// SPDX-License-Identifier: Apache-2.0
#include "restored_video.hpp"

#include "atomic_file.hpp"

#include <opencv2/imgproc.hpp>

#include <cstdio>

namespace dynblur_samples {

using namespace cv;

RestoredVideo::RestoredVideo(const std::string& videoPath, const std::string& csvPath,
                             const std::vector<FrameRecord>& log, Size size, const std::string& csvHeader)
{
    const double fps = log.size() > 1 ? (log.size() - 1) / (log.back().frameStart - log.front().frameStart) : 30.0;
    const std::string video = temporaryFor(videoPath), csv = temporaryFor(csvPath);
    writer_.open(video, VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, size, true);
    if (!writer_.isOpened())
        CV_Error(Error::StsError, "--out: cannot write a video to '" + videoPath + "'");
    csv_.open(csv);
    if (!csv_)
        CV_Error(Error::StsError, "--csv: cannot write '" + csvPath + "'");
    csv_ << csvHeader;
}

RestoredVideo::~RestoredVideo()
{
    if (committed_)
        return;
    writer_.release();
    csv_.close();
    for (const std::string& temporary : temporaries_)
        std::remove(temporary.c_str());
}

void RestoredVideo::write(const Mat& frame)
{
    Mat color = frame;
    if (frame.channels() == 1)
        cvtColor(frame, color, COLOR_GRAY2BGR);
    writer_.write(color);
}

void RestoredVideo::close()
{
    writer_.release();
    csv_.close();
    if (!csv_)
        CV_Error(Error::StsError, "--csv: cannot write '" + csvPath() + "'");
}

std::string RestoredVideo::temporaryFor(const std::string& path)
{
    targets_.push_back(path);
    temporaries_.push_back(temporaryPathFor(path));
    return temporaries_.back();
}

void RestoredVideo::commit()
{
    for (size_t i = 0; i < targets_.size(); i++)
        renameIntoPlace(temporaries_[i], targets_[i]);
    committed_ = true;
}

}  // namespace dynblur_samples
