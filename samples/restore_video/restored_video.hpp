// SPDX-License-Identifier: Apache-2.0
// What dynblur_restore_video writes: the restored video and its per-frame CSV (and the contact sheet)
// go to temporary files beside their targets and are renamed into place once the whole recording is
// done. A failure removes them, or, where the frames written so far are worth keeping (a long clip),
// keepWritten() closes and keeps the video and the CSV as far as they go.
#ifndef DYNBLUR_SAMPLES_RESTORED_VIDEO_HPP
#define DYNBLUR_SAMPLES_RESTORED_VIDEO_HPP

#include <opencv2/dynblur.hpp>
#include <opencv2/videoio.hpp>

#include <fstream>
#include <string>
#include <vector>

namespace dynblur_samples {

/* The per-frame CSV's columns, the same in every mode: the frame, its window under the motion it was
   restored with, whether it was restored, the correction, the consistency, the reason, the window under
   the model as told, the blur; then a rendered recording's truth (--truth). */
extern const char* const kFrameCsvHeader;

//! One CSV line up to blur_px (kFrameCsvHeader), without its line end; `reason` has its commas replaced.
std::string frameCsvColumns(int frame, const std::string& window, bool restored,
                            const cv::dynblur::MotionCorrection& c, const std::string& reason,
                            const std::string& windowAsTold, double blurPx);

class RestoredVideo
{
public:
    /** Opens the video (`fps` frames per second, color: mp4v when `videoPath` ends in .mp4, MJPG
    otherwise) and the CSV with its header line; throws cv::Exception naming --out or --csv when either
    cannot be written. */
    RestoredVideo(const std::string& videoPath, const std::string& csvPath, double fps, cv::Size size,
                  const std::string& csvHeader);
    //! Removes the temporary files unless commit() or keepWritten() renamed them into place.
    ~RestoredVideo();
    RestoredVideo(const RestoredVideo&) = delete;
    RestoredVideo& operator=(const RestoredVideo&) = delete;

    //! Appends a frame (a gray one as color).
    void write(const cv::Mat& frame);
    int framesWritten() const { return written_; }
    std::ofstream& csv() { return csv_; }
    //! Closes both files; throws naming --csv when its writing failed.
    void close();
    //! A temporary name for another file written with the video (renamed into place by commit()).
    std::string temporaryFor(const std::string& path);
    //! Renames every file into place, the video first.
    void commit();
    /** After a failure: closes the video and the CSV and renames them into place, as far as they were
    written; the other files are removed. Returns a sentence naming both and the frames they hold. */
    std::string keepWritten();

    const std::string& videoPath() const { return targets_[0]; }
    const std::string& csvPath() const { return targets_[1]; }

private:
    std::vector<std::string> targets_, temporaries_;
    cv::VideoWriter writer_;
    std::ofstream csv_;
    int written_ = 0;
    bool committed_ = false;
};

}  // namespace dynblur_samples

#endif
