// SPDX-License-Identifier: Apache-2.0
// Fuzzes the response-log CSV reader (samples/support/response_log.cpp) and what
// dynblur_identify_plant does with a log it accepted: the motion check, the schedule from the level
// column, and Plant::identify (on logs of at most kMaxIdentifySamples samples, to keep the fuzzer
// fast: identification is O(samples) per cost evaluation).
#include "fuzz_common.hpp"
#include "response_log.hpp"

#include <opencv2/dynblur.hpp>

#include <string>

using namespace cv::dynblur;

namespace {
const size_t kMaxIdentifySamples = 64;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    dynblur_samples::ResponseLog log;
    try
    {
        log = dynblur_samples::parseResponseLog(text, "fuzz.csv");
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
        return 0;
    }
    if (log.theta.size() != log.t.size() || (log.hasLevel() && log.level.size() != log.t.size()))
        std::abort();
    try
    {
        dynblur_samples::checkResponseLog(log, 8);
        if (!log.hasLevel())
            return 0;
        const SwitchSchedule schedule = dynblur_samples::scheduleFromLevels(log);
        if (log.t.size() > kMaxIdentifySamples)
            return 0;
        double rms = 0, delay = 0;
        const cv::Ptr<Plant> plant = Plant::identify(log.t, log.theta, schedule, true, &rms, &delay);
        if (!plant)
            std::abort();
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    return 0;
}
