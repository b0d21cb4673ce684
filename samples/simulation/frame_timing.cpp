// SPDX-License-Identifier: Apache-2.0
#include "frame_timing.hpp"

namespace dynblur_samples {

const char* exposureWindowName(int window)
{
    static const char* names[] = {"?", "I", "II", "III", "IV"};
    return names[window >= 1 && window <= 4 ? window : 0];
}

bool frameStartInWindow(const cv::Ptr<cv::dynblur::Plant>& plant, const cv::dynblur::SwitchSchedule& schedule,
                        cv::dynblur::RollingShutter shutter, int window, double& frameStart, double step,
                        double horizon)
{
    const double readout = shutter.readoutInterval()[1] - shutter.frameStart;
    const double first = schedule.times.empty() ? 0.0 : schedule.times.front();
    double runStart = 0, runEnd = 0;
    bool inRun = false;
    for (double start = first - readout - step; start < first + horizon; start += step)
    {
        shutter.frameStart = start;
        const bool matches = cv::dynblur::classifyExposure(plant, schedule, shutter) == window;
        if (matches && !inRun)
            runStart = start, inRun = true;
        if (inRun && !matches)
            break;
        if (inRun)
            runEnd = start;
    }
    if (!inRun)
        return false;
    frameStart = 0.5 * (runStart + runEnd);
    return true;
}

}  // namespace dynblur_samples
