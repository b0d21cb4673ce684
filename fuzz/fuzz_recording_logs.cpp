// SPDX-License-Identifier: Apache-2.0
// Fuzzes the recording's two CSV readers (samples/support/recording.cpp): the frame log and the
// command log, and what the timing calibration and the video restorer do with a command log they
// accepted (the schedule around an instant). The input is read as both logs.
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
        if (log.times.empty() || log.times.size() != log.levels.size())
            std::abort();
        for (double t : {log.times.front() - 1.0, log.times.front(), log.times.back(), log.times.back() + 5.0})
        {
            const cv::dynblur::SwitchSchedule s = log.scheduleAround(t, t + 0.05);
            s.validate();  // a schedule the library accepts, or a refusal naming why
        }
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    return 0;
}
