// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video's contact sheet (OUT_frames.png): the most blurred moving frames, each as
// recorded beside its restoration, labelled with its window, blur, correction and outcome.
#ifndef DYNBLUR_SAMPLES_CONTACT_SHEET_HPP
#define DYNBLUR_SAMPLES_CONTACT_SHEET_HPP

#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {

class ContactSheet
{
public:
    //! Keeps the `rows` most blurred frames offered.
    explicit ContactSheet(size_t rows) : rows_(rows) {}

    /** Offers a moving frame: `window` its label ("II", or "II (as told III)"), `blurPx` the largest
    image motion during one row's exposure, `gain` the truth's ", +1.23 dB" or "". */
    void offer(const cv::Mat& recorded, const cv::Mat& restored, int frame, const std::string& window, double blurPx,
               const cv::dynblur::MotionCorrection& c, const std::string& gain);
    bool empty() const { return kept_.empty(); }
    //! The kept rows in frame order, one above the other.
    cv::Mat render() const;

private:
    struct Row
    {
        int frame = 0;
        double blurPx = 0;
        cv::Mat image;
    };
    size_t rows_;
    std::vector<Row> kept_;
};

}  // namespace dynblur_samples

#endif
