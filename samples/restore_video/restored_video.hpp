// SPDX-License-Identifier: Apache-2.0
// What dynblur_restore_video writes, written whole: the restored video and its per-frame CSV (and
// the contact sheet) go to temporary files beside their targets and are renamed into place only once
// the whole recording is done; a failure removes them.
#ifndef DYNBLUR_SAMPLES_RESTORED_VIDEO_HPP
#define DYNBLUR_SAMPLES_RESTORED_VIDEO_HPP

#include "recording.hpp"

#include <opencv2/videoio.hpp>

#include <fstream>
#include <string>
#include <vector>

namespace dynblur_samples {

class RestoredVideo
{
public:
    /** Opens the video (MJPG at the frame log's rate, color) and the CSV with its header line; throws
    cv::Exception naming --out or --csv when either cannot be written. */
    RestoredVideo(const std::string& videoPath, const std::string& csvPath, const std::vector<FrameRecord>& log,
                  cv::Size size, const std::string& csvHeader);
    //! Removes the temporary files unless commit() renamed them into place.
    ~RestoredVideo();
    RestoredVideo(const RestoredVideo&) = delete;
    RestoredVideo& operator=(const RestoredVideo&) = delete;

    //! Appends a frame (a gray one as color).
    void write(const cv::Mat& frame);
    std::ofstream& csv() { return csv_; }
    //! Closes both files; throws naming --csv when its writing failed.
    void close();
    //! A temporary name for another file written with the video (renamed into place by commit()).
    std::string temporaryFor(const std::string& path);
    //! Renames every file into place, the video first.
    void commit();

    const std::string& videoPath() const { return targets_[0]; }
    const std::string& csvPath() const { return targets_[1]; }

private:
    std::vector<std::string> targets_, temporaries_;
    cv::VideoWriter writer_;
    std::ofstream csv_;
    bool committed_ = false;
};

}  // namespace dynblur_samples

#endif
