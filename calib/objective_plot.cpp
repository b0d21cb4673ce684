// SPDX-License-Identifier: Apache-2.0
#include "objective_plot.hpp"

#include "atomic_file.hpp"  // samples/support
#include "plot.hpp"

#include <algorithm>
#include <cstdio>
#include <vector>

void writeObjectivePlot(const cv::dynblur::TimingCalibration& t, const std::string& title, const std::string& curve,
                        const std::string& path)
{
    std::vector<double> ms;
    for (double offset : t.scanTimeOffsets)
        ms.push_back(offset * 1e3);
    dynblur_plot::Figure figure(900, title);
    figure.addPanel("", "mean squared residual (noise^2)")
        .line(ms, t.scanObjective, curve)
        .hLine(*std::min_element(t.scanObjective.begin(), t.scanObjective.end()));
    figure.xLabel("clock offset (ms)");
    const std::string temporary = dynblur_samples::temporaryPathFor(path);
    if (!figure.save(temporary))
        CV_Error(cv::Error::StsError, "cannot write '" + path + "'");
    dynblur_samples::renameIntoPlace(temporary, path);
    std::printf("wrote %s\n", path.c_str());
}
