// SPDX-License-Identifier: Apache-2.0
#include "objective_plot.hpp"

#include "atomic_file.hpp"  // samples/support
#include "plot.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

//! The offsets in ms and the objective, of the scanned offsets within `halfWidthMs` of `centreMs`.
void scanWithin(const cv::dynblur::TimingCalibration& t, double centreMs, double halfWidthMs, std::vector<double>& ms,
                std::vector<double>& objective)
{
    for (size_t i = 0; i < t.scanTimeOffsets.size(); i++)
        if (std::abs(t.scanTimeOffsets[i] * 1e3 - centreMs) <= halfWidthMs)
            ms.push_back(t.scanTimeOffsets[i] * 1e3), objective.push_back(t.scanObjective[i]);
}

//! Writes the figures one above the other, whole or not at all; prints the path.
void save(const std::vector<const dynblur_plot::Figure*>& figures, const std::string& path)
{
    std::vector<cv::Mat> images;
    for (const dynblur_plot::Figure* figure : figures)
        images.push_back(figure->render());
    cv::Mat image;
    cv::vconcat(images, image);
    const std::string temporary = dynblur_samples::temporaryPathFor(path);
    if (!cv::imwrite(temporary, image))
        CV_Error(cv::Error::StsError, "cannot write '" + path + "'");
    dynblur_samples::renameIntoPlace(temporary, path);
    std::printf("wrote %s\n", path.c_str());
}

}  // namespace

void writeObjectivePlot(const cv::dynblur::TimingCalibration& t, const std::string& title, const std::string& curve,
                        const std::string& path)
{
    std::vector<double> ms, objective;
    scanWithin(t, 0, INFINITY, ms, objective);
    dynblur_plot::Figure figure(900, title);
    figure.addPanel("", "mean squared residual (noise^2)")
        .line(ms, objective, curve)
        .hLine(*std::min_element(objective.begin(), objective.end()));
    figure.xLabel("clock offset (ms)");
    save({&figure}, path);
}

void writeOffsetScanPlot(const cv::dynblur::TimingCalibration& t, const std::string& title, const std::string& path)
{
    const double found = t.correction.timeOffset * 1e3;
    std::vector<double> ms, explained, nearMs, nearExplained;
    scanWithin(t, 0, INFINITY, ms, explained);
    scanWithin(t, found, 50, nearMs, nearExplained);
    // The whole window shows whether one offset stands out; the 100 ms around it, how sharply.
    dynblur_plot::Figure whole(900, title);
    whole.addPanel("the whole window searched", "share of the turn explained")
        .line(ms, explained, "the log at each clock offset")
        .yLimits(0, 1);
    whole.xLabel("clock offset (ms)");
    dynblur_plot::Figure near(900);
    near.addPanel(cv::format("within 50 ms of the offset found, %+.2f ms", found), "share of the turn explained")
        .line(nearMs, nearExplained, "the log at each clock offset")
        .hLine(t.explainedMotion, cv::format("at the offset found: %.0f %%", 100 * t.explainedMotion))
        .yLimits(0, 1);
    near.xLabel("clock offset (ms)");
    save({&whole, &near}, path);
}
