// SPDX-License-Identifier: Apache-2.0
// Fuzzes the recording's two CSV readers (samples/support/recording.cpp): the frame log and the
// command log (one level column, or one per axis of a mount), and what the timing calibration and
// the video restorer do with a command log they accepted (each axis's schedule around an instant). The
// input is read as both logs.
#include "fuzz_common.hpp"
#include "recording.hpp"

#include <cmath>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    try
    {
        const std::vector<dynblur_samples::FrameRecord> frames =
            dynblur_samples::parseFrameLog(text, "fuzz.csv", 0.008, NAN);
        for (size_t i = 1; i < frames.size(); i++)
            if (frames[i].frame <= frames[i - 1].frame || !(frames[i].frameStart > frames[i - 1].frameStart))
                std::abort();
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    try
    {
        const dynblur_samples::CommandLog log = dynblur_samples::parseCommandLog(text, "fuzz.csv");
        if (log.times.empty() || log.axisCount() < 1)
            std::abort();
        for (const std::vector<int>& axisLevels : log.levels)  // one row per axis, each as long as the times
            if (axisLevels.size() != log.times.size())
                std::abort();
        for (double t : {log.times.front() - 1.0, log.times.front(), log.times.back(), log.times.back() + 5.0})
            for (int axis = 0; axis < log.axisCount(); axis++)
            {
                // A schedule the library accepts, or a refusal naming why; from the log's start and
                // from a still at the first command.
                log.scheduleAround(t, t + 0.05, axis).validate();
                log.scheduleAround(t, t + 0.05, axis, log.times.front()).validate();
            }
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    return 0;
}
