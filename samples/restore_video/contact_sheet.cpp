// SPDX-License-Identifier: Apache-2.0
#include "contact_sheet.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

namespace {

//! One cell: the image 480 px wide under two lines of text.
Mat cell(const Mat& image, const std::string& line1, const std::string& line2)
{
    Mat small, color;
    resize(image, small, Size(480, image.rows * 480 / image.cols), 0, 0, INTER_AREA);
    color = small;
    if (small.channels() == 1)
        cvtColor(small, color, COLOR_GRAY2BGR);
    rectangle(color, Rect(0, 0, color.cols, 38), Scalar(0, 0, 0), FILLED);
    putText(color, line1, Point(5, 15), FONT_HERSHEY_SIMPLEX, 0.45, Scalar(255, 255, 255), 1, LINE_AA);
    putText(color, line2, Point(5, 32), FONT_HERSHEY_SIMPLEX, 0.45, Scalar(255, 255, 255), 1, LINE_AA);
    return color;
}

}  // namespace

void ContactSheet::offer(const Mat& recorded, const Mat& restored, int frame, const std::string& window,
                         double blurPx, const MotionCorrection& c, const std::string& gain)
{
    // A measured motion has no plant: its wn stays 1 and goes unsaid.
    const std::string correction =
        format("clock %+.2f ms, line delay x%.3f", c.timeOffset * 1e3, c.lineDelayScale) +
        (c.naturalFreqScale != 1 ? format(", wn x%.3f", c.naturalFreqScale) : std::string());
    // Without a still frame (a measured motion as calibrated) there is no consistency to show.
    const std::string consistency = std::isnan(c.consistency) ? "" : format(", consistency %.2f", c.consistency);
    Row row{frame, blurPx, Mat()};
    hconcat(cell(recorded, format("frame %d: as recorded", frame),
                 format("window %s, blur %.0f px", window.c_str(), blurPx)),
            cell(restored,
                 (c.applied ? "RESTORED" : "REFUSED (written as recorded)") + consistency +
                     (c.applied ? gain : std::string()),
                 correction),
            row.image);
    kept_.push_back(row);
    // Keep the most blurred ones.
    if (kept_.size() > rows_)
        kept_.erase(std::min_element(kept_.begin(), kept_.end(),
                                          [](const Row& a, const Row& b) { return a.blurPx < b.blurPx; }));
}

Mat ContactSheet::render() const
{
    std::vector<Row> rows = kept_;
    std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.frame < b.frame; });
    std::vector<Mat> images;
    for (const Row& row : rows)
        images.push_back(row.image);
    Mat sheet;
    vconcat(images, sheet);
    return sheet;
}

}  // namespace dynblur_samples
