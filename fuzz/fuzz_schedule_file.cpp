// SPDX-License-Identifier: Apache-2.0
// Fuzzes SwitchSchedule::load, the reader of schedule files (YAML/XML/JSON through FileStorage):
// dynblur_actuator_ctl --upload, dynblur_identify_plant --schedule and the demo's --schedule. A
// schedule that loads goes where those programs send it: the actuator driver's host-side check and
// encoding (nothing is sent: the bus is never connected) and the plant's prediction.
#include "fuzz_common.hpp"

#include <opencv2/dynblur.hpp>

#include <cmath>

using namespace cv::dynblur;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string& path = dynblur_fuzz::writeScratchFile(data, size, "_schedule.yml");
    SwitchSchedule schedule;
    try
    {
        schedule = SwitchSchedule::load(path);
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
        return 0;
    }
    if (schedule.times.empty() || schedule.times.size() != schedule.levels.size())
        std::abort();  // load() validates

    static const cv::Ptr<ActuatorDriver> driver =
        ActuatorDriver::create(ActuatorBus::create("tcp://127.0.0.1:1"), ActuatorLimits());
    try
    {
        driver->checkSchedule(schedule);
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    try
    {
        const std::vector<int> registers = encodeSchedule(schedule);
        for (int word : registers)
            if (word < 0 || word > 65535)
                std::abort();  // every register is a 16-bit word
        (void)busChecksum(registers);
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    try
    {
        static const cv::Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
        const double t0 = schedule.times.front(), t1 = schedule.times.back();
        std::vector<double> t = {t0 - 0.01, t0, 0.5 * (t0 + t1), t1, t1 + 0.05};
        cv::Mat theta, omega;
        plant->response(schedule, t, theta);
        plant->velocity(schedule, t, omega);
        (void)schedule.levelAt(t[2]);
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    return 0;
}
