// SPDX-License-Identifier: Apache-2.0
#include "restored_video.hpp"

#include "atomic_file.hpp"

#include <opencv2/imgproc.hpp>

#include <cstdio>

namespace dynblur_samples {

using namespace cv;

const char* const kFrameCsvHeader =
    "frame,window,restored,time_offset_s,line_delay_scale,natural_freq_scale,damping_scale,consistency,reason,"
    "window_as_told,blur_px,window_true,psnr_recorded_db,psnr_restored_db,gain_db";

std::string frameCsvColumns(int frame, const std::string& window, bool restored, const dynblur::MotionCorrection& c,
                            const std::string& reason, const std::string& windowAsTold, double blurPx)
{
    std::string text = reason;
    for (char& ch : text)
        ch = ch == ',' || ch == '"' || ch == '\n' ? ';' : ch;
    return format("%d,%s,%d,%.9f,%.6f,%.6f,%.6f,%.4f,%s,%s,%.2f", frame, window.c_str(), int(restored), c.timeOffset,
                  c.lineDelayScale, c.naturalFreqScale, c.dampingScale, c.consistency, text.c_str(),
                  windowAsTold.c_str(), blurPx);
}

RestoredVideo::RestoredVideo(const std::string& videoPath, const std::string& csvPath, double fps, Size size,
                             const std::string& csvHeader)
{
    const std::string video = temporaryFor(videoPath), csv = temporaryFor(csvPath);
    // What this OpenCV's FFmpeg writes: MPEG-4 Part 2 in an .mp4, Motion JPEG in anything else (.avi).
    const bool mp4 = videoPath.size() > 4 && videoPath.compare(videoPath.size() - 4, 4, ".mp4") == 0;
    const int fourcc = mp4 ? VideoWriter::fourcc('m', 'p', '4', 'v') : VideoWriter::fourcc('M', 'J', 'P', 'G');
    writer_.open(video, fourcc, fps, size, true);
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
    written_++;
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

std::string RestoredVideo::keepWritten()
{
    writer_.release();
    csv_.close();
    for (size_t i = 2; i < temporaries_.size(); i++)
        std::remove(temporaries_[i].c_str());
    for (size_t i = 0; i < 2; i++)
        renameIntoPlace(temporaries_[i], targets_[i]);
    committed_ = true;
    return format("the %d frame(s) written before it are kept, closed: %s and %s", written_, videoPath().c_str(),
                  csvPath().c_str());
}

}  // namespace dynblur_samples
